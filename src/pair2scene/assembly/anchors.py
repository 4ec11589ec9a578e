"""Keeping a floor object at its functional anchor the way the training rooms do.

The layout model draws a chair in its table's frame, and nearly all of its draws stand at
the table facing it; but placement takes the *first* candidate that survives the tests,
and where the facing ones collide (with the table's legs, another chair, a wall) a rare
sideways or distant draw survives instead. Measured on 30 fit rooms per type before this
rule: 36 % of living-room chairs within 1 m of a table did not face it, most of them
turned by exactly 90 degrees, and some chairs stood 3 m from their table.

:class:`AnchorRules` holds what the hierarchy statistics learned per (dependent,
functional anchor) pair (:attr:`~pair2scene.curation.stats.HierarchyStats.func_geometry`):
the share of dependents whose front points at the anchor's footprint
(:func:`~pair2scene.scene.relations.faces`: chairs at dining tables 0.98, nightstands
beside beds 0.08, a floor lamp by an armchair 0.27), the share that stand where the
anchor's front points at them (a TV stand in front of its sofa 0.73, a chair at a desk
0.81, at a dining table 0.20), the share of the others that stand by the anchor's back
half (a nightstand by the head of its bed, 30 of 31) and the spread of the gap between
their footprints. Per object, the placer draws whether it faces its anchor, whether it
stands in front of it and, if not and the pair keeps to a half (:data:`HALF_MIN_SHARE`),
by which half (each with the learned share, seeded by the object's id and the scene
seed) and rejects candidates that do not (``faces_away``, ``not_in_front``,
``wrong_half``) or that stand farther
from the anchor than the training rooms' pairs do (``far_from_anchor``,
:attr:`PairGeometry.max_gap`; an across-the-room pair on the wall the anchor faces is
exempt, :meth:`AnchorCheck.reason`). An object none of whose candidates passes is
dropped with the reason, as a chair with no room left at its table should be, rather than
left elsewhere in the room.

The same holds for an object on a support (:class:`SpotRules`). The model draws a
television in its stand's frame, but broadly: at temperature 0.8 its centre's offset
along the stand has a standard deviation of 0.22 m and 4 % of its draws face backwards,
where the real televisions all stand centred on their stand (offset under 0.03 m) facing
its way. The statistics keep, per (dependent, support) pair, the share of dependents
facing their support's way and the mean and spread of where they stand on it
(:attr:`~pair2scene.curation.stats.HierarchyStats.sup_geometry`); the placer rejects a
candidate turned away where the pair's dependents nearly always face the support's way
(``turned``) and one standing farther from the pair's usual spot than the training rooms'
did (``off_spot``). A cup on a table, which stands anywhere any way, is not held.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, field

import numpy as np

from pair2scene.assembly.walls import faced_by
from pair2scene.assets.forms import form_key
from pair2scene.curation.stats import HierarchyStats, aligned, mean_std
from pair2scene.curation.stats import parallel as lies_parallel
from pair2scene.scene.geometry import OrientedBox
from pair2scene.scene.relations import by_back_half, faces, footprint, footprint_gap
from pair2scene.scene.walls import Wall

MIN_PAIRS = 5
"""Pairs seen fewer times than this in the training rooms get no rule (too few to say)."""
GAP_SPREAD = 2.0
"""A candidate may stand this many standard deviations beyond the pair's mean gap..."""
GAP_MARGIN_M = 0.15
"""... plus this margin (m): a hand's width for the pushes that settle a candidate."""
ACROSS_M = 1.0
"""Pairs whose mean gap exceeds this stand across the room from each other (a TV stand
and its sofa: 1.84 m in the training rooms); the others side by side (a chair and its
table 0.00 m, a floor lamp and its armchair 0.19 m, a coffee table and its sofa 0.42 m)."""
_SALT = 19
"""Mixed into the object's seed for the facing draw (independent of its other draws)."""
HALF_MIN_SHARE = 0.8
"""A pair whose dependents, of those their anchor does not face, stood by one half of it
(behind its middle, or before it) at least this often in the training rooms keeps each to
a half, drawn with that share (:attr:`PairGeometry.behind`): a nightstand by the head of
its bed (30 of 31), a plunger by a toilet's tank (23 of 23). Below it (a chair at a
dining table 0.68, a floor lamp by an armchair 0.42) either half is taken."""

IN_FRONT_MIN_SHARE = 0.5
"""A pair whose dependents stood where their anchor faces them at least this often in the
training rooms (a TV stand in front of its sofa 0.73, a chair at a desk 0.81) has each
dependent drawn in front with that share and held there (``not_in_front``); below it
nothing is held, and the half rule decides. A chair at a dining table stood at the
table's front 0.20 of the time: a table's front is one of its sides, and four chairs each
drawn "in front" with 0.20 held two or more of them to that one side 0.18 of the time
(1 - 0.8^4 - 4 x 0.2 x 0.8^3). In 120 fit living rooms, 5 of the 17 chairs dropped at
their table had ``not_in_front`` as their first or second reason. Below it too: a side
table by a bed (0.16: it stands by the head, :data:`HALF_MIN_SHARE`), a stool at a counter
(0.23)."""


@dataclass(frozen=True)
class PairGeometry:
    """What the training rooms did for one (dependent, functional anchor) pair."""

    n: int
    facing: float
    """Share of dependents facing their anchor."""
    faced: float
    """Share of dependents standing where their anchor faces them."""
    gap_mean: float
    gap_std: float
    behind: float | None = None
    """Share of the dependents their anchor does not face that stood by its back half
    (their centre behind its middle, in its frame); None where that is unknown (older
    statistics) or undecided (between ``1 - HALF_MIN_SHARE`` and
    :data:`HALF_MIN_SHARE`, or fewer than :data:`MIN_PAIRS` such dependents)."""

    @property
    def max_gap(self) -> float:
        """Largest footprint gap (m) a placed dependent may keep from its anchor."""
        return self.gap_mean + GAP_SPREAD * self.gap_std + GAP_MARGIN_M


@dataclass(frozen=True)
class AnchorCheck:
    """One object's test against its placed functional anchor."""

    anchor: OrientedBox
    max_gap: float
    must_face: bool
    in_front: bool = False
    """Whether the object must stand where the anchor's front points at it."""
    across: bool = False
    """Whether the pair stands across the room (:data:`ACROSS_M`)."""
    half: int = 0
    """-1: the object must stand by the anchor's back half (its centre behind the
    anchor's middle, in the anchor's frame), 1: by its front half, 0: either."""
    min_gap: float = 0.0
    """Nearest the object may stand to the anchor, footprint to footprint (``near_anchor``):
    two sofas facing each other leave room between them."""

    def reason(self, box: OrientedBox, wall: Wall | None = None) -> str | None:
        """Why ``box`` cannot stand where it is relative to the anchor, or None.

        ``wall``: the wall ``box`` was drawn against. When the pair stands across the
        room and the anchor faces that wall (a TV stand on the wall opposite the sofa),
        the wall sets the distance, not the pair's learned gap: the anchor was placed
        first, knowing nothing of its dependent, and a sofa against one wall of a 6 m
        room is 5 m from the other."""
        if self.must_face and not faces(box, self.anchor):
            return "faces_away"
        if self.in_front and not faces(self.anchor, box):
            return "not_in_front"
        if self.half and by_back_half(box, self.anchor) != (self.half < 0):
            return "wrong_half"
        if self.across and wall is not None and faced_by(wall, self.anchor):
            return None
        gap = footprint_gap(footprint(box), footprint(self.anchor))
        if gap > self.max_gap:
            return "far_from_anchor"
        if self.min_gap > 0 and gap < self.min_gap:
            return "near_anchor"
        return None


@dataclass
class _PairRules:
    """Rules per (dependent, anchor) pair, from the statistics' running sums of the pairs
    seen at least :data:`MIN_PAIRS` times."""

    pairs: dict[str, dict[str, object]] = field(default_factory=dict)

    @classmethod
    def _from_sums(cls, table: dict[str, dict[str, list[float]]], make):
        """``make(sums)`` per pair of ``table`` (dependent -> anchor -> sums, the count
        first) seen often enough."""
        pairs: dict[str, dict[str, object]] = {}
        for dep, per_anchor in table.items():
            for anchor, sums in per_anchor.items():
                if sums[0] >= MIN_PAIRS:
                    pairs.setdefault(dep, {})[anchor] = make(*sums)
        return cls(pairs)

    def rule(self, dependent: str, anchor: str):
        """The pair's rule, or None when it has none."""
        return self.pairs.get(dependent, {}).get(anchor)

    def _drawn(self, dependent: str, anchor: str, seed: int, salt: int, k: int):
        """The pair's rule and ``k`` uniform draws seeded by the object (``seed``: its
        asset seed) and ``salt``; None when the pair has no rule."""
        rule = self.rule(dependent, anchor)
        if rule is None:
            return None
        return rule, np.random.default_rng([seed, salt]).random(k)


@dataclass
class AnchorRules(_PairRules):
    """Facing shares and gap spreads per (dependent, functional anchor) pair."""

    @classmethod
    def from_stats(cls, stats: HierarchyStats) -> AnchorRules:
        def make(n, facing, faced, total, squares, behind=None) -> PairGeometry:
            share = None
            if behind is not None and n - faced >= MIN_PAIRS:
                share = behind / (n - faced)
                share = share if max(share, 1.0 - share) >= HALF_MIN_SHARE else None
            return PairGeometry(int(n), facing / n, faced / n, *mean_std(n, total, squares),
                                share)  # fmt: skip

        return cls._from_sums(stats.func_geometry, make)

    def check(
        self, dependent: str, anchor: str, anchor_box: OrientedBox, seed: int
    ) -> AnchorCheck | None:
        """The test for one object (``seed``: its asset seed) at an anchor of category
        ``anchor`` standing at ``anchor_box``; None when the pair has no rule."""
        drawn = self._drawn(dependent, anchor, seed, _SALT, 3)
        if drawn is None:
            return None
        rule, u = drawn
        in_front = rule.faced >= IN_FRONT_MIN_SHARE and bool(u[1] < rule.faced)
        half = 0  # (in front of the anchor: its front half already)
        if not in_front and rule.behind is not None:
            half = -1 if u[2] < rule.behind else 1
        return AnchorCheck(anchor_box, rule.max_gap, bool(u[0] < rule.facing), in_front,
                           rule.gap_mean > ACROSS_M, half)  # fmt: skip

    def across(self, dependent: str, anchor: str, seed: int) -> bool:
        """Whether a mounted object (``seed``: its asset seed) hangs on a wall its floor
        anchor faces, across the room from it, rather than over it: drawn with the share
        of the pair's training objects the anchor faced (:attr:`PairGeometry.faced`, the
        draw :meth:`check` makes for ``in_front``). A television anchored to a sofa hangs
        across from it 11 times of 20, to an armchair 15 of 16; a painting over its bed
        25 times of 120, the other 95 across from it. False when the pair has no rule."""
        drawn = self._drawn(dependent, anchor, seed, _SALT, 2)
        return drawn is not None and bool(drawn[1][1] < drawn[0].faced)


ALIGNED_MIN = 0.97
"""A (dependent, support) pair whose dependents faced their support's way at least this
often keeps them so (each with that share: a television on its stand, 0.99 of 149);
below it, any yaw the model draws is taken. Objects on the training rooms' counters face
the counter's way 0.78-0.96 of the time (AI2-THOR places them square to it), the val
rooms' less often; holding pairs from 0.75 up took the kitchens' pose MMD from 0.061 to
0.083 (60 fit kitchens, seeds 30-89), and from 0.97 up left it at 0.061."""
MAX_OVERHANG = 1.2
"""Widest a dependent is drawn against its support: a television on two feet stands them
at 0.8 of its width, so one 1.2 times as wide as its stand still stands on it."""
SPOT_SPREAD = 2.0
"""A candidate may stand this many standard deviations from the pair's mean spot..."""
SPOT_MARGIN = 0.1
"""... plus this margin, in the support's canonical frame (a tenth of its half width)."""
PIN_STD = 0.03
"""A (dependent, support) pair whose dependents' spot along an axis of the support spread
less than this (canonical units, a fraction of the support's half size) in the training
rooms, over at least :data:`PIN_MIN_PAIRS` of them, is pinned there: a television on its
stand, centred to 0.012 (149 of them), a hand towel on its holder. Each candidate is
first tried moved onto the pair's mean along that axis (:meth:`SpotCheck.pinned`)."""
PIN_MIN_PAIRS = 20
PARALLEL_MIN = 0.75
"""A (dependent, support) pair whose dependents lay parallel to their support (its way
or the reverse, :func:`~pair2scene.curation.stats.parallel`) at least this often, or at
most one minus it, over at least :data:`PIN_MIN_PAIRS` of them, has each dependent drawn
parallel or crosswise with the pair's share, and candidates the other way rejected
(``crosswise``): pillows lie across the head of their bed 0.79 of the time in the
training tuples, where the layout model's draws turned most a quarter and 0.27 of those
placed on the beds of 120 fit bedrooms lay so."""
PARALLEL_ASPECT_MIN = 1.1
"""... when the object's footprint is at least this elongated (long side over short): a
rounder one (a cup, an apple, a pot) looks the same either way, and holding its draws to
a way would only cost candidates."""
_INSIDE = 1e-6
"""How far inside its spot :meth:`SpotCheck.onto` puts a box (canonical units)."""


@dataclass(frozen=True)
class SpotGeometry:
    """What the training rooms did for one (dependent, support) pair; ``u`` along the
    support's width, ``v`` along its depth, in its canonical frame (-1 to 1)."""

    n: int
    aligned: float
    """Share of dependents facing the support's way."""
    u: tuple[float, float]
    """Mean and standard deviation of ``u``."""
    v: tuple[float, float]
    w: tuple[float, float] = (0.0, 0.0)
    """Mean and standard deviation of the ratio of the long sides of the dependent's and
    the support's footprints."""
    parallel: float | None = None
    """Share of dependents lying parallel to the support (None: statistics written before
    it was counted)."""

    @property
    def holds_parallel(self) -> bool:
        """Whether the pair's dependents are drawn parallel or crosswise
        (:data:`PARALLEL_MIN`)."""
        p = self.parallel
        return p is not None and self.n >= PIN_MIN_PAIRS and max(p, 1.0 - p) >= PARALLEL_MIN

    @property
    def overhang(self) -> float:
        """How wide a dependent may be drawn against a surface of its support (the long
        side's share, :func:`~pair2scene.assembly.place.surface_fit`): one standard
        deviation beyond the pair's mean ratio, at most :data:`MAX_OVERHANG`. A
        television may be as wide as its stand and more, a book is far smaller than its
        shelf."""
        return min(self.w[0] + self.w[1], MAX_OVERHANG)

    def window(self, axis: str) -> tuple[float, float]:
        """Where along ``axis`` ("u" or "v") a placed dependent may stand."""
        mean, std = getattr(self, axis)
        reach = SPOT_SPREAD * std + SPOT_MARGIN
        return mean - reach, mean + reach


@dataclass(frozen=True)
class SpotCheck:
    """One object's test against the support it rests on."""

    support: OrientedBox
    must_align: bool
    u: tuple[float, float]
    v: tuple[float, float]
    pin: tuple[float | None, float | None] = (None, None)
    """The spot along ``u`` and ``v`` a pinned pair stands at (None: not pinned)."""
    parallel: bool | None = None
    """The object lies parallel to its support (True) or crosswise (False); None: either."""

    def pinned(self, box: OrientedBox) -> OrientedBox | None:
        """``box`` moved level onto the pinned spot along each pinned axis (height and yaw
        kept); None when the pair is pinned along neither."""
        if self.pin == (None, None):
            return None
        local = box.in_frame_of(self.support)
        center = local.center.copy()
        for axis, at in enumerate(self.pin):
            if at is not None:
                center[axis] = at
        return OrientedBox(center, local.size, local.rotation).from_frame_of(self.support)

    def onto(self, box: OrientedBox) -> OrientedBox:
        """``box`` moved level to the nearest point of its spot (height and yaw kept)."""
        local = box.in_frame_of(self.support)
        center = local.center.copy()
        inside = np.array([-_INSIDE, _INSIDE])  # just within: no rounding puts it off again
        center[0] = np.clip(center[0], *(np.asarray(self.u) - inside))
        center[1] = np.clip(center[1], *(np.asarray(self.v) - inside))
        return OrientedBox(center, local.size, local.rotation).from_frame_of(self.support)

    def reason(self, box: OrientedBox) -> str | None:
        """Why ``box`` cannot stand where it is on the support, or None."""
        local = box.in_frame_of(self.support)
        if self.must_align and not aligned(local.yaw):
            return "turned"
        if self.parallel is not None and lies_parallel(local.yaw) != self.parallel:
            return "crosswise"
        u, v = local.center[:2]
        if not (self.u[0] <= u <= self.u[1] and self.v[0] <= v <= self.v[1]):
            return "off_spot"
        return None


def _elongated(size: Sequence[float]) -> bool:
    """Whether a footprint (``size``'s x and y) is at least :data:`PARALLEL_ASPECT_MIN`
    times as long as it is wide."""
    short, long = sorted(float(v) for v in size[:2])
    return long >= PARALLEL_ASPECT_MIN * max(short, 1e-9)


@dataclass
class SpotRules(_PairRules):
    """Facing shares and spots per (dependent, support) pair."""

    @classmethod
    def from_stats(cls, stats: HierarchyStats) -> SpotRules:
        def make(n, facing, su, suu, sv, svv, sw, sww, along=None) -> SpotGeometry:
            u, v, w = mean_std(n, su, suu), mean_std(n, sv, svv), mean_std(n, sw, sww)
            return SpotGeometry(int(n), facing / n, u, v, w,
                                None if along is None else along / n)  # fmt: skip

        return cls._from_sums(stats.sup_geometry, make)

    def check(
        self,
        dependent: str,
        support: str,
        support_box: OrientedBox,
        seed: int,
        size: Sequence[float] | None = None,
    ) -> SpotCheck | None:
        """The test for one object (``seed``: its asset seed; ``size``: its box, without
        which it is not held parallel or crosswise) on a support of category ``support``
        standing at ``support_box``; None when the pair has no rule."""
        drawn = self._drawn(dependent, support, seed, _SALT + 1, 2)
        if drawn is None:
            return None
        rule, u = drawn
        must = rule.aligned >= ALIGNED_MIN and bool(u[0] < rule.aligned)
        pin = tuple(
            mean if rule.n >= PIN_MIN_PAIRS and std < PIN_STD else None
            for mean, std in (rule.u, rule.v)
        )
        lie = None  # (an L or C counter's runs lie both ways: what stands on it, too)
        if rule.holds_parallel and size is not None and _elongated(size):
            if form_key(support, support_box.size) is None:
                lie = bool(u[1] < rule.parallel)
        return SpotCheck(support_box, must, rule.window("u"), rule.window("v"), pin, lie)

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
0.81, at a dining table 0.20) and the spread of the gap between their footprints. Per
object, the placer draws whether it faces its anchor and whether it stands in front of
it (each with the learned share, seeded by the object's id and the scene seed) and
rejects candidates that do not (``faces_away``, ``not_in_front``) or that stand farther
from the anchor than the training rooms' pairs do (``far_from_anchor``,
:attr:`PairGeometry.max_gap`; an across-the-room pair on the wall the anchor faces is
exempt, :meth:`AnchorCheck.reason`). An object none of whose candidates passes is
dropped with the reason, as a chair with no room left at its table should be, rather than
left elsewhere in the room.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from pair2scene.assembly.walls import faced_by
from pair2scene.curation.stats import HierarchyStats
from pair2scene.scene.geometry import OrientedBox
from pair2scene.scene.relations import faces, footprint, footprint_gap
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
        if self.across and wall is not None and faced_by(wall, self.anchor):
            return None
        if footprint_gap(footprint(box), footprint(self.anchor)) > self.max_gap:
            return "far_from_anchor"
        return None


@dataclass
class AnchorRules:
    """Facing shares and gap spreads per (dependent, functional anchor) pair."""

    pairs: dict[str, dict[str, PairGeometry]] = field(default_factory=dict)

    @classmethod
    def from_stats(cls, stats: HierarchyStats) -> AnchorRules:
        pairs: dict[str, dict[str, PairGeometry]] = {}
        for dep, per_anchor in stats.func_geometry.items():
            for anchor, (n, facing, faced, total, squares) in per_anchor.items():
                if n < MIN_PAIRS:
                    continue
                mean = total / n
                std = float(np.sqrt(max(squares / n - mean * mean, 0.0)))
                rule = PairGeometry(int(n), facing / n, faced / n, mean, std)
                pairs.setdefault(dep, {})[anchor] = rule
        return cls(pairs)

    def rule(self, dependent: str, anchor: str) -> PairGeometry | None:
        return self.pairs.get(dependent, {}).get(anchor)

    def check(
        self, dependent: str, anchor: str, anchor_box: OrientedBox, seed: int
    ) -> AnchorCheck | None:
        """The test for one object (``seed``: its asset seed) at an anchor of category
        ``anchor`` standing at ``anchor_box``; None when the pair has no rule."""
        rule = self.rule(dependent, anchor)
        if rule is None:
            return None
        u = np.random.default_rng([seed, _SALT]).random(2)
        return AnchorCheck(anchor_box, rule.max_gap, bool(u[0] < rule.facing),
                           bool(u[1] < rule.faced), rule.gap_mean > ACROSS_M)  # fmt: skip

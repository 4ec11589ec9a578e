"""Which floor objects take a wall as an anchor, and which wall.

:class:`WallRules` holds what the hierarchy statistics learned from the training rooms
(:class:`~pair2scene.curation.stats.HierarchyStats`): per room type and category, the
share of floor objects standing against a wall (beds, dressers, fridges and counters
nearly always; chairs and dining tables rarely), and per (dependent, functional anchor)
pair how far the anchor stands from the dependent's wall (a nightstand's bed: half a bed
length; a TV stand's sofa: across the room).

The placer asks, per floor object: does it stand against a wall (a draw seeded by the
object's id and the scene seed), and if so, in which order to try the room's walls
(:func:`wall_order`): only walls with a free stretch at least as wide as the object
(:func:`free_length`: doors, windows below the object's top and the objects already
standing along the wall subtracted), the pair's learned distance first when the object
has a functional anchor, else at random weighted by free length.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from pair2scene.assets.forms import form_key
from pair2scene.curation.stats import (
    HierarchyStats,
    anchored_key,
    mean_std,
    seats_key,
    under_key,
)
from pair2scene.scene.geometry import OrientedBox, yaw_to_matrix
from pair2scene.scene.model import Room
from pair2scene.scene.walls import Wall

DOOR_MARGIN_M = 0.1
"""Free wall kept beside a door's frame."""
MIN_DISTANCE_STD_M = 0.3
"""Floor on the spread of a pair's learned anchor distance (few pairs have many rooms)."""
_SALT = 18
"""Mixed into the object's seed for the wall draw (independent of its asset's draws)."""
_CORNER_SALT = 23
"""The same for the corner draw."""
_SIDEWAYS_SALT = 29
"""The same for the sideways draw."""
_APART_SALT = 31
"""The same for a mounted object's draw of keeping apart from the others on its wall."""
MIN_GAP_PAIRS = 20
"""Neighbouring pairs on walls the statistics must have seen for the share hanging close
together to be used."""
CORNER_GAP_M = 0.005
"""Gap left between an object put in a corner and the second wall."""
MIN_FORM_OBJECTS = 5
"""Objects of a form (an L counter) a room type must have held for its own wall, corner
and sideways shares to be used there; fewer, and the category's shares in that room type
stand in (one L counter in the training bathrooms, standing sideways, would otherwise
turn every generated bathroom's L sideways)."""
MIN_SPLIT_OBJECTS = 5
"""Objects with a functional anchor (or without one) a room type must have held of a
category for their own wall, corner and sideways shares to be used there (:func:`_share`'s
``anchored``); fewer, and the category's shares stand in."""


STAND_INS: dict[str, str] = {"wardrobe": "dresser", "cabinet": "dresser", "dressing_table": "desk"}
"""Furniture no training room held, and the category whose wall, corner and sideways
shares it takes: a wardrobe a text asks for stands against a wall as dressers do (0.99 in
bedrooms), where no counts of its own left it mid-room."""


@dataclass
class WallRules:
    """Wall rates per room type and category, and anchor distances per pair."""

    rates: dict[str, dict[str, tuple[float, float]]] = field(default_factory=dict)
    """room type -> category -> (against a wall, on the floor); a composed type's are its
    base types' counts, weighted by the recipe (not whole numbers)."""
    distances: dict[str, dict[str, tuple[float, float]]] = field(default_factory=dict)
    """dependent -> functional anchor -> (mean, std) of the anchor's distance (m) from the
    dependent's wall."""
    corners: dict[str, dict[str, tuple[float, float]]] = field(default_factory=dict)
    """room type -> category -> (in a corner, back against a wall): how many of the
    objects with their back against a wall stood against two at once."""
    sideways: dict[str, dict[str, tuple[float, float]]] = field(default_factory=dict)
    """room type -> category -> (sideways, against a wall): how many of the objects
    against a wall had a side against it and their back against none (a sofa's arm)."""
    close_share: float | None = None
    """Share of neighbouring objects on one wall hanging close together
    (:attr:`~pair2scene.curation.stats.HierarchyStats.wall_gaps`); None: not known, no
    object kept apart."""

    @classmethod
    def from_stats(cls, stats: HierarchyStats) -> WallRules:
        from pair2scene.hierarchy.room_types import composable

        # a composed type (an office) stands its pieces as its base types' rooms do
        types = {rt: stats.room_type(rt) for rt in (*stats.room_types, *composable(stats))}
        rates = {
            rt: {c: (rs.against_wall.get(c, 0), n) for c, n in rs.on_floor.items()}
            for rt, rs in types.items()
        }
        corners = {  # (an object with only a side against a wall is in no corner)
            rt: {
                c: (rs.in_corner.get(c, 0), n - rs.sideways.get(c, 0))
                for c, n in rs.against_wall.items()
            }
            for rt, rs in types.items()
        }
        sideways = {
            rt: {c: (rs.sideways.get(c, 0), n) for c, n in rs.against_wall.items()}
            for rt, rs in types.items()
        }
        distances: dict[str, dict[str, tuple[float, float]]] = {}
        for dep, per_anchor in stats.wall_anchor.items():
            for anchor, (n, total, squares) in per_anchor.items():
                if n < 1:
                    continue
                distances.setdefault(dep, {})[anchor] = mean_std(n, total, squares)
        gaps = stats.wall_gaps
        close = gaps[1] / gaps[0] if gaps is not None and gaps[0] >= MIN_GAP_PAIRS else None
        return cls(rates, distances, corners, sideways, close)

    def rate(self, room_type: str, category: str, size=None, **split) -> float:
        """Share of ``category``'s floor objects in ``room_type`` rooms against a wall (over
        every room type when this one never held it; 0 when none did). With the object's
        ``size``, the share of its form's (an L counter's, :func:`form_key`) where the
        statistics counted enough of that form in ``room_type`` (:data:`MIN_FORM_OBJECTS`).
        ``split`` narrows the share to the category's objects like this one, where enough
        were counted (:data:`MIN_SPLIT_OBJECTS`; :func:`_share`): ``anchored`` (True: its
        functional anchor stands in the room; False: it has none; a kitchen chair at a
        table 0.21, alone 0.80), ``under`` (True: a painting, mirror or wall lamp hangs
        over it, :func:`~pair2scene.curation.stats.under_key`; a living-room sofa with
        nothing hung over it, 0.79 instead of 0.82) and ``seats`` (a table's seats,
        :func:`~pair2scene.curation.stats.seats_key`, in place of ``anchored``: a
        living-room dining table with no chair 1.00, with four 0.00)."""
        return _share(self.rates, room_type, category, size, **split)

    def against_wall(self, room_type: str, category: str, seed: int, size=None, **split) -> bool:
        """Whether an object (``seed``: its asset seed; ``size``, ``split``: as :meth:`rate`)
        stands against a wall: a draw."""
        return _drawn(self.rates, _SALT, room_type, category, seed, size, split)

    def corner_rate(self, room_type: str, category: str, size=None, **split) -> float:
        """Share of ``category``'s objects against a wall in ``room_type`` rooms that stand
        in a corner (over every room type when this one never had one against a wall; of
        its form's with ``size`` and of those like it, ``split``, as :meth:`rate`)."""
        return _share(self.corners, room_type, category, size, **split)

    def in_corner(self, room_type: str, category: str, seed: int, size=None, **split) -> bool:
        """Whether an object against a wall (``seed``: its asset seed) stands in a corner:
        a draw, independent of the wall draw."""
        return _drawn(self.corners, _CORNER_SALT, room_type, category, seed, size, split)

    def sideways_rate(self, room_type: str, category: str, size=None, **split) -> float:
        """Share of ``category``'s objects against a wall in ``room_type`` rooms that stand
        with a side, not their back, against it (pooled, of its form and of those like it,
        as :meth:`rate`)."""
        return _share(self.sideways, room_type, category, size, **split)

    def turned(self, room_type: str, category: str, seed: int, size=None, **split) -> bool:
        """Whether an object against a wall (``seed``: its asset seed) stands sideways to
        it: a draw, independent of the wall and corner draws."""
        return _drawn(self.sideways, _SIDEWAYS_SALT, room_type, category, seed, size, split)

    def keeps_apart(self, seed: int) -> bool:
        """Whether a mounted object (``seed``: its asset seed) hangs at least
        :data:`~pair2scene.curation.stats.CLOSE_WALL_M` from the others on its wall: a
        draw with one minus :attr:`close_share` (never when that is not known)."""
        if self.close_share is None:
            return False
        return bool(np.random.default_rng([seed, _APART_SALT]).random() >= self.close_share)

    def distance(self, dependent: str, anchor: str) -> tuple[float, float] | None:
        """(mean, std) of ``anchor``'s distance from ``dependent``'s wall, if learned."""
        return self.distances.get(dependent, {}).get(anchor)


def _key(
    table: dict[str, dict[str, tuple[float, float]]], room_type: str, category: str, size
) -> str:
    """``category``'s form key at ``size`` when the counts :func:`_share` reads for it
    (``room_type``'s, or pooled over room types when that one never held the category)
    hold at least :data:`MIN_FORM_OBJECTS` of that form, else ``category`` (statistics
    written before forms were counted hold none)."""
    form = None if size is None else form_key(category, size)
    if form is None:
        return category
    own = table.get(room_type, {})
    if own.get(category, (0, 0))[1] > 0:
        n = own.get(form, (0, 0))[1]
    else:
        n = sum(r.get(form, (0, 0))[1] for r in table.values())
    return form if n >= MIN_FORM_OBJECTS else category


def _drawn(table, salt: int, room_type: str, category: str, seed: int, size, split) -> bool:
    """A draw seeded by the object (``seed``) and ``salt``, true with :func:`_share`."""
    u = np.random.default_rng([seed, salt]).random()
    return bool(u < _share(table, room_type, category, size, **split))


def _share(
    table: dict[str, dict[str, tuple[float, float]]],
    room_type: str,
    category: str,
    size=None,
    *,
    anchored: bool | None = None,
    under: bool | None = None,
    seats: int | None = None,
) -> float:
    """``part / whole`` of ``table[room_type]``'s entry for ``category``, pooled over every
    room type when this one has no whole for the category; 0 when none has. The entry is
    the form's at ``size`` (:func:`_key`); else, with ``anchored``, the category's objects
    with a functional anchor (True) or without one (False: the category's counts less
    those with one), when :data:`MIN_SPLIT_OBJECTS` of them were counted; else the
    category's; with ``seats``, first the category's objects with that many seats
    (:func:`~pair2scene.curation.stats.seats_key`), when :data:`MIN_SPLIT_OBJECTS` of them
    were counted, in place of the ``anchored`` split. Then, with ``under``, of those the
    ones a wall object hangs over (True, :func:`~pair2scene.curation.stats.under_key`) or
    the others (False), when :data:`MIN_SPLIT_OBJECTS` of them were counted."""
    if category in STAND_INS and not any(category in r for r in table.values()):
        category = STAND_INS[category]
    key = _key(table, room_type, category, size)

    def counts(name: str) -> tuple[float, float]:
        if table.get(room_type, {}).get(key, (0, 0))[1] > 0:
            return table[room_type].get(name, (0, 0))
        pooled = [r[name] for r in table.values() if name in r]
        return sum(a for a, _ in pooled), sum(m for _, m in pooled)

    def less(name: str, other: str | None) -> tuple[float, float]:
        """The counts of ``name`` less those of ``other`` (None: nothing)."""
        a, m = counts(name)
        b, n = (0, 0) if other is None else counts(other)
        return a - b, m - n

    chosen: tuple[str, str | None] = (key, None)  # the counts of [0] less those of [1]
    if (
        key == category
        and seats is not None
        and less(seats_key(category, seats), None)[1] >= MIN_SPLIT_OBJECTS
    ):
        chosen = (seats_key(category, seats), None)
    elif key == category and anchored is not None:
        mark = anchored_key(category)
        split = (mark, None) if anchored else (key, mark)
        if less(*split)[1] >= MIN_SPLIT_OBJECTS:
            chosen = split
    part, whole = less(*chosen)
    if under is not None:  # of those, the ones a wall object hangs over, or the others
        hung = less(under_key(chosen[0]), None if chosen[1] is None else under_key(chosen[1]))
        own = hung if under else (part - hung[0], whole - hung[1])
        if own[1] >= MIN_SPLIT_OBJECTS:
            part, whole = own
    return min(1.0, part / whole) if whole > 0 else 0.0


def intervals_minus(free: list[tuple[float, float]], lo: float, hi: float):
    """The intervals ``free`` with (lo, hi) taken out."""
    out = []
    for a, b in free:
        if hi <= a or lo >= b:
            out.append((a, b))
            continue
        if lo > a:
            out.append((a, lo))
        if hi < b:
            out.append((hi, b))
    return out


def free_stretches(
    wall: Wall,
    room: Room,
    placed: list[OrientedBox],
    depth: float,
    height: float,
) -> list[tuple[float, float]]:
    """The stretches (along the wall, from its midpoint) where an object ``depth`` deep
    and ``height`` tall could stand with its back to ``wall``: the wall minus its doors
    (and :data:`DOOR_MARGIN_M` beside them), the windows whose sill is below the object's
    top, and what already stands within ``depth`` of the wall."""
    half = wall.length / 2
    free = [(-half, half)]
    for opening in (*room.doors, *room.windows):
        if opening.kind == "window" and opening.z_min >= height:
            continue
        span = wall.span(opening.p0, opening.p1)
        if span is None:  # not on this wall
            continue
        margin = DOOR_MARGIN_M if opening.kind == "door" else 0.0
        free = intervals_minus(free, span[0] - margin, span[1] + margin)
    for box in placed:
        corners = wall.local(box.corners()[:, :2])
        if corners[:, 1].min() > depth or corners[:, 1].max() < -0.05:
            continue
        free = intervals_minus(free, corners[:, 0].min(), corners[:, 0].max())
    return free


def within_reach(
    wall: Wall, anchor: OrientedBox, depth: float, gap: float, width: float, facing: bool
) -> bool:
    """Whether an object ``depth`` deep and ``width`` wide standing with its back to
    ``wall`` can come within ``gap`` of ``anchor``'s footprint: the anchor's nearest
    corner is at most ``depth + gap`` from the wall's line and its span along the wall
    meets the wall widened by that much and half the object. ``facing``: the object
    faces the anchor, so it stands between the wall and the anchor, which must leave it
    its depth. A chair at a table in the middle of the room, or at a table whose end is
    half a chair from the wall, has no such wall."""
    corners = wall.local(anchor.corners()[:, :2])
    nearest = corners[:, 1].min()
    if nearest > depth + gap or corners[:, 1].max() < 0.0 or (facing and nearest < depth):
        return False
    half = wall.length / 2 + depth + gap + width / 2
    return bool(corners[:, 0].max() >= -half and corners[:, 0].min() <= half)


def to_corners(
    box: OrientedBox, wall: Wall, ends: tuple[bool, bool], gap: float = CORNER_GAP_M
) -> list[tuple[int, OrientedBox]]:
    """``box`` (standing against ``wall``) slid along the wall into each of its convex
    corners (``ends``: whether the wall's start and end are such corners,
    :func:`~pair2scene.scene.walls.convex_ends`), ``gap`` short of the other wall, the
    nearer corner first, as (0 for the start or 1 for the end, box); none when neither
    end is a corner or the box is longer than the wall."""
    lo, hi = wall.extent(box)
    half = wall.length / 2
    if hi - lo > wall.length:
        return []
    shifts = []  # (distance moved, end, shift along the wall)
    if ends[0]:
        shifts.append((abs(lo + half), 0, -half + gap - lo))
    if ends[1]:
        shifts.append((abs(half - hi), 1, half - gap - hi))
    out = []
    for _, end, shift in sorted(shifts):
        center = box.center.copy()
        center[:2] += shift * wall.direction
        out.append((end, OrientedBox(center, box.size, box.rotation)))
    return out


def turn_sideways(
    box: OrientedBox, wall: Wall, toward: np.ndarray, gap: float = CORNER_GAP_M
) -> OrientedBox:
    """``box`` turned to stand with a side against ``wall``, ``gap`` off it, where its
    centre was along the wall, its front pointing along the wall to the side of
    ``toward`` (a point, xy: the room's centre, so that it faces into the room)."""
    along = float(wall.local(box.center[:2])[0])
    ahead = float(wall.local(np.asarray(toward, dtype=float)[:2])[0])
    front = wall.direction if ahead >= along else -wall.direction
    center = box.center.copy()
    center[:2] = wall.midpoint + along * wall.direction + (box.half_size[0] + gap) * wall.normal
    return OrientedBox(center, box.size, yaw_to_matrix(float(np.arctan2(-front[0], front[1]))))


def free_length(stretches: list[tuple[float, float]], width: float) -> float:
    """Summed length of the stretches at least ``width`` long (where the object fits)."""
    return float(sum(b - a for a, b in stretches if b - a >= width))


def wall_order(
    walls: list[Wall],
    free: list[float],
    rng: np.random.Generator,
    anchor: OrientedBox | None = None,
    distance: tuple[float, float] | None = None,
    in_front: bool = False,
) -> list[int]:
    """Indices into ``walls`` to try, best first, among those with free length > 0.

    With a functional ``anchor`` and its learned ``distance`` (mean, std) from the
    dependent's wall: by how well the anchor's distance from each wall matches it.
    Otherwise a random order weighted by free length (longer free walls first, more
    often). ``in_front``: the object must stand where the anchor's front points (a TV
    stand before its sofa), so only the walls the anchor faces (:func:`faced_by`) are
    tried when it faces any with room (the placer splits its candidates among the walls
    it tries: a wall behind the sofa would waste its share).
    """
    usable = [i for i, f in enumerate(free) if f > 0]
    if anchor is not None and in_front:
        usable = [i for i in usable if faced_by(walls[i], anchor)] or usable
    if not usable:
        return []
    keys = weighted_keys(rng, [free[i] for i in usable])
    if anchor is not None and distance is not None:
        mean, std = distance
        std = max(std, MIN_DISTANCE_STD_M)
        scores = []
        for k, i in zip(keys, usable):
            d = float(walls[i].local(anchor.center[:2])[1])
            scores.append((-(((d - mean) / std) ** 2), k))
    else:
        scores = [(0.0, k) for k in keys]
    return [i for _, i in sorted(zip(scores, usable), key=lambda t: t[0], reverse=True)]


def weighted_keys(rng: np.random.Generator, weights) -> np.ndarray:
    """One sort key per weight, ``u ** (1 / w)``: sorted descending they give a random
    order in which heavier items come first more often (weighted sampling without
    replacement)."""
    return rng.random(len(weights)) ** (1.0 / np.asarray(weights, dtype=float))


def walls_with_room(walls: list[Wall], room: Room, width: float) -> list[Wall]:
    """The ``walls`` with a stretch free of doors and windows at least ``width`` long:
    where an object that wide can hang across the room from a floor object facing them
    (a television opposite the sofa, :func:`faced_by`)."""
    return [
        wall
        for wall in walls
        if free_length(free_stretches(wall, room, [], 0.0, room.height), width) > 0.0
    ]


def faced_by(wall: Wall, box: OrientedBox) -> bool:
    """Whether ``box``'s front points at ``wall``: the wall's inward normal against the
    front within 45 degrees."""
    front = box.rotation[:2, 1]
    norm = float(np.linalg.norm(front))
    return bool(norm > 1e-9 and float(wall.normal @ front) / norm < -np.sqrt(0.5))

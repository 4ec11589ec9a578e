"""Layout realism: measures of how furniture is arranged, that real rooms get too.

Each measure counts, per room, how many of the objects it looks at pass a test (the
numerator) out of how many it looks at (the denominator); a set of rooms is pooled by
summing the counts (:func:`layout_report`), and a measure is *measurable* in a room when
its denominator there is not zero. The same functions measure generated and reference
rooms, so the figures compare directly.

- ``against_wall``: floor objects whose back face stands against a wall facing into the
  room (:func:`pair2scene.scene.walls.against_wall`: within 0.15 m, parallel within 15
  degrees, overlapping the wall), pooled over :data:`WALL_FURNITURE` and per category
  (``against_wall/<category>``).
- ``chairs_facing_table``: chairs (:data:`CHAIRS`) with a table (:data:`TABLES`) within
  :data:`TABLE_NEAR_M` (footprint to footprint) whose front points at the nearest such
  table: the angle between the chair's +y and the direction from its centre to the
  nearest point of the table's footprint is below :data:`FACING_MAX_DEG`.
- ``sofas_facing_tv``: sofas in a room with a television or a TV stand (:data:`SCREENS`)
  whose front points at one of them (angle to the direction of its centre below
  :data:`FACING_MAX_DEG`).
- ``nightstands_at_bed_head``: nightstands (side tables, :data:`NIGHTSTANDS`) in a room
  with a bed, that stand beside the head end of a bed (:func:`beside_bed_head`).

Only floor objects take part (:func:`on_floor`) — except televisions, which may hang on
a wall or stand on their stand — and never structure or parts of furniture.
"""

from __future__ import annotations

from collections.abc import Iterable, Sequence

import numpy as np

from pair2scene.categories import BY_NAME, SuperCategory
from pair2scene.scene.geometry import OrientedBox
from pair2scene.scene.model import FLOOR, Scene, SceneObject
from pair2scene.scene.navigation import footprint_polygon as footprint
from pair2scene.scene.walls import against_wall, walls_of

WALL_FURNITURE = (
    "bed", "sofa", "dresser", "wardrobe", "tv_stand", "shelving_unit", "fridge", "counter_top",
    "toilet", "bathtub",
)  # fmt: skip
"""Furniture that real rooms put with its back to a wall (issue 18): the categories pooled
in the ``against_wall`` rate, each also reported on its own (toilets and bathtubs for
bathrooms). AI2-THOR's counters are cabinet runs from the floor since the adapters fold
their slabs over the cabinets (:mod:`pair2scene.data.fixtures`), so they count too."""
CHAIRS = ("chair",)
"""Seats that are pulled up to a table: ``chair`` (dining, desk and office chairs). Stools
are left out: bar stools are mostly round, so their +y says nothing (ProcTHOR turns them
any way at its counters), and armchairs are lounge seats that face a coffee table or a
TV and stand *beside* side tables."""
TABLES = ("dining_table", "desk", "dressing_table", "side_table")
"""What a chair is pulled up to: dining tables, desks, dressing tables and side tables.
Coffee tables are not sat at; counters are for stools."""
SCREENS = ("television", "tv_stand")
"""What a sofa faces: the television, or its stand when the room has no TV object."""
NIGHTSTANDS = ("side_table",)
"""Nightstands: the canonical vocabulary files them under ``side_table``; in a room with
a bed, every side table is looked at."""
BEDS = ("bed",)
FLOOR_TOLERANCE_M = 0.02
"""With no support known, an object whose bottom is this close to the floor stands on it."""
TABLE_NEAR_M = 1.0
"""A chair with a table's footprint this close to its own (gap, m) is at that table."""
FACING_MAX_DEG = 45.0
"""An object faces a target when its +y is within this many degrees of the direction to
the target: half of a right angle, so a chair set square to the table's side or end
passes and one turned sideways (90 degrees) or away does not."""
BED_SIDE_MARGIN_M = 0.1
"""A nightstand's centre must lie beyond the bed's side less this margin (it may overlap
the bed's box a little: the box includes the overhang of a duvet)..."""
BED_SIDE_REACH_M = 0.6
"""... and at most this far beyond the side (m)..."""
BED_HEAD_MARGIN_M = 0.3
"""... and in the head half of the bed: between its centre and this far behind its
headboard (local y from -(half length + margin) to 0; the headboard is at -y)."""

MEASURES = ("against_wall", "chairs_facing_table", "sofas_facing_tv", "nightstands_at_bed_head")
"""The pooled measures, in the order they are reported."""
_SKIPPED = (SuperCategory.STRUCTURE, SuperCategory.PART)


# -- which objects ---------------------------------------------------------------------
def _counted(o: SceneObject) -> bool:
    cat = BY_NAME.get(o.category)
    return o.part_of is None and (cat is None or cat.super not in _SKIPPED)


def on_floor(o: SceneObject, floor_z: float = 0.0) -> bool:
    """Whether ``o`` stands on the floor: its support is the floor, or (support unknown)
    its bottom is within :data:`FLOOR_TOLERANCE_M` of it."""
    if o.support is not None:
        return o.support == FLOOR
    return o.box.bottom <= floor_z + FLOOR_TOLERANCE_M


def _floor_objects(scene: Scene) -> list[SceneObject]:
    return [o for o in scene.objects if _counted(o) and on_floor(o)]


# -- geometry --------------------------------------------------------------------------
def _closest_on_segments(point: np.ndarray, a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """(M, 2) closest point to ``point`` (2,) on each segment a[i] -> b[i]."""
    d = b - a
    t = np.einsum("ij,ij->i", point - a, d) / np.maximum(np.einsum("ij,ij->i", d, d), 1e-18)
    return a + np.clip(t, 0.0, 1.0)[:, None] * d


def _inside_convex(point: np.ndarray, poly: np.ndarray) -> bool:
    """Whether ``point`` lies in the counter-clockwise convex polygon ``poly``."""
    e = np.roll(poly, -1, axis=0) - poly
    r = point - poly
    return bool(np.all(e[:, 0] * r[:, 1] - e[:, 1] * r[:, 0] >= -1e-12))


def nearest_point(point: np.ndarray, poly: np.ndarray) -> np.ndarray:
    """The point of the convex polygon ``poly`` (inside included) nearest to ``point``."""
    point = np.asarray(point, float)
    if _inside_convex(point, poly):
        return point
    near = _closest_on_segments(point, poly, np.roll(poly, -1, axis=0))
    return near[np.argmin(np.linalg.norm(near - point, axis=1))]


def footprint_gap(a: np.ndarray, b: np.ndarray) -> float:
    """Distance between two convex polygons (counter-clockwise, (N, 2)); 0 when they
    overlap."""
    for p, q in ((a, b), (b, a)):  # separating axis: the edge normals of both
        e = np.roll(p, -1, axis=0) - p
        n = np.stack([e[:, 1], -e[:, 0]], axis=1)
        if np.any((q @ n.T).min(axis=0) > np.einsum("ij,ij->i", p, n) + 1e-12):
            break
    else:
        return 0.0
    best = np.inf
    for p, q in ((a, b), (b, a)):  # apart: the closest pair has a vertex of one of them
        q1 = np.roll(q, -1, axis=0)
        for v in p:
            near = _closest_on_segments(v, q, q1)
            best = min(best, float(np.linalg.norm(near - v, axis=1).min()))
    return best


def facing_angle(box: OrientedBox, target_xy: np.ndarray) -> float:
    """Degrees between ``box``'s front (+y, seen from above) and the direction from its
    centre to ``target_xy``; 0 when the target is at the centre itself."""
    front = box.rotation[:2, 1]
    to = np.asarray(target_xy, float) - box.center[:2]
    nf, nt = float(np.linalg.norm(front)), float(np.linalg.norm(to))
    if nt < 1e-9:
        return 0.0
    if nf < 1e-9:  # lying on its back: no front seen from above
        return 180.0
    cos = float(front @ to) / (nf * nt)
    return float(np.degrees(np.arccos(np.clip(cos, -1.0, 1.0))))


def beside_bed_head(nightstand: OrientedBox, bed: OrientedBox) -> bool:
    """Whether ``nightstand``'s centre lies beside the head end of ``bed``: in the bed's
    frame, beyond its side (|x| > half width - :data:`BED_SIDE_MARGIN_M`) by at most
    :data:`BED_SIDE_REACH_M`, and in its head half (-(half length +
    :data:`BED_HEAD_MARGIN_M`) <= y < 0, the headboard being at -y)."""
    x, y, _ = bed.to_local(nightstand.center[None])[0]
    hw, hl = bed.half_size[0], bed.half_size[1]
    beside = hw - BED_SIDE_MARGIN_M < abs(x) <= hw + BED_SIDE_REACH_M
    return bool(beside and -(hl + BED_HEAD_MARGIN_M) <= y < 0.0)


# -- the measures, one room ------------------------------------------------------------
def against_wall_counts(scene: Scene) -> dict[str, list[int]]:
    """category -> [against a wall, floor objects] over the room's floor objects."""
    walls = walls_of(scene.room.floor_polygon)
    out: dict[str, list[int]] = {}
    for o in _floor_objects(scene):
        row = out.setdefault(o.category, [0, 0])
        row[0] += against_wall(o.box, walls)
        row[1] += 1
    return dict(sorted(out.items()))


def chairs_facing_table(scene: Scene) -> list[int]:
    """[facing their table, chairs with a table within :data:`TABLE_NEAR_M`]."""
    floor = _floor_objects(scene)
    tables = [footprint(o.box) for o in floor if o.category in TABLES]
    facing = total = 0
    if not tables:
        return [0, 0]
    for chair in (o for o in floor if o.category in CHAIRS):
        mine = footprint(chair.box)
        gaps = [footprint_gap(mine, t) for t in tables]
        k = int(np.argmin(gaps))
        if gaps[k] > TABLE_NEAR_M:
            continue
        total += 1
        target = nearest_point(chair.box.center[:2], tables[k])
        if np.linalg.norm(target - chair.box.center[:2]) < 1e-9:  # under the table
            target = tables[k].mean(axis=0)
        facing += facing_angle(chair.box, target) < FACING_MAX_DEG
    return [facing, total]


def sofas_facing_tv(scene: Scene) -> list[int]:
    """[facing a TV or TV stand, sofas in a room that has one]."""
    screens = [o for o in scene.objects if _counted(o) and o.category in SCREENS]
    if not screens:
        return [0, 0]
    sofas = [o for o in _floor_objects(scene) if o.category == "sofa"]
    facing = sum(
        any(facing_angle(s.box, t.box.center[:2]) < FACING_MAX_DEG for t in screens) for s in sofas
    )
    return [int(facing), len(sofas)]


def nightstands_at_bed_head(scene: Scene) -> list[int]:
    """[beside the head end of a bed, nightstands in a room with a bed]."""
    floor = _floor_objects(scene)
    beds = [o.box for o in floor if o.category in BEDS]
    if not beds:
        return [0, 0]
    stands = [o for o in floor if o.category in NIGHTSTANDS]
    ok = sum(any(beside_bed_head(n.box, b) for b in beds) for n in stands)
    return [int(ok), len(stands)]


def layout_measures(scene: Scene) -> dict[str, list[int]]:
    """Every measure of one room as [numerator, denominator]: the pooled ones of
    :data:`MEASURES` and ``against_wall/<category>`` for each floor category."""
    walls = against_wall_counts(scene)
    pooled = [0, 0]
    for cat in WALL_FURNITURE:
        n, d = walls.get(cat, (0, 0))
        pooled[0] += n
        pooled[1] += d
    out = {
        "against_wall": pooled,
        "chairs_facing_table": chairs_facing_table(scene),
        "sofas_facing_tv": sofas_facing_tv(scene),
        "nightstands_at_bed_head": nightstands_at_bed_head(scene),
    }
    out.update({f"against_wall/{cat}": list(c) for cat, c in walls.items()})
    return out


def _stat(num: int, den: int, rooms: int) -> dict:
    return {"rate": num / den if den else None, "count": [num, den], "rooms": rooms}


def pool(per_scene: Iterable[dict[str, Sequence[int]]]) -> dict[str, dict]:
    """measure -> ``{"rate", "count": [numerator, denominator], "rooms"}`` summed over
    rooms (``rate`` None when no room was measurable; ``rooms``: rooms measurable in)."""
    sums: dict[str, list[int]] = {}
    for measures in per_scene:
        for key, (n, d) in measures.items():
            row = sums.setdefault(key, [0, 0, 0])
            row[0] += int(n)
            row[1] += int(d)
            row[2] += d > 0
    for key in MEASURES:
        sums.setdefault(key, [0, 0, 0])
    return {key: _stat(*sums[key]) for key in _ordered(sums)}


def _ordered(keys: Iterable[str]) -> list[str]:
    """The pooled measures, then the wall furniture's categories, then other categories."""
    keys = set(keys)
    walls = [f"against_wall/{c}" for c in WALL_FURNITURE]
    rest = sorted(keys - set(MEASURES) - set(walls))
    return [k for k in (*MEASURES, *walls) if k in keys] + rest


def layout_report(scenes: Iterable[Scene]) -> dict[str, dict]:
    """Every measure pooled over ``scenes`` (:func:`pool` of :func:`layout_measures`)."""
    return pool(layout_measures(s) for s in scenes)


def layout_section(reference: Sequence[Scene], generated: Sequence[Scene]) -> dict:
    """The evaluation report's ``layout`` section: one row per measure, ``{"generated":
    stat, "reference": stat}`` (stats as in :func:`pool`), for :data:`MEASURES` and the
    against-wall rate of every :data:`WALL_FURNITURE` category; ``against_wall_other``
    holds the same rows for the other floor categories either set has."""
    gen, ref = layout_report(generated), layout_report(reference)
    empty = _stat(0, 0, 0)
    keys = _ordered(set(gen) | set(ref) | {f"against_wall/{c}" for c in WALL_FURNITURE})
    rows = {k: {"generated": gen.get(k, empty), "reference": ref.get(k, empty)} for k in keys}
    main = [*MEASURES, *(f"against_wall/{c}" for c in WALL_FURNITURE)]
    out = {k: rows[k] for k in main}
    out["against_wall_other"] = {
        k.removeprefix("against_wall/"): v for k, v in rows.items() if k not in out
    }
    return out

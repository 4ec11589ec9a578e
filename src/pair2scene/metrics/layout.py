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
- ``in_corner``: the same floor objects standing against two walls at once, in a corner
  of the room (:func:`pair2scene.scene.walls.in_corner`: any two faces within 0.15 m of
  two walls), pooled and per category (``in_corner/<category>``, the section's
  ``in_corner_by_category``): real kitchens put 0.86 of their counters and 0.87 of their
  fridges in a corner, real bedrooms 0.82 of their dressers.
- ``chairs_facing_table``: chairs (:data:`CHAIRS`) with a table (:data:`TABLES`) within
  :data:`TABLE_NEAR_M` (footprint to footprint) whose front points at the nearest such
  table: the angle between the chair's +y and the direction from its centre to the
  nearest point of the table's footprint is below :data:`FACING_MAX_DEG`.
- ``tables_with_a_chair`` and ``tables_seating_four``: dining tables (:data:`DINING_TABLES`)
  with at least one chair at them, and with four or more: a chair is at the table
  (:data:`TABLES`) nearest it, when that is within :data:`TABLE_NEAR_M`, whichever way it
  faces (:func:`chairs_per_table`). The training rooms' dining tables: 0.83 / 0.32 in
  kitchens, 0.46 / 0.21 in living rooms, 1.00 / 0.30 in bedrooms.
- ``sofas_facing_tv``: sofas in a room with a television or a TV stand (:data:`SCREENS`)
  whose front points at one of them (angle to the direction of its centre below
  :data:`FACING_MAX_DEG`).
- ``sofas_with_coffee_table``: sofas in a room with a coffee table that have one in front
  of them (:func:`in_front`, within :data:`COFFEE_TABLE_FRONT_M`). The training rooms:
  0.88 of 25 sofas, the val rooms 0.71 of 7 (AI2-THOR + ProcTHOR-1k living rooms).
- ``nightstands_at_bed_head``: nightstands (side tables, :data:`NIGHTSTANDS`) in a room
  with a bed, that stand beside the head end of a bed (:func:`beside_bed_head`).
- ``floor_overlaps``: floor objects standing over or under another floor object's
  footprint, by more than :data:`~pair2scene.curation.stats.FLOOR_OVERLAP_SHARE` of the
  smaller one's (:func:`~pair2scene.curation.stats.footprint_overlap`), out of the floor
  objects: a side table under a dining table's edge, a lamp inside an armchair's
  outline. Seats tucked under what they are pulled up to (:data:`TUCKED`) are not
  counted: real rooms are full of them.
- ``floor_askew``: floor objects turned more than 5 degrees off the walls' axes (every 90
  degrees; :func:`~pair2scene.curation.stats.askew_bin`), out of the floor objects: real
  rooms leave chairs as pulled out and turn armchairs, lamps and plants to the room (0.22
  of the val living rooms' floor objects, 62 of 280).
- ``floor_isolated``: floor objects standing alone in the room, further than 0.5 m from
  every wall and every other floor object
  (:func:`~pair2scene.scene.relations.stands_alone`), out of the floor objects: in real
  rooms a basketball or a dog bed, never a side table or a house plant.
- ``rooms_sparse`` / ``rooms_crowded``: rooms whose floor objects' footprints cover less
  than :data:`SPARSE_SHARE` (0.12) / more than :data:`CROWDED_SHARE` (0.35) of the floor
  (:func:`floor_share`), out of the rooms: a large room with a small set of furniture, or
  a small room packed full.

Only floor objects take part (:func:`on_floor`) — except televisions, which may hang on
a wall or stand on their stand — and never structure or parts of furniture.
"""

from __future__ import annotations

from collections.abc import Iterable, Sequence

import numpy as np

from pair2scene.categories import BY_NAME, SuperCategory
from pair2scene.curation.stats import askew_bin, footprint_share, one_over_another
from pair2scene.scene.geometry import OrientedBox
from pair2scene.scene.model import FLOOR, Scene, SceneObject
from pair2scene.scene.relations import (
    FACING_MAX_DEG,
    alone_in_room,
    angle_to_footprint,
    facing_angle,
    footprint,
    footprint_gap,
)
from pair2scene.scene.walls import against_wall, in_corner, walls_of

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
TABLES = ("dining_table", "desk", "dressing_table")
"""What a chair is pulled up to: dining tables, desks and dressing tables. Coffee tables
are not sat at; counters are for stools; a side table stands *beside* a seat: of the
chairs whose nearest table within 1 m is a side table, 1 of 7 faces it in the training
rooms (AI2-THOR + ProcTHOR-1k train) and 0 of 2 in the val rooms, against 712 of 730 at
dining tables and desks."""
TUCKED = (("chair", "stool"), ("dining_table", "desk", "dressing_table", "counter_top"))
"""Seats, and what they tuck under: pairs of these overlap in real rooms (691 chairs under
dining tables and 19 under desks in the curated training rooms) and are not counted by
``floor_overlaps``."""
DINING_TABLES = ("dining_table",)
"""Tables whose chairs are counted (``tables_with_a_chair``, ``tables_seating_four``);
desks and dressing tables take one chair, if any."""
SEATS_FOUR = 4
"""Chairs at a table that make it a full one (``tables_seating_four``)."""
SCREENS = ("television", "tv_stand")
"""What a sofa faces: the television, or its stand when the room has no TV object."""
COFFEE_TABLE_FRONT_M = 2.0
"""How far ahead of a sofa's front a coffee table's centre may stand to be in front of it:
the training rooms' stood 0.6-1.6 m from the sofa's box in 24 of the 29 in front."""
FRONT_SIDE_M = 0.3
"""... and how far past the sofa's ends, sideways."""
NIGHTSTANDS = ("side_table",)
"""Nightstands: the canonical vocabulary files them under ``side_table``; in a room with
a bed, every side table is looked at."""
BEDS = ("bed",)
FLOOR_TOLERANCE_M = 0.02
"""With no support known, an object whose bottom is this close to the floor stands on it."""
TABLE_NEAR_M = 1.0
"""A chair with a table's footprint this close to its own (gap, m) is at that table."""
BED_SIDE_MARGIN_M = 0.1
"""A nightstand's centre must lie beyond the bed's side less this margin (it may overlap
the bed's box a little: the box includes the overhang of a duvet)..."""
BED_SIDE_REACH_M = 0.6
"""... and at most this far beyond the side (m)..."""
BED_HEAD_MARGIN_M = 0.3
"""... and in the head half of the bed: between its centre and this far behind its
headboard (local y from -(half length + margin) to 0; the headboard is at -y)."""

SPARSE_SHARE = 0.12
"""A room whose floor objects' footprints cover less of its floor than this is sparse. The
AI2-THOR + ProcTHOR-1k train rooms: 0.04 of the bedrooms, 0.08 of the living rooms, 0.09
of the kitchens (val 0.08 / 0.13 / 0.10)."""
CROWDED_SHARE = 0.35
"""... and more than this, crowded: train 0.15 / 0.09 / 0.15 (val 0.11 / 0.16 / 0.28), near
the rooms' 95th percentiles that generation holds a room under
(:data:`~pair2scene.assembly.rooms.MAX_FLOOR_SHARE`, 0.4)."""

MEASURES = (
    "against_wall",
    "in_corner",
    "chairs_facing_table",
    "tables_with_a_chair",
    "tables_seating_four",
    "sofas_facing_tv",
    "sofas_with_coffee_table",
    "nightstands_at_bed_head",
    "floor_overlaps",
    "floor_askew",
    "floor_isolated",
    "rooms_sparse",
    "rooms_crowded",
)
"""The pooled measures, in the order they are reported."""
_SKIPPED = (SuperCategory.STRUCTURE, SuperCategory.PART)


# -- which objects ---------------------------------------------------------------------
def counted(o: SceneObject) -> bool:
    """Whether ``o`` takes part in the measures: not structure, not a part of furniture."""
    cat = BY_NAME.get(o.category)
    return o.part_of is None and (cat is None or cat.super not in _SKIPPED)


def on_floor(o: SceneObject, floor_z: float = 0.0) -> bool:
    """Whether ``o`` stands on the floor: its support is the floor, or (support unknown)
    its bottom is within :data:`FLOOR_TOLERANCE_M` of it."""
    if o.support is not None:
        return o.support == FLOOR
    return o.box.bottom <= floor_z + FLOOR_TOLERANCE_M


def _floor_objects(scene: Scene) -> list[SceneObject]:
    return [o for o in scene.objects if counted(o) and on_floor(o)]


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
    """category -> [against a wall, floor objects, in a corner] over the room's floor
    objects."""
    walls = walls_of(scene.room.floor_polygon)
    out: dict[str, list[int]] = {}
    for o in _floor_objects(scene):
        row = out.setdefault(o.category, [0, 0, 0])
        row[0] += against_wall(o.box, walls)
        row[1] += 1
        row[2] += in_corner(o.box, walls)
    return dict(sorted(out.items()))


def _chairs_at_tables(floor: list[SceneObject]):
    """(table objects, [(chair, index of the table it is at)]): each chair at its nearest
    table (:data:`TABLES`) within :data:`TABLE_NEAR_M`, footprint to footprint."""
    tables = [o for o in floor if o.category in TABLES]
    prints = [footprint(t.box) for t in tables]
    at = []
    for chair in (o for o in floor if o.category in CHAIRS) if tables else ():
        mine = footprint(chair.box)
        gaps = [footprint_gap(mine, t) for t in prints]
        k = int(np.argmin(gaps))
        if gaps[k] <= TABLE_NEAR_M:
            at.append((chair, k))
    return tables, at


def chairs_facing_table(scene: Scene) -> list[int]:
    """[facing their table, chairs with a table within :data:`TABLE_NEAR_M`]."""
    tables, at = _chairs_at_tables(_floor_objects(scene))
    facing = sum(angle_to_footprint(c.box, footprint(tables[k].box)) < FACING_MAX_DEG
                 for c, k in at)  # fmt: skip
    return [int(facing), len(at)]


def chairs_per_table(scene: Scene) -> list[int]:
    """Chairs at each dining table of the room (:data:`DINING_TABLES`; see
    :func:`_chairs_at_tables`), in the room's order of its tables."""
    tables, at = _chairs_at_tables(_floor_objects(scene))
    counts = [0] * len(tables)
    for _, k in at:
        counts[k] += 1
    return [n for n, t in zip(counts, tables) if t.category in DINING_TABLES]


def sofas_facing_tv(scene: Scene) -> list[int]:
    """[facing a TV or TV stand, sofas in a room that has one]."""
    screens = [o for o in scene.objects if counted(o) and o.category in SCREENS]
    if not screens:
        return [0, 0]
    sofas = [o for o in _floor_objects(scene) if o.category == "sofa"]
    facing = sum(
        any(facing_angle(s.box, t.box.center[:2]) < FACING_MAX_DEG for t in screens) for s in sofas
    )
    return [int(facing), len(sofas)]


def in_front(box: OrientedBox, point: np.ndarray, reach: float, side: float) -> bool:
    """Whether ``point`` (3,) lies ahead of ``box``'s front, by at most ``reach``, and
    beside it by at most ``side`` past either end (in the box's frame: +y its front; its
    height is not looked at)."""
    x, y, _ = box.to_local(np.asarray(point, float)[None])[0]
    hw, hd = box.half_size[0], box.half_size[1]
    return bool(0.0 < y - hd <= reach and abs(x) <= hw + side)


def sofas_with_coffee_table(scene: Scene) -> list[int]:
    """[with a coffee table in front, sofas in a room that has a coffee table]."""
    floor = _floor_objects(scene)
    tables = [o.box.center for o in floor if o.category == "coffee_table"]
    if not tables:
        return [0, 0]
    sofas = [o.box for o in floor if o.category == "sofa"]
    near = sum(
        any(in_front(s, t, COFFEE_TABLE_FRONT_M, FRONT_SIDE_M) for t in tables) for s in sofas
    )
    return [int(near), len(sofas)]


def nightstands_at_bed_head(scene: Scene) -> list[int]:
    """[beside the head end of a bed, nightstands in a room with a bed]."""
    floor = _floor_objects(scene)
    beds = [o.box for o in floor if o.category in BEDS]
    if not beds:
        return [0, 0]
    stands = [o for o in floor if o.category in NIGHTSTANDS]
    ok = sum(any(beside_bed_head(n.box, b) for b in beds) for n in stands)
    return [int(ok), len(stands)]


def _tucked(a: str, b: str) -> bool:
    seats, tables = TUCKED
    return (a in seats and b in tables) or (b in seats and a in tables)


def floor_overlaps(scene: Scene) -> list[int]:
    """[floor objects over or under another's footprint (seats under tables excepted),
    floor objects]."""
    floor = _floor_objects(scene)
    over = set()
    for i, j in one_over_another([footprint(o.box) for o in floor]):
        if not _tucked(floor[i].category, floor[j].category):
            over.update((i, j))
    return [len(over), len(floor)]


def floor_askew(scene: Scene) -> list[int]:
    """[floor objects turned off the walls' axes by more than 5 degrees, floor objects]."""
    floor = _floor_objects(scene)
    return [sum(askew_bin(o.box.yaw) > 0 for o in floor), len(floor)]


def floor_isolated(scene: Scene) -> list[int]:
    """[floor objects standing alone in the room, floor objects]."""
    floor = _floor_objects(scene)
    alone = alone_in_room([footprint(o.box) for o in floor], scene.room.floor_polygon)
    return [sum(alone), len(floor)]


def floor_share(scene: Scene) -> float | None:
    """How much of the room's floor its floor objects' footprints cover (box width x depth,
    summed; overlaps counted twice); None for a room without floor area."""
    if abs(scene.room.area) <= 0:
        return None
    return footprint_share(scene.room, _floor_objects(scene))


def rooms_by_share(scene: Scene) -> tuple[list[int], list[int]]:
    """([sparse, 1], [crowded, 1]) of the room by :func:`floor_share`
    (:data:`SPARSE_SHARE`, :data:`CROWDED_SHARE`); ([0, 0], [0, 0]) without floor area."""
    share = floor_share(scene)
    if share is None:
        return [0, 0], [0, 0]
    return [int(share < SPARSE_SHARE), 1], [int(share > CROWDED_SHARE), 1]


def layout_measures(scene: Scene) -> dict[str, list[int]]:
    """Every measure of one room as [numerator, denominator]: the pooled ones of
    :data:`MEASURES` and ``against_wall/<category>`` for each floor category."""
    walls = against_wall_counts(scene)
    seats = chairs_per_table(scene)
    pooled, corners = [0, 0], [0, 0]
    for cat in WALL_FURNITURE:
        n, d, c = walls.get(cat, (0, 0, 0))
        pooled[0] += n
        pooled[1] += d
        corners[0] += c
        corners[1] += d
    out = {
        "against_wall": pooled,
        "in_corner": corners,
        "chairs_facing_table": chairs_facing_table(scene),
        "tables_with_a_chair": [sum(n > 0 for n in seats), len(seats)],
        "tables_seating_four": [sum(n >= SEATS_FOUR for n in seats), len(seats)],
        "sofas_facing_tv": sofas_facing_tv(scene),
        "sofas_with_coffee_table": sofas_with_coffee_table(scene),
        "nightstands_at_bed_head": nightstands_at_bed_head(scene),
        "floor_overlaps": floor_overlaps(scene),
        "floor_askew": floor_askew(scene),
        "floor_isolated": floor_isolated(scene),
    }
    out["rooms_sparse"], out["rooms_crowded"] = rooms_by_share(scene)
    out.update({f"against_wall/{cat}": [n, d] for cat, (n, d, _) in walls.items()})
    out.update({f"in_corner/{cat}": [c, d] for cat, (_, d, c) in walls.items()})
    return out


def stat(num: int, den: int, rooms: int) -> dict:
    """A measure's pooled stat: its rate (None when nothing was measurable), counts and
    the number of rooms it was measurable in."""
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
    return {key: stat(*sums[key]) for key in _ordered(sums)}


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
    empty = stat(0, 0, 0)
    keys = _ordered(set(gen) | set(ref) | {f"{p}/{c}" for c in WALL_FURNITURE
                                           for p in ("against_wall", "in_corner")})  # fmt: skip
    rows = {k: {"generated": gen.get(k, empty), "reference": ref.get(k, empty)} for k in keys}
    main = [*MEASURES, *(f"against_wall/{c}" for c in WALL_FURNITURE)]
    out = {k: rows[k] for k in main}
    corner = {k: v for k, v in rows.items() if k.startswith("in_corner/")}
    out["against_wall_other"] = {
        k.removeprefix("against_wall/"): v for k, v in rows.items()
        if k not in out and k not in corner
    }  # fmt: skip
    out["in_corner_by_category"] = {
        k.removeprefix("in_corner/"): corner.get(k, {"generated": empty, "reference": empty})
        for k in (f"in_corner/{c}" for c in WALL_FURNITURE)
    }
    return out

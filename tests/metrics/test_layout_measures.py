"""Layout realism measures on hand-built rooms with known answers, and their place in the
evaluation report."""

from __future__ import annotations

import json

import numpy as np
import pytest

from clitools import run_cli
from pair2scene.metrics.layout import (
    WALL_FURNITURE,
    against_wall_counts,
    beside_bed_head,
    chairs_facing_table,
    chairs_per_table,
    floor_askew,
    floor_isolated,
    floor_share,
    layout_measures,
    layout_report,
    nightstands_at_bed_head,
    on_floor,
    sofas_facing_tv,
    sofas_with_coffee_table,
)
from pair2scene.scene.geometry import OrientedBox
from pair2scene.scene.model import FLOOR, Room, Scene, SceneObject
from pair2scene.scene.relations import (
    facing_angle,
    footprint,
    footprint_gap,
    nearest_point,
    stands_alone,
    wall_gap,
)

SQUARE = np.array([[0, 0], [4, 0], [4, 4], [0, 4]], float)
L_SHAPE = np.array([[0, 0], [4, 0], [4, 2], [2, 2], [2, 4], [0, 4]], float)
"""4 x 4 m with its top-right quarter cut out: two walls meet at the reflex corner (2, 2)."""
BED = [1.6, 2.0, 0.6]
EAST, NORTH, WEST, SOUTH = -np.pi / 2, 0.0, np.pi / 2, np.pi
"""Yaws that turn an object's front (+y) to face +x, +y, -x, -y."""


def obj(oid, cat, xy, size, yaw=0.0, support=FLOOR, z=None, **kw) -> SceneObject:
    center = [xy[0], xy[1], size[2] / 2 if z is None else z]
    return SceneObject(oid, cat, OrientedBox.from_yaw(center, size, yaw), support=support, **kw)


def room(*objects, polygon=SQUARE, kind="bedroom", sid="s") -> Scene:
    return Scene(sid, Room(kind, polygon, 2.7), list(objects))


# -- against a wall --------------------------------------------------------------------
def test_a_bed_against_a_wall_mid_room_and_facing_the_wall():
    against = obj("b1", "bed", [2, 1.05], BED)  # headboard 5 cm off the wall y = 0
    middle = obj("b2", "bed", [2, 2], BED)
    facing_wall = obj("b3", "bed", [2, 1.05], BED, yaw=SOUTH)  # its foot at the wall
    assert against_wall_counts(room(against)) == {"bed": [1, 1, 0]}
    assert against_wall_counts(room(middle)) == {"bed": [0, 1, 0]}
    assert against_wall_counts(room(facing_wall)) == {"bed": [0, 1, 0]}
    # turned to the east wall x = 4, 10 cm off it
    east = obj("b4", "bed", [4 - 1.0 - 0.1, 2], BED, yaw=WEST)
    assert against_wall_counts(room(east)) == {"bed": [1, 1, 0]}


def test_per_category_and_pooled_over_the_wall_furniture():
    scene = room(
        obj("bed", "bed", [2, 1.05], BED),  # against
        obj("dresser", "dresser", [2, 2.5], [1.2, 0.5, 0.8]),  # mid-room
        obj("wardrobe", "wardrobe", [0.32, 3], [1.0, 0.6, 2.0], yaw=WEST),  # faces the wall
        obj("chair", "chair", [3.75, 3.75], [0.45, 0.45, 0.9], yaw=SOUTH),  # not wall furniture
        obj("drawer", "drawer", [2, 2.5], [0.5, 0.4, 0.2], part_of="dresser", support=None),
    )
    m = layout_measures(scene)
    assert m["against_wall"] == [1, 3]
    assert m["against_wall/bed"] == [1, 1] and m["against_wall/dresser"] == [0, 1]
    assert m["against_wall/wardrobe"] == [0, 1] and m["against_wall/chair"] == [1, 1]
    assert "against_wall/drawer" not in m
    assert {"bed", "sofa", "dresser", "wardrobe", "fridge", "counter_top"} <= set(WALL_FURNITURE)


def test_only_floor_objects_count():
    on_it = obj("d", "dresser", [2, 0.3], [1.2, 0.5, 0.8], support="platform")
    unknown_low = obj("b", "bed", [2, 1.05], BED, support=None, z=0.31)  # 1 cm up
    unknown_high = obj("f", "fridge", [3.6, 0.35], [0.7, 0.7, 1.8], support=None, z=1.0)
    assert not on_floor(on_it) and on_floor(unknown_low) and not on_floor(unknown_high)
    assert against_wall_counts(room(on_it, unknown_low, unknown_high)) == {"bed": [1, 1, 0]}


def test_l_shaped_room_walls_at_the_reflex_corner():
    # the bed's back against the wall (4, 2) -> (2, 2) from below, facing -y
    bed = obj("bed", "bed", [3, 2 - 0.9 - 0.05], [1.6, 1.8, 0.6], yaw=SOUTH)
    # a dresser's back against the wall (2, 2) -> (2, 4) from the west, facing -x
    dresser = obj("dresser", "dresser", [2 - 0.25 - 0.03, 3], [1.2, 0.5, 0.8], yaw=WEST)
    # a shelving unit in the cut-out corner's diagonal, 0.5 m from both walls
    shelf = obj("shelf", "shelving_unit", [1.2, 1.2], [0.8, 0.3, 1.8], yaw=np.pi / 4)
    counts = against_wall_counts(room(bed, dresser, shelf, polygon=L_SHAPE))
    assert counts == {"bed": [1, 1, 0], "dresser": [1, 1, 0], "shelving_unit": [0, 1, 0]}
    # the same bed in the square room stands mid-room: the L's walls are what it touches
    assert against_wall_counts(room(bed)) == {"bed": [0, 1, 0]}


def test_in_a_corner_takes_two_walls_and_not_the_inner_corner_of_an_l():
    fridge = obj("f", "fridge", [4 - 0.35 - 0.05, 4 - 0.35 - 0.05], [0.7, 0.7, 1.8], yaw=SOUTH)
    counter = obj("c", "counter_top", [2, 0.3], [1.2, 0.6, 0.9])  # back to y = 0 only
    chair = obj("ch", "chair", [0.3, 0.3], CHAIR_SIZE)  # a corner, but no wall furniture
    m = layout_measures(room(fridge, counter, chair, kind="kitchen"))
    assert m["in_corner"] == [1, 2] and m["against_wall"] == [2, 2]
    assert m["in_corner/fridge"] == [1, 1] and m["in_corner/counter_top"] == [0, 1]
    assert m["in_corner/chair"] == [1, 1]
    # in the L, a dresser pushed into the inner corner (2, 2) from below-left touches
    # both of its walls only from outside the room: it stands against one
    dresser = obj("d", "dresser", [0.62, 3.73], [1.2, 0.5, 0.8], yaw=SOUTH)  # NW: a corner
    inner = obj("i", "dresser", [2.62, 1.73], [1.2, 0.5, 0.8], yaw=SOUTH)  # x = 2.02 .. 3.22
    counts = against_wall_counts(room(dresser, inner, polygon=L_SHAPE))
    assert counts == {"dresser": [2, 2, 1]}


# -- chairs at tables ------------------------------------------------------------------
CHAIR_SIZE = [0.45, 0.45, 0.9]
TABLE = obj("table", "dining_table", [2, 2], [1.2, 0.8, 0.75])
CHAIR = [0.45, 0.45, 0.9]


def test_chairs_facing_their_table_or_away():
    scene = room(
        TABLE,
        obj("c_south", "chair", [2, 1.25], CHAIR, yaw=NORTH),  # faces the table
        obj("c_east", "chair", [2.95, 2], CHAIR, yaw=WEST),  # faces the table
        obj("c_north", "chair", [2, 2.75], CHAIR, yaw=NORTH),  # turned away
        obj("c_far", "chair", [3.6, 3.6], CHAIR, yaw=SOUTH),  # 1.2 m off: at no table
    )
    assert chairs_facing_table(scene) == [2, 3]


@pytest.mark.parametrize("degrees, facing", [(0, True), (40, True), (50, False), (180, False)])
def test_facing_threshold_is_45_degrees(degrees, facing):
    chair = obj("c", "chair", [2, 1.25], CHAIR, yaw=np.radians(degrees))
    assert chairs_facing_table(room(TABLE, chair)) == [int(facing), 1]


def test_a_chair_under_the_table_faces_its_centre_and_other_seats_do_not_count():
    tucked = obj("c", "chair", [2, 1.7], CHAIR, yaw=NORTH)  # centre inside the footprint
    assert chairs_facing_table(room(TABLE, tucked)) == [1, 1]
    armchair = obj("a", "armchair", [2, 1.25], [0.8, 0.8, 0.9], yaw=SOUTH)
    assert chairs_facing_table(room(TABLE, armchair)) == [0, 0]
    coffee = obj("t", "coffee_table", [2, 2], [1.0, 0.6, 0.45])
    chair = obj("c", "chair", [2, 1.25], CHAIR, yaw=NORTH)
    assert chairs_facing_table(room(coffee, chair)) == [0, 0]
    assert chairs_facing_table(room(chair)) == [0, 0]


def test_a_chair_beside_a_side_table_is_at_no_table():
    """A side table stands beside a seat (the training rooms' chairs face theirs 1 time
    in 7): a chair next to one is not counted; with a dining table near as well, it is
    counted at the dining table, which it does not face."""
    side = obj("s", "side_table", [2, 2], [0.5, 0.5, 0.6])
    beside = obj("c", "chair", [2.6, 2], CHAIR, yaw=WEST)  # turned to the side table
    assert chairs_facing_table(room(side, beside)) == [0, 0]
    table = obj("t", "dining_table", [2, 3.05], [1.2, 0.8, 0.75])  # 0.4 m north of it
    assert chairs_facing_table(room(side, table, beside)) == [0, 1]


def test_the_nearest_table_is_the_one_faced():
    desk = obj("desk", "desk", [2, 0.4], [1.2, 0.6, 0.75])
    # 0.13 m from the desk, 0.33 m from the dining table: it is at the desk
    chair = obj("c", "chair", [2, 1.05], CHAIR, yaw=SOUTH)
    assert chairs_facing_table(room(TABLE, desk, chair)) == [1, 1]


def test_chairs_per_dining_table_whichever_way_they_face():
    """Four chairs round the dining table (one turned away: still at it), one at the desk
    beside it, one across the room: the table seats four, the desk is not counted."""
    desk = obj("desk", "desk", [0.7, 0.4], [1.2, 0.6, 0.75])
    chairs = [
        obj("n", "chair", [2, 2.75], CHAIR, yaw=SOUTH),
        obj("s", "chair", [2, 1.25], CHAIR, yaw=SOUTH),  # turned away, at the table
        obj("e", "chair", [2.95, 2], CHAIR, yaw=WEST),
        obj("w", "chair", [1.05, 2], CHAIR, yaw=EAST),
        obj("d", "chair", [0.7, 0.95], CHAIR, yaw=SOUTH),  # at the desk
        obj("far", "chair", [3.7, 3.7], CHAIR),  # 1.1 m off: at none
    ]
    assert chairs_per_table(room(TABLE, desk, *chairs)) == [4]
    assert chairs_per_table(room(TABLE, desk, *chairs[4:])) == [0]
    assert chairs_per_table(room(desk, *chairs)) == []  # no dining table: none measured
    measures = layout_measures(room(TABLE, desk, *chairs[1:]))
    assert measures["tables_with_a_chair"] == [1, 1]
    assert measures["tables_seating_four"] == [0, 1]  # three left at it


# -- sofas and TVs ---------------------------------------------------------------------
def test_a_sofa_facing_the_tv_stand_and_one_facing_away():
    stand = obj("tv", "tv_stand", [2, 0.25], [1.2, 0.45, 0.5])
    facing = obj("s1", "sofa", [2, 3.5], [2.0, 0.9, 0.8], yaw=SOUTH)
    away = obj("s2", "sofa", [0.5, 2], [2.0, 0.9, 0.8], yaw=WEST)  # faces the west wall
    assert sofas_facing_tv(room(stand, facing, away, kind="living_room")) == [1, 2]
    assert sofas_facing_tv(room(facing, away, kind="living_room")) == [0, 0]  # no TV
    # a television on the east wall (no support, 1.2 m up) counts as well
    tv = obj("tv2", "television", [3.95, 2], [1.0, 0.05, 0.6], yaw=WEST, support=None, z=1.2)
    east = obj("s3", "sofa", [2.2, 2], [2.0, 0.9, 0.8], yaw=EAST)
    assert sofas_facing_tv(room(tv, east, away, kind="living_room")) == [1, 2]


def test_a_coffee_table_in_front_of_one_sofa_behind_another_and_too_far():
    """A sofa against the south wall facing north (front +y): a table 1.0 m ahead of its
    front counts; the same table is behind a sofa facing south, and 2.6 m ahead of a
    third; past a sofa's end by more than 0.3 m it is beside, not in front."""
    table = obj("t", "coffee_table", [2, 2], [1.0, 0.6, 0.45])
    north = obj("s1", "sofa", [2, 0.55], [2.0, 0.9, 0.8], yaw=NORTH)  # front at y = 1.0
    south = obj("s2", "sofa", [2, 1.0], [2.0, 0.9, 0.8], yaw=SOUTH)  # table behind it
    assert sofas_with_coffee_table(room(table, north, kind="living_room")) == [1, 1]
    assert sofas_with_coffee_table(room(table, south, kind="living_room")) == [0, 1]
    far = obj("t2", "coffee_table", [2, 3.65], [1.0, 0.6, 0.45])  # 2.65 m ahead
    assert sofas_with_coffee_table(room(far, north, kind="living_room")) == [0, 1]
    aside = obj("t3", "coffee_table", [3.4, 1.6], [0.5, 0.5, 0.45])  # 0.4 m past its end
    assert sofas_with_coffee_table(room(aside, north, kind="living_room")) == [0, 1]
    assert sofas_with_coffee_table(room(north, kind="living_room")) == [0, 0]  # no table
    assert layout_measures(room(table, north, south))["sofas_with_coffee_table"] == [1, 2]


# -- nightstands -----------------------------------------------------------------------
STAND = [0.5, 0.4, 0.55]


def test_nightstands_at_the_head_end_and_at_the_foot_end():
    bed = obj("bed", "bed", [2, 1.05], BED)  # headboard at y = 0.05
    head = obj("n1", "side_table", [2 - 0.8 - 0.3, 0.3], STAND)
    foot = obj("n2", "side_table", [3.1, 1.8], STAND)
    far = obj("n3", "side_table", [3.9, 0.3], STAND)  # 1.1 m beyond the side
    assert nightstands_at_bed_head(room(bed, head, foot, far)) == [1, 3]
    assert nightstands_at_bed_head(room(head, foot)) == [0, 0]  # no bed: nothing measured


def test_nightstand_in_a_turned_bed_frame():
    bed = OrientedBox.from_yaw([2.95, 2, 0.3], BED, WEST)  # headboard at the east wall
    assert beside_bed_head(OrientedBox.from_yaw([3.7, 3.1, 0.275], STAND), bed)
    assert beside_bed_head(OrientedBox.from_yaw([3.7, 0.9, 0.275], STAND), bed)
    assert not beside_bed_head(OrientedBox.from_yaw([2.2, 3.1, 0.275], STAND), bed)  # foot
    assert not beside_bed_head(OrientedBox.from_yaw([3.3, 2.0, 0.275], STAND), bed)  # on it


# -- geometry helpers ------------------------------------------------------------------
def test_floor_objects_turned_off_the_walls_axes():
    """A chair left 12 degrees off, one turned a full quarter and one 4 degrees off (square),
    an armchair at 40 degrees (-50 from the next axis) and a book on the table (not on the
    floor): two of four floor objects are askew."""
    scene = room(
        obj("c1", "chair", [1, 1], [0.45, 0.45, 0.9], yaw=np.radians(12)),
        obj("c2", "chair", [2, 1], [0.45, 0.45, 0.9], yaw=np.radians(90)),
        obj("c3", "chair", [3, 1], [0.45, 0.45, 0.9], yaw=np.radians(-4)),
        obj("a1", "armchair", [2, 3], [0.8, 0.8, 0.9], yaw=np.radians(40)),
        obj("bk", "book", [1, 1], [0.2, 0.15, 0.03], support="c1", z=0.5, yaw=0.3),
    )
    assert floor_askew(scene) == [2, 4]
    assert layout_measures(scene)["floor_askew"] == [2, 4]


def test_floor_objects_standing_alone_in_the_room():
    """In the 4 x 4 m room: a plant at the centre alone (1.8 m from the walls), a side
    table 0.45 m from a wall (not alone), two chairs 0.4 m apart mid-room (each has
    company), a book on a chair (not a floor object)."""
    scene = room(
        obj("p", "house_plant", [2.0, 2.0], [0.4, 0.4, 0.8]),
        obj("t", "side_table", [0.7, 3.0], [0.5, 0.5, 0.6]),
        obj("c1", "chair", [1.4, 1.0], [0.4, 0.4, 0.9]),
        obj("c2", "chair", [2.2, 1.0], [0.4, 0.4, 0.9]),
        obj("bk", "book", [1.4, 1.0], [0.2, 0.15, 0.03], support="c1", z=0.5),
    )
    assert floor_isolated(scene) == [1, 4]
    assert layout_measures(scene)["floor_isolated"] == [1, 4]
    lone = room(obj("p", "house_plant", [2.0, 2.0], [0.4, 0.4, 0.8]))
    assert floor_isolated(lone) == [1, 1]
    assert floor_isolated(room()) == [0, 0]


def test_rooms_sparse_and_crowded_by_their_floor_share():
    """In the 4 x 4 m room (16 m2): a 1.6 x 2.0 bed alone covers 0.2 of the floor, neither
    sparse nor crowded; a 1 x 1 cabinet alone 0.0625, sparse; bed, wardrobe, desk and
    dresser, turned or not, 6.13 m2 (0.38), crowded. A book on the bed and a painting on a wall
    cover nothing; the L-shaped room's floor is 12 m2."""
    bed = obj("b", "bed", [2, 1.05], BED)
    book = obj("bk", "book", [2, 1.05], [0.2, 0.15, 0.03], support="b", z=0.62)
    painting = obj("pa", "painting", [2, 0.02], [0.8, 0.04, 0.6], support="wall:0", z=1.5)
    scene = room(bed, book, painting)
    assert floor_share(scene) == pytest.approx(3.2 / 16)
    measures = layout_measures(scene)
    assert (measures["rooms_sparse"], measures["rooms_crowded"]) == ([0, 1], [0, 1])
    sparse = room(obj("c", "cabinet", [0.5, 0.5], [1.0, 1.0, 0.8]))
    assert floor_share(sparse) == pytest.approx(1 / 16)
    assert layout_measures(sparse)["rooms_sparse"] == [1, 1]
    full = room(bed, obj("w", "wardrobe", [3.5, 2], [2.0, 0.6, 2.0], yaw=EAST),
                obj("d", "desk", [1, 3.5], [1.4, 0.7, 0.75]),
                obj("dr", "dresser", [3, 3.7], [1.5, 0.5, 0.9]))  # fmt: skip
    assert floor_share(full) == pytest.approx(6.13 / 16)
    assert layout_measures(full)["rooms_crowded"] == [1, 1]
    assert floor_share(room(bed, polygon=L_SHAPE)) == pytest.approx(3.2 / 12)
    report = layout_report([scene, sparse, full])
    assert report["rooms_sparse"]["count"] == [1, 3]
    assert report["rooms_crowded"]["count"] == [1, 3]


def test_wall_gap_and_standing_alone_in_an_l_shaped_room():
    """The L's reflex corner (2, 2) is a wall too: a box 0.28 m from it has company."""
    near = footprint(OrientedBox.from_yaw([1.6, 1.6, 0.4], [0.4, 0.4, 0.8]))
    assert wall_gap(near, L_SHAPE) == pytest.approx(np.hypot(0.2, 0.2))  # (1.8, 1.8) to (2, 2)
    assert not stands_alone(near, L_SHAPE, [])
    mid = footprint(OrientedBox.from_yaw([1.0, 1.0, 0.4], [0.4, 0.4, 0.8]))
    assert wall_gap(mid, L_SHAPE) == pytest.approx(0.8)
    assert stands_alone(mid, L_SHAPE, [])
    assert not stands_alone(mid, L_SHAPE, [near])  # 0.2 m apart
    far = footprint(OrientedBox.from_yaw([2.8, 1.0, 0.4], [0.4, 0.4, 0.8]))  # 1.4 m off
    assert stands_alone(mid, L_SHAPE, [far])
    other = footprint(OrientedBox.from_yaw([1.0, 1.8, 0.4], [0.4, 0.4, 0.8]))  # 0.4 m off
    assert not stands_alone(mid, L_SHAPE, [far, other])
    assert stands_alone(mid, L_SHAPE, [other], gap=0.3)


def test_footprint_gap_and_nearest_point():
    a = footprint(OrientedBox.from_yaw([0, 0, 0.5], [2, 2, 1]))
    b = footprint(OrientedBox.from_yaw([3, 0, 0.5], [2, 2, 1], np.pi / 4))  # diamond
    assert footprint_gap(a, b) == pytest.approx(3 - 1 - np.sqrt(2))
    assert footprint_gap(a, footprint(OrientedBox.from_yaw([1.5, 0.5, 0.5], [2, 2, 1]))) == 0
    assert footprint_gap(b, a) == pytest.approx(footprint_gap(a, b))
    np.testing.assert_allclose(nearest_point(np.array([3.0, 0.5]), a), [1, 0.5])
    np.testing.assert_allclose(nearest_point(np.array([0.2, 0.1]), a), [0.2, 0.1])
    box = OrientedBox.from_yaw([0, 0, 0.5], [1, 1, 1], WEST)  # faces -x
    assert facing_angle(box, np.array([-1.0, 0.0])) == pytest.approx(0, abs=1e-9)
    assert facing_angle(box, np.array([0.0, 1.0])) == pytest.approx(90)


# -- pooled over scenes, and in the report ---------------------------------------------
def bedroom(sid: str, against: bool) -> Scene:
    y = 1.05 if against else 2.0
    return room(
        obj("bed", "bed", [2, y], BED),
        obj("ns", "side_table", [2 - 0.8 - 0.3, y - 0.75], STAND),
        sid=sid,
    )


def test_pooled_rates_come_from_summed_counts():
    kitchen = room(TABLE, obj("c", "chair", [2, 1.25], CHAIR), kind="kitchen", sid="k")
    report = layout_report([bedroom("a", True), bedroom("b", False), kitchen])
    assert report["against_wall"] == {"rate": 0.5, "count": [1, 2], "rooms": 2}
    assert report["against_wall/bed"] == {"rate": 0.5, "count": [1, 2], "rooms": 2}
    assert report["chairs_facing_table"] == {"rate": 1.0, "count": [1, 1], "rooms": 1}
    assert report["nightstands_at_bed_head"] == {"rate": 1.0, "count": [2, 2], "rooms": 2}
    assert report["sofas_facing_tv"] == {"rate": None, "count": [0, 0], "rooms": 0}


def write_set(folder, scenes):
    from pair2scene.io.scene_json import write_scene

    for s in scenes:
        write_scene(s, folder / s.id / "scene.json")
    return folder


def test_evaluate_reports_the_layout_section_for_both_sides(tmp_path):
    from pair2scene.evaluate import evaluate

    gen = write_set(tmp_path / "gen", [bedroom("g0", False), bedroom("g1", True)])
    ref = write_set(tmp_path / "ref", [bedroom(f"r{i}", True) for i in range(3)])
    out = tmp_path / "report.json"
    report = evaluate(gen, [str(ref)], out, physics=False, images=False, progress=False)
    assert json.loads(out.read_text()) == report
    layout = report["layout"]
    assert layout["against_wall/bed"]["generated"] == {"rate": 0.5, "count": [1, 2], "rooms": 2}
    assert layout["against_wall/bed"]["reference"] == {"rate": 1.0, "count": [3, 3], "rooms": 3}
    assert layout["nightstands_at_bed_head"]["reference"]["count"] == [3, 3]
    assert layout["sofas_facing_tv"]["generated"]["rate"] is None
    assert layout["against_wall_other"]["side_table"]["generated"]["count"][1] == 2
    for key in ("collision_rate", "category_kl", "pose_mmd", "fid", "details"):
        assert key in report  # the existing keys stay

    proc = run_cli("evaluate", "--scenes", str(gen), "--reference", str(ref), "--out",
                   str(out), "--no-physics", "--no-images")  # fmt: skip
    assert proc.returncode == 0, proc.stderr
    assert "layout" in proc.stdout and "generated" in proc.stdout
    line = next(s for s in proc.stdout.splitlines() if "against_wall/bed" in s)
    assert "0.50 (1/2)" in line and "1.00 (3/3)" in line
    assert "sofas_facing_tv" not in proc.stdout  # measurable on neither side

"""Corners (objects against two walls, as a kitchen's counters and fridge stand) and the
walls an object with a functional anchor can reach from."""

from __future__ import annotations

import numpy as np
import pytest

from pair2scene.assembly.walls import WallRules, to_corners, within_reach
from pair2scene.curation.stats import HierarchyStats
from pair2scene.scene.geometry import OrientedBox
from pair2scene.scene.model import FLOOR, Room, Scene, SceneObject
from pair2scene.scene.walls import convex_ends, in_corner, walls_of

RECT = np.array([[0, 0], [4, 0], [4, 3], [0, 3]], float)
L_SHAPE = np.array([[0, 0], [4, 0], [4, 2], [2, 2], [2, 4], [0, 4]], float)


def test_convex_ends_leave_out_the_inner_corner_of_an_l_shaped_room():
    assert convex_ends(walls_of(RECT)) == {i: (True, True) for i in range(4)}
    ends = convex_ends(walls_of(L_SHAPE))
    # walls 2 ((4,2)->(2,2)) and 3 ((2,2)->(2,4)) meet at the inner corner (2,2)
    assert ends[2] == (True, False) and ends[3] == (False, True)
    assert ends[0] == ends[1] == ends[4] == ends[5] == (True, True)


def test_in_corner_needs_two_walls():
    walls = walls_of(RECT)
    fridge = OrientedBox.from_yaw([3.6, 2.6, 0.9], [0.8, 0.8, 1.8], np.pi)  # NE corner
    assert in_corner(fridge, walls)
    middle = OrientedBox.from_yaw([2.0, 2.6, 0.9], [0.8, 0.8, 1.8], np.pi)  # north wall only
    assert not in_corner(middle, walls)


def test_to_corners_slides_along_the_wall_into_the_nearer_convex_corner_first():
    walls = walls_of(RECT)
    north = walls[2]  # (4,3) -> (0,3): its start is the NE corner, its end the NW one
    box = OrientedBox.from_yaw([2.7, 2.6, 0.9], [0.8, 0.8, 1.8], np.pi)
    (e0, east), (e1, west) = to_corners(box, north, (True, True))
    assert (e0, e1) == (0, 1)
    assert east.center[0] == pytest.approx(4 - 0.4 - 0.005)
    assert west.center[0] == pytest.approx(0.4 + 0.005)
    assert east.center[1] == pytest.approx(2.6) and east.center[2] == pytest.approx(0.9)
    assert in_corner(east, walls) and in_corner(west, walls)
    ((end, only),) = to_corners(box, north, (False, True))  # the NE end is no corner
    assert end == 1 and only.center[0] == pytest.approx(0.4 + 0.005)
    assert to_corners(box, north, (False, False)) == []
    long = OrientedBox.from_yaw([2.0, 2.6, 0.5], [4.5, 0.8, 1.0], np.pi)
    assert to_corners(long, north, (True, True)) == []  # longer than the wall


def test_within_reach_keeps_a_chair_at_its_table_off_walls_it_cannot_reach_from():
    walls = walls_of(RECT)
    mid = OrientedBox.from_yaw([2.0, 1.5, 0.4], [1.2, 0.8, 0.75], 0.0)  # mid-room table
    assert not any(within_reach(w, mid, 0.5, 0.3, 0.45, facing=True) for w in walls)
    # a table 0.6 m off the west wall (its end): a chair 0.5 deep fits between and faces it
    west_table = OrientedBox.from_yaw([1.2, 1.5, 0.4], [1.2, 0.8, 0.75], 0.0)
    reach = [within_reach(w, west_table, 0.5, 0.3, 0.45, facing=True) for w in walls]
    assert reach == [False, False, False, True]
    # 0.3 m off: a facing chair does not fit, one standing beside (not facing) does
    tight = OrientedBox.from_yaw([0.9, 1.5, 0.4], [1.2, 0.8, 0.75], 0.0)
    assert not within_reach(walls[3], tight, 0.5, 0.3, 0.45, facing=True)
    assert within_reach(walls[3], tight, 0.5, 0.3, 0.45, facing=False)


def _kitchen(i: int) -> Scene:
    room = Room("kitchen", RECT)
    fridge = OrientedBox.from_yaw([3.6, 2.6, 0.9], [0.8, 0.8, 1.8], np.pi)  # corner
    counter = OrientedBox.from_yaw([2.0, 2.7, 0.45], [1.2, 0.6, 0.9], np.pi)  # wall only
    if i % 2:
        counter = OrientedBox.from_yaw([0.6, 2.7, 0.45], [1.2, 0.6, 0.9], np.pi)  # corner
    objects = [
        SceneObject("fridge_0", "fridge", fridge, None, FLOOR),
        SceneObject("counter_0", "counter_top", counter, None, FLOOR),
    ]
    return Scene(f"k{i}", room, objects)


def test_statistics_learn_corner_rates_that_round_trip():
    stats = HierarchyStats.fit([_kitchen(i) for i in range(4)])
    rs = stats.room_types["kitchen"]
    assert rs.against_wall["fridge"] == 4 and rs.in_corner["fridge"] == 4
    assert rs.against_wall["counter_top"] == 4 and rs.in_corner["counter_top"] == 2
    back = HierarchyStats.from_json(stats.to_json())
    assert back.room_types["kitchen"].in_corner == rs.in_corner
    rules = WallRules.from_stats(back)
    assert rules.corner_rate("kitchen", "fridge") == 1.0
    assert rules.corner_rate("kitchen", "counter_top") == 0.5
    assert rules.corner_rate("bedroom", "fridge") == 1.0  # pooled over room types
    draws = [rules.in_corner("kitchen", "counter_top", s) for s in range(400)]
    assert 0.4 < np.mean(draws) < 0.6
    assert draws == [rules.in_corner("kitchen", "counter_top", s) for s in range(400)]


def test_a_corner_missed_twice_is_not_tried_again_for_that_object():
    from pair2scene.assembly.place import CORNER_TRIES, _Context, _variants

    walls = walls_of(RECT)
    ctx = _Context(FLOOR, {}, Room("kitchen", RECT), (), (), [], None, None, None)
    ctx.wall, ctx.corner = walls[2], (True, True)
    box = OrientedBox.from_yaw([2.7, 2.6, 0.9], [0.8, 0.8, 1.8], np.pi)
    tags = [tag for tag, _ in _variants(box, ctx)]
    assert tags == [(2, 0), (2, 1), None]  # both corners, the nearer first, then as drawn
    ctx.corner_misses[(2, 0)] = CORNER_TRIES
    assert [tag for tag, _ in _variants(box, ctx)] == [(2, 1), None]
    ctx.corner_misses[(2, 1)] = CORNER_TRIES - 1
    assert [tag for tag, _ in _variants(box, ctx)] == [(2, 1), None]
    ctx.corner = None  # not a corner object: the drawn box alone
    ((tag, same),) = _variants(box, ctx)
    assert tag is None and same is box


def test_statistics_written_before_corner_counts_put_nothing_in_a_corner():
    doc = HierarchyStats.fit([_kitchen(i) for i in range(4)]).to_dict()
    for walls in (rd["walls"] for rd in doc["room_types"].values()):
        for row in walls.values():
            del row["in_corner"]
    old = HierarchyStats.from_dict(doc)
    assert old.room_types["kitchen"].against_wall["fridge"] == 4  # the wall counts stay
    rules = WallRules.from_stats(old)
    assert rules.corner_rate("kitchen", "fridge") == 0.0
    assert not any(rules.in_corner("kitchen", "fridge", s) for s in range(50))

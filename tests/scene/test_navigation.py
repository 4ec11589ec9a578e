"""Navigable rooms: free floor, reachability from the doors, fronts, door swings, and the
placement guard, on hand-built rooms with known answers."""

from __future__ import annotations

import numpy as np
import pytest

from pair2scene.errors import UserError
from pair2scene.scene.geometry import OrientedBox
from pair2scene.scene.model import FLOOR, Opening, Room, Scene, SceneObject
from pair2scene.scene.navigation import (
    FloorGuard,
    NavigationConfig,
    footprint_polygon,
    navigability,
    navigation_report,
)

SQUARE = np.array([[0, 0], [5, 0], [5, 5], [0, 5]], float)
DOOR = Opening("door", (2.0, 0.0), (3.0, 0.0), id="door0")  # bottom wall, x 2..3


def room(polygon=SQUARE, doors=(DOOR,)) -> Room:
    return Room("bedroom", polygon, doors=tuple(doors))


def obj(oid, center_xy, size_xy, yaw=0.0, height=1.0, category="wardrobe", support=FLOOR):
    box = OrientedBox.from_yaw([*center_xy, height / 2], [*size_xy, height], yaw)
    return SceneObject(oid, category, box, support=support)


def row(y: float, depth: float, x0: float, x1: float, prefix="w") -> list[SceneObject]:
    """Wardrobes side by side from x0 to x1, centred on y, facing +y."""
    n = max(int(round(x1 - x0)), 1)
    w = (x1 - x0) / n
    return [obj(f"{prefix}{i}", (x0 + (i + 0.5) * w, y), (w, depth)) for i in range(n)]


def test_empty_room_is_fully_reachable():
    nav = navigability(room(), [])
    assert nav.reachable_fraction == 1.0
    assert nav.free_floor_fraction == 1.0
    assert nav.swept_fraction > 0.99  # only the corners a disc cannot sweep
    assert nav.door_clear and nav.n_doors == 1 and nav.start == "door"
    assert nav.reachable_objects == 1.0 and nav.n_objects == 0
    # free for the centre: 0.2 m off every wall
    assert nav.free_area_m2 == pytest.approx(4.6 * 4.6, abs=0.05)


def test_wall_to_wall_row_cuts_the_room():
    # wardrobes y 1.2..1.8, facing +y (away from the door at y = 0)
    nav = navigability(room(), row(1.5, 0.6, 0.0, 5.0))
    below, above = 1.2 - 0.2 - 0.2, 4.8 - 2.0  # free depth for the centre either side
    assert nav.reachable_fraction == pytest.approx(below / (below + above), abs=0.02)
    assert nav.reachable_objects == 0.0  # their fronts face the cut-off part
    assert len(nav.unreachable) == 5
    assert nav.door_clear


@pytest.mark.parametrize(("gap", "expected"), [(0.35, False), (0.5, True)])
def test_gap_narrower_than_the_agent_blocks(gap, expected):
    left = row(2.5, 0.6, 0.0, 2.0, "a")
    right = row(2.5, 0.6, 2.0 + gap, 5.0, "b")
    nav = navigability(room(), left + right, agent_radius=0.2)
    assert (nav.reachable_fraction > 0.99) is expected
    if not expected:
        assert nav.reachable_fraction == pytest.approx(0.5, abs=0.03)


def test_l_shaped_room():
    ell = np.array([[0, 0], [6, 0], [6, 2], [2, 2], [2, 6], [0, 6]], float)
    door = Opening("door", (4.5, 0.0), (5.5, 0.0))
    assert navigability(room(ell, [door]), []).reachable_fraction == 1.0
    # a block across the vertical arm at y 3..3.5 cuts its top off
    block = obj("block", (1.0, 3.25), (2.0, 0.5))
    nav = navigability(room(ell, [door]), [block])
    top = 1.6 * (5.8 - 3.7)  # free for the centre above the block
    total = nav.free_area_m2
    assert nav.reachable_fraction == pytest.approx(1 - top / total, abs=0.02)


def test_object_in_the_door_swing():
    chair = obj("chair_0", (2.5, 0.5), (0.5, 0.5), category="chair")
    nav = navigability(room(), [chair])
    assert not nav.door_clear
    assert nav.blocked_doors == (0,) and nav.door_blockers == ("chair_0",)
    beside = obj("chair_1", (1.2, 0.5), (0.5, 0.5), category="chair")  # clear of x 2..3
    assert navigability(room(), [beside]).door_clear


def test_objects_on_furniture_and_on_walls_are_not_obstacles():
    painting = SceneObject("p", "painting", OrientedBox.from_yaw([2.5, 0.6, 1.5], [1, 1, 1]))
    book = SceneObject("b", "book", OrientedBox.from_yaw([2.5, 2.5, 0.8], [1, 1, 0.1]),
                       support="table_0")  # fmt: skip
    nav = navigability(room(), [painting, book])
    assert nav.door_clear and nav.reachable_fraction == 1.0 and nav.n_objects == 0
    # on a flat support at the floor: it blocks (inside the support anyway), is not judged
    slab = obj("slab", (2.5, 2.5), (1.0, 1.0), height=0.01, category="counter_top")
    low = SceneObject("k", "fork", OrientedBox.from_yaw([2.5, 2.5, 0.02], [0.2, 0.03, 0.02]),
                      support="slab")  # fmt: skip
    assert navigability(room(), [slab, low]).n_objects == 1


def test_bed_facing_a_wall_is_not_reachable_from_its_front():
    # 2 m long bed, front (+y) 0.1 m from the top wall
    bed = obj("bed_0", (2.5, 5.0 - 0.1 - 1.0), (1.6, 2.0), category="bed")
    nav = navigability(room(), [bed])
    assert nav.unreachable == ("bed_0",) and nav.reachable_objects == 0.0
    turned = obj("bed_1", (2.5, 0.1 + 1.0 + 2.0), (1.6, 2.0), yaw=np.pi, category="bed")
    assert navigability(room(), [turned]).unreachable == ()  # now facing the door side


def test_chair_under_a_table_is_reached_by_its_sides():
    # a bench south of a long table facing it (+y), its front 0.15 m under the table: the
    # cells before its front (and round its front corners) are all under or by the table
    table = obj("table_0", (2.5, 3.0), (2.4, 0.8), height=0.75, category="dining_table")
    bench = obj("bench_0", (2.5, 2.6 - 0.225 + 0.15), (1.0, 0.45), category="bench")
    nav = navigability(room(), [table, bench])
    assert nav.unreachable == ()
    assert nav.by_side == ("bench_0",)
    fronts_only = NavigationConfig(any_side_below_m=0.0)
    chair = obj("chair_0", (2.5, 2.6 - 0.225 + 0.15), (0.45, 0.45), category="chair")
    assert navigability(room(), [table, chair], config=fronts_only).by_side == ("chair_0",)


def test_small_objects_count_from_any_face():
    # a plant in a corner, its front to the wall: reached from its back
    plant = obj("plant", (0.25, 4.75), (0.4, 0.4), category="house_plant")
    assert navigability(room(), [plant]).by_side == ("plant",)
    fronts_only = NavigationConfig(any_side_below_m=0.0)
    assert navigability(room(), [plant], config=fronts_only).unreachable == ("plant",)


def test_room_without_a_door_starts_from_its_largest_part():
    nav = navigability(room(doors=()), row(1.5, 0.6, 0.0, 5.0))
    assert nav.start == "largest" and nav.door_clear
    assert nav.reachable_fraction == pytest.approx(2.8 / 3.6, abs=0.02)


def test_guard_rejects_the_candidate_closing_the_last_gap():
    guard = FloorGuard(room())
    boxes = [o.box for o in row(2.5, 0.6, 0.0, 5.0)]
    for box in boxes[:-1]:
        assert not guard.blocks(box)
        guard.add(box)
    assert guard.reason(boxes[-1]) == "cut"
    # against a wall, out of the way: fine
    desk = obj("desk", (4.65, 1.0), (0.7, 1.2), yaw=np.pi / 2, category="desk").box
    assert guard.reason(desk) is None


def test_guard_keeps_the_rooms_reachable_share():
    # a 3 x 3 m room; two cabinets back to the top wall, 1.4 m apart, and a sideboard
    # closing the gap between them 0.6 m from the wall: a pocket of 1.0 x 0.2 m for the
    # agent's centre, under min_cut_area_m2 (0.25) but 5 % of the free floor
    small = room(np.array([[0, 0], [3, 0], [3, 3], [0, 3]], float),
                 doors=(Opening("door", (1.0, 0.0), (2.0, 0.0), id="d"),))  # fmt: skip
    legs = [
        obj("a", (0.4, 2.4), (0.8, 1.2), yaw=np.pi),
        obj("b", (2.6, 2.4), (0.8, 1.2), yaw=np.pi),
    ]
    sideboard = obj("c", (1.5, 2.15), (1.4, 0.5), yaw=np.pi)
    nav = navigability(small, [*legs, sideboard])
    assert nav.free_area_m2 - nav.reachable_area_m2 == pytest.approx(0.2, abs=0.01)
    assert nav.reachable_fraction == pytest.approx(3.755 / 3.955, abs=0.002)
    for share, reason in ((None, "cut"), (0.9, None), (0.0, None)):
        cfg = NavigationConfig() if share is None else NavigationConfig(min_reachable_share=share)
        guard = FloorGuard(small, cfg)
        for o in legs:
            assert guard.reason(o.box) is None
            guard.add(o.box)
        assert guard.reason(sideboard.box) == reason, share
    # a room already below the share (a kept object made it so): what cuts nothing off
    # may still stand
    low = FloorGuard(small)
    for o in [*legs, sideboard]:
        low.add(o.box)
    assert low.reason(obj("d", (2.7, 0.6), (0.6, 0.5)).box) is None
    with pytest.raises(UserError, match="min-reachable-share"):
        NavigationConfig(min_reachable_share=1.5)


def test_guard_front_and_door_reasons():
    guard = FloorGuard(room())
    bed = obj("bed", (2.5, 5.0 - 0.1 - 1.0), (1.6, 2.0), category="bed").box
    assert guard.reason(bed) == "front"
    assert guard.reason(obj("c", (2.5, 0.4), (0.5, 0.5)).box) == "door"
    swing = FloorGuard.for_room(room(), door_clearance=0.3)
    assert swing.reason(obj("c", (2.5, 0.5), (0.5, 0.4)).box) is None  # beyond 0.3 m


def test_guard_protects_the_front_of_a_placed_object():
    guard = FloorGuard(room())
    wardrobe = obj("w", (2.5, 4.7), (1.0, 0.6), yaw=np.pi).box  # back to the top wall
    guard.add(wardrobe)
    # a long sideboard 0.3 m in front of it, wall to wall on the left, leaving a pocket
    sideboard = obj("s", (1.9, 4.4 - 0.3 - 0.25), (3.8, 0.5), yaw=np.pi).box
    assert guard.reason(sideboard) in ("front_of_other", "cut")
    relaxed = FloorGuard(room(), NavigationConfig(protect_fronts=False, min_cut_area_m2=10,
                                                  min_reachable_share=0.0))  # fmt: skip
    relaxed.add(wardrobe)
    assert relaxed.reason(sideboard) is None


def test_guard_agrees_with_navigability():
    objs = row(1.5, 0.6, 0.0, 3.0) + [obj("bed", (4.0, 3.5), (1.4, 2.0), yaw=np.pi)]
    guard = FloorGuard(room())
    for o in objs:
        guard.add(o.box)
    assert guard.reachable_area_m2 == pytest.approx(navigability(room(), objs).reachable_area_m2)


def test_footprint_of_a_turned_and_a_tilted_box():
    box = OrientedBox.from_yaw([1, 1, 0.5], [2, 1, 1], np.pi / 2)
    poly = footprint_polygon(box)
    assert np.ptp(poly[:, 0]) == pytest.approx(1) and np.ptp(poly[:, 1]) == pytest.approx(2)
    tilted = OrientedBox(np.array([0, 0, 1.0]), np.array([1, 1, 1.0]),
                         np.array([[1, 0, 0], [0, 0, -1], [0, 1, 0]], float))  # fmt: skip
    assert len(footprint_polygon(tilted)) == 4


def test_navigation_report_pools_rooms():
    scenes = [
        Scene("a", room(), []),
        Scene("b", room(), row(1.5, 0.6, 0.0, 5.0)),
        Scene("c", Room("kitchen", SQUARE), []),
    ]
    rep = navigation_report(scenes)
    assert rep["all"]["rooms"] == 3
    assert rep["all"]["share_rooms_reachable"] == pytest.approx(2 / 3, abs=1e-3)
    assert rep["all"]["floor_objects"] == 5 and rep["all"]["share_objects_reachable"] == 0.0
    assert rep["all"]["rooms_with_doors"] == 2 and rep["all"]["share_doors_clear"] == 1.0
    assert set(rep["by_room_type"]) == {"bedroom", "kitchen"}


@pytest.mark.parametrize(
    ("field", "value"),
    [("agent_radius_m", 0.0), ("resolution_m", -1.0), ("resolution_m", 1.0),
     ("resolution_m", 1e-9), ("resolution_m", 0.0099),
     ("front_reach_m", float("nan")), ("door_swing_m", -0.1)],
)  # fmt: skip
def test_config_range_checks(field, value):
    with pytest.raises(UserError, match="--assembly.navigation." + field.replace("_", "-")):
        NavigationConfig(**{field: value})


def test_upright_fast_path_matches_the_polygon_distance():
    from pair2scene.scene.navigation import _Grid

    grid = _Grid.of(SQUARE, 0.05)
    rng = np.random.default_rng(0)
    for _ in range(20):
        box = OrientedBox.from_yaw([*rng.uniform(0, 5, 2), 0.5], [*rng.uniform(0.2, 2, 2), 1],
                                   rng.uniform(-np.pi, np.pi))  # fmt: skip
        for within in (0.0, 0.2):
            win_a, fast = grid.near_box(box, within)
            win_b, slow = grid.near(footprint_polygon(box), within)
            assert win_a == win_b
            if win_a is not None:
                assert np.array_equal(fast, slow)


def test_guard_with_a_shut_door_keeps_the_largest_part_connected():
    guard = FloorGuard(room())
    guard.add(obj("kept", (2.5, 0.3), (1.6, 0.6)).box)  # a kept object across the door
    assert guard.door_shut
    assert guard.reason(obj("desk", (4.65, 2.5), (0.7, 1.2), yaw=np.pi / 2).box) is None
    assert guard.reason(row(2.5, 0.6, 0.0, 5.0)[2].box) is None  # one wardrobe: no cut
    full = FloorGuard(room())
    for o in row(2.5, 0.6, 0.0, 4.0):
        full.add(o.box)
    assert not full.door_shut and full.reason(row(2.5, 0.6, 0.0, 5.0)[4].box) == "cut"

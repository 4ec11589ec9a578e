"""Hanging objects on walls: where on the wall, what blocks them, and placement."""

from __future__ import annotations

import numpy as np
import pytest

from pair2scene.assembly.mounting import (
    MOUNT_GAP_M,
    dress_window,
    hang,
    mount,
    mount_blocked,
    mount_order,
)
from pair2scene.scene.geometry import OrientedBox
from pair2scene.scene.model import Opening, Room, wall_index
from pair2scene.scene.walls import walls_of

SQUARE = np.array([[0.0, 0.0], [4.0, 0.0], [4.0, 5.0], [0.0, 5.0]])
WALLS = walls_of(SQUARE)  # 0: y = 0, 1: x = 4, 2: y = 5, 3: x = 0
DOOR = Opening("door", (1.0, 0.0), (1.9, 0.0), 0.0, 2.1)
WINDOW = Opening("window", (2.5, 5.0), (1.5, 5.0), 0.9, 2.0)
ROOM = Room("bedroom", SQUARE, 2.6, (DOOR,), (WINDOW,))


def _gap_to(box: OrientedBox, wall) -> float:
    return float(wall.local(box.corners()[:, :2])[:, 1].min())


@pytest.mark.parametrize("wall", WALLS, ids=lambda w: f"wall{w.index}")
def test_hang_puts_the_back_on_the_wall_facing_the_room(wall):
    box = hang(wall, 0.3, 1.5, np.array([0.8, 0.05, 0.6]))
    assert _gap_to(box, wall) == pytest.approx(MOUNT_GAP_M)
    np.testing.assert_allclose(box.rotation[:2, 1], wall.normal, atol=1e-12)
    assert wall.local(box.center[:2])[0] == pytest.approx(0.3)
    assert box.center[2] == pytest.approx(1.5)


def test_mount_keeps_the_draw_on_the_wall_and_under_the_ceiling():
    drawn = OrientedBox.from_yaw([9.0, 0.7, 3.0], [0.8, 0.05, 0.6], 1.0)
    box = mount(drawn, WALLS[0], 2.6, 0.05)
    assert box.corners()[:, 0].max() == pytest.approx(4.0)  # slid to the wall's end
    assert box.top == pytest.approx(2.55)
    assert mount(OrientedBox.from_yaw([1, 1, 1], [4.5, 0.05, 0.6], 0), WALLS[0], 2.6, 0.05) is None


def test_blocked_over_a_door_a_window_behind_a_wardrobe_or_off_the_wall():
    on = lambda w, along, z, size=(0.6, 0.04, 0.5): hang(WALLS[w], along, z, np.array(size))  # noqa: E731
    assert mount_blocked(on(0, -0.55, 1.5), WALLS[0], ROOM, False, []) == "door"
    assert mount_blocked(on(0, -0.55, 2.45, (0.6, 0.04, 0.1)), WALLS[0], ROOM, False, []) is None
    assert mount_blocked(on(2, 0.0, 1.4), WALLS[2], ROOM, False, []) == "window"
    assert mount_blocked(on(2, 0.0, 1.4), WALLS[2], ROOM, True, []) is None  # curtains
    wardrobe = OrientedBox.from_yaw([4.0 - 0.35, 2.5, 1.0], [1.0, 0.6, 2.0], np.pi / 2)
    assert mount_blocked(on(1, 0.0, 1.5), WALLS[1], ROOM, False, [wardrobe]) == "hidden"
    assert mount_blocked(on(1, 0.0, 1.5), WALLS[1], ROOM, False, []) is None
    assert mount_blocked(on(1, 1.5, 1.5), WALLS[1], ROOM, False, [wardrobe]) is None


def test_curtains_hang_centred_on_the_window_from_above_it():
    box = dress_window(WINDOW, WALLS[2], np.array([1.4, 0.1, 2.0]), 2.6, 0.05)
    assert box.center[0] == pytest.approx(2.0)
    assert box.top == pytest.approx(2.0 + 0.12)
    assert _gap_to(box, WALLS[2]) == pytest.approx(MOUNT_GAP_M)
    assert dress_window(WINDOW, WALLS[0], np.array([1.4, 0.1, 2.0]), 2.6, 0.05) is None


def test_mount_order_tries_the_anchors_wall_then_the_wall_it_faces():
    rng = np.random.default_rng(0)
    bed = OrientedBox.from_yaw([3.0, 2.5, 0.5], [1.6, 2.0, 1.0], np.pi / 2)  # back on wall 1
    assert [w.index for w in mount_order(WALLS, rng, bed)][:2] == [1, 3]
    assert [w.index for w in mount_order(WALLS, rng, None, only=2)] == [2]
    assert sorted(w.index for w in mount_order(WALLS, rng)) == [0, 1, 2, 3]


@pytest.fixture(scope="module")
def placed():
    pytest.importorskip("torch")
    from pair2scene.assembly.place import Placer
    from pair2scene.hierarchy.tree import Hierarchy
    from pair2scene.model import from_pretrained

    h = Hierarchy("bedroom")
    bed = h.add("bed", "floor")
    h.add("painting", "wall", bed.id)
    h.add("painting", "wall")
    h.add("mirror", "wall")
    h.add("curtains", "wall")
    return Placer(from_pretrained()).place(h.validate(), ROOM, seed=3)


def test_placement_hangs_every_wall_object_on_a_named_wall_clear_of_door_and_window(placed):
    mounted = [o for o in placed.scene.objects if o.category != "bed"]
    assert len(mounted) + len(placed.stats.dropped) == 4
    assert len(mounted) >= 3
    for o in mounted:
        i = wall_index(o.support)
        assert i is not None, o.support
        wall = WALLS[i]
        assert abs(_gap_to(o.box, wall) - MOUNT_GAP_M) < 1e-9
        assert mount_blocked(o.box, wall, ROOM, o.category == "curtains", []) is None
        assert o.box.top <= 2.6 - 0.05 + 1e-9 and o.box.bottom >= 0.05 - 1e-9
    curtains = [o for o in mounted if o.category == "curtains"]
    for c in curtains:  # at the window
        assert c.support == "wall:2" and c.box.center[0] == pytest.approx(2.0)

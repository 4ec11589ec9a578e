"""A room's walls: segments, inward normals, frames, and which wall an object stands against."""

from __future__ import annotations

import numpy as np
import pytest

from pair2scene.scene.geometry import OrientedBox
from pair2scene.scene.model import Room
from pair2scene.scene.walls import (
    EMBEDDED_M,
    WALL_FRAME_DEPTH_M,
    against_wall,
    in_corner,
    wall_contact,
    walls_near,
    walls_of,
)

RECT = Room("bedroom", np.array([[0, 0], [4, 0], [4, 3], [0, 3]], float))
L_ROOM = Room("bedroom", np.array([[0, 0], [4, 0], [4, 2], [2, 2], [2, 4], [0, 4]], float))


def test_walls_have_inward_normals_in_rectangles_and_l_shapes():
    for room in (RECT, L_ROOM):
        for w in walls_of(room.floor_polygon):
            inside = w.midpoint + 0.01 * w.normal
            outside = w.midpoint - 0.01 * w.normal
            assert room.contains_xy(inside[None])[0] and not room.contains_xy(outside[None])[0]
    assert len(walls_of(L_ROOM.floor_polygon)) == 6


def test_wall_local_gives_along_and_inward_for_any_leading_shape():
    rng = np.random.default_rng(0)
    for w in walls_of(L_ROOM.floor_polygon):
        ends = w.local(np.array([w.p0, w.p1]))
        np.testing.assert_allclose(ends, [[-w.length / 2, 0.0], [w.length / 2, 0.0]], atol=1e-12)
        assert w.local(w.midpoint + 0.3 * w.normal) == pytest.approx([0.0, 0.3])
        pts = rng.uniform(-1, 5, size=(7, 3, 2))
        rel = pts - w.midpoint
        expected = np.stack([rel @ w.direction, rel @ w.normal], axis=-1)
        assert w.local(pts).shape == (7, 3, 2)
        assert w.local(pts).tobytes() == expected.tobytes()


def test_bed_with_its_headboard_to_the_wall_faces_in():
    walls = walls_of(RECT.floor_polygon)
    head_to_wall = OrientedBox.from_yaw([2, 1.95, 0.3], [1.6, 2.0, 0.6], np.pi)  # back at y=2.95
    contact = wall_contact(head_to_wall, walls)
    assert contact.face == "back" and contact.wall == 2
    assert contact.gap == pytest.approx(0.05) and contact.offset == pytest.approx(0.0)
    assert against_wall(head_to_wall, walls)
    mid_room = OrientedBox.from_yaw([2, 1.5, 0.3], [1.6, 2.0, 0.6], np.pi)
    assert wall_contact(mid_room, walls) is None and not against_wall(mid_room, walls)
    facing_wall = OrientedBox.from_yaw([2, 1.95, 0.3], [1.6, 2.0, 0.6], 0.0)  # front at y=2.95
    assert wall_contact(facing_wall, walls).face == "front"
    assert not against_wall(facing_wall, walls)
    turned = OrientedBox.from_yaw([2, 1.95, 0.3], [1.6, 2.0, 0.6], np.pi + np.radians(25))
    assert not against_wall(turned, walls)


def test_a_back_that_reaches_into_its_wall_stands_against_it():
    """A counter spanning wall to wall whose box reaches 0.30 m into the wall behind it (as
    AI2-THOR's FloorPlan411 counter) stands back to that wall, not sideways; one reaching
    further than EMBEDDED_M does not."""
    walls = walls_of(RECT.floor_polygon)
    depth = 1.36
    for beyond, against in ((0.30, True), (EMBEDDED_M - 0.05, True), (EMBEDDED_M + 0.1, False)):
        counter = OrientedBox.from_yaw([2, 3 + beyond - depth / 2, 0.45], [4.2, depth, 0.9], np.pi)
        assert against_wall(counter, walls) is against, beyond
        assert against_wall(counter, walls, max_gap=0.3) is against, beyond
    # a face short of the wall by more than the gap stays off it, whatever the depth allowed
    short = OrientedBox.from_yaw([2, 3 - 0.2 - depth / 2, 0.45], [3.0, depth, 0.9], np.pi)
    assert not against_wall(short, walls)


def test_a_pot_turned_any_way_stands_by_the_walls_its_footprint_reaches():
    walls = walls_of(RECT.floor_polygon)  # 0: y = 0, 1: x = 4, 2: y = 3, 3: x = 0
    half_diagonal = 0.2 * np.sqrt(2)  # of a 0.4 x 0.4 pot turned 45 degrees
    pot = OrientedBox.from_yaw([2, 3 - half_diagonal - 0.1, 0.3], [0.4, 0.4, 0.6], np.pi / 4)
    assert wall_contact(pot, walls) is None  # no face parallel to the wall
    assert walls_near(pot, walls) == {2}
    assert walls_near(pot, walls, max_gap=0.05) == set()
    corner = OrientedBox.from_yaw([4 - 0.3, 3 - 0.3, 0.3], [0.4, 0.4, 0.6], np.radians(30))
    assert walls_near(corner, walls) == {1, 2} and not in_corner(corner, walls)
    assert walls_near(OrientedBox.from_yaw([2, 1.5, 0.3], [0.4, 0.4, 0.6], 0.3), walls) == set()
    # the inner corner of an L: near the wall x = 2 (y 2..4) only where the footprint is
    # beside it, not past its end (below y = 2, where it stands by the wall y = 2 instead)
    l_walls = walls_of(L_ROOM.floor_polygon)
    beside = OrientedBox.from_yaw([1.8, 3.0, 0.3], [0.3, 0.3, 0.6], np.pi / 4)
    beyond_end = OrientedBox.from_yaw([2.15, 1.75, 0.3], [0.3, 0.3, 0.6], np.pi / 4)
    x2 = next(w.index for w in l_walls if np.allclose(w.p0[0], 2) and np.allclose(w.p1[0], 2))
    assert x2 in walls_near(beside, l_walls)
    y2 = next(w.index for w in l_walls if np.allclose([w.p0[1], w.p1[1]], 2))
    assert walls_near(beyond_end, l_walls) == {y2}


def test_side_to_the_wall_and_the_inner_corner_of_an_l():
    walls = walls_of(RECT.floor_polygon)
    desk = OrientedBox.from_yaw([0.65, 1.5, 0.4], [1.2, 0.6, 0.8], 0.0)  # left side at x=0.05
    contacts = wall_contact(desk, walls)
    assert contacts.face in ("left", "right") and contacts.wall == 3
    # against the L's inner wall (x = 2 for y in 2..4), not past its end
    walls_l = walls_of(L_ROOM.floor_polygon)
    shelf = OrientedBox.from_yaw([1.8, 3.0, 1.0], [1.0, 0.4, 2.0], np.pi / 2)  # back at x=2
    assert wall_contact(shelf, walls_l).wall == 3
    beyond = OrientedBox.from_yaw([3.8, 1.0, 1.0], [1.0, 0.4, 2.0], np.pi / 2)  # at x=4, y<2
    assert wall_contact(beyond, walls_l).wall == 1


def test_wall_frame_puts_the_wall_at_y_zero_and_metres_inward():
    wall = walls_of(RECT.floor_polygon)[2]  # y = 3, normal -y
    frame = wall.frame(2.7)
    bed = OrientedBox.from_yaw([1.0, 1.95, 0.3], [1.6, 2.0, 0.6], np.pi)
    local = bed.in_frame_of(frame)
    assert local.center[1] * WALL_FRAME_DEPTH_M == pytest.approx(1.05)
    assert local.center[0] == pytest.approx(1.0 / 2)  # 1 m right of the wall's midpoint / half
    assert local.center[2] * 1.35 == pytest.approx(0.3 - 1.35)
    assert local.yaw == pytest.approx(0.0, abs=1e-9)  # facing into the room


def test_face_contacts_of_the_faces_asked_are_those_of_all_faces():
    """Asking one face gives the same contacts (the same numbers) as asking all of them and
    keeping that face's: placement asks the back first."""
    from pair2scene.scene.walls import FACES, face_contacts, walls_of

    walls = walls_of(np.array([[0, 0], [4, 0], [4, 3], [0, 3]], float))
    corner = OrientedBox.from_yaw([0.3, 2.7, 0.4], [0.6, 0.6, 0.8], np.pi)  # in the corner
    every = face_contacts(corner, walls)
    assert sorted(c.face for c in every) == ["back", "right"]
    for face in FACES:
        assert face_contacts(corner, walls, faces=(face,)) == [c for c in every if c.face == face]
    assert face_contacts(corner, walls, faces=()) == []

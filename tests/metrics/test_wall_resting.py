"""The floating check for wall-mounted objects (support ``wall:<i>``), on hand-built rooms
with known answers: flush on its wall it rests; 3 cm off, 1 cm into the wall, on the
wrong wall, or turned away from it, it does not."""

from __future__ import annotations

import numpy as np
import pytest

from pair2scene.assets.mesh import Asset, Part, box
from pair2scene.metrics.physical import floating, intersecting, physical_report, wall_rest
from pair2scene.scene.geometry import OrientedBox, euler_to_matrix
from pair2scene.scene.model import FLOOR, Room, Scene, SceneObject, wall_support
from pair2scene.scene.walls import walls_of

# 5 x 4 m; wall 0 is y = 0 (inward +y), wall 1 x = 5, wall 2 y = 4, wall 3 x = 0
ROOM = Room("bedroom", np.array([[0, 0], [5, 0], [5, 4], [0, 4]], float), 2.7)
SIZE = [0.8, 0.04, 0.6]  # a painting: 4 cm deep, its back at local -y


def cube(size) -> Asset:
    return Asset("box", np.asarray(size, float), (Part("b", box([0, 0, 0], size)),))


def painting_at(y_back: float, yaw: float = 0.0, support: str = wall_support(0)):
    """A painting centred at x = 2.5, z = 1.5 facing +y, its back ``y_back`` from wall 0
    (negative: into the wall)."""
    center = [2.5, y_back + SIZE[1] / 2, 1.5]
    return SceneObject("painting_0", "painting", OrientedBox.from_yaw(center, SIZE, yaw),
                       None, support)  # fmt: skip


def scene_of(*objects: SceneObject, room: Room = ROOM) -> tuple[Scene, dict]:
    return Scene("s", room, list(objects)), {o.id: cube(o.box.size) for o in objects}


def test_flush_on_its_wall_rests_and_is_no_collision():
    bed = SceneObject("bed_0", "bed", OrientedBox.from_yaw([2.5, 1.0, 0.3], [1.6, 2.0, 0.6]),
                      None, FLOOR)  # fmt: skip
    scene, assets = scene_of(bed, painting_at(0.0))
    assert floating(scene, assets) == {}
    assert intersecting(scene, assets) == {}
    report = physical_report(scene, assets, simulate=False)
    assert report["floating_rate"] == 0.0 and report["collision_rate"] == 0.0


@pytest.mark.parametrize(
    "y_back, rests",
    [
        (0.0, True),
        (0.009, True),  # within the 1 cm gap
        (-0.004, True),  # 4 mm into the wall: within the 5 mm tolerance
        (0.03, False),  # 3 cm off the wall: floating
        (-0.01, False),  # 1 cm into the wall: not resting
    ],
)
def test_gap_and_penetration_known_answers(y_back, rests):
    scene, assets = scene_of(painting_at(y_back))
    flo = floating(scene, assets)
    assert ("painting_0" not in flo) is rests, flo


def test_the_reasons_name_the_gap_and_the_depth():
    scene, assets = scene_of(painting_at(0.03))
    assert "0.030 m off wall 0" in floating(scene, assets)["painting_0"]
    scene, assets = scene_of(painting_at(-0.01))
    why = floating(scene, assets)["painting_0"]
    assert "through wall 0" in why and "0.010" in why
    report = physical_report(scene, assets, simulate=False)
    assert report["floating_rate"] == 1.0 and report["floating"] == {"painting_0": why}


@pytest.mark.parametrize("support", [wall_support(1), wall_support(2), wall_support(3)])
def test_flush_on_wall_0_but_named_on_another_wall_floats(support):
    scene, assets = scene_of(painting_at(0.0, support=support))
    assert "painting_0" in floating(scene, assets)


@pytest.mark.parametrize("support", [wall_support(4), wall_support(17), "wall", "wall:x"])
def test_a_wall_the_room_does_not_have_floats(support):
    scene, assets = scene_of(painting_at(0.0, support=support))
    assert "painting_0" in floating(scene, assets)


def test_parallel_within_15_degrees():
    # turned 10 degrees about z, one end of its back on the wall: rests
    obj = painting_at(0.0, yaw=np.radians(10))
    corners = obj.box.corners()
    lift = -corners[:, 1].min()  # push it out of the wall so its nearest corner touches
    obj = obj.with_box(OrientedBox(obj.box.center + [0, lift, 0], obj.box.size,
                                   obj.box.rotation))  # fmt: skip
    scene, assets = scene_of(obj)
    assert floating(scene, assets) == {}
    # turned 20 degrees: no face parallel enough
    obj = painting_at(0.0, yaw=np.radians(20))
    lift = -obj.box.corners()[:, 1].min()
    obj = obj.with_box(OrientedBox(obj.box.center + [0, lift, 0], obj.box.size,
                                   obj.box.rotation))  # fmt: skip
    scene, assets = scene_of(obj)
    assert "no face parallel" in floating(scene, assets)["painting_0"]


def tipped(angles_deg) -> SceneObject:
    """The painting rotated by x, y, z angles (degrees) and pushed out of wall 0 until
    its nearest corner touches the wall's line."""
    rot = euler_to_matrix(np.radians(angles_deg), "zxy")
    b = OrientedBox(np.array([2.5, 0.5, 1.5]), np.array(SIZE), rot)
    b = OrientedBox(b.center - [0, b.corners()[:, 1].min(), 0], b.size, b.rotation)
    return SceneObject("painting_0", "painting", b, None, wall_support(0))


def test_tipped_forward_like_a_hung_frame_or_hung_crooked_rests():
    # tipped forward about its x axis, the top edge on the wall: rests within 15 degrees
    top_edge = tipped([-8.0, 0.0, 0.0])
    assert top_edge.box.rotation[2, 1] != 0.0  # the back face is no longer vertical
    assert floating(*scene_of(top_edge)) == {}
    assert "no face parallel" in floating(*scene_of(tipped([-20.0, 0.0, 0.0])))["painting_0"]
    # turned in the wall's plane (about y): the back stays flat on the wall
    assert floating(*scene_of(tipped([0.0, 25.0, 0.0]))) == {}


def test_the_back_is_preferred_but_any_vertical_face_holds():
    # facing along the wall, its left side (-x) flush on wall 0: still hangs on it
    obj = SceneObject("mirror_0", "mirror",
                      OrientedBox.from_yaw([2.5, 0.4, 1.5], SIZE, np.pi / 2), None,
                      wall_support(0))  # fmt: skip
    scene, assets = scene_of(obj)
    assert floating(scene, assets) == {}


def test_beside_the_wall_segment_floats_and_unknown_support_is_not_judged():
    # on the line of wall 0 but past its end at x = 5
    obj = SceneObject("painting_0", "painting", OrientedBox.from_yaw([5.6, 0.02, 1.5], SIZE),
                      None, wall_support(0))  # fmt: skip
    scene, assets = scene_of(obj)
    assert "beside wall 0" in floating(scene, assets)["painting_0"]
    # far from every wall, support unknown (a real room's painting): not judged
    obj = SceneObject("painting_1", "painting", OrientedBox.from_yaw([2.5, 2.0, 1.5], SIZE))
    scene, assets = scene_of(obj)
    assert floating(scene, assets) == {}


def test_a_slanted_wall_of_a_pentagon():
    # a room with a 45-degree corner cut: wall 1 runs from (4, 0) to (5, 1)
    room = Room("bedroom", np.array([[0, 0], [4, 0], [5, 1], [5, 4], [0, 4]], float), 2.7)
    wall = walls_of(room.floor_polygon)[1]
    yaw = wall.yaw  # +x along the wall, +y (the front) its inward normal
    center = [*(wall.midpoint + wall.normal * 0.02), 1.4]
    obj = SceneObject("mirror_0", "mirror", OrientedBox.from_yaw(center, [0.5, 0.04, 0.7], yaw),
                      None, wall_support(1))  # fmt: skip
    scene, assets = scene_of(obj, room=room)
    assert floating(scene, assets) == {}
    assert wall_rest(obj.box, wall, room.height) is None
    deep = obj.with_box(OrientedBox.from_yaw(center - np.r_[wall.normal * 0.03, 0.0],
                                             [0.5, 0.04, 0.7], yaw))  # fmt: skip
    assert "through wall 1" in wall_rest(deep.box, wall, room.height)
    assert "painting_0" not in floating(*scene_of(painting_at(0.0), room=room))

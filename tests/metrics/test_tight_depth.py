"""The depth evaluate measures between two meshes: the smaller of fcl's EPA depth and the
least overlap along the parts' face normals (both bound the true depth from above)."""

from __future__ import annotations

import numpy as np
import pytest

from pair2scene.assets.registry import generate
from pair2scene.scene.geometry import OrientedBox, yaw_to_matrix
from pair2scene.scene.model import FLOOR, Room, Scene, SceneObject

ROOM = Room("living_room", np.array([[0, 0], [9, 0], [9, 6], [0, 6]], float), 2.6)
TURNED = yaw_to_matrix(np.pi / 2)


def test_the_evaluated_depth_takes_the_shortest_way_out_of_a_thin_contact():
    """fcl's EPA read a pen's clip 9.7 mm into a plate's rim (a ``beyond`` living room as
    scene.json rebuilt it) where a 1.8 mm move along a face normal frees it; evaluate's
    depth is the smaller of the two bounds, placement's the plain one."""
    from pair2scene.assembly.collision import MeshWorld, Shape, face_axis_depth
    from pair2scene.metrics.physical import COLLISION_DEPTH_M, intersecting

    plate = generate("plate", [0.306107, 0.278215, 0.01385], 1817140313)
    pen = generate("pen", [0.011337, 0.201606, 0.012074], 276131283)
    boxes = {
        "plate_0": OrientedBox(
            [7.335497, 3.174735, 0.778801], plate.size, yaw_to_matrix(np.pi / 2)
        ),
        "pen_2": OrientedBox([7.2674, 3.00186, 0.777913], pen.size),
    }
    shapes = {}
    for oid, asset in (("plate_0", plate), ("pen_2", pen)):
        shapes[oid] = Shape(asset)
        shapes[oid].set_pose(boxes[oid].rotation, boxes[oid].center)
    world = MeshWorld()
    plain = world.penetration(shapes["plate_0"], shapes["pen_2"])
    tight = world.penetration(shapes["plate_0"], shapes["pen_2"], tight=True)
    assert tight <= plain
    assert tight == pytest.approx(0.0018, abs=3e-4)  # the rim's top face: 1.8 mm
    scene = Scene("s", ROOM, [
        SceneObject("plate_0", "plate", boxes["plate_0"], None, FLOOR),
        SceneObject("pen_2", "pen", boxes["pen_2"], None, FLOOR),
    ])  # fmt: skip
    assert intersecting(scene, {"plate_0": plate, "pen_2": pen}) == {}
    # a box sunk 3 mm into another: the tight depth is the overlap itself
    from pair2scene.assets.registry import fallback_box

    a = b = fallback_box("box", np.array([0.4, 0.4, 0.4]))  # one cube part each
    sa, sb = Shape(a), Shape(b)
    sa.set_pose(np.eye(3), np.array([0.0, 0.0, 0.2]))
    sb.set_pose(np.eye(3), np.array([0.0, 0.0, 0.597]))
    assert face_axis_depth(sa, 0, sb, 0) == pytest.approx(0.003)
    assert world.penetration(sa, sb, tight=True) == pytest.approx(0.003, abs=1e-4)
    assert COLLISION_DEPTH_M > 0.003

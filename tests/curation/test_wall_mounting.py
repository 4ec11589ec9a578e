"""Objects nothing carries that touch a wall hang on it, with the floor object below (or
facing them) as their functional anchor."""

from __future__ import annotations

import numpy as np
import pytest

from pair2scene.curation.tuples import RelationKind, scene_tuples
from pair2scene.curation.wall_objects import back_to_wall, mount_on_walls, wall_anchors
from pair2scene.scene.geometry import OrientedBox
from pair2scene.scene.model import FLOOR, Room, Scene, SceneObject
from pair2scene.scene.walls import face_contacts, walls_of

SQUARE = np.array([[0.0, 0.0], [4.0, 0.0], [4.0, 5.0], [0.0, 5.0]])  # wall 0: y = 0


def _scene(*objects: SceneObject) -> Scene:
    return Scene("s", Room("bedroom", SQUARE, 2.6), list(objects))


def _on_wall0(oid: str, cat: str, x: float, z: float, size, yaw: float = np.pi / 2 * 0,
              gap: float = 0.005, support=None) -> SceneObject:  # fmt: skip
    """An object whose face lies ``gap`` off wall 0 (y = 0); yaw 0 puts its back there."""
    size = np.asarray(size, float)
    box = OrientedBox.from_yaw([x, gap + size[1] / 2, z], size, yaw)
    return SceneObject(oid, cat, box, support=support)


def test_a_painting_touching_a_wall_hangs_on_it_facing_the_room():
    painting = _on_wall0("painting_0", "painting", 2.0, 1.5, [0.8, 0.04, 0.6])
    scene = mount_on_walls(_scene(painting))
    (o,) = scene.objects
    assert o.support == "wall:0"
    np.testing.assert_allclose(o.box.corners(), painting.box.corners(), atol=1e-9)


def test_a_mirror_stored_facing_the_wall_is_turned_round_keeping_its_box():
    mirror = _on_wall0("mirror_0", "mirror", 1.0, 1.4, [0.6, 0.03, 0.9], yaw=np.pi)
    (o,) = mount_on_walls(_scene(mirror)).objects
    assert o.support == "wall:0"
    assert face_contacts(o.box, walls_of(SQUARE), 0.3, 20)[0].face == "back"
    assert o.box.rotation[:2, 1] @ np.array([0.0, 1.0]) == pytest.approx(1.0)  # into the room
    np.testing.assert_allclose(
        np.sort(o.box.corners(), axis=0), np.sort(mirror.box.corners(), axis=0), atol=1e-9
    )


@pytest.mark.parametrize("face", ["left", "right", "front", "back"])
def test_back_to_wall_keeps_the_region_and_makes_that_face_the_back(face):
    box = OrientedBox.from_yaw([1.0, 2.0, 1.0], [0.5, 0.2, 0.4], 0.3)
    turned = back_to_wall(box, face)
    np.testing.assert_allclose(
        np.sort(turned.corners(), axis=0), np.sort(box.corners(), axis=0), atol=1e-9
    )
    normals = {"back": -box.rotation[:, 1], "front": box.rotation[:, 1],
               "left": -box.rotation[:, 0], "right": box.rotation[:, 0]}  # fmt: skip
    np.testing.assert_allclose(-turned.rotation[:, 1], normals[face], atol=1e-9)


def test_what_is_not_mounted():
    far = _on_wall0("painting_1", "painting", 2.0, 1.5, [0.8, 0.04, 0.6], gap=0.5)
    bowl = _on_wall0("bowl_0", "bowl", 3.0, 1.0, [0.2, 0.2, 0.1])  # nothing carries it
    held = _on_wall0("painting_2", "painting", 1.0, 1.5, [0.8, 0.04, 0.6], support=FLOOR)
    scene = mount_on_walls(_scene(far, bowl, held))
    assert [o.support for o in scene.objects] == [None, None, FLOOR]


def test_a_tv_mounted_across_the_room_from_a_sofa_facing_it():
    tv = _on_wall0("television_0", "television", 2.0, 1.3, [1.2, 0.08, 0.7])
    sofa = SceneObject("sofa_0", "sofa", OrientedBox.from_yaw([2.0, 4.5, 0.4], [2.0, 0.9, 0.8],
                       np.pi), support=FLOOR)  # fmt: skip
    scene = wall_anchors(mount_on_walls(_scene(tv, sofa)))
    assert scene.get("television_0").functional_anchor == "sofa_0"


def test_a_painting_above_the_bed_takes_the_bed_and_one_elsewhere_none():
    bed = SceneObject("bed_0", "bed", OrientedBox.from_yaw([2.0, 1.05, 0.5], [1.6, 2.0, 1.0], 0),
                      support=FLOOR)  # fmt: skip
    above = _on_wall0("painting_0", "painting", 2.1, 1.6, [0.8, 0.04, 0.6])
    beside = _on_wall0("painting_1", "painting", 3.6, 1.6, [0.5, 0.04, 0.4])
    low = _on_wall0("painting_2", "painting", 1.6, 0.8, [0.3, 0.04, 0.3], gap=0.005)
    scene = wall_anchors(mount_on_walls(_scene(bed, above, beside, low)))
    assert scene.get("painting_0").functional_anchor == "bed_0"
    assert scene.get("painting_1").functional_anchor is None
    assert scene.get("painting_2").functional_anchor is None  # behind the headboard


def test_a_mounted_object_gives_a_tuple_whose_support_is_its_wall_frame():
    bed = SceneObject("bed_0", "bed", OrientedBox.from_yaw([2.0, 1.05, 0.5], [1.6, 2.0, 1.0], 0),
                      support=FLOOR)  # fmt: skip
    painting = _on_wall0("painting_0", "painting", 2.0, 1.6, [0.8, 0.04, 0.6])
    scene = wall_anchors(mount_on_walls(_scene(bed, painting)))
    t = next(t for t in scene_tuples(scene) if t.dependent.id == "painting_0")
    assert t.support.category == "wall" and t.support.id == "wall_0" and t.support.asset is None
    assert t.kind is RelationKind.FUNCTIONAL and t.functional.id == "bed_0"
    frame = walls_of(SQUARE)[0].frame(2.6)
    np.testing.assert_allclose(t.support.box.to_vector(), frame.to_vector())
    local = t.canonical.center * frame.half_size
    assert local[1] == pytest.approx(0.005 + 0.02)  # metres from the wall into the room
    assert local[2] + 1.3 == pytest.approx(1.6)  # the frame spans floor to ceiling


def test_a_painting_touching_a_wall_edge_on_is_not_hung_on_it():
    edge_on = _on_wall0("painting_0", "painting", 2.0, 1.5, [0.02, 0.7, 0.5])
    rail = _on_wall0("towel_holder_0", "towel_holder", 1.0, 1.0, [0.1, 0.25, 0.1])
    scene = mount_on_walls(_scene(edge_on, rail))
    assert [o.support for o in scene.objects] == [None, "wall:0"]


def test_a_painting_lying_flat_beside_a_wall_is_not_hung_on_it():
    lying = _on_wall0("painting_0", "painting", 2.0, 0.8, [0.8, 0.5, 0.09])
    assert mount_on_walls(_scene(lying)).objects[0].support is None

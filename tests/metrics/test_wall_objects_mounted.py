"""Wall objects per room count what a generated room hangs on its walls (support
``wall:<i>``, a mounted television or towel holder included) and, in real rooms as their
source gives them, what nothing carries, of a category that hangs, touching a wall."""

from __future__ import annotations

import numpy as np

from pair2scene.metrics.wall_objects import is_wall_object, wall_report, wall_section
from pair2scene.scene.geometry import OrientedBox
from pair2scene.scene.model import FLOOR, Room, Scene, SceneObject, wall_support
from pair2scene.scene.walls import walls_of

SQUARE = np.array([[0, 0], [4, 0], [4, 4], [0, 4]], float)


def _obj(oid: str, category: str, support=FLOOR, part_of=None) -> SceneObject:
    box = OrientedBox.from_yaw([1, 1, 1.5], [0.6, 0.05, 0.5])
    return SceneObject(oid, category, box, None, support, part_of=part_of)


def generated() -> Scene:
    return Scene("g", Room("living_room", SQUARE), [
        _obj("sofa_0", "sofa"),
        _obj("tv_stand_0", "tv_stand"),
        _obj("television_0", "television", "tv_stand_0"),  # on a stand: not on a wall
        _obj("television_1", "television", wall_support(2)),  # mounted: a wall object
        _obj("painting_0", "painting", wall_support(0)),
        _obj("towel_holder_0", "towel_holder", wall_support(3)),
        _obj("curtains_0", "curtains", wall_support(1)),
    ])  # fmt: skip


def test_mounted_objects_count_whatever_their_category():
    report = wall_report([generated()])
    assert report["wall_objects_per_room"] == {"rate": 4.0, "count": [4, 1], "rooms": 1}
    # the shares stay per wall-object category, of every counted object
    assert report["wall_share/painting"]["count"] == [1, 7]
    assert "wall_share/television" not in report
    walls = walls_of(SQUARE)
    ids = [o.id for o in generated().objects if is_wall_object(o, walls)]
    assert ids == ["television_1", "painting_0", "towel_holder_0", "curtains_0"]


def _at_wall0(oid: str, category: str, gap: float, support=None) -> SceneObject:
    box = OrientedBox.from_yaw([2, gap + 0.025, 1.5], [0.6, 0.05, 0.5])  # back to wall 0
    return SceneObject(oid, category, box, None, support)


def test_real_rooms_count_what_hangs_against_a_wall():
    real = Scene("r", Room("living_room", SQUARE), [
        _obj("sofa_0", "sofa"),
        _at_wall0("television_0", "television", 0.005),  # mounted: counted
        _at_wall0("painting_0", "painting", 0.005),
        _at_wall0("mirror_0", "mirror", 0.02),
        _at_wall0("painting_1", "painting", 1.0),  # a metre off every wall: not hung
        _at_wall0("vase_0", "vase", 0.0),  # nothing carries it, but vases do not hang
        SceneObject("blinds_0", "blinds", _at_wall0("b", "blinds", 0.0).box, None, None,
                    source_support="floor"),  # the source says it stands on the floor
        _obj("drawer_0", "drawer", "sofa_0", part_of="sofa_0"),
    ])  # fmt: skip
    assert wall_report([real])["wall_objects_per_room"]["count"] == [3, 1]
    section = wall_section([real], [generated()])
    row = section["wall_objects_per_room"]
    assert (row["generated"]["rate"], row["reference"]["rate"]) == (4.0, 3.0)


def test_wall_objects_over_doors_and_windows_are_counted_curtains_at_windows_are_not():
    from pair2scene.scene.model import Opening

    door = Opening("door", (1.5, 0.0), (2.5, 0.0), 0.0, 2.1)
    window = Opening("window", (1.5, 0.0), (2.5, 0.0), 0.9, 2.0)
    room = Room("bedroom", SQUARE, 2.6, (door,))
    over = Scene("a", room, [_at_wall0("painting_0", "painting", 0.005, wall_support(0))])
    assert wall_report([over])["over_openings"]["count"] == [1, 1]
    room = Room("bedroom", SQUARE, 2.6, (), (window,))
    at = Scene("b", room, [_at_wall0("curtains_0", "curtains", 0.005, wall_support(0)),
                           _at_wall0("mirror_0", "mirror", 0.005, wall_support(0))])  # fmt: skip
    assert wall_report([at])["over_openings"]["count"] == [1, 2]  # the mirror


def test_covered_counts_wall_objects_hidden_by_what_stands_in_front():
    room = Room("living_room", SQUARE, 2.6)
    vase = OrientedBox.from_yaw([2, 0.2, 1.5], [0.4, 0.2, 0.5], 0.0)  # in front of the face
    scene = Scene("c", room, [
        _at_wall0("painting_0", "painting", 0.005, wall_support(0)),
        _at_wall0("curtains_0", "curtains", 0.005, wall_support(0)),  # hung behind it: left out
        SceneObject("vase_0", "vase", vase, None, "dresser_0"),
    ])  # fmt: skip
    assert wall_report([scene])["covered"]["count"] == [1, 1]
    far = SceneObject("vase_0", "vase", OrientedBox.from_yaw([2, 1.2, 1.5], [0.4, 0.2, 0.5]),
                      None, "floor")  # fmt: skip
    assert wall_report([Scene("d", room, [scene.objects[0], far])])["covered"]["count"] == [0, 1]


def test_what_rests_on_a_wall_object_does_not_cover_it():
    room = Room("bathroom", SQUARE, 2.6)
    rail = _at_wall0("towel_holder_0", "towel_holder", 0.005, wall_support(0))
    towel = SceneObject("towel_0", "towel", OrientedBox.from_yaw([2, 0.05, 1.4], [0.5, 0.05, 0.6]),
                        None, "towel_holder_0")  # fmt: skip
    assert wall_report([Scene("t", room, [rail, towel])])["covered"]["count"] == [0, 1]
    towel = SceneObject(towel.id, towel.category, towel.box, None, "floor")  # not on it
    assert wall_report([Scene("t", room, [rail, towel])])["covered"]["count"] == [1, 1]

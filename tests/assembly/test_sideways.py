"""Objects against a wall with a side, not their back, to it (a sofa's arm to the wall)."""

from __future__ import annotations

import numpy as np
import pytest

from pair2scene.assembly.walls import WallRules, turn_sideways
from pair2scene.curation.stats import HierarchyStats
from pair2scene.scene.geometry import OrientedBox
from pair2scene.scene.model import FLOOR, Room, Scene, SceneObject
from pair2scene.scene.walls import against_wall, face_contacts, walls_of

RECT = np.array([[0, 0], [5, 0], [5, 4], [0, 4]], float)


def _living(i: int) -> Scene:
    """A sofa (2.0 x 0.9 m): back to the north wall mid-wall (i = 0), back to it in the
    north-east corner (1), its right arm to the east wall facing along it (2); an
    armchair in the middle of the room (against no wall)."""
    sofa = [
        OrientedBox.from_yaw([2.5, 3.55, 0.4], [2.0, 0.9, 0.8], np.pi),
        OrientedBox.from_yaw([4.0, 3.55, 0.4], [2.0, 0.9, 0.8], np.pi),
        OrientedBox.from_yaw([3.995, 2.0, 0.4], [2.0, 0.9, 0.8], 0.0),  # facing north
    ][i]
    chair = OrientedBox.from_yaw([2.0, 1.5, 0.4], [0.8, 0.8, 0.8], 0.3)
    objects = [
        SceneObject("sofa_0", "sofa", sofa, None, FLOOR),
        SceneObject("armchair_0", "armchair", chair, None, FLOOR),
    ]
    return Scene(f"l{i}", Room("living_room", RECT), objects)


def test_the_three_sofas_stand_as_described():
    walls = walls_of(RECT)
    faces = [sorted({c.face for c in face_contacts(_living(i).objects[0].box, walls)})
             for i in range(3)]  # fmt: skip
    assert faces == [["back"], ["back", "left"], ["right"]]
    assert [against_wall(_living(i).objects[0].box, walls) for i in range(3)] == [1, 1, 0]


def test_statistics_count_sideways_objects_and_keep_them_out_of_the_corner_share():
    stats = HierarchyStats.fit([_living(i) for i in range(3)])
    rs = stats.room_types["living_room"]
    assert rs.against_wall["sofa"] == 3 and rs.sideways["sofa"] == 1
    assert rs.in_corner["sofa"] == 1 and rs.against_wall["armchair"] == 0
    back = HierarchyStats.from_json(stats.to_json())
    assert back.room_types["living_room"].sideways == rs.sideways
    rules = WallRules.from_stats(back)
    assert rules.rate("living_room", "sofa") == 1.0
    assert rules.sideways_rate("living_room", "sofa") == pytest.approx(1 / 3)
    # of the two sofas with their back to a wall, one stood in a corner
    assert rules.corner_rate("living_room", "sofa") == 0.5
    assert rules.sideways_rate("bedroom", "sofa") == pytest.approx(1 / 3)  # pooled
    assert rules.sideways_rate("living_room", "armchair") == 0.0  # never against a wall
    draws = [rules.turned("living_room", "sofa", s) for s in range(600)]
    assert 0.28 < np.mean(draws) < 0.39
    assert draws == [rules.turned("living_room", "sofa", s) for s in range(600)]
    # independent of the wall and corner draws
    corners = [rules.in_corner("living_room", "sofa", s) for s in range(600)]
    assert 0.1 < np.mean(np.array(draws) & np.array(corners)) < 0.25


def test_statistics_written_before_the_sideways_counts_turn_nothing():
    stats = HierarchyStats.fit([_living(i) for i in range(3)])
    doc = stats.to_dict()
    for walls in (rd["walls"] for rd in doc["room_types"].values()):
        for row in walls.values():
            del row["sideways"]
    rules = WallRules.from_stats(HierarchyStats.from_dict(doc))
    assert rules.sideways_rate("living_room", "sofa") == 0.0
    assert rules.corner_rate("living_room", "sofa") == pytest.approx(1 / 3)  # as before
    assert not any(rules.turned("living_room", "sofa", s) for s in range(50))


@pytest.mark.parametrize("index", [0, 1, 2, 3])
def test_turn_sideways_puts_a_side_flush_to_the_wall_facing_along_it_into_the_room(index):
    walls = walls_of(RECT)
    wall = walls[index]
    drawn = OrientedBox.from_yaw([1.2, 1.1, 0.4], [2.0, 0.9, 0.8], 0.4)  # anywhere
    centre = np.array([2.5, 2.0])
    box = turn_sideways(drawn, wall, centre, gap=0.005)
    (contact,) = face_contacts(box, walls)
    assert contact.wall == index and contact.face in ("left", "right")
    assert contact.gap == pytest.approx(0.005) and contact.angle == pytest.approx(0.0, abs=1e-6)
    along = wall.local(drawn.center[:2])[0]
    assert wall.local(box.center[:2])[0] == pytest.approx(along)  # where it was along it
    assert box.center[2] == drawn.center[2] and np.allclose(box.size, drawn.size)
    front = box.rotation[:2, 1]
    assert abs(front @ wall.direction) == pytest.approx(1.0)  # along the wall ...
    ahead = wall.local(centre)[0] - along
    assert np.sign(front @ wall.direction) == np.sign(ahead)  # ... towards the room's middle


def test_a_sideways_object_tries_the_turned_box_first_then_the_drawn_one():
    from pair2scene.assembly.place import _Context, _variants

    walls = walls_of(RECT)
    ctx = _Context(FLOOR, {}, Room("living_room", RECT), (), (), [], None, None, None)
    ctx.wall, ctx.sideways = walls[1], True
    box = OrientedBox.from_yaw([4.5, 1.0, 0.4], [2.0, 0.9, 0.8], np.pi / 2)
    (t0, turned), (t1, same) = _variants(box, ctx)
    assert t0 is None and t1 is None and same is box
    assert {c.face for c in face_contacts(turned, walls)} <= {"left", "right"}
    ctx.wall = None  # no wall drawn: nothing to turn against
    assert [b for _, b in _variants(box, ctx)] == [box]


@pytest.mark.parametrize("sideways", [True, False])
def test_placement_stands_a_sofa_sideways_as_often_as_the_rules_say(sideways):
    pytest.importorskip("torch")
    from pair2scene.assembly.place import AssemblyConfig, Placer
    from pair2scene.hierarchy.tree import Hierarchy
    from pair2scene.model import from_pretrained

    rules = WallRules(
        rates={"living_room": {"sofa": (1.0, 1.0)}},
        sideways={"living_room": {"sofa": (1.0, 1.0)}},
    )
    placer = Placer(from_pretrained(), config=AssemblyConfig(sideways=sideways), walls=rules)
    room = Room("living_room", RECT)
    walls = walls_of(RECT)
    for seed in range(3):
        h = Hierarchy("living_room")
        h.add("sofa", FLOOR)
        (sofa,) = placer.place(h.validate(), room, seed=seed).scene.objects
        faces = {c.face for c in face_contacts(sofa.box, walls)}
        assert faces, "against a wall"
        assert ("back" in faces) != sideways


@pytest.mark.parametrize("sideways", [False, True])
def test_a_candidate_drawn_back_to_its_wall_may_not_stand_side_to_it(sideways):
    """Drawn against the east wall and not turned by the wall rules, a sofa whose arm
    touches the wall is rejected (side_to_wall): the sideways share is the rules' draw,
    not the model's yaw. Turned by them, it stands."""
    from pair2scene.assembly.place import Placer, _Context, _stack

    walls = walls_of(RECT)
    ctx = _Context(FLOOR, {}, Room("living_room", RECT), ([], None), _stack([], 0.0), [],
                   None, None, None)  # fmt: skip
    ctx.wall, ctx.sideways = walls[1], sideways
    arm = OrientedBox.from_yaw([3.995, 2.0, 0.4], [2.0, 0.9, 0.8], 0.0)
    back = OrientedBox.from_yaw([4.545, 2.0, 0.4], [2.0, 0.9, 0.8], np.pi / 2)
    assert {c.face for c in face_contacts(arm, [walls[1]])} == {"right"}
    assert {c.face for c in face_contacts(back, [walls[1]])} == {"back"}
    placer = Placer.__new__(Placer)
    assert placer._blocked(arm, ctx)[0] == (None if sideways else "side_to_wall")
    assert placer._blocked(back, ctx)[0] is None

"""Hierarchy statistics on a tiny scene set: known counts, merging, JSON round trip."""

from __future__ import annotations

import json
from collections import Counter

import numpy as np
import pytest

from pair2scene.curation.stats import STATS_FORMAT, HierarchyStats
from pair2scene.errors import UserError
from pair2scene.scene.geometry import OrientedBox
from pair2scene.scene.model import FLOOR, Room, Scene, SceneObject

ROOM = np.array([[0, 0], [4, 0], [4, 4], [0, 4]], float)


def room(scene_id: str, room_type: str, spec: list[tuple]) -> Scene:
    """spec: (id, category, support, functional anchor)."""
    objects = [
        SceneObject(oid, cat, OrientedBox.from_yaw([1, 1, 0.5], [0.5, 0.5, 1.0]), None, sup, fa)
        for oid, cat, sup, fa in spec
    ]
    return Scene(scene_id, Room(room_type, ROOM), objects, source="test", split="train")


def scenes() -> list[Scene]:
    bed_a = room("bed_a", "bedroom", [
        ("bed_0", "bed", FLOOR, None),
        ("side_0", "side_table", FLOOR, "bed_0"),
        ("side_1", "side_table", FLOOR, "bed_0"),
        ("lamp_0", "table_lamp", "side_0", None),
        ("book_0", "book", "side_1", None),
        ("painting_0", "painting", None, None),          # no support: not placed
        ("drawer_0", "drawer", "side_0", None),          # part: not placed
    ])  # fmt: skip
    bed_b = room("bed_b", "bedroom", [
        ("bed_0", "bed", FLOOR, None),
        ("side_0", "side_table", FLOOR, "bed_0"),
        ("side_1", "side_table", FLOOR, "bed_0"),
        ("lamp_0", "table_lamp", "side_0", None),
    ])  # fmt: skip
    kitchen = room("kitchen_a", "kitchen", [
        ("counter_0", "counter_top", FLOOR, None),
        ("fridge_0", "fridge", FLOOR, None),
        ("plate_0", "plate", "counter_0", None),
        ("fork_0", "fork", "counter_0", "plate_0"),
        ("mug_0", "mug", FLOOR, None),                   # small object on the floor: no template
    ])  # fmt: skip
    return [bed_a, bed_b, kitchen]


def test_counts():
    stats = HierarchyStats.fit(scenes())
    assert stats.rooms == 3
    assert stats.sup_dep[FLOOR] == {
        "bed": 2, "side_table": 4, "counter_top": 1, "fridge": 1, "mug": 1
    }  # fmt: skip
    assert stats.sup_dep["side_table"] == {"table_lamp": 2, "book": 1}
    assert stats.sup_dep["counter_top"] == {"plate": 1, "fork": 1}
    assert "painting" not in str(stats.sup_dep) and "drawer" not in str(stats.sup_dep)
    assert stats.func_dep == {
        FLOOR: {"bed": {"side_table": 4}}, "counter_top": {"plate": {"fork": 1}}
    }  # fmt: skip

    bedroom = stats.room_types["bedroom"]
    assert bedroom.rooms == 2
    assert stats.templates("bedroom") == [({"bed": 1, "side_table": 2}, 2)]
    assert bedroom.furniture_counts() == {"bed": {1: 2}, "side_table": {2: 2}}
    assert bedroom.object_counts == {5: 1, 4: 1}
    assert bedroom.layout_counts == {(("bed", "side_table", "side_table"), 5): 1,
                                     (("bed", "side_table", "side_table"), 4): 1}  # fmt: skip
    # the mug on the kitchen floor joins its template (small objects on the floor do)
    assert stats.templates("kitchen") == [({"counter_top": 1, "fridge": 1, "mug": 1}, 1)]
    assert stats.room_types["kitchen"].object_counts == {5: 1}
    assert stats.templates("bathroom") == []


def test_templates_rank_and_count_distributions():
    rooms = [
        room(f"r{i}", "living_room", [(f"s{i}", "sofa", FLOOR, None)] + extra)
        for i, extra in enumerate(
            [[], [], [("a", "armchair", FLOOR, None)], [("a", "armchair", FLOOR, None),
                                                        ("b", "armchair", FLOOR, None)]]
        )
    ]  # fmt: skip
    rs = HierarchyStats.fit(rooms).room_types["living_room"]
    assert rs.templates() == [
        ({"sofa": 1}, 2),
        ({"armchair": 2, "sofa": 1}, 1),
        ({"armchair": 1, "sofa": 1}, 1),
    ]  # ties: by the sorted category list
    assert rs.templates(top=1) == [({"sofa": 1}, 2)]
    assert rs.furniture_counts() == {"armchair": {0: 2, 1: 1, 2: 1}, "sofa": {1: 4}}


def test_merge_equals_fit_of_the_union():
    s = scenes()
    merged = HierarchyStats.merge([HierarchyStats.fit(s[:1]), HierarchyStats.fit(s[1:])])
    assert merged.to_dict() == HierarchyStats.fit(s).to_dict()


def test_json_round_trip():
    stats = HierarchyStats.fit(scenes())
    text = stats.to_json()
    doc = json.loads(text)
    assert doc["format"] == STATS_FORMAT and doc["version"] == 1
    assert doc["room_types"]["bedroom"]["object_counts"] == {"4": 1, "5": 1}
    assert doc["room_types"]["bedroom"]["furniture_counts"]["side_table"] == {"2": 2}
    back = HierarchyStats.from_json(text)
    assert back.to_json() == text
    assert back.sup_dep == stats.sup_dep and back.func_dep == stats.func_dep
    assert back.room_types["bedroom"].layout_counts == stats.room_types["bedroom"].layout_counts
    (template,) = doc["room_types"]["bedroom"]["templates"]
    assert template["object_counts"] == {"4": 1, "5": 1}


def test_statistics_without_joint_counts_still_load():
    """Files written before the per-template counts: both marginals, no joint."""
    doc = json.loads(HierarchyStats.fit(scenes()).to_json())
    for rd in doc["room_types"].values():
        for t in rd["templates"]:
            del t["object_counts"]
    old = HierarchyStats.from_dict(doc)
    assert old.room_types["bedroom"].layout_counts == {}
    assert old.room_types["bedroom"].object_counts == {5: 1, 4: 1}


@pytest.mark.parametrize(
    "text, message",
    [
        ("{nope", "not valid JSON"),
        ('{"format": "other"}', "not a pair2scene.hierarchy_stats file"),
        (json.dumps({"format": STATS_FORMAT, "version": 99}), "version 99"),
        (json.dumps({"format": STATS_FORMAT, "version": 1}), "malformed statistics"),
    ],
)
def test_bad_json_is_a_user_error(text, message):
    with pytest.raises(UserError, match=message):
        HierarchyStats.from_json(text, "stats.json")


@pytest.mark.parametrize(
    "row",
    [
        {"on_floor": -3, "against_wall": 0},
        {"on_floor": 2, "against_wall": 3},
        {"on_floor": 4, "against_wall": 2, "in_corner": 3},
        {"on_floor": 4, "against_wall": 2, "sideways": -1},
    ],
)
def test_impossible_wall_counts_are_a_user_error(row):
    doc = json.loads(HierarchyStats.fit(scenes()).to_json())
    doc["room_types"]["bedroom"]["walls"]["counter_top#shaped"] = row
    with pytest.raises(UserError, match="malformed statistics.*walls of counter_top#shaped"):
        HierarchyStats.from_dict(doc, "stats.json")


def test_windows_per_room_and_their_shapes_are_counted():
    from pair2scene.scene.model import Opening

    s = scenes()
    win = Opening("window", (4.0, 1.0), (4.0, 2.2), 0.9, 2.1)
    s[0] = Scene(s[0].id, Room("bedroom", ROOM, windows=(win, win)), s[0].objects)
    stats = HierarchyStats.fit(s)
    rs = stats.room_types["bedroom"]
    assert rs.window_counts == {2: 1, 0: 1}
    assert rs.window_shapes == {(1.2, 0.9, 2.1): 2}
    back = HierarchyStats.from_json(stats.to_json()).room_types["bedroom"]
    assert back.window_counts == rs.window_counts and back.window_shapes == rs.window_shapes
    pooled = stats.room_type("garage")  # no garage in training: every room type pooled
    assert pooled.window_counts == {2: 1, 0: 2} and pooled.rooms == 3


def test_what_rests_on_a_support_s_top_and_what_inside():
    """``on_top`` counts dependents resting on their support's box top: a fridge's eggs
    on its shelves are inside, a mug on the table on top; a support whose top holds
    nothing (of enough dependents) keeps it free in placement."""

    def obj(oid, cat, z0, h, sup):
        return SceneObject(oid, cat, OrientedBox.from_yaw([1, 1, z0 + h / 2], [0.1, 0.1, h]),
                           None, sup)  # fmt: skip

    rooms = []
    for i in range(25):
        objects = [
            obj("fridge_0", "fridge", 0.0, 1.8, FLOOR),
            obj("egg_0", "egg", 0.4 + 0.02 * i, 0.07, "fridge_0"),  # on a shelf inside
            obj("table_0", "dining_table", 0.0, 0.75, FLOOR),
            obj("mug_0", "mug", 0.75, 0.1, "table_0"),  # on the top
        ]
        rooms.append(Scene(f"k{i}", Room("kitchen", ROOM), objects, source="test", split="train"))
    stats = HierarchyStats.fit(rooms)
    assert stats.on_top == {"fridge": 0, "dining_table": 25}
    assert stats.top_kept_free() == frozenset({"fridge"})
    assert stats.top_kept_free(min_dependents=30) == frozenset()  # too few to tell
    back = HierarchyStats.from_json(stats.to_json())
    assert back.on_top == stats.on_top
    assert HierarchyStats.merge([stats, back]).on_top == {"fridge": 0, "dining_table": 50}
    doc = json.loads(stats.to_json())
    del doc["on_top"]  # written before it was kept: no rule
    old = HierarchyStats.from_dict(doc)
    assert old.on_top is None and old.top_kept_free() == frozenset()


def test_a_template_keeps_which_members_sat_at_which():
    """Three living rooms of one layout, a table and four chairs each: all four at the
    table in two of them, none in the third. The template keeps the two patterns apart,
    where a share (8 of 12) would seat chairs at the table one by one."""
    chairs = [(f"c{i}", "chair", FLOOR) for i in range(4)]
    rooms = [
        room(name, "living_room", [("t", "dining_table", FLOOR, None)]
             + [(*c, anchor) for c in chairs])
        for name, anchor in (("r0", "t"), ("r1", None), ("r2", "t"))
    ]  # fmt: skip
    stats = HierarchyStats.fit(rooms)
    rs = stats.room_types["living_room"]
    layout = ["chair"] * 4 + ["dining_table"]
    drawn = Counter()
    for seed in range(60):
        pattern = rs.template_anchors(layout, np.random.default_rng(seed))
        drawn[json.dumps(pattern, sort_keys=True)] += 1
    assert drawn.keys() == {"{}", '{"chair": {"dining_table": 4}}'}
    assert 30 < drawn['{"chair": {"dining_table": 4}}'] < 55, drawn  # 2 rooms of 3
    assert rs.template_anchors(["dining_table"], np.random.default_rng(0)) is None
    (template,) = stats.to_dict()["room_types"]["living_room"]["templates"]
    assert template["anchored"] == [[{}, 1], [{"chair>dining_table": 4}, 2]]
    back = HierarchyStats.from_json(stats.to_json()).room_types["living_room"]
    assert back.layout_anchors == rs.layout_anchors
    doc = stats.to_dict()  # statistics written before it was kept: no patterns
    del doc["room_types"]["living_room"]["templates"][0]["anchored"]
    old = HierarchyStats.from_dict(doc).room_types["living_room"]
    assert old.template_anchors(layout, np.random.default_rng(0)) is None


@pytest.mark.parametrize(
    "pattern, message",
    [({"chair>sofa": 1}, "not two of the template's members"),
     ({"chair": 1}, "not two of the template's members"),
     ({"chair>dining_table": 5}, "5 of its 4 members")],
)  # fmt: skip
def test_impossible_template_anchors_are_a_user_error(pattern, message):
    rooms = [
        room(f"r{i}", "living_room", [("t", "dining_table", FLOOR, None),
                                      ("c0", "chair", FLOOR, "t"), ("c1", "chair", FLOOR, None),
                                      ("c2", "chair", FLOOR, None), ("c3", "chair", FLOOR, None)])
        for i in range(2)
    ]  # fmt: skip
    doc = HierarchyStats.fit(rooms).to_dict()
    doc["room_types"]["living_room"]["templates"][0]["anchored"] = [[pattern, 2]]
    with pytest.raises(UserError, match=f"malformed statistics.*{message}"):
        HierarchyStats.from_dict(doc, "stats.json")


def test_free_standing_floor_objects_count_their_turn_off_the_walls():
    """Chairs mid-room turned 0, 12 and 25 degrees and one against a wall turned 12: the
    three free-standing ones are counted in their bins, the one by the wall not; the
    counts survive JSON and merging, and a wrong row is a user error."""
    from pair2scene.curation.stats import ASKEW_BINS_DEG, askew_bin

    def chair(oid, xy, degrees):
        box = OrientedBox.from_yaw([*xy, 0.45], [0.45, 0.45, 0.9], np.radians(degrees))
        return SceneObject(oid, "chair", box, None, FLOOR, None)

    # (c3: its box reaches the wall y = 0)
    chairs = [chair("c0", [2, 2], 0), chair("c1", [1, 2], 12), chair("c2", [3, 2], -25),
              chair("c3", [2, 0.24], 12)]  # fmt: skip
    scene = Scene("s", Room("living_room", ROOM), chairs, source="test", split="train")
    stats = HierarchyStats.fit([scene])
    assert [askew_bin(np.radians(d)) for d in (0, 12, -25, 89, 46)] == [0, 2, 4, 0, 5]
    assert stats.askew == {"chair": [1, 0, 1, 0, 1, 0]}
    back = HierarchyStats.from_json(stats.to_json())
    assert back.askew == stats.askew
    assert HierarchyStats.merge([stats, stats]).askew == {"chair": [2, 0, 2, 0, 2, 0]}
    shares = HierarchyStats.merge([stats] * 7).askew_shares()
    np.testing.assert_allclose(shares["chair"], [1 / 3, 0, 1 / 3, 0, 1 / 3, 0])
    assert stats.askew_shares() == {}  # 3 objects: too few to say
    doc = json.loads(stats.to_json())
    del doc["askew"]
    assert HierarchyStats.from_dict(doc).askew is None  # written before it was kept
    doc["askew"] = {"chair": [1, 2]}
    with pytest.raises(UserError, match=f"askew of chair: {len(ASKEW_BINS_DEG)} counts"):
        HierarchyStats.from_dict(doc, "stats.json")


def test_floor_objects_standing_alone_are_counted_per_category():
    """A plant mid-room (alone), one by a wall and two chairs side by side mid-room: one of
    the plants stood alone, none of the chairs; the counts survive JSON and merging, give
    shares from 20 objects on, and a wrong row is a user error."""

    def thing(oid, category, xy, size=(0.4, 0.4, 0.8)):
        box = OrientedBox.from_yaw([*xy, size[2] / 2], list(size), 0.0)
        return SceneObject(oid, category, box, None, FLOOR, None)

    objects = [thing("p0", "house_plant", [2.0, 3.0]), thing("p1", "house_plant", [0.3, 2.0]),
               thing("c0", "chair", [1.6, 1.5]), thing("c1", "chair", [2.4, 1.5])]  # fmt: skip
    scene = Scene("s", Room("living_room", ROOM), objects, source="test", split="train")
    stats = HierarchyStats.fit([scene])
    assert stats.isolated == {"house_plant": [1, 2], "chair": [0, 2]}
    assert HierarchyStats.from_json(stats.to_json()).isolated == stats.isolated
    merged = HierarchyStats.merge([stats] * 10)
    assert merged.isolated == {"house_plant": [10, 20], "chair": [0, 20]}
    assert merged.isolated_shares() == {"chair": 0.0, "house_plant": 0.5}
    assert stats.isolated_shares() == {}  # 2 objects each: too few to say
    doc = json.loads(stats.to_json())
    del doc["isolated"]
    assert HierarchyStats.from_dict(doc).isolated is None  # written before it was kept
    assert HierarchyStats.merge([HierarchyStats.from_dict(doc), stats]).isolated is None
    for row, message in (([3, 2], "3 alone of 2"), ([1], "ValueError"), ([-1, 2], "-1 alone")):
        doc["isolated"] = {"chair": row}
        with pytest.raises(UserError, match=message):
            HierarchyStats.from_dict(doc, "stats.json")


def test_pots_turned_any_way_stand_by_the_walls_their_footprint_reaches():
    """Turned 40 degrees, a plant whose footprint comes 0.05 m from a wall stands by it and
    one within reach of two stands in a corner, never sideways; a chair turned so stands
    by no wall (its face is not parallel to one); a plant mid-room stands free (0 to 4 m
    room)."""

    def thing(oid, category, xy, degrees=40.0):
        box = OrientedBox.from_yaw([*xy, 0.4], [0.4, 0.4, 0.8], np.radians(degrees))
        return SceneObject(oid, category, box, None, FLOOR, None)

    reach = 0.2 * np.sqrt(2) * np.cos(np.radians(5)) + 0.05  # half diagonal's reach, + gap
    objects = [
        thing("p0", "house_plant", [2.0, reach]),  # by the wall y = 0
        thing("p1", "house_plant", [4 - reach, 4 - reach]),  # in the corner (4, 4)
        thing("p2", "house_plant", [2.0, 2.0]),  # mid-room
        thing("c0", "chair", [1.0, reach]),  # turned: no face against the wall
        thing("p3", "house_plant", [3.0, 0.2], degrees=0.0),  # square to the wall y = 0
    ]
    scene = Scene("s", Room("living_room", ROOM), objects, source="test", split="train")
    walls = HierarchyStats.fit([scene]).room_type("living_room")
    assert walls.on_floor["house_plant"] == 4 and walls.against_wall["house_plant"] == 3
    assert walls.in_corner["house_plant"] == 1 and walls.sideways["house_plant"] == 0
    assert walls.against_wall["chair"] == 0

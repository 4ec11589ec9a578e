"""Wall objects in the hierarchy statistics and in synthesized hierarchies."""

from __future__ import annotations

from collections import Counter

import numpy as np

from pair2scene.curation.stats import HierarchyStats, split_member, template_member
from pair2scene.hierarchy.synthesis import SynthesisConfig, synthesize
from pair2scene.scene.geometry import OrientedBox
from pair2scene.scene.model import FLOOR, Room, Scene, SceneObject

ROOM = np.array([[0, 0], [4, 0], [4, 4], [0, 4]], float)


def _room(scene_id: str, spec: list[tuple]) -> Scene:
    objects = [
        SceneObject(oid, cat, OrientedBox.from_yaw([1, 1, 0.5], [0.5, 0.5, 1.0]), None, sup, fa)
        for oid, cat, sup, fa in spec
    ]
    return Scene(scene_id, Room("bedroom", ROOM), objects, source="test", split="train")


def _scenes() -> list[Scene]:
    return [
        _room("a", [("bed_0", "bed", FLOOR, None), ("painting_0", "painting", "wall:1", "bed_0"),
                    ("painting_1", "painting", "wall:2", None),
                    ("television_0", "television", "wall:3", "bed_0")]),
        _room("b", [("bed_0", "bed", FLOOR, None), ("painting_0", "painting", "wall:0", "bed_0"),
                    ("television_0", "television", "bed_0", None)]),
    ]  # fmt: skip


def test_wall_objects_join_the_templates_and_the_wall_statistics():
    stats = HierarchyStats.fit(_scenes())
    rs = stats.room_types["bedroom"]
    assert rs.layouts == Counter({
        ("bed", "painting@wall", "painting@wall", "television@wall"): 1,
        ("bed", "painting@wall"): 1,
    })  # fmt: skip
    assert stats.sup_dep["wall"] == Counter({"painting": 3, "television": 1})
    assert stats.func_dep["wall"]["bed"] == Counter({"painting": 2, "television": 1})
    # every wall object stood in a room with a bed: the denominator of "hangs over it"
    assert stats.func_present["wall"]["bed"] == Counter({"painting": 3, "television": 1})
    assert rs.object_counts == Counter({4: 1, 3: 1})  # wall objects are placed objects
    back = HierarchyStats.from_json(stats.to_json())
    assert back.room_types["bedroom"].layouts == rs.layouts


def test_template_members():
    tv = SceneObject("t", "television", OrientedBox.from_yaw([0, 0, 1], [1, 0.1, 0.6]))
    assert template_member(tv) is None  # not placed yet
    assert template_member(SceneObject("t", "television", tv.box, support="wall:2")) == (
        "television@wall"
    )
    assert template_member(SceneObject("b", "bed", tv.box, support=FLOOR)) == "bed"
    assert split_member("painting@wall") == ("painting", True)
    assert split_member("bed") == ("bed", False)


def test_synthesis_hangs_template_wall_objects_on_walls_over_their_anchor():
    stats = HierarchyStats.fit(_scenes())
    seen = Counter()
    for seed in range(20):
        h = synthesize(stats, "bedroom", SynthesisConfig(mode="fit", seed=seed))
        for n in h.nodes:
            if n.category == "painting":
                assert h.support[n.id] == "wall"
                seen[h.functional.get(n.id)] += 1
        assert [s.dependent.category for s in h.sequence()][0] == "bed"
    # 2 of 3 paintings hung over the bed in the data
    assert seen["bed_0"] > 0 and seen[None] > 0


def test_mount_heights_are_counted_per_category_and_survive_json():
    scenes = _scenes()  # every box's centre at 0.5 m; set the wall objects' heights
    heights = {("a", "painting_0"): 1.4, ("a", "painting_1"): 1.8, ("b", "painting_0"): 1.6,
               ("a", "television_0"): 1.5}  # fmt: skip
    for s in scenes:
        for i, o in enumerate(s.objects):
            z = heights.get((s.id, o.id))
            if z is not None:
                s.objects[i] = SceneObject(o.id, o.category,
                                           OrientedBox.from_yaw([1, 1, z], [0.5, 0.1, 0.4]),
                                           None, o.support, o.functional_anchor)  # fmt: skip
    stats = HierarchyStats.fit(scenes)
    # the television on the bed in room b rests on a support, not a wall: not counted
    assert set(stats.mount_height) == {"painting", "television"}
    np.testing.assert_allclose(stats.mount_height["painting"]["wall"], [3.0, 4.8, 7.76])
    np.testing.assert_allclose(stats.mount_height["television"]["wall"], [1.0, 1.5, 2.25])
    back = HierarchyStats.from_json(stats.to_json())
    np.testing.assert_allclose(back.mount_height["painting"]["wall"], [3.0, 4.8, 7.76])
    merged = HierarchyStats.merge([stats, stats])
    assert merged.mount_height["painting"]["wall"][0] == 6.0

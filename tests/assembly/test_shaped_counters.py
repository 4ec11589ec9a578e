"""L and C counters stand as the training rooms' do: against a wall nearly always (91 of
94, against 120 of 140 straight runs) and almost never sideways (1 of 91)."""

from __future__ import annotations

from dataclasses import replace

import numpy as np

from pair2scene.assembly.walls import WallRules
from pair2scene.assets.forms import SHAPED, form_key, form_of
from pair2scene.curation.stats import HierarchyStats
from pair2scene.scene.geometry import OrientedBox
from pair2scene.scene.model import FLOOR, Room, Scene, SceneObject

RECT = np.array([[0, 0], [5, 0], [5, 4], [0, 4]], float)


def test_a_counter_deeper_and_wider_than_the_threshold_takes_the_shaped_form():
    assert form_of("counter_top", [2.4, 1.8, 0.9]) == SHAPED
    assert form_of("counter_top", [2.4, 0.6, 0.9]) is None  # a straight run
    assert form_of("counter_top", [1.0, 1.0, 0.9]) is None  # a block under 1.1 m
    assert form_of("dining_table", [2.4, 1.8, 0.75]) is None  # only counters have forms
    assert form_key("counter_top", [2.4, 1.8, 0.9]) == "counter_top#shaped"
    assert form_key("counter_top", [2.4, 0.6, 0.9]) is None


def _kitchen(i: int) -> Scene:
    """A run mid-room in every other room; an L in the NE corner in each."""
    room = Room("kitchen", RECT)
    l_counter = OrientedBox.from_yaw([4.0, 3.1, 0.45], [2.0, 1.8, 0.9], np.pi)
    run = OrientedBox.from_yaw([2.0, 3.7, 0.45], [1.6, 0.6, 0.9], np.pi)  # north wall
    if i % 2:
        run = OrientedBox.from_yaw([2.0, 1.5, 0.45], [1.6, 0.6, 0.9], 0.0)  # an island
    objects = [
        SceneObject("counter_0", "counter_top", l_counter, None, FLOOR),
        SceneObject("counter_1", "counter_top", run, None, FLOOR),
    ]
    return Scene(f"k{i}", room, objects)


def test_statistics_count_the_shaped_form_apart_and_round_trip():
    stats = HierarchyStats.fit([_kitchen(i) for i in range(6)])
    rs = stats.room_types["kitchen"]
    assert rs.on_floor["counter_top"] == 12 and rs.against_wall["counter_top"] == 9
    assert rs.on_floor["counter_top#shaped"] == 6 and rs.against_wall["counter_top#shaped"] == 6
    assert rs.in_corner["counter_top#shaped"] == 6
    back = HierarchyStats.from_json(stats.to_json())
    assert back.room_types["kitchen"].on_floor == rs.on_floor
    rules = WallRules.from_stats(back)
    shaped, run = [2.0, 1.8, 0.9], [1.6, 0.6, 0.9]
    assert rules.rate("kitchen", "counter_top") == 0.75  # the category, as before
    assert rules.rate("kitchen", "counter_top", run) == 0.75
    assert rules.rate("kitchen", "counter_top", shaped) == 1.0
    assert rules.corner_rate("kitchen", "counter_top", shaped) == 1.0
    assert all(rules.against_wall("kitchen", "counter_top", s, shaped) for s in range(50))
    assert rules.rate("bedroom", "counter_top", shaped) == 1.0  # pooled over room types


def test_a_form_seen_a_few_times_takes_its_categorys_shares():
    """One L counter in four kitchens, against no wall: its form's 0 of 1 is not trusted,
    the category's 3 of 4 stands in (MIN_FORM_OBJECTS)."""
    scenes = [_kitchen(i) for i in range(4)]
    for scene in scenes[1:]:  # three kitchens keep only their run, all against the wall
        scene.objects[:] = [o for o in scene.objects if o.id == "counter_1"]
        scene.objects[0] = replace(scene.objects[0], box=OrientedBox.from_yaw(
            [2.0, 3.7, 0.45], [1.6, 0.6, 0.9], np.pi))  # fmt: skip
    island = OrientedBox.from_yaw([2.5, 2.0, 0.45], [2.0, 1.8, 0.9], 0.0)  # an L mid-room
    scenes[0].objects[0] = replace(scenes[0].objects[0], box=island)
    rules = WallRules.from_stats(HierarchyStats.fit(scenes))
    assert rules.rates["kitchen"]["counter_top#shaped"] == (0, 1)
    assert rules.rate("kitchen", "counter_top", [2.0, 1.8, 0.9]) == 0.8  # 4 of 5


def test_statistics_without_forms_give_the_category_rate():
    doc = HierarchyStats.fit([_kitchen(i) for i in range(4)]).to_dict()
    for walls in (rd["walls"] for rd in doc["room_types"].values()):
        walls.pop("counter_top#shaped", None)
    rules = WallRules.from_stats(HierarchyStats.from_dict(doc))
    assert rules.rate("kitchen", "counter_top", [2.0, 1.8, 0.9]) == 0.75

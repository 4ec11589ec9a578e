"""L and C counters stand as the training rooms' do: against a wall nearly always (91 of
94, against 120 of 140 straight runs), never sideways, and an L in the corner where its
side run goes along the second wall."""

from __future__ import annotations

import numpy as np
import pytest

from pair2scene.assembly.walls import WallRules, to_corners
from pair2scene.assets.forms import SHAPED, arm_side, form_key, form_of, is_form_key
from pair2scene.assets.registry import generate
from pair2scene.curation.stats import HierarchyStats
from pair2scene.scene.geometry import OrientedBox
from pair2scene.scene.model import FLOOR, Room, Scene, SceneObject
from pair2scene.scene.walls import in_corner, walls_of

RECT = np.array([[0, 0], [5, 0], [5, 4], [0, 4]], float)


def test_a_counter_deeper_and_wider_than_the_threshold_takes_the_shaped_form():
    assert form_of("counter_top", [2.4, 1.8, 0.9]) == SHAPED
    assert form_of("counter_top", [2.4, 0.6, 0.9]) is None  # a straight run
    assert form_of("counter_top", [1.0, 1.0, 0.9]) is None  # a block under 1.1 m
    assert form_of("dining_table", [2.4, 1.8, 0.75]) is None  # only counters have forms
    assert form_key("counter_top", [2.4, 1.8, 0.9]) == "counter_top#shaped"
    assert form_key("counter_top", [2.4, 0.6, 0.9]) is None
    assert is_form_key("counter_top#shaped") and not is_form_key("counter_top")


def test_arm_side_tells_an_l_from_a_c_and_a_run():
    sides = {arm_side(generate("counter_top", [2.4, 1.8, 0.9], s).parts) for s in range(40)}
    assert sides == {0, 1}  # Ls (the side run at +x) and Cs (both sides) both occur
    run = generate("counter_top", [2.4, 0.6, 0.9], 0)
    assert arm_side(run.parts) == 0
    for s in range(40):
        parts = generate("counter_top", [2.4, 1.8, 0.9], s).parts
        right = [p for p in parts if p.name.startswith("right_")]
        left = [p for p in parts if p.name.startswith("left_")]
        assert right and arm_side(parts) == (0 if left else 1)
        # the side run stands at the counter's +x end
        assert min(p.mesh.vertices[:, 0].min() for p in right) > 0


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
    stats = HierarchyStats.fit([_kitchen(i) for i in range(4)])
    rs = stats.room_types["kitchen"]
    assert rs.on_floor["counter_top"] == 8 and rs.against_wall["counter_top"] == 6
    assert rs.on_floor["counter_top#shaped"] == 4 and rs.against_wall["counter_top#shaped"] == 4
    assert rs.in_corner["counter_top#shaped"] == 4
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


def test_statistics_without_forms_give_the_category_rate():
    doc = HierarchyStats.fit([_kitchen(i) for i in range(4)]).to_dict()
    for walls in (rd["walls"] for rd in doc["room_types"].values()):
        walls.pop("counter_top#shaped", None)
    rules = WallRules.from_stats(HierarchyStats.from_dict(doc))
    assert rules.rate("kitchen", "counter_top", [2.0, 1.8, 0.9]) == 0.75


@pytest.mark.parametrize("yaw", [0.0, np.pi])
def test_an_l_counter_goes_only_into_the_corner_on_its_side_runs_side(yaw):
    walls = walls_of(RECT)
    wall = walls[2] if yaw == np.pi else walls[0]  # north (facing -y) or south (+y)
    y = 3.1 if yaw == np.pi else 0.9
    box = OrientedBox.from_yaw([2.5, y, 0.45], [2.0, 1.8, 0.9], yaw)
    both = to_corners(box, wall, (True, True))
    assert len(both) == 2
    ((end, right),) = to_corners(box, wall, (True, True), arm=1)
    # the box's +x: world +x facing +y (south wall), world -x facing -y (north wall)
    x_dir = box.rotation[:2, 0]
    moved = right.center[:2] - box.center[:2]
    assert float(moved @ x_dir) > 0 and in_corner(right, walls)
    ((_, left),) = to_corners(box, wall, (True, True), arm=-1)
    assert float((left.center[:2] - box.center[:2]) @ x_dir) < 0
    # only the other end a convex corner (an inner corner on the arm's side): none fits
    assert to_corners(box, wall, (end == 1, end == 0), arm=1) == []

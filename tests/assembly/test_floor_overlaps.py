"""Floor objects over or under another's footprint: the overlap of two footprints, what
the statistics count, which pairs the rule lets overlap, and placement pushing the others
clear (issue 18: rooms that look furnished, not a side table under a dining table's
edge)."""

from __future__ import annotations

from collections import Counter

import numpy as np
import pytest

from pair2scene.assembly.overlaps import MIN_OVERLAPS, FloorOverlaps
from pair2scene.assembly.place import AssemblyConfig, Placer
from pair2scene.assets.registry import generate
from pair2scene.curation.stats import (
    FLOOR_OVERLAP_SHARE,
    HierarchyStats,
    floor_overlaps,
    footprint_overlap,
    overlap_key,
)
from pair2scene.errors import UserError
from pair2scene.hierarchy.tree import Hierarchy
from pair2scene.scene.geometry import OrientedBox, convex_overlap_area
from pair2scene.scene.model import FLOOR, Room, Scene, SceneObject
from pair2scene.scene.relations import footprint

ROOM = Room("living_room", np.array([[0, 0], [6, 0], [6, 5], [0, 5]], float), 2.6)
TABLE = OrientedBox.from_yaw([3.0, 2.5, 0.375], [1.6, 0.9, 0.75])
"""A dining table in the middle of the room: x 2.2 to 3.8, y 2.05 to 2.95."""
UNDER_EDGE = OrientedBox.from_yaw([3.0, 2.0, 0.225], [0.4, 0.4, 0.45])
"""A low box half under the table's south edge: 0.15 of its 0.4 m depth, 0.375 of its
footprint, between the table's legs and below its top."""
SQUARE = np.array([[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]])


def test_the_overlap_of_two_convex_footprints():
    assert convex_overlap_area(SQUARE, SQUARE + 0.5) == pytest.approx(0.25)
    assert convex_overlap_area(SQUARE, SQUARE + 2.0) == 0.0
    assert convex_overlap_area(SQUARE, SQUARE + [1.0, 0.0]) == pytest.approx(0.0)  # touching
    inner = 0.25 + 0.5 * SQUARE
    assert convex_overlap_area(SQUARE, inner) == pytest.approx(0.25)  # inside: all of it
    assert convex_overlap_area(inner, SQUARE) == pytest.approx(0.25)
    # a square turned 45 degrees about the unit square's centre: the octagon they share
    h = np.sqrt(0.5)
    diamond = 0.5 + np.array([[h, 0.0], [0.0, h], [-h, 0.0], [0.0, -h]])
    octagon = 1.0 - 4 * 0.5 * (h - 0.5) ** 2 * 2  # the square less four corner triangles
    assert convex_overlap_area(SQUARE, diamond) == pytest.approx(octagon)
    # as a share of the smaller one
    assert footprint_overlap(footprint(TABLE), footprint(UNDER_EDGE)) == pytest.approx(0.375)


def _room(i: int) -> Scene:
    """A table with a chair tucked half under it, a side table half under its other
    edge, and an armchair beside it, touching."""
    chair = OrientedBox.from_yaw([2.5, 3.0 + 0.01 * i, 0.45], [0.5, 0.5, 0.9], np.pi)
    side = OrientedBox.from_yaw([3.0, 2.0, 0.225], [0.4, 0.4, 0.45])
    arm = OrientedBox.from_yaw([4.2, 2.5, 0.4], [0.8, 0.8, 0.8])  # x from 3.8: touching
    objects = [
        SceneObject("table_0", "dining_table", TABLE, None, FLOOR),
        SceneObject("chair_0", "chair", chair, None, FLOOR, functional_anchor="table_0"),
        SceneObject("side_table_0", "side_table", side, None, FLOOR),
        SceneObject("armchair_0", "armchair", arm, None, FLOOR),
        SceneObject(
            "vase_0", "vase", OrientedBox.from_yaw([3.0, 2.5, 0.85], [0.1] * 3), None, "table_0"
        ),  # fmt: skip  (on the table: not a floor object)
    ]
    return Scene(f"r{i}", ROOM, objects)


def test_statistics_count_the_pairs_that_overlap():
    assert overlap_key("dining_table", "chair") == "chair|dining_table"
    assert floor_overlaps(_room(0).objects) == Counter(
        {"chair|dining_table": 1, "dining_table|side_table": 1}
    )
    stats = HierarchyStats.fit([_room(i) for i in range(4)])
    assert stats.floor_overlaps == Counter({"chair|dining_table": 4, "dining_table|side_table": 4})
    assert HierarchyStats.from_json(stats.to_json()).floor_overlaps == stats.floor_overlaps
    merged = HierarchyStats.merge([HierarchyStats.fit([_room(i)]) for i in range(3)])
    assert merged.floor_overlaps == Counter({"chair|dining_table": 3, "dining_table|side_table": 3})
    doc = stats.to_dict()
    doc["floor_overlaps"]["chair|dining_table"] = -1
    with pytest.raises(UserError, match="floor_overlaps"):
        HierarchyStats.from_dict(doc)
    del doc["floor_overlaps"]  # written before it was kept: loaded, and no rule
    old = HierarchyStats.from_dict(doc)
    assert old.floor_overlaps is None
    assert FloorOverlaps.from_stats(old) is None
    assert HierarchyStats.merge([old, stats]).floor_overlaps is None


def test_the_rule_lets_overlap_only_pairs_seen_often_enough():
    stats = HierarchyStats.fit([_room(i) for i in range(MIN_OVERLAPS)])
    stats.floor_overlaps["dining_table|side_table"] = MIN_OVERLAPS - 1
    rule = FloorOverlaps.from_stats(stats)
    assert rule.allows("chair", "dining_table") and rule.allows("dining_table", "chair")
    assert not rule.allows("side_table", "dining_table")
    assert not rule.allows("armchair", "dining_table")  # never seen overlapping
    placed = [("t", "dining_table", TABLE)]
    assert rule.check("side_table", placed).hits(UNDER_EDGE) == ["t"]
    assert rule.check("chair", placed).hits(UNDER_EDGE) == []  # a chair may tuck under
    beside = OrientedBox.from_yaw([3.0, 1.84, 0.225], [0.4, 0.4, 0.45])  # 0.01 m under
    assert footprint_overlap(footprint(TABLE), footprint(beside)) < FLOOR_OVERLAP_SHARE
    assert rule.check("side_table", placed).hits(beside) == []


class _UnderTheTable:
    """A stand-in model: the table where given, anything else half under its south edge."""

    honours_temperature = False
    draws_in_frames = False

    def draw(self, query, n, temperature, generator):
        box = TABLE if query.category == "dining_table" else UNDER_EDGE
        return np.repeat(box.to_vector()[None], n, axis=0), None


@pytest.mark.parametrize("category", ["side_table", "chair"])
@pytest.mark.parametrize("separate", [True, False])
def test_placement_pushes_a_floor_object_from_under_another(category, separate):
    h = Hierarchy("living_room")
    table = h.add("dining_table", FLOOR)
    other = h.add(category, FLOOR)
    assets = {
        table.id: generate("dining_table", TABLE.size, 0, style=0),
        other.id: generate(category, UNDER_EDGE.size, 0),
    }
    config = AssemblyConfig(walls=False, navigable=False, separate_footprints=separate,
                            candidates=4, batches=1)  # fmt: skip
    rule = FloorOverlaps(frozenset({"chair|dining_table"}))
    result = Placer(_UnderTheTable(), config=config, overlaps=rule).place(
        h.validate(), ROOM, seed=0, assets=assets
    )
    assert result.stats.placed == 2, result.stats.dropped
    boxes = {o.category: o.box for o in result.scene.objects}
    share = footprint_overlap(footprint(boxes["dining_table"]), footprint(boxes[category]))
    if separate and category == "side_table":
        assert share <= FLOOR_OVERLAP_SHARE  # pushed out from under the edge
        assert boxes[category].center[1] < 2.0  # southwards, the short way out
    else:  # a chair may tuck under its table; without the rule, anything may
        assert share == pytest.approx(0.375, abs=0.01)


def test_evaluate_counts_floor_objects_over_or_under_another():
    from pair2scene.metrics.layout import floor_overlaps as measure
    from pair2scene.metrics.layout import layout_section

    # the side table under the table's edge and the table: 2 of the 4 floor objects; the
    # chair tucked under the table is not counted, nor the armchair touching it, nor the
    # vase on it
    assert measure(_room(0)) == [2, 4]
    apart = Scene("a", ROOM, [o for o in _room(0).objects if o.category != "side_table"])
    assert measure(apart) == [0, 3]
    row = layout_section([_room(0)], [apart, apart])["floor_overlaps"]
    assert row["reference"]["count"] == [2, 4] and row["generated"]["count"] == [0, 6]

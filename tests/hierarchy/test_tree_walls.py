"""Hierarchies with wall-mounted objects: walls are roots after the floor, and a wall
object may take a floor object as its functional anchor."""

from __future__ import annotations

import pytest

from pair2scene.hierarchy.tree import Hierarchy, HierarchyError


def bedroom() -> Hierarchy:
    h = Hierarchy("bedroom")
    bed = h.add("bed", "floor")
    table = h.add("side_table", "floor", bed.id)
    h.add("painting", "wall", bed.id)
    h.add("curtains", "wall")
    h.add("mirror", "wall:2")
    h.add("table_lamp", table.id)
    return h.validate()


def test_walls_are_roots_placed_after_the_floor_and_before_what_rests_on_furniture():
    seq = [(s.dependent.id, s.support, s.functional) for s in bedroom().sequence()]
    assert seq == [
        ("bed_0", "floor", None),
        ("side_table_0", "floor", "bed_0"),
        ("painting_0", "wall", "bed_0"),
        ("curtains_0", "wall", None),
        ("mirror_0", "wall:2", None),
        ("table_lamp_0", "side_table_0", None),
    ]
    assert bedroom().roots() == ["floor", "wall", "wall:2"]


def test_round_trip_keeps_walls_and_floor_anchors():
    h = bedroom()
    back = Hierarchy.from_dict(h.to_dict())
    assert back.support == h.support and back.functional == h.functional
    edges = h.to_dict()["support_tree"]["edges"]
    assert {"parent": {"id": "wall", "category": "wall"},
            "child": {"id": "painting_0", "category": "painting"}} in edges  # fmt: skip


@pytest.mark.parametrize("support", ["wall:x", "wall:", "walls", "wall:-1"])
def test_malformed_walls_are_refused(support):
    h = Hierarchy("bedroom")
    h.add("painting", support)
    with pytest.raises(HierarchyError, match="rests on"):
        h.validate()


def test_only_wall_objects_may_take_an_anchor_on_another_support():
    h = Hierarchy("bedroom")
    bed = h.add("bed", "floor")
    desk = h.add("desk", "floor")
    h.add("book", desk.id, bed.id)
    with pytest.raises(HierarchyError, match="must share the support"):
        h.validate()
    h = Hierarchy("bedroom")
    desk = h.add("desk", "floor")
    book = h.add("book", desk.id)
    h.add("painting", "wall", book.id)  # a painting hangs over floor objects only
    with pytest.raises(HierarchyError, match="must share the support"):
        h.validate()


def test_a_wall_object_over_its_anchor_round_trips_and_is_checked():
    h = bedroom()
    h.over.add("painting_0")
    doc = h.validate().to_dict()
    (tree,) = [t for t in doc["functional_trees"] if t["support_anchor"]["id"] == "wall"]
    over = {e["dependent"]["id"]: e.get("over", False) for e in tree["edges"]}
    assert over == {"painting_0": True, "curtains_0": False}
    assert Hierarchy.from_dict(doc).over == {"painting_0"}
    assert Hierarchy.from_dict(bedroom().to_dict()).over == set()  # absent: not over
    (edge,) = [e for e in tree["edges"] if "over" in e]
    edge["over"] = "yes"
    with pytest.raises(HierarchyError, match="malformed hierarchy.*'over'"):
        Hierarchy.from_dict(doc)
    for node_id, message in [
        ("curtains_0", "with a functional anchor"),  # no anchor
        ("side_table_0", "a node on a wall"),  # on the floor
        ("nobody", "a node on a wall"),
    ]:
        h = bedroom()
        h.over.add(node_id)
        with pytest.raises(HierarchyError, match=message):
            h.validate()
    h = Hierarchy("bedroom")  # over a wall object: nothing to hang over on the floor
    painting = h.add("painting", "wall")
    h.add("wall_lamp", "wall", painting.id)
    h.over.add("wall_lamp_0")
    with pytest.raises(HierarchyError, match="must stand on the floor"):
        h.validate()


def test_a_wall_object_across_from_its_anchor_round_trips_and_is_checked():
    h = bedroom()
    h.across.add("painting_0")
    doc = h.validate().to_dict()
    (tree,) = [t for t in doc["functional_trees"] if t["support_anchor"]["id"] == "wall"]
    flags = {e["dependent"]["id"]: (e.get("over"), e.get("across")) for e in tree["edges"]}
    assert flags == {"painting_0": (None, True), "curtains_0": (None, None)}
    back = Hierarchy.from_dict(doc)
    assert back.across == {"painting_0"} and back.over == set()
    (edge,) = [e for e in tree["edges"] if "across" in e]
    edge["across"] = 1
    with pytest.raises(HierarchyError, match="malformed hierarchy.*'across'"):
        Hierarchy.from_dict(doc)
    for node_id, message in [
        ("curtains_0", "across from its anchor, so it must be.*functional anchor"),
        ("side_table_0", "a node on a wall"),
    ]:
        h = bedroom()
        h.across.add(node_id)
        with pytest.raises(HierarchyError, match=message):
            h.validate()
    h = bedroom()
    h.over.add("painting_0")
    h.across.add("painting_0")
    with pytest.raises(HierarchyError, match="both over and across"):
        h.validate()

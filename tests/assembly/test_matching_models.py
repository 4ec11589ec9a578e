"""A room's floor objects of one category are one model as often as the training rooms'."""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest

from pair2scene.assembly.place import AssemblyConfig, Placer
from pair2scene.curation.stats import HierarchyStats
from pair2scene.errors import UserError
from pair2scene.hierarchy.tree import Hierarchy
from pair2scene.scene.geometry import OrientedBox
from pair2scene.scene.model import FLOOR, AssetRef, Room, Scene, SceneObject

ROOM = np.array([[0, 0], [4, 0], [4, 4], [0, 4]], float)


def _room(scene_id: str, spec: list[tuple]) -> Scene:
    """spec: (id, category, support, asset id or None)."""
    box = OrientedBox.from_yaw([1, 1, 0.5], [0.5, 0.5, 1.0])
    objects = [
        SceneObject(oid, cat, box, None if aid is None else AssetRef("ai2thor", aid), sup)
        for oid, cat, sup, aid in spec
    ]
    return Scene(scene_id, Room("kitchen", ROOM), objects, source="test", split="train")


def test_rooms_with_two_or_more_of_a_floor_category_are_counted():
    scenes = [
        _room("a", [("c0", "chair", FLOOR, "Chair_1"), ("c1", "chair", FLOOR, "Chair_1"),
                    ("t0", "dining_table", FLOOR, "Table_1"),
                    ("m0", "mug", "t0", "Mug_1"), ("m1", "mug", "t0", "Mug_2")]),
        _room("b", [("c0", "chair", FLOOR, "Chair_1"), ("c1", "chair", FLOOR, "Chair_2"),
                    ("c2", "chair", FLOOR, None)]),
        _room("c", [("c0", "chair", FLOOR, "Chair_3")]),  # one chair: not a set
    ]  # fmt: skip
    stats = HierarchyStats.fit(scenes)
    assert stats.same_model == {"chair": [2, 1]}  # (mugs stand on a table: not floor objects)
    assert stats.same_model_shares(min_rooms=2) == {"chair": 0.5}
    assert stats.same_model_shares(min_rooms=3) == {}
    back = HierarchyStats.from_json(stats.to_json())
    assert back.same_model == stats.same_model
    merged = HierarchyStats.merge([stats, back])
    assert merged.same_model == {"chair": [4, 2]}
    doc = stats.to_dict()
    doc.pop("same_model")  # statistics written before it was kept
    assert HierarchyStats.from_dict(doc).same_model_shares(min_rooms=0) == {}
    doc["same_model"] = {"chair": [1, 2]}
    with pytest.raises(UserError, match="malformed"):
        HierarchyStats.from_dict(doc)


def _kitchen() -> Hierarchy:
    h = Hierarchy("kitchen")
    table = h.add("dining_table", FLOOR)
    for _ in range(4):
        h.add("chair", FLOOR, table.id)
    h.add("stool", FLOOR)
    h.add("stool", FLOOR)
    h.add("cup", table.id)
    h.add("cup", table.id)
    return h


def _models(placer: Placer, h: Hierarchy, seed: int, category: str) -> set:
    assets = placer.assets_for(h, seed)
    return {id(assets[n.id]) for n in h.nodes if n.category == category}


def test_a_room_shares_a_model_as_often_as_the_training_rooms():
    h = _kitchen()
    # Each object's mesh drawn anew (with the asset library, two stools drawn at one size
    # are one mesh whatever the shares)
    drawn = AssemblyConfig(asset_library=False)
    always = Placer(None, config=drawn, same_model={"chair": 1.0, "cup": 1.0})
    for seed in range(5):
        assert len(_models(always, h, seed, "chair")) == 1  # one model for the four
        assert len(_models(always, h, seed, "stool")) == 2  # stools: no share known
        assert len(_models(always, h, seed, "cup")) == 2  # on a table: each its own
    never = Placer(None, config=drawn, same_model={"chair": 0.0})
    assert all(len(_models(never, h, s, "chair")) == 4 for s in range(5))
    off = Placer(None, config=replace(drawn, matching=False), same_model={"chair": 1.0})
    assert all(len(_models(off, h, s, "chair")) == 4 for s in range(5))
    half = Placer(None, config=drawn, same_model={"chair": 0.5})
    shared = [len(_models(half, h, s, "chair")) == 1 for s in range(40)]
    assert 8 <= sum(shared) <= 32  # (drawn per room)
    assert shared == [len(_models(half, h, s, "chair")) == 1 for s in range(40)]  # same seed
    first = always.assets_for(h, 0)
    chairs = [n.id for n in h.nodes if n.category == "chair"]
    assert first[chairs[0]] is first[chairs[3]]
    assert never.assets_for(h, 0)[chairs[0]].size.tolist() == first[chairs[0]].size.tolist()

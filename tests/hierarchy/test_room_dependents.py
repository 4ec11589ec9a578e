"""What rests on what is drawn per room type: a bathroom's counter holds a bathroom's
things, not a kitchen's (room-type ``sup_dep`` in the statistics, shrunk towards the
pooled rates)."""

from __future__ import annotations

import json
from collections import Counter

import numpy as np
import pytest

from pair2scene.curation.stats import HierarchyStats
from pair2scene.hierarchy.synthesis import (
    ROOM_PRIOR,
    Statistics,
    SynthesisConfig,
    load_stats,
    synthesize,
)
from pair2scene.scene.geometry import OrientedBox
from pair2scene.scene.model import FLOOR, Room, Scene, SceneObject

ROOM = np.array([[0, 0], [4, 0], [4, 4], [0, 4]], float)


def room(scene_id: str, room_type: str, spec: list[tuple]) -> Scene:
    """spec: (id, category, support)."""
    objects = [
        SceneObject(oid, cat, OrientedBox.from_yaw([1, 1, 0.5], [0.5, 0.5, 1.0]), None, sup, None)
        for oid, cat, sup in spec
    ]
    return Scene(scene_id, Room(room_type, ROOM), objects, source="test", split="train")


def corpus() -> list[Scene]:
    kitchen = room("k", "kitchen", [
        ("counter_0", "counter_top", FLOOR), ("bread_0", "bread", "counter_0"),
        ("lettuce_0", "lettuce", "counter_0"), ("soap_0", "soap_bottle", "counter_0"),
        ("counter_1", "counter_top", FLOOR), ("bread_1", "bread", "counter_1"),
    ])  # fmt: skip
    bathroom = room("b", "bathroom", [
        ("counter_0", "counter_top", FLOOR), ("soap_0", "soap_bottle", "counter_0"),
        ("toilet_0", "toilet", FLOOR),
    ])  # fmt: skip
    return [kitchen, bathroom]


def test_room_types_keep_their_own_support_counts():
    stats = HierarchyStats.fit(corpus())
    bath = stats.room_types["bathroom"].sup_dep
    assert bath == {FLOOR: {"counter_top": 1, "toilet": 1}, "counter_top": {"soap_bottle": 1}}
    kitchen = stats.room_types["kitchen"].sup_dep
    assert kitchen["counter_top"] == {"bread": 2, "lettuce": 1, "soap_bottle": 1}
    # pooled over both, as before
    assert stats.sup_dep["counter_top"] == {"bread": 2, "lettuce": 1, "soap_bottle": 2}
    # JSON round trip and merging keep them
    again = HierarchyStats.from_json(json.dumps(stats.to_dict()))
    assert again.room_types["bathroom"].sup_dep == bath
    merged = HierarchyStats.merge(
        [HierarchyStats.fit(corpus()[:1]), HierarchyStats.fit(corpus()[1:])]
    )
    assert merged.room_types["kitchen"].sup_dep == kitchen
    assert merged.to_dict() == stats.to_dict()


def test_statistics_written_before_load_with_pooled_rates():
    doc = HierarchyStats.fit(corpus()).to_dict()
    for rd in doc["room_types"].values():
        del rd["sup_dep"]
    old = HierarchyStats.from_dict(doc)
    assert old.room_types["bathroom"].sup_dep == {}
    pooled = dict(Statistics(old).dependents("counter_top"))
    assert dict(Statistics(old, old.room_types["bathroom"]).dependents("counter_top")) == pooled


def test_a_bathroom_counter_holds_what_bathrooms_held():
    stats = HierarchyStats.fit(corpus())
    pooled = dict(Statistics(stats).dependents("counter_top"))
    # 3 counters hold 2 bread, 1 lettuce, 2 soap bottles
    assert pooled == pytest.approx({"bread": 2 / 3, "lettuce": 1 / 3, "soap_bottle": 2 / 3})
    bath = dict(Statistics(stats, stats.room_types["bathroom"]).dependents("counter_top"))
    # only what bathrooms held; its one counter's soap shrunk towards the pooled 2/3
    assert bath == pytest.approx({"soap_bottle": (1 + ROOM_PRIOR * 2 / 3) / (1 + ROOM_PRIOR)})
    kitchen = dict(Statistics(stats, stats.room_types["kitchen"]).dependents("counter_top"))
    assert kitchen["bread"] == pytest.approx((2 + ROOM_PRIOR * 2 / 3) / (2 + ROOM_PRIOR))
    assert set(kitchen) == {"bread", "lettuce", "soap_bottle"}


def test_generated_bathrooms_hold_no_kitchen_things():
    stats = load_stats()
    bath = stats.room_types["bathroom"]
    held = Counter()
    for deps in bath.sup_dep.values():
        held.update(deps)
    assert held["toilet"] > 0 and held["bread"] == 0 and held["lettuce"] == 0
    drawn = Counter()
    for seed in range(30):
        h = synthesize(stats, "bathroom", SynthesisConfig(mode="fit", seed=seed))
        drawn.update(n.category for n in h.nodes)
    strangers = {c: n for c, n in drawn.items() if held[c] == 0}
    assert not strangers, f"bathrooms drew what no training bathroom held: {strangers}"
    # and kitchens still hold a kitchen's things
    kitchen = Counter()
    for seed in range(30):
        kitchen.update(
            n.category for n in synthesize(stats, "kitchen", SynthesisConfig(seed=seed)).nodes
        )
    assert kitchen["bread"] + kitchen["lettuce"] + kitchen["apple"] > 0


def test_a_named_stranger_still_rests_on_what_the_room_has():
    """A bowl no training bathroom held, named in the text, rests on a bathroom's piece
    that any room's bowls rest on (a counter), not on a dining table added for it."""
    from pair2scene.hierarchy.build import build_hierarchy

    for seed in range(5):
        h = build_hierarchy(text="a bathroom with a counter and a bowl", seed=seed, llm="never")
        assert h.room_type == "bathroom"
        bowls = [n for n in h.nodes if n.category == "bowl"]
        assert bowls, seed
        holders = {h.by_id()[h.support[b.id]].category for b in bowls if h.support[b.id] != FLOOR}
        assert holders and "dining_table" not in holders, (seed, holders)
        assert not any(note.startswith("added") for note in h.notes), h.notes

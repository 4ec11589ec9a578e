"""Composed room types (office, study, dining room, kids' room): recipes, synthesis, the
room-level statistics they borrow, aliases, errors and one generated office end to end."""

from __future__ import annotations

import json
from collections import Counter
from dataclasses import replace

import numpy as np
import pytest

from clitools import run_cli
from pair2scene.assembly.rooms import RoomTable
from pair2scene.curation.stats import HierarchyStats, split_member
from pair2scene.errors import UserError
from pair2scene.hierarchy import room_types
from pair2scene.hierarchy.build import build_hierarchy, room_key
from pair2scene.hierarchy.synthesis import (
    Statistics,
    SynthesisConfig,
    load_stats,
    synthesize,
    training_mean,
)
from pair2scene.scene.model import FLOOR

COMPOSED = ["office", "study", "dining_room", "kids_room"]


@pytest.fixture(scope="module")
def stats() -> HierarchyStats:
    return load_stats()


def test_the_bundled_recipes(stats):
    types = room_types.composed_types()
    assert set(COMPOSED) <= set(types)
    assert room_types.composable(stats) == sorted(types)  # every base type is trained
    office = types["office"]
    assert {"bed", "fridge", "toilet"} <= office.exclude
    assert {r.category: r.count for r in office.require}["desk"] == (1, 2)
    (chair,) = [r for r in office.require if r.category == "chair"]
    assert (chair.per, chair.anchor) == ("desk", "desk")
    assert "bed" in {r.category for r in types["kids_room"].require}
    assert "bed" in types["dining_room"].exclude
    for spec in types.values():
        assert spec.note and all(b in stats.room_types for b, _ in spec.bases)


@pytest.mark.parametrize("room", COMPOSED)
def test_composed_rooms_hold_their_furniture_and_nothing_excluded(stats, room):
    spec = room_types.composed_types()[room]
    bases = dict(spec.bases)
    base_mean = sum(w * training_mean(stats, b) for b, w in bases.items()) / sum(bases.values())
    counts = []
    for seed in range(20):
        h = synthesize(stats, room, SynthesisConfig(seed=seed)).validate()
        assert h.room_type == room
        cats = {n.id: n.category for n in h.nodes}
        floor = Counter(n.category for n in h.children(FLOOR))
        for r in spec.require:
            times = 1 if r.per is None else floor[r.per]
            assert r.count[0] * times <= floor[r.category] <= r.count[1] * times, (seed, r)
            if r.anchor is not None:
                for n in h.children(FLOOR):
                    if n.category == r.category:  # every one of them at an anchor piece
                        assert cats.get(h.functional.get(n.id)) == r.anchor, (seed, n.id)
        assert not spec.exclude & set(cats.values()), (seed, spec.exclude & set(cats.values()))
        counts.append(len(h))
        assert 4 <= len(h) <= 50, (seed, len(h))
    assert 0.5 * base_mean <= np.mean(counts) <= 1.3 * base_mean, (np.mean(counts), base_mean)


def test_every_office_has_a_desk_with_a_chair_at_it(stats):
    for seed in range(20):
        h = synthesize(stats, "office", SynthesisConfig(seed=seed))
        cats = {n.id: n.category for n in h.nodes}
        floor = [n.category for n in h.children(FLOOR)]
        assert "desk" in floor and "bed" not in floor
        at_desk = [d for d, a in h.functional.items() if cats[d] == "chair" and cats[a] == "desk"]
        assert at_desk, seed


def test_beyond_mode_composes_too(stats):
    h = synthesize(stats, "office", SynthesisConfig(mode="beyond", max_objects=60, seed=1))
    assert len(h) == 60
    cats = Counter(n.category for n in h.children(FLOOR))
    assert cats["desk"] >= 1 and not {"bed", "sofa", "fridge"} & set(cats)


def test_composition_is_deterministic_and_leaves_the_statistics_alone(stats):
    before = json.dumps(stats.to_dict(), sort_keys=True)
    a = room_types.compose(stats, "office", seed=0)
    b = room_types.compose(stats, "office", seed=0)
    c = room_types.compose(stats, "office", seed=1)
    assert a.layout_counts == b.layout_counts and a.layout_counts != c.layout_counts
    assert a.rooms == sum(a.layouts.values()) == sum(a.object_counts.values())
    for layout in a.layouts:
        cats = Counter(split_member(m)[0] for m in layout)
        assert 1 <= cats["desk"] <= 2 and cats["desk"] <= cats["chair"] <= 2 * cats["desk"]
        assert not {"bed", "sofa", "dining_table"} & set(cats)
    view = room_types.room_view(stats, "office")
    assert view.func_dep[FLOOR]["desk"]["chair"] == view.func_present[FLOOR]["desk"]["chair"]
    assert "chair" not in view.func_dep[FLOOR]["dining_table"]
    assert stats.func_dep[FLOOR]["dining_table"]["chair"] > 0  # the shared ones unchanged
    synthesize(stats, "office", SynthesisConfig(seed=3))
    assert json.dumps(stats.to_dict(), sort_keys=True) == before
    one = synthesize(stats, "kids_room", SynthesisConfig(seed=5)).to_dict()
    assert synthesize(stats, "kids_room", SynthesisConfig(seed=5)).to_dict() == one


def test_a_composed_type_draws_with_its_own_view_of_the_shared_rules(stats):
    st, office = Statistics.for_room(stats, "office")
    assert "chair" not in st.stats.func_dep[FLOOR]["dining_table"]
    assert "chair" in stats.func_dep[FLOOR]["dining_table"]  # the shared ones unchanged
    again = Statistics.for_room(stats, "office")[1]
    assert again.layouts == office.layouts  # composed alike each time
    st, living = Statistics.for_room(stats, "living_room")
    assert living is stats.room_types["living_room"] and st.stats is stats


def test_trained_rooms_of_a_type_win_over_its_recipe(stats):
    own = replace(stats, room_types={**stats.room_types, "office": stats.room_types["bedroom"]})
    st = Statistics(own)
    assert st.room("office") is stats.room_types["bedroom"]
    assert "office" not in room_types.composable(own)
    only_kitchens = replace(stats, room_types={"kitchen": stats.room_types["kitchen"]})
    assert room_types.composable(only_kitchens) == ["dining_room"]  # no bedroom, no living room
    with pytest.raises(UserError, match="composed from them: dining_room$"):
        Statistics(only_kitchens).room("office")


@pytest.mark.parametrize(
    "name, key",
    [
        ("office", "office"),
        ("Home office", "office"),
        ("home-office", "office"),
        ("study", "study"),
        ("Dining room", "dining_room"),
        ("kids' room", "kids_room"),
        ("Kids room", "kids_room"),
        ("kid's room", "kids_room"),
        ("children's room", "kids_room"),
        ("Children\u2019s room", "kids_room"),
        ("Living room", "living_room"),
        ("living-room", "living_room"),
        ("bedroom", "bedroom"),
        ("garage", "garage"),
    ],
)
def test_room_names_and_aliases(name, key):
    assert room_key(name) == key
    assert room_key(key) == key


def test_an_alias_builds_its_type(stats):
    h = build_hierarchy(room="children's room", seed=2, stats=stats)
    assert h.room_type == "kids_room"
    assert h.to_dict() == build_hierarchy(room="kids_room", seed=2, stats=stats).to_dict()


def test_an_unknown_type_is_one_line_listing_trained_and_composed(stats):
    with pytest.raises(UserError) as info:
        synthesize(stats, "garage")
    msg = str(info.value)
    assert msg.startswith("unknown room type 'garage'") and "\n" not in msg
    for name in [*stats.room_types, *COMPOSED]:
        assert name in msg
    proc = run_cli("hierarchy", "--room", "garage")
    assert proc.returncode == 2 and proc.stdout == "" and "Traceback" not in proc.stderr
    (line,) = proc.stderr.splitlines()
    assert line.startswith("error: unknown room type 'garage'")
    assert "bedroom" in line and "office" in line and "kids_room" in line


def test_base_types_give_windows_and_wall_rates(stats):
    pooled = stats.room_type("office")
    living, bed = stats.room_types["living_room"], stats.room_types["bedroom"]
    total = living.rooms + bed.rooms
    assert pooled.rooms == total
    for k in set(living.window_counts) | set(bed.window_counts):
        want = (0.6 * total / living.rooms * living.window_counts.get(k, 0)
                + 0.4 * total / bed.rooms * bed.window_counts.get(k, 0))  # fmt: skip
        assert pooled.window_counts[k] == pytest.approx(want)
    assert sum(pooled.window_counts.values()) == pytest.approx(total)
    assert set(pooled.window_shapes) == set(living.window_shapes) | set(bed.window_shapes)
    composed = room_types.compose(stats, "office")
    assert composed.window_counts == pooled.window_counts
    assert composed.against_wall == pooled.against_wall
    # a type with no recipe still pools every type
    assert stats.room_type("garage").rooms == sum(rs.rooms for rs in stats.room_types.values())
    assert stats.room_type("bedroom") is bed


def test_composed_rooms_are_sized_like_their_base_types():
    table = RoomTable(
        {
            "bedroom": np.array([[3.0, 3.0, 2.5]]),
            "living_room": np.array([[6.0, 5.0, 2.5], [6.0, 5.0, 2.5], [6.0, 5.0, 2.5]]),
            "kitchen": np.array([[10.0, 10.0, 3.0]]),
        }
    )
    areas = Counter(
        float(np.prod(table.draw("office", np.random.default_rng(s))[:2])) for s in range(400)
    )
    assert set(areas) == {9.0, 30.0}  # never a kitchen's
    assert 0.3 < areas[9.0] / 400 < 0.5  # bedrooms weigh 0.4, however few their rooms
    large = {float(np.prod(table.draw("office", np.random.default_rng(s), 20.0)[:2]))
             for s in range(20)}  # fmt: skip
    assert large == {30.0}
    assert float(np.prod(table.draw("office", np.random.default_rng(0), 500.0)[:2])) == 30.0
    kids = {
        float(np.prod(table.draw("kids_room", np.random.default_rng(s))[:2])) for s in range(20)
    }
    assert kids == {9.0}
    anything = {float(np.prod(table.draw("garage", np.random.default_rng(s))[:2]))
                for s in range(60)}  # fmt: skip
    assert anything == {9.0, 30.0, 100.0}


@pytest.mark.parametrize(
    "doc, words",
    [
        ({"bases": {}}, "bases"),
        ({"bases": {"bedroom": 1}, "require": {"spaceship": {"count": [1, 1]}}}, "unknown"),
        ({"bases": {"bedroom": 1}, "require": {"book": {"count": [1, 1]}}}, "not floor"),
        ({"bases": {"bedroom": 1}, "require": {"desk": {"count": [2, 1]}}}, "count"),
        (
            {"bases": {"bedroom": 1}, "require": {"desk": {"count": [1, 1]}}, "exclude": ["desk"]},
            "required and excluded",
        ),
        ({"bases": {"bedroom": 1}, "require": {"chair": {"count": [1, 1], "per": "chair"}}}, "per"),
    ],
)
def test_malformed_recipes_are_one_line_errors(doc, words):
    with pytest.raises(UserError, match=words) as info:
        room_types._parse("den", doc, "room_types.json")
    assert "\n" not in str(info.value)


def test_generate_an_office_end_to_end(tmp_path):
    pytest.importorskip("torch")
    out = tmp_path / "out"
    proc = run_cli("generate", "--room", "office", "--num", "1", "--out", str(out))
    assert proc.returncode == 0, proc.stderr
    scene = json.loads((out / "office_0000" / "scene.json").read_text())
    assert scene["room"]["type"] == "office"
    cats = Counter(o["category"] for o in scene["objects"] if o["support"] == FLOOR)
    assert cats["desk"] >= 1 and "bed" not in cats
    proc = run_cli("validate", str(out / "office_0000" / "scene.json"))
    assert proc.returncode == 0, proc.stderr


@pytest.mark.parametrize("text, room", [("a study with a desk", "study"),
                                        ("a kids room with a bed", "kids_room")])  # fmt: skip
def test_text_naming_a_composed_type_gets_its_recipe(text, room):
    """A description naming a composed type draws that type's rooms: a study's furniture
    beside the named desk (its chair at the desk), a kids' room's around the bed."""
    from pair2scene.hierarchy.build import build_hierarchy

    seen = Counter()
    for seed in range(5):
        h = build_hierarchy(text=text, seed=seed, llm="never")
        assert h.room_type == room
        cats = Counter(n.category for n in h.nodes)
        seen.update(cats.keys())
        assert len(h.nodes) > 4  # the room's furniture and what it holds, not just the noun
    if room == "study":
        assert seen["chair"] == 5 and seen["bed"] == 0
    else:
        assert seen["bed"] == 5 and seen["desk"] >= 1

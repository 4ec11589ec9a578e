"""Counters as cabinet runs and fixture parts as parts (pair2scene.data.fixtures)."""

from __future__ import annotations

import numpy as np
import pytest

from pair2scene.curation.support import extract_support
from pair2scene.curation.tuples import scene_tuples
from pair2scene.data.base import SourceReport
from pair2scene.data.fixtures import build_kitchens_and_bathrooms, counter_runs
from pair2scene.scene.geometry import OrientedBox
from pair2scene.scene.model import FLOOR, AssetRef, Room, Scene, SceneObject


def _obj(oid, cat, center, size, label=None, support=None, yaw=0.0):
    box = OrientedBox.from_yaw(np.array(center, float), np.array(size, float), yaw)
    return SceneObject(oid, cat, box, AssetRef("ai2thor", None), support, None, label, support)


ROOM = Room("kitchen", np.array([[0, 0], [4, 0], [4, 4], [0, 4]], float), 2.5)


def kitchen() -> list[SceneObject]:
    """An AI2-THOR-like kitchen: a 2 cm counter-top slab (its top at 0.92 m) along the
    wall y = 0 over two base cabinets, a microwave on it."""
    return [
        _obj("counter_top_0", "counter_top", (1.0, 0.3, 0.91), (1.6, 0.6, 0.02), "CounterTop"),
        _obj("cabinet_door_0", "cabinet_door", (0.6, 0.25, 0.45), (0.7, 0.5, 0.8), "Cabinet"),
        _obj("cabinet_door_1", "cabinet_door", (1.4, 0.25, 0.45), (0.7, 0.5, 0.8), "Cabinet"),
        _obj("microwave_0", "microwave", (1.0, 0.3, 1.07), (0.5, 0.35, 0.3), "Microwave",
             support="counter_top_0"),
        _obj("chair_0", "chair", (2.5, 2.0, 0.45), (0.45, 0.45, 0.9), "Chair", FLOOR),
    ]  # fmt: skip


def test_counter_slab_becomes_a_run_from_the_floor_with_its_cabinets_folded_in():
    report = SourceReport()
    out = {o.id: o for o in counter_runs(kitchen(), ROOM.floor_polygon.mean(0), report)}
    counter = out["counter_top_0"]
    assert counter.box.bottom == pytest.approx(0.0, abs=1e-9)
    assert counter.box.top == pytest.approx(0.92)
    assert sorted(counter.box.size[:2]) == pytest.approx([0.6, 1.6])
    # its front (+y) faces the room, away from the wall at y = 0
    front = counter.box.rotation @ np.array([0.0, 1.0, 0.0])
    assert front[1] > 0.99
    for cid in ("cabinet_door_0", "cabinet_door_1"):
        assert out[cid].part_of == "counter_top_0"
        assert out[cid].support == "counter_top_0"
    assert out["microwave_0"].support == "counter_top_0"
    assert out["chair_0"].part_of is None and out["chair_0"].support == FLOOR
    # curation: the microwave rests on the counter's top; the cabinets give no tuple
    scene = Scene("k", ROOM, list(out.values()), source="ai2thor")
    tuples = scene_tuples(extract_support(scene))
    deps = {t.dependent.id: t.support.id for t in tuples}
    assert deps["microwave_0"] == "counter_top_0"
    assert deps["counter_top_0"] == FLOOR
    assert "cabinet_door_0" not in deps and "cabinet_door_1" not in deps


def test_l_shaped_slab_is_cut_into_runs_along_its_edges():
    # a 2.5 x 2.5 m slab over cabinets along two walls (x = 0 and y = 0): an L
    objs = [_obj("counter_top_0", "counter_top", (1.25, 1.25, 0.91), (2.5, 2.5, 0.02))]
    k = 0
    for x in (0.35, 1.05, 1.75, 2.2):
        objs.append(_obj(f"drawer_{k}", "drawer", (x, 0.3, 0.45), (0.6, 0.55, 0.8)))
        k += 1
    for y in (1.0, 1.7, 2.2):
        objs.append(_obj(f"drawer_{k}", "drawer", (0.3, y, 0.45), (0.55, 0.6, 0.8)))
        k += 1
    out = counter_runs(objs, np.array([2.0, 2.0]), SourceReport())
    runs = [o for o in out if o.category == "counter_top"]
    assert len(runs) == 2
    area = sum(r.box.size[0] * r.box.size[1] for r in runs)
    assert area < 0.5 * 2.5 * 2.5  # not the whole corner of the kitchen
    assert all(r.box.bottom == pytest.approx(0.0, abs=1e-9) for r in runs)
    assert all(o.part_of in {r.id for r in runs} for o in out if o.category == "drawer")


def test_faucet_on_a_bathtub_is_a_part_not_a_tuple():
    room = Room("bathroom", np.array([[0, 0], [3, 0], [3, 3], [0, 3]], float), 2.5)
    objs = [
        _obj("bathtub_0", "bathtub", (0.4, 1.5, 0.28), (0.75, 1.7, 0.56), "Bathtub", FLOOR),
        _obj("faucet_0", "faucet", (0.1, 1.5, 0.6), (0.1, 0.2, 0.12), "Faucet", "bathtub_0"),
        _obj("shower_0", "shower", (0.05, 1.5, 1.9), (0.1, 0.2, 0.2), "ShowerHead"),
        _obj("soap_bar_0", "soap_bar", (0.3, 2.2, 0.58), (0.08, 0.05, 0.03), "SoapBar",
             "bathtub_0"),
    ]  # fmt: skip
    report = SourceReport()
    out = {o.id: o for o in build_kitchens_and_bathrooms(objs, room.floor_polygon.mean(0), report)}
    assert out["faucet_0"].part_of == "bathtub_0"
    assert out["shower_0"].part_of == "bathtub_0"
    assert report.warnings["Faucet: part of its bathtub"] == 1
    scene = Scene("b", room, list(out.values()), source="ai2thor")
    why = __import__("collections").Counter()
    deps = {t.dependent.id for t in scene_tuples(extract_support(scene), skipped=why)}
    assert "faucet_0" not in deps and "shower_0" not in deps
    assert {"bathtub_0", "soap_bar_0"} <= deps
    assert why["part of another object"] == 2


def test_burners_on_no_counter_make_a_free_standing_range():
    objs = [
        _obj(f"stove_{i}", "stove", (x, y, 0.93), (0.2, 0.2, 0.03), "StoveBurner")
        for i, (x, y) in enumerate([(1.0, 0.2), (1.4, 0.2), (1.0, 0.5), (1.4, 0.5)])
    ]
    objs.append(_obj("stove_knob_0", "stove_knob", (1.2, 0.62, 0.88), (0.05, 0.05, 0.05),
                     "StoveKnob"))  # fmt: skip
    objs.append(_obj("pan_0", "pan", (1.0, 0.2, 0.98), (0.3, 0.3, 0.06), "Pan", "stove_0"))
    report = SourceReport()
    out = build_kitchens_and_bathrooms(objs, np.array([2.0, 2.0]), report)
    ranges = [o for o in out if o.id.startswith("stove_range")]
    assert len(ranges) == 1
    rng = ranges[0]
    assert rng.box.bottom == pytest.approx(0.0, abs=1e-9)
    assert rng.box.top == pytest.approx(0.915)
    by_id = {o.id: o for o in out}
    assert all(by_id[f"stove_{i}"].part_of == rng.id for i in range(4))
    assert by_id["stove_knob_0"].part_of == rng.id
    assert by_id["pan_0"].support == rng.id


def test_procthor_counters_are_whole_bodies_and_untouched():
    tall = _obj("counter_top_0", "counter_top", (1.0, 0.3, 0.47), (1.6, 0.6, 0.94), None, FLOOR)
    out = counter_runs([tall], np.array([2.0, 2.0]), SourceReport())
    assert len(out) == 1 and out[0] is tall


def test_ai2thor_fixture_kitchen_counters_reach_the_floor(fixtures):
    from pair2scene.data.ai2thor import load_ai2thor

    corpus = load_ai2thor(fixtures / "ai2thor")
    kitchen = next(s for s in corpus.scenes if s.id.endswith("FloorPlan1"))
    counters = [o for o in kitchen.objects if o.category == "counter_top"]
    assert counters
    assert all(o.box.bottom == pytest.approx(0.0, abs=1e-6) for o in counters)
    assert all(o.box.top > 0.8 for o in counters)
    loose = [
        o
        for o in kitchen.objects
        if o.source_label in ("Faucet", "StoveKnob") and o.part_of is None
    ]
    assert loose == []

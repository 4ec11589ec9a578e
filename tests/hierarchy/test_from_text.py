"""Text-guided hierarchies: named objects always present, the rest from the statistics."""

from __future__ import annotations

import json
import os

import pytest
from test_synthesis import GOOD

from clitools import run_cli
from llm_server import ChatServer, ok
from pair2scene.hierarchy.build import build_hierarchy
from pair2scene.scene.model import FLOOR

HEADLINE = "a bedroom with two nightstands and a lamp on each nightstand"


def offline(text: str, seed: int = 0, **kw):
    return build_hierarchy(text=text, seed=seed, llm="never", **kw)


@pytest.mark.parametrize("seed", range(10))
def test_headline_lamps_on_different_nightstands(seed):
    h = offline(HEADLINE, seed)
    counts = h.category_counts()
    assert h.room_type == "bedroom"
    assert counts["bed"] >= 1 and counts["side_table"] == 2 and counts["table_lamp"] == 2
    lamps = [n for n in h.nodes if n.category == "table_lamp"]
    holders = {h.support[n.id] for n in lamps}
    assert len(holders) == 2
    assert all(h.by_id()[x].category == "side_table" for x in holders)


def test_headline_through_the_cli_json():
    proc = run_cli("hierarchy", "--text", HEADLINE, "--json", "--llm", "never")
    assert proc.returncode == 0, proc.stderr
    doc = json.loads(proc.stdout)
    cats = {n["id"]: n["category"] for n in doc["nodes"]}
    assert sorted(cats.values()).count("side_table") == 2
    lamp_edges = [e for e in doc["support_tree"]["edges"] if e["child"]["category"] == "table_lamp"]
    assert len(lamp_edges) == 2
    assert {e["parent"]["category"] for e in lamp_edges} == {"side_table"}
    assert len({e["parent"]["id"] for e in lamp_edges}) == 2
    assert "bed" in cats.values()
    order = [s["dependent"]["id"] for s in doc["sequence"]]
    for e in lamp_edges:
        assert order.index(e["parent"]["id"]) < order.index(e["child"]["id"])


@pytest.mark.parametrize("seed", range(5))
def test_nightstands_stand_at_the_rooms_beds(seed):
    """Nightstands the text relates to nothing stand at a bed: the text's ("a double bed,
    two nightstands"), else the room's (the template's), spread over them in turn."""
    for text in (HEADLINE, "a bedroom with a double bed, two nightstands and a wardrobe"):
        h = offline(text, seed)
        beds = [n.id for n in h.nodes if n.category == "bed"]
        stands = [n.id for n in h.nodes if n.category == "side_table"]
        assert beds and len(stands) == 2
        assert all(h.functional.get(s) in beds for s in stands)
        if len(beds) > 1:
            assert len({h.functional[s] for s in stands}) == 2  # one at each bed


def test_a_named_anchor_is_added_before_what_stands_at_it_whatever_the_texts_order():
    """ "two chairs and a dining table": the table is added first, so the chairs find it
    and take it as their anchor; in the text's order the chairs came first and stood at
    no table."""
    for text in ("a living room with two chairs and a dining table",
                 "a living room with a dining table and two chairs"):  # fmt: skip
        seated = 0
        for seed in range(20):
            h = offline(text, seed)
            table = [n.id for n in h.nodes if n.category == "dining_table"][-1]
            chairs = [n.id for n in h.nodes if n.category == "chair"]
            seated += sum(h.functional.get(c) == table for c in chairs[-2:])
        assert seated >= 32, (text, seated)


def test_named_objects_stand_at_the_named_object_they_take_as_anchor():
    """What the text names together and the training rooms relate is related, though the
    text says nothing of it: the chair at the named desk (the statistics' chance alone, 27
    of the 55 chairs beside a desk, stood it elsewhere in 15 of 20 of these rooms, where
    the template's dining table took 5 of them), the side table at the sofa; a chair
    named with both a dining table and a desk sits at the table, the pair the training
    rooms made most often."""
    cases = [
        ("a bedroom with a bed, a desk and a chair", "chair", "desk"),
        ("a living room with a sofa and a side table", "side_table", "sofa"),
        ("a kitchen with a counter and two stools", "stool", "counter_top"),
        ("a room with a desk, a dining table and a chair", "chair", "dining_table"),
    ]
    for text, dependent, anchor in cases:
        for seed in range(10):
            h = offline(text, seed)
            cats = {n.id: n.category for n in h.nodes}
            named = [n.id for n in h.nodes if n.category == dependent][-1]
            assert cats.get(h.functional.get(named)) == anchor, (text, seed)


def test_functional_phrases_and_each():
    h = offline("an office with two desks, each with a chair and a laptop")
    desks = [n.id for n in h.nodes if n.category == "desk"]
    chairs = [n.id for n in h.nodes if n.category == "chair"]
    laptops = [n.id for n in h.nodes if n.category == "laptop"]
    assert len(desks) == len(chairs) == len(laptops) == 2
    assert sorted(h.functional[c] for c in chairs) == sorted(desks)
    assert sorted(h.support[x] for x in laptops) == sorted(desks)
    assert all(h.support[c] == FLOOR for c in chairs)


def test_dining_room_for_eight():
    h = offline("a dining room for eight")
    table = next(n.id for n in h.nodes if n.category == "dining_table")
    chairs = [n.id for n in h.nodes if n.category == "chair"]
    assert len(chairs) == 8 and all(h.functional[c] == table for c in chairs)


def test_large_furniture_faces_the_floor_standing_anchor():
    h = offline("a living room with a tv on a tv stand and a sofa facing the tv")
    sofa = next(n.id for n in h.nodes if n.category == "sofa")
    stand = next(n.id for n in h.nodes if n.category == "tv_stand")
    assert h.support[sofa] == FLOOR and h.functional[sofa] == stand


def test_named_counts_are_not_changed_by_the_statistics():
    for seed in range(5):
        h = offline("a kitchen with three mugs and a bowl", seed)
        assert h.category_counts()["mug"] == 3 and h.category_counts()["bowl"] == 1
        assert h.room_type == "kitchen" and len(h) > 4  # completed from the statistics


def test_beyond_text_and_notes():
    h = offline("a bedroom with a bookcase full of books", mode="beyond", max_objects=70)
    assert 60 <= len(h) <= 70
    h = offline("a bedroom with a spaceship and 1000 books")
    assert any("spaceship" in n for n in h.notes) and any("capped" in n for n in h.notes)
    h = offline("a pen")
    assert h.support[next(n.id for n in h.nodes if n.category == "pen")] != FLOOR


def test_unknown_room_is_built_from_the_named_objects():
    h = offline("a studio apartment with a sofa and a bed")
    assert h.room_type == "apartment" and {"sofa", "bed"} <= set(h.category_counts())


def test_cli_text_errors_and_the_llm_switch(tmp_path):
    proc = run_cli("hierarchy", "--text", "xyzzy blorp", "--llm", "never")
    assert proc.returncode == 2 and proc.stderr.startswith("error: ")
    proc = run_cli("hierarchy", "--text", "a bed", "--llm", "always")
    if "PAIR2SCENE_LLM_BASE_URL" not in os.environ:
        assert proc.returncode == 2 and "needs an endpoint" in proc.stderr
    with ChatServer() as server:
        server.replies.append(ok(GOOD))
        env = {"PAIR2SCENE_LLM_BASE_URL": server.base_url, "PAIR2SCENE_LLM_MODEL": "m",
               "PAIR2SCENE_CACHE": str(tmp_path)}  # fmt: skip
        proc = run_cli_env(env, "hierarchy", "--text", HEADLINE, "--json")
        assert proc.returncode == 0, proc.stderr
        doc = json.loads(proc.stdout)
        assert doc["objects"] == 5 and "LLM" in doc["notes"][-1]
        assert len(server.requests) == 1


def run_cli_env(env: dict, *args: str):
    import subprocess
    import sys

    return subprocess.run(
        [sys.executable, "-m", "pair2scene", *args],
        capture_output=True, text=True, timeout=120, env={**os.environ, **env},
    )  # fmt: skip

"""The hand labels of functional relations (docs/functional_labels.json) are valid:
the format, rooms of the val splits, objects of those rooms, pairs within one
support group, one anchor per dependent and no cycle."""

import json
from collections import Counter
from pathlib import Path

import pytest

from pair2scene.categories import SuperCategory
from pair2scene.data.ai2thor import load_ai2thor
from pair2scene.data.procthor import load_procthor

LABELS = Path(__file__).resolve().parents[2] / "docs" / "functional_labels.json"
MIN_ROOMS = 20
SOURCES = {"ai2thor", "procthor"}


@pytest.fixture(scope="module")
def labels() -> dict:
    return json.loads(LABELS.read_text(encoding="utf-8"))


@pytest.fixture(scope="module")
def val_scenes(ai2thor_databases, procthor_1k) -> dict:
    """scene id -> Scene for the val split of both sources."""
    scenes = load_ai2thor(ai2thor_databases, split="val").scenes
    scenes += load_procthor(procthor_1k / "val.jsonl.gz", split="val").scenes
    return {s.id: s for s in scenes}


def test_format(labels):
    assert labels["format"] == "pair2scene.functional_labels"
    assert labels["version"] == 1
    assert set(labels) == {"format", "version", "rules", "rooms"}
    assert labels["rules"] and all(isinstance(r, str) and r for r in labels["rules"])
    for room in labels["rooms"]:
        assert set(room) == {"room", "source", "pairs", "notes"}, room.get("room")
        assert room["source"] in SOURCES
        assert room["room"].startswith(room["source"] + "/")
        assert isinstance(room["notes"], str)
        for pair in room["pairs"]:
            assert isinstance(pair, list) and len(pair) == 2, (room["room"], pair)
            assert all(isinstance(x, str) for x in pair)


def test_enough_rooms_of_both_sources(labels):
    rooms = [r["room"] for r in labels["rooms"]]
    assert len(rooms) == len(set(rooms)), "a room is labelled twice"
    assert len(rooms) >= MIN_ROOMS
    per_source = Counter(r["source"] for r in labels["rooms"])
    assert all(per_source[s] >= 12 for s in SOURCES), per_source


@pytest.mark.shared_data
def test_pairs_are_functional_pairs_of_their_room(labels, val_scenes):
    for room in labels["rooms"]:
        rid = room["room"]
        assert rid in val_scenes, f"{rid} is not a room of the val split"
        scene = val_scenes[rid]
        objects = scene.by_id()
        anchor_of: dict[str, str] = {}
        for anchor, dependent in room["pairs"]:
            where = f"{rid}: ({anchor}, {dependent})"
            assert anchor in objects and dependent in objects, f"{where}: unknown object id"
            assert anchor != dependent, where
            a, d = objects[anchor], objects[dependent]
            assert a.support is not None and a.support == d.support, (
                f"{where}: supports {a.support!r} and {d.support!r} differ"
            )
            for o in (a, d):
                assert o.part_of is None, f"{where}: {o.id} is a part"
                assert o.super not in (SuperCategory.PART, SuperCategory.STRUCTURE), where
            assert dependent not in anchor_of, f"{rid}: {dependent} has two anchors"
            anchor_of[dependent] = anchor
        for start in anchor_of:
            seen, x = {start}, start
            while x in anchor_of:
                x = anchor_of[x]
                assert x not in seen, f"{rid}: functional cycle through {start}"
                seen.add(x)

"""Issue 21, text: counts a user means ("0 beds", "no beds", "-5 beds") and bounds (a
description is read up to MAX_TEXT_CHARS, its objects stop at MAX_OBJECTS_LIMIT)."""

from __future__ import annotations

import time

import pytest

from pair2scene.errors import UserError
from pair2scene.hierarchy.build import build_hierarchy
from pair2scene.hierarchy.synthesis import MAX_OBJECTS_LIMIT
from pair2scene.hierarchy.text import MAX_TEXT_CHARS, limit_text, parse_text

SEEDS = range(6)


def counts(spec) -> list[tuple[str, int]]:
    return [(m.category, m.count) for m in spec.mentions]


@pytest.mark.parametrize(
    "text", ["a bedroom with 0 beds", "a bedroom with zero beds", "a bedroom with no beds",
             "a bedroom without a bed", "A bedroom. No beds."]
)  # fmt: skip
def test_none_of_a_category_means_none_in_the_hierarchy(text):
    spec = parse_text(text)
    assert spec.room_type == "bedroom" and counts(spec) == [] and spec.excluded == ("bed",)
    for seed in SEEDS:  # a bedroom's template always has a bed: the text's "none" wins
        h = build_hierarchy(text=text, seed=seed, llm="never")
        assert "bed" not in h.category_counts(), (seed, h.category_counts())
        assert len(h) > 0


def test_none_of_a_generic_noun_and_of_a_wall_object():
    spec = parse_text("a bedroom with a bed, no lamps and no curtains")
    assert counts(spec) == [("bed", 1)]
    assert {"table_lamp", "floor_lamp", "wall_lamp", "curtains"} <= set(spec.excluded)
    for seed in SEEDS:
        cats = build_hierarchy(text=spec.text, seed=seed, llm="never").category_counts()
        assert cats["bed"] == 1
        assert not {"table_lamp", "floor_lamp", "wall_lamp", "curtains"} & set(cats), cats


def test_a_category_also_asked_for_is_not_excluded():
    spec = parse_text("a bedroom with no beds and then a bed after all")
    assert counts(spec) == [("bed", 1)] and spec.excluded == ()
    spec = parse_text("a bedroom with 2 beds, 0 pillows")
    assert counts(spec) == [("bed", 2)] and spec.excluded == ("pillow",)


@pytest.mark.parametrize(
    "text", ["-5 beds", "a bedroom with -5 beds", "a bedroom with -2 chairs and a desk",
             "a room with (-1 lamps)", "a bedroom with \u22123 beds"]
)  # fmt: skip
def test_a_negative_count_is_refused_in_one_line(text):
    with pytest.raises(UserError, match="a count must be a positive number") as err:
        parse_text(text)
    assert "\n" not in str(err.value)
    with pytest.raises(UserError, match="a count must be a positive number"):
        build_hierarchy(text=text, llm="never")


def test_dashes_that_are_not_minus_signs_still_read():
    assert counts(parse_text("a room with 3-4 chairs")) == [("chair", 3)]
    assert counts(parse_text("- 2 chairs\n- a bed")) == [("chair", 2), ("bed", 1)]
    assert counts(parse_text("a wall-mounted tv and 5 books")) == [("television", 1), ("book", 5)]


def test_a_long_text_is_cut_with_a_note():
    sentence = "a bedroom with two beds and a lamp on each bed. "
    text = (sentence * (100_000 // len(sentence) + 1))[:100_000]
    spec = parse_text(text)
    assert len(spec.text) <= MAX_TEXT_CHARS and text.startswith(spec.text)
    assert text[len(spec.text)].isspace()  # cut at a word break
    (note,) = spec.notes
    assert f"of its {len(text)} characters" in note and str(MAX_TEXT_CHARS) in note
    start = time.monotonic()
    h = build_hierarchy(text=text, llm="never")
    assert time.monotonic() - start < 10
    assert len(h) <= MAX_OBJECTS_LIMIT
    assert [n for n in h.notes if "was cut at" in n] == [note]
    assert parse_text("a bedroom with a bed").notes == ()
    short, notes = limit_text("  " + "a bed " * 10)
    assert notes == [] and "a bed" in short


def test_the_llm_reads_the_same_cut_text(monkeypatch):
    import pair2scene.hierarchy.llm as llm

    asked: list[str] = []

    class Client:
        def complete_json(self, messages, schema, name):
            asked.append(messages[-1]["content"])
            return {"room_type": "bedroom", "objects": [{"id": "bed_0", "category": "bed"}],
                    "support_tree": [{"parent": "Floor", "child": "bed_0"}],
                    "functional_trees": []}  # fmt: skip

    monkeypatch.setattr(llm, "llm_client_from_env", lambda: Client())
    text = "a bedroom with a bed " + "and a lamp " * 20_000 + "and a SPACESHIP"
    h = build_hierarchy(text=text, llm="always")
    assert len(asked) == 1 and "SPACESHIP" not in asked[0]
    assert len(asked[0]) < MAX_TEXT_CHARS + 10_000  # the text, and the prompt's own words
    assert "was cut at" in h.notes[0]
    with pytest.raises(UserError, match="a count must be a positive number"):
        build_hierarchy(text="a bedroom with -5 beds", llm="always")
    assert len(asked) == 1  # refused before the LLM is asked


@pytest.mark.parametrize(
    "text",
    [
        "a bedroom with 100 beds and 100 pillows on each bed",
        "a living room with 100 shelves with 100 books on each shelf and 100 vases on each shelf",
        "a bedroom with 1000000 paintings on the wall, 1000000 books, 1000000 vases, "
        "1000000 pillows, 1000000 mugs and 1000000 plates",
        "an office with 100 desks, 100 laptops on each desk and 100 chairs at each desk",
    ],
)
def test_the_objects_a_text_asks_for_stop_at_the_limit(text):
    start = time.monotonic()
    for mode in ("fit", "beyond"):
        h = build_hierarchy(text=text, mode=mode, llm="never")
        assert len(h) <= MAX_OBJECTS_LIMIT
        assert any("MAX_OBJECTS_LIMIT" in n for n in h.notes), h.notes
    assert time.monotonic() - start < 20


def test_a_huge_number_reads_as_a_capped_count():
    h = build_hierarchy(text="a bedroom with " + "9" * 1500 + " books", llm="never")
    assert len(h) <= MAX_OBJECTS_LIMIT
    assert any("count capped" in n for n in h.notes)

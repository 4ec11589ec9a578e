"""Floor objects a text stands face to face ("two sofas facing each other",
``Hierarchy.facing``), from the parser through the hierarchy file to placement."""

from __future__ import annotations

import json

import numpy as np
import pytest

from pair2scene.assembly.anchors import AnchorCheck
from pair2scene.assembly.place import FACING_GAP_M, FACING_MIN_GAP_M, facing_at
from pair2scene.hierarchy.build import build_hierarchy
from pair2scene.hierarchy.text import parse_text
from pair2scene.hierarchy.tree import Hierarchy, HierarchyError
from pair2scene.metrics.layout import footprint, footprint_gap
from pair2scene.scene.geometry import OrientedBox
from pair2scene.scene.relations import faces

SOFAS = "a living room with two sofas facing each other and a coffee table between them"


@pytest.mark.parametrize(
    "text, facing, relations",
    [
        (SOFAS, ["sofa"], [("coffee_table", "sofa")]),
        ("a living room with a sofa and an armchair facing each other", ["armchair"],
         [("armchair", "sofa")]),
        ("a bedroom with two beds opposite one another", ["bed"], []),
        # beside each other relates them, but nothing faces
        ("a living room with an armchair and a sofa next to each other", [],
         [("sofa", "armchair")]),
        ("a living room with two chairs next to each other", [], []),
    ],
)  # fmt: skip
def test_the_parser_reads_what_faces_each_other(text, facing, relations):
    spec = parse_text(text)
    cats = {m.ref: m.category for m in spec.mentions}
    assert [cats[r] for r in spec.facing] == facing
    assert [(cats[r.dependent], cats[r.anchor]) for r in spec.relations] == relations
    assert spec.unparsed == ()  # "each other" is understood


def test_facing_round_trips_and_is_checked():
    h = build_hierarchy(text=SOFAS, seed=0, llm="never")
    assert h.facing == {"sofa_1"} and h.functional["sofa_1"] == "sofa_0"
    doc = json.loads(json.dumps(h.to_dict()))
    flags = [e for t in doc["functional_trees"] for e in t["edges"] if e.get("facing")]
    assert [(e["anchor"]["id"], e["dependent"]["id"]) for e in flags] == [("sofa_0", "sofa_1")]
    assert Hierarchy.from_dict(doc).facing == {"sofa_1"}
    h.facing.add("sofa_0")  # no functional anchor
    with pytest.raises(HierarchyError, match="faces its anchor, so it must be a node on the floor"):
        h.validate()


def test_a_check_may_keep_its_object_off_the_anchor():
    anchor = OrientedBox.from_yaw([0, 0, 0.4], [2.0, 0.9, 0.8], 0.0)
    check = AnchorCheck(anchor, 3.0, must_face=True, in_front=True, min_gap=1.0)
    touching = OrientedBox.from_yaw([0, 0.9, 0.4], [2.0, 0.9, 0.8], np.pi)
    apart = OrientedBox.from_yaw([0, 2.4, 0.4], [2.0, 0.9, 0.8], np.pi)
    assert check.reason(touching) == "near_anchor"
    assert check.reason(apart) is None
    assert AnchorCheck(anchor, 3.0, must_face=True).reason(touching) is None  # (min_gap 0)


@pytest.mark.parametrize("yaw", [0.0, 0.7, np.pi / 2])
@pytest.mark.parametrize("drawn", [[0.3, 0.2], [5.0, -3.0], [-0.4, 1.9]])
def test_facing_at_sets_a_box_across_from_its_anchor(yaw, drawn):
    anchor = OrientedBox.from_yaw([1, 1, 0.4], [2.0, 0.9, 0.8], yaw)
    box = OrientedBox.from_yaw([1 + drawn[0], 1 + drawn[1], 0.45], [1.8, 0.8, 0.9], 2.0)
    set_ = facing_at(box, anchor)
    gap = footprint_gap(footprint(set_), footprint(anchor))
    assert FACING_MIN_GAP_M <= gap <= FACING_GAP_M
    assert faces(set_, anchor) and faces(anchor, set_)
    assert np.allclose(set_.size, box.size) and set_.center[2] == box.center[2]


def test_generated_sofas_face_each_other(tmp_path):
    from pair2scene.generate import generate_scenes
    from pair2scene.io.scene_json import read_scene

    generate_scenes(tmp_path, text=SOFAS, num=4, progress=False)
    faced = 0
    for path in sorted(tmp_path.glob("*/scene.json")):
        by_id = {o.id: o for o in read_scene(path).objects}
        if "sofa_1" in by_id:
            a, b = by_id["sofa_0"].box, by_id["sofa_1"].box
            gap = footprint_gap(footprint(a), footprint(b))
            assert faces(a, b) and faces(b, a) and FACING_MIN_GAP_M - 1e-6 <= gap <= FACING_GAP_M
            faced += 1
    assert faced >= 2  # (a second sofa with no room across from the first is dropped)


def test_the_printed_hierarchy_marks_facing(capsys):
    from pair2scene.cli import main

    assert main(["hierarchy", "--text", SOFAS, "--llm", "never"]) == 0
    assert "- sofa_1  [facing sofa_0]" in [
        line.strip() for line in capsys.readouterr().out.splitlines()
    ]


def test_an_llm_reply_may_face_an_object_to_its_anchor():
    import copy

    from test_synthesis import GOOD

    from pair2scene.hierarchy.llm import hierarchy_from_reply

    reply = copy.deepcopy(GOOD)
    reply["functional_trees"][0]["edges"][0]["facing"] = True  # side_table_0 at bed_0
    assert hierarchy_from_reply(reply).facing == {"side_table_0"}

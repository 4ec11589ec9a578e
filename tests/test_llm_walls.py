"""Wall-mounted objects in the LLM hierarchy path, against a real HTTP server on 127.0.0.1."""

from __future__ import annotations

import copy
import json

import pytest

from llm_server import ChatServer, Reply, completion, ok
from pair2scene.hierarchy.llm import (
    hierarchy_from_llm,
    hierarchy_from_reply,
    messages,
    reply_schema,
)
from pair2scene.hierarchy.tree import HierarchyError
from pair2scene.llm import LLMClient, LLMConfig, validate_json
from pair2scene.scene.model import FLOOR, WALL

TEXT = "a living room with a sofa, a painting above the sofa, a TV on the wall and curtains"

WALLS = {
    "room_type": "living_room",
    "objects": [
        {"id": "sofa_0", "category": "sofa"},
        {"id": "coffee_table_0", "category": "coffee_table"},
        {"id": "table_lamp_0", "category": "table_lamp"},
        {"id": "painting_0", "category": "painting"},
        {"id": "television_0", "category": "television"},
        {"id": "curtains_0", "category": "curtains"},
        {"id": "curtains_1", "category": "curtains"},
        {"id": "mirror_0", "category": "mirror"},
    ],
    "support_tree": [
        {"parent": "Floor", "child": "sofa_0"},
        {"parent": "Floor", "child": "coffee_table_0"},
        {"parent": "coffee_table_0", "child": "table_lamp_0"},
        {"parent": "Wall", "child": "painting_0"},
        {"parent": "wall", "child": "television_0"},
        {"parent": "Wall", "child": "curtains_0"},
        {"parent": "Wall", "child": "curtains_1"},
        {"parent": "wall:2", "child": "mirror_0"},
    ],
    "functional_trees": [
        {"support_anchor": "Floor", "edges": [{"anchor": "sofa_0", "dependent": "coffee_table_0"}]},
        {
            "support_anchor": "Wall",
            "edges": [
                {"anchor": "sofa_0", "dependent": "painting_0"},
                {"anchor": "sofa_0", "dependent": "television_0"},
                {"anchor": "Wall", "dependent": "curtains_0"},
                {"anchor": "painting_0", "dependent": "curtains_1"},
            ],
        },
    ],
}


def edited(edit) -> dict:
    reply = copy.deepcopy(WALLS)
    edit(reply)
    return reply


@pytest.fixture
def llm(tmp_path):
    with ChatServer() as server:
        config = LLMConfig(server.base_url, "test-model")
        yield server, LLMClient(config, tmp_path / "llm", sleep=lambda s: None)


def test_a_reply_with_wall_objects_becomes_a_hierarchy(llm):
    server, client = llm
    server.replies.append(ok(WALLS))
    h = hierarchy_from_llm(client, TEXT)
    assert {n.id: h.support[n.id] for n in h.nodes} == {
        "sofa_0": FLOOR, "coffee_table_0": FLOOR, "table_lamp_0": "coffee_table_0",
        "painting_0": WALL, "television_0": WALL, "curtains_0": WALL, "curtains_1": WALL,
        "mirror_0": "wall:2",
    }  # fmt: skip
    assert h.functional == {
        "coffee_table_0": "sofa_0",
        "painting_0": "sofa_0",
        "television_0": "sofa_0",
    }
    # curtains hang at windows: the anchor the reply gave curtains_1 is dropped, with a note
    assert h.notes == [
        "curtains_1: dropped the functional anchor painting_0 (curtains hang at a window)",
        "hierarchy from the LLM",
    ]
    order = [s.dependent.id for s in h.sequence()]
    assert order.index("sofa_0") < order.index("painting_0")
    assert order.index("coffee_table_0") < order.index("mirror_0")
    (request,) = server.requests
    schema = request.body["response_format"]["json_schema"]["schema"]
    parent = schema["properties"]["support_tree"]["items"]["properties"]["parent"]
    assert "'Wall'" in parent["description"] and "'Floor'" in parent["description"]
    anchor = schema["properties"]["functional_trees"]["items"]["properties"]["support_anchor"]
    assert "'Wall'" in anchor["description"]


def test_the_prompt_says_what_hangs_on_walls():
    system, user = (m["content"] for m in messages("a bedroom with a painting above the bed"))
    assert "rest on the Wall" in system
    assert "paintings, mirrors, curtains, blinds, wall lamps and wall-mounted TVs" in user
    assert "parent 'Floor', 'Wall' or an object id" in user
    assert "a painting above the bed" in user and "opposite the sofa" in user
    assert "Curtains and blinds hang at windows, one object per window" in user
    assert "A TV on a TV stand or a table rests on it" in user
    example = json.loads(user.split("Example reply: ", 1)[1])
    validate_json(example, reply_schema())
    h = hierarchy_from_reply(example)
    assert h.support["painting_0"] == WALL and h.functional["painting_0"] == "desk_0"
    assert h.support["curtains_0"] == WALL and "curtains_0" not in h.functional


def test_the_schema_still_takes_the_floor_only_replies():
    reply = edited(lambda r: None)
    validate_json(reply, reply_schema())
    floor_only = {
        "room_type": "bedroom",
        "objects": [{"id": "bed_0", "category": "bed"}],
        "support_tree": [{"parent": "Floor", "child": "bed_0"}],
        "functional_trees": [],
    }
    validate_json(floor_only, reply_schema())
    assert hierarchy_from_reply(floor_only).support == {"bed_0": FLOOR}


def _on_a_table(r: dict) -> None:
    r["functional_trees"][1]["edges"][0]["anchor"] = "table_lamp_0"


def _floor_object_anchored_to_the_wall(r: dict) -> None:
    r["functional_trees"][0]["edges"].append({"anchor": "television_0", "dependent": "sofa_0"})


def _wall_object_in_the_floor_tree(r: dict) -> None:
    r["functional_trees"][0]["edges"].append({"anchor": "sofa_0", "dependent": "painting_0"})


GARBAGE = {
    "malformed wall": (
        lambda r: r["support_tree"][3].update(parent="wall:abc"),
        "'wall:abc' is not a wall: a wall is 'Wall' (or 'wall:<index>')",
    ),
    "wall object anchored to an object on a table": (
        _on_a_table,
        "'painting_0' hangs on a wall, its anchor must stand on the Floor or hang on that "
        "wall, but 'table_lamp_0' rests on 'coffee_table_0'",
    ),
    "floor object anchored to a wall object": (
        _floor_object_anchored_to_the_wall,
        "functional anchor 'television_0' rests on 'wall': a functional anchor must share",
    ),
    "wall object in the Floor's tree": (_wall_object_in_the_floor_tree, "does not rest on it"),
    "the wall resting on something": (
        lambda r: r["support_tree"].append({"parent": "Floor", "child": "Wall"}),
        "the Wall cannot rest on anything",
    ),
    "the wall as a dependent": (
        lambda r: r["functional_trees"][1]["edges"].append(
            {"anchor": "sofa_0", "dependent": "wall"}
        ),
        "the Wall cannot be a functional dependent",
    ),
    "anchored to the wall from the floor": (
        lambda r: r["functional_trees"][0]["edges"].append(
            {"anchor": "Wall", "dependent": "sofa_0"}
        ),
        "functional anchor 'wall' is not a node",
    ),
    "unknown wall object": (
        lambda r: r["support_tree"].append({"parent": "Wall", "child": "ghost_0"}),
        "'ghost_0' is used in a tree but is not among the objects",
    ),
}


@pytest.mark.parametrize("name", sorted(GARBAGE))
def test_garbage_is_a_clear_hierarchy_error(name):
    edit, message = GARBAGE[name]
    reply = edited(edit)
    validate_json(reply, reply_schema())  # the schema lets it through: the tree check does not
    with pytest.raises(HierarchyError) as info:
        hierarchy_from_reply(reply)
    assert message in str(info.value) and "\n" not in str(info.value)


def test_garbage_gets_one_repair_round_then_a_clear_error(llm):
    server, client = llm
    bad = edited(lambda r: r["support_tree"][3].update(parent="wall:abc"))
    server.replies += [ok(bad), ok(WALLS)]
    h = hierarchy_from_llm(client, TEXT)
    assert h.support["painting_0"] == WALL and "repair" in h.notes[-1]
    repair = server.requests[1].body["messages"][-1]["content"]
    assert "'wall:abc'" in repair and repair.startswith("That reply is invalid")

    server.replies += [Reply(body=completion("no json here")), ok(edited(_on_a_table))]
    with pytest.raises(HierarchyError, match="after one repair round: .*'table_lamp_0' rests on"):
        hierarchy_from_llm(client, TEXT + ", and a lamp")


def _flag(reply: dict, key: str, dependent: str = "painting_0") -> None:
    for tree in reply["functional_trees"]:
        for e in tree["edges"]:
            if e["dependent"] == dependent:
                e[key] = True


@pytest.mark.parametrize(
    "key, bad, error",
    [
        ("over", lambda r: _flag(r, "over", "coffee_table_0"), "a node on a wall"),  # floor
        ("across", lambda r: (_flag(r, "across"), _flag(r, "over")), "both over and across"),
    ],
)
def test_an_edge_hangs_over_or_across_from_its_floor_anchor(llm, key, bad, error):
    """ "over": true on a wall object's edge is the offline parser's "above the sofa",
    "across": true its "a TV opposite the sofa"; on an edge that cannot hang so (a floor
    object; both at once) it is refused, with one repair round."""
    reply = edited(lambda r: _flag(r, key))
    validate_json(reply, reply_schema())
    h = hierarchy_from_reply(reply)
    assert getattr(h, key) == {"painting_0"}
    assert (h.over | h.across) == {"painting_0"}
    assert getattr(hierarchy_from_reply(WALLS), key) == set()
    wrong = edited(bad)
    with pytest.raises(HierarchyError, match=error):
        hierarchy_from_reply(wrong)
    server, client = llm
    server.replies += [ok(wrong), ok(reply)]
    h = hierarchy_from_llm(client, TEXT)
    assert getattr(h, key) == {"painting_0"} and "repair" in h.notes[-1]
    not_bool = edited(lambda r: r["functional_trees"][1]["edges"][0].update({key: "yes"}))
    with pytest.raises(Exception, match=key):
        validate_json(not_bool, reply_schema())

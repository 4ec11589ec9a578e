"""Floor objects a text wants clear of every wall: "a kitchen island", "a table in the
middle of the room" (``Hierarchy.mid_room``), from the parser through the hierarchy file to
placement."""

from __future__ import annotations

import json

import pytest

from pair2scene.assembly.place import MID_ROOM_GAP_M, MIN_ISLAND_M, mid_room_fit
from pair2scene.hierarchy.build import build_hierarchy
from pair2scene.hierarchy.text import parse_text
from pair2scene.hierarchy.tree import Hierarchy, HierarchyError
from pair2scene.scene.walls import walls_near, walls_of


def _mid(text: str) -> list[str]:
    spec = parse_text(text)
    cats = {m.ref: m.category for m in spec.mentions}
    return [cats[r] for r in spec.mid_room]


@pytest.mark.parametrize(
    "text, expected",
    [
        ("a kitchen with an island and four bar stools", ["counter_top"]),
        ("a kitchen with two kitchen islands", ["counter_top"]),
        ("a living room with a coffee table in the middle of the room", ["coffee_table"]),
        ("a dining room with a table for six in the centre of the room", ["dining_table"]),
        ("a kitchen with a table in the middle and a fridge", ["dining_table"]),
        ("a bedroom with a bed in the center of the bedroom", ["bed"]),
        # the middle of an object is a relation to it, not to the room
        ("a living room with a vase in the middle of the table", []),
        ("a kitchen with a counter and a fridge", []),
        ("a living room with a mirror in the middle of the wall", []),
    ],
)
def test_the_parser_reads_what_stands_mid_room(text, expected):
    assert _mid(text) == expected


def test_mid_room_round_trips_and_is_checked():
    h = Hierarchy("kitchen")
    island = h.add("counter_top", "floor")
    h.add("counter_top", "floor")
    h.add("stool", "floor", island.id)
    cup = h.add("cup", island.id)
    h.mid_room.add(island.id)
    doc = json.loads(json.dumps(h.validate().to_dict()))
    flags = [e for t in doc["functional_trees"] for e in t["edges"] if e.get("mid_room")]
    assert [e["dependent"]["id"] for e in flags] == [island.id]
    assert Hierarchy.from_dict(doc).mid_room == {island.id}
    flags[0]["mid_room"] = "yes"
    with pytest.raises(HierarchyError, match="malformed hierarchy.*'mid_room'"):
        Hierarchy.from_dict(doc)
    h.mid_room.add(cup.id)
    with pytest.raises(HierarchyError, match="stands mid-room, so it must be a node on the floor"):
        h.validate()


def test_an_island_is_a_counter_besides_the_rooms_own():
    """The island stands mid-room; the counters the statistics give a kitchen stay (a text
    naming "a counter" has only the ones it names)."""
    for seed in range(5):
        h = build_hierarchy(text="a kitchen with an island and four bar stools", seed=seed,
                            llm="never")  # fmt: skip
        counters = [n.id for n in h.nodes if n.category == "counter_top"]
        (island,) = h.mid_room
        assert island in counters and len(counters) >= 2
        stools = [n.id for n in h.nodes if n.category == "stool"]
        assert len(stools) == 4 and all(h.functional[s] == island for s in stools)


def test_an_island_is_drawn_straight_and_long_enough():
    fits = mid_room_fit("counter_top")
    sizes = [[2.0, 0.9, 0.9], [1.0, 0.6, 0.9], [2.4, 1.8, 0.9], [MIN_ISLAND_M, 0.6, 0.9]]
    assert fits(sizes).tolist() == [True, False, False, True]  # long enough, and no L
    assert mid_room_fit("dining_table")([[0.8, 0.8, 0.75]]).tolist() == [True]


def test_generated_islands_and_tables_stand_clear_of_the_walls(tmp_path):
    from pair2scene.generate import generate_scenes
    from pair2scene.io.scene_json import read_scene

    for text in ("a kitchen with an island and four bar stools",
                 "a dining room with a table for six in the middle of the room"):  # fmt: skip
        out = tmp_path / text.split()[1]
        generate_scenes(out, text=text, num=4, progress=False)
        clear = 0
        for seed, path in enumerate(sorted(out.glob("*/scene.json"))):
            h = build_hierarchy(text=text, seed=seed, llm="never")
            scene = read_scene(path)
            walls = walls_of(scene.room.floor_polygon)
            for obj in scene.objects:
                if obj.id in h.mid_room:
                    clear += not walls_near(obj.box, walls, MID_ROOM_GAP_M - 1e-6)
        assert clear >= 3, text  # (a room with no such spot takes the nearest to one)


def test_an_llm_reply_may_stand_an_object_mid_room():
    import copy

    from test_synthesis import GOOD

    from pair2scene.hierarchy.llm import hierarchy_from_reply

    reply = copy.deepcopy(GOOD)
    reply["functional_trees"][0]["edges"].append(
        {"anchor": "Floor", "dependent": "bed_0", "mid_room": True}
    )
    assert hierarchy_from_reply(reply).mid_room == {"bed_0"}
    reply = copy.deepcopy(GOOD)
    reply["functional_trees"].append(
        {"support_anchor": "side_table_0",
         "edges": [{"anchor": "side_table_0", "dependent": "table_lamp_0", "mid_room": True}]}
    )  # fmt: skip
    with pytest.raises(HierarchyError, match="must be a node on the floor"):
        hierarchy_from_reply(reply)


def test_the_printed_hierarchy_marks_mid_room_over_and_across(capsys):
    from pair2scene.cli import main

    text = ("a living room with a sofa, a painting above the sofa, a tv on the wall opposite "
            "the sofa and a coffee table in the middle of the room")  # fmt: skip
    assert main(["hierarchy", "--text", text, "--llm", "never"]) == 0
    lines = [line.strip() for line in capsys.readouterr().out.splitlines()]
    assert "- coffee_table_0  [at sofa_0]  [mid-room]" in lines  # named both: at the sofa
    assert "- painting_0  [over sofa_0]" in lines
    assert "- television_0  [across from sofa_0]" in lines

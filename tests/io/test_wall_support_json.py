"""scene.json and wall-mounted objects: ``support: "wall:<i>"`` is read, checked against
the room's floor polygon and written back; every other ``wall...`` support is one error
line naming the field."""

from __future__ import annotations

import copy
import json

import numpy as np
import pytest

from pair2scene.cli import main
from pair2scene.errors import SceneFileError
from pair2scene.io.scene_json import read_scene, scene_from_dict, scene_to_dict, write_scene
from pair2scene.scene.walls import walls_of

EYE = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]]


def _o(oid: str, category: str, center, size, support, anchor=None) -> dict:
    return {"id": oid, "category": category, "center": center, "size": size,
            "rotation": EYE, "support": support, "functional_anchor": anchor,
            "asset": None}  # fmt: skip


def doc() -> dict:
    """A 4 x 3 m room (4 walls): a bed, a painting above it on wall 0 (y = 0), a towel
    holder on wall 1 (x = 4) with a towel on it."""
    return {
        "format": "pair2scene.scene",
        "version": 1,
        "id": "w0",
        "room": {
            "type": "bedroom",
            "height": 2.7,
            "floor_polygon": [[0.0, 0.0], [4.0, 0.0], [4.0, 3.0], [0.0, 3.0]],
        },
        "objects": [
            _o("bed_0", "bed", [2.0, 1.0, 0.3], [1.6, 2.0, 0.6], "floor"),
            _o("painting_0", "painting", [2.0, 0.02, 1.5], [0.8, 0.04, 0.6], "wall:0", "bed_0"),
            _o("towel_holder_0", "towel_holder", [3.95, 2.0, 1.0], [0.1, 0.5, 0.1], "wall:1"),
            _o("towel_0", "towel", [3.95, 2.0, 1.08], [0.08, 0.4, 0.06], "towel_holder_0"),
        ],
    }


def with_support(i: int, support) -> dict:
    d = copy.deepcopy(doc())
    d["objects"][i]["support"] = support
    return d


def test_wall_supports_read_and_write_back_unchanged(tmp_path):
    scene = scene_from_dict(doc())
    supports = {o.id: o.support for o in scene.objects}
    assert supports["painting_0"] == "wall:0" and supports["towel_holder_0"] == "wall:1"
    assert supports["towel_0"] == "towel_holder_0"  # the cycle walk stops at the wall
    assert scene.get("painting_0").functional_anchor == "bed_0"
    path = write_scene(scene, tmp_path / "scene.json")
    written = json.loads(path.read_text())
    assert [o["support"] for o in written["objects"]] == [
        "floor", "wall:0", "wall:1", "towel_holder_0"]  # fmt: skip
    back = read_scene(path)
    assert [o.support for o in back.objects] == [o.support for o in scene.objects]
    assert scene_to_dict(back)["objects"] == written["objects"]


def test_every_edge_of_the_polygon_is_a_valid_wall():
    for i in range(4):
        assert scene_from_dict(with_support(1, f"wall:{i}")).objects[1].support == f"wall:{i}"


@pytest.mark.parametrize(
    "support, words",
    [
        ("wall", "only valid in hierarchies"),
        ("wall:4", "wall index 4 out of range"),
        ("wall:9", "wall index 9 out of range"),
        ("wall:x", "malformed wall support"),
        ("wall:-1", "malformed wall support"),
        ("wall:01", "malformed wall support"),
        ("wall: 1", "malformed wall support"),
        ("wall:1.0", "malformed wall support"),
        ("wall:", "malformed wall support"),
        ("wall:²", "malformed wall support"),  # a unicode digit int() cannot read
    ],
)
def test_other_wall_supports_are_one_error_line(support, words, tmp_path, capsys):
    with pytest.raises(SceneFileError) as info:
        scene_from_dict(with_support(1, support), "x/scene.json")
    err = info.value
    assert err.field == "objects[1].support" and words in err.problem
    assert "\n" not in str(err) and "wall:<i>" in err.problem
    # through the CLI: exit code 2 and one "error:" line
    path = tmp_path / "scene.json"
    path.write_text(json.dumps(with_support(1, support)), encoding="utf-8")
    assert main(["validate", str(path)]) == 2
    out, errtext = capsys.readouterr()
    lines = errtext.splitlines()
    assert out == "" and len(lines) == 1
    assert lines[0].startswith(f"error: {path}: objects[1].support: ")


def test_an_object_id_that_starts_with_wall_is_still_an_object():
    d = doc()
    d["objects"].append(_o("wall_shelf_0", "shelf", [0.1, 1.5, 1.2], [0.2, 0.8, 0.04], "wall:3"))
    d["objects"].append(_o("vase_0", "vase", [0.1, 1.5, 1.3], [0.1, 0.1, 0.2], "wall_shelf_0"))
    scene = scene_from_dict(d)
    assert scene.get("vase_0").support == "wall_shelf_0"
    # an id that would read as a wall is reserved, like "floor"
    d["objects"][-1]["id"] = "wall:2"
    with pytest.raises(SceneFileError) as info:
        scene_from_dict(d)
    assert info.value.field == "objects[5].id" and "reserved for walls" in info.value.problem


def test_a_cycle_below_a_wall_object_is_still_found():
    d = with_support(2, "towel_0")  # the holder now hangs on the towel that hangs on it
    with pytest.raises(SceneFileError) as info:
        scene_from_dict(d)
    assert info.value.field == "objects[2].support" and "cycle" in info.value.problem


def test_a_wall_of_no_length_is_rejected():
    d = doc()
    d["room"]["floor_polygon"] = [[0.0, 0.0], [4.0, 0.0], [4.0, 0.0], [4.0, 3.0], [0.0, 3.0]]
    d["objects"][1]["support"] = "wall:1"
    d["objects"][2]["support"] = "wall:2"
    with pytest.raises(SceneFileError) as info:
        scene_from_dict(d)
    assert info.value.field == "objects[1].support" and "no length" in info.value.problem
    d["objects"][1]["support"] = "wall:4"  # 5 vertices: edge 4 runs back to the start
    assert scene_from_dict(d).objects[1].support == "wall:4"


def test_a_clockwise_polygon_keeps_each_object_on_its_own_wall(tmp_path):
    d = doc()
    # the same room listed clockwise: edge 0 is now x = 0, edge 3 is y = 0
    d["room"]["floor_polygon"] = [[0.0, 0.0], [0.0, 3.0], [4.0, 3.0], [4.0, 0.0]]
    d["objects"][1]["support"] = "wall:3"  # the painting, at y = 0
    d["objects"][2]["support"] = "wall:1"  # the holder... on y = 3 as listed
    scene = scene_from_dict(d)
    walls = {w.index: w for w in walls_of(scene.room.floor_polygon)}

    def wall_of(oid: str):
        return walls[int(scene.get(oid).support.split(":")[1])]

    painting_wall = wall_of("painting_0")
    np.testing.assert_allclose([painting_wall.p0[1], painting_wall.p1[1]], [0.0, 0.0])
    holder_wall = wall_of("towel_holder_0")
    np.testing.assert_allclose([holder_wall.p0[1], holder_wall.p1[1]], [3.0, 3.0])
    # written back counter-clockwise, the names follow the written polygon
    back = read_scene(write_scene(scene, tmp_path / "scene.json"))
    assert [o.support for o in back.objects] == [o.support for o in scene.objects]

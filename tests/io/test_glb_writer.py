"""scene.glb, our own binary glTF writer: the container read by hand against the glTF 2.0
layout rules, then read back by a spec-following reader (trimesh) to see the scene upright
in glTF's y-up frame with every object's vertices where pair2scene put them; and
``generate`` no longer imports trimesh."""

from __future__ import annotations

import io
import json
import struct
import subprocess
import sys

import numpy as np
import pytest

from pair2scene.assets.mesh import Asset, Mesh, Part
from pair2scene.assets.registry import generate
from pair2scene.io.glb import glb_bytes
from pair2scene.io.scene_meshes import (
    FLOOR_THICKNESS_M,
    object_meshes,
    room_color,
    room_meshes,
    semantic_color,
)
from pair2scene.scene.geometry import OrientedBox
from pair2scene.scene.model import FLOOR, Opening, Room, Scene, SceneObject

ROOM = Room("bedroom", np.array([[0, 0], [4, 0], [4, 3], [0, 3]], float), 2.6,
            (Opening("door", (1.0, 0.0), (1.9, 0.0), 0.0, 2.1, "door_0"),),
            (Opening("window", (1.0, 3.0), (2.5, 3.0), 0.8, 2.0, "window_0"),))  # fmt: skip
COMPONENTS = {5123: ("<u2", 2), 5125: ("<u4", 4), 5126: ("<f4", 4)}
WIDTH = {"SCALAR": 1, "VEC3": 3}
ARRAY_BUFFER, ELEMENT_ARRAY_BUFFER = 34962, 34963


def bedroom() -> tuple[Scene, dict]:
    bed = OrientedBox.from_yaw([2.0, 1.9, 0.3], [1.6, 2.0, 0.6])
    table = OrientedBox.from_yaw([0.5, 2.5, 0.3], [0.5, 0.5, 0.6], np.pi / 2)
    lamp = OrientedBox.from_yaw([0.5, 2.5, 0.8], [0.2, 0.2, 0.4])
    objects = [
        SceneObject("bed_0", "bed", bed, None, FLOOR),
        SceneObject("side_table_0", "side_table", table, None, FLOOR, "bed_0"),
        SceneObject("table_lamp_0", "table_lamp", lamp, None, "side_table_0"),
    ]
    assets = {o.id: generate(o.category, o.box.size, 0) for o in objects}
    return Scene("s0", ROOM, objects), assets


def read_glb(data: bytes) -> tuple[dict, bytes]:
    """The JSON document and the BIN chunk of a GLB, checking its container by hand."""
    magic, version, length = struct.unpack_from("<4sII", data, 0)
    assert (magic, version, length) == (b"glTF", 2, len(data))
    json_length, json_type = struct.unpack_from("<I4s", data, 12)
    assert json_type == b"JSON" and json_length % 4 == 0
    text = data[20 : 20 + json_length]
    assert text.rstrip(b" ").endswith(b"}")  # padded with spaces only
    at = 20 + json_length
    bin_length, bin_type = struct.unpack_from("<I4s", data, at)
    assert bin_type == b"BIN\0" and bin_length % 4 == 0 and at + 8 + bin_length == len(data)
    doc = json.loads(text)
    (buffer,) = doc["buffers"]
    assert "uri" not in buffer and buffer["byteLength"] <= bin_length < buffer["byteLength"] + 4
    return doc, data[at + 8 :]


def accessor(doc: dict, blob: bytes, index: int) -> np.ndarray:
    """The (count, width) data of accessor ``index``, checking it fits its buffer view."""
    a = doc["accessors"][index]
    view = doc["bufferViews"][a["bufferView"]]
    dtype, size = COMPONENTS[a["componentType"]]
    offset = a.get("byteOffset", 0)
    assert view["byteOffset"] % 4 == 0 and offset % size == 0
    assert view["byteOffset"] + view["byteLength"] <= doc["buffers"][0]["byteLength"]
    assert a["count"] >= 1
    assert a["count"] * WIDTH[a["type"]] * size <= view["byteLength"] - offset
    data = np.frombuffer(blob, dtype, a["count"] * WIDTH[a["type"]], view["byteOffset"] + offset)
    return data.reshape(a["count"], WIDTH[a["type"]])


def primitive_data(doc: dict, blob: bytes, node: dict) -> tuple[np.ndarray, np.ndarray]:
    """(positions (V, 3), faces (F, 3)) of a node's one triangle primitive."""
    (prim,) = doc["meshes"][node["mesh"]]["primitives"]
    assert prim.get("mode", 4) == 4  # triangles
    pos_index, idx_index = prim["attributes"]["POSITION"], prim["indices"]
    positions, indices = accessor(doc, blob, pos_index), accessor(doc, blob, idx_index)
    for i, target in ((pos_index, ARRAY_BUFFER), (idx_index, ELEMENT_ARRAY_BUFFER)):
        assert doc["bufferViews"][doc["accessors"][i]["bufferView"]]["target"] == target
    pos = doc["accessors"][pos_index]
    assert pos["componentType"] == 5126 and pos["type"] == "VEC3"
    assert pos["min"] == positions.min(0).tolist() and pos["max"] == positions.max(0).tolist()
    component = doc["accessors"][idx_index]["componentType"]
    assert component == (5123 if len(positions) <= 0xFFFF else 5125)
    assert len(indices) % 3 == 0 and indices.max() < len(positions)
    return positions, indices.reshape(-1, 3)


def srgb_to_linear(c: int) -> float:
    x = c / 255
    return x / 12.92 if x <= 0.04045 else ((x + 0.055) / 1.055) ** 2.4


def test_the_container_accessors_and_data_follow_the_glb_layout():
    scene, assets = bedroom()
    doc, blob = read_glb(glb_bytes(scene, assets))
    assert doc["asset"] == {"version": "2.0", "generator": "pair2scene"}
    expected = [*room_meshes(scene.room), *((o, m) for o, _, m in object_meshes(scene, assets))]
    children = [doc["nodes"][i] for i in doc["nodes"][0]["children"]]
    assert [n["name"] for n in children] == [name for name, _ in expected]
    for node, (name, mesh) in zip(children, expected):
        positions, faces = primitive_data(doc, blob, node)
        assert np.array_equal(positions, mesh.vertices.astype(np.float32)), name
        assert np.array_equal(faces, mesh.faces), name


def test_one_root_node_turns_z_up_into_y_up():
    scene, assets = bedroom()
    doc, _ = read_glb(glb_bytes(scene, assets))
    root = doc["nodes"][0]
    assert doc["scenes"][doc["scene"]]["nodes"] == [0] and root["name"] == "pair2scene"
    np.testing.assert_allclose(root["rotation"], [-np.sqrt(0.5), 0, 0, np.sqrt(0.5)])
    assert not {"matrix", "translation", "scale", "mesh"} & set(root)
    assert sorted(root["children"]) == list(range(1, len(doc["nodes"])))
    for node in doc["nodes"][1:]:  # the vertices are world coordinates under the root
        assert set(node) == {"name", "mesh"}, node


def test_colours_are_the_semantic_ones_in_linear_light_one_material_each():
    scene, assets = bedroom()
    doc, _ = read_glb(glb_bytes(scene, assets))
    category = {o.id: o.category for o in scene.objects}
    colours = set()
    for node in doc["nodes"][1:]:
        name = node["name"]
        rgb = semantic_color(category[name]) if name in category else room_color(name)
        colours.add(rgb)
        (prim,) = doc["meshes"][node["mesh"]]["primitives"]
        pbr = doc["materials"][prim["material"]]["pbrMetallicRoughness"]
        linear = [srgb_to_linear(c) for c in rgb]
        np.testing.assert_allclose(pbr["baseColorFactor"], [*linear, 1.0], atol=1e-6)
        assert pbr["metallicFactor"] == 0 and pbr["roughnessFactor"] == pytest.approx(0.9)
    assert len(doc["materials"]) == len(colours) >= 6  # floor, wall, pane, three objects
    assert srgb_to_linear(128) == pytest.approx(0.2158605)  # the sRGB curve, not c / 255


def test_the_same_scene_gives_the_same_bytes():
    data = glb_bytes(*bedroom())
    assert glb_bytes(*bedroom()) == data


@pytest.mark.parametrize("n", [0xFFFF, 0x10000])
def test_large_meshes_get_32_bit_indices(n):
    t = np.arange(n) / n
    vertices = np.stack([np.cos(40 * t), np.sin(40 * t), t], 1) * [0.2, 0.2, 0.5]
    faces = np.stack([np.arange(n - 2), np.arange(1, n - 1), np.arange(2, n)], 1)
    asset = Asset("vase", np.array([0.4, 0.4, 0.5]), (Part("body", Mesh(vertices, faces)),))
    box = OrientedBox.from_yaw([1.0, 1.0, 0.25], [0.4, 0.4, 0.5])
    scene = Scene("big", ROOM, [SceneObject("vase_0", "vase", box, None, FLOOR)])
    doc, blob = read_glb(glb_bytes(scene, {"vase_0": asset}))
    (node,) = [nd for nd in doc["nodes"] if nd["name"] == "vase_0"]
    positions, read = primitive_data(doc, blob, node)  # checks the index type for n
    assert len(positions) == n and np.array_equal(read, faces)


def test_a_glb_reader_sees_the_scene_upright_in_y_up():
    """trimesh applies the node transforms as the glTF spec says: the floor is then a
    horizontal slab just under y = 0, the walls rise along +y to the room's height, every
    object stands at y >= 0, and an object's vertices are ours turned (x, y, z) ->
    (x, z, -y); without the root rotation the floor would stand on its edge."""
    trimesh = pytest.importorskip("trimesh")
    scene, assets = bedroom()
    loaded = trimesh.load(io.BytesIO(glb_bytes(scene, assets)), file_type="glb", process=False)
    assert {o.id for o in scene.objects} | {"floor"} <= set(loaded.graph.nodes_geometry)

    def world(name: str) -> np.ndarray:
        transform, geometry = loaded.graph[name]
        return trimesh.transform_points(loaded.geometry[geometry].vertices, transform)

    floor = world("floor")
    np.testing.assert_allclose([floor[:, 1].min(), floor[:, 1].max()],
                               [-FLOOR_THICKNESS_M, 0.0], atol=1e-6)  # fmt: skip
    assert np.ptp(floor[:, 0]) > 4 and np.ptp(floor[:, 2]) > 3  # spread over x and z
    walls = [n for n in loaded.graph.nodes_geometry if n.startswith("wall_")]
    assert walls
    for name in walls:
        y = world(name)[:, 1]
        np.testing.assert_allclose([y.min(), y.max()], [0.0, ROOM.height], atol=1e-6)
    np.testing.assert_allclose(loaded.bounds[:, 1], [-FLOOR_THICKNESS_M, ROOM.height], atol=1e-6)
    ours = {oid: mesh for oid, _, mesh in object_meshes(scene, assets)}
    for oid, mesh in ours.items():
        v = world(oid)
        assert v[:, 1].min() >= -1e-6, oid
        x, y, z = mesh.vertices.T
        np.testing.assert_allclose(v, np.stack([x, z, -y], 1), atol=1e-6, err_msg=oid)
    assert world("bed_0")[:, 1].min() == pytest.approx(0.0, abs=1e-6)
    assert world("table_lamp_0")[:, 1].min() == pytest.approx(0.6, abs=1e-6)  # on the table
    lamp_geometry = loaded.geometry[loaded.graph["table_lamp_0"][1]]
    np.testing.assert_allclose(lamp_geometry.vertices, ours["table_lamp_0"].vertices, atol=1e-6)
    assert np.array_equal(lamp_geometry.faces, ours["table_lamp_0"].faces)


def test_generate_does_not_import_trimesh(tmp_path):
    pytest.importorskip("torch")
    code = (
        "import sys\n"
        "from pair2scene.cli import main\n"
        f"rc = main(['generate', '--room', 'bedroom', '--out', {str(tmp_path / 'out')!r}])\n"
        "print(rc, sorted(m for m in sys.modules if m.split('.')[0] == 'trimesh'))\n"
    )
    proc = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                          timeout=300)  # fmt: skip
    assert proc.returncode == 0, proc.stderr
    assert proc.stdout.split("\n")[-2] == "0 []", proc.stdout
    assert (tmp_path / "out" / "bedroom_0000" / "scene.glb").read_bytes()[:4] == b"glTF"

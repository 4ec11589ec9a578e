"""``scene.glb``: the placed scene as binary glTF 2.0, written here with numpy, struct and
json (no trimesh: importing it would cost every ``generate`` run about half a second).

Frame: glTF is y up (+y up, +z front, metres), pair2scene is z up. The one root node
``pair2scene`` (the scene's only root) carries the rotation of -90 degrees about x that maps
our (x, y, z) to glTF's (x, z, -y), so viewers show the scene upright (our +y, the front
of an unturned object, becomes glTF's -z); under it the vertices stay in pair2scene's
world coordinates (z up, metres). Its children: one node per :func:`room_meshes` piece
named as there (``floor``, ``wall_<i>_<j>``, ``door_<i>_<j>``, ``window_<i>_<j>[_pane]``),
then one per object named by its id, each with a mesh of one triangle primitive (POSITION
and indices, no normals: viewers shade flat faces themselves).

Colours are today's semantic ones (:func:`room_color`, :func:`semantic_color`, sRGB 0-255),
one material per distinct colour; glTF's ``baseColorFactor`` is linear, so they are
converted from sRGB and a viewer shows the sRGB colour. The same scene gives the same bytes.
"""

from __future__ import annotations

import json
import math
import struct

import numpy as np

from pair2scene.assets.mesh import Asset, Mesh
from pair2scene.io.scene_meshes import SceneMeshes, room_color, semantic_color
from pair2scene.scene.model import Scene

ROOT_NODE = "pair2scene"
Z_UP_TO_Y_UP = [-math.sqrt(0.5), 0.0, 0.0, math.sqrt(0.5)]
"""Quaternion (x, y, z, w) of the root node: -90 degrees about x, (x, y, z) -> (x, z, -y)."""
ROUGHNESS = 0.9
_GLB_MAGIC, _GLB_VERSION = 0x46546C67, 2  # b"glTF"
_CHUNK_JSON, _CHUNK_BIN = 0x4E4F534A, 0x004E4942  # b"JSON", b"BIN\0"
_FLOAT, _USHORT, _UINT = 5126, 5123, 5125
_ARRAY_BUFFER, _ELEMENT_ARRAY_BUFFER = 34962, 34963
_TRIANGLES = 4


def glb_bytes(scene: Scene, assets: dict[str, Asset], meshes: SceneMeshes | None = None) -> bytes:
    """The scene as a binary glTF: node name = object id; floor and walls included.
    ``meshes``: the scene's meshes when the caller has them already."""
    meshes = meshes or SceneMeshes.of(scene, assets)
    pieces = [(name, mesh, room_color(name)) for name, mesh in meshes.room]
    pieces += [(oid, mesh, semantic_color(cat)) for oid, cat, mesh in meshes.objects]
    doc = _Gltf()
    nodes = [doc.node(name, mesh, rgb) for name, mesh, rgb in pieces]
    root = {"name": ROOT_NODE, "rotation": Z_UP_TO_Y_UP, "children": list(range(1, len(nodes) + 1))}
    gltf = {
        "asset": {"version": "2.0", "generator": "pair2scene"},
        "scene": 0,
        "scenes": [{"name": scene.id, "nodes": [0]}],
        "nodes": [root, *nodes],
        "meshes": doc.meshes,
        "materials": doc.materials,
        "accessors": doc.accessors,
        "bufferViews": doc.views,
        "buffers": [{"byteLength": doc.size}],
    }
    return _glb(json.dumps(gltf, separators=(",", ":")).encode(), b"".join(doc.chunks))


class _Gltf:
    """The meshes, materials, accessors and buffer views of a glTF document as they are
    added, and the binary buffer they point into (each view 4-byte aligned)."""

    def __init__(self) -> None:
        self.meshes: list[dict] = []
        self.materials: list[dict] = []
        self.accessors: list[dict] = []
        self.views: list[dict] = []
        self.chunks: list[bytes] = []
        self.size = 0
        self._material_of: dict[tuple[int, int, int], int] = {}

    def node(self, name: str, mesh: Mesh, rgb: tuple[int, int, int]) -> dict:
        """A node named ``name`` showing ``mesh`` in ``rgb`` (an empty mesh: no mesh)."""
        if len(mesh.faces) == 0:
            return {"name": name}
        positions = mesh.vertices.astype("<f4")
        # 16-bit indices while they stay below 65535 (reserved for primitive restart)
        index_type = _USHORT if len(positions) <= 0xFFFF else _UINT
        indices = mesh.faces.reshape(-1).astype("<u2" if index_type == _USHORT else "<u4")
        position = self._accessor(positions, _FLOAT, "VEC3", _ARRAY_BUFFER)
        self.accessors[position]["min"] = positions.min(0).tolist()
        self.accessors[position]["max"] = positions.max(0).tolist()
        primitive = {
            "attributes": {"POSITION": position},
            "indices": self._accessor(indices, index_type, "SCALAR", _ELEMENT_ARRAY_BUFFER),
            "material": self._material(rgb),
            "mode": _TRIANGLES,
        }
        self.meshes.append({"name": name, "primitives": [primitive]})
        return {"name": name, "mesh": len(self.meshes) - 1}

    def _accessor(self, data: np.ndarray, component: int, kind: str, target: int) -> int:
        """Index of a new accessor over ``data`` in a buffer view of its own."""
        raw = data.tobytes()
        self.views.append(
            {"buffer": 0, "byteOffset": self.size, "byteLength": len(raw), "target": target}
        )
        self.chunks += [raw, bytes(-len(raw) % 4)]
        self.size += len(raw) + (-len(raw) % 4)
        self.accessors.append(
            {"bufferView": len(self.views) - 1, "componentType": component,
             "count": len(data), "type": kind}
        )  # fmt: skip
        return len(self.accessors) - 1

    def _material(self, rgb: tuple[int, int, int]) -> int:
        """Index of the material of sRGB colour ``rgb`` (0-255), added on first use."""
        if rgb not in self._material_of:
            linear = [round(_srgb_to_linear(c / 255), 6) for c in rgb]
            self._material_of[rgb] = len(self.materials)
            self.materials.append(
                {
                    "name": "rgb_{:02x}{:02x}{:02x}".format(*rgb),
                    "pbrMetallicRoughness": {
                        "baseColorFactor": [*linear, 1.0],
                        "metallicFactor": 0.0,
                        "roughnessFactor": ROUGHNESS,
                    },
                }
            )
        return self._material_of[rgb]


def _srgb_to_linear(c: float) -> float:
    """An sRGB-encoded channel in [0, 1] as linear light (the sRGB transfer function)."""
    return c / 12.92 if c <= 0.04045 else ((c + 0.055) / 1.055) ** 2.4


def _glb(json_chunk: bytes, bin_chunk: bytes) -> bytes:
    """The GLB container: 12-byte header, JSON chunk padded with spaces, BIN chunk padded
    with zeros (both to 4 bytes)."""
    json_chunk += b" " * (-len(json_chunk) % 4)
    bin_chunk += bytes(-len(bin_chunk) % 4)
    total = 12 + 8 + len(json_chunk) + 8 + len(bin_chunk)
    return b"".join(
        [
            struct.pack("<III", _GLB_MAGIC, _GLB_VERSION, total),
            struct.pack("<II", len(json_chunk), _CHUNK_JSON),
            json_chunk,
            struct.pack("<II", len(bin_chunk), _CHUNK_BIN),
            bin_chunk,
        ]
    )

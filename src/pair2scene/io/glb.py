"""``scene.glb``: the placed scene as binary glTF, one node per object named by its id
(its asset's mesh in world coordinates, z up as everywhere in pair2scene), plus ``floor``
, ``wall_<i>_<j>`` and ``window_<i>_<j>[_pane]`` nodes (:func:`room_meshes`)."""

from __future__ import annotations

import numpy as np

from pair2scene.assets.mesh import Asset, Mesh
from pair2scene.io.scene_meshes import (
    object_meshes,
    room_color,
    room_meshes,
    semantic_color,
)
from pair2scene.scene.model import Scene


def glb_bytes(scene: Scene, assets: dict[str, Asset]) -> bytes:
    """The scene as a binary glTF: node name = object id; floor and walls included."""
    import trimesh

    tscene = trimesh.Scene()
    for name, mesh in room_meshes(scene.room):
        rgb = room_color(name)
        tscene.add_geometry(_trimesh(mesh, rgb), node_name=name, geom_name=name)
    for oid, category, mesh in object_meshes(scene, assets):
        tscene.add_geometry(_trimesh(mesh, semantic_color(category)), node_name=oid, geom_name=oid)
    return tscene.export(file_type="glb")


def _trimesh(mesh: Mesh, rgb):
    import trimesh

    m = trimesh.Trimesh(mesh.vertices, mesh.faces, process=False)
    m.visual.face_colors = np.tile([*rgb, 255], (len(mesh.faces), 1)).astype(np.uint8)
    return m

"""Scene folders: scene.json (the contract), scene.glb (node per object id), bev.png."""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest
from PIL import Image

from pair2scene.assets.registry import generate
from pair2scene.io.export import DEFAULT_FORMATS, FORMATS, write_scene_folder
from pair2scene.io.scene_json import read_scene
from pair2scene.io.scene_meshes import room_color, room_meshes, semantic_color
from pair2scene.scene.geometry import OrientedBox
from pair2scene.scene.model import FLOOR, Opening, Room, Scene, SceneObject


def small_scene():
    room = Room("bedroom", np.array([[0, 0], [4, 0], [4, 3], [0, 3]], float), 2.6,
                (Opening("door", (1.0, 0.0), (1.9, 0.0), 0.0, 2.1, "door_0"),))  # fmt: skip
    bed = OrientedBox.from_yaw([2.0, 1.9, 0.3], [1.6, 2.0, 0.6])
    lamp = OrientedBox.from_yaw([0.5, 2.5, 0.8], [0.2, 0.2, 0.4])
    table = OrientedBox.from_yaw([0.5, 2.5, 0.3], [0.5, 0.5, 0.6])
    objects = [
        SceneObject("bed_0", "bed", bed, None, FLOOR),
        SceneObject("side_table_0", "side_table", table, None, FLOOR, "bed_0"),
        SceneObject("table_lamp_0", "table_lamp", lamp, None, "side_table_0"),
    ]
    assets = {o.id: generate(o.category, o.box.size, 0) for o in objects}
    return Scene("s0", room, objects, source="pair2scene", stats={"objects_placed": 3}), assets


def test_folder_has_all_three_and_scene_json_reads_back(tmp_path):
    scene, assets = small_scene()
    folder = write_scene_folder(tmp_path / "s0", scene, assets)
    assert sorted(p.name for p in folder.iterdir()) == [
        "bev.png",
        "scene.glb",
        "scene.html",
        "scene.json",
    ]
    back = read_scene(folder / "scene.json")
    assert [o.id for o in back.objects] == ["bed_0", "side_table_0", "table_lamp_0"]
    assert (
        back.objects[2].support == "side_table_0" and back.objects[1].functional_anchor == "bed_0"
    )
    img = Image.open(folder / "bev.png")
    assert img.size[0] > img.size[1] >= 512
    # overwriting replaces the folder as a whole and leaves no temporary folders behind
    write_scene_folder(tmp_path / "s0", scene, assets)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["s0"]


def test_folder_files_are_those_each_format_makes_on_its_own(tmp_path):
    """The folder draws its GLB, viewer page and top view from one set of scene meshes
    (the page embeds the GLB made once; the top view is drawn while the rest is
    written): each file holds what its format's function gives on its own."""
    from pair2scene.io.bev import bev_png
    from pair2scene.io.glb import glb_bytes
    from pair2scene.io.viewer import scene_html

    scene, assets = small_scene()
    folder = write_scene_folder(tmp_path / "s0", scene, assets)
    assert (folder / "scene.glb").read_bytes() == glb_bytes(scene, assets)
    assert (folder / "bev.png").read_bytes() == bev_png(scene, assets)
    page = scene_html(scene, assets, back_link="../index.html")
    assert (folder / "scene.html").read_bytes() == page


def test_glb_nodes_are_object_ids_with_floor_and_walls(tmp_path):
    trimesh = pytest.importorskip("trimesh")
    scene, assets = small_scene()
    folder = write_scene_folder(tmp_path / "s0", scene, assets)
    loaded = trimesh.load(folder / "scene.glb")
    nodes = set(loaded.graph.nodes_geometry)
    assert {"bed_0", "side_table_0", "table_lamp_0", "floor"} <= nodes
    assert any(n.startswith("wall_") for n in nodes)
    lamp = loaded.geometry[loaded.graph["table_lamp_0"][1]]
    np.testing.assert_allclose(lamp.bounds.mean(0)[:2], [0.5, 2.5], atol=0.02)


def test_walls_leave_the_door_open_and_colours_are_stable():
    scene, _ = small_scene()
    walls = dict(room_meshes(scene.room))
    bottom = [m for n, m in walls.items() if n.startswith("wall_0_")]
    assert len(bottom) == 2  # left of the door, right of the door
    (lintel,) = [m for n, m in walls.items() if n.startswith("door_0_")]
    assert lintel.bounds[0, 2] == pytest.approx(2.1)
    # seen from above the door is a gap in the wall: its lintel takes the floor's colour
    assert room_color("door_0_1", top_view=True) == room_color("floor") != room_color("door_0_1")
    assert semantic_color("bed") == semantic_color("bed") != semantic_color("mug")


def test_a_summary_in_another_shape_is_one_line(tmp_path):
    import json

    from pair2scene.errors import UserError
    from pair2scene.io.summary import SUMMARY_FORMAT, read_summary

    doc = {"format": SUMMARY_FORMAT, "version": 1, "request": {}, "scenes": "oops"}
    (tmp_path / "summary.json").write_text(json.dumps(doc))
    with pytest.raises(UserError, match="scenes: must be a list"):
        read_summary(tmp_path)


def test_every_scene_file_has_one_exporter():
    assert [FORMATS[f].entry for f in DEFAULT_FORMATS] == [
        "scene.json",
        "scene.glb",
        "bev.png",
        "scene.html",
    ]


def test_windows_are_cut_into_their_wall_with_a_pane_and_marked_in_the_top_view():
    from pair2scene.io.scene_meshes import WALL_RGB, WINDOW_RGB, room_color
    from pair2scene.scene.model import Opening

    scene, _ = small_scene()
    window = Opening("window", (1.0, 3.0), (2.5, 3.0), 0.8, 2.0, "window_0")
    room = replace(scene.room, windows=(window,))
    pieces = dict(room_meshes(room))
    at = {n: m for n, m in pieces.items() if n.startswith("window_")}
    assert len(at) == 3  # the wall under the sill, the lintel, the pane
    (pane,) = [m for n, m in at.items() if n.endswith("_pane")]
    np.testing.assert_allclose(pane.bounds[:, 2], [0.8, 2.0])
    np.testing.assert_allclose(sorted(pane.bounds[:, 0]), [1.0, 2.5])
    sill, lintel = sorted((m for n, m in at.items() if not n.endswith("_pane")),
                          key=lambda m: m.bounds[0, 2])  # fmt: skip
    assert sill.bounds[1, 2] == pytest.approx(0.8) and lintel.bounds[0, 2] == pytest.approx(2.0)
    assert room_color("window_2_1_pane") == WINDOW_RGB == room_color("window_2_1", top_view=True)
    assert room_color("window_2_1") == WALL_RGB == room_color("wall_0_0", top_view=True)


def test_an_l_shaped_room_gets_an_l_shaped_floor_slab_facing_out():
    from pair2scene.io.scene_meshes import FLOOR_THICKNESS_M, WALL_THICKNESS_M, floor_slab

    ell = np.array([[0, 0], [4, 0], [4, 2], [2, 2], [2, 4], [0, 4]], float)
    slab = floor_slab(ell, WALL_THICKNESS_M)
    up = slab.face_normals[:, 2] > 0.9
    t = WALL_THICKNESS_M
    # the L (12 m2) grown by the walls' thickness: its 16 m of edges, 5 convex corners
    # adding a square each, 1 concave corner taking one away; not the 4.2 x 4.2 bounds
    assert slab.face_areas[up].sum() == pytest.approx(12 + t * 16 + t * t * 4)
    assert np.allclose(slab.bounds, [[-t, -t, -FLOOR_THICKNESS_M], [4 + t, 4 + t, 0]])
    sides = np.abs(slab.face_normals[:, 2]) < 0.1
    centre = slab.triangles[sides].mean(1)[:, :2]
    inward = np.array([[1.0, 1.0]]) - centre  # a point inside the L
    assert ((slab.face_normals[sides][:, :2] * inward).sum(1) < 0).all()  # walls face out

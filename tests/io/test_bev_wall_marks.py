"""Wall-mounted objects in the exports: marks along their wall in the top view (in their
category's colour, over any furniture), and meshes at their boxes in front of the walls in
the GLB and in rendered views."""

from __future__ import annotations

import io

import numpy as np
import pytest

from pair2scene.assets.registry import generate
from pair2scene.io.bev import WALL_MARK_PX, bev_camera, bev_image, wall_marks
from pair2scene.io.glb import glb_bytes
from pair2scene.io.scene_meshes import object_meshes, room_meshes, semantic_color
from pair2scene.render import render_meshes
from pair2scene.scene.geometry import OrientedBox
from pair2scene.scene.model import FLOOR, Opening, Room, Scene, SceneObject, wall_support
from pair2scene.scene.walls import walls_of

# 4 x 3 m: wall 0 is y = 0, wall 1 x = 4, wall 2 y = 3, wall 3 x = 0
ROOM = Room("bedroom", np.array([[0, 0], [4, 0], [4, 3], [0, 3]], float), 2.6,
            (Opening("door", (0.3, 0.0), (1.2, 0.0), 0.0, 2.1, "door_0"),),
            (Opening("window", (1.0, 3.0), (2.5, 3.0), 0.8, 2.0, "window_0"),))  # fmt: skip
PAINTING = OrientedBox.from_yaw([2.5, 0.02, 1.25], [0.8, 0.04, 0.5])  # x 2.1-2.9 on wall 0
CURTAINS = OrientedBox.from_yaw([1.75, 2.92, 1.4], [1.9, 0.16, 2.2], np.pi)  # facing -y


def wall_scene(*extra: SceneObject) -> tuple[Scene, dict]:
    objects = [
        # the bed's headboard against wall 0, under the painting
        SceneObject("bed_0", "bed", OrientedBox.from_yaw([2.5, 1.0, 0.5], [1.6, 2.0, 1.0]),
                    None, FLOOR),  # fmt: skip
        # a wardrobe against wall 0, taller than the painting is high
        SceneObject("wardrobe_0", "wardrobe",
                    OrientedBox.from_yaw([3.65, 0.3, 1.0], [0.6, 0.6, 2.0]), None, FLOOR),
        SceneObject("painting_0", "painting", PAINTING, None, wall_support(0), "bed_0"),
        SceneObject("curtains_0", "curtains", CURTAINS, None, wall_support(2)),
        *extra,
    ]  # fmt: skip
    assets = {o.id: generate(o.category, o.box.size, 0) for o in objects}
    return Scene("w", ROOM, objects), assets


def mark_pixels(scene: Scene, wall: int, lo: float, hi: float, size: int) -> np.ndarray:
    """Pixel (col, row) of points just inside ``wall`` between ``lo`` and ``hi`` metres
    from its start (p0), half the mark's thickness in."""
    camera = bev_camera(scene.room, size)
    w = walls_of(scene.room.floor_polygon)[wall]
    t = np.linspace(lo, hi, 25)
    depth = WALL_MARK_PX / 2 * camera.pixel_m
    xy = w.p0 + np.outer(t, w.direction) + w.normal * depth
    px = camera.project(np.c_[xy, np.zeros(len(xy))])
    return np.floor(px).astype(int)


def colours_at(img, pixels: np.ndarray) -> set[tuple[int, int, int]]:
    rgb = np.asarray(img.convert("RGB"))
    return {tuple(int(v) for v in rgb[r, c]) for c, r in pixels}


def test_a_painting_on_wall_0_is_a_bar_of_its_colour_along_the_wall():
    scene, assets = wall_scene()
    size = 512
    img = bev_image(scene, assets, size)
    painting, curtains = semantic_color("painting"), semantic_color("curtains")
    assert painting != curtains
    # along wall 0 over the painting (2.1-2.9 m), over the bed's headboard
    assert colours_at(img, mark_pixels(scene, 0, 2.15, 2.85, size)) == {painting}
    # wall 2 runs from (4, 3) to (0, 3): the curtains (x 0.8-2.7) are 1.3-3.2 m along it
    assert colours_at(img, mark_pixels(scene, 2, 1.35, 3.15, size)) == {curtains}
    # beside the painting, along the same wall, the wardrobe
    assert colours_at(img, mark_pixels(scene, 0, 3.4, 3.9, size)).isdisjoint({painting})
    assert painting not in colours_at(img, mark_pixels(scene, 1, 0.2, 2.8, size))
    # the mark is a few pixels thick, not a band across the room
    camera = bev_camera(scene.room, size)
    deep = camera.project([[2.5, 12 * camera.pixel_m, 0.0]])[0].astype(int)
    assert tuple(np.asarray(img)[deep[1], deep[0]]) != painting


def test_which_objects_are_marked():
    # a real room's mirror on wall 3 (support unknown), and a painting that says it hangs
    # on wall 1 but floats mid-room
    mirror = OrientedBox.from_yaw([0.02, 1.5, 1.4], [0.6, 0.04, 0.9], -np.pi / 2)
    real = SceneObject("mirror_0", "mirror", mirror)
    mid = OrientedBox.from_yaw([2.0, 1.5, 1.5], [0.5, 0.04, 0.4])
    astray = SceneObject("painting_1", "painting", mid, None, wall_support(1))
    scene, _ = wall_scene(real, astray)
    marks = {m.object_id: m for m in wall_marks(scene)}
    assert set(marks) == {"painting_0", "curtains_0", "mirror_0"}
    assert marks["painting_0"].wall.index == 0 and marks["mirror_0"].wall.index == 3
    assert (marks["painting_0"].lo, marks["painting_0"].hi) == pytest.approx((0.1, 0.9))
    assert [m.object_id for m in wall_marks(scene)][0] == "curtains_0"  # widest first


def test_walls_stand_outside_the_room_so_wall_objects_show():
    scene, assets = wall_scene()
    for name, mesh in room_meshes(scene.room):
        if name == "floor":
            continue
        i = int(name.split("_")[1])
        inward = walls_of(scene.room.floor_polygon)[i].local(mesh.vertices[:, :2])[:, 1]
        assert inward.max() <= 1e-9, name  # no wall reaches into the room
    # seen from the room (+y), wall 0 behind the painting: the painting is in the picture
    meshes = [m for n, m in room_meshes(scene.room) if n.startswith("wall_0_")]
    (painting,) = [m for oid, _, m in object_meshes(scene, assets) if oid == "painting_0"]
    assert painting.vertices[:, 1].min() >= -1e-9
    colours = [(90, 90, 90)] * len(meshes) + [(255, 0, 0)]
    img = render_meshes([*meshes, painting], colours, (0.0, 10.0), 256)
    rgb = np.asarray(img, dtype=int)
    red = (rgb[..., 0] > 120) & (rgb[..., 1] < 40) & (rgb[..., 2] < 40)
    assert red.sum() > 200


def test_the_glb_has_the_wall_objects_at_their_boxes():
    trimesh = pytest.importorskip("trimesh")
    scene, assets = wall_scene()
    loaded = trimesh.load(io.BytesIO(glb_bytes(scene, assets)), file_type="glb")
    nodes = set(loaded.graph.nodes_geometry)
    assert {"painting_0", "curtains_0", "bed_0"} <= nodes
    for oid, box in (("painting_0", PAINTING), ("curtains_0", CURTAINS)):
        # relative to the root node: the file's y-up rotation undone, our z-up world
        transform, geom = loaded.graph.get(oid, frame_from="pair2scene")
        mesh = loaded.geometry[geom].copy()
        mesh.apply_transform(transform)
        lo, hi = box.aabb()
        assert np.all(mesh.bounds[0] >= lo - 1e-3) and np.all(mesh.bounds[1] <= hi + 1e-3), oid
        np.testing.assert_allclose(mesh.bounds.mean(0)[:2], box.center[:2], atol=0.05)

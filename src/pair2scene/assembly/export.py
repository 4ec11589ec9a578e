"""Writing a placed scene: ``scene.json``, ``scene.glb`` and ``bev.png``, into one folder.

- ``scene.glb``: one node per object named by its id (its asset's mesh, in world
  coordinates, z up as everywhere in pair2scene), plus ``floor`` and ``wall_<i>`` nodes
  (walls leave the door openings free).
- ``bev.png``: the top view, objects in semantic colours (one hue family per
  super-category, a shade per category), the floor and walls, a legend of the categories.

:func:`write_scene_folder` writes everything into a temporary folder beside the target and
renames it into place, so an interrupted run never leaves a half-written scene folder.
"""

from __future__ import annotations

import colorsys
import shutil
import tempfile
import zlib
from pathlib import Path

import numpy as np

from pair2scene.assets.mesh import Mesh, box_between
from pair2scene.categories import BY_NAME, SuperCategory
from pair2scene.io.atomic import atomic_write_bytes
from pair2scene.io.scene_json import write_scene
from pair2scene.scene.model import Room, Scene

WALL_THICKNESS_M = 0.1
FLOOR_THICKNESS_M = 0.05
BEV_SIZE = 768
LEGEND_WIDTH = 220
SUPER_HUES = {
    SuperCategory.LARGE_FURNITURE: 0.08,
    SuperCategory.SMALL_OBJECT: 0.58,
    SuperCategory.WALL_OBJECT: 0.80,
    SuperCategory.FIXTURE: 0.33,
}
"""Hue per super-category (orange furniture, blue small objects, purple wall objects, green
fixtures); categories vary in lightness and saturation within their family."""
FLOOR_RGB = (232, 228, 220)
WALL_RGB = (90, 90, 90)


def semantic_color(category: str) -> tuple[int, int, int]:
    """A stable RGB for a category: its super-category's hue, a shade from its name."""
    cat = BY_NAME.get(category)
    hue = SUPER_HUES.get(cat.super if cat else SuperCategory.UNKNOWN, 0.0)
    k = zlib.crc32(category.encode())
    light = 0.35 + 0.35 * ((k & 0xFF) / 255)
    sat = 0.45 + 0.5 * (((k >> 8) & 0xFF) / 255)
    hue = (hue + 0.06 * ((((k >> 16) & 0xFF) / 255) - 0.5)) % 1.0
    r, g, b = colorsys.hls_to_rgb(hue, light, sat)
    return int(r * 255), int(g * 255), int(b * 255)


def object_meshes(scene: Scene, assets: dict) -> list[tuple[str, str, Mesh]]:
    """(object id, category, world mesh) of every object of ``scene`` with an asset."""
    out = []
    for o in scene.objects:
        asset = assets.get(o.id)
        if asset is not None:
            out.append((o.id, o.category, asset.mesh.transformed(o.box.rotation, o.box.center)))
    return out


def room_meshes(room: Room) -> list[tuple[str, Mesh]]:
    """The floor slab under z = 0 and one wall per polygon edge, door openings left free."""
    poly = np.asarray(room.floor_polygon, dtype=float)
    lo, hi = poly.min(0), poly.max(0)
    t = WALL_THICKNESS_M
    out = [
        (
            "floor",
            box_between([lo[0] - t, lo[1] - t, -FLOOR_THICKNESS_M], [hi[0] + t, hi[1] + t, 0.0]),
        )
    ]
    for i in range(len(poly)):
        a, b = poly[i], poly[(i + 1) % len(poly)]
        length = float(np.linalg.norm(b - a))
        if length < 1e-6:
            continue
        u = (b - a) / length
        normal = np.array([u[1], -u[0]])  # outward for a counter-clockwise polygon
        cuts = []  # (start, end, door top) along the edge
        for door in room.doors:
            p0, p1 = np.asarray(door.p0, float), np.asarray(door.p1, float)
            s0, s1 = sorted(((p0 - a) @ u, (p1 - a) @ u))
            off = max(abs((p0 - a) @ normal), abs((p1 - a) @ normal))
            if off < 1e-3 and s1 > 0 and s0 < length:
                cuts.append((max(s0, 0.0), min(s1, length), door.z_max))
        spans, at = [], 0.0
        for s0, s1, top in sorted(cuts):
            spans.append((at, s0, 0.0, room.height))
            spans.append((s0, s1, top, room.height))  # the lintel above the door
            at = s1
        spans.append((at, length, 0.0, room.height))
        yaw_rot = np.array([[u[0], -u[1], 0.0], [u[1], u[0], 0.0], [0.0, 0.0, 1.0]])
        for j, (s0, s1, z0, z1) in enumerate(
            s for s in spans if s[1] - s[0] > 1e-6 and s[3] > s[2]
        ):
            local = box_between([s0, 0.0, z0], [s1, t, z1])
            out.append((f"wall_{i}_{j}", local.transformed(yaw_rot, [a[0], a[1], 0.0])))
    return out


def glb_bytes(scene: Scene, assets: dict) -> bytes:
    """The scene as a binary glTF: node name = object id; floor and walls included."""
    import trimesh

    tscene = trimesh.Scene()
    for name, mesh in room_meshes(scene.room):
        rgb = FLOOR_RGB if name == "floor" else WALL_RGB
        tscene.add_geometry(_trimesh(mesh, rgb), node_name=name, geom_name=name)
    for oid, category, mesh in object_meshes(scene, assets):
        tscene.add_geometry(_trimesh(mesh, semantic_color(category)), node_name=oid, geom_name=oid)
    return tscene.export(file_type="glb")


def _trimesh(mesh: Mesh, rgb):
    import trimesh

    m = trimesh.Trimesh(mesh.vertices, mesh.faces, process=False)
    m.visual.face_colors = np.tile([*rgb, 255], (len(mesh.faces), 1)).astype(np.uint8)
    return m


def bev_image(scene: Scene, assets: dict, size: int = BEV_SIZE):
    """Top view (PIL image): floor, walls, objects in semantic colours, and a legend."""
    from PIL import Image, ImageDraw

    from pair2scene.render import caption_font, render_meshes

    walls = room_meshes(scene.room)
    objs = object_meshes(scene, assets)
    # Draw low objects last so what rests on furniture shows on top of it in the view.
    meshes = [m for _, m in walls] + [m for _, _, m in objs]
    colors = [FLOOR_RGB if n == "floor" else WALL_RGB for n, _ in walls]
    colors += [semantic_color(c) for _, c, _ in objs]
    b = scene.room.bounds
    lo, hi = b.center - b.half_size, b.center + b.half_size
    bounds = np.array([[lo[0] - WALL_THICKNESS_M, lo[1] - WALL_THICKNESS_M, 0.0],
                       [hi[0] + WALL_THICKNESS_M, hi[1] + WALL_THICKNESS_M, hi[2]]])  # fmt: skip
    view = render_meshes(meshes, colors, "top", size, bounds=bounds)
    cats = sorted({c for _, c, _ in objs})
    font = caption_font(14)
    out = Image.new("RGB", (size + LEGEND_WIDTH, size), (255, 255, 255))
    out.paste(view, (0, 0))
    draw = ImageDraw.Draw(out)
    y = 12
    draw.text(
        (size + 12, y),
        f"{scene.room.type}: {len(scene.objects)} objects",
        fill=(0, 0, 0),
        font=font,
    )
    y += 26
    for c in cats:
        if y > size - 20:
            draw.text((size + 12, y), "...", fill=(0, 0, 0), font=font)
            break
        draw.rectangle(
            [size + 12, y + 2, size + 26, y + 16], fill=semantic_color(c), outline=(0, 0, 0)
        )
        n = sum(1 for _, cc, _ in objs if cc == c)
        draw.text((size + 34, y), f"{c} x{n}" if n > 1 else c, fill=(0, 0, 0), font=font)
        y += 20
    return out


def write_scene_folder(folder: str | Path, scene: Scene, assets: dict) -> Path:
    """Write ``scene.json``, ``scene.glb`` and ``bev.png`` into ``folder`` atomically (all
    three appear together, or the folder is left as it was)."""
    import io

    folder = Path(folder)
    folder.parent.mkdir(parents=True, exist_ok=True)
    tmp = Path(tempfile.mkdtemp(dir=folder.parent, prefix=f".{folder.name}."))
    try:
        write_scene(scene, tmp / "scene.json")
        atomic_write_bytes(tmp / "scene.glb", glb_bytes(scene, assets))
        buf = io.BytesIO()
        bev_image(scene, assets).save(buf, format="PNG", optimize=False)
        atomic_write_bytes(tmp / "bev.png", buf.getvalue())
        if folder.exists():
            old = Path(tempfile.mkdtemp(dir=folder.parent, prefix=f".{folder.name}.old."))
            folder.rename(old / "x")
            tmp.rename(folder)
            shutil.rmtree(old, ignore_errors=True)
        else:
            tmp.rename(folder)
    except BaseException:
        shutil.rmtree(tmp, ignore_errors=True)
        raise
    return folder

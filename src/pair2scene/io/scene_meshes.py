"""The one description of a placed scene that every export format draws on: each object's
world mesh (its asset posed by its box), the room's floor slab and walls (door openings
left free), and the semantic colour of a category (one hue family per super-category, a
shade per category). Formats (:mod:`pair2scene.io.glb`, :mod:`pair2scene.io.bev`...) share
this, never each other's internals.
"""

from __future__ import annotations

import colorsys
import zlib

import numpy as np

from pair2scene.assets.mesh import Mesh, box_between
from pair2scene.categories import BY_NAME, SuperCategory
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

"""The one description of a placed scene that every export format draws on: each object's
world mesh (its asset posed by its box), the room's floor slab, walls (door and window
openings left free) and window panes, and the semantic colour of a category (one hue
family per super-category, a shade per category). Formats (:mod:`pair2scene.io.glb`,
:mod:`pair2scene.io.bev`...) share this, never each other's internals.
"""

from __future__ import annotations

import colorsys
import zlib
from dataclasses import dataclass

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
WINDOW_RGB = (120, 190, 235)
"""Window panes; in the top view also the wall above and below a window, so a window shows
as a light-blue mark along its wall as a door shows as a gap."""


def room_color(name: str, top_view: bool = False) -> tuple[int, int, int]:
    """The colour of a :func:`room_meshes` piece: the floor, a window's pane (and, seen
    from above, the wall above and below it: ``window_*``), or wall (a door's lintel
    ``door_*`` too, but seen from above it takes the floor's colour: a gap)."""
    if name == "floor":
        return FLOOR_RGB
    if name.endswith("_pane") or (top_view and name.startswith("window_")):
        return WINDOW_RGB
    if top_view and name.startswith("door_"):
        return FLOOR_RGB
    return WALL_RGB


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


@dataclass(frozen=True)
class SceneMeshes:
    """:func:`room_meshes` and :func:`object_meshes` of one scene, worked out once for
    every format of a scene folder that draws them (the GLB, the viewer page's GLB, the
    top view)."""

    room: list[tuple[str, Mesh]]
    objects: list[tuple[str, str, Mesh]]

    @classmethod
    def of(cls, scene: Scene, assets: dict) -> SceneMeshes:
        return cls(room_meshes(scene.room), object_meshes(scene, assets))


def floor_slab(polygon: np.ndarray, grow: float) -> Mesh:
    """The floor: the room's polygon grown by ``grow`` (under the walls too, mitred
    corners), :data:`FLOOR_THICKNESS_M` thick below z = 0, faces outward. An L-shaped room
    gets an L-shaped floor, not its bounding rectangle."""
    import shapely
    from shapely.geometry.polygon import orient

    shape = orient(shapely.Polygon(polygon).buffer(grow, join_style="mitre"), 1.0)
    tris = [np.asarray(g.exterior.coords)[:3] for g in
            shapely.constrained_delaunay_triangles(shape).geoms]  # fmt: skip
    verts, faces = [], []
    for tri in tris:
        (x0, y0), (x1, y1), (x2, y2) = tri
        if (x1 - x0) * (y2 - y0) - (y1 - y0) * (x2 - x0) < 0:
            tri = tri[::-1]  # counter-clockwise seen from above
        k = len(verts)
        verts += [[x, y, 0.0] for x, y in tri] + [[x, y, -FLOOR_THICKNESS_M] for x, y in tri]
        faces += [[k, k + 1, k + 2], [k + 3, k + 5, k + 4]]  # top up, bottom down
    ring = np.asarray(shape.exterior.coords)[:-1]  # counter-clockwise
    for i in range(len(ring)):
        (xa, ya), (xb, yb) = ring[i], ring[(i + 1) % len(ring)]
        k = len(verts)
        verts += [[xa, ya, -FLOOR_THICKNESS_M], [xb, yb, -FLOOR_THICKNESS_M], [xb, yb, 0.0],
                  [xa, ya, 0.0]]  # fmt: skip
        faces += [[k, k + 1, k + 2], [k, k + 2, k + 3]]  # facing out of the room
    return Mesh(np.asarray(verts, dtype=float), np.asarray(faces, dtype=np.int64))


def room_meshes(room: Room) -> list[tuple[str, Mesh]]:
    """The floor slab under z = 0 and one wall per polygon edge, door and window openings
    left free: ``floor``, ``wall_<edge>_<piece>``, the lintel above each door
    ``door_<edge>_<piece>``, the wall below and above each window
    ``window_<edge>_<piece>`` and its glass ``window_<edge>_<piece>_pane``.

    Walls stand outside the floor polygon, :data:`WALL_THICKNESS_M` thick, their inner
    face on the polygon's edge: what stands or hangs against a wall (a wardrobe, a
    painting flush on it) stays in front of the wall, visible. A wall reaches past its end
    over the corner where the room's corner is convex, so the outside corner is closed."""
    poly = np.asarray(room.floor_polygon, dtype=float)
    t = WALL_THICKNESS_M
    out = [("floor", floor_slab(poly, t))]
    for i in range(len(poly)):
        a, b = poly[i], poly[(i + 1) % len(poly)]
        length = float(np.linalg.norm(b - a))
        if length < 1e-6:
            continue
        u = (b - a) / length
        normal = np.array([u[1], -u[0]])  # outward for a counter-clockwise polygon
        after = poly[(i + 2) % len(poly)] - b  # the next edge: a left turn is convex
        convex = u[0] * after[1] - u[1] * after[0] > 1e-9 * max(np.linalg.norm(after), 1.0)
        cuts = []  # (start, end, bottom, top, kind) of each opening along the edge
        for opening in (*room.doors, *room.windows):
            p0, p1 = np.asarray(opening.p0, float), np.asarray(opening.p1, float)
            s0, s1 = sorted(((p0 - a) @ u, (p1 - a) @ u))
            off = max(abs((p0 - a) @ normal), abs((p1 - a) @ normal))
            if off < 1e-3 and s1 > 0 and s0 < length:
                bottom = 0.0 if opening.kind == "door" else max(opening.z_min, 0.0)
                cuts.append((max(s0, 0.0), min(s1, length), bottom, opening.z_max, opening.kind))
        spans, at = [], 0.0  # (start, end, bottom, top, name prefix)
        for s0, s1, bottom, top, kind in sorted(cuts):
            s0 = max(s0, at)  # (overlapping openings: the first one's cut holds)
            if s1 <= s0:
                continue
            prefix = kind  # "door": its lintel; "window": the wall below and above it
            spans.append((at, s0, 0.0, room.height, "wall"))
            spans.append((s0, s1, 0.0, bottom, prefix))  # the wall under a window's sill
            spans.append((s0, s1, top, room.height, prefix))  # the lintel above it
            if kind == "window":
                spans.append((s0, s1, bottom, top, "pane"))
            at = s1
        spans.append((at, length + (t if convex else 0.0), 0.0, room.height, "wall"))
        yaw_rot = np.array([[u[0], -u[1], 0.0], [u[1], u[0], 0.0], [0.0, 0.0, 1.0]])
        j = 0
        for s0, s1, z0, z1, prefix in spans:
            if s1 - s0 <= 1e-6 or z1 <= z0:
                continue
            # local y is the inward normal: the wall is y in [-t, 0], outside the room
            if prefix == "pane":  # thin glass in the middle of the wall
                local = box_between([s0, -0.55 * t, z0], [s1, -0.45 * t, z1])
                name = f"window_{i}_{j}_pane"
            else:
                local = box_between([s0, -t, z0], [s1, 0.0, z1])
                name = f"{prefix}_{i}_{j}"
            out.append((name, local.transformed(yaw_rot, [a[0], a[1], 0.0])))
            j += 1
    return out

"""``bev.png``: the top view of a placed scene: floor, walls, objects in semantic colours,
and a legend of the categories.

Wall-mounted objects are drawn the way doors and windows are, as marks along their wall:
a bar :data:`WALL_MARK_PX` pixels thick in the object's category colour, lying just
inside the wall's line over the object's extent along it, drawn over everything else so
no furniture hides it. Which objects: those hung on a wall (support ``wall:<i>``), and in
real scenes whose supports are unknown (None) those of a wall-object category that stand
against a wall (:func:`~pair2scene.scene.walls.wall_contact`). A wall object that is not
near its wall keeps its mesh in the view, where it is.
"""

from __future__ import annotations

import io
from collections.abc import Callable
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from pair2scene.assets.mesh import Asset
from pair2scene.curation.wall_objects import MOUNT_ANGLE_DEG, MOUNT_GAP_M, hung_on
from pair2scene.io.scene_meshes import (
    WALL_THICKNESS_M,
    SceneMeshes,
    room_color,
    semantic_color,
)
from pair2scene.scene.model import Room, Scene, SceneObject
from pair2scene.scene.walls import Wall, face_contacts, walls_of

if TYPE_CHECKING:
    from PIL import Image

    from pair2scene.assets.mesh import Mesh
    from pair2scene.render import Camera

BEV_SIZE = 768
LEGEND_WIDTH = 220
WALL_MARK_PX = 4
"""Thickness of a wall object's mark, in pixels, inward from its wall's line."""


@dataclass(frozen=True)
class WallMark:
    """A wall object's mark in the top view: the stretch of its wall it covers."""

    object_id: str
    category: str
    wall: Wall
    lo: float
    """Start of the stretch along the wall, from its midpoint (m)."""
    hi: float
    """End of the stretch (m), > lo."""

    def quad(self, depth: float) -> np.ndarray:
        """(4, 2) world xy corners of the bar: the stretch, ``depth`` m into the room."""
        w = self.wall
        a, b = w.midpoint + w.direction * self.lo, w.midpoint + w.direction * self.hi
        inward = w.normal * depth
        return np.array([a, b, b + inward, a + inward])


def _mark_wall(o: SceneObject, walls: dict[int, Wall]) -> Wall | None:
    """The wall ``o`` is marked on (:func:`~pair2scene.curation.wall_objects.hung_on`), or
    None when it is drawn as a mesh (one hung far from its wall: where it is)."""
    wall = hung_on(o, list(walls.values()))
    if wall is None or not face_contacts(o.box, [wall], MOUNT_GAP_M, MOUNT_ANGLE_DEG):
        return None
    return wall


def wall_marks(scene: Scene) -> list[WallMark]:
    """The marks of the scene's wall objects (see the module docstring), widest first so
    that a narrow one on the same stretch (a painting on a curtain's) stays visible."""
    walls = {w.index: w for w in walls_of(scene.room.floor_polygon)}
    out = []
    for o in scene.objects:
        wall = _mark_wall(o, walls)
        if wall is None:
            continue
        half = wall.length / 2
        lo, hi = wall.extent(o.box)
        lo, hi = max(lo, -half), min(hi, half)
        if hi > lo:
            out.append(WallMark(o.id, o.category, wall, lo, hi))
    out.sort(key=lambda m: (-(m.hi - m.lo), m.object_id))
    return out


def bev_camera(room: Room, size: int = BEV_SIZE) -> Camera:
    """The top view's camera: the room's bounds and its walls' thickness, framed in a
    ``size`` x ``size`` picture (``camera.project`` maps world points to its pixels)."""
    from pair2scene.render import fit_camera

    b = room.bounds
    lo, hi = b.center - b.half_size, b.center + b.half_size
    lo = np.array([lo[0] - WALL_THICKNESS_M, lo[1] - WALL_THICKNESS_M, 0.0])
    hi = np.array([hi[0] + WALL_THICKNESS_M, hi[1] + WALL_THICKNESS_M, hi[2]])
    corners = np.array([[x, y, z] for x in (lo[0], hi[0]) for y in (lo[1], hi[1])
                        for z in (lo[2], hi[2])])  # fmt: skip
    return fit_camera("top", corners, size)


def start_bev(
    scene: Scene,
    assets: dict[str, Asset],
    size: int = BEV_SIZE,
    meshes: SceneMeshes | None = None,
) -> Callable[[], Image.Image]:
    """Start drawing :func:`bev_image` (the driver draws in its threads while the caller
    goes on); the function returned waits for it and adds the marks and legend.
    ``meshes``: the scene's meshes when the caller has them already."""
    from pair2scene.render import start_render

    meshes = meshes or SceneMeshes.of(scene, assets)
    walls = meshes.room
    marks = wall_marks(scene)
    marked = {m.object_id for m in marks}
    objs = [(oid, c, m) for oid, c, m in meshes.objects if oid not in marked]
    # Draw low objects last so what rests on furniture shows on top of it in the view.
    drawn_meshes = [m for _, m in walls] + [m for _, _, m in objs]
    colors = [room_color(n, top_view=True) for n, _ in walls]
    colors += [semantic_color(c) for _, c, _ in objs]
    camera = bev_camera(scene.room, size)
    pending = start_render(drawn_meshes, colors, camera=camera)
    return lambda: _finish_bev(scene, pending.image(), camera, marks, objs, size)


def bev_image(scene: Scene, assets: dict[str, Asset], size: int = BEV_SIZE) -> Image.Image:
    """Top view (PIL image): floor, walls, objects in semantic colours, wall objects as
    marks along their walls, and a legend."""
    return start_bev(scene, assets, size)()


def _finish_bev(
    scene: Scene,
    view: Image.Image,
    camera: Camera,
    marks: list[WallMark],
    objs: list[tuple[str, str, Mesh]],
    size: int,
) -> Image.Image:
    """The drawn room ``view`` with the wall marks over it and the legend beside it."""
    from PIL import Image, ImageDraw

    from pair2scene.render import caption_font

    draw = ImageDraw.Draw(view)
    for mark in marks:
        quad = mark.quad(WALL_MARK_PX * camera.pixel_m)
        px = camera.project(np.c_[quad, np.full(4, scene.room.height)])
        draw.polygon([tuple(p) for p in px], fill=semantic_color(mark.category))
    drawn = [c for _, c, _ in objs] + [m.category for m in marks]
    cats = sorted(set(drawn))
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
        n = drawn.count(c)
        draw.text((size + 34, y), f"{c} x{n}" if n > 1 else c, fill=(0, 0, 0), font=font)
        y += 20
    return out


def bev_png(scene: Scene, assets: dict[str, Asset]) -> bytes:
    """:func:`bev_image` as PNG bytes."""
    return png_bytes(bev_image(scene, assets))


def png_bytes(image: Image.Image) -> bytes:
    """A top view as the bytes of ``bev.png``."""
    buf = io.BytesIO()
    image.save(buf, format="PNG", optimize=False)
    return buf.getvalue()

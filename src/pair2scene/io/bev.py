"""``bev.png``: the top view of a placed scene: floor, walls, objects in semantic colours,
and a legend of the categories."""

from __future__ import annotations

import io

import numpy as np

from pair2scene.assets.mesh import Asset
from pair2scene.io.scene_meshes import (
    WALL_THICKNESS_M,
    object_meshes,
    room_color,
    room_meshes,
    semantic_color,
)
from pair2scene.scene.model import Scene

BEV_SIZE = 768
LEGEND_WIDTH = 220


def bev_image(scene: Scene, assets: dict[str, Asset], size: int = BEV_SIZE):
    """Top view (PIL image): floor, walls, objects in semantic colours, and a legend."""
    from PIL import Image, ImageDraw

    from pair2scene.render import caption_font, render_meshes

    walls = room_meshes(scene.room)
    objs = object_meshes(scene, assets)
    # Draw low objects last so what rests on furniture shows on top of it in the view.
    meshes = [m for _, m in walls] + [m for _, _, m in objs]
    colors = [room_color(n, top_view=True) for n, _ in walls]
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


def bev_png(scene: Scene, assets: dict[str, Asset]) -> bytes:
    """:func:`bev_image` as PNG bytes."""
    buf = io.BytesIO()
    bev_image(scene, assets).save(buf, format="PNG", optimize=False)
    return buf.getvalue()

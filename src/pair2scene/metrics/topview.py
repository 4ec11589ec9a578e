"""Semantic top views: the single renderer behind FID, KID and SCA.

Image metrics compare pictures, so real and generated scenes must be drawn by
exactly the same code or the metric measures the renderer. Following DiffuScene,
a scene is seen orthographically from above: every object is its oriented box's
footprint filled with its category's colour, on a white background with no floor
and no walls, so only the layout and the categories reach the classifier. The view
is framed on the room's bounds with a fixed margin, so rooms of one size are drawn
at one scale whoever produced them.
"""

from __future__ import annotations

import numpy as np
from PIL import Image, ImageDraw

from pair2scene.errors import UserError
from pair2scene.io.scene_meshes import semantic_color
from pair2scene.scene.geometry import convex_hull_2d

MARGIN = 1.05
"""View side over the room's largest extent: a little air so boxes at walls are whole."""
BACKGROUND = (255, 255, 255)


def _frame(scene) -> tuple[np.ndarray, float]:
    """Centre (2,) and side (m) of the square view.

    The room's bounds frame the view (so a generated room is framed like the real
    one it imitates); the objects' bounds stand in when the room has no polygon.
    """
    poly = np.asarray(getattr(scene.room, "floor_polygon", ()), dtype=float).reshape(-1, 2)
    if len(poly) and np.ptp(poly, axis=0).max() > 0:
        lo, hi = poly.min(0), poly.max(0)
    elif scene.objects:
        xy = np.concatenate([o.box.corners()[:, :2] for o in scene.objects])
        lo, hi = xy.min(0), xy.max(0)
    else:
        lo, hi = np.zeros(2), np.zeros(2)
    side = float((hi - lo).max()) * MARGIN
    return (lo + hi) / 2, side if side > 0 else 1.0


def topview(scene, size: int = 256) -> np.ndarray:
    """Orthographic semantic top view of ``scene``: (size, size, 3) uint8, +y up.

    Objects are drawn from the lowest top to the highest (ties by id, for
    determinism), so what stands on a table covers the table as seen from above.
    """
    if not isinstance(size, int | np.integer) or size < 1:
        raise UserError(f"top view size must be a positive integer, got {size!r}")
    center, side = _frame(scene)
    scale = size / side
    origin = center + np.array([-side / 2, side / 2])  # world xy of the image's top-left
    image = Image.new("RGB", (size, size), BACKGROUND)
    draw = ImageDraw.Draw(image)
    for obj in sorted(scene.objects, key=lambda o: (o.box.top, o.id)):
        xy = obj.box.corners()[:, :2]
        # PIL puts pixel centres on integers: shift by half a pixel so a box covering
        # [a, b] in continuous image coordinates fills the pixels centred inside it
        cols = (xy[:, 0] - origin[0]) * scale - 0.5
        rows = (origin[1] - xy[:, 1]) * scale - 0.5
        footprint = convex_hull_2d(np.stack([cols, rows], axis=1))
        if len(footprint) >= 3:
            draw.polygon(footprint, fill=semantic_color(obj.category))
    return np.asarray(image, dtype=np.uint8)


def topview_batch(scenes, size: int = 256) -> np.ndarray:
    """Top views of many scenes stacked: (N, size, size, 3) uint8."""
    images = [topview(s, size) for s in scenes]
    if not images:
        return np.zeros((0, size, size, 3), dtype=np.uint8)
    return np.stack(images)


def contact_sheet(images, cols: int = 8) -> Image.Image:
    """Images (N, H, W, 3) tiled row by row on white: to eyeball what the metrics saw."""
    images = np.asarray(images, dtype=np.uint8)
    if images.ndim != 4 or images.shape[-1] != 3 or len(images) == 0 or cols < 1:
        raise UserError("contact sheet needs a non-empty (N, H, W, 3) stack and cols >= 1")
    n, h, w, _ = images.shape
    rows = -(-n // cols)
    sheet = np.full((rows * h, min(cols, n) * w, 3), 255, dtype=np.uint8)
    for i, img in enumerate(images):
        r, c = divmod(i, cols)
        sheet[r * h : (r + 1) * h, c * w : (c + 1) * w] = img
    return Image.fromarray(sheet)

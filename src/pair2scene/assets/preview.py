"""A pure-CPU picture of a mesh: painter's algorithm with flat shading, in PIL.

Slower and cruder than the moderngl renderer, but needs nothing beyond Pillow;
used as its fallback and for quick looks while writing generators.
"""

from __future__ import annotations

import numpy as np

from pair2scene.assets.mesh import Mesh

LIGHT = np.array([0.35, 0.55, 0.75])
"""Direction towards the light (world): from the front (+y) right, above."""


def view_rotation(azimuth_deg: float, elevation_deg: float) -> np.ndarray:
    """(3, 3) world -> camera (x right, y up, z towards the viewer).

    azimuth 0 looks at the object's front (+y) from in front of it; elevation 90
    looks straight down (top view, +y up in the picture)."""
    az, el = np.radians(azimuth_deg), np.radians(elevation_deg)
    # viewer direction (from object to camera)
    d = np.array([np.sin(az) * np.cos(el), np.cos(az) * np.cos(el), np.sin(el)])
    up_hint = np.array([0.0, 0.0, 1.0]) if abs(d[2]) < 0.999 else np.array([0.0, 1.0, 0.0])
    right = np.cross(up_hint, d)
    right /= np.linalg.norm(right)
    up = np.cross(d, right)
    return np.stack([right, up, d])


def render_mesh(
    mesh: Mesh,
    size: int = 256,
    azimuth: float = 35.0,
    elevation: float = 30.0,
    color: tuple[int, int, int] = (200, 170, 130),
    background: tuple[int, int, int] = (255, 255, 255),
    margin: float = 0.08,
):
    """A PIL image (size x size) of ``mesh``, orthographic, fitted to the frame."""
    from PIL import Image, ImageDraw

    img = Image.new("RGB", (size, size), background)
    if len(mesh.faces) == 0:
        return img
    rot = view_rotation(azimuth, elevation)
    v = mesh.vertices @ rot.T
    lo, hi = v[:, :2].min(0), v[:, :2].max(0)
    scale = (1 - 2 * margin) * size / max(float((hi - lo).max()), 1e-9)
    mid = (lo + hi) / 2
    xy = (v[:, :2] - mid) * scale
    px = np.stack([size / 2 + xy[:, 0], size / 2 - xy[:, 1]], axis=1)
    normals = mesh.face_normals
    facing = normals @ rot[2] > 1e-9
    shade = 0.35 + 0.65 * np.clip(normals @ (LIGHT / np.linalg.norm(LIGHT)), 0, 1)
    depth = v[mesh.faces, 2].mean(1)
    draw = ImageDraw.Draw(img)
    base = np.asarray(color, dtype=float)
    order = np.argsort(depth)  # far to near
    for f in order[facing[order]]:
        c = tuple(int(x) for x in np.clip(base * shade[f], 0, 255))
        draw.polygon([tuple(p) for p in px[mesh.faces[f]]], fill=c)
    return img

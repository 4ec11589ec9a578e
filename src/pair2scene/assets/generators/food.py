"""Food: apple, tomato, potato, egg, lettuce, bread.

Round things fill the box with elliptic sections (radii ``size_x/2``, ``size_y/2``), so
no generator assumes a square footprint. Parts are convex, built inside
[-size/2, size/2] (+z up, +y front, +x right).
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from pair2scene.assets.generators.shapes import (
    beam,
    ellipse_arc,
    in_long_frame,
    lathe,
    rest_flat,
)
from pair2scene.assets.mesh import (
    Mesh,
    Part,
    box_between,
    ellipsoid,
    hull,
    prism,
)
from pair2scene.assets.mesh import rod as _rod
from pair2scene.assets.registry import register
from pair2scene.scene.geometry import rot_y as _rot_y
from pair2scene.scene.geometry import rot_z as _rot_z


@register("apple", variants=2)
def apple(size, rng, style, support_heights):
    """An apple with a stem: 0 round, 1 taller with a tapered bottom and a leaf."""
    sx, sy, h = (float(v) for v in size)
    rx, ry, z0, zt = sx / 2, sy / 2, -h / 2, h / 2
    zb = z0 + 0.9 * h
    # (fraction of body height, fraction of radius): a round body, narrower at the base,
    # with a flat crown where the stem sits (the dimple cannot be convex)
    if style == 0:
        t = [0.0, 0.05, 0.15, 0.3, 0.5, 0.65, 0.8, 0.9, 0.97, 1.0]
        r = [0.3, 0.55, 0.78, 0.93, 1.0, 0.98, 0.86, 0.65, 0.42, 0.3]
    else:
        t = [0.0, 0.06, 0.2, 0.4, 0.62, 0.78, 0.9, 0.97, 1.0]
        r = [0.28, 0.5, 0.75, 0.92, 1.0, 0.94, 0.75, 0.5, 0.32]
    profile = np.c_[r, z0 + np.asarray(t) * (zb - z0)]
    stem_r = float(np.clip(0.05 * min(rx, ry), 0.0015, 0.006))
    lean = rng.uniform(0.03, 0.08) * rx
    parts = [
        Part("body", lathe(profile, rx, ry, center=(0, 0), hull_of_rings=False)),
        Part("stem", _rod((0, 0, zb - 0.04 * h), (lean, 0, zt), stem_r, 0.8 * stem_r, 6)),
    ]
    if style == 1:
        leaf = ellipsoid((0, 0, 0), (0.3 * rx, 0.12 * ry, 0.015 * h), 4, 8)
        parts.append(Part("leaf", leaf.transformed(_rot_y(-0.35), (-0.3 * rx, 0, zb + 0.02 * h))))
    return parts


@register("tomato", variants=2)
def tomato(size, rng, style, support_heights):
    """A tomato with a green calyx and stem: 0 smooth, 1 ribbed (lobed) beefsteak."""
    sx, sy, h = (float(v) for v in size)
    rx, ry, z0, zt = sx / 2, sy / 2, -h / 2, h / 2
    zb = z0 + 0.9 * h
    if style == 0:
        parts = [
            Part(
                "body",
                lathe(
                    [
                        (0.45, z0),
                        (0.82, z0 + 0.12 * h),
                        (1.0, z0 + 0.45 * h),
                        (0.88, z0 + 0.75 * h),
                        (0.45, zb),
                    ],
                    rx,
                    ry,
                    center=(0, 0),
                    hull_of_rings=False,
                ),
            )
        ]
    else:
        parts = [
            Part(
                "core",
                lathe(
                    [(0.5, z0 + 0.03 * h), (1.0, z0 + 0.45 * h), (0.5, zb)],
                    0.8 * rx,
                    0.8 * ry,
                    center=(0, 0),
                    hull_of_rings=False,
                ),
            )
        ]
        n = 6
        off = rng.uniform(0, np.pi / n)
        for i in range(n):
            a = off + 2 * np.pi * i / n
            c = (0.32 * rx * np.cos(a), 0.32 * ry * np.sin(a), z0 + 0.46 * h)
            parts.append(Part(f"lobe_{i}", ellipsoid(c, (0.68 * rx, 0.68 * ry, 0.44 * h), 6, 10)))
    # calyx: thin sepals radiating from the top, drooping a little
    n_sep = 5
    w = 0.12 * min(rx, ry)
    th = 0.02 * h
    for i in range(n_sep):
        a = 2 * np.pi * i / n_sep + 0.3
        # the ribbed lobes reach the crown, so there the sepals lie flatter
        tip = (0.42 * rx * np.cos(a), 0.42 * ry * np.sin(a), zb - (0.06 if style == 0 else 0.0) * h)
        parts.append(
            Part(
                f"sepal_{i}",
                beam((0, 0, zb + 0.01 * h), tip, w, th, side=(-np.sin(a), np.cos(a), 0)),
            )
        )
    parts.append(
        Part(
            "stem",
            _rod((0, 0, zb - 0.02 * h), (0, 0, zt), 0.05 * min(rx, ry), 0.04 * min(rx, ry), 6),
        )
    )
    return parts


POTATO_SEAT = 0.8
"""A potato's points lower than this share of its half-height are pressed onto its
bottom: it rests on a flat patch (about 0.6 of its width across), as a real potato
settles on its flattest side. A rounder bottom rolled 17-52 degrees under gravity in
curation, and 12 of the 13 potatoes on counters and tables of 25 ProcTHOR kitchens were
dropped for it."""


def _lumpy(
    center: Sequence[float],
    radii: Sequence[float],
    rng: np.random.Generator,
    jitter: float,
    n: int = 48,
    seat: float | None = None,
) -> Mesh:
    """Convex hull of n points on an ellipsoid (3,) radii, each radius jittered by a
    relative ``jitter`` (a potato's irregular outline). ``seat``: points below ``-seat``
    of the z radius are pressed onto a flat bottom there, and the body is stretched back
    down to ``-radii z``."""
    k = np.arange(n) + 0.5
    phi = np.arccos(1 - 2 * k / n)
    theta = np.pi * (1 + 5**0.5) * k
    dirs = np.stack([np.cos(theta) * np.sin(phi), np.sin(theta) * np.sin(phi), np.cos(phi)], 1)
    scale = 1 + jitter * rng.standard_normal(n)
    pts = dirs * np.clip(scale, 0.7, 1.3)[:, None] * radii
    if seat is not None:
        rz = float(radii[2])
        top = pts[:, 2].max()
        z = np.maximum(pts[:, 2], -seat * rz)
        pts[:, 2] = top - (top - z) * (top + rz) / (top + seat * rz)
    return hull(np.asarray(center) + pts)


@register("potato", variants=2)
def potato(size, rng, style, support_heights):
    """A potato: 0 one lumpy oval, 1 two fused lumps along its long axis."""
    sx, sy, h = (float(v) for v in size)
    rx, ry, rz = sx / 2, sy / 2, h / 2
    if style == 0:
        return [Part("body", _lumpy((0, 0, 0), (rx, ry, rz), rng, 0.06, seat=POTATO_SEAT))]
    along_y = sy >= sx
    axis = np.array([0.0, 1.0, 0.0]) if along_y else np.array([1.0, 0.0, 0.0])
    long_r = ry if along_y else rx
    r_a = np.array([rx, ry, rz]) * np.where(axis > 0, 0.62, 1.0)
    r_b = np.array([rx, ry, rz]) * np.where(axis > 0, 0.5, 0.85)
    return [
        Part("lump_0", _lumpy(-axis * (long_r - r_a @ axis), r_a, rng, 0.05, seat=POTATO_SEAT)),
        Part("lump_1", _lumpy(axis * (long_r - r_b @ axis), r_b, rng, 0.05, seat=POTATO_SEAT)),
    ]


EGG_SEAT = 0.84
"""An egg's profile starts this share of a half turn from its broad end's pole: a flat
seat about half its width across, as an egg stands in a tray's cup. Eggs with a round
pole (EGG_SEAT 1) toppled under gravity in curation: 15 of the 33 eggs standing in 25
ProcTHOR fridges."""


@register("egg", variants=2)
def egg(size, rng, style, support_heights):
    """An egg standing on its broad end: 0 pointed (hen's egg), 1 rounder."""
    sx, sy, h = (float(v) for v in size)
    rx, ry, z0 = sx / 2, sy / 2, -h / 2
    k = rng.uniform(0.14, 0.2) if style == 0 else rng.uniform(0.02, 0.05)
    # denser rings near the ends; the broad end is cut flat (EGG_SEAT) so it stands
    u = np.cos(np.linspace(np.pi * EGG_SEAT, 0.0, 11))
    r = np.sqrt(np.clip(1 - u**2, 0, None)) * (1 - k * u)
    r /= r.max()
    r[-1] = 0.0
    u = -1 + (u - u[0]) / (1 - u[0]) * 2  # the cut end on the box bottom
    return [
        Part(
            "shell",
            lathe(np.c_[r, z0 + (u + 1) / 2 * h], rx, ry, center=(0, 0), hull_of_rings=False),
        )
    ]


LETTUCE_REST = 0.8
"""A romaine head lying on its side rests on its outer leaves pressed flat: what lay below
this share of its half height (:func:`~pair2scene.assets.generators.shapes.rest_flat`)."""


@register("lettuce", variants=2)
def lettuce(size, rng, style, support_heights):
    """A lettuce: 0 round head with leaves wrapped around a core, 1 romaine head lying on
    its side, leaves fanning out from the stalk along the longer horizontal axis."""
    sx, sy, h = (float(v) for v in size)
    if style == 0:
        rx, ry, rz = sx / 2, sy / 2, h / 2
        parts = [Part("core", ellipsoid((0, 0, 0.02 * rz), (0.8 * rx, 0.8 * ry, 0.92 * rz), 6, 12))]
        n = 7
        off = rng.uniform(0, 2 * np.pi)
        for i in range(n):
            a = off + 2 * np.pi * i / n
            # an outer leaf stands tangentially against the core, its top leaning in
            # slightly so the head reads as wrapped, not open
            leaf = ellipsoid((0, 0, 0), (0.14, 0.6, 0.72), 6, 10)
            leaf = leaf.transformed(
                _rot_z(a) @ _rot_y(-rng.uniform(0.1, 0.2)),
                (0.68 * np.cos(a), 0.68 * np.sin(a), -0.2),
            )
            parts.append(Part(f"leaf_{i}", leaf.scaled((rx, ry, rz))))
        for i in range(3):
            a = off + 2 * np.pi * i / 3 + 0.5
            # crinkled top: loose leaves folded over the crown
            leaf = ellipsoid((0, 0, 0), (0.5, 0.3, 0.12), 4, 10)
            leaf = leaf.transformed(
                _rot_z(a) @ _rot_y(0.35), (0.3 * np.cos(a), 0.3 * np.sin(a), 0.75)
            )
            parts.append(Part(f"top_leaf_{i}", leaf.scaled((rx, ry, rz))))
        return parts

    def build(length, w, hh, turned):
        hl, hw, hz = length / 2, w / 2, hh / 2
        out = [
            Part(
                "stalk",
                _rod((-hl, 0, -0.2 * hz), (-0.4 * hl, 0, -0.1 * hz), 0.35 * hw, 0.6 * hw, 10),
            )
        ]
        spec = [
            (0.1, 0.0, 0.0, 0.0),
            (0.15, 0.35, 0.1, 0.18),
            (0.15, -0.35, 0.1, -0.18),
            (0.2, 0.2, 0.45, 0.08),
            (0.2, -0.2, 0.45, -0.08),
        ]
        for i, (cx, cy, cz, yaw) in enumerate(spec):
            leaf = ellipsoid((0, 0, 0), (0.75 * hl, 0.55 * hw, 0.55 * hz), 6, 12)
            leaf = leaf.transformed(
                _rot_z(yaw + rng.uniform(-0.04, 0.04)), (cx * hl, cy * hw, (cz - 0.35) * hz)
            )
            out.append(Part(f"leaf_{i}", leaf))
        # its outer leaves pressed flat underneath: on the round ones it rolled 4-7 cm in
        # the simulation (7 of 20 lettuces in 30 kitchens)
        return rest_flat(out, hz, LETTUCE_REST)

    return in_long_frame(size, build)


@register("bread", variants=2)
def bread(size, rng, style, support_heights):
    """A loaf of bread: 0 tin loaf (box base, domed top), 1 oval baton with score marks."""
    sx, sy, h = (float(v) for v in size)
    z0, zt = -h / 2, h / 2
    if style == 0:

        def build(length, w, hh, turned):
            hz0 = -hh / 2
            zs = hz0 + rng.uniform(0.5, 0.58) * hh
            base = box_between((-0.48 * length, -0.46 * w, hz0), (0.48 * length, 0.46 * w, zs))
            arc = ellipse_arc(0, zs, 0.5 * w, hh / 2 - zs, 9, 0.0, np.pi, endpoint=True)
            dome = prism(arc, -length / 2, length / 2)
            # prism extrudes along z: turn its axis onto x, its outline's (x, y) onto (y, z)
            dome = dome.transformed(np.array([[0.0, 0.0, 1.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]]))
            return [Part("base", base), Part("top", dome)]

        return in_long_frame(size, build)
    rx, ry = sx / 2, sy / 2
    parts = [
        Part(
            "loaf",
            lathe(
                [
                    (0.84, z0),
                    (0.97, z0 + 0.16 * h),
                    (1.0, z0 + 0.3 * h),
                    (0.88, z0 + 0.66 * h),
                    (0.55, z0 + 0.9 * h),
                    (0.18, zt),
                ],
                rx,
                ry,
                center=(0, 0),
                hull_of_rings=False,
            ),
        )
    ]
    long_x = sx >= sy
    lmax = max(rx, ry)
    for i, f in enumerate((-0.4, 0.0, 0.4)):
        slash = ellipsoid((0, 0, 0), (0.2 * lmax, 0.04 * lmax, 0.03 * h), 4, 8)
        rot = _rot_z(0.9 if long_x else 0.9 + np.pi / 2)
        c = (f * rx, 0.0, 0.0) if long_x else (0.0, f * ry, 0.0)
        r_frac = np.hypot(c[0] / rx, c[1] / ry)
        z = z0 + h * (0.9 if r_frac < 0.2 else 0.8)
        parts.append(Part(f"score_{i}", slash.transformed(rot, (c[0], c[1], z))))
    return parts

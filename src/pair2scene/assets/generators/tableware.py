"""Tableware, bottles, utensils and cleaning things: small objects on counters and shelves.

Kitchen appliances live in ``appliances.py``, food in ``food.py``; the shared helpers
(``lathe``, ``beam``, ``rounded_outline`` ...) in ``shapes.py``.

Every generator builds convex parts in metres inside [-size/2, size/2] (+z up,
+y front, +x right). Round things fill the box with elliptic sections (radii
``size_x/2``, ``size_y/2``), so no generator has to assume a square footprint.

Hollow vessels (bowl, mug, cup, pot, pan, vase, the ladle's bowl) are a floor
disc plus a ring of wall sectors: each sector is a convex hexahedron swept
between two angles, so the cavity stays empty for placement and physics while
every part stays convex.

Orientation conventions used by this family (object front is +y):

- mug and pot handles lie along x (mug at +x, pot at both sides); a pan's long handle
  points along the box's longer horizontal side: +x, or +y in a box deeper than wide;
- kettle, spray bottle and soap pump point their spout / nozzle toward +y, a
  kettle's side handle is at -y;
- utensils (fork, knife, butter knife, spoon, spatula, ladle) lie with their
  length along y, the working end (tines, blade, bowl) at +y and the handle at
  -y. Flat utensils whose box is taller than wide (a knife resting on its
  spine, as some datasets store it) are built with the blade plane vertical.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence

import numpy as np

from pair2scene.assets.generators.shapes import (
    FINE_SEGMENTS,
    ROD_SEGMENTS,
    beam,
    box_handle,
    ellipse_arc,
    in_long_frame,
    lathe,
    rotate_parts,
    rounded_outline,
)
from pair2scene.assets.mesh import (
    Mesh,
    Part,
    box_between,
    cylinder,
    ellipsoid,
    frustum,
    hull,
    prism,
)
from pair2scene.assets.mesh import rod as _rod
from pair2scene.assets.registry import register
from pair2scene.scene.geometry import rot_y as _rot_y

SECTORS = 12
"""Wall sectors of a hollow vessel: round enough, and a modest part count (one part each)."""
FORK_ARCH = 0.4
"""Where along its handle (0 at the neck, 1 at the end) a fork's arch is highest."""
EDGE_RATIO = 1.2
"""A utensil box taller than this times its width holds the utensil on its edge."""
UPRIGHT_RATIO = 0.8
"""A scrub brush box taller than this times its footprint holds a standing (toilet) brush."""

# Hexahedron faces, counter-clockwise from outside, for corners in mesh.box's order
# (x-, y-, z- first). ``_sector`` maps x to the radial direction (inner -> outer), y to the
# sweep (angle a0 -> a1) and z to up: radial x sweep = +z, so the orientation holds.
_HEX_FACES = np.array(
    [
        [0, 2, 1], [0, 3, 2],
        [4, 5, 6], [4, 6, 7],
        [0, 1, 5], [0, 5, 4],
        [1, 2, 6], [1, 6, 5],
        [2, 3, 7], [2, 7, 6],
        [3, 0, 4], [3, 4, 7],
    ]
)  # fmt: skip


# -- small geometry helpers ---------------------------------------------------------------


def _frame(direction: np.ndarray) -> np.ndarray:
    """(3, 3) proper rotation whose third column is the unit ``direction`` (3,)."""
    d = direction / np.linalg.norm(direction)
    a = np.array([1.0, 0.0, 0.0]) if abs(d[0]) < 0.9 else np.array([0.0, 1.0, 0.0])
    e1 = np.cross(a, d)
    e1 /= np.linalg.norm(e1)
    return np.column_stack([e1, np.cross(d, e1), d])


def _sector(
    center: Sequence[float], rx: float, ry: float, quad: np.ndarray, a0: float, a1: float
) -> Mesh:
    """Convex hexahedron sweeping a radial cross-section between angles a0 < a1.

    quad : (4, 2) rows (r, z), counter-clockwise in the (r, z) plane: inner-low,
    outer-low, outer-high, inner-high; r is a fraction of the radii (rx, ry). All six
    faces are planar (chords between the two angles are parallel), so the piece is
    exactly convex."""
    d0 = np.array([rx * np.cos(a0), ry * np.sin(a0)])
    d1 = np.array([rx * np.cos(a1), ry * np.sin(a1)])
    order = ((0, d0), (1, d0), (1, d1), (0, d1), (3, d0), (2, d0), (2, d1), (3, d1))
    corners = [
        [center[0] + quad[k][0] * d[0], center[1] + quad[k][0] * d[1], quad[k][1]] for k, d in order
    ]
    return Mesh(np.array(corners), _HEX_FACES)


def _shell(
    prefix: str,
    center: Sequence[float],
    rx: float,
    ry: float,
    levels: Sequence[Sequence[float]],
    thickness: float,
    sectors: int = SECTORS,
) -> list[Part]:
    """A hollow wall of revolution as a ring of convex sectors per band.

    levels : (K, 2) rows (r_outer, z) of the outer profile, r a fraction of (rx, ry);
    thickness : wall thickness in metres (measured horizontally). Parts are named
    ``{prefix}_{band}_{sector}``."""
    t = thickness / min(rx, ry)
    a = np.linspace(0.0, 2.0 * np.pi, sectors + 1)
    parts = []
    for k in range(len(levels) - 1):
        (r0, z0), (r1, z1) = levels[k], levels[k + 1]
        quad = np.array([[r0 - t, z0], [r0, z0], [r1, z1], [r1 - t, z1]])
        for i in range(sectors):
            parts.append(Part(f"{prefix}_{k}_{i}", _sector(center, rx, ry, quad, a[i], a[i + 1])))
    return parts


def _ring(
    prefix: str,
    center: Sequence[float],
    rx: float,
    ry: float,
    quad: np.ndarray,
    sectors: int = SECTORS,
) -> list[Part]:
    """A ring of sectors sweeping one (4, 2) cross-section quad (see ``_sector``)."""
    a = np.linspace(0.0, 2.0 * np.pi, sectors + 1)
    return [
        Part(f"{prefix}_{i}", _sector(center, rx, ry, np.asarray(quad), a[i], a[i + 1]))
        for i in range(sectors)
    ]


def _disc(
    center: Sequence[float], rx: float, ry: float, z0: float, z1: float, segments: int = SECTORS
) -> Mesh:
    """Elliptic disc from z0 to z1 (its sides line up with a ``_shell`` of as many sectors)."""
    return frustum((center[0], center[1], z0), z1 - z0, (rx, ry), (rx, ry), segments)


def _extruded_hull(points: Sequence[Sequence[float]], z0: float, z1: float) -> Mesh:
    """Convex hull of a 2D outline (N, 2) extruded from z0 to z1 (outline order free)."""
    p = np.asarray(points, dtype=float)
    return hull(np.concatenate([np.c_[p, np.full(len(p), z0)], np.c_[p, np.full(len(p), z1)]]))


def _wall(rx: float, ry: float, frac: float = 0.06, lo: float = 0.002, hi: float = 0.015) -> float:
    """Wall thickness in metres for a vessel of radii rx, ry: ``frac`` of the smaller
    radius, clamped so tiny cups stay solid and big pots do not get slabs."""
    return float(np.clip(frac * min(rx, ry), lo, hi))


def _flat_utensil(
    size: np.ndarray, build: Callable[[float, float, float], list[Part]]
) -> list[Part]:
    """Call ``build(width, length, thickness)`` (width along x, length along y, lying flat)
    and turn the result onto its edge when the box is taller than wide."""
    sx, sy, sz = (float(v) for v in size)
    if sz > EDGE_RATIO * sx:
        # the build's width (x) becomes the box height (z), its thickness the box width
        return rotate_parts(build(sz, sy, sx), _rot_y(np.pi / 2))
    return build(sx, sy, sz)


# -- vessels ------------------------------------------------------------------------------
@register("bowl", variants=2)
def bowl(size, rng, style, support_heights):
    """A bowl, hollow: 0 round with a foot ring, 1 flared conical serving bowl."""
    sx, sy, h = (float(v) for v in size)
    rx, ry, z0, zt = sx / 2, sy / 2, -h / 2, h / 2
    c = (0.0, 0.0)
    t = _wall(rx, ry)
    floor_t = float(np.clip(0.08 * h, 0.002, 0.012))
    if style == 0:
        foot_h = 0.07 * h
        rb = rng.uniform(0.46, 0.52)
        zb = z0 + foot_h
        parts = [
            Part(
                "foot",
                frustum(
                    (0, 0, z0),
                    foot_h,
                    (0.85 * rb * rx, 0.85 * rb * ry),
                    (rb * rx, rb * ry),
                    SECTORS,
                ),
            ),
            Part("floor", _disc(c, rb * rx, rb * ry, zb, zb + floor_t)),
        ]
        mid = rng.uniform(0.84, 0.9)
        levels = [(rb, zb), (mid, zb + 0.42 * (zt - zb)), (1.0, zt)]
    else:
        rb = rng.uniform(0.55, 0.62)
        parts = [Part("floor", _disc(c, rb * rx, rb * ry, z0, z0 + floor_t))]
        levels = [(rb, z0), (1.0, zt)]
    return parts + _shell("wall", c, rx, ry, levels, t)


@register("cup", variants=2)
def cup(size, rng, style, support_heights):
    """A drinking cup or glass, hollow: 0 flared tumbler, 1 stemmed wine glass."""
    sx, sy, h = (float(v) for v in size)
    rx, ry, z0, zt = sx / 2, sy / 2, -h / 2, h / 2
    c = (0.0, 0.0)
    t = _wall(rx, ry, 0.07)
    if style == 0:
        rb = rng.uniform(0.74, 0.84)
        # thick glass bottom, as tumblers have
        floor_t = float(np.clip(0.1 * h, 0.004, 0.02))
        return [Part("floor", _disc(c, rb * rx, rb * ry, z0, z0 + floor_t))] + _shell(
            "wall", c, rx, ry, [(rb, z0), (1.0, zt)], t
        )
    foot_h = float(np.clip(0.03 * h, 0.002, 0.006))
    z_bowl = z0 + rng.uniform(0.4, 0.48) * h
    stem_r = 0.08 * min(rx, ry)
    rb = 0.5
    bowl_floor = 0.05 * h
    parts = [
        Part(
            "foot",
            frustum((0, 0, z0), foot_h, (0.8 * rx, 0.8 * ry), (0.7 * rx, 0.7 * ry), FINE_SEGMENTS),
        ),
        Part("stem", cylinder((0, 0, (z0 + z_bowl) / 2), stem_r, z_bowl - z0, ROD_SEGMENTS)),
        # radii in proportion at both ends: a circle-to-ellipse frustum has warped sides
        Part(
            "bowl_base",
            frustum(
                (0, 0, z_bowl - bowl_floor),
                bowl_floor,
                (0.16 * rx, 0.16 * ry),
                (rb * rx, rb * ry),
                SECTORS,
            ),
        ),
    ]
    levels = [(rb, z_bowl), (1.0, z_bowl + 0.5 * (zt - z_bowl)), (0.9, zt)]
    return parts + _shell("wall", c, rx, ry, levels, t)


@register("mug", variants=2)
def mug(size, rng, style, support_heights):
    """A mug, hollow, handle at +x: 0 straight with a rounded handle, 1 tapered with a
    square handle."""
    sx, sy, h = (float(v) for v in size)
    z0, zt = -h / 2, h / 2
    handle_w = float(np.clip(rng.uniform(0.24, 0.3) * sx, 0.01, 0.6 * sy))
    rx, ry = (sx - handle_w) / 2, sy / 2
    c = (-sx / 2 + rx, 0.0)
    t = _wall(rx, ry, 0.08, 0.002, 0.012)
    floor_t = float(np.clip(0.08 * h, 0.003, 0.015))
    rb = 1.0 if style == 0 else rng.uniform(0.8, 0.86)
    parts = [Part("floor", _disc(c, rb * rx, rb * ry, z0, z0 + floor_t))]
    parts += _shell("wall", c, rx, ry, [(rb, z0), (1.0, zt)], t)
    bar = float(np.clip(0.1 * h, 0.004, 0.015))
    width = float(np.clip(0.16 * sy, 0.006, 0.025))
    z_lo, z_hi = z0 + 0.2 * h, z0 + 0.84 * h
    # the handle starts inside the wall at its height so the two overlap, never gap
    r_at = rb + (1.0 - rb) * 0.5
    x_in = c[0] + (r_at - 0.6 * t / rx) * rx
    parts += box_handle(x_in, sx / 2, z_lo, z_hi, width, bar, rounded=style == 0)
    return parts


@register("plate", variants=2)
def plate(size, rng, style, support_heights):
    """A plate, shallow: flat base, floor and a rising rim. 0 dinner plate with a sloped
    rim, 1 soup plate with a deeper well and a flat wide rim."""
    sx, sy, h = (float(v) for v in size)
    rx, ry, z0 = sx / 2, sy / 2, -h / 2
    c = (0.0, 0.0)
    sectors = FINE_SEGMENTS  # a plate is seen mostly from above: its outline must look round
    foot_h = 0.2 * h
    zf = z0 + foot_h
    floor_t = 0.25 * h
    rw = rng.uniform(0.6, 0.66) if style == 0 else rng.uniform(0.48, 0.54)
    parts = [
        Part(
            "foot",
            frustum(
                (0, 0, z0),
                foot_h,
                (0.62 * rw * rx, 0.62 * rw * ry),
                (0.7 * rw * rx, 0.7 * rw * ry),
                sectors,
            ),
        ),
        Part("floor", _disc(c, rw * rx, rw * ry, zf, zf + floor_t, sectors)),
    ]
    if style == 0:
        quad = [[rw - 0.04, zf], [1.0, z0 + 0.75 * h], [1.0, h / 2], [rw - 0.04, zf + floor_t]]
        return parts + _ring("rim", c, rx, ry, np.array(quad), sectors)
    r_mid = rw + 0.12
    well = [[rw - 0.04, zf], [r_mid, z0 + 0.72 * h], [r_mid, h / 2], [rw - 0.04, zf + floor_t]]
    flat = [
        [r_mid - 0.02, z0 + 0.72 * h],
        [1.0, z0 + 0.78 * h],
        [1.0, h / 2],
        [r_mid - 0.02, h / 2],
    ]
    return (
        parts
        + _ring("well", c, rx, ry, np.array(well), sectors)
        + _ring("rim", c, rx, ry, np.array(flat), sectors)
    )


@register("pot", variants=2)
def pot(size, rng, style, support_heights):
    """A cooking pot, hollow, with two handles at -x and +x: 0 tall stockpot with loop
    handles, 1 low casserole with tab handles and a rounded bottom edge."""
    sx, sy, h = (float(v) for v in size)
    z0, zt = -h / 2, h / 2
    hx = float(np.clip(rng.uniform(0.1, 0.13) * sx, 0.012, 0.07))
    rx, ry = sx / 2 - hx, sy / 2
    c = (0.0, 0.0)
    t = _wall(rx, ry, 0.04, 0.002, 0.008)
    floor_t = float(np.clip(0.05 * h, 0.003, 0.01))
    bar = float(np.clip(0.07 * h, 0.004, 0.015))
    if style == 0:
        parts = [Part("floor", _disc(c, rx, ry, z0, z0 + floor_t))]
        parts += _shell("wall", c, rx, ry, [(1.0, z0), (1.0, zt - 0.06 * h), (1.03, zt)], t)
        zh = zt - 0.2 * h
        span = float(np.clip(0.5 * ry, 0.02, 0.1))
        for side, name in ((1.0, "right"), (-1.0, "left")):
            x_in, x_out = side * (rx - t / 2), side * sx / 2
            lo, hi = min(x_in, x_out), max(x_in, x_out)
            parts += [
                Part(
                    f"handle_{name}_arm_0",
                    box_between((lo, span / 2 - bar, zh - bar), (hi, span / 2, zh)),
                ),
                Part(
                    f"handle_{name}_arm_1",
                    box_between((lo, -span / 2, zh - bar), (hi, -span / 2 + bar, zh)),
                ),
                Part(
                    f"handle_{name}_grip",
                    box_between(
                        (hi - bar if side > 0 else lo, -span / 2, zh - bar),
                        (hi if side > 0 else lo + bar, span / 2, zh),
                    ),
                ),
            ]
        return parts
    rb = 0.88
    parts = [Part("floor", _disc(c, rb * rx, rb * ry, z0, z0 + floor_t))]
    parts += _shell("wall", c, rx, ry, [(rb, z0), (1.0, z0 + 0.18 * h), (1.0, zt)], t)
    zh = zt - 0.12 * h
    span = float(np.clip(0.7 * ry, 0.03, 0.14))
    for side, name in ((1.0, "right"), (-1.0, "left")):
        x_in, x_out = side * (rx - t / 2), side * sx / 2
        parts.append(
            Part(
                f"handle_{name}",
                _extruded_hull(
                    [
                        (x_in, -span / 2),
                        (x_in, span / 2),
                        (x_out, 0.3 * span),
                        (x_out, -0.3 * span),
                    ],
                    zh - bar,
                    zh,
                ),
            )
        )
    return parts


@register("pan", variants=2)
def pan(size, rng, style, support_heights):
    """A frying pan, hollow, its long handle along the longer horizontal side: toward +x,
    or toward +y in a box deeper than wide (as AI2-THOR stores pans). 0 flared skillet
    with a flat handle, 1 round-sided pan with a round handle."""
    return in_long_frame(size, lambda length, w, h, turned: _pan(length, w, h, rng, style))


def _pan(sx, sy, h, rng, style):
    """A pan with its handle toward +x in a box (sx, sy, h)."""
    z0, zt = -h / 2, h / 2
    handle_len = rng.uniform(0.4, 0.45) * sx
    rx, ry = (sx - handle_len) / 2, sy / 2
    c = (-sx / 2 + rx, 0.0)
    t = _wall(rx, ry, 0.03, 0.002, 0.006)
    body_h = rng.uniform(0.58, 0.66) * h
    zb = z0 + body_h
    floor_t = float(np.clip(0.12 * body_h, 0.002, 0.008))
    grip = float(np.clip(0.09 * sy, 0.012, 0.035))
    thick = float(np.clip(0.15 * h, 0.005, 0.016))
    x_rim = c[0] + rx - t
    if style == 0:
        rb = rng.uniform(0.76, 0.82)
        parts = [Part("floor", _disc(c, rb * rx, rb * ry, z0, z0 + floor_t))]
        parts += _shell("wall", c, rx, ry, [(rb, z0), (1.0, zb)], t)
        x_mid = x_rim + 0.22 * handle_len
        parts += [
            Part(
                "handle_neck",
                beam(
                    (x_rim - t, 0, zb - thick / 2),
                    (x_mid, 0, zb + 0.2 * (zt - zb)),
                    0.6 * grip,
                    thick,
                ),
            ),
            Part(
                "handle",
                beam(
                    (x_mid - thick / 2, 0, zb + 0.2 * (zt - zb)),
                    (sx / 2, 0, zt - thick / 2),
                    grip,
                    thick,
                ),
            ),
        ]
        return parts
    rb = rng.uniform(0.7, 0.76)
    parts = [Part("floor", _disc(c, rb * rx, rb * ry, z0, z0 + floor_t))]
    parts += _shell("wall", c, rx, ry, [(rb, z0), (0.94, z0 + 0.45 * body_h), (1.0, zb)], t)
    r = float(np.clip(0.035 * sy, 0.004, 0.012))  # a round grip, thicker than the flat one
    parts += [
        Part(
            "handle_neck",
            _rod((x_rim - t, 0, zb - r), (x_rim + 0.15 * handle_len, 0, zb), 0.7 * r, 0.8 * r),
        ),
        Part(
            "handle", _rod((x_rim + 0.14 * handle_len, 0, zb), (sx / 2 - r, 0, zt - r), r, 1.15 * r)
        ),
        Part("handle_end", ellipsoid((sx / 2 - r, 0, zt - r), 1.15 * r, 4, ROD_SEGMENTS)),
    ]
    return parts


@register("kettle", variants=2)
def kettle(size, rng, style, support_heights):
    """A kettle, spout toward +y: 0 stovetop kettle with an arched top handle, 1 electric
    jug kettle on a base with a side handle at -y."""
    sx, sy, h = (float(v) for v in size)
    z0, zt = -h / 2, h / 2
    rx = sx / 2
    if style == 0:
        spout_len = rng.uniform(0.2, 0.26) * sy
        ry = (sy - spout_len) / 2
        cy = -sy / 2 + ry
        hb = rng.uniform(0.66, 0.72) * h
        zb = z0 + hb
        profile = [(0.9, z0), (1.0, z0 + 0.3 * hb), (0.86, z0 + 0.72 * hb), (0.42, zb)]
        parts = [
            Part("body", lathe(profile, rx, ry, center=(0, cy), hull_of_rings=False)),
            Part(
                "lid_knob",
                lathe(
                    [(1.0, zb - 0.01 * h), (1.0, zb + 0.05 * h), (0.6, zb + 0.08 * h)],
                    0.12 * rx,
                    0.12 * ry,
                    ROD_SEGMENTS,
                    center=(0, cy),
                    hull_of_rings=False,
                ),
            ),
        ]
        r0 = 0.16 * min(rx, ry)
        parts.append(
            Part(
                "spout",
                _rod(
                    (0, cy + 0.7 * ry, z0 + 0.3 * hb),
                    (0, sy / 2 - 0.05 * r0, z0 + 0.82 * hb),
                    r0,
                    0.45 * r0,
                ),
            )
        )
        bar = float(np.clip(0.07 * h, 0.006, 0.02))
        w = float(np.clip(0.12 * sx, 0.01, 0.03))
        yb, yt = 0.34 * ry, 0.42 * ry
        parts += [
            Part(
                "handle_post_back",
                beam(
                    (0, cy - yb, zb - 0.06 * hb), (0, cy - yt, zt - bar / 2), w, bar, side=(1, 0, 0)
                ),
            ),
            Part(
                "handle_post_front",
                beam(
                    (0, cy + yb, zb - 0.06 * hb), (0, cy + yt, zt - bar / 2), w, bar, side=(1, 0, 0)
                ),
            ),
            Part(
                "handle",
                box_between((-w / 2, cy - yt - bar / 2, zt - bar), (w / 2, cy + yt + bar / 2, zt)),
            ),
        ]
        return parts
    handle_len = rng.uniform(0.18, 0.22) * sy
    spout_len = 0.1 * sy
    ry = (sy - handle_len - spout_len) / 2
    cy = -sy / 2 + handle_len + ry
    base_h = 0.07 * h
    zb = zt - 0.04 * h
    top = rng.uniform(0.84, 0.9)
    parts = [
        Part("base", frustum((0, cy, z0), base_h, (1.02 * rx, 1.02 * ry), (rx, ry), FINE_SEGMENTS)),
        Part(
            "body",
            lathe(
                [(0.98, z0 + base_h), (1.0, z0 + 0.4 * h), (top, zb)],
                rx,
                ry,
                center=(0, cy),
                hull_of_rings=False,
            ),
        ),
        Part(
            "lid",
            lathe(
                [(1.0, zb - 0.01 * h), (1.0, zb + 0.02 * h), (0.4, zt)],
                0.8 * top * rx,
                0.8 * top * ry,
                center=(0, cy),
                hull_of_rings=False,
            ),
        ),
    ]
    ys = cy + ry * top
    parts.append(
        Part(
            "spout",
            hull(
                [
                    (-0.3 * rx, ys - 0.12 * ry, zb),
                    (0.3 * rx, ys - 0.12 * ry, zb),
                    (-0.22 * rx, ys - 0.05 * ry, zb - 0.18 * h),
                    (0.22 * rx, ys - 0.05 * ry, zb - 0.18 * h),
                    (-0.1 * rx, sy / 2, zb + 0.01 * h),
                    (0.1 * rx, sy / 2, zb + 0.01 * h),
                ]
            ),
        )
    )
    bar = float(np.clip(0.08 * h, 0.008, 0.025))
    w = float(np.clip(0.2 * sx, 0.012, 0.035))
    y_in, y_out = cy - 0.85 * ry, -sy / 2
    z_hi, z_lo = zb - 0.06 * h, z0 + 0.3 * h
    parts += [
        Part("handle_top", box_between((-w / 2, y_out, z_hi - bar), (w / 2, y_in, z_hi))),
        Part("handle_grip", box_between((-w / 2, y_out, z_lo), (w / 2, y_out + bar, z_hi))),
        Part("handle_bottom", box_between((-w / 2, y_out, z_lo), (w / 2, y_in, z_lo + bar))),
    ]
    return parts


@register("vase", variants=2)
def vase(size, rng, style, support_heights):
    """A vase, hollow: 0 round belly with a neck and a flared lip, 1 tall tapered
    cylinder with a thick base."""
    sx, sy, h = (float(v) for v in size)
    rx, ry, z0, zt = sx / 2, sy / 2, -h / 2, h / 2
    c = (0.0, 0.0)
    t = _wall(rx, ry, 0.06, 0.002, 0.012)
    if style == 0:
        rb = rng.uniform(0.55, 0.62)
        neck = rng.uniform(0.48, 0.56)
        levels = [(rb, z0), (1.0, z0 + 0.36 * h), (neck, z0 + 0.78 * h), (0.78, zt)]
        floor_t = float(np.clip(0.05 * h, 0.003, 0.015))
        return [Part("floor", _disc(c, rb * rx, rb * ry, z0, z0 + floor_t))] + _shell(
            "wall", c, rx, ry, levels, t
        )
    rb = rng.uniform(0.72, 0.8)
    base_h = 0.12 * h
    levels = [(rb, z0), (0.86, z0 + 0.55 * h), (1.0, zt)]
    return [Part("base", _disc(c, rb * rx, rb * ry, z0, z0 + base_h))] + _shell(
        "wall", c, rx, ry, levels, t
    )


# -- bottles and dispensers ---------------------------------------------------------------
def _octagon(rx: float, ry: float, chamfer: float, cx: float = 0.0, cy: float = 0.0) -> np.ndarray:
    """(8, 2) rectangle outline with chamfered corners (chamfer as a fraction of the radii)."""
    a, b = rx * (1 - chamfer), ry * (1 - chamfer)
    return np.array(
        [(rx, -b), (rx, b), (a, ry), (-a, ry), (-rx, b), (-rx, -b), (-a, -ry), (a, -ry)]
    ) + (cx, cy)


def _neck_and_cap(
    rx: float,
    ry: float,
    z_neck: float,
    z_cap: float,
    zt: float,
    neck: float,
    cap: float,
) -> list[Part]:
    """Bottle neck (fraction ``neck`` of the radii) from z_neck to z_cap, cap to zt."""
    return [
        Part(
            "neck",
            _disc(
                (0, 0), neck * rx, neck * ry, z_neck, z_cap + 0.01 * (zt - z_neck), FINE_SEGMENTS
            ),
        ),
        Part("cap", _disc((0, 0), cap * rx, cap * ry, z_cap, zt, FINE_SEGMENTS)),
    ]


@register("bottle", variants=2)
def bottle(size, rng, style, support_heights):
    """A bottle with a screw cap: 0 round with a sloping shoulder, 1 square-ish with
    chamfered edges and a short shoulder."""
    sx, sy, h = (float(v) for v in size)
    rx, ry, z0, zt = sx / 2, sy / 2, -h / 2, h / 2
    neck = rng.uniform(0.3, 0.36)
    z_cap = zt - 0.08 * h
    if style == 0:
        z_sh = z0 + rng.uniform(0.55, 0.62) * h
        z_neck = z0 + 0.82 * h
        body = lathe(
            [
                (0.9, z0),
                (1.0, z0 + 0.03 * h),
                (1.0, z_sh),
                (0.75, z_sh + 0.55 * (z_neck - z_sh)),
                (neck, z_neck),
            ],
            rx,
            ry,
            center=(0, 0),
            hull_of_rings=False,
        )
        parts = [Part("body", body)]
    else:
        z_sh = z0 + rng.uniform(0.68, 0.72) * h
        z_neck = z0 + 0.8 * h
        outline = _octagon(rx, ry, 0.3)
        top = ellipse_arc(0, 0, neck * rx, neck * ry)
        parts = [
            Part("body", prism(outline, z0, z_sh)),
            Part(
                "shoulder",
                hull(
                    np.concatenate(
                        [
                            np.c_[0.97 * outline, np.full(8, z_sh)],
                            np.c_[top, np.full(FINE_SEGMENTS, z_neck)],
                        ]
                    )
                ),
            ),
        ]
    return parts + _neck_and_cap(rx, ry, z_neck - 0.01 * h, z_cap, zt, neck, neck + 0.05)


@register("wine_bottle", variants=2)
def wine_bottle(size, rng, style, support_heights):
    """A wine bottle with a long neck and a foil capsule: 0 high-shouldered (Bordeaux),
    1 sloping-shouldered (Burgundy)."""
    sx, sy, h = (float(v) for v in size)
    rx, ry, z0, zt = sx / 2, sy / 2, -h / 2, h / 2
    neck = rng.uniform(0.3, 0.34)
    if style == 0:
        z_sh = z0 + rng.uniform(0.58, 0.62) * h
        z_neck = z_sh + 0.1 * h
        profile = [
            (0.95, z0),
            (1.0, z0 + 0.02 * h),
            (1.0, z_sh),
            (0.88, z_sh + 0.035 * h),
            (0.55, z_sh + 0.075 * h),
            (neck, z_neck),
        ]
    else:
        z_sh = z0 + rng.uniform(0.45, 0.5) * h
        z_neck = z_sh + 0.25 * h
        profile = [
            (0.95, z0),
            (1.0, z0 + 0.02 * h),
            (1.0, z_sh),
            (0.9, z_sh + 0.09 * h),
            (0.62, z_sh + 0.18 * h),
            (neck, z_neck),
        ]
    z_caps = zt - 0.13 * h
    return [
        Part("body", lathe(profile, rx, ry, center=(0, 0), hull_of_rings=False)),
        Part(
            "neck",
            lathe(
                [(1.0, z_neck - 0.01 * h), (0.92, z_caps + 0.01 * h)],
                neck * rx,
                neck * ry,
                center=(0, 0),
                hull_of_rings=False,
            ),
        ),
        Part(
            "capsule",
            lathe(
                [(0.98, z_caps), (1.06, zt - 0.025 * h), (1.0, zt)],
                neck * rx,
                neck * ry,
                center=(0, 0),
                hull_of_rings=False,
            ),
        ),
    ]


@register("spray_bottle", variants=2)
def spray_bottle(size, rng, style, support_heights):
    """A spray bottle with a trigger head, nozzle toward +y: 0 round body, 1 flat
    chamfered body with a waist-high shoulder."""
    sx, sy, h = (float(v) for v in size)
    z0, zt = -h / 2, h / 2
    rx = sx / 2
    ry = rng.uniform(0.34, 0.38) * sy
    cy = -sy / 2 + ry
    z_sh = z0 + rng.uniform(0.58, 0.64) * h
    z_col = z0 + 0.7 * h
    if style == 0:
        parts = [
            Part(
                "body",
                lathe(
                    [(0.94, z0), (1.0, z0 + 0.03 * h), (1.0, z_sh), (0.45, z_col)],
                    rx,
                    ry,
                    center=(0, cy),
                    hull_of_rings=False,
                ),
            )
        ]
    else:
        outline = _octagon(rx, ry, 0.35, 0.0, cy)
        parts = [
            Part("body", prism(outline, z0, z_sh)),
            Part(
                "shoulder",
                hull(
                    np.concatenate(
                        [
                            np.c_[outline, np.full(8, z_sh)],
                            np.c_[
                                ellipse_arc(0, cy, 0.45 * rx, 0.45 * ry),
                                np.full(FINE_SEGMENTS, z_col),
                            ],
                        ]
                    )
                ),
            ),
        ]
    collar_r = 0.4
    z_head = z0 + 0.76 * h
    parts.append(
        Part(
            "collar",
            _disc((0, cy), collar_r * rx, collar_r * ry, z_col - 0.01 * h, z_head, FINE_SEGMENTS),
        )
    )
    hw = 0.3 * sx
    y_back = cy - 0.5 * ry
    y_front = sy / 2 - 0.07 * sy
    parts.append(
        Part(
            "head",
            hull(
                [
                    (-hw, y_back, z_head),
                    (hw, y_back, z_head),
                    (-hw, y_back, zt),
                    (hw, y_back, zt),
                    (-0.8 * hw, y_front, zt - 0.08 * h),
                    (0.8 * hw, y_front, zt - 0.08 * h),
                    (-0.8 * hw, y_front, zt - 0.02 * h),
                    (0.8 * hw, y_front, zt - 0.02 * h),
                    (-0.9 * hw, cy + 0.3 * ry, z_head),
                    (0.9 * hw, cy + 0.3 * ry, z_head),
                ]
            ),
        )
    )
    nr = 0.035 * h
    parts.append(
        Part(
            "nozzle",
            _rod((0, y_front - 0.01 * sy, zt - 0.05 * h), (0, sy / 2, zt - 0.05 * h), nr, 0.8 * nr),
        )
    )
    y_tr = y_front - 0.18 * sy
    parts.append(
        Part(
            "trigger",
            beam(
                (0, y_tr, zt - 0.09 * h),
                (0, y_tr + 0.06 * sy, zt - 0.24 * h),
                0.4 * sx,
                0.05 * sy,
                side=(1, 0, 0),
            ),
        )
    )
    return parts


@register("soap_bottle", variants=2)
def soap_bottle(size, rng, style, support_heights):
    """A liquid soap bottle with a pump, nozzle toward +y: 0 round body, 1 rectangular
    body."""
    sx, sy, h = (float(v) for v in size)
    z0, zt = -h / 2, h / 2
    rx = sx / 2
    nozzle = rng.uniform(0.18, 0.24) * sy
    ry = (sy - nozzle) / 2
    cy = -sy / 2 + ry
    z_sh = z0 + rng.uniform(0.6, 0.66) * h
    z_col = z0 + 0.72 * h
    if style == 0:
        parts = [
            Part(
                "body",
                lathe(
                    [
                        (0.92, z0),
                        (1.0, z0 + 0.05 * h),
                        (1.0, z_sh),
                        (0.85, z_sh + 0.05 * h),
                        (0.35, z_col),
                    ],
                    rx,
                    ry,
                    center=(0, cy),
                    hull_of_rings=False,
                ),
            )
        ]
    else:
        outline = _octagon(rx, ry, 0.12, 0.0, cy)
        parts = [
            Part("body", prism(outline, z0, z_sh)),
            Part(
                "shoulder",
                hull(
                    np.concatenate(
                        [
                            np.c_[outline, np.full(8, z_sh)],
                            np.c_[
                                ellipse_arc(0, cy, 0.35 * rx, 0.35 * ry),
                                np.full(FINE_SEGMENTS, z_col),
                            ],
                        ]
                    )
                ),
            ),
        ]
    cr = min(0.3 * rx, 0.3 * ry)
    z_col_top = z0 + 0.78 * h
    z_head = zt - 0.07 * h
    parts += [
        Part(
            "collar",
            cylinder(
                (0, cy, (z_col + z_col_top) / 2 - 0.005 * h),
                cr,
                z_col_top - z_col + 0.01 * h,
                FINE_SEGMENTS,
            ),
        ),
        Part(
            "stem",
            cylinder(
                (0, cy, (z_col_top + z_head) / 2),
                0.35 * cr,
                z_head - z_col_top + 0.01 * h,
                ROD_SEGMENTS,
            ),
        ),
        Part(
            "pump_head",
            lathe(
                [(1.0, z_head), (1.0, zt - 0.02 * h), (0.7, zt)],
                1.1 * cr,
                1.1 * cr,
                FINE_SEGMENTS,
                center=(0, cy),
                hull_of_rings=False,
            ),
        ),
        Part(
            "nozzle",
            beam(
                (0, cy, zt - 0.035 * h),
                (0, sy / 2, zt - 0.045 * h),
                0.6 * cr,
                0.03 * h,
                side=(1, 0, 0),
            ),
        ),
    ]
    return parts


@register("salt_shaker", variants=2)
def salt_shaker(size, rng, style, support_heights):
    """A salt shaker: 0 straight glass cylinder with a domed metal cap, 1 hexagonal
    faceted body with a flat cap."""
    sx, sy, h = (float(v) for v in size)
    rx, ry, z0, zt = sx / 2, sy / 2, -h / 2, h / 2
    z_cap = z0 + rng.uniform(0.66, 0.72) * h
    if style == 0:
        return [
            Part(
                "body",
                lathe(
                    [(0.9, z0), (0.93, z0 + 0.03 * h), (0.93, z_cap)],
                    rx,
                    ry,
                    center=(0, 0),
                    hull_of_rings=False,
                ),
            ),
            Part(
                "cap",
                lathe(
                    [
                        (1.0, z_cap - 0.02 * h),
                        (1.0, z_cap + 0.12 * h),
                        (0.85, zt - 0.08 * h),
                        (0.5, zt),
                    ],
                    rx,
                    ry,
                    center=(0, 0),
                    hull_of_rings=False,
                ),
            ),
        ]
    hexagon = ellipse_arc(0, 0, rx, ry, 6, np.pi / 6, 2 * np.pi + np.pi / 6)
    return [
        Part("body", prism(hexagon, z0, z_cap)),
        Part(
            "cap",
            _disc((0, 0), 0.82 * rx, 0.82 * ry, z_cap - 0.02 * h, zt - 0.04 * h, FINE_SEGMENTS),
        ),
        Part(
            "cap_top",
            lathe(
                [(1.0, zt - 0.045 * h), (0.85, zt)],
                0.82 * rx,
                0.82 * ry,
                center=(0, 0),
                hull_of_rings=False,
            ),
        ),
    ]


@register("pepper_shaker", variants=2)
def pepper_shaker(size, rng, style, support_heights):
    """A pepper shaker: 0 tall waisted pepper mill with a knob, 1 round-bellied shaker
    with a conical cap."""
    sx, sy, h = (float(v) for v in size)
    rx, ry, z0, zt = sx / 2, sy / 2, -h / 2, h / 2
    if style == 0:
        waist = rng.uniform(0.5, 0.58)
        z1, z2, z3 = z0 + 0.1 * h, z0 + 0.45 * h, z0 + 0.76 * h
        return [
            Part(
                "base",
                frustum((0, 0, z0), z1 - z0, (rx, ry), (0.82 * rx, 0.82 * ry), FINE_SEGMENTS),
            ),
            Part(
                "body_lower",
                frustum(
                    (0, 0, z1),
                    z2 - z1,
                    (0.82 * rx, 0.82 * ry),
                    (waist * rx, waist * ry),
                    FINE_SEGMENTS,
                ),
            ),
            Part(
                "body_upper",
                frustum(
                    (0, 0, z2),
                    z3 - z2,
                    (waist * rx, waist * ry),
                    (0.85 * rx, 0.85 * ry),
                    FINE_SEGMENTS,
                ),
            ),
            Part(
                "crown",
                lathe(
                    [(0.85, z3), (0.75, z0 + 0.86 * h), (0.3, z0 + 0.92 * h)],
                    rx,
                    ry,
                    center=(0, 0),
                    hull_of_rings=False,
                ),
            ),
            Part(
                "knob",
                ellipsoid((0, 0, z0 + 0.95 * h), (0.2 * rx, 0.2 * ry, 0.05 * h), 6, ROD_SEGMENTS),
            ),
        ]
    z_b = z0 + rng.uniform(0.66, 0.7) * h
    return [
        Part(
            "body",
            lathe(
                [
                    (0.6, z0),
                    (0.9, z0 + 0.12 * h),
                    (1.0, z0 + 0.35 * h),
                    (0.88, z0 + 0.56 * h),
                    (0.55, z_b),
                ],
                rx,
                ry,
                center=(0, 0),
                hull_of_rings=False,
            ),
        ),
        Part(
            "cap",
            lathe(
                [(0.58, z_b - 0.02 * h), (0.58, z_b + 0.08 * h), (0.12, zt)],
                rx,
                ry,
                center=(0, 0),
                hull_of_rings=False,
            ),
        ),
    ]


# -- utensils (lying flat, length along y, working end at +y) ----------------------------
def _taper(
    front: tuple[float, float, float, float],
    back: tuple[float, float, float, float],
    round_back: bool = False,
) -> Mesh:
    """A straight tapered slab (a utensil neck or handle), centred on x = 0.

    front, back : (y, z_bottom, width, thickness) of the two end sections; the back end
    is a half-disc when ``round_back``."""
    y, z, w, t = back
    if round_back:
        arc = ellipse_arc(0, y + w / 2, w / 2, w / 2, 7, np.pi, 2 * np.pi, endpoint=True)
        back_pts = [(x, yy, z) for x, yy in arc] + [(x, yy, z + t) for x, yy in arc]
    else:
        back_pts = [(sx * w / 2, y, zz) for sx in (-1, 1) for zz in (z, z + t)]
    y, z, w, t = front
    front_pts = [(sx * w / 2, y, zz) for sx in (-1, 1) for zz in (z, z + t)]
    return hull(front_pts + back_pts)


def _fork(w, length, t, rng, style):
    z0, zt = -t / 2, t / 2
    y0, yt = -length / 2, length / 2
    plate_t = float(np.clip(0.22 * t, 0.0012, 0.004))
    n = 4 if style == 0 else 3
    y_tines = yt - rng.uniform(0.2, 0.24) * length
    y_head = y_tines - 0.08 * length
    y_neck = y_head - 0.1 * length
    neck_w = 0.2 * w
    gap_frac = 0.7 if style == 0 else 1.0
    tw = w / (n + (n - 1) * gap_frac)
    parts = [
        Part(
            f"tine_{i}",
            box_between(
                (-w / 2 + i * tw * (1 + gap_frac), y_tines - 0.002, z0),
                (-w / 2 + i * tw * (1 + gap_frac) + tw, yt, z0 + plate_t),
            ),
        )
        for i in range(n)
    ]
    # The neck and handle arch over the table, highest at FORK_ARCH of the handle, and
    # the handle's end comes down onto it: the fork rests on its tines and the end of its
    # handle (raised to the box top at the end, the handle tipped it over its head: 11 of
    # 22 forks in 30 kitchens moved 2.7 cm in the simulation).
    z_neck = z0 + 0.6 * (t - plate_t)
    end_w = (0.55 if style == 0 else 0.42) * w
    y_peak = y_neck - FORK_ARCH * (y_neck - y0)
    peak_w = 0.8 * neck_w + FORK_ARCH * (end_w - 0.8 * neck_w)
    parts += [
        Part(
            "head",
            _extruded_hull(
                [(-w / 2, y_tines), (w / 2, y_tines), (neck_w / 2, y_head), (-neck_w / 2, y_head)],
                z0,
                z0 + plate_t,
            ),
        ),
        Part(
            "neck",
            _taper((y_head + 0.002, z0, neck_w, plate_t), (y_neck, z_neck, 0.8 * neck_w, plate_t)),
        ),
        Part(
            "handle_arch",
            _taper(
                (y_neck + 0.002, z_neck, 0.8 * neck_w, plate_t),
                (y_peak, zt - plate_t, peak_w, plate_t),
            ),
        ),
        Part(
            "handle",
            _taper(
                (y_peak + 0.002, zt - plate_t, peak_w, plate_t),
                (y0, z0, end_w, plate_t),
                round_back=style == 0,
            ),
        ),
    ]
    return parts


@register("fork", variants=2)
def fork(size, rng, style, support_heights):
    """A table fork lying flat, tines toward +y: 0 four tines and a rounded handle,
    1 three tines and a narrow square-ended handle."""
    return _flat_utensil(size, lambda w, length, t: _fork(w, length, t, rng, style))


def _knife(w, length, t, rng, style, butter):
    y0, yt = -length / 2, length / 2
    handle_len = (rng.uniform(0.5, 0.56) if butter else rng.uniform(0.36, 0.42)) * length
    yb = y0 + handle_len
    blade_t = float(np.clip(0.15 * t, 0.0008, 0.003))
    bz0, bz1 = -blade_t / 2, blade_t / 2
    lb = yt - yb
    if butter:
        bw = 0.85 * w
        # rounded blunt tip; the edge (-x) is straight, the blade widens a little to the tip
        tip = ellipse_arc(0, yt - bw / 2, bw / 2, bw / 2, 8, 0.0, np.pi, endpoint=True)
        blade = [(-bw / 2, yb), (0.3 * bw, yb), *tip.tolist()]
        handle_w = 0.8 * w
        hx = 0.0
    elif style == 0:
        # chef's knife: straight spine at +x, curved edge rising to the tip
        curve = ellipse_arc(w / 2, yb + 0.45 * lb, w, 0.55 * lb, 8, np.pi, np.pi / 2, endpoint=True)
        blade = [(w / 2, yb), (-w / 2, yb), *curve.tolist()]
        handle_w = 0.42 * w
        hx = w / 2 - handle_w / 2 - 0.1 * w
    else:
        # bread knife: parallel edges and a rounded tip
        tip = ellipse_arc(0, yt - w / 2, w / 2, w / 2, 8, 0.0, np.pi, endpoint=True)
        blade = [(-w / 2, yb), (w / 2, yb), *tip.tolist()]
        handle_w = 0.75 * w
        hx = 0.0
    parts = [Part("blade", _extruded_hull(blade, bz0, bz1))]
    ht = t if not butter else max(0.5 * t, 2 * blade_t)
    hz = (-t / 2, -t / 2 + ht) if butter else (-t / 2, t / 2)
    round_end = butter or style == 0
    outline = rounded_outline(
        hx - handle_w / 2,
        hx + handle_w / 2,
        y0,
        yb,
        (0.0, 0.0, 0.45 * handle_w, 0.45 * handle_w) if round_end else 0.15 * handle_w,
    )
    parts.append(Part("handle", prism(outline, *hz)))
    if butter and style == 1:
        # a bulb at the end of the handle, the classic table-knife look
        parts.append(
            Part(
                "handle_end",
                _extruded_hull(
                    ellipse_arc(0, y0 + 0.6 * w, w / 2 * 1.0, 0.6 * w, 12), hz[0], hz[1] + 0.3 * ht
                ),
            )
        )
    if not butter:
        parts.append(
            Part(
                "bolster",
                box_between(
                    (hx - 0.55 * handle_w, yb - 0.02 * length, -0.4 * t),
                    (hx + 0.55 * handle_w, yb + 0.01 * length, 0.4 * t),
                ),
            )
        )
    return parts


@register("knife", variants=2)
def knife(size, rng, style, support_heights):
    """A kitchen knife lying flat, blade toward +y: 0 chef's knife with a pointed curved
    blade, 1 bread knife with a straight blade and a rounded tip."""
    return _flat_utensil(size, lambda w, length, t: _knife(w, length, t, rng, style, False))


@register("butter_knife", variants=2)
def butter_knife(size, rng, style, support_heights):
    """A table (butter) knife lying flat, rounded blade toward +y: 0 plain handle,
    1 handle with a bulb end."""
    return _flat_utensil(size, lambda w, length, t: _knife(w, length, t, rng, style, True))


def _spoon(w, length, t, rng, style):
    z0, zt = -t / 2, t / 2
    y0, yt = -length / 2, length / 2
    plate_t = float(np.clip(0.2 * t, 0.0012, 0.004))
    if style == 0:
        bowl_len = rng.uniform(0.3, 0.34) * length
    else:
        bowl_len = min(1.15 * w, rng.uniform(0.24, 0.28) * length)
    by = yt - bowl_len / 2
    depth = rng.uniform(0.55, 0.65) * t
    bowl = lathe(
        [(0.45, z0), (0.8, z0 + 0.45 * depth), (1.0, z0 + depth)],
        w / 2,
        bowl_len / 2,
        center=(0, by),
        hull_of_rings=False,
    )
    neck_w = 0.18 * w
    y_bowl = by - 0.42 * bowl_len
    y_neck = y_bowl - 0.14 * length
    z_neck = z0 + 0.5 * (t - plate_t)
    return [
        Part("bowl", bowl),
        Part(
            "neck",
            _taper(
                (y_bowl, z0 + depth - plate_t, neck_w, plate_t),
                (y_neck, z_neck, 0.7 * neck_w, plate_t),
            ),
        ),
        Part(
            "handle",
            _taper(
                (y_neck + 0.002, z_neck, 0.7 * neck_w, plate_t),
                (y0, zt - plate_t, (0.5 if style == 0 else 0.38) * w, plate_t),
                round_back=True,
            ),
        ),
    ]


@register("spoon", variants=2)
def spoon(size, rng, style, support_heights):
    """A spoon lying flat, bowl toward +y: 0 tablespoon with an oval bowl, 1 soup spoon
    with a round bowl and a slimmer handle."""
    return _flat_utensil(size, lambda w, length, t: _spoon(w, length, t, rng, style))


def _spatula(w, length, t, rng, style):
    z0, zt = -t / 2, t / 2
    y0, yt = -length / 2, length / 2
    blade_t = float(np.clip(0.15 * t, 0.001, 0.004))
    blade_len = rng.uniform(0.3, 0.34) * length
    yb = yt - blade_len
    parts = []
    if style == 0:
        # slotted turner: rails and bars with open slots between them
        n = 5
        sw = w / (2 * n - 1)
        bar = 0.16 * blade_len
        parts.append(
            Part(
                "blade_back",
                _extruded_hull(
                    [
                        (-0.85 * w / 2, yb),
                        (0.85 * w / 2, yb),
                        (w / 2, yb + bar),
                        (-w / 2, yb + bar),
                    ],
                    z0,
                    z0 + blade_t,
                ),
            )
        )
        parts.append(
            Part(
                "blade_front", box_between((-w / 2, yt - 0.6 * bar, z0), (w / 2, yt, z0 + blade_t))
            )
        )
        for i in range(n):
            x = -w / 2 + 2 * i * sw
            parts.append(
                Part(
                    f"blade_strip_{i}",
                    box_between(
                        (x, yb + bar - 0.001, z0), (x + sw, yt - 0.6 * bar + 0.001, z0 + blade_t)
                    ),
                )
            )
    else:
        outline = rounded_outline(
            -w / 2, w / 2, yb + 0.2 * blade_len, yt, (0.25 * w, 0.25 * w, 0.0, 0.0)
        )
        outline = np.vstack([outline, [(-0.3 * w, yb), (0.3 * w, yb)]])
        parts.append(Part("blade", _extruded_hull(outline, z0, z0 + blade_t)))
    neck_w = 0.16 * w
    y_neck = yb - 0.12 * length
    handle_t = float(np.clip(0.35 * t, 0.002, 0.012))
    z_neck = zt - handle_t - 0.2 * (t - handle_t - blade_t)
    y_front = yb + 0.01 * length
    parts += [
        Part(
            "neck",
            _taper((y_front, z0, 2 * neck_w, blade_t), (y_neck, z_neck, neck_w, handle_t)),
        ),
        Part(
            "handle",
            _taper(
                (y_neck + 0.002, z_neck, neck_w, handle_t),
                (y0, zt - handle_t, 0.32 * w, handle_t),
                round_back=True,
            ),
        ),
    ]
    return parts


@register("spatula", variants=2)
def spatula(size, rng, style, support_heights):
    """A spatula (turner) lying flat, blade toward +y: 0 slotted blade, 1 solid blade
    with rounded corners."""
    return _flat_utensil(size, lambda w, length, t: _spatula(w, length, t, rng, style))


@register("ladle", variants=2)
def ladle(size, rng, style, support_heights):
    """A ladle lying flat, hollow bowl toward +y, handle toward -y ending in a hook:
    0 round deep bowl, 1 shallow oval bowl with a longer hook."""
    sx, sy, h = (float(v) for v in size)
    z0, zt = -h / 2, h / 2
    y0, yt = -sy / 2, sy / 2
    rx = sx / 2
    ry = min(rx, 0.2 * sy) if style == 0 else min(1.25 * rx, 0.26 * sy)
    cy = yt - ry
    t = _wall(rx, ry, 0.06, 0.0012, 0.004)
    levels = (
        [(0.4, z0), (0.82, z0 + 0.42 * h), (1.0, zt)]
        if style == 0
        else [(0.55, z0), (0.9, z0 + 0.45 * h), (1.0, zt)]
    )
    parts = [
        Part("bowl_floor", _disc((0, cy), levels[0][0] * rx, levels[0][0] * ry, z0, z0 + 2 * t, 10))
    ]
    parts += _shell("bowl_wall", (0, cy), rx, ry, levels, t, sectors=10)
    bar = float(np.clip(0.12 * h, 0.002, 0.008))
    w = float(np.clip(0.18 * sx, 0.006, 0.025))
    y_rim = cy - 0.92 * ry
    hook = (0.06 if style == 0 else 0.1) * sy
    z_end = z0 + (0.45 if style == 0 else 0.3) * h
    parts += [
        Part(
            "handle", beam((0, y_rim, zt - bar / 2), (0, y0 + hook, z_end), w, bar, side=(1, 0, 0))
        ),
        Part(
            "hook",
            beam(
                (0, y0 + hook + bar / 2, z_end),
                (0, y0 + bar / 2, z_end - 0.25 * h),
                w,
                bar,
                side=(1, 0, 0),
            ),
        ),
    ]
    return parts


# -- cleaning, household ------------------------------------------------------------------
@register("aluminum_foil", variants=2)
def aluminum_foil(size, rng, style, support_heights):
    """A roll of aluminium foil in its carton, along the longer side: 0 open lid showing
    the roll, 1 closed lid with a sheet of foil hanging out at the front."""

    def build(length, w, h, turned):
        z0, zt = -h / 2, h / 2
        tw = float(np.clip(0.04 * w, 0.0008, 0.003))
        x0, x1, y0, y1 = -length / 2, length / 2, -w / 2, w / 2
        if style == 0:
            hc = rng.uniform(0.58, 0.64) * h
            zc = z0 + hc
            parts = [
                Part("carton_bottom", box_between((x0, y0, z0), (x1, y1, z0 + tw))),
                Part("carton_front", box_between((x0, y1 - tw, z0), (x1, y1, zc))),
                Part("carton_back", box_between((x0, y0, z0), (x1, y0 + tw, zc))),
                Part("carton_end_0", box_between((x0, y0, z0), (x0 + tw, y1, zc))),
                Part("carton_end_1", box_between((x1 - tw, y0, z0), (x1, y1, zc))),
            ]
            rr = 0.42 * min(w - 2 * tw, hc)
            parts.append(
                Part(
                    "roll",
                    _rod(
                        (x0 + 1.5 * tw, 0, z0 + tw + rr),
                        (x1 - 1.5 * tw, 0, z0 + tw + rr),
                        rr,
                        rr,
                        12,
                    ),
                )
            )
            # lid hinged on the back top edge, opened until it reaches the box top
            open_ang = float(np.arcsin(np.clip((zt - zc) / w, 0.0, 1.0)))
            tip = np.array([0.0, y0 + w * np.cos(open_ang), zc + w * np.sin(open_ang)])
            parts.append(
                Part(
                    "lid",
                    beam(
                        (0.0, y0 + tw / 2, zc),
                        (0.0, tip[1], tip[2] - tw / 2),
                        length,
                        tw,
                        side=(1, 0, 0),
                    ),
                )
            )
            return parts
        lip = 0.35 * h
        return [
            Part("carton", box_between((x0, y0, z0), (x1, y1 - tw, zt - tw))),
            Part("lid", box_between((x0, y0, zt - tw), (x1, y1, zt))),
            Part("lid_flap", box_between((x0, y1 - tw, zt - lip), (x1, y1, zt))),
            Part(
                "foil_sheet",
                beam(
                    (0.0, y1 - 0.5 * tw, zt - lip),
                    (0.0, y1, z0 + 0.12 * h),
                    0.9 * length,
                    0.5 * tw,
                    side=(1, 0, 0),
                ),
            ),
        ]

    return in_long_frame(size, build)


@register("dish_sponge", variants=2)
def dish_sponge(size, rng, style, support_heights):
    """A kitchen sponge with a scouring layer on top: 0 rectangular block, 1 waisted
    (grip) sponge."""
    sx, sy, h = (float(v) for v in size)
    z0, zt = -h / 2, h / 2
    zs = z0 + rng.uniform(0.62, 0.7) * h
    r = 0.12 * min(sx, sy)
    if style == 0:
        return [
            Part("sponge", prism(rounded_outline(-sx / 2, sx / 2, -sy / 2, sy / 2, r), z0, zs)),
            Part("scourer", prism(rounded_outline(-sx / 2, sx / 2, -sy / 2, sy / 2, r), zs, zt)),
        ]
    along_y = sy >= sx
    lx, ly = (sx / 2, sy / 2) if along_y else (sy / 2, sx / 2)  # across, along
    lobe = 0.36 * ly
    pieces = {
        "sponge_end_0": (-lx, lx, -ly, -ly + lobe, (0, 0, r, r)),
        "sponge_middle": (-0.78 * lx, 0.78 * lx, -ly + lobe - 0.001, ly - lobe + 0.001, 0.0),
        "sponge_end_1": (-lx, lx, ly - lobe, ly, (r, r, 0, 0)),
    }
    parts = []
    for name, (a0, a1, b0, b1, rad) in pieces.items():
        outline = rounded_outline(b0, b1, a0, a1, rad)[:, ::-1]  # along y: swap to (x, y)
        if not along_y:
            outline = outline[:, ::-1]
        parts.append(Part(name, prism(outline, z0, zs)))
    scour = rounded_outline(-0.78 * lx, 0.78 * lx, -ly, ly, 0.5 * r)
    parts.append(Part("scourer", prism(scour if along_y else scour[:, ::-1], zs, zt)))
    return parts


@register("soap_bar", variants=2)
def soap_bar(size, rng, style, support_heights):
    """A bar of soap: 0 rounded rectangular pillow, 1 oval pebble."""
    sx, sy, h = (float(v) for v in size)
    z0, zt = -h / 2, h / 2
    if style == 0:
        r = rng.uniform(0.2, 0.28) * min(sx, sy)
        levels = [(0.9, z0), (1.0, z0 + 0.35 * h), (0.96, zt - 0.2 * h), (0.8, zt)]
        pts = [
            np.c_[
                rounded_outline(-s * sx / 2, s * sx / 2, -s * sy / 2, s * sy / 2, s * r, 3),
                np.full(16, z),
            ]
            for s, z in levels
        ]
        return [Part("bar", hull(np.concatenate(pts)))]
    return [
        Part(
            "bar",
            lathe(
                [(0.82, z0), (1.0, z0 + 0.3 * h), (0.9, z0 + 0.75 * h), (0.55, zt)],
                sx / 2,
                sy / 2,
                center=(0, 0),
                hull_of_rings=False,
            ),
        )
    ]


def _bristles(
    x0: float, x1: float, y0: float, y1: float, z0: float, z1: float, nx: int, ny: int
) -> list[Part]:
    """An nx x ny grid of bristle tufts (boxes) filling [x0, x1] x [y0, y1]."""
    gx, gy = (x1 - x0) / nx, (y1 - y0) / ny
    return [
        Part(
            f"bristles_{i * ny + j}",
            box_between(
                (x0 + (i + 0.15) * gx, y0 + (j + 0.15) * gy, z0),
                (x0 + (i + 0.85) * gx, y0 + (j + 0.85) * gy, z1 + 0.001),
            ),
        )
        for i in range(nx)
        for j in range(ny)
    ]


@register("scrub_brush", variants=2)
def scrub_brush(size, rng, style, support_heights):
    """A scrub brush. In a tall box, a standing (toilet) brush: 0 in a closed holder,
    1 on an open stand with the bristle head visible. In a flat box, a hand brush:
    0 block with a knob, 1 pointed block with a loop handle."""
    sx, sy, h = (float(v) for v in size)
    rx, ry, z0, zt = sx / 2, sy / 2, -h / 2, h / 2
    hr = float(np.clip(0.1 * min(rx, ry), 0.005, 0.015))
    if h > UPRIGHT_RATIO * max(sx, sy):
        if style == 0:
            zh = z0 + rng.uniform(0.34, 0.4) * h
            return [
                Part(
                    "holder",
                    lathe(
                        [(0.85, z0), (1.0, z0 + 0.08 * h), (0.92, zh)],
                        rx,
                        ry,
                        center=(0, 0),
                        hull_of_rings=False,
                    ),
                ),
                Part(
                    "holder_rim",
                    _disc(
                        (0, 0), 0.75 * rx, 0.75 * ry, zh - 0.01 * h, zh + 0.015 * h, FINE_SEGMENTS
                    ),
                ),
                Part("handle", _rod((0, 0, zh), (0, 0, zt - 0.06 * h), hr, 0.9 * hr)),
                Part(
                    "knob",
                    ellipsoid((0, 0, zt - 0.06 * h), (2 * hr, 2 * hr, 0.06 * h), 6, ROD_SEGMENTS),
                ),
            ]
        base_h = 0.04 * h
        zb = z0 + base_h
        head_h = 0.2 * h
        return [
            Part(
                "stand",
                lathe(
                    [(1.0, z0), (1.0, zb - 0.01 * h), (0.9, zb)],
                    rx,
                    ry,
                    center=(0, 0),
                    hull_of_rings=False,
                ),
            ),
            Part(
                "head",
                ellipsoid((0, 0, zb + head_h / 2), (0.62 * rx, 0.62 * ry, head_h / 2), 6, 12),
            ),
            Part(
                "ferrule",
                _rod((0, 0, zb + 0.8 * head_h), (0, 0, zb + head_h + 0.06 * h), 1.6 * hr, 1.2 * hr),
            ),
            Part("handle", _rod((0, 0, zb + head_h), (0, 0, zt - 0.03 * h), hr, 0.9 * hr)),
            Part(
                "knob",
                ellipsoid((0, 0, zt - 0.03 * h), (1.6 * hr, 1.6 * hr, 0.03 * h), 4, ROD_SEGMENTS),
            ),
        ]
    bristle_h = 0.3 * h
    zb = z0 + bristle_h
    block_h = 0.3 * h
    if style == 0:
        parts = [
            Part(
                "block",
                prism(rounded_outline(-rx, rx, -ry, ry, 0.3 * min(rx, ry)), zb, zb + block_h),
            )
        ]
        parts += _bristles(
            -0.88 * rx,
            0.88 * rx,
            -0.9 * ry,
            0.9 * ry,
            z0,
            zb,
            3 if sx < sy else 5,
            5 if sx < sy else 3,
        )
        kr = 0.35 * min(rx, ry)
        parts.append(
            Part(
                "knob",
                lathe(
                    [(0.6, zb + block_h - 0.01 * h), (1.0, zt - 0.15 * h), (0.7, zt)],
                    kr,
                    kr,
                    center=(0, 0),
                    hull_of_rings=False,
                ),
            )
        )
        return parts
    outline = np.array([(-rx, -ry), (rx, -ry), (rx, 0.3 * ry), (0.0, ry), (-rx, 0.3 * ry)])
    parts = [Part("block", prism(outline, zb, zb + block_h))]
    parts += _bristles(-0.8 * rx, 0.8 * rx, -0.9 * ry, 0.2 * ry, z0, zb, 3, 4)
    parts += _bristles(-0.35 * rx, 0.35 * rx, 0.2 * ry, 0.6 * ry, z0, zb, 1, 1)
    bar = float(np.clip(0.12 * h, 0.004, 0.012))
    w = 0.3 * sx
    zt_b = zb + block_h
    parts += [
        Part(
            "handle_post_0",
            box_between((-w / 2, -0.65 * ry, zt_b - 0.001), (w / 2, -0.65 * ry + bar, zt)),
        ),
        Part(
            "handle_post_1",
            box_between((-w / 2, 0.25 * ry - bar, zt_b - 0.001), (w / 2, 0.25 * ry, zt)),
        ),
        Part("handle", box_between((-w / 2, -0.65 * ry, zt - bar), (w / 2, 0.25 * ry, zt))),
    ]
    return parts


@register("plunger", variants=2)
def plunger(size, rng, style, support_heights):
    """A plunger standing on its rubber cup: 0 plain cup, 1 flange cup."""
    sx, sy, h = (float(v) for v in size)
    rx, ry, z0, zt = sx / 2, sy / 2, -h / 2, h / 2
    hr = float(np.clip(0.1 * min(rx, ry), 0.006, 0.02))
    parts = []
    zc = z0
    if style == 1:
        flange = 0.06 * h
        parts.append(
            Part(
                "flange",
                frustum(
                    (0, 0, z0), flange, (0.5 * rx, 0.5 * ry), (0.62 * rx, 0.62 * ry), FINE_SEGMENTS
                ),
            )
        )
        zc = z0 + 0.8 * flange
    hc = rng.uniform(0.2, 0.24) * h
    parts += [
        Part(
            "cup",
            lathe(
                [(1.0, zc), (0.96, zc + 0.3 * hc), (0.78, zc + 0.7 * hc), (0.3, zc + hc)],
                rx,
                ry,
                center=(0, 0),
                hull_of_rings=False,
            ),
        ),
        Part("handle", _rod((0, 0, zc + 0.9 * hc), (0, 0, zt - 0.03 * h), hr, hr)),
        Part(
            "handle_end",
            lathe(
                [(1.0, zt - 0.04 * h), (1.0, zt - 0.01 * h), (0.6, zt)],
                1.25 * hr,
                1.25 * hr,
                ROD_SEGMENTS,
                center=(0, 0),
                hull_of_rings=False,
            ),
        ),
    ]
    return parts


@register("candle", variants=2)
def candle(size, rng, style, support_heights):
    """A candle: 0 pillar candle with a wick, 1 taper candle in a holder with a flame."""
    sx, sy, h = (float(v) for v in size)
    rx, ry, z0, zt = sx / 2, sy / 2, -h / 2, h / 2
    if style == 0:
        zb = zt - rng.uniform(0.06, 0.1) * h
        wr = float(np.clip(0.05 * min(rx, ry), 0.0008, 0.003))
        return [
            Part(
                "body",
                lathe(
                    [(1.0, z0), (1.0, zb - 0.02 * h), (0.9, zb)],
                    rx,
                    ry,
                    center=(0, 0),
                    hull_of_rings=False,
                ),
            ),
            Part("wick", _rod((0, 0, zb - 0.005 * h), (0.02 * rx, 0, zt), wr, 0.8 * wr, 6)),
        ]
    z1, z2, z3 = z0 + 0.04 * h, z0 + 0.2 * h, z0 + 0.26 * h
    cr = 0.24
    zc = zt - rng.uniform(0.13, 0.16) * h
    return [
        Part("dish", frustum((0, 0, z0), z1 - z0, (rx, ry), (0.9 * rx, 0.9 * ry), FINE_SEGMENTS)),
        Part("stem", _rod((0, 0, z1 - 0.001), (0, 0, z2), 0.12 * min(rx, ry), 0.1 * min(rx, ry))),
        Part(
            "socket",
            frustum(
                (0, 0, z2 - 0.001),
                z3 - z2,
                (0.2 * rx, 0.2 * ry),
                (0.34 * rx, 0.34 * ry),
                FINE_SEGMENTS,
            ),
        ),
        Part(
            "taper",
            lathe(
                [(1.0, z3 - 0.01 * h), (0.85, zc - 0.02 * h), (0.5, zc)],
                cr * rx,
                cr * ry,
                ROD_SEGMENTS,
                center=(0, 0),
                hull_of_rings=False,
            ),
        ),
        Part(
            "wick",
            _rod(
                (0, 0, zc - 0.005 * h),
                (0, 0, zc + 0.03 * h),
                0.02 * min(rx, ry),
                0.02 * min(rx, ry),
                6,
            ),
        ),
        Part(
            "flame",
            lathe(
                [(0.0, zc + 0.02 * h), (0.8, zc + 0.05 * h), (1.0, zc + 0.07 * h), (0.0, zt)],
                0.14 * rx,
                0.14 * ry,
                ROD_SEGMENTS,
                center=(0, 0),
                hull_of_rings=False,
            ),
        ),
    ]

"""Small household objects: electronics, books, bedding, rolls, sports gear and ornaments.

Every generator follows the registry contract: ``fn(size, rng, style, support_heights)``
returns convex parts inside the box [-size/2, size/2] (+z up, +y front, +x right). Objects
with a face (screens, clocks, the teddy bear) face +y. Where an object can lie or stand,
the box decides:

- long things (pen, pencil, baseball bat, tennis racket, dumbbell) lie along the longer
  horizontal axis and stand upright when the box is tallest along z;
- a book lies flat (cover up, spine at -x) unless size z > size y: then it stands on its
  bottom edge like a book on a shelf, spine facing +y (out of the shelf);
- a pillow lies flat unless size z > size y: then it stands with its face toward +y;
- towels and hand towels hang draped over a bar when size z > 2 * size y (as on a towel
  holder), otherwise they lie folded;
- a watch lies open, band spread, in a flat box and stands on its closed band otherwise;
- phones, remotes, cards, keys, discs and newspapers always lie flat, lengthwise along the
  box's longer horizontal side.

Shapes are built from the convex primitives of :mod:`pair2scene.assets.mesh`; concave
shapes (rings, frames, the hole of a roll) are split into many convex pieces.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from pair2scene.assets.generators.shapes import (
    FINE_SEGMENTS,
    ROD_SEGMENTS,
    ROUND_SEGMENTS,
    clip,
    rest_flat,
)
from pair2scene.assets.mesh import (
    Mesh,
    Part,
    box,
    box_between,
    cylinder,
    ellipsoid,
    frustum,
    hull,
    prism,
)
from pair2scene.assets.mesh import rod as _rod
from pair2scene.assets.registry import register
from pair2scene.scene.geometry import rot_x as _rot_x
from pair2scene.scene.geometry import rot_y as _rot_y
from pair2scene.scene.geometry import rot_z as _rot_z

ELL_RINGS = 6
"""Latitude rings of a small ellipsoid (a teddy's ear, a lump on a bag)."""

_TAU = 2.0 * np.pi


# -- small geometry helpers -----------------------------------------------------------------


_Z_TO_X = np.array([[0.0, 0.0, 1.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]])
"""Local z -> x, local x -> y, local y -> z: lays a z-axis primitive along x."""
_Z_TO_Y = np.array([[1.0, 0.0, 0.0], [0.0, 0.0, 1.0], [0.0, -1.0, 0.0]])
"""Local z -> y, local x -> x, local y -> -z: lays a z-axis primitive along y."""


def _cyl_x(
    center: Sequence[float], r_y: float, r_z: float, length: float, segments: int = ROUND_SEGMENTS
) -> Mesh:
    """Elliptic cylinder along x: centre (3,), semi-axes along y and z, full length."""
    return cylinder(center, (r_y, r_z), length, segments, rotation=_Z_TO_X)


def _cyl_y(
    center: Sequence[float], r_x: float, r_z: float, length: float, segments: int = ROUND_SEGMENTS
) -> Mesh:
    """Elliptic cylinder along y: centre (3,), semi-axes along x and z, full length."""
    return cylinder(center, (r_x, r_z), length, segments, rotation=_Z_TO_Y)


def _cyl_z(
    center: Sequence[float], r_x: float, r_y: float, height: float, segments: int = ROUND_SEGMENTS
) -> Mesh:
    """Elliptic cylinder along z: centre (3,), semi-axes along x and y, full height."""
    return cylinder(center, (r_x, r_y), height, segments)


def _ell(
    center: Sequence[float],
    radii: Sequence[float],
    rotation: np.ndarray | None = None,
    rings: int = ELL_RINGS,
    segments: int = ROUND_SEGMENTS,
) -> Mesh:
    """Ellipsoid with semi-axes ``radii`` (3,), rotated (3, 3) about its centre (3,)."""
    m = ellipsoid((0.0, 0.0, 0.0), radii, rings, segments)
    return m.transformed(rotation, center)


def _rounded_rect(w: float, d: float, r: float, arc: int = 3) -> np.ndarray:
    """(4 * arc, 2) counter-clockwise rounded rectangle of width w (x), depth d (y),
    corner radius r, centred at the origin."""
    r = float(np.clip(r, 1e-6, 0.49 * min(w, d)))
    cx, cy = w / 2 - r, d / 2 - r
    pts = []
    for k, (sx, sy) in enumerate(((1, 1), (-1, 1), (-1, -1), (1, -1))):
        a = np.linspace(0.0, np.pi / 2, arc) + k * np.pi / 2
        pts.append(np.c_[sx * cx + r * np.cos(a), sy * cy + r * np.sin(a)])
    return np.concatenate(pts)


def _rounded_block(
    center: Sequence[float], w: float, d: float, h: float, r: float, arc: int = 3
) -> Mesh:
    """Rounded-corner slab: centre (3,), width w (x), depth d (y), height h (z)."""
    c = np.asarray(center, dtype=float)
    poly = _rounded_rect(w, d, r, arc) + c[:2]
    return prism(poly, c[2] - h / 2, c[2] + h / 2)


def _superellipse(a: float, b: float, n: int, p: float) -> np.ndarray:
    """(n, 2) counter-clockwise superellipse |x/a|^p + |y/b|^p = 1 (p = 2: an ellipse)."""
    t = np.linspace(0.0, _TAU, n, endpoint=False)
    c, s = np.cos(t), np.sin(t)
    return np.c_[a * np.sign(c) * np.abs(c) ** (2 / p), b * np.sign(s) * np.abs(s) ** (2 / p)]


def _ring_segments(
    r_in: float,
    r_out: float,
    z0: float,
    z1: float,
    n: int,
    r_in_y: float | None = None,
    r_out_y: float | None = None,
) -> list[Mesh]:
    """A flat (elliptic) annulus about +z from z0 to z1 as ``n`` convex trapezoid prisms;
    optional y semi-axes make it elliptic. Returns n meshes."""
    riy = r_in if r_in_y is None else r_in_y
    roy = r_out if r_out_y is None else r_out_y
    a = np.linspace(0.0, _TAU, n + 1)
    out = []
    for a0, a1 in zip(a[:-1], a[1:]):
        c0, s0, c1, s1 = np.cos(a0), np.sin(a0), np.cos(a1), np.sin(a1)
        poly = [
            (r_in * c0, riy * s0),
            (r_out * c0, roy * s0),
            (r_out * c1, roy * s1),
            (r_in * c1, riy * s1),
        ]
        out.append(prism(poly, z0, z1))
    return out


def _loop_rods(
    points: np.ndarray, radius: float, closed: bool = True, segments: int = ROD_SEGMENTS
) -> list[Mesh]:
    """Rods joining consecutive points (N, 3): a polyline (or closed loop) of N(-1) rods."""
    pts = np.asarray(points, dtype=float)
    pairs = zip(pts, np.roll(pts, -1, axis=0)) if closed else zip(pts[:-1], pts[1:])
    return [_rod(p, q, radius, segments=segments) for p, q in pairs]


def _pose(
    parts: list[Part],
    rotation: np.ndarray | None = None,
    translation: Sequence[float] | None = None,
) -> list[Part]:
    """Rotate (3, 3) then translate (3,) every part."""
    return [Part(p.name, p.mesh.transformed(rotation, translation)) for p in parts]


def _scaled(parts: list[Part], scale: Sequence[float]) -> list[Part]:
    """Scale every part per axis (3,) about the origin (unit-box designs -> the real box)."""
    return [Part(p.name, p.mesh.scaled(scale)) for p in parts]


_FLAT_X_LONG = np.array([[0.0, 1.0, 0.0], [-1.0, 0.0, 0.0], [0.0, 0.0, 1.0]])
"""Canonical x -> local -y, canonical y -> local x: a lengthwise canonical object along x."""
_UPRIGHT = np.array([[1.0, 0.0, 0.0], [0.0, 0.0, -1.0], [0.0, 1.0, 0.0]])
"""Canonical y -> local z, canonical z -> local -y: a lengthwise object stood on its end,
its canonical top facing the front."""


def _flat_frame(size: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """For an object that always lies flat and is built lengthwise along canonical y:
    its canonical size (3,) and the rotation (3, 3) canonical -> local."""
    sx, sy, sz = size
    if sx > sy:
        return np.array([sy, sx, sz]), _FLAT_X_LONG
    return np.array([sx, sy, sz]), np.eye(3)


def _long_frame(size: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Like :func:`_flat_frame`, but the object stands on its end when z is the longest
    extent (a bat in a corner, a pen in a cup): canonical +y then points up."""
    sx, sy, sz = size
    if sz > max(sx, sy):
        return np.array([sx, sz, sy]), _UPRIGHT
    return _flat_frame(size)


def _face_down(parts: list[Part], size: np.ndarray) -> list[Part]:
    """The parts of a lengthwise round object built along canonical y (a bat, a pen),
    turned half a side about its axis when it lies (its box not tallest in z): a face of
    each ROUND_SEGMENTS part down, where a vertex was (ROUND_SEGMENTS puts one on each
    box face). On that edge lying bats and pens rolled 2-3 cm in ``evaluate``'s
    simulation; the registry fits the turned parts to the box again."""
    if size[2] > max(size[0], size[1]):
        return parts
    return _pose(parts, _rot_y(np.pi / ROUND_SEGMENTS))


# -- displays: television, monitor, desktop computer, laptop, keyboard ------------------------
def _display(
    x0: float,
    x1: float,
    y0: float,
    y1: float,
    z0: float,
    z1: float,
    bezel: float,
    chin: float = 0.0,
) -> list[Part]:
    """A flat display between the given x, y, z limits: housing plus a screen on its +y face
    inset by ``bezel`` (and a wider ``chin`` at the bottom). Returns [panel, screen]."""
    st = clip(0.12 * (y1 - y0), 0.0008, 0.004)  # screen glass proud of the bezel
    panel = box_between((x0, y0, z0), (x1, y1 - st, z1))
    screen = box_between(
        (x0 + bezel, y1 - st - 1e-4, z0 + bezel + chin), (x1 - bezel, y1, z1 - bezel)
    )
    return [Part("panel", panel), Part("screen", screen)]


def _back_cover(x_half: float, y_back: float, depth: float, z0: float, z1: float) -> Mesh:
    """The tapered electronics housing behind a display: a frustum-like hull from the panel's
    back (at y_back) ``depth`` towards -y, between z0 and z1, half width x_half."""
    t = 0.35 * min(x_half, (z1 - z0) / 2)  # taper so it reads as a moulded shell
    pts = [(sx * x_half, y_back + 1e-4, z) for sx in (-1, 1) for z in (z0, z1)]
    pts += [(sx * (x_half - t), y_back - depth, z) for sx in (-1, 1) for z in (z0 + t, z1 - t)]
    return hull(pts)


@register("television", variants=3)
def television(size, rng, style, support_heights):
    """Flat-screen TV facing +y: on a pedestal (0), on two feet (1) or wall-mounted (2)."""
    sx, sy, sz = size
    hx, hy, hz = size / 2
    bezel = clip(0.012 * min(sx, sz), 0.004, 0.025)
    parts: list[Part] = []
    if style == 2:
        # wall-mounted: the panel at the front of the box, a bracket behind it to the wall
        pd = clip(0.45 * sy, 0.012, 0.07)
        parts += _display(-hx, hx, hy - pd, hy, -hz, hz, bezel)
        bw, bh = 0.3 * sx, 0.35 * sz
        parts.append(
            Part(
                "wall_bracket",
                box_between((-bw / 2, -hy, -bh / 2), (bw / 2, hy - pd + 1e-4, bh / 2)),
            )
        )
        return parts
    pd = min(clip(0.22 * sy, 0.012, 0.07), 0.5 * sy)
    foot_h = clip(0.025 * sz, 0.006, 0.025)
    lift = clip(0.07 * sz * rng.uniform(0.8, 1.2), 0.02, 0.12)
    z0 = -hz + foot_h + lift
    y0, y1 = -pd / 2, pd / 2
    parts += _display(-hx, hx, y0, y1, z0, hz, bezel)
    room = y0 + hy  # depth left behind the panel within the box
    parts.append(
        Part(
            "back_cover",
            _back_cover(
                0.32 * sx, y0, min(0.9 * pd, 0.9 * room), z0 + 0.1 * (hz - z0), z0 + 0.6 * (hz - z0)
            ),
        )
    )
    if style == 0:
        fw = clip(0.38 * sx * rng.uniform(0.9, 1.1), 0.08, sx)
        parts.append(
            Part(
                "foot", _rounded_block((0, 0, -hz + foot_h / 2), fw, sy, foot_h, 0.2 * min(fw, sy))
            )
        )
        nw, nd = clip(0.08 * sx, 0.02, 0.12), clip(0.5 * pd, 0.008, 0.04)
        parts.append(
            Part(
                "neck",
                box_between(
                    (-nw / 2, y0 - nd, -hz + foot_h * 0.5),
                    (nw / 2, y0 + 1e-4, z0 + 0.25 * (hz - z0)),
                ),
            )
        )
    else:
        fx = hx - clip(0.1 * sx, 0.03, 0.2)
        fw = clip(0.02 * sx, 0.008, 0.03)
        for i, cx in enumerate((-fx, fx)):
            pts = [
                (cx + sxx * fw / 2, y, z)
                for sxx in (-1, 1)
                for y, z in (
                    (-0.3 * pd, z0 + 0.02 * (hz - z0)),
                    (0.3 * pd, z0 + 0.02 * (hz - z0)),
                    (-hy, -hz),
                    (hy, -hz),
                )
            ]
            parts.append(Part(f"foot_{i}", hull(pts)))
    return parts


@register("monitor", variants=2)
def monitor(size, rng, style, support_heights):
    """Computer monitor facing +y: on a neck and flat foot (0) or a slanted arm on a round
    foot (1)."""
    sx, sy, sz = size
    hx, hy, hz = size / 2
    pd = min(clip(0.2 * sy, 0.008, 0.05), 0.4 * sy)
    foot_h = clip(0.03 * sz, 0.005, 0.02)
    lift = clip(0.16 * sz * rng.uniform(0.85, 1.15), 0.03, 0.15)
    z0 = -hz + foot_h + lift
    y1 = hy - clip(0.12 * sy, 0.0, 0.04) if style == 0 else hy - 0.05 * sy
    y0 = y1 - pd
    bezel = clip(0.02 * min(sx, sz), 0.004, 0.02)
    parts = _display(-hx, hx, y0, y1, z0, hz, bezel)
    parts.append(
        Part(
            "back_cover",
            _back_cover(
                0.25 * sx,
                y0,
                min(0.7 * pd, 0.5 * (y0 + hy)),
                z0 + 0.25 * (hz - z0),
                z0 + 0.75 * (hz - z0),
            ),
        )
    )
    if style == 0:
        fw = clip(0.4 * sx, 0.06, sx)
        parts.append(
            Part(
                "foot", _rounded_block((0, 0, -hz + foot_h / 2), fw, sy, foot_h, 0.15 * min(fw, sy))
            )
        )
        nw, nd = clip(0.1 * sx, 0.02, 0.08), clip(0.12 * sy, 0.008, 0.03)
        yb = y0 - 0.5 * min(0.7 * pd, 0.5 * (y0 + hy))
        parts.append(
            Part(
                "neck",
                box_between(
                    (-nw / 2, yb - nd, -hz + foot_h / 2), (nw / 2, yb, z0 + 0.55 * (hz - z0))
                ),
            )
        )
    else:
        rx, ry = clip(0.2 * sx, 0.05, hx), hy
        parts.append(Part("foot", _cyl_z((0, 0, -hz + foot_h / 2), rx, ry, foot_h, FINE_SEGMENTS)))
        r = clip(0.025 * sz, 0.006, 0.02)
        top = (0.0, y0 - r, z0 + 0.5 * (hz - z0))
        parts.append(
            Part("arm", _rod((0.0, -0.55 * hy, -hz + foot_h), top, r, segments=ROUND_SEGMENTS))
        )
    return parts


def _key_grid(
    x0: float,
    x1: float,
    y0: float,
    y1: float,
    z_base: float,
    key_h: float,
    rows: Sequence[int],
    gap: float,
) -> list[Part]:
    """Single keys in the rectangle x0..x1, y0..y1: ``rows`` holds the key count per row,
    listed from the row nearest the typist (+y, at y1) to the farthest (at y0). Keys stand
    ``key_h`` above the deck at z_base."""
    parts = []
    n_rows = len(rows)
    pitch_y = (y1 - y0) / n_rows
    for r, n in enumerate(rows):
        ya, yb = y1 - (r + 1) * pitch_y + gap / 2, y1 - r * pitch_y - gap / 2
        pitch_x = (x1 - x0) / n
        for k in range(n):
            xa, xb = x0 + k * pitch_x + gap / 2, x0 + (k + 1) * pitch_x - gap / 2
            parts.append(
                Part(
                    f"key_{r}_{k}",
                    box_between((xa, ya, z_base - 0.3 * key_h), (xb, yb, z_base + key_h)),
                )
            )
    return parts


@register("keyboard", variants=2)
def keyboard(size, rng, style, support_heights):
    """Computer keyboard, keys up, typing side toward +y: a flat compact board of single
    keys (0) or a wedge full-size board whose key rows are split into blocks (1)."""
    sx, sy, sz = size
    hx, hy, hz = size / 2
    key_h = clip(0.3 * sz, 0.0008, 0.008)
    margin = clip(0.05 * min(sx, sy), 0.003, 0.015)
    gap = clip(0.15 * (sy - 2 * margin) / 5, 0.0005, 0.003)
    if style == 0:
        deck = hz - key_h
        parts = [
            Part(
                "base",
                _rounded_block(
                    (0, 0, (deck - hz) / 2), sx, sy, deck + hz, clip(0.08 * sy, 0.002, 0.012)
                ),
            )
        ]
        n = int(rng.integers(10, 13))
        rows = [n - 1, n - 1, n, n]
        x0, x1, y0, y1 = -hx + margin, hx - margin, -hy + margin, hy - margin
        pitch = (y1 - y0) / 5
        parts += _key_grid(x0, x1, y0, y1 - pitch, deck, key_h, rows, gap)
        # the row nearest the typist: modifier keys either side of a wide space bar
        w = x1 - x0
        for name, a, b in (
            ("key_mod_0", 0.0, 0.2),
            ("space_bar", 0.2, 0.78),
            ("key_mod_1", 0.78, 1.0),
        ):
            parts.append(
                Part(
                    name,
                    box_between(
                        (x0 + a * w + gap / 2, y1 - pitch + gap / 2, deck - 0.3 * key_h),
                        (x0 + b * w - gap / 2, y1 - gap / 2, hz),
                    ),
                )
            )
        return parts
    # wedge: the deck rises toward the back (-y), as on keyboards with feet out
    z_front, z_back = -hz + 0.55 * (sz - key_h), hz - key_h
    base_pts = [
        (sxx * hx, y, z)
        for sxx in (-1, 1)
        for y, z in ((-hy, -hz), (hy, -hz), (hy, z_front), (-hy, z_back))
    ]
    parts = [Part("base", hull(base_pts))]

    def deck(y: float) -> float:
        return z_front + (z_back - z_front) * (hy - y) / sy

    x0, x1, y0, y1 = -hx + margin, hx - margin, -hy + margin, hy - margin
    pitch = (y1 - y0) / 6
    w = x1 - x0
    blocks = ((0.0, 0.64), (0.67, 0.79), (0.82, 1.0))  # main, navigation, number pad
    for r in range(6):
        ya, yb = y1 - (r + 1) * pitch + gap / 2, y1 - r * pitch - gap / 2
        if r == 5:  # function keys, set apart from the main block
            yb -= 0.25 * pitch
        zb = deck(0.5 * (ya + yb))
        for b, (a0, a1) in enumerate(blocks):
            if r == 5 and b == 2:
                continue
            if r in (1, 2) and b == 1:  # no navigation keys beside the middle rows
                continue
            parts.append(
                Part(
                    f"key_row_{r}_{b}",
                    box_between((x0 + a0 * w, ya, zb - 0.3 * key_h), (x0 + a1 * w, yb, zb + key_h)),
                )
            )
    return parts


@register("laptop", variants=2)
def laptop(size, rng, style, support_heights):
    """Open laptop: base on the bottom with keyboard and touchpad, lid rising at -y tilted
    back with its screen facing +y; key rows as strips (0) or single keys (1)."""
    sx, sy, sz = size
    hx, hy, hz = size / 2
    bt = clip(0.06 * sz, 0.005, 0.025)  # base thickness
    lt = clip(0.5 * bt, 0.003, 0.01)  # lid thickness
    tilt = np.radians(rng.uniform(12.0, 22.0))  # lid leans back from vertical
    lid_len = (sz - bt) / np.cos(tilt)
    # the lid leans over the back of the box; keep at least 45 % of the depth for the base
    tilt = min(tilt, np.arcsin(min(1.0, 0.55 * sy / lid_len)))
    lid_len = (sz - bt) / np.cos(tilt)
    base_d = max(sy - lid_len * np.sin(tilt) - lt * np.cos(tilt), 0.45 * sy)
    yb0 = hy - base_d  # the hinge line
    ztop = -hz + bt
    parts = [
        Part(
            "base",
            _rounded_block(
                (0, hy - base_d / 2, -hz + bt / 2), sx, base_d, bt, clip(0.03 * sx, 0.002, 0.015)
            ),
        )
    ]
    rot = _rot_x(tilt)  # local z -> up the lid, local y -> the lid's screen normal
    up, normal = rot[:, 2], rot[:, 1]
    hinge = np.array([0.0, yb0, ztop])
    lid_c = hinge + up * lid_len / 2 - normal * lt / 2
    parts.append(Part("lid", box(lid_c, (sx, lt, lid_len), rot)))
    bezel = clip(0.04 * min(sx, lid_len), 0.004, 0.02)
    st = 0.3 * lt
    scr_c = hinge + up * (lid_len / 2 + 0.5 * bezel) + normal * st / 2
    parts.append(Part("screen", box(scr_c, (sx - 2 * bezel, st, lid_len - 3 * bezel), rot)))
    parts.append(
        Part(
            "hinge",
            _cyl_x(
                (0.0, yb0 + 0.3 * bt, ztop - 0.3 * bt), 0.45 * bt, 0.45 * bt, 0.7 * sx, ROD_SEGMENTS
            ),
        )
    )
    # keyboard area on the back 55 % of the deck, touchpad centred in front of it
    key_h = clip(0.15 * bt, 0.0005, 0.002)
    mx = clip(0.06 * sx, 0.008, 0.03)
    ky0, ky1 = yb0 + 0.08 * base_d, yb0 + 0.58 * base_d
    gap = clip(0.012 * base_d, 0.0005, 0.003)
    if style == 0:
        n_rows = 5
        pitch = (ky1 - ky0) / n_rows
        for r in range(n_rows):
            ya, yb = ky0 + r * pitch + gap / 2, ky0 + (r + 1) * pitch - gap / 2
            # the front row (space bar) is short
            inset = 0.22 * (sx - 2 * mx) if r == n_rows - 1 else 0.0
            parts.append(
                Part(
                    f"key_row_{r}",
                    box_between(
                        (-hx + mx + inset, ya, ztop - key_h), (hx - mx - inset, yb, ztop + key_h)
                    ),
                )
            )
    else:
        n = int(rng.integers(10, 13))  # at most 56 parts
        parts += _key_grid(-hx + mx, hx - mx, ky0, ky1, ztop, key_h, [3] + [n] * 4, gap)
    tw, td = clip(0.3 * sx, 0.03, 0.14), 0.28 * base_d
    ty1 = ky1 + 0.06 * base_d
    parts.append(
        Part(
            "touchpad",
            box_between((-tw / 2, ty1, ztop - key_h), (tw / 2, ty1 + td, ztop + 0.5 * key_h)),
        )
    )
    return parts


@register("desktop_computer", variants=2)
def desktop_computer(size, rng, style, support_heights):
    """Desktop computer facing +y: a monitor on a stand beside a tower case (0) or an
    all-in-one screen with keyboard and mouse in front (1)."""
    sx, sy, sz = size
    hx, hy, hz = size / 2
    parts: list[Part] = []
    if style == 0:
        tw = clip(0.22 * sx * rng.uniform(0.9, 1.1), 0.06, 0.25)
        th = clip(rng.uniform(0.75, 0.95) * sz, 0.0, sz)
        gap = clip(0.04 * sx, 0.01, 0.08)
        tx0 = hx - tw
        parts.append(Part("tower", box_between((tx0, -hy, -hz), (hx, hy - 0.012 * sy, -hz + th))))
        inset = 0.08 * tw
        parts.append(
            Part(
                "tower_front",
                box_between(
                    (tx0 + inset, hy - 0.013 * sy, -hz + 0.04 * th),
                    (hx - inset, hy - 0.005 * sy, -hz + 0.96 * th),
                ),
            )
        )
        parts.append(
            Part(
                "drive_bay",
                box_between(
                    (tx0 + 2 * inset, hy - 0.008 * sy, -hz + 0.8 * th),
                    (hx - 2 * inset, hy, -hz + 0.86 * th),
                ),
            )
        )
        parts.append(
            Part(
                "power_button",
                _cyl_y(
                    (hx - tw / 2, hy - 0.006 * sy, -hz + 0.7 * th), 0.08 * tw, 0.08 * tw, 0.012 * sy
                ),
            )
        )
        mx0, mx1 = -hx, tx0 - gap
        mw, mc = mx1 - mx0, (mx0 + mx1) / 2
        pd = clip(0.15 * sy, 0.008, 0.04)
        foot_h = clip(0.03 * sz, 0.005, 0.02)
        z0 = -hz + foot_h + clip(0.15 * sz, 0.03, 0.14)
        y1 = 0.15 * sy
        parts += _display(mx0, mx1, y1 - pd, y1, z0, hz, clip(0.02 * mw, 0.004, 0.02))
        fw = clip(0.4 * mw, 0.06, mw)
        parts.append(
            Part(
                "foot",
                _rounded_block(
                    (mc, -0.05 * sy, -hz + foot_h / 2), fw, 0.8 * sy, foot_h, 0.15 * min(fw, sy)
                ),
            )
        )
        nw = clip(0.1 * mw, 0.02, 0.07)
        parts.append(
            Part(
                "neck",
                box_between(
                    (mc - nw / 2, y1 - pd - 0.1 * sy, -hz + foot_h / 2),
                    (mc + nw / 2, y1 - pd + 1e-4, z0 + 0.5 * (hz - z0)),
                ),
            )
        )
        return parts
    # all-in-one: keyboard and mouse take the front of the box
    kd = clip(0.35 * sy, 0.05, 0.2)
    kt = clip(0.04 * sz, 0.008, 0.025)
    kw = 0.62 * sx
    parts.append(
        Part(
            "keyboard",
            _rounded_block((-0.08 * sx, hy - kd / 2, -hz + kt / 2), kw, kd, kt, 0.05 * kd),
        )
    )
    for r in range(4):
        ya = hy - kd + (0.1 + 0.2 * r) * kd
        parts.append(
            Part(
                f"key_row_{r}",
                box_between(
                    (-0.08 * sx - 0.45 * kw, ya, -hz + kt),
                    (-0.08 * sx + 0.45 * kw, ya + 0.15 * kd, -hz + 1.25 * kt),
                ),
            )
        )
    mouse_h = 1.3 * kt
    parts.append(
        Part(
            "mouse",
            _ell(
                (0.36 * sx, hy - 0.5 * kd, -hz + mouse_h / 2),
                (clip(0.035 * sx, 0.02, 0.035), clip(0.3 * kd, 0.03, 0.06), mouse_h / 2),
            ),
        )
    )
    foot_h = clip(0.02 * sz, 0.004, 0.015)
    sy_m = sy - kd - 0.02 * sy  # the monitor's depth budget
    pd = clip(0.2 * sy_m, 0.01, 0.05)
    y1 = -hy + 0.75 * sy_m
    z0 = -hz + clip(0.18 * sz, 0.05, 0.15)
    chin = 0.12 * (hz - z0)
    parts += _display(-hx, hx, y1 - pd, y1, z0, hz, clip(0.015 * sx, 0.004, 0.015), chin)
    fw = clip(0.3 * sx, 0.08, sx)
    parts.append(
        Part("foot", box_between((-fw / 2, -hy, -hz), (fw / 2, y1 - pd * 0.5, -hz + foot_h)))
    )
    lw = 0.7 * fw
    leg = [
        (sxx * lw / 2, y, z)
        for sxx in (-1, 1)
        for y, z in (
            (-hy + 0.05 * sy_m, -hz),
            (-hy + 0.3 * sy_m, -hz),
            (y1 - pd, z0 + 0.55 * (hz - z0)),
            (y1 - pd - 0.1 * sy_m, z0 + 0.6 * (hz - z0)),
        )
    ]
    parts.append(Part("leg", hull(leg)))
    return parts


# -- book, pillow, box, statue, clock, tissues, teddy ---------------------------------
_STAND_BOOK = np.array([[0.0, 0.0, -1.0], [-1.0, 0.0, 0.0], [0.0, 1.0, 0.0]])
"""Canonical flat book (spine at -x, pages along y, thickness z) -> standing: the spine
faces +y, the page height runs up z, the thickness along x."""


@register("book", variants=2)
def book(size, rng, style, support_heights):
    """Closed book: hardcover with a rounded spine and covers overhanging the pages (0) or a
    paperback with flush covers (1). Lies flat (front cover up, spine along the -x edge) or,
    when size z > size y, stands on its bottom edge with the spine facing +y."""
    standing = size[2] > size[1]
    w, d, t = (size[1], size[2], size[0]) if standing else size
    hw, hd, ht = w / 2, d / 2, t / 2
    if style == 0:
        ct = clip(0.08 * t, 0.0008, 0.003)
        over = clip(0.02 * min(w, d), 0.001, 0.004) * rng.uniform(0.8, 1.2)
        rx = clip(0.2 * t, 0.001, 0.1 * w)
        parts = [
            Part("spine", _cyl_y((-hw + rx, 0, 0), rx, ht, d, ROUND_SEGMENTS)),
            Part("back_cover", box_between((-hw + rx, -hd, -ht), (hw, hd, -ht + ct))),
            Part("front_cover", box_between((-hw + rx, -hd, ht - ct), (hw, hd, ht))),
            Part(
                "pages",
                box_between(
                    (-hw + rx, -hd + over, -ht + ct - 1e-4), (hw - over, hd - over, ht - ct + 1e-4)
                ),
            ),
        ]
    else:
        ct = clip(0.03 * t, 0.0004, 0.0012)
        inset = clip(0.01 * min(w, d), 0.0005, 0.002) * rng.uniform(0.8, 1.2)
        parts = [
            Part("spine", box_between((-hw, -hd, -ht), (-hw + ct, hd, ht))),
            Part("back_cover", box_between((-hw, -hd, -ht), (hw, hd, -ht + ct))),
            Part("front_cover", box_between((-hw, -hd, ht - ct), (hw, hd, ht))),
            Part(
                "pages",
                box_between(
                    (-hw + ct - 1e-4, -hd + inset, -ht + ct - 1e-4),
                    (hw - inset, hd - inset, ht - ct + 1e-4),
                ),
            ),
        ]
    return _pose(parts, _STAND_BOOK) if standing else parts


_STAND_FACE = np.array([[1.0, 0.0, 0.0], [0.0, 0.0, -1.0], [0.0, 1.0, 0.0]])
"""Canonical flat cushion (thickness along z) -> standing with its face toward +y."""


def _pillow_body(a: float, b: float, ht: float, p: float, puff: float) -> Mesh:
    """Puffy cushion of half-extents a (x), b (y), ht (z): a seam ring (superellipse,
    exponent p) at z = 0 and nested rings rising toward the middle. ``puff`` in (0, 1]:
    how soon the thickness builds up from the seam."""
    pts = [np.c_[_superellipse(a, b, 24, p), np.zeros(24)]]
    for k in (0.9, 0.7, 0.45, 0.2):
        h = ht * (1.0 - k**2) ** (0.5 * puff)
        ring = _superellipse(k * a, k * b, 16, p)
        pts += [np.c_[ring, np.full(16, h)], np.c_[ring, np.full(16, -h)]]
    pts.append([[0.0, 0.0, ht], [0.0, 0.0, -ht]])
    return hull(np.concatenate(pts))


PILLOW_REST = 0.75
"""A lying pillow rests on a flat underside: what lay below this share of its half
thickness is pressed flat (the rest of its lower half stretched to keep its box), as a
pillow's own weight flattens it. A rigid pillow with a domed (or, a bolster, round)
underside rocked 2-4 cm on a mattress in the stability simulation: 11 of 48 in 30
bedrooms."""


@register("pillow", variants=3)
def pillow(size, rng, style, support_heights):
    """Pillow: a puffy rectangle with pointed corners and piping along its seam (0), a round
    tufted cushion with piping and a button (1), or a bolster roll with buttoned ends (2).
    Lies flat on a pressed-flat underside (:data:`PILLOW_REST`, :func:`rest_flat`), or
    stands facing +y when size z > size y."""
    standing = size[2] > size[1]
    w, d, t = (size[0], size[2], size[1]) if standing else size
    a, b, ht = w / 2, d / 2, t / 2
    pr = clip(0.05 * t, 0.0015, 0.008)
    puff = rng.uniform(0.6, 1.0)
    parts: list[Part] = []
    if style in (0, 1):
        p = 3.2 if style == 0 else 2.0
        parts.append(Part("body", _pillow_body(a - pr, b - pr, ht, p, puff)))
        seam = np.c_[_superellipse(a - pr, b - pr, 16, p), np.zeros(16)]
        parts += [Part(f"piping_{i}", m) for i, m in enumerate(_loop_rods(seam, pr))]
        if style == 1:
            br = clip(0.05 * min(w, d), 0.004, 0.02)
            parts.append(Part("button", _ell((0, 0, ht - 0.3 * br), (br, br, 0.5 * br))))
    else:
        cap = 0.06 * w
        parts.append(Part("body", _cyl_x((0, 0, 0), b, ht, w - 2 * cap, FINE_SEGMENTS)))
        for i, sgn in enumerate((-1, 1)):
            x = sgn * (a - cap)
            parts.append(
                Part(
                    f"end_{i}", _ell((x, 0, 0), (cap, 0.97 * b, 0.97 * ht), segments=FINE_SEGMENTS)
                )
            )
            ring = np.c_[
                np.full(12, x),
                b * np.cos(np.linspace(0, _TAU, 12, endpoint=False)),
                ht * np.sin(np.linspace(0, _TAU, 12, endpoint=False)),
            ]
            parts += [Part(f"piping_{i}_{k}", m) for k, m in enumerate(_loop_rods(ring, pr))]
            br = 0.2 * min(b, ht)
            parts.append(
                Part(f"button_{i}", _ell((sgn * (a - 0.3 * br), 0, 0), (0.3 * br, br, br * ht / b)))
            )
    return _pose(parts, _STAND_FACE) if standing else rest_flat(parts, ht, PILLOW_REST)


@register("box", variants=2)
def cardboard_box(size, rng, style, support_heights):
    """Cardboard box: open with its four flaps folded outward (0), or closed and taped
    across the top (1)."""
    sx, sy, sz = size
    hx, hy, hz = size / 2
    if style == 1:
        tt = clip(0.004 * sz, 0.0005, 0.002)  # tape thickness
        tw = clip(0.15 * sx, 0.01, 0.06)
        return [
            Part("body", box_between((-hx, -hy + tt, -hz), (hx, hy - tt, hz - tt))),
            Part("tape_top", box_between((-tw / 2, -hy, hz - tt - 1e-4), (tw / 2, hy, hz))),
            Part(
                "tape_front",
                box_between((-tw / 2, hy - tt - 1e-4, hz - 0.3 * sz), (tw / 2, hy, hz)),
            ),
            Part(
                "tape_back",
                box_between((-tw / 2, -hy, hz - 0.3 * sz), (tw / 2, -hy + tt + 1e-4, hz)),
            ),
        ]
    wt = clip(0.012 * min(sx, sy), 0.001, 0.006)
    ang = np.radians(rng.uniform(25.0, 45.0))  # flaps lean out from vertical
    fl = min(0.28 * min(sx, sy), 0.45 * sz)
    bx, by = sx - 2 * fl * np.sin(ang), sy - 2 * fl * np.sin(ang)
    bh = sz - fl * np.cos(ang)
    ztop = -hz + bh
    parts = [Part("bottom", box_between((-bx / 2, -by / 2, -hz), (bx / 2, by / 2, -hz + wt)))]
    parts += [
        Part("wall_front", box_between((-bx / 2, by / 2 - wt, -hz), (bx / 2, by / 2, ztop))),
        Part("wall_back", box_between((-bx / 2, -by / 2, -hz), (bx / 2, -by / 2 + wt, ztop))),
        Part("wall_left", box_between((-bx / 2, -by / 2, -hz), (-bx / 2 + wt, by / 2, ztop))),
        Part("wall_right", box_between((bx / 2 - wt, -by / 2, -hz), (bx / 2, by / 2, ztop))),
    ]
    for name, rot, hinge, dims in (
        ("flap_front", _rot_x(-ang), (0, by / 2 - wt / 2, ztop), (bx, wt, fl)),
        ("flap_back", _rot_x(ang), (0, -by / 2 + wt / 2, ztop), (bx, wt, fl)),
        ("flap_right", _rot_y(ang), (bx / 2 - wt / 2, 0, ztop), (wt, by, fl)),
        ("flap_left", _rot_y(-ang), (-bx / 2 + wt / 2, 0, ztop), (wt, by, fl)),
    ):
        c = np.asarray(hinge) + rot[:, 2] * fl / 2
        parts.append(Part(name, box(c, dims, rot)))
    return parts


@register("statue", variants=2)
def statue(size, rng, style, support_heights):
    """Figurine on a plinth: abstract stacked ellipsoids (0) or a bust, head and shoulders
    facing +y (1)."""
    sx, sy, sz = size
    hx, hy, hz = size / 2
    plinth_h = sz * rng.uniform(0.08, 0.13)
    z0 = -hz + plinth_h
    parts: list[Part] = []
    if style == 0:
        parts.append(Part("plinth", box_between((-hx, -hy, -hz), (hx, hy, z0 - 0.3 * plinth_h))))
        parts.append(
            Part(
                "plinth_top", box_between((-0.85 * hx, -0.85 * hy, -hz), (0.85 * hx, 0.85 * hy, z0))
            )
        )
        n = int(rng.integers(3, 5))
        slots = rng.uniform(0.7, 1.3, n)
        slots *= (hz - z0) / slots.sum()
        top = z0
        for i, h in enumerate(slots):
            rz = 0.62 * h  # overlap the neighbours so the stack reads as one figure
            cz = top + h / 2 if i < n - 1 else hz - rz
            shrink = 1.0 - 0.12 * i
            r = (hx * shrink * rng.uniform(0.55, 0.8), hy * shrink * rng.uniform(0.55, 0.8), rz)
            off = rng.uniform(-0.08, 0.08, 2) * (hx, hy)
            parts.append(Part(f"stone_{i}", _ell((off[0], off[1], cz), r, rings=8)))
            top += h
        return parts
    parts.append(
        Part("plinth", _cyl_z((0, 0, -hz + plinth_h / 2), 0.7 * hx, hy, plinth_h, FINE_SEGMENTS))
    )
    # torso: a tapered trunk up to rounded shoulders
    z_sh = z0 + 0.3 * sz
    t = np.linspace(0.0, _TAU, FINE_SEGMENTS, endpoint=False)
    dome = [
        np.c_[
            hx * np.cos(t) * np.cos(phi),
            0.6 * hy * np.sin(t) * np.cos(phi),
            np.full_like(t, z_sh + 0.12 * sz * np.sin(phi)),
        ]
        for phi in np.radians([0.0, 35.0, 65.0, 90.0])
    ]
    waist = np.c_[0.62 * hx * np.cos(t), 0.48 * hy * np.sin(t), np.full_like(t, z0)]
    parts.append(Part("torso", hull(np.concatenate(dome + [waist]))))
    head_rz = 0.2 * sz
    head_c = (0.0, 0.08 * hy, hz - head_rz)
    neck_r = 0.2 * hx
    parts.append(
        Part(
            "neck",
            _cyl_z(
                (0, 0.04 * hy, 0.5 * (z_sh + head_c[2])),
                neck_r,
                min(neck_r, 0.4 * hy),
                head_c[2] - z_sh,
            ),
        )
    )
    parts.append(Part("head", _ell(head_c, (0.45 * hx, 0.6 * hy, head_rz), rings=8)))
    parts.append(
        Part(
            "nose",
            _ell(
                (0.0, head_c[1] + 0.58 * hy, head_c[2] - 0.1 * head_rz),
                (0.06 * hx, 0.1 * hy, 0.2 * head_rz),
            ),
        )
    )
    parts.append(
        Part(
            "hair",
            _ell(
                (0.0, head_c[1] - 0.1 * hy, head_c[2] + 0.22 * head_rz),
                (0.46 * hx, 0.55 * hy, 0.8 * head_rz),
                rings=8,
            ),
        )
    )
    return parts


@register("alarm_clock", variants=2)
def alarm_clock(size, rng, style, support_heights):
    """Alarm clock facing +y: a round twin-bell clock on splayed feet (0) or a digital clock
    with its display on a backward-sloping face (1)."""
    sx, sy, sz = size
    hx, hy, hz = size / 2
    if style == 1:
        bh = clip(0.04 * sz, 0.002, 0.008)  # buttons on top
        top = hz - bh
        slope_run = 0.3 * sy * rng.uniform(0.8, 1.2)  # the face leans back by this much
        bev = 0.06 * min(sx, sz)
        pts = []
        for sxx in (-1, 1):
            x_in = sxx * (hx - bev)
            pts += [
                (sxx * hx, -hy, -hz),
                (sxx * hx, hy, -hz),
                (sxx * hx, -hy, top - bev),
                (x_in, -hy, top),
                (x_in, hy - slope_run, top),
                (sxx * hx, hy - slope_run * (1 - bev / sz), top - bev),
            ]
        parts = [Part("body", hull(pts))]
        slope = np.arctan2(slope_run, sz - bh)
        rot = _rot_x(slope)  # local y -> the face normal, local z -> up the face
        face_len = np.hypot(slope_run, top + hz)
        dt = clip(0.02 * sy, 0.001, 0.004)
        c = np.array([0.0, hy - slope_run / 2, (top - hz) / 2]) + rot[:, 1] * (dt / 2 - 1e-4)
        parts.append(Part("display", box(c, (0.78 * sx, dt, 0.55 * face_len), rot)))
        for i, x in enumerate((-0.2 * sx, 0.05 * sx)):
            parts.append(
                Part(
                    f"button_{i}",
                    box_between((x, -0.35 * hy, top - 1e-4), (x + 0.15 * sx, -0.05 * hy, hz)),
                )
            )
        return parts
    # twin-bell clock, laid out in units of the body radius R: 2.65 R tall; the bells sit
    # 40..65 degrees off the top, further out on a wider box, so that it is filled
    big_r = min(sz / 2.65, hx / 1.04)
    bell_a = np.arcsin(np.clip(hx / big_r - 0.4, np.sin(np.radians(40)), np.sin(np.radians(65))))
    zc = -hz + 1.33 * big_r
    knob_l = 0.15 * sy
    y0, y1 = -hy + 0.8 * knob_l, hy - 0.05 * sy  # body depth
    yc = 0.5 * (y0 + y1)
    parts = [
        Part("body", _cyl_y((0, yc, zc), big_r, big_r, y1 - y0, FINE_SEGMENTS)),
        Part(
            "bezel",
            _cyl_y(
                (0, y1 - 0.07 * (y1 - y0), zc),
                1.04 * big_r,
                1.04 * big_r,
                0.16 * (y1 - y0),
                FINE_SEGMENTS,
            ),
        ),
        Part(
            "face",
            _cyl_y((0, hy - 0.03 * sy, zc), 0.86 * big_r, 0.86 * big_r, 0.036 * sy, FINE_SEGMENTS),
        ),
        Part(
            "wind_key",
            _cyl_y((0, -hy + knob_l / 2, zc), 0.2 * big_r, 0.2 * big_r, knob_l, ROD_SEGMENTS),
        ),
    ]
    for name, length, width in (("hour_hand", 0.5, 0.08), ("minute_hand", 0.75, 0.06)):
        rot = _rot_y(rng.uniform(0.0, _TAU))
        c = np.array([0.0, hy - 0.008 * sy, zc]) + rot[:, 2] * length * big_r / 2
        parts.append(Part(name, box(c, (width * big_r, 0.016 * sy, length * big_r), rot)))
    rb = 0.4 * big_r
    for i, sgn in enumerate((-1, 1)):
        bc = (sgn * 1.0 * big_r * np.sin(bell_a), yc, zc + 1.0 * big_r * np.cos(bell_a))
        parts.append(
            Part(f"bell_{i}", _ell(bc, (rb, min(rb, 0.5 * (y1 - y0)), rb), _rot_y(sgn * bell_a)))
        )
        a = bell_a - np.radians(2.0)
        start = np.array([sgn * 0.7 * big_r * np.sin(a), yc, zc - 0.7 * big_r * np.cos(a)])
        end = np.array([sgn * 1.15 * big_r * np.sin(a), yc, -hz + 0.1 * big_r])
        parts.append(Part(f"leg_{i}", _rod(start, end, 0.07 * big_r)))
        # flat pads, deep along y: two round feet touch at two points on a line and the
        # clock tips over (measured in MuJoCo); pads give a rectangle to stand on
        pad = (0.24 * big_r, 0.8 * (y1 - y0), 0.12 * big_r)
        parts.append(Part(f"foot_{i}", box((end[0], yc, -hz + pad[2] / 2), pad)))
    parts.append(
        Part("hammer", _rod((0, yc, zc + 0.9 * big_r), (0, yc, zc + 1.22 * big_r), 0.06 * big_r))
    )
    parts.append(Part("hammer_head", _ell((0, yc, zc + 1.22 * big_r), (0.1 * big_r,) * 3)))
    return parts


@register("tissue_box", variants=2)
def tissue_box(size, rng, style, support_heights):
    """Tissue box with a tissue tuft rising from its oval slot: a plain box (0) or a box with
    bevelled top edges (1)."""
    sx, sy, sz = size
    hx, hy, hz = size / 2
    body_h = sz * rng.uniform(0.62, 0.72)
    zt = -hz + body_h
    if style == 0:
        parts = [Part("body", box_between((-hx, -hy, -hz), (hx, hy, zt)))]
        srx, sry = 0.33 * sx, 0.2 * sy
    else:
        bev = 0.12 * min(sx, sy, body_h)
        pts = [(a * hx, b * hy, z) for a in (-1, 1) for b in (-1, 1) for z in (-hz, zt - bev)]
        pts += [(a * (hx - bev), b * (hy - bev), zt) for a in (-1, 1) for b in (-1, 1)]
        parts = [Part("body", hull(pts))]
        srx, sry = 0.25 * sx, 0.25 * sy
    parts.append(Part("slot", _cyl_z((0, 0, zt), srx, sry, 0.02 * body_h, FINE_SEGMENTS)))
    tuft_h = hz - zt
    tt = clip(0.006 * min(sx, sy), 0.0008, 0.003)  # a sheet's apparent thickness
    for i in range(2):
        # two thin, slightly leaning sheets crossing at an angle
        rot = _rot_z((-1) ** i * rng.uniform(0.2, 0.45))
        lean = rng.uniform(-0.25, 0.25) * sry
        pts = []
        for u, z in ((0.45, zt - 0.02 * body_h), (0.9, zt + 0.55 * tuft_h), (0.35, hz)):
            v = lean * (z - zt) / tuft_h
            pts += [(su * u * srx, v + e, z) for su in (-1, 1) for e in (-tt, tt)]
        pts += [(rng.uniform(-0.3, 0.3) * srx, lean + e, hz) for e in (-tt, tt)]
        parts.append(Part(f"tissue_{i}", hull(np.asarray(pts) @ rot.T)))
    return parts


def _teddy_unit(sitting: bool) -> list[Part]:
    """A teddy bear in the unit box [-0.5, 0.5]^3 facing +y (ellipsoids only)."""
    e = _ell
    parts = []
    if sitting:
        parts += [Part("body", e((0, -0.15, -0.17), (0.3, 0.35, 0.31), rings=8))]
        for i, s in enumerate((-1, 1)):
            parts += [
                Part(f"leg_{i}", e((s * 0.2, 0.14, -0.37), (0.13, 0.3, 0.12))),
                Part(f"foot_{i}", e((s * 0.2, 0.42, -0.36), (0.11, 0.06, 0.12))),
                Part(
                    f"arm_{i}",
                    e((s * 0.36, -0.02, -0.1), (0.13, 0.13, 0.2), _rot_y(s * 0.5) @ _rot_x(0.5)),
                ),
            ]
        head = (0.0, -0.1, 0.24)
    else:
        parts += [Part("body", e((0, -0.1, -0.06), (0.27, 0.34, 0.26), rings=8))]
        for i, s in enumerate((-1, 1)):
            parts += [
                Part(f"leg_{i}", e((s * 0.13, -0.05, -0.32), (0.13, 0.16, 0.17))),
                Part(f"foot_{i}", e((s * 0.13, 0.12, -0.44), (0.12, 0.26, 0.06))),
                # arms reach forward, as if for a hug
                Part(
                    f"arm_{i}",
                    e((s * 0.3, 0.1, -0.02), (0.11, 0.22, 0.15), _rot_y(s * 0.3) @ _rot_x(0.35)),
                ),
            ]
        head = (0.0, -0.05, 0.26)
    hx_, hy_, hz_ = head
    parts += [Part("head", e(head, (0.24, 0.22, 0.2), rings=8))]
    for i, s in enumerate((-1, 1)):
        parts += [
            Part(f"ear_{i}", e((s * 0.17, hy_ - 0.03, hz_ + 0.17), (0.08, 0.04, 0.07))),
            Part(f"eye_{i}", e((s * 0.08, hy_ + 0.19, hz_ + 0.06), (0.025, 0.02, 0.025))),
        ]
    parts += [
        Part("snout", e((0.0, hy_ + 0.2, hz_ - 0.05), (0.1, 0.08, 0.07))),
        Part("nose", e((0.0, hy_ + 0.28, hz_ - 0.02), (0.035, 0.02, 0.025))),
    ]
    return parts


@register("teddy_bear", variants=2)
def teddy_bear(size, rng, style, support_heights):
    """Teddy bear facing +y, all ellipsoids: sitting with legs forward (0) or standing (1)."""
    parts = _teddy_unit(sitting=style == 0)
    # a little jitter of the head tilt keeps a shelf of bears from looking cloned
    tilt = _rot_y(rng.uniform(-0.12, 0.12))
    centre = np.array([0.0, 0.0, 0.25])  # about the neck
    parts = [
        Part(p.name, p.mesh.transformed(tilt, centre - tilt @ centre))
        if p.name in ("head", "snout", "nose") or p.name.startswith(("ear", "eye"))
        else p
        for p in parts
    ]
    # all ellipsoids touch the ground at points and the bear rolls over (measured in
    # MuJoCo): a flat felt pad under the body gives it something to sit or stand on
    hx, hy, hz = np.asarray(size) / 2
    pad = (0.9 * hx, 0.9 * hy, 0.04 * hz)
    return [*_scaled(parts, size), Part("pad", box((0.0, 0.0, -hz + pad[2] / 2), pad))]


# -- flat hand-held things: remote, phone, card, watch, keys, disc ----------------------------
def _bevelled_slab(w: float, d: float, z0: float, z1: float, r: float, bevel: float) -> Mesh:
    """Rounded slab from z0 to z1 whose bottom edge is bevelled in by ``bevel``: the soft
    underside of a remote or a phone. Width w (x), depth d (y)."""
    lo = _rounded_rect(w - 2 * bevel, d - 2 * bevel, max(r - bevel, 1e-4))
    hi = _rounded_rect(w, d, r)
    zm = z0 + 0.45 * (z1 - z0)
    return hull(
        np.r_[
            np.c_[lo, np.full(len(lo), z0)],
            np.c_[hi, np.full(len(hi), zm)],
            np.c_[hi, np.full(len(hi), z1)],
        ]
    )


@register("remote_control", variants=2)
def remote_control(size, rng, style, support_heights):
    """TV remote lying flat along its box's longer side, buttons up, power button at the
    far end: a keypad remote (0) or a slim remote with a round pad and few buttons (1)."""
    csize, rot = _flat_frame(size)
    w, length, t = csize
    hw, hl, ht = csize / 2
    bh = clip(0.15 * t, 0.0006, 0.003)  # button height
    top = ht - bh
    corner = 0.2 * w if style == 0 else 0.49 * w
    parts = [Part("body", _bevelled_slab(w, length, -ht, top, corner, 0.12 * min(w, t)))]

    def button(name: str, x: float, y: float, r: float) -> Part:
        return Part(name, _cyl_z((x, y, top + bh / 2 - 1e-4), r, r, bh + 2e-4, ROD_SEGMENTS))

    def key(name: str, x: float, y: float, kw: float, kd: float) -> Part:
        return Part(name, box((x, y, top + bh / 2 - 1e-4), (kw, kd, bh + 2e-4)))

    parts.append(button("power_button", 0.22 * w, hl - 0.07 * length, 0.09 * w))
    if style == 0:
        parts.append(
            Part(
                "pad",
                _cyl_z(
                    (0, hl - 0.3 * length, top + 0.3 * bh),
                    0.32 * w,
                    0.32 * w,
                    0.6 * bh,
                    ROUND_SEGMENTS,
                ),
            )
        )
        parts.append(button("ok_button", 0.0, hl - 0.3 * length, 0.12 * w))
        for r in range(4):
            for c in range(3):
                parts.append(
                    key(
                        f"key_{r}_{c}",
                        (c - 1) * 0.27 * w,
                        hl - (0.5 + 0.09 * r) * length,
                        0.2 * w,
                        0.055 * length,
                    )
                )
        for i, x in enumerate((-0.25 * w, 0.25 * w)):
            parts.append(key(f"rocker_{i}", x, hl - 0.88 * length, 0.16 * w, 0.12 * length))
    else:
        yc = hl - 0.28 * length
        ring = _ring_segments(0.2 * w, 0.36 * w, top - 1e-4, ht, 8)
        parts += [Part(f"pad_{i}", m.transformed(None, (0, yc, 0))) for i, m in enumerate(ring)]
        parts.append(button("ok_button", 0.0, yc, 0.14 * w))
        for i in range(3):
            parts.append(button(f"button_{i}", (i - 1) * 0.28 * w, hl - 0.5 * length, 0.09 * w))
        parts.append(key("volume", 0.0, hl - 0.68 * length, 0.16 * w, 0.14 * length))
    return _pose(parts, rot)


@register("cell_phone", variants=2)
def cell_phone(size, rng, style, support_heights):
    """Smartphone lying flat, screen up: edge-to-edge screen with a camera notch (0) or a
    screen framed by bezels with a round home button (1)."""
    csize, rot = _flat_frame(size)
    w, length, t = csize
    hw, hl, ht = csize / 2
    gt = clip(0.1 * t, 0.0002, 0.001)  # glass standing proud of the frame
    sb = clip(0.012 * w, 0.0003, 0.001)  # side buttons standing out of the frame
    r = (0.13 if style == 0 else 0.09) * w
    parts = [Part("body", _bevelled_slab(w - 2 * sb, length, -ht, ht - gt, r, 0.1 * t))]
    if style == 0:
        b = 0.035 * w
        # the camera notch stands a hair above the glass so that the two never coincide
        parts.append(
            Part(
                "screen",
                _rounded_block(
                    (0, 0, ht - 0.55 * gt), w - 2 * sb - 2 * b, length - 2 * b, 0.9 * gt, r - b
                ),
            )
        )
        parts.append(
            Part(
                "notch",
                box((0, hl - b - 0.015 * length, ht - gt / 2), (0.3 * w, 0.03 * length, gt)),
            )
        )
    else:
        bx, by = 0.06 * w, 0.13 * length
        parts.append(
            Part("screen", box((0, 0, ht - gt / 2), (w - 2 * sb - 2 * bx, length - 2 * by, gt)))
        )
        hb = 0.3 * by
        parts.append(
            Part("home_button", _cyl_z((0, -hl + by / 2, ht - gt / 2), hb, hb, gt, ROUND_SEGMENTS))
        )
        parts.append(Part("speaker", box((0, hl - by / 2, ht - gt / 2), (0.22 * w, 0.12 * by, gt))))
    bt = 0.35 * t
    parts.append(Part("power_key", box((hw - sb, 0.2 * length, 0), (2 * sb, 0.1 * length, bt))))
    parts.append(Part("volume_key", box((-hw + sb, 0.25 * length, 0), (2 * sb, 0.16 * length, bt))))
    return _pose(parts, rot)


@register("credit_card", variants=2)
def credit_card(size, rng, style, support_heights):
    """Bank card lying flat: front up with chip, embossed number and logo (0) or back up with
    the magnetic stripe and signature panel (1)."""
    csize, rot = _flat_frame(size)
    w, length, t = csize
    hw, hl, ht = csize / 2
    dh = 0.3 * t  # relief of the print and chip
    parts = [Part("card", _rounded_block((0, 0, -dh / 2), w, length, t - dh, 0.06 * w))]
    zc = ht - dh / 2

    def plate(name: str, x: float, y: float, pw: float, pd: float) -> Part:
        return Part(name, box((x, y, zc - 1e-5), (pw, pd, dh + 2e-5)))

    if style == 0:
        # laid out for a card read landscape, its long side along canonical y
        parts.append(plate("chip", 0.05 * w, -0.3 * length, 0.2 * w, 0.14 * length))
        for g in range(4):
            parts.append(
                plate(
                    f"digits_{g}", -0.15 * w, (-0.33 + 0.22 * g) * length, 0.08 * w, 0.18 * length
                )
            )
        parts.append(plate("name", -0.32 * w, -0.2 * length, 0.05 * w, 0.45 * length))
        for i, dy in enumerate((-0.04, 0.04)):
            parts.append(
                Part(
                    f"logo_{i}",
                    _cyl_z(
                        (-0.3 * w, (0.33 + dy) * length, zc), 0.09 * w, 0.09 * w, dh, ROUND_SEGMENTS
                    ),
                )
            )
    else:
        parts.append(plate("stripe", 0.28 * w, 0.0, 0.18 * w, length - 1e-4))
        parts.append(plate("signature", 0.0, -0.12 * length, 0.12 * w, 0.55 * length))
        parts.append(plate("hologram", -0.25 * w, 0.3 * length, 0.22 * w, 0.18 * length))
    return _pose(parts, rot)


def _strip_between(p0: np.ndarray, p1: np.ndarray, width: float, thick: float) -> Mesh:
    """A flat strip (box) from p0 (3,) to p1 (3,) in a plane x = const: ``width`` along x,
    ``thick`` across the strip."""
    d = np.asarray(p1, dtype=float) - np.asarray(p0, dtype=float)
    rot = _rot_x(np.arctan2(-d[1], d[2]))  # local z along the strip
    return box((np.asarray(p0) + np.asarray(p1)) / 2, (width, thick, np.linalg.norm(d)), rot)


def _watch_face(
    style: int, rng: np.random.Generator, z0: float, z1: float, cw: float, cd: float
) -> list[Part]:
    """The watch head between heights z0 and z1, ``cw`` x ``cd`` across: a round case with
    crystal and hands (style 0) or a square case with a display (style 1)."""
    h = z1 - z0
    case_h = 0.7 * h
    if style == 1:
        return [
            Part(
                "case", _rounded_block((0, 0, z0 + case_h / 2), cw, cd, case_h, 0.2 * min(cw, cd))
            ),
            Part(
                "display", box((0, 0, z1 - 0.15 * h - 1e-5), (0.72 * cw, 0.72 * cd, 0.3 * h + 2e-5))
            ),
        ]
    rc = 0.5 * min(cw, cd)
    parts = [
        Part("case", _cyl_z((0, 0, z0 + case_h / 2), rc, rc, case_h, FINE_SEGMENTS)),
        Part("crystal", _cyl_z((0, 0, z1 - 0.2 * h), 0.86 * rc, 0.86 * rc, 0.2 * h, FINE_SEGMENTS)),
        Part(
            "crown",
            _cyl_x((rc * 1.04, 0, z0 + case_h / 2), 0.15 * rc, 0.15 * rc, 0.16 * rc, ROD_SEGMENTS),
        ),
    ]
    for name, frac in (("hour_hand", 0.45), ("minute_hand", 0.7)):
        hand = box((0, frac * rc * 0.86 / 2, z1 - 0.1 * h), (0.07 * rc, frac * rc * 0.86, 0.2 * h))
        parts.append(Part(name, hand.transformed(_rot_z(rng.uniform(0, _TAU)), None)))
    return parts


@register("watch", variants=2)
def watch(size, rng, style, support_heights):
    """Wristwatch: a round analog dial on a leather strap (0) or a square digital case on a
    link bracelet (1). When the box is flat the watch lies dial up with its band spread
    along the box's longer side; when the box is tall enough the band is closed and
    stands as a loop under the watch head, which faces up."""
    csize, rot = _flat_frame(size)
    w, length, t = csize
    hw, hl, ht = csize / 2
    if t < 0.35 * length:
        # lying open: strap halves spread out, buckle at -y
        head_d = min(w, 0.4 * length)
        st = clip(0.3 * t, 0.0008, 0.004)  # strap thickness
        sw = 0.62 * w
        parts = _watch_face(style, rng, -ht, ht, 0.9 * w if style == 1 else w, head_d)
        ends = ((0.35 * head_d, hl), (-hl + 0.06 * length, -0.35 * head_d))
        for i, (y0, y1) in enumerate(ends):
            if style == 0:
                parts.append(
                    Part(f"strap_{i}", box_between((-sw / 2, y0, -ht), (sw / 2, y1, -ht + st)))
                )
                continue
            n = int(np.clip(round((y1 - y0) / (0.12 * w)), 2, 8))
            edges = np.linspace(y0, y1, n + 1)
            gap = 0.1 * (edges[1] - edges[0])
            parts += [
                Part(
                    f"link_{i}_{k}",
                    box_between((-sw / 2, a + gap / 2, -ht), (sw / 2, b - gap / 2, -ht + st)),
                )
                for k, (a, b) in enumerate(zip(edges[:-1], edges[1:]))
            ]
        bk = 0.07 * length  # the clasp at the end of the -y strap
        for i, x in enumerate((-0.55 * sw, 0.55 * sw)):
            parts.append(
                Part(f"buckle_{i}", box((x, -hl + bk / 2, -ht + st), (0.1 * sw, bk, 1.5 * st)))
            )
        parts.append(
            Part("buckle_end", box((0, -hl + 0.1 * bk, -ht + st), (1.2 * sw, 0.2 * bk, 1.5 * st)))
        )
        return _pose(parts, rot)
    # closed band standing as a loop (in the y-z plane) under the head
    head_h = 0.2 * t
    bt = clip(0.06 * t, 0.001, 0.004)
    bw = 0.62 * w
    a, b = hl - bt / 2, (t - head_h) / 2 - bt / 2
    zc = -ht + bt / 2 + b
    n = 14
    ang = np.linspace(0.0, _TAU, n + 1)[:-1] + np.pi / n
    ring = np.c_[np.zeros(n), a * np.cos(ang), zc + b * np.sin(ang)]
    parts = [
        Part(f"band_{i}", _strip_between(p, q, bw, bt))
        for i, (p, q) in enumerate(zip(ring, np.roll(ring, -1, axis=0)))
    ]
    top = zc + b
    parts += _watch_face(style, rng, top - 0.2 * head_h, ht, 0.9 * w, min(0.5 * length, w))
    return _pose(parts, rot)


def _key(
    z0: float, thick: float, length: float, teeth: int, rng: np.random.Generator
) -> list[Part]:
    """A flat key along +y whose ring hole is at the origin: bow, blade and teeth, between
    z0 and z0 + thick."""
    z1 = z0 + thick
    bow_w, bow_d = 0.36 * length, 0.3 * length
    parts = [
        Part(
            "bow",
            _rounded_block(
                (0, 0.1 * length, (z0 + z1) / 2), bow_w, bow_d, thick, 0.4 * bow_w, arc=3
            ),
        ),
        Part(
            "blade", box_between((-0.06 * length, 0.24 * length, z0), (0.07 * length, length, z1))
        ),
    ]
    ys = np.linspace(0.42, 0.9, teeth) * length
    for i, y in enumerate(ys):
        d = rng.uniform(0.03, 0.06) * length
        parts.append(
            Part(
                f"tooth_{i}",
                box_between(
                    (0.07 * length - 1e-4, y - 0.04 * length, z0),
                    (0.07 * length + d, y + 0.03 * length, z1),
                ),
            )
        )
    return parts


@register("key_chain", variants=2)
def key_chain(size, rng, style, support_heights):
    """Keys on a split ring lying flat: two keys (0) or three keys and a fob (1)."""
    csize, rot = _flat_frame(size)
    w, length, t = csize
    hw, hl, ht = csize / 2
    rr = 0.13 * length  # ring radius
    wire = 0.035 * length
    ring_c = np.array([0.0, -hl + rr + wire, 0.0])
    ang = np.linspace(0.0, _TAU, 11)[:-1]
    loop = np.c_[rr * np.cos(ang), rr * np.sin(ang), np.zeros(10)] + ring_c
    parts = [
        Part(
            f"ring_{i}",
            box(
                ((p + q) / 2)[:2].tolist() + [-ht + 0.25 * t],
                (np.linalg.norm(q - p) + wire, wire, 0.5 * t),
                _rot_z(np.arctan2(*(q - p)[[1, 0]])),
            ),
        )
        for i, (p, q) in enumerate(zip(loop, np.roll(loop, -1, axis=0)))
    ]
    key_len = length - 2 * rr - wire
    n = 2 if style == 0 else 3
    spread = np.radians(rng.uniform(18.0, 28.0))
    angles = np.linspace(-spread, spread, n) + rng.uniform(-0.1, 0.1)
    thick = 0.4 * t
    for k, a in enumerate(angles):
        anchor = ring_c + rr * np.array([np.sin(a), np.cos(a), 0.0])
        key = _key(-ht + (0.6 * k / max(n - 1, 1)) * t, thick, key_len, 3, rng)
        parts += [Part(f"key_{k}_{p.name}", p.mesh.transformed(_rot_z(-a), anchor)) for p in key]
    if style == 1:
        a = np.radians(rng.uniform(115.0, 135.0))  # the fob hangs off to one side
        anchor = ring_c + rr * np.array([np.sin(a), np.cos(a), 0.0])
        fob = _rounded_block(
            (0, 0.45 * key_len * 0.6, -ht + 0.5 * t),
            0.4 * key_len,
            0.6 * key_len,
            0.9 * t,
            0.15 * key_len,
        )
        parts.append(Part("fob", fob.transformed(_rot_z(-a), anchor)))
    return _pose(parts, rot)


@register("cd", variants=2)
def cd(size, rng, style, support_heights):
    """Compact disc lying flat: a bare disc with its centre hole (0) or a jewel case with
    hinge and cover insert (1)."""
    sx, sy, sz = size
    hx, hy, hz = size / 2
    if style == 0:
        hole = 0.125  # share of the radius (15 mm hole in a 120 mm disc)
        parts = [
            Part(f"disc_{i}", m)
            for i, m in enumerate(
                _ring_segments(hole * hx, hx, -hz, hz - 0.3 * sz, 16, hole * hy, hy)
            )
        ]
        parts += [
            Part(f"hub_{i}", m)
            for i, m in enumerate(
                _ring_segments(hole * hx, 0.3 * hx, hz - 0.31 * sz, hz, 8, hole * hy, 0.3 * hy)
            )
        ]
        return parts
    hinge_r = 0.5 * sz
    lid_t = 0.3 * sz
    return [
        Part("tray", box_between((-hx + hinge_r, -hy, -hz), (hx, hy, hz - lid_t))),
        Part("lid", box_between((-hx + hinge_r, -hy, hz - lid_t - 1e-4), (hx, hy, hz))),
        Part("hinge", _cyl_y((-hx + hinge_r, 0, 0), hinge_r, hinge_r, sy, ROD_SEGMENTS)),
        Part(
            "insert",
            box_between(
                (-hx + 3 * hinge_r, -hy + 0.04 * sy, hz - 1e-4),
                (hx - 0.04 * sx, hy - 0.04 * sy, hz + 0.05 * sz),
            ),
        ),
        Part(
            "disc",
            _cyl_z((0.05 * sx, 0, hz + 0.06 * sz), 0.42 * sx, 0.42 * sy, 0.02 * sz, FINE_SEGMENTS),
        ),
    ]


# -- writing things, paper and textiles ------------------------------------------------------
@register("pen", variants=2)
def pen(size, rng, style, support_heights):
    """Pen along its box's longest side (standing tip down when the box is tall): a capped
    ballpoint with a clip on the cap (0) or a click pen with grip, clip and plunger (1)."""
    csize, rot = _long_frame(size)
    w, length, t = csize
    hl = length / 2
    # the barrel rests on the bottom; the clip stands off its top up to the box top
    r = min(0.5 * w, t / 2.25)
    tip_l = 0.07 * length
    y_tip = -hl
    parts = [
        Part("tip", _rod((0, y_tip + tip_l, 0), (0, y_tip, 0), 0.75 * r, 0.12 * r, ROUND_SEGMENTS))
    ]
    if style == 0:
        cap_l = 0.3 * length
        parts += [
            Part(
                "barrel",
                _rod(
                    (0, y_tip + tip_l - 1e-4, 0),
                    (0, hl - 0.04 * length, 0),
                    r,
                    0.9 * r,
                    ROUND_SEGMENTS,
                ),
            ),
            Part(
                "cap",
                _rod(
                    (0, y_tip + 0.6 * tip_l, 0),
                    (0, y_tip + 0.6 * tip_l + cap_l, 0),
                    1.12 * r,
                    1.1 * r,
                    ROUND_SEGMENTS,
                ),
            ),
            Part(
                "end_plug",
                _rod(
                    (0, hl - 0.04 * length - 1e-4, 0), (0, hl, 0), 0.9 * r, 0.7 * r, ROUND_SEGMENTS
                ),
            ),
        ]
        clip_y = (y_tip + 0.6 * tip_l + 0.3 * cap_l, y_tip + 0.6 * tip_l + cap_l)
    else:
        grip_l = 0.25 * length
        parts += [
            Part(
                "grip",
                _rod(
                    (0, y_tip + tip_l - 1e-4, 0),
                    (0, y_tip + tip_l + grip_l, 0),
                    1.05 * r,
                    1.05 * r,
                    ROUND_SEGMENTS,
                ),
            ),
            Part(
                "barrel",
                _rod(
                    (0, y_tip + tip_l + grip_l - 1e-4, 0),
                    (0, hl - 0.06 * length, 0),
                    r,
                    r,
                    ROUND_SEGMENTS,
                ),
            ),
            Part(
                "plunger",
                _rod(
                    (0, hl - 0.06 * length - 1e-4, 0), (0, hl, 0), 0.55 * r, 0.5 * r, ROUND_SEGMENTS
                ),
            ),
        ]
        clip_y = (hl - 0.35 * length, hl - 0.08 * length)
    # the clip rides on top of the barrel (canonical +z)
    parts.append(
        Part("clip", box_between((-0.25 * r, clip_y[0], 0.8 * r), (0.25 * r, clip_y[1], 1.25 * r)))
    )
    lift = (0.0, 0.0, -t / 2 + r)
    return _pose(_pose(_face_down(parts, size), None, lift), rot)


@register("pencil", variants=2)
def pencil(size, rng, style, support_heights):
    """Pencil along its box's longest side (standing point down when the box is tall): a
    hexagonal pencil sharpened to a cone with a ferrule and eraser (0) or an unsharpened-end
    hexagonal pencil without eraser (1)."""
    csize, rot = _long_frame(size)
    w, length, t = csize
    hl = length / 2
    # hexagon circumradius; corners at +-x so that the pencil rests on a flat face
    r = min(0.5 * w, 0.5 * t / np.cos(np.pi / 6))
    hexagon = [(r * np.cos(a), r * np.sin(a)) for a in np.radians(np.arange(0, 360, 60))]

    def hex_section(name: str, y0: float, y1: float) -> Part:
        return Part(name, prism(hexagon, y0, y1).transformed(_Z_TO_Y, None))

    cone_l = 0.1 * length * rng.uniform(0.85, 1.15)
    lead_l = 0.25 * cone_l
    y_body0 = -hl + cone_l
    parts = [
        Part(
            "wood_cone",
            _rod((0, y_body0 + 1e-4, 0), (0, -hl + lead_l, 0), 0.97 * r, 0.3 * r, ROUND_SEGMENTS),
        ),
        Part(
            "lead", _rod((0, -hl + lead_l + 1e-4, 0), (0, -hl, 0), 0.3 * r, 0.05 * r, ROD_SEGMENTS)
        ),
    ]
    if style == 0:
        fer_l, ers_l = 0.06 * length, 0.05 * length
        y_body1 = hl - fer_l - ers_l
        parts += [
            hex_section("body", y_body0, y_body1),
            Part(
                "ferrule",
                _rod(
                    (0, y_body1 - 1e-4, 0), (0, hl - ers_l, 0), 0.95 * r, 0.95 * r, ROUND_SEGMENTS
                ),
            ),
            Part(
                "eraser",
                _rod((0, hl - ers_l - 1e-4, 0), (0, hl, 0), 0.85 * r, 0.8 * r, ROUND_SEGMENTS),
            ),
        ]
    else:
        parts.append(hex_section("body", y_body0, hl))
    return _pose(parts, rot)


@register("newspaper", variants=2)
def newspaper(size, rng, style, support_heights):
    """Newspaper lying flat along its box's longer side: folded, its sheets slightly askew
    with the rounded fold along -x (0), or rolled up with two rubber bands (1)."""
    csize, rot = _flat_frame(size)
    w, length, t = csize
    hw, hl, ht = csize / 2
    if style == 1:
        ry, rz = hw, ht
        band_l = 0.03 * length
        parts = [
            Part("roll", _cyl_y((0, 0, 0), 0.95 * ry, 0.95 * rz, length, FINE_SEGMENTS)),
            Part("edge", box_between((-0.2 * w, -hl, 0.7 * rz), (0.45 * w, hl, 0.93 * rz))),
        ]
        for i, y in enumerate((-0.25 * length, 0.25 * length)):
            parts.append(Part(f"band_{i}", _cyl_y((0, y, 0), ry, rz, band_l, FINE_SEGMENTS)))
        return _pose(parts, rot)
    n = 3
    st = t / n
    fold_r = ht
    parts = [Part("fold", _cyl_y((-hw + fold_r, 0, 0), fold_r, ht, length, ROUND_SEGMENTS))]
    for k in range(n):
        skew = rng.uniform(-0.015, 0.015) * min(w, length)  # sheets never lie quite square
        shrink = 0.015 * k * w
        z0 = -ht + k * st
        parts.append(
            Part(
                f"sheet_{k}",
                box_between(
                    (-hw + fold_r, -hl + abs(skew), z0),
                    (hw - shrink + skew, hl - abs(skew), z0 + st * 1.02),
                ),
            )
        )
    return _pose(parts, rot)


@register("cloth", variants=2)
def cloth(size, rng, style, support_heights):
    """Cleaning cloth lying flat: folded into a square of askew layers (0) or crumpled into
    a heap of irregular folds (1)."""
    sx, sy, sz = size
    hx, hy, hz = size / 2
    parts: list[Part] = []
    if style == 0:
        n = 3
        lt = sz / n
        for k in range(n):
            ang = rng.uniform(-0.06, 0.06)
            scale = 1.0 - 0.05 * k
            poly = _rounded_rect(0.94 * sx * scale, 0.94 * sy * scale, 0.05 * min(sx, sy))
            poly = poly @ _rot_z(ang)[:2, :2].T + rng.uniform(-0.02, 0.02, 2) * (sx, sy)
            parts.append(Part(f"layer_{k}", prism(poly, -hz + k * lt, -hz + (k + 1.02) * lt)))
        parts.append(
            Part("fold", _cyl_y((hx - 0.5 * lt, 0, -hz + lt), 0.5 * lt, lt, 0.9 * sy, ROD_SEGMENTS))
        )
        return parts
    # crumpled: an irregular flat sheet with ridges of fabric gathered on it
    ang = np.sort(rng.uniform(0.0, _TAU, 12))
    rad = rng.uniform(0.75, 1.0, 12)
    rim = np.c_[rad * np.cos(ang), rad * np.sin(ang)]
    rim *= np.array([hx, hy]) / np.abs(rim).max(0)  # the sheet spans the box
    parts.append(
        Part(
            "sheet",
            hull(
                np.r_[np.c_[rim, np.full(12, -hz)], np.c_[0.9 * rim, np.full(12, -hz + 0.25 * sz)]]
            ),
        )
    )
    for k in range(5):
        c = rng.uniform(-0.22, 0.22, 2) * (sx, sy)
        m = min(sx, sy)
        length, width = rng.uniform(0.3, 0.5) * m, rng.uniform(0.14, 0.24) * m
        h = sz * (1.0 if k == 0 else rng.uniform(0.5, 0.9))
        rot = _rot_z(rng.uniform(0.0, np.pi))
        parts.append(
            Part(f"ridge_{k}", _ell((c[0], c[1], -hz + h / 2), (length / 2, width / 2, h / 2), rot))
        )
    return parts


def _draped(w: float, d: float, h: float, bands: bool) -> list[Part]:
    """A cloth hung over a bar, filling the box w (x) by d (y) by h (z) centred at the
    origin: the fold over the bar on top, a long front layer and a shorter back layer,
    optional woven bands near the hem."""
    hw, hd, hh = w / 2, d / 2, h / 2
    lt = clip(0.28 * d, 0.001, 0.015)  # layer thickness
    fold_r = hd
    z_fold = hh - fold_r
    parts = [
        Part("fold", _cyl_x((0, 0, z_fold), hd, fold_r, w, ROUND_SEGMENTS)),
        Part("front_layer", box_between((-hw, hd - lt, -hh), (hw, hd - 0.2 * lt, z_fold))),
        Part("back_layer", box_between((-hw, -hd, -hh + 0.12 * h), (hw, -hd + lt, z_fold))),
    ]
    if bands:
        for i, z in enumerate((-hh + 0.06 * h, -hh + 0.11 * h)):
            parts.append(
                Part(
                    f"band_{i}",
                    box_between((-hw, hd - 1.1 * lt, z - 0.015 * h), (hw, hd, z + 0.015 * h)),
                )
            )
    return parts


def _folded_stack(
    sx: float, sy: float, sz: float, n: int, bands: bool, rng: np.random.Generator
) -> list[Part]:
    """``n`` folded towels stacked in the box: each a slab whose folded edge (at +y) is
    rounded, slightly shifted against the one below. Optional bands along the folded edge."""
    hx, hy, hz = sx / 2, sy / 2, sz / 2
    th = sz / n
    parts = []
    for k in range(n):
        z0 = -hz + k * th
        dx = rng.uniform(-0.02, 0.02) * sx
        r = 0.5 * th
        t = np.linspace(-np.pi / 2, np.pi / 2, 7)
        front = np.c_[hy - r + r * np.cos(t), z0 + r + r * np.sin(t)]
        rb = 0.25 * th  # the back edge is a flatter fold
        back = np.c_[-hy + rb - rb * np.cos(t[::-1]), z0 + r + r * np.sin(t[::-1])]
        polygon = np.r_[front, back]
        section = prism(polygon, -hx + 0.02 * sx + dx, hx - 0.02 * sx + dx)
        parts.append(Part(f"towel_{k}", section.transformed(_Z_TO_X, None)))
        if bands:
            parts.append(
                Part(
                    f"band_{k}",
                    box_between(
                        (-hx + 0.12 * sx + dx, hy - 0.6 * r, z0 + 0.1 * th),
                        (-hx + 0.2 * sx + dx, hy + 0.01 * r, z0 + 0.9 * th),
                    ),
                )
            )
    return parts


def _hangs(size: np.ndarray) -> bool:
    """A towel hangs over a bar when its box is upright and thin (as on a towel holder)."""
    return bool(size[2] > 2.0 * size[1])


@register("towel", variants=2)
def towel(size, rng, style, support_heights):
    """Bath towel: folded stack of two to four towels (0) or rolled towels stacked spa-style
    with woven bands (1). In an upright thin box the towel hangs folded over a bar
    (plain (0) or with hem bands (1))."""
    sx, sy, sz = size
    if _hangs(size):
        return _draped(sx, sy, sz, bands=style == 1)
    if style == 0:
        n = int(np.clip(round(sz / (0.12 * sy) * rng.uniform(0.8, 1.2)), 2, 4))
        return _folded_stack(sx, sy, sz, n, bands=False, rng=rng)
    # rolls along x: two side by side below, one on top (or a single row in a flat box)
    hx, hy, hz = size / 2
    two_rows = sz > 0.7 * sy
    r_y = hy / 2
    r_z = hz / 2 if two_rows else hz
    rows = [(-r_y, -hz + r_z), (r_y, -hz + r_z)]
    if two_rows:
        rows.append((0.0, hz - r_z))
    parts = []
    for k, (y, z) in enumerate(rows):
        parts.append(Part(f"roll_{k}", _cyl_x((0, y, z), r_y, r_z, sx * 0.94, FINE_SEGMENTS)))
        for i, x in enumerate((-0.36 * sx, 0.36 * sx)):
            parts.append(
                Part(
                    f"band_{k}_{i}",
                    _cyl_x((x, y, z), 1.03 * r_y, 1.03 * r_z, 0.05 * sx, FINE_SEGMENTS),
                )
            )
    return parts


@register("hand_towel", variants=2)
def hand_towel(size, rng, style, support_heights):
    """Hand towel: hung folded over a bar in an upright thin box, else lying folded once; plain
    (0) or with woven bands near the hem (1)."""
    sx, sy, sz = size
    if _hangs(size):
        return _draped(sx, sy, sz, bands=style == 1)
    return _folded_stack(sx, sy, sz, 1, bands=style == 1, rng=rng)


def _paper_roll(
    rx: float, ry: float, core: float, z0: float, z_paper: float, z_core: float
) -> list[Part]:
    """A paper roll (outer radii rx, ry) wound on a hollow card core (``core`` as a
    share of the radii): paper from z0 to z_paper, the core standing to z_core."""
    paper = _ring_segments(core * rx, rx, z0, z_paper, 12, core * ry, ry)
    card = _ring_segments(
        0.85 * core * rx, core * rx + 1e-4, z0, z_core, 8, 0.85 * core * ry, core * ry + 1e-4
    )
    return [Part(f"roll_{i}", m) for i, m in enumerate(paper)] + [
        Part(f"core_{i}", m) for i, m in enumerate(card)
    ]


@register("toilet_paper", variants=2)
def toilet_paper(size, rng, style, support_heights):
    """Toilet paper roll with its cardboard core: standing on end, the loose end hanging at
    its side (0), or lying along x as on a holder with a sheet hanging down the front (1)."""
    sx, sy, sz = size
    hx, hy, hz = size / 2
    core = 0.38  # core radius as a share of the roll's
    parts: list[Part] = []
    if style == 0:
        rx, ry = 0.97 * hx, 0.97 * hy  # the loose sheet takes the rest
        parts += _paper_roll(rx, ry, core, -hz, hz - 0.02 * sz, hz)
        parts.append(
            Part("sheet", box_between((-0.3 * rx, ry - 0.01 * sy, -hz), (0.3 * rx, hy, 0.4 * hz)))
        )
        return parts
    # lying along x: the roll in the upper part of the box, its sheet down to the bottom
    ry = 0.97 * hy
    rz = min(hz, ry * 1.0)
    zc = hz - rz
    lay = _Z_TO_X
    segs = _ring_segments(core * ry, ry, -0.96 * hx, 0.96 * hx, 12, core * rz, rz)
    parts += [Part(f"roll_{i}", m.transformed(lay, (0, 0, zc))) for i, m in enumerate(segs)]
    segs = _ring_segments(
        0.85 * core * ry, core * ry + 1e-4, -hx, hx, 8, 0.85 * core * rz, core * rz + 1e-4
    )
    parts += [Part(f"core_{i}", m.transformed(lay, (0, 0, zc))) for i, m in enumerate(segs)]
    parts.append(
        Part("sheet", box_between((-0.96 * hx, ry - 0.005 * sy, -hz), (0.96 * hx, hy, zc)))
    )
    return parts


@register("paper_towel_roll", variants=2)
def paper_towel_roll(size, rng, style, support_heights):
    """Kitchen paper towel roll: standing on a holder (round base, centre rod with a knob)
    with its loose sheet at the side (0), or a bare standing roll showing its core (1)."""
    sx, sy, sz = size
    hx, hy, hz = size / 2
    rx, ry = 0.96 * hx, 0.96 * hy
    parts: list[Part] = []
    if style == 1:
        core = 0.3
        parts += _paper_roll(rx, ry, core, -hz, hz - 0.01 * sz, hz)
    else:
        base_h = clip(0.04 * sz, 0.005, 0.02)
        knob_h = clip(0.08 * sz, 0.01, 0.04)
        rod_r = 0.09 * min(rx, ry)
        parts += [
            Part("base", _cyl_z((0, 0, -hz + base_h / 2), hx, hy, base_h, FINE_SEGMENTS)),
            Part("rod", _cyl_z((0, 0, 0), rod_r, rod_r, sz - knob_h, ROD_SEGMENTS)),
            Part("knob", _ell((0, 0, hz - knob_h / 2), (1.8 * rod_r, 1.8 * rod_r, knob_h / 2))),
            Part(
                "roll",
                _cyl_z(
                    (0, 0, 0.5 * (-hz + base_h + hz - 1.5 * knob_h)),
                    0.93 * rx,
                    0.93 * ry,
                    sz - base_h - 1.5 * knob_h,
                    FINE_SEGMENTS,
                ),
            ),
        ]
    parts.append(
        Part(
            "sheet",
            box_between((-0.35 * rx, ry - 0.005 * sy, -0.4 * hz), (0.35 * rx, hy, 0.6 * hz)),
        )
    )
    return parts


# -- garden, sport, shoes, bags and ornaments -------------------------------------------------
@register("watering_can", variants=2)
def watering_can(size, rng, style, support_heights):
    """Watering can, spout toward +y: a round can with an arched top handle (0) or a tall
    tapered can with a loop handle at the back (1)."""
    # designed in the unit box, then stretched onto the real one
    parts: list[Part] = []
    if style == 0:
        body_top = 0.05
        parts.append(
            Part(
                "body",
                _cyl_z((0, -0.17, (-0.5 + body_top) / 2), 0.5, 0.33, body_top + 0.5, FINE_SEGMENTS),
            )
        )
        parts.append(
            Part("lid", _ell((0, -0.17, body_top), (0.47, 0.31, 0.08), segments=FINE_SEGMENTS))
        )
        arch = np.array(
            [[0, -0.42, 0.0], [0, -0.36, 0.38], [0, -0.17, 0.46], [0, 0.02, 0.38], [0, 0.08, 0.0]]
        )
        parts += [
            Part(f"handle_{i}", m) for i, m in enumerate(_loop_rods(arch, 0.035, closed=False))
        ]
        spout0, spout1 = np.array([0, 0.1, -0.32]), np.array([0, 0.4, 0.3])
    else:
        # top radii in the bottom's proportion: keeps the side faces planar (convex)
        parts.append(
            Part(
                "body",
                frustum(
                    (0, -0.12, -0.5), 0.75, (0.5, 0.33), (0.36, 0.36 * 0.33 / 0.5), FINE_SEGMENTS
                ),
            )
        )
        parts.append(
            Part("filler", _rod((0, -0.08, 0.2), (0, -0.02, 0.4), 0.13, 0.15, ROUND_SEGMENTS))
        )
        loop = np.array([[0, -0.36, 0.15], [0, -0.5, 0.25], [0, -0.5, -0.1], [0, -0.41, -0.25]])
        parts += [
            Part(f"handle_{i}", m) for i, m in enumerate(_loop_rods(loop, 0.035, closed=False))
        ]
        spout0, spout1 = np.array([0, 0.15, -0.35]), np.array([0, 0.42, 0.35])
    d = (spout1 - spout0) / np.linalg.norm(spout1 - spout0)
    parts.append(Part("spout", _rod(spout0, spout1, 0.05, 0.03)))
    parts.append(
        Part("rose", _rod(spout1 - 0.02 * d, spout1 + 0.13 * d, 0.04, 0.1, ROUND_SEGMENTS))
    )
    parts = _scaled(parts, size)
    jitter = rng.uniform(0.97, 1.03, 3)  # small proportion play, refitted by the registry
    return _scaled(parts, jitter)


@register("baseball_bat", variants=2)
def baseball_bat(size, rng, style, support_heights):
    """Baseball bat along its box's longest side (barrel down when standing upright): a
    tapered wooden bat with a domed end (0) or a metal bat with a taped grip and flat end
    cap (1)."""
    csize, rot = _long_frame(size)
    w, length, t = csize
    hl = length / 2
    big_r = 0.5 * min(w, t)
    # along canonical y: the barrel at -y, the knob at +y
    if style == 0:
        prof = [
            (-hl + 0.02 * length, 1.0),
            (-hl + 0.3 * length, 1.0),
            (0.12 * length, 0.42),
            (hl - 0.03 * length, 0.36),
        ]
    else:
        prof = [
            (-hl + 0.01 * length, 1.0),
            (-hl + 0.4 * length, 1.0),
            (0.0, 0.42),
            (hl - 0.03 * length, 0.4),
        ]
    names = ("barrel", "taper", "handle")
    parts = [
        Part(n, _rod((0, y0, 0), (0, y1 + 1e-4, 0), r0 * big_r, r1 * big_r, ROUND_SEGMENTS))
        for n, (y0, r0), (y1, r1) in zip(names, prof[:-1], prof[1:])
    ]
    parts.append(
        Part(
            "knob",
            _rod(
                (0, hl - 0.03 * length, 0), (0, hl, 0), 0.58 * big_r, 0.52 * big_r, ROUND_SEGMENTS
            ),
        )
    )
    if style == 0:
        parts.append(Part("end", _ell((0, -hl + 0.02 * length, 0), (big_r, 0.02 * length, big_r))))
    else:
        parts.append(
            Part(
                "end_cap",
                _rod(
                    (0, -hl, 0), (0, -hl + 0.012 * length, 0), 0.95 * big_r, big_r, ROUND_SEGMENTS
                ),
            )
        )
        parts.append(
            Part(
                "grip",
                _rod(
                    (0, 0.2 * length, 0),
                    (0, hl - 0.03 * length, 0),
                    0.46 * big_r,
                    0.46 * big_r,
                    ROUND_SEGMENTS,
                ),
            )
        )
    return _pose(_face_down(parts, size), rot)


BALL_REST = 0.9
"""A ball rests on a flat patch where it touches (:func:`rest_flat` below this share of
its half height: its body's first ring of vertices round the pole, about a third of its
radius across; the lower half stretched by up to 5 % to keep the box)."""


@register("basketball", variants=2)
def basketball(size, rng, style, support_heights):
    """Basketball: a sphere with its raised seams (thin discs cutting through it): the
    classic eight-panel seam pattern (0) or a four-panel pattern (1)."""
    r = size / 2
    seam = 1.02  # seam discs stand just proud of the ball
    parts = [Part("ball", ellipsoid((0, 0, 0), r, 10, FINE_SEGMENTS))]
    planes = (
        [np.eye(3), _rot_x(np.pi / 2)]
        if style == 1
        else [
            np.eye(3),
            _rot_x(np.pi / 2),
            _rot_y(np.pi / 2) @ _rot_x(0.35),
            _rot_y(np.pi / 2) @ _rot_x(-0.35),
        ]
    )
    spin = _rot_z(rng.uniform(0.0, np.pi))
    for i, rot in enumerate(planes):
        disc = cylinder((0, 0, 0), seam, 0.03, FINE_SEGMENTS + 4, rotation=spin @ rot)
        parts.append(Part(f"seam_{i}", disc.scaled(r)))
    # a little flat where it rests, as a ball's weight flattens it: on its pole and the
    # edge of a seam through it, it rolled off beds and chairs in the simulation (5 of 5
    # on beds in 30 bedrooms, 0.06-0.8 m)
    return rest_flat(parts, seam * r[2], BALL_REST)


@register("tennis_racket", variants=2)
def tennis_racket(size, rng, style, support_heights):
    """Tennis racket along its box's longest side, lying flat (standing on its handle when
    the box is tall): an open-throat racket with a string grid (0) or one in a head
    cover (1)."""
    csize, rot = _long_frame(size)
    w, length, t = csize
    hw, hl, ht = csize / 2
    head_l = min(0.46 * length, 1.45 * w)  # head length along y
    a, b = hw, head_l / 2
    yc = hl - b
    fw = clip(0.06 * w, 0.006, 0.02)  # frame width
    parts: list[Part] = []
    if style == 0:
        n = 14
        ang = np.linspace(0.0, _TAU, n + 1)[:-1]
        ring = np.c_[(a - fw / 2) * np.cos(ang), yc + (b - fw / 2) * np.sin(ang)]
        for i, (p, q) in enumerate(zip(ring, np.roll(ring, -1, axis=0))):
            d = q - p
            parts.append(
                Part(
                    f"frame_{i}",
                    box(
                        ((p + q) / 2).tolist() + [0.0],
                        (np.linalg.norm(d) + fw * 0.6, fw, t),
                        _rot_z(np.arctan2(d[1], d[0])),
                    ),
                )
            )
        st = 0.2 * t
        for i, x in enumerate(np.linspace(-0.7, 0.7, 6) * (a - fw)):
            half = (b - fw) * np.sqrt(1 - (x / (a - fw)) ** 2)
            parts.append(Part(f"string_main_{i}", box((x, yc, 0), (0.2 * fw, 2 * half, st))))
        for i, y in enumerate(np.linspace(-0.75, 0.75, 7) * (b - fw)):
            half = (a - fw) * np.sqrt(1 - (y / (b - fw)) ** 2)
            parts.append(Part(f"string_cross_{i}", box((0, yc + y, 0), (2 * half, 0.2 * fw, st))))
    else:
        parts.append(Part("head_cover", _cyl_z((0, yc, 0), hw, b, t, FINE_SEGMENTS)))
        parts.append(
            Part("cover_seam", _cyl_z((0, yc, 0), 0.97 * hw, 0.97 * b, 1.15 * t, FINE_SEGMENTS))
        )
    handle_r = clip(0.11 * w, 0.005, ht / np.cos(np.pi / 8))
    y_throat = yc - b + 0.3 * fw
    y_grip = -hl + 0.38 * length
    for i, sgn in enumerate((-1, 1)):
        p = (sgn * 0.5 * a, y_throat + 0.1 * b, 0.0)
        parts.append(
            Part(
                f"throat_{i}",
                _rod(
                    p, (sgn * 0.3 * handle_r, y_grip, 0.0), min(0.6 * fw, ht), segments=ROD_SEGMENTS
                ),
            )
        )
    parts.append(
        Part(
            "shaft",
            _rod(
                (0, y_grip - 0.05 * length, 0),
                (0, y_grip + 0.02 * length, 0),
                0.9 * handle_r,
                0.6 * handle_r,
                ROD_SEGMENTS,
            ),
        )
    )
    parts.append(
        Part(
            "handle",
            _rod(
                (0, -hl + 0.02 * length, 0),
                (0, y_grip - 0.04 * length, 0),
                handle_r,
                handle_r,
                ROD_SEGMENTS,
            ),
        )
    )
    parts.append(
        Part(
            "butt_cap",
            _rod(
                (0, -hl, 0),
                (0, -hl + 0.02 * length + 1e-4, 0),
                0.9 * handle_r,
                1.05 * handle_r,
                ROD_SEGMENTS,
            ),
        )
    )
    return _pose(parts, rot)


@register("dumbbell", variants=2)
def dumbbell(size, rng, style, support_heights):
    """Dumbbell along its box's longer side: hexagonal rubber heads (0) or stacked round
    plates held by collars (1)."""
    csize, rot = _long_frame(size)
    w, length, t = csize
    hl = length / 2
    grip_r = 0.17 * min(w, t)
    parts = [Part("handle", _cyl_y((0, 0, 0), grip_r, grip_r, length * 0.98, ROUND_SEGMENTS))]
    if style == 0:
        head_l = 0.26 * length * rng.uniform(0.9, 1.1)
        # flats at top and bottom: six sides with corners at +-x
        r = min(0.5 * w, 0.5 * t / np.cos(np.pi / 6))
        hexagon = [(r * np.cos(a), r * np.sin(a)) for a in np.radians(np.arange(0, 360, 60))]
        for i, sgn in enumerate((-1, 1)):
            y0 = sgn * hl
            y1 = sgn * (hl - head_l)
            lo, hi = min(y0, y1), max(y0, y1)
            parts.append(Part(f"head_{i}", prism(hexagon, lo, hi).transformed(_Z_TO_Y, None)))
            parts.append(
                Part(
                    f"collar_{i}",
                    _cyl_y(
                        (0, sgn * (hl - head_l - 0.02 * length), 0),
                        1.6 * grip_r,
                        1.6 * grip_r,
                        0.04 * length,
                        ROUND_SEGMENTS,
                    ),
                )
            )
        return _pose(parts, rot)
    r = 0.5 * min(w, t)
    pl = 0.055 * length  # plate thickness
    for i, sgn in enumerate((-1, 1)):
        y = sgn * (hl - 0.06 * length)
        for k, scale in enumerate((1.0, 0.82, 0.66)):
            yk = y - sgn * (k * pl * 1.05 + pl / 2)
            parts.append(
                Part(f"plate_{i}_{k}", _cyl_y((0, yk, 0), scale * r, scale * r, pl, FINE_SEGMENTS))
            )
        inner = y - sgn * (3.2 * pl + 0.025 * length)
        parts.append(
            Part(
                f"collar_{i}",
                _cyl_y((0, inner, 0), 0.3 * r, 0.3 * r, 0.05 * length, ROUND_SEGMENTS),
            )
        )
        parts.append(
            Part(
                f"outer_collar_{i}",
                _cyl_y(
                    (0, y + sgn * 0.025 * length, 0),
                    0.3 * r,
                    0.3 * r,
                    0.05 * length,
                    ROUND_SEGMENTS,
                ),
            )
        )
    return _pose(parts, rot)


def _boot(bw: float, bl: float, h: float, style: int) -> list[Part]:
    """One boot, toe toward +y, centred on the origin's x-y, sole at z = 0: width bw,
    length bl, height h."""
    hw, hl = bw / 2, bl / 2
    st = clip(0.08 * bl, 0.008, 0.03)  # sole
    outline = _superellipse(hw, hl, 16, 2.3)
    outline[:, 0] *= np.where(outline[:, 1] < 0, 0.85, 1.0)  # a narrower heel
    parts = [Part("sole", prism(outline, 0.0, st))]
    vamp_h = min(0.33 * bl, 0.6 * h)
    t = np.linspace(0.0, _TAU, 12, endpoint=False)
    dome = [
        np.c_[
            0.95 * hw * np.cos(t) * np.cos(p),
            0.5 * bl * 0.96 * np.sin(t) * np.cos(p),
            np.full(12, st + vamp_h * np.sin(p)),
        ]
        for p in np.radians([0.0, 30.0, 60.0, 85.0])
    ]
    vamp = np.concatenate(dome)
    vamp[:, 1] = np.where(vamp[:, 1] > 0, vamp[:, 1], vamp[:, 1] * 0.95)
    parts.append(Part("vamp", hull(vamp)))
    shaft_c = -hl + 0.24 * bl
    srx, sry = 0.82 * hw, 0.21 * bl
    cuff_h = 0.08 * h if style == 0 else 0.0
    parts.append(
        Part(
            "shaft",
            _cyl_z(
                (0, shaft_c, st + (h - st - cuff_h) / 2), srx, sry, h - st - cuff_h, ROUND_SEGMENTS
            ),
        )
    )
    if style == 0:
        parts.append(
            Part(
                "cuff",
                _cyl_z(
                    (0, shaft_c, h - cuff_h / 2), 1.08 * srx, 1.08 * sry, cuff_h, ROUND_SEGMENTS
                ),
            )
        )
        parts.append(
            Part(
                "heel",
                box_between(
                    (-0.8 * hw, -hl + 0.02 * bl, 0.0), (0.8 * hw, -hl + 0.28 * bl, 1.8 * st)
                ),
            )
        )
        parts.append(
            Part(
                "pull_tab",
                box_between(
                    (-0.15 * srx, shaft_c - sry - 0.03 * bl, h - 0.2 * h),
                    (0.15 * srx, shaft_c - sry + 0.02 * bl, h),
                ),
            )
        )
    else:
        # laces climbing the front of the shaft
        z_lo, z_hi = st + 0.7 * vamp_h, h - 0.06 * h
        for k, z in enumerate(np.linspace(z_lo, z_hi, 4)):
            parts.append(
                Part(
                    f"lace_{k}",
                    box((0, shaft_c + sry * 0.97, z), (1.1 * srx, 0.06 * sry, 0.025 * h)),
                )
            )
        parts.append(
            Part("toe_cap", _ell((0, hl - 0.17 * bl, st), (0.93 * hw, 0.16 * bl, 0.5 * vamp_h)))
        )
    return parts


@register("boots", variants=2)
def boots(size, rng, style, support_heights):
    """A pair of boots side by side, toes toward +y: tall riding boots with heels and cuffs
    (0) or laced work boots with toe caps (1)."""
    sx, sy, sz = size
    hx, hy, hz = size / 2
    gap = 0.06 * sx
    bw = (sx - gap) / 2
    parts: list[Part] = []
    for sgn in (-1, 1):
        splay = _rot_z(-sgn * np.radians(rng.uniform(2.0, 6.0)))  # toes turn out a little
        one = _boot(bw * 0.95, sy * 0.96, sz, style)
        parts += [
            Part(
                f"{'left' if sgn < 0 else 'right'}_{p.name}",
                p.mesh.transformed(splay, (sgn * (gap + bw) / 2, 0.0, -hz)),
            )
            for p in one
        ]
    return parts


@register("garbage_bag", variants=2)
def garbage_bag(size, rng, style, support_heights):
    """Full garbage bag tied at the top: a round lumpy sack with two knot ears (0) or a tall
    bin-liner bag with a flat bottom and a twisted neck (1)."""
    parts: list[Part] = []
    # unit-box design, stretched onto the real box
    if style == 0:
        t = np.linspace(0.0, _TAU, 14, endpoint=False)
        rings = []
        for phi in np.radians([-90.0, -70.0, -45.0, -20.0, 5.0, 30.0, 55.0, 75.0]):
            rad = 0.5 * np.cos(phi) * rng.uniform(0.9, 1.0, 14)
            rings.append(
                np.c_[rad * np.cos(t), rad * np.sin(t), np.full(14, -0.12 + 0.36 * np.sin(phi))]
            )
        body = np.concatenate(rings)
        body[:, 2] = np.maximum(body[:, 2], -0.5)
        parts.append(Part("sack", hull(body)))
        for k in range(3):
            a = rng.uniform(0.0, _TAU)
            c = (0.27 * np.cos(a), 0.27 * np.sin(a), rng.uniform(-0.25, 0.05))
            parts.append(
                Part(f"lump_{k}", _ell(c, (0.2, 0.2, 0.2) * rng.uniform(0.8, 1.0, 3), rings=6))
            )
        neck_z0 = 0.16
    else:
        t = np.linspace(0.0, _TAU, 14, endpoint=False)
        base = np.c_[_superellipse(0.46, 0.46, 14, 3.0), np.full(14, -0.5)]
        belly = np.c_[
            0.5 * np.cos(t) * rng.uniform(0.92, 1.0, 14),
            0.5 * np.sin(t) * rng.uniform(0.92, 1.0, 14),
            np.full(14, -0.05),
        ]
        shoulder = np.c_[0.33 * np.cos(t), 0.33 * np.sin(t), np.full(14, 0.22)]
        parts.append(Part("sack", hull(np.r_[base, belly, shoulder])))
        neck_z0 = 0.2
    parts.append(Part("neck", _rod((0, 0, neck_z0), (0, 0, 0.36), 0.12, 0.05, ROUND_SEGMENTS)))
    parts.append(Part("knot", _ell((0, 0, 0.37), (0.07, 0.07, 0.05))))
    for i, sgn in enumerate((-1, 1)):
        ear = _ell((0, 0, 0.0), (0.035, 0.1, 0.075), _rot_y(sgn * 0.6) @ _rot_z(0.4))
        parts.append(Part(f"ear_{i}", ear.transformed(None, (sgn * 0.1, 0.0, 0.43))))
    return _scaled(parts, size)


@register("decor", variants=3)
def decor(size, rng, style, support_heights):
    """Generic ornament: a bowl of decorative spheres, on a pedestal when the box is tall (0);
    an orb on a stand circled by a tilted ring (1); or (2) dried branches in a slim vase when
    the box is tall, three pillars of different heights on a tray when it is low."""
    sx, sy, sz = size
    hx, hy, hz = size / 2
    parts: list[Part] = []
    if style == 0:
        bowl_h = min(sz, 0.55 * min(sx, sy))
        z0 = hz - bowl_h
        if z0 > -hz + 1e-6:  # tall box: stand the bowl on a column
            col_r = 0.28 * min(sx, sy)
            parts.append(
                Part(
                    "pedestal_base",
                    _cyl_z((0, 0, -hz + 0.02 * sz), 0.4 * hx, 0.4 * hy, 0.04 * sz, FINE_SEGMENTS),
                )
            )
            parts.append(
                Part(
                    "pedestal",
                    _cyl_z((0, 0, (-hz + z0) / 2), col_r, col_r, z0 + hz + 1e-4, FINE_SEGMENTS),
                )
            )
        rim_h = 0.55 * bowl_h
        parts.append(
            Part(
                "bowl", frustum((0, 0, z0), rim_h, (0.45 * hx, 0.45 * hy), (hx, hy), FINE_SEGMENTS)
            )
        )
        n = int(rng.integers(3, 6))
        ang = np.linspace(0.0, _TAU, n, endpoint=False) + rng.uniform(0, _TAU)
        r = 0.3 * min(hx, hy)
        rz = 0.5 * (hz - (z0 + 0.6 * rim_h))
        for k, a in enumerate(ang):
            c = (0.48 * hx * np.cos(a), 0.48 * hy * np.sin(a), z0 + 0.6 * rim_h + rz * 0.9)
            parts.append(Part(f"sphere_{k}", _ell(c, (r, r * hy / hx, rz * 0.9), rings=8)))
        parts.append(Part("sphere_top", _ell((0, 0, hz - rz), (r, r * hy / hx, rz), rings=8)))
        return parts
    if style == 1:
        base_h = 0.08 * sz
        orb_r = 0.5 * min(sx, sy, 0.6 * sz)
        zc = hz - orb_r
        parts += [
            Part("base", _cyl_z((0, 0, -hz + base_h / 2), hx, hy, base_h, FINE_SEGMENTS)),
            Part(
                "stem",
                _cyl_z(
                    (0, 0, 0.5 * (-hz + base_h + zc)),
                    0.08 * orb_r,
                    0.08 * orb_r,
                    zc + hz - base_h,
                    ROD_SEGMENTS,
                ),
            ),
            Part("orb", _ell((0, 0, zc), (0.7 * orb_r,) * 3, rings=8, segments=FINE_SEGMENTS)),
        ]
        tilt = _rot_x(rng.uniform(0.4, 0.7)) @ _rot_z(rng.uniform(0, np.pi))
        n = 14
        ang = np.linspace(0.0, _TAU, n, endpoint=False)
        ring = np.c_[0.93 * orb_r * np.cos(ang), 0.93 * orb_r * np.sin(ang), np.zeros(n)]
        ring = ring @ tilt.T + (0, 0, zc)
        parts += [
            Part(f"ring_{i}", m) for i, m in enumerate(_loop_rods(ring, 0.06 * orb_r, segments=6))
        ]
        return parts
    if sz < 1.5 * max(sx, sy):
        # a low box: three pillars of different heights on a tray
        tray_h = clip(0.08 * sz, 0.004, 0.03)
        parts.append(
            Part(
                "tray", _rounded_block((0, 0, -hz + tray_h / 2), sx, sy, tray_h, 0.15 * min(sx, sy))
            )
        )
        pr = 0.2 * min(sx, sy)
        spots = ((-0.45 * hx, 0.25 * hy), (0.1 * hx, -0.3 * hy), (0.55 * hx, 0.3 * hy))
        heights = np.array([1.0, rng.uniform(0.55, 0.8), rng.uniform(0.35, 0.55)])
        for k, ((x, y), h) in enumerate(zip(spots, rng.permutation(heights))):
            ph = h * (sz - tray_h)
            parts.append(
                Part(
                    f"pillar_{k}",
                    _cyl_z((x, y, -hz + tray_h + ph / 2 - 1e-4), pr, pr, ph, FINE_SEGMENTS),
                )
            )
        return parts
    vase_h = 0.45 * sz
    vr = 0.35 * min(sx, sy)
    parts.append(
        Part("vase", _rod((0, 0, -hz), (0, 0, -hz + 0.7 * vase_h), 0.7 * vr, vr, FINE_SEGMENTS))
    )
    parts.append(
        Part(
            "vase_neck",
            _rod(
                (0, 0, -hz + 0.7 * vase_h - 1e-4),
                (0, 0, -hz + vase_h),
                vr,
                0.55 * vr,
                FINE_SEGMENTS,
            ),
        )
    )
    n = int(rng.integers(3, 6))
    br = clip(0.01 * sz, 0.002, 0.012)
    # branches spread evenly around so that together they span the box
    spokes = np.linspace(0.0, _TAU, n, endpoint=False) + rng.uniform(0, _TAU)
    for k, a in enumerate(spokes + rng.uniform(-0.3, 0.3, n)):
        lean = rng.uniform(0.75, 1.0)
        tip = (
            lean * (hx - br) * np.cos(a),
            lean * (hy - br) * np.sin(a),
            hz - rng.uniform(0.0, 0.25) * (sz - vase_h) if k else hz,
        )
        root = (0.0, 0.0, -hz + 0.5 * vase_h)
        mid = np.array(root) + 0.55 * (np.array(tip) - root)
        parts.append(Part(f"branch_{k}", _rod(root, tip, br, 0.5 * br, ROD_SEGMENTS)))
        twig_dir = np.array([np.cos(a + 0.8), np.sin(a + 0.8), 1.2])
        twig_end = mid + 0.2 * (sz - vase_h) * twig_dir / np.linalg.norm(twig_dir)
        twig_end[:2] = np.clip(twig_end[:2], (-hx, -hy), (hx, hy))
        parts.append(Part(f"twig_{k}", _rod(mid, twig_end, 0.6 * br, 0.3 * br, 6)))
    return parts

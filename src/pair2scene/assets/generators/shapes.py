"""Shape helpers shared by every generator family: one home for each building block.

Generator modules import their helpers from here, never from a sibling generator
module (``tests/assets/test_shapes.py`` checks that no second ``lathe``, ``clip`` or
``slab`` appears). Arrays: points are (N, 3) rows (x, y, z) in metres; outlines are
(N, 2) rows (x, y); profiles are (K, 2) rows (radius factor, z).
"""

from __future__ import annotations

import functools
from collections.abc import Callable, Sequence

import numpy as np

from pair2scene.assets.mesh import Mesh, Part, box, box_between, cylinder, frustum, hull, prism
from pair2scene.assets.registry import GeneratorFn
from pair2scene.scene.geometry import rot_z

# -- segment counts -------------------------------------------------------------------
ROUND_SEGMENTS = 12
"""Sides of a round part on a small object or fixture (posts, wheels, bins, a toilet bowl):
reads as round at 256 px, cheap to build; a multiple of 4 so the extreme vertices lie
exactly on the box faces."""
FINE_SEGMENTS = 16
"""Sides of a large round part that dominates the silhouette (a table top, a column, a
bottle, a lamp shade): these are seen large, so they get more sides than ROUND_SEGMENTS."""
ROD_SEGMENTS = 8
"""Sides of a thin round part (legs, tubes, knobs, handles): a few pixels wide, its
roundness is not visible."""

JITTER = 0.06
"""Relative proportion jitter per draw: variety between seeds without changing the type."""

ROT_X90 = np.array([[1.0, 0.0, 0.0], [0.0, 0.0, -1.0], [0.0, 1.0, 0.0]])
"""(3, 3) +90 deg about x: a +z axis becomes -y (a cylinder lying along y); ring y becomes z."""
ROT_Y90 = np.array([[0.0, 0.0, 1.0], [0.0, 1.0, 0.0], [-1.0, 0.0, 0.0]])
"""(3, 3) +90 deg about y: a +z axis becomes +x (a cylinder lying along x); ring x becomes -z."""


# -- scalars ------------------------------------------------------------------------------
def clip(x: float, lo: float, hi: float, cap: float = np.inf) -> float:
    """``x`` held in [lo, hi] (real-world limits), then never above ``cap`` (a share of the
    box). When the box is too small for ``lo``, ``hi`` and then ``cap`` win, so a part never
    outgrows the box. Scalars in, a Python float out."""
    return float(min(max(x, lo), hi, cap))


# -- solids -------------------------------------------------------------------------------
def slab(name: str, lo: Sequence[float], hi: Sequence[float]) -> Part:
    """An axis-aligned box part from its min (3,) and max (3,) corners."""
    return Part(name, box_between(lo, hi))


def lathe(
    profile: Sequence[Sequence[float]],
    rx: float,
    ry: float,
    segments: int = FINE_SEGMENTS,
    center: Sequence[float] = (0.0, 0.0),
    hull_of_rings: bool = True,
) -> Mesh:
    """Solid of revolution about a vertical axis, with elliptic sections.

    profile : (K, 2) rows (r, z), z increasing; r is a factor of the radii, so the ring at z
    has radii (r * rx, r * ry). center : (2,) axis position (x, y). Each ring has
    ``segments`` vertices, angle 0 on +x; use a multiple of 4 so the solid reaches +-rx and
    +-ry exactly. The solid is convex when r is a concave function of z (bulges, tapers,
    domes).

    hull_of_rings=True returns the convex hull of the rings (any profile gives a convex
    part). False keeps every ring vertex in profile order and closes each end with a fan
    around a centre vertex; r == 0 at an end makes an apex instead. The two constructions
    also multiply in different orders ((r * rx) * cos vs r * (rx * cos)); both are kept so
    that existing assets stay byte-identical.
    """
    cx, cy = float(center[0]), float(center[1])
    if hull_of_rings:
        pts = [ring_points(r * rx, r * ry, z, segments, cx, cy) for r, z in profile]
        return hull(np.concatenate(pts))
    n = segments
    a = np.linspace(0.0, 2.0 * np.pi, n, endpoint=False)
    ux, uy = rx * np.cos(a), ry * np.sin(a)
    verts: list[np.ndarray] = []
    rings: list[np.ndarray | int] = []  # vertex indices of each level, or an apex index
    count = 0
    z_ends = (float(profile[0][1]), float(profile[-1][1]))
    for r, z in profile:
        if r <= 0.0:
            verts.append(np.array([[cx, cy, z]]))
            rings.append(count)
            count += 1
        else:
            verts.append(np.stack([cx + r * ux, cy + r * uy, np.full(n, float(z))], axis=1))
            rings.append(np.arange(count, count + n))
            count += n
    faces: list[list[int]] = []
    for lo, hi in zip(rings[:-1], rings[1:]):
        for i in range(n):
            j = (i + 1) % n
            if isinstance(lo, int):
                faces.append([lo, hi[j], hi[i]])
            elif isinstance(hi, int):
                faces.append([lo[i], lo[j], hi])
            else:
                faces += [[lo[i], lo[j], hi[j]], [lo[i], hi[j], hi[i]]]
    for end, z, flip in ((rings[0], z_ends[0], True), (rings[-1], z_ends[1], False)):
        if isinstance(end, int):
            continue
        c = count
        verts.append(np.array([[cx, cy, z]]))
        count += 1
        for i in range(n):
            j = (i + 1) % n
            faces.append([c, end[j], end[i]] if flip else [c, end[i], end[j]])
    return Mesh(np.concatenate(verts), np.array(faces))


# -- furniture building blocks (tables, seating, beds, storage) ---------------------------
def jitter(rng: np.random.Generator, frac: float = JITTER) -> float:
    """A factor drawn uniformly from [1 - frac, 1 + frac]."""
    return float(1.0 + rng.uniform(-frac, frac))


def tapered_box(
    cx: float, cy: float, z0: float, z1: float, top: Sequence[float], bottom: Sequence[float]
) -> Mesh:
    """A square-section post from z0 to z1 whose (x, y) section shrinks linearly from
    ``top`` (2,) at z1 to ``bottom`` (2,) at z0: a tapered leg. Convex because the two
    end rectangles are parallel and equally oriented."""
    m = box((cx, cy, (z0 + z1) / 2), (top[0], top[1], z1 - z0))
    v = m.vertices.copy()
    low = v[:, 2] < (z0 + z1) / 2
    v[low, 0] = cx + (v[low, 0] - cx) * bottom[0] / top[0]
    v[low, 1] = cy + (v[low, 1] - cy) * bottom[1] / top[1]
    return Mesh(v, m.faces)


def sheared(mesh: Mesh, dy_per_dz: float, z_ref: float) -> Mesh:
    """``mesh`` with y shifted by ``dy_per_dz * (z - z_ref)``: a leaning back or headboard.
    A shear is affine with determinant 1, so convexity and orientation are kept."""
    v = mesh.vertices.copy()
    v[:, 1] += dy_per_dz * (v[:, 2] - z_ref)
    return Mesh(v, mesh.faces)


def ring_points(
    rx: float,
    ry: float,
    z: float,
    segments: int,
    cx: float = 0.0,
    cy: float = 0.0,
    phase: float = 0.0,
) -> np.ndarray:
    """(segments, 3) points on an ellipse at height z (angle 0 on +x)."""
    a = phase + np.linspace(0.0, 2.0 * np.pi, segments, endpoint=False)
    return np.stack([cx + rx * np.cos(a), cy + ry * np.sin(a), np.full(segments, z)], axis=1)


def rounded_rect(
    x0: float, x1: float, y0: float, y1: float, radius: float, corner_segments: int = 3
) -> np.ndarray:
    """(4 * (corner_segments + 1), 2) counter-clockwise outline of a rectangle with
    rounded corners; it still reaches x0, x1, y0 and y1."""
    r = min(radius, (x1 - x0) / 2 * 0.999, (y1 - y0) / 2 * 0.999)
    corners = [
        (x1 - r, y0 + r, -np.pi / 2),
        (x1 - r, y1 - r, 0.0),
        (x0 + r, y1 - r, np.pi / 2),
        (x0 + r, y0 + r, np.pi),
    ]
    pts = []
    for cx, cy, a0 in corners:
        a = a0 + np.linspace(0.0, np.pi / 2, corner_segments + 1)
        pts.append(np.stack([cx + r * np.cos(a), cy + r * np.sin(a)], axis=1))
    return np.concatenate(pts)


def rounded_slab(
    name: str, x0: float, x1: float, y0: float, y1: float, z0: float, z1: float, radius: float
) -> Part:
    """A slab with rounded vertical edges (a cushion, a soft top), as one convex prism."""
    return Part(name, prism(rounded_rect(x0, x1, y0, y1, radius), z0, z1))


def z_cylinder(
    cx: float,
    cy: float,
    z0: float,
    z1: float,
    radius: float | Sequence[float],
    segments: int = FINE_SEGMENTS,
) -> Mesh:
    """Upright (elliptic) cylinder from z0 to z1 centred on (cx, cy)."""
    return frustum((cx, cy, z0), z1 - z0, radius, radius, segments)


def x_cylinder(
    x0: float,
    x1: float,
    cy: float,
    cz: float,
    ry: float,
    rz: float,
    segments: int = FINE_SEGMENTS,
) -> Mesh:
    """Elliptic cylinder lying along x from x0 to x1 (a bolster, a rolled arm)."""
    return cylinder(((x0 + x1) / 2, cy, cz), (rz, ry), x1 - x0, segments, ROT_Y90)


def y_cylinder(
    y0: float,
    y1: float,
    cx: float,
    cz: float,
    rx: float,
    rz: float,
    segments: int = FINE_SEGMENTS,
) -> Mesh:
    """Elliptic cylinder lying along y from y0 to y1 (a sled runner, a side bolster)."""
    return cylinder((cx, (y0 + y1) / 2, cz), (rx, rz), y1 - y0, segments, ROT_X90)


def corner_legs(
    lx: float,
    ly: float,
    z0: float,
    z1: float,
    thickness: float,
    round_legs: bool = False,
    taper: float = 1.0,
) -> list[Part]:
    """Four legs centred on (+-lx, +-ly) from z0 to z1, named leg_0..leg_3
    (counter-clockwise from back-left); ``taper`` is the foot's width over the top's."""
    parts = []
    for i, (sx, sy) in enumerate([(-1, -1), (1, -1), (1, 1), (-1, 1)]):
        cx, cy = sx * lx, sy * ly
        if round_legs:
            r = thickness / 2
            mesh = frustum((cx, cy, z0), z1 - z0, r * taper, r, ROD_SEGMENTS)
        else:
            t = (thickness, thickness)
            mesh = tapered_box(cx, cy, z0, z1, t, (thickness * taper, thickness * taper))
        parts.append(Part(f"leg_{i}", mesh))
    return parts


def ring_of_boxes(
    prefix: str,
    rx: float,
    ry: float,
    z: float,
    segments: int,
    width: float,
    height: float,
    cx: float = 0.0,
    cy: float = 0.0,
) -> list[Part]:
    """A closed ring (a footrest, a rim) of ``segments`` straight boxes along an ellipse of
    radii (rx, ry) at height z; each box spans one chord, a little longer so corners meet."""
    a = np.linspace(0.0, 2.0 * np.pi, segments + 1)
    p = np.stack([cx + rx * np.cos(a), cy + ry * np.sin(a)], axis=1)  # (segments + 1, 2)
    parts = []
    for i in range(segments):
        d = p[i + 1] - p[i]
        length = float(np.hypot(*d)) + width
        ang = float(np.arctan2(d[1], d[0]))
        c, s = np.cos(ang), np.sin(ang)
        rot = np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])
        mid = (p[i] + p[i + 1]) / 2
        parts.append(Part(f"{prefix}_{i}", box((mid[0], mid[1], z), (length, width, height), rot)))
    return parts


def drawer_front(
    name: str,
    x0: float,
    x1: float,
    y_back: float,
    y_front: float,
    z0: float,
    z1: float,
    knob: bool = True,
) -> list[Part]:
    """A drawer front panel facing +y and its handle, which ends exactly at ``y_front``."""
    handle_d = clip(0.3 * (y_front - y_back), 0.008, 0.025)
    panel_front = y_front - handle_d
    parts = [slab(name, (x0, y_back, z0), (x1, panel_front, z1))]
    if knob:
        h = clip(0.18 * (z1 - z0), 0.008, 0.025)
        w = clip(0.3 * (x1 - x0), 0.02, 0.14)
        xm, zm = (x0 + x1) / 2, (z0 + z1) / 2
        parts.append(
            slab(
                f"{name}_handle",
                (xm - w / 2, panel_front, zm - h / 2),
                (xm + w / 2, y_front, zm + h / 2),
            )
        )
    return parts


def floor_to_centre(parts: list[Part], height: float) -> list[Part]:
    """Parts built in floor coordinates (z in [0, height]) moved into the centred box."""
    shift = np.array([0.0, 0.0, -height / 2])
    return [Part(p.name, p.mesh.transformed(None, shift)) for p in parts]


def min_design_extent(extent: float) -> Callable[[GeneratorFn], GeneratorFn]:
    """Decorator for a generator: a box thinner than ``extent`` (m) along any axis is built
    at a uniformly larger size and its parts scaled back, so the result is the same shape,
    smaller. The absolute clamps (a leg at least 2 cm thick) suit furniture-sized boxes; a
    doll-house box would otherwise get parts thicker than the box, turned inside out."""

    def deco(fn: GeneratorFn) -> GeneratorFn:
        @functools.wraps(fn)
        def wrapped(
            size: np.ndarray,
            rng: np.random.Generator,
            style: int,
            support_heights: Sequence[float] | None = None,
        ) -> list[Part]:
            s = max(1.0, extent / float(np.min(size)))
            if s == 1.0:
                return fn(size, rng, style, support_heights)
            heights = None if support_heights is None else [h * s for h in support_heights]
            parts = fn(np.asarray(size, dtype=float) * s, rng, style, heights)
            return [Part(p.name, p.mesh.scaled(1.0 / s)) for p in parts]

        return wrapped

    return deco


# -- small-object building blocks (tableware, appliances, food) ---------------------------
def beam(
    p0: Sequence[float],
    p1: Sequence[float],
    width: float,
    thickness: float,
    side: Sequence[float] = (0.0, 1.0, 0.0),
) -> Mesh:
    """Box from point p0 (3,) to p1 (3,): ``width`` along ``side`` (3,) (made orthogonal
    to the beam), ``thickness`` across both."""
    p0, p1 = np.asarray(p0, dtype=float), np.asarray(p1, dtype=float)
    u = p1 - p0
    length = float(np.linalg.norm(u))
    u /= length
    s = np.asarray(side, dtype=float)
    s = s - (s @ u) * u
    s /= np.linalg.norm(s)
    rot = np.column_stack([u, s, np.cross(u, s)])
    return box((p0 + p1) / 2, (length, width, thickness), rotation=rot)


def rounded_outline(
    x0: float,
    x1: float,
    y0: float,
    y1: float,
    radii: Sequence[float] | float,
    corner_segments: int = 4,
) -> np.ndarray:
    """(N, 2) counter-clockwise convex outline of a rectangle with rounded corners.

    Unlike :func:`rounded_rect` (one radius, furniture) each corner has its own radius and
    a repeated point where two arcs meet is dropped. radii : one radius or four, for
    corners (x1, y0), (x1, y1), (x0, y1), (x0, y0); 0 keeps a corner sharp."""
    r = np.broadcast_to(np.asarray(radii, dtype=float), (4,))
    lim = 0.5 * min(x1 - x0, y1 - y0)
    corners = ((x1, y0, -np.pi / 2), (x1, y1, 0.0), (x0, y1, np.pi / 2), (x0, y0, np.pi))
    pts = []
    for (cx, cy, start), rad in zip(corners, r):
        rad = min(rad, lim)
        sx = -1.0 if cx == x1 else 1.0
        sy = -1.0 if cy == y1 else 1.0
        if rad <= 0.0:
            pts.append((cx, cy))
            continue
        ox, oy = cx + sx * rad, cy + sy * rad
        for t in np.linspace(start, start + np.pi / 2, corner_segments + 1):
            pts.append((ox + rad * np.cos(t), oy + rad * np.sin(t)))
    p = np.array(pts)
    # arcs meeting on a side shorter than two radii share a point: drop the repeat
    keep = np.linalg.norm(p - np.roll(p, 1, axis=0), axis=1) > 1e-9
    return p[keep]


def ellipse_arc(
    cx: float,
    cy: float,
    rx: float,
    ry: float,
    n: int = FINE_SEGMENTS,
    a0: float = 0.0,
    a1: float = 2.0 * np.pi,
    endpoint: bool = False,
) -> np.ndarray:
    """(n, 2) points on an ellipse arc from angle a0 to a1."""
    a = np.linspace(a0, a1, n, endpoint=endpoint)
    return np.stack([cx + rx * np.cos(a), cy + ry * np.sin(a)], axis=1)


def rotate_parts(parts: list[Part], rotation: np.ndarray) -> list[Part]:
    return [Part(p.name, p.mesh.transformed(rotation)) for p in parts]


def in_long_frame(
    size: np.ndarray, build: Callable[[float, float, float, bool], list[Part]]
) -> list[Part]:
    """Call ``build(length, width, height, turned)`` with the length along the box's longer
    horizontal axis (built along x); ``turned`` is True when it is turned onto y (the
    build's +x then ends up at +y, so a feature at +x faces the front)."""
    sx, sy, sz = (float(v) for v in size)
    if sx >= sy:
        return build(sx, sy, sz, False)
    return rotate_parts(build(sy, sx, sz, True), rot_z(np.pi / 2))


def box_handle(
    x_in: float,
    x_out: float,
    z_lo: float,
    z_hi: float,
    width: float,
    bar: float,
    rounded: bool,
    y: float = 0.0,
    prefix: str = "handle",
) -> list[Part]:
    """A handle (a mug's, a carafe's) in the xz plane at ``y``, from the body (x_in) out to
    x_out, made of boxes: top arm, grip, bottom arm (and two chamfer boxes when ``rounded``)."""
    parts = _handle_at_origin(x_in, x_out, z_lo, z_hi, width, bar, rounded)
    return [
        Part(p.name.replace("handle", prefix, 1), p.mesh.transformed(None, (0, y, 0)))
        for p in parts
    ]


def _handle_at_origin(x_in, x_out, z_lo, z_hi, width, bar, rounded):
    """The boxes of ``box_handle`` at y = 0."""
    hw = width / 2
    if not rounded:
        return [
            Part("handle_top", box_between((x_in, -hw, z_hi - bar), (x_out, hw, z_hi))),
            Part("handle_grip", box_between((x_out - bar, -hw, z_lo), (x_out, hw, z_hi))),
            Part("handle_bottom", box_between((x_in, -hw, z_lo), (x_out, hw, z_lo + bar))),
        ]
    ch = 0.45 * min(x_out - x_in, (z_hi - z_lo) / 2)
    xm = x_out - bar / 2
    return [
        Part("handle_top", box_between((x_in, -hw, z_hi - bar), (x_out - ch, hw, z_hi))),
        Part(
            "handle_corner_top",
            beam(
                (x_out - ch - bar / 4, 0, z_hi - bar / 2), (xm, 0, z_hi - ch + bar / 4), width, bar
            ),
        ),
        Part("handle_grip", box_between((x_out - bar, -hw, z_lo + ch), (x_out, hw, z_hi - ch))),
        Part(
            "handle_corner_bottom",
            beam(
                (xm, 0, z_lo + ch - bar / 4), (x_out - ch - bar / 4, 0, z_lo + bar / 2), width, bar
            ),
        ),
        Part("handle_bottom", box_between((x_in, -hw, z_lo), (x_out - ch, hw, z_lo + bar))),
    ]


# -- rods and frames (fixtures, lighting) -------------------------------------------------
def axis_frame(direction: np.ndarray) -> np.ndarray:
    """(3, 3) right-handed rotation whose third column is the unit ``direction`` (3,)."""
    d = direction / np.linalg.norm(direction)
    helper = np.array([1.0, 0.0, 0.0]) if abs(d[0]) < 0.9 else np.array([0.0, 1.0, 0.0])
    u = np.cross(helper, d)
    u /= np.linalg.norm(u)
    return np.stack([u, np.cross(d, u), d], axis=1)


def bar(
    p0: Sequence[float],
    p1: Sequence[float],
    radius: float,
    segments: int = ROD_SEGMENTS,
    extend0: float = 0.0,
    extend1: float = 0.0,
) -> Mesh:
    """Round bar from p0 (3,) to p1 (3,), lengthened past p0 / p1 by ``extend0`` /
    ``extend1`` (so that bars meeting at an angle leave no gap)."""
    a, b = np.asarray(p0, dtype=float), np.asarray(p1, dtype=float)
    d = b - a
    length = float(np.linalg.norm(d))
    u = d / length
    return frustum(
        a - u * extend0,
        length + extend0 + extend1,
        radius,
        radius,
        segments,
        rotation=axis_frame(u),
    )


PRESSED_FLAT_M = 5e-4
"""A part this thin or less once pressed is part of the flat underside, not a part."""


def rest_flat(parts: list[Part], ht: float, share: float) -> list[Part]:
    """``parts`` (centred at z = 0, ``ht`` their half height) with their lower halves
    pressed flat at -``ht``: every vertex below z = 0 moves to ``max(z, -share ht) /
    share``, and each part becomes the convex hull of its moved vertices (so it stays
    convex). What lay below ``share`` of the half height is pressed flat (a pillow under
    its own weight, a lettuce's outer leaves), the rest of the lower half stretched to
    keep the box. A part pressed into the underside whole is left out."""
    out = []
    for part in parts:
        v = part.mesh.vertices
        if v[:, 2].min() >= 0.0:
            out.append(part)
            continue
        low = v[:, 2] < 0.0
        z = np.where(low, np.maximum(v[:, 2], -share * ht) / share, v[:, 2])
        if z.max() - z.min() > PRESSED_FLAT_M:
            out.append(Part(part.name, hull(np.c_[v[:, :2], z])))
    return out

"""Tables, desks, dressing tables, beds and dog beds.

The first section holds the small building blocks every furniture generator of
this family uses (``seating.py`` imports them too): legs, tapered posts, lathed
solids, rounded slabs, rings of boxes. Generators build in *floor coordinates*
(z from 0 at the floor to the box height, x and y centred) and hand their parts
to :func:`floor_to_centre` last, so the geometry reads like a carpenter's
drawing; every part is one closed convex primitive.
"""

from __future__ import annotations

import functools
from collections.abc import Callable, Sequence

import numpy as np

from pair2scene.assets.mesh import Mesh, Part, box, box_between, cylinder, frustum, hull, prism
from pair2scene.assets.registry import GeneratorFn, register

ROUND_SEGMENTS = 16
"""Sides of large round parts (table tops, columns, bases): read as round at 256 px."""
THIN_SEGMENTS = 8
"""Sides of thin round parts (legs, tubes): they cover a few pixels, 8 sides suffice."""
JITTER = 0.06
"""Relative proportion jitter per draw: variety between seeds without changing the type."""

ROT_X90 = np.array([[1.0, 0.0, 0.0], [0.0, 0.0, -1.0], [0.0, 1.0, 0.0]])
"""(3, 3) +90 deg about x: a +z axis becomes -y (a cylinder lying along y); ring y becomes z."""
ROT_Y90 = np.array([[0.0, 0.0, 1.0], [0.0, 1.0, 0.0], [-1.0, 0.0, 0.0]])
"""(3, 3) +90 deg about y: a +z axis becomes +x (a cylinder lying along x); ring x becomes -z."""


# -- building blocks ----------------------------------------------------------------
def clamp(x: float, lo: float, hi: float) -> float:
    """``x`` limited to [lo, hi] (lo wins when the range is empty)."""
    return float(max(min(x, hi), lo))


def jitter(rng: np.random.Generator, frac: float = JITTER) -> float:
    """A factor drawn uniformly from [1 - frac, 1 + frac]."""
    return float(1.0 + rng.uniform(-frac, frac))


def slab(name: str, lo: Sequence[float], hi: Sequence[float]) -> Part:
    """An axis-aligned box part from its min (3,) and max (3,) corners."""
    return Part(name, box_between(lo, hi))


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


def lathe(
    profile: Sequence[tuple[float, float]],
    rx: float,
    ry: float,
    segments: int = ROUND_SEGMENTS,
    cx: float = 0.0,
    cy: float = 0.0,
) -> Mesh:
    """Convex solid of revolution: ``profile`` (K, 2) rows (radius factor, z) give rings of
    radii (factor * rx, factor * ry); the hull of the rings (a pouf, a bulging base).
    Use segments divisible by 4 so the solid reaches +-rx and +-ry exactly."""
    pts = [ring_points(f * rx, f * ry, z, segments, cx, cy) for f, z in profile]
    return hull(np.concatenate(pts))


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
    segments: int = ROUND_SEGMENTS,
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
    segments: int = THIN_SEGMENTS * 2,
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
    segments: int = THIN_SEGMENTS * 2,
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
            mesh = frustum((cx, cy, z0), z1 - z0, r * taper, r, THIN_SEGMENTS)
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
    handle_d = clamp(0.3 * (y_front - y_back), 0.008, 0.025)
    panel_front = y_front - handle_d
    parts = [slab(name, (x0, y_back, z0), (x1, panel_front, z1))]
    if knob:
        h = clamp(0.18 * (z1 - z0), 0.008, 0.025)
        w = clamp(0.3 * (x1 - x0), 0.02, 0.14)
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


def _top_thickness(
    sz: float, rng: np.random.Generator, frac: float = 0.05, lo: float = 0.02, hi: float = 0.06
) -> float:
    """Table-top thickness from the height, never more than a sixth of it."""
    return min(clamp(frac * sz, lo, hi) * jitter(rng), sz / 6)


# -- tables ---------------------------------------------------------------------------
@register("dining_table", variants=3)
@min_design_extent(0.4)
def dining_table(
    size: np.ndarray,
    rng: np.random.Generator,
    style: int,
    support_heights: Sequence[float] | None = None,
) -> list[Part]:
    """Dining table: four legs with an apron (0), pedestal with a round/oval top (1) or
    trestle (2). The top is the whole upper face; the space under its centre is free
    (style 1: free around the column)."""
    sx, sy, sz = (float(v) for v in size)
    hx, hy, short = sx / 2, sy / 2, min(sx, sy)
    top_t = _top_thickness(sz, rng)
    under = sz - top_t
    if style == 0:
        parts = [slab("top", (-hx, -hy, under), (hx, hy, sz))]
        leg = clamp(0.06 * short, 0.03, 0.09) * jitter(rng)
        inset = clamp(0.04 * short, 0.01, 0.06) * jitter(rng)
        lx, ly = hx - inset - leg / 2, hy - inset - leg / 2
        parts += corner_legs(lx, ly, 0.0, under, leg, taper=0.7)
        apron_h, apron_t = clamp(0.12 * sz, 0.02, 0.11), 0.4 * leg
        z0 = under - apron_h
        parts += [
            slab("apron_front", (-lx, ly - apron_t / 2, z0), (lx, ly + apron_t / 2, under)),
            slab("apron_back", (-lx, -ly - apron_t / 2, z0), (lx, -ly + apron_t / 2, under)),
            slab("apron_left", (-lx - apron_t / 2, -ly, z0), (-lx + apron_t / 2, ly, under)),
            slab("apron_right", (lx - apron_t / 2, -ly, z0), (lx + apron_t / 2, ly, under)),
        ]
    elif style == 1:
        parts = [Part("top", z_cylinder(0.0, 0.0, under, sz, (hx, hy)))]
        col_r = clamp(0.06 * short, 0.03, 0.09) * jitter(rng)
        foot_h = clamp(0.06 * sz, 0.02, 0.06)
        elongated = max(sx, sy) > 1.5 * short
        # one column under a round-ish top, two along the long axis of an oval one
        offs = [0.0] if not elongated else [-0.28, 0.28]
        for i, f in enumerate(offs):
            cx, cy = (f * sx, 0.0) if sx >= sy else (0.0, f * sy)
            foot_r = 0.3 * short
            parts.append(
                Part(
                    f"foot_{i}",
                    frustum((cx, cy, 0.0), foot_h, foot_r, 0.5 * foot_r, ROUND_SEGMENTS),
                )
            )
            parts.append(
                Part(f"column_{i}", z_cylinder(cx, cy, foot_h, under, col_r, THIN_SEGMENTS * 2))
            )
            cap_h = clamp(0.04 * sz, 0.01, 0.04)
            parts.append(
                Part(
                    f"cap_{i}",
                    frustum((cx, cy, under - cap_h), cap_h, col_r, 2.5 * col_r, THIN_SEGMENTS * 2),
                )
            )
    else:
        parts = [slab("top", (-hx, -hy, under), (hx, hy, sz))]
        ut = clamp(0.04 * short, 0.025, 0.07) * jitter(rng)
        ud = clamp(0.2 * sy, 0.05, 0.2)
        ex = hx - clamp(0.12 * sx, 0.04, 0.3) * jitter(rng)
        foot_h, cleat_h = clamp(0.06 * sz, 0.02, 0.07), clamp(0.05 * sz, 0.015, 0.06)
        fy, cy_ = 0.42 * sy, 0.4 * sy
        for i, s in enumerate((-1, 1)):
            x = s * ex
            parts += [
                slab(f"foot_{i}", (x - 0.8 * ut, -fy, 0.0), (x + 0.8 * ut, fy, foot_h)),
                slab(
                    f"upright_{i}",
                    (x - ut / 2, -ud / 2, foot_h),
                    (x + ut / 2, ud / 2, under - cleat_h),
                ),
                slab(
                    f"cleat_{i}", (x - 0.8 * ut, -cy_, under - cleat_h), (x + 0.8 * ut, cy_, under)
                ),
            ]
        st_h = clamp(0.07 * sz, 0.02, 0.07)
        st_z = 0.22 * sz
        parts.append(slab("stretcher", (-ex, -0.3 * ud, st_z), (ex, 0.3 * ud, st_z + st_h)))
    return floor_to_centre(parts, sz)


@register("coffee_table", variants=3)
@min_design_extent(0.25)
def coffee_table(
    size: np.ndarray,
    rng: np.random.Generator,
    style: int,
    support_heights: Sequence[float] | None = None,
) -> list[Part]:
    """Coffee table: four legs and a lower shelf (0), oval top on splayed round legs (1)
    or waterfall side panels with a lower shelf (2)."""
    sx, sy, sz = (float(v) for v in size)
    hx, hy, short = sx / 2, sy / 2, min(sx, sy)
    top_t = _top_thickness(sz, rng, 0.08, 0.02, 0.05)
    under = sz - top_t
    shelf_z = clamp(0.15 * sz, 0.03, 0.1) * jitter(rng)
    shelf_t = 0.6 * top_t
    if style == 0:
        parts = [slab("top", (-hx, -hy, under), (hx, hy, sz))]
        leg = clamp(0.07 * short, 0.025, 0.07) * jitter(rng)
        inset = clamp(0.03 * short, 0.0, 0.04)
        lx, ly = hx - inset - leg / 2, hy - inset - leg / 2
        parts += corner_legs(lx, ly, 0.0, under, leg)
        parts.append(slab("shelf", (-lx, -ly, shelf_z), (lx, ly, shelf_z + shelf_t)))
    elif style == 1:
        parts = [Part("top", z_cylinder(0.0, 0.0, under, sz, (hx, hy)))]
        r = clamp(0.035 * short, 0.012, 0.03) * jitter(rng)
        for i, a in enumerate(np.radians([45.0, 135.0, 225.0, 315.0])):
            c, s = np.cos(a), np.sin(a)
            # legs splay outwards: feet further out than the tops
            top_ring = ring_points(r, r, under, THIN_SEGMENTS, 0.55 * hx * c, 0.55 * hy * s)
            foot_ring = ring_points(
                0.6 * r, 0.6 * r, 0.0, THIN_SEGMENTS, 0.72 * hx * c, 0.72 * hy * s
            )
            parts.append(Part(f"leg_{i}", hull(np.concatenate([top_ring, foot_ring]))))
    else:
        parts = [slab("top", (-hx, -hy, under), (hx, hy, sz))]
        pt = top_t
        parts += [
            slab("side_left", (-hx, -hy, 0.0), (-hx + pt, hy, under)),
            slab("side_right", (hx - pt, -hy, 0.0), (hx, hy, under)),
            slab(
                "shelf",
                (-hx + pt, -hy + 0.05 * sy, shelf_z),
                (hx - pt, hy - 0.05 * sy, shelf_z + shelf_t),
            ),
        ]
    return floor_to_centre(parts, sz)


@register("side_table", variants=3)
@min_design_extent(0.25)
def side_table(
    size: np.ndarray,
    rng: np.random.Generator,
    style: int,
    support_heights: Sequence[float] | None = None,
) -> list[Part]:
    """Side table / nightstand: legs with a drawer and a lower shelf (0), a small cabinet
    with a drawer over an open niche (1) or a round pedestal table (2)."""
    sx, sy, sz = (float(v) for v in size)
    hx, hy, short = sx / 2, sy / 2, min(sx, sy)
    top_t = _top_thickness(sz, rng, 0.05, 0.015, 0.04)
    under = sz - top_t
    if style == 0:
        parts = [slab("top", (-hx, -hy, under), (hx, hy, sz))]
        leg = clamp(0.08 * short, 0.02, 0.05) * jitter(rng)
        inset = clamp(0.03 * short, 0.0, 0.03)
        lx, ly = hx - inset - leg / 2, hy - inset - leg / 2
        parts += corner_legs(lx, ly, 0.0, under, leg, taper=0.75)
        box_h = clamp(0.2 * sz, 0.04, 0.15)
        # the drawer box between the legs, its front flush with the legs' front faces
        parts.append(slab("drawer_box", (-lx, -ly, under - box_h), (lx, ly, under)))
        parts += drawer_front(
            "drawer",
            -lx + leg / 2,
            lx - leg / 2,
            ly,
            hy,
            under - box_h + 0.1 * box_h,
            under - 0.1 * box_h,
        )
        shelf_z = clamp(0.15 * sz, 0.03, 0.1)
        parts.append(slab("shelf", (-lx, -ly, shelf_z), (lx, ly, shelf_z + 0.7 * top_t)))
    elif style == 1:
        leg_h = clamp(0.1 * sz, 0.02, 0.08) * jitter(rng)
        wall = clamp(0.05 * short, 0.012, 0.025)
        over = clamp(0.02 * short, 0.0, 0.015)
        x0, x1 = -hx + over, hx - over
        front = hy - clamp(0.06 * sy, 0.015, 0.03)  # carcass front; drawer and handle ahead
        parts = [slab("top", (-hx, -hy, under), (hx, hy, sz))]
        leg = clamp(0.08 * short, 0.02, 0.045)
        parts += corner_legs(x1 - leg / 2, front - leg / 2, 0.0, leg_h, leg, taper=0.7)
        parts += [
            slab("side_left", (x0, -hy + over, leg_h), (x0 + wall, front, under)),
            slab("side_right", (x1 - wall, -hy + over, leg_h), (x1, front, under)),
            slab("back", (x0, -hy + over, leg_h), (x1, -hy + over + wall, under)),
            slab("bottom", (x0, -hy + over, leg_h), (x1, front, leg_h + wall)),
        ]
        div_z = leg_h + 0.55 * (under - leg_h)
        parts.append(slab("shelf", (x0, -hy + over, div_z - wall), (x1, front, div_z)))
        parts += drawer_front(
            "drawer", x0 + 0.003, x1 - 0.003, front - wall, hy, div_z + 0.004, under - 0.004
        )
    else:
        parts = [Part("top", z_cylinder(0.0, 0.0, under, sz, (hx, hy)))]
        col_r = clamp(0.07 * short, 0.015, 0.05) * jitter(rng)
        base_h = clamp(0.05 * sz, 0.015, 0.04)
        parts += [
            Part(
                "base",
                frustum(
                    (0.0, 0.0, 0.0),
                    base_h,
                    (0.7 * hx, 0.7 * hy),
                    (0.6 * hx, 0.6 * hy),
                    ROUND_SEGMENTS,
                ),
            ),
            Part("column", z_cylinder(0.0, 0.0, base_h, under, col_r, THIN_SEGMENTS * 2)),
        ]
    return floor_to_centre(parts, sz)


HUTCH_MIN_HEIGHT = 1.05
"""m; a desk box at least this tall holds a hutch above a ~0.76 m work top."""
MIRROR_MIN_HEIGHT = 1.05
"""m; a dressing-table box at least this tall holds a standing mirror above the top."""
WORK_HEIGHT = 0.76
"""m; usual height of a desk or dressing-table top when something stands above it."""


def _work_height(sz: float, rng: np.random.Generator) -> float:
    """Height of a work top with a hutch or mirror above it, within a box of height sz."""
    return min(WORK_HEIGHT * jitter(rng, 0.03), 0.62 * sz)


@register("desk", variants=3)
@min_design_extent(0.35)
def desk(
    size: np.ndarray,
    rng: np.random.Generator,
    style: int,
    support_heights: Sequence[float] | None = None,
) -> list[Part]:
    """Desk: slim legs with a modesty panel (0), a drawer pedestal at +x and a panel end
    at -x (1), or panel ends with a centre drawer (2). In a box tall enough, a hutch with a
    shelf stands on the back of the top. The knee space under the top is open toward +y."""
    sx, sy, sz = (float(v) for v in size)
    hx, hy, short = sx / 2, sy / 2, min(sx, sy)
    hutch = sz >= HUTCH_MIN_HEIGHT  # a box this tall in the data holds a hutch
    work = _work_height(sz, rng) if hutch else sz
    top_t = _top_thickness(work, rng, 0.04, 0.018, 0.04)
    under = work - top_t
    pt = clamp(0.03 * short, 0.015, 0.035)  # panel thickness
    front_d = clamp(0.05 * sy, 0.015, 0.03)  # depth of a drawer front and its handle
    parts = [slab("top", (-hx, -hy, under), (hx, hy, work))]
    if style == 0:
        leg = clamp(0.05 * short, 0.02, 0.05) * jitter(rng)
        inset = clamp(0.03 * short, 0.005, 0.03)
        lx, ly = hx - inset - leg / 2, hy - inset - leg / 2
        parts += corner_legs(lx, ly, 0.0, under, leg)
        rail_h = clamp(0.08 * under, 0.02, 0.06)
        parts += [
            slab(
                "modesty_panel", (-lx, -ly - pt / 2, under - 0.4 * under), (lx, -ly + pt / 2, under)
            ),
            slab("rail_left", (-lx - pt / 2, -ly, under - rail_h), (-lx + pt / 2, ly, under)),
            slab("rail_right", (lx - pt / 2, -ly, under - rail_h), (lx + pt / 2, ly, under)),
        ]
    elif style == 1:
        ped_w = min(clamp(0.3 * sx, 0.2, 0.45), 0.4 * sx) * jitter(rng)
        px0, front = hx - ped_w, hy - front_d
        kick = clamp(0.06 * under, 0.015, 0.05)
        parts += [
            slab("pedestal", (px0, -hy + pt, 0.0), (hx, front, under)),
            slab("side_left", (-hx, -hy + pt, 0.0), (-hx + pt, hy - pt, under)),
            slab(
                "modesty_panel",
                (-hx + pt, -hy + pt, under - 0.45 * under),
                (px0, -hy + 2 * pt, under),
            ),
        ]
        n = 3 if under > 0.5 else 2
        edges = np.linspace(kick, under - 0.01, n + 1)
        for i in range(n):
            parts += drawer_front(
                f"drawer_{i}",
                px0 + 0.004,
                hx - 0.004,
                front - 0.005,
                hy,
                edges[i] + 0.003,
                edges[i + 1] - 0.003,
            )
    else:
        front = hy - pt - front_d  # the handle ends flush with the side panels
        drawer_h = clamp(0.14 * under, 0.04, 0.12)
        parts += [
            slab("side_left", (-hx, -hy, 0.0), (-hx + pt, hy - pt, under)),
            slab("side_right", (hx - pt, -hy, 0.0), (hx, hy - pt, under)),
            slab(
                "back_rail",
                (-hx + pt, -hy + pt, 0.15 * under),
                (hx - pt, -hy + 2 * pt, 0.3 * under),
            ),
            slab(
                "drawer_box", (-0.3 * sx, -hy + 2 * pt, under - drawer_h), (0.3 * sx, front, under)
            ),
        ]
        parts += drawer_front(
            "drawer",
            -0.3 * sx + 0.004,
            0.3 * sx - 0.004,
            front - 0.005,
            hy - pt,
            under - drawer_h + 0.004,
            under - 0.004,
        )
    if hutch:
        hd = clamp(0.4 * sy, 0.15, 0.32)
        shelf_z = work + 0.5 * (sz - work)
        parts += [
            slab("hutch_left", (-hx, -hy, work), (-hx + pt, -hy + hd, sz)),
            slab("hutch_right", (hx - pt, -hy, work), (hx, -hy + hd, sz)),
            slab("hutch_back", (-hx + pt, -hy, work), (hx - pt, -hy + pt, sz - pt)),
            slab("hutch_top", (-hx + pt, -hy, sz - pt), (hx - pt, -hy + hd, sz)),
            slab("hutch_shelf", (-hx + pt, -hy + pt, shelf_z - pt), (hx - pt, -hy + hd, shelf_z)),
        ]
    return floor_to_centre(parts, sz)


@register("dressing_table", variants=2)
@min_design_extent(0.3)
def dressing_table(
    size: np.ndarray,
    rng: np.random.Generator,
    style: int,
    support_heights: Sequence[float] | None = None,
) -> list[Part]:
    """Dressing table: round tapered legs, an apron drawer and a framed rectangular mirror
    (0), or two drawer pedestals around the knee space and an oval mirror (1). The mirror
    stands on the top's back edge when the box is tall enough for one."""
    sx, sy, sz = (float(v) for v in size)
    hx, hy, short = sx / 2, sy / 2, min(sx, sy)
    mirror = sz >= MIRROR_MIN_HEIGHT
    work = _work_height(sz, rng) if mirror else sz
    top_t = _top_thickness(work, rng, 0.04, 0.018, 0.035)
    under = work - top_t
    front_d = clamp(0.05 * sy, 0.015, 0.03)
    frame_t = clamp(0.05 * sy, 0.015, 0.035)  # mirror frame depth
    parts = [slab("top", (-hx, -hy, under), (hx, hy, work))]
    if style == 0:
        leg = clamp(0.06 * short, 0.025, 0.05) * jitter(rng)
        inset = clamp(0.03 * short, 0.005, 0.03)
        lx, ly = hx - inset - leg / 2, hy - inset - leg / 2
        parts += corner_legs(lx, ly, 0.0, under, leg, round_legs=True, taper=0.55)
        drawer_h = clamp(0.18 * under, 0.05, 0.14)
        parts.append(slab("drawer_box", (-lx, -ly, under - drawer_h), (lx, ly, under)))
        parts += drawer_front(
            "drawer",
            -0.3 * sx,
            0.3 * sx,
            ly - 0.005,
            min(hy, ly + leg / 2 + 0.015),
            under - drawer_h + 0.005,
            under - 0.005,
        )
        if mirror:
            mw = min(0.7 * sx, 1.2) * jitter(rng)
            border = clamp(0.06 * mw, 0.02, 0.05)
            parts += [
                slab("mirror_frame", (-mw / 2, -hy, work), (mw / 2, -hy + frame_t, sz)),
                slab(
                    "mirror",
                    (-mw / 2 + border, -hy + frame_t, work + border),
                    (mw / 2 - border, -hy + frame_t + 0.004, sz - border),
                ),
            ]
    else:
        ped_w = min(clamp(0.25 * sx, 0.15, 0.4), 0.3 * sx) * jitter(rng)
        front = hy - front_d
        n = 3 if under > 0.55 else 2
        edges = np.linspace(0.02 * under, under - 0.005, n + 1)
        for side, (x0, x1) in (("left", (-hx, -hx + ped_w)), ("right", (hx - ped_w, hx))):
            parts.append(slab(f"pedestal_{side}", (x0, -hy, 0.0), (x1, front, under)))
            for i in range(n):
                parts += drawer_front(
                    f"drawer_{side}_{i}",
                    x0 + 0.004,
                    x1 - 0.004,
                    front - 0.005,
                    hy,
                    edges[i] + 0.003,
                    edges[i + 1] - 0.003,
                )
        if mirror:
            stand_h = clamp(0.1 * (sz - work), 0.02, 0.06)
            rz = (sz - work - stand_h) / 2
            rx = min(0.3 * sx, 0.75 * rz) * jitter(rng)
            cz = work + stand_h + rz
            parts += [
                slab(
                    "mirror_stand",
                    (-0.4 * rx, -hy, work),
                    (0.4 * rx, -hy + 3 * frame_t, work + stand_h),
                ),
                Part(
                    "mirror_frame",
                    y_cylinder(-hy + frame_t, -hy + 2 * frame_t, 0.0, cz, rx, rz, ROUND_SEGMENTS),
                ),
                Part(
                    "mirror",
                    y_cylinder(
                        -hy + 2 * frame_t,
                        -hy + 2 * frame_t + 0.004,
                        0.0,
                        cz,
                        0.9 * rx,
                        rz - 0.1 * rx,
                        ROUND_SEGMENTS,
                    ),
                ),
            ]
    return floor_to_centre(parts, sz)


@register("bed", variants=3)
@min_design_extent(0.4)
def bed(
    size: np.ndarray,
    rng: np.random.Generator,
    style: int,
    support_heights: Sequence[float] | None = None,
) -> list[Part]:
    """Bed: a mattress (the upward surface, near half the box height) on a frame, with a
    headboard at -y spanning the full height. Upholstered base on a recessed plinth with a
    padded headboard (0), wooden frame with corner posts and a footboard (1), or a low
    platform wider than the mattress with a slatted headboard (2)."""
    sx, sy, sz = (float(v) for v in size)
    hx, hy = sx / 2, sy / 2
    mat_top = clamp(0.5 * jitter(rng, 0.05), 0.35, 0.7) * sz
    mat_t = min(clamp(0.22 * sz, 0.08, 0.3) * jitter(rng), 0.6 * mat_top)
    frame_top = mat_top - mat_t
    mi = clamp(0.015 * sx, 0.005, 0.03)  # mattress inset from the frame's edge
    if style == 0:
        hb_t = clamp(0.06 * sy, 0.05, 0.14)
        pi_ = clamp(0.05 * min(sx, sy), 0.02, 0.08)
        plinth_h = 0.3 * frame_top
        pad_t = 0.5 * hb_t
        parts = [
            slab("headboard", (-hx, -hy, 0.0), (hx, -hy + hb_t, sz)),
            rounded_slab(
                "headboard_pad",
                -hx + 0.04 * sx,
                hx - 0.04 * sx,
                -hy + hb_t,
                -hy + hb_t + pad_t,
                mat_top,
                sz - 0.12 * (sz - mat_top),
                pad_t / 2,
            ),
            slab("plinth", (-hx + pi_, -hy + hb_t, 0.0), (hx - pi_, hy - pi_, plinth_h)),
            slab("frame", (-hx, -hy + hb_t, plinth_h), (hx, hy, frame_top)),
            rounded_slab(
                "mattress", -hx + mi, hx - mi, -hy + hb_t, hy - mi, frame_top, mat_top, 2 * mi
            ),
        ]
    elif style == 1:
        post = clamp(0.04 * sx, 0.04, 0.08) * jitter(rng)
        pt = 0.5 * post
        foot_top = min(mat_top + clamp(0.12 * sz, 0.04, 0.15), sz)
        rail_h = clamp(0.15 * sz, 0.05, 0.2)
        frame_bot = max(frame_top - rail_h, 0.05 * sz)
        px, hyp, fyp = hx - post / 2, -hy + post / 2, hy - post / 2
        parts = [
            slab(
                "headboard_post_left",
                (-px - post / 2, hyp - post / 2, 0.0),
                (-px + post / 2, hyp + post / 2, sz),
            ),
            slab(
                "headboard_post_right",
                (px - post / 2, hyp - post / 2, 0.0),
                (px + post / 2, hyp + post / 2, sz),
            ),
            slab(
                "footboard_post_right",
                (px - post / 2, fyp - post / 2, 0.0),
                (px + post / 2, fyp + post / 2, foot_top),
            ),
            slab(
                "footboard_post_left",
                (-px - post / 2, fyp - post / 2, 0.0),
                (-px + post / 2, fyp + post / 2, foot_top),
            ),
            slab(
                "headboard",
                (-px, hyp - pt / 2, frame_bot),
                (px, hyp + pt / 2, sz - 0.1 * (sz - mat_top)),
            ),
            slab(
                "footboard",
                (-px, fyp - pt / 2, frame_bot),
                (px, fyp + pt / 2, foot_top - 0.02 * sz),
            ),
            slab("rail_left", (-hx, hyp, frame_bot), (-hx + pt, fyp, frame_top)),
            slab("rail_right", (hx - pt, hyp, frame_bot), (hx, fyp, frame_top)),
            slab("frame", (-hx + pt, hyp, frame_top - 0.3 * rail_h), (hx - pt, fyp, frame_top)),
            rounded_slab(
                "mattress",
                -hx + mi,
                hx - mi,
                hyp + post / 2,
                fyp - post / 2,
                frame_top,
                mat_top,
                2 * mi,
            ),
        ]
    else:
        rim = clamp(0.05 * min(sx, sy), 0.04, 0.12) * jitter(rng)  # platform beyond mattress
        hb_t = clamp(0.04 * sy, 0.03, 0.08)
        plat_t = clamp(0.35 * frame_top, 0.03, 0.08)
        plinth_in = clamp(0.08 * min(sx, sy), 0.05, 0.2)
        slat_top = sz - 0.08 * (sz - mat_top)
        n_slats = int(clamp(round(sx / 0.25), 3, 9))
        slat_w = 0.45 * sx / n_slats
        parts = [
            slab(
                "plinth",
                (-hx + plinth_in, -hy + hb_t, 0.0),
                (hx - plinth_in, hy - plinth_in, frame_top - plat_t),
            ),
            slab("frame", (-hx, -hy + hb_t, frame_top - plat_t), (hx, hy, frame_top)),
            rounded_slab(
                "mattress", -hx + rim, hx - rim, -hy + hb_t, hy - rim, frame_top, mat_top, 2 * mi
            ),
            slab("headboard", (-hx, -hy, 0.0), (hx, -hy + hb_t, frame_top + 0.5 * mat_t)),
            slab("headboard_rail", (-hx, -hy, slat_top), (hx, -hy + hb_t, sz)),
        ]
        xs = np.linspace(-hx + slat_w, hx - slat_w, n_slats)
        for i, x in enumerate(xs):
            parts.append(
                slab(
                    f"headboard_slat_{i}",
                    (x - slat_w / 2, -hy + 0.2 * hb_t, frame_top),
                    (x + slat_w / 2, -hy + 0.8 * hb_t, slat_top),
                )
            )
    return floor_to_centre(parts, sz)


@register("dog_bed", variants=2)
@min_design_extent(0.1)
def dog_bed(
    size: np.ndarray,
    rng: np.random.Generator,
    style: int,
    support_heights: Sequence[float] | None = None,
) -> list[Part]:
    """Dog bed: an oval cushion in a padded rim that dips at the front (0), or a
    rectangular cushion framed by bolsters, the back one highest (1)."""
    sx, sy, sz = (float(v) for v in size)
    hx, hy, short = sx / 2, sy / 2, min(sx, sy)
    base_t = min(clamp(0.35 * sz, 0.02, 0.08) * jitter(rng), 0.45 * sz)
    if style == 0:
        w = clamp(0.16 * short, 0.03, 0.15) * jitter(rng)  # rim width
        parts = [
            Part(
                "cushion",
                lathe(
                    [(1.0, 0.0), (1.0, 0.7 * base_t), (0.93, base_t)], hx - 0.7 * w, hy - 0.7 * w
                ),
            )
        ]
        n = 12  # rim pieces; a multiple of 4 so the rim reaches +-x, +-y exactly

        def rim_height(a: float) -> float:
            # full height at the back (-y), lowest at the front opening (+y)
            return base_t + (sz - base_t) * (0.5 + 0.5 * (1.0 - np.sin(a)) / 2)

        for i in range(n):
            pts = []
            for a in (2 * np.pi * i / n, 2 * np.pi * (i + 1) / n):
                c, s, h = np.cos(a), np.sin(a), rim_height(a)
                pts += [
                    (hx * c, hy * s, 0.0),
                    (hx * c, hy * s, h - 0.3 * w),
                    ((hx - 0.5 * w) * c, (hy - 0.5 * w) * s, h),
                    ((hx - w) * c, (hy - w) * s, h - 0.3 * w),
                    ((hx - w) * c, (hy - w) * s, 0.0),
                ]
            parts.append(Part(f"rim_{i}", hull(np.array(pts))))
    else:
        rb = clamp(0.1 * sy, 0.03, 0.12) * jitter(rng)  # back bolster half-depth
        rs = clamp(0.08 * sx, 0.025, 0.1)  # side bolster half-width
        rf = 0.8 * rs
        hs, hf = 0.8 * sz, 0.55 * sz
        parts = [
            rounded_slab("cushion", -hx + rs, hx - rs, -hy + rb, hy - rf, 0.0, base_t, 0.5 * rs),
            Part("bolster_back", x_cylinder(-hx, hx, -hy + rb, sz / 2, rb, sz / 2)),
            Part("bolster_left", y_cylinder(-hy + rb, hy - rf, -hx + rs, hs / 2, rs, hs / 2)),
            Part("bolster_right", y_cylinder(-hy + rb, hy - rf, hx - rs, hs / 2, rs, hs / 2)),
            Part("bolster_front", x_cylinder(-hx + rs, hx - rs, hy - rf, hf / 2, rf, hf / 2)),
        ]
    return floor_to_centre(parts, sz)

"""Tables, desks and dressing tables.

The building blocks these share with seating and beds (legs, tapered posts, lathed
solids, rounded slabs, rings of boxes) are in ``shapes.py``. Generators build in
*floor coordinates* (z from 0 at the floor to the box height, x and y centred) and
hand their parts to :func:`floor_to_centre` last, so the geometry reads like a
carpenter's drawing; every part is one closed convex primitive.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from pair2scene.assets.generators.shapes import (
    FINE_SEGMENTS,
    ROD_SEGMENTS,
    clip,
    corner_legs,
    drawer_front,
    floor_to_centre,
    jitter,
    min_design_extent,
    ring_points,
    slab,
    y_cylinder,
    z_cylinder,
)
from pair2scene.assets.mesh import Part, frustum, hull
from pair2scene.assets.registry import register


def _top_thickness(
    sz: float, rng: np.random.Generator, frac: float = 0.05, lo: float = 0.02, hi: float = 0.06
) -> float:
    """Table-top thickness from the height, never more than a sixth of it."""
    return min(clip(frac * sz, lo, hi) * jitter(rng), sz / 6)


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
        leg = clip(0.06 * short, 0.03, 0.09) * jitter(rng)
        inset = clip(0.04 * short, 0.01, 0.06) * jitter(rng)
        lx, ly = hx - inset - leg / 2, hy - inset - leg / 2
        parts += corner_legs(lx, ly, 0.0, under, leg, taper=0.7)
        apron_h, apron_t = clip(0.12 * sz, 0.02, 0.11), 0.4 * leg
        z0 = under - apron_h
        parts += [
            slab("apron_front", (-lx, ly - apron_t / 2, z0), (lx, ly + apron_t / 2, under)),
            slab("apron_back", (-lx, -ly - apron_t / 2, z0), (lx, -ly + apron_t / 2, under)),
            slab("apron_left", (-lx - apron_t / 2, -ly, z0), (-lx + apron_t / 2, ly, under)),
            slab("apron_right", (lx - apron_t / 2, -ly, z0), (lx + apron_t / 2, ly, under)),
        ]
    elif style == 1:
        parts = [Part("top", z_cylinder(0.0, 0.0, under, sz, (hx, hy)))]
        col_r = clip(0.06 * short, 0.03, 0.09) * jitter(rng)
        foot_h = clip(0.06 * sz, 0.02, 0.06)
        elongated = max(sx, sy) > 1.5 * short
        # one column under a round-ish top, two along the long axis of an oval one
        offs = [0.0] if not elongated else [-0.28, 0.28]
        for i, f in enumerate(offs):
            cx, cy = (f * sx, 0.0) if sx >= sy else (0.0, f * sy)
            foot_r = 0.3 * short
            parts.append(
                Part(
                    f"foot_{i}",
                    frustum((cx, cy, 0.0), foot_h, foot_r, 0.5 * foot_r, FINE_SEGMENTS),
                )
            )
            parts.append(
                Part(f"column_{i}", z_cylinder(cx, cy, foot_h, under, col_r, FINE_SEGMENTS))
            )
            cap_h = clip(0.04 * sz, 0.01, 0.04)
            parts.append(
                Part(
                    f"cap_{i}",
                    frustum((cx, cy, under - cap_h), cap_h, col_r, 2.5 * col_r, FINE_SEGMENTS),
                )
            )
    else:
        parts = [slab("top", (-hx, -hy, under), (hx, hy, sz))]
        ut = clip(0.04 * short, 0.025, 0.07) * jitter(rng)
        ud = clip(0.2 * sy, 0.05, 0.2)
        ex = hx - clip(0.12 * sx, 0.04, 0.3) * jitter(rng)
        foot_h, cleat_h = clip(0.06 * sz, 0.02, 0.07), clip(0.05 * sz, 0.015, 0.06)
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
        st_h = clip(0.07 * sz, 0.02, 0.07)
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
    shelf_z = clip(0.15 * sz, 0.03, 0.1) * jitter(rng)
    shelf_t = 0.6 * top_t
    if style == 0:
        parts = [slab("top", (-hx, -hy, under), (hx, hy, sz))]
        leg = clip(0.07 * short, 0.025, 0.07) * jitter(rng)
        inset = clip(0.03 * short, 0.0, 0.04)
        lx, ly = hx - inset - leg / 2, hy - inset - leg / 2
        parts += corner_legs(lx, ly, 0.0, under, leg)
        parts.append(slab("shelf", (-lx, -ly, shelf_z), (lx, ly, shelf_z + shelf_t)))
    elif style == 1:
        parts = [Part("top", z_cylinder(0.0, 0.0, under, sz, (hx, hy)))]
        r = clip(0.035 * short, 0.012, 0.03) * jitter(rng)
        for i, a in enumerate(np.radians([45.0, 135.0, 225.0, 315.0])):
            c, s = np.cos(a), np.sin(a)
            # legs splay outwards: feet further out than the tops
            top_ring = ring_points(r, r, under, ROD_SEGMENTS, 0.55 * hx * c, 0.55 * hy * s)
            foot_ring = ring_points(
                0.6 * r, 0.6 * r, 0.0, ROD_SEGMENTS, 0.72 * hx * c, 0.72 * hy * s
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
        leg = clip(0.08 * short, 0.02, 0.05) * jitter(rng)
        inset = clip(0.03 * short, 0.0, 0.03)
        lx, ly = hx - inset - leg / 2, hy - inset - leg / 2
        parts += corner_legs(lx, ly, 0.0, under, leg, taper=0.75)
        box_h = clip(0.2 * sz, 0.04, 0.15)
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
        shelf_z = clip(0.15 * sz, 0.03, 0.1)
        parts.append(slab("shelf", (-lx, -ly, shelf_z), (lx, ly, shelf_z + 0.7 * top_t)))
    elif style == 1:
        leg_h = clip(0.1 * sz, 0.02, 0.08) * jitter(rng)
        wall = clip(0.05 * short, 0.012, 0.025)
        over = clip(0.02 * short, 0.0, 0.015)
        x0, x1 = -hx + over, hx - over
        front = hy - clip(0.06 * sy, 0.015, 0.03)  # carcass front; drawer and handle ahead
        parts = [slab("top", (-hx, -hy, under), (hx, hy, sz))]
        leg = clip(0.08 * short, 0.02, 0.045)
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
        col_r = clip(0.07 * short, 0.015, 0.05) * jitter(rng)
        base_h = clip(0.05 * sz, 0.015, 0.04)
        parts += [
            Part(
                "base",
                frustum(
                    (0.0, 0.0, 0.0),
                    base_h,
                    (0.7 * hx, 0.7 * hy),
                    (0.6 * hx, 0.6 * hy),
                    FINE_SEGMENTS,
                ),
            ),
            Part("column", z_cylinder(0.0, 0.0, base_h, under, col_r, FINE_SEGMENTS)),
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
    pt = clip(0.03 * short, 0.015, 0.035)  # panel thickness
    front_d = clip(0.05 * sy, 0.015, 0.03)  # depth of a drawer front and its handle
    parts = [slab("top", (-hx, -hy, under), (hx, hy, work))]
    if style == 0:
        leg = clip(0.05 * short, 0.02, 0.05) * jitter(rng)
        inset = clip(0.03 * short, 0.005, 0.03)
        lx, ly = hx - inset - leg / 2, hy - inset - leg / 2
        parts += corner_legs(lx, ly, 0.0, under, leg)
        rail_h = clip(0.08 * under, 0.02, 0.06)
        parts += [
            slab(
                "modesty_panel", (-lx, -ly - pt / 2, under - 0.4 * under), (lx, -ly + pt / 2, under)
            ),
            slab("rail_left", (-lx - pt / 2, -ly, under - rail_h), (-lx + pt / 2, ly, under)),
            slab("rail_right", (lx - pt / 2, -ly, under - rail_h), (lx + pt / 2, ly, under)),
        ]
    elif style == 1:
        ped_w = min(clip(0.3 * sx, 0.2, 0.45), 0.4 * sx) * jitter(rng)
        px0, front = hx - ped_w, hy - front_d
        kick = clip(0.06 * under, 0.015, 0.05)
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
        drawer_h = clip(0.14 * under, 0.04, 0.12)
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
        hd = clip(0.4 * sy, 0.15, 0.32)
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
    front_d = clip(0.05 * sy, 0.015, 0.03)
    frame_t = clip(0.05 * sy, 0.015, 0.035)  # mirror frame depth
    parts = [slab("top", (-hx, -hy, under), (hx, hy, work))]
    if style == 0:
        leg = clip(0.06 * short, 0.025, 0.05) * jitter(rng)
        inset = clip(0.03 * short, 0.005, 0.03)
        lx, ly = hx - inset - leg / 2, hy - inset - leg / 2
        parts += corner_legs(lx, ly, 0.0, under, leg, round_legs=True, taper=0.55)
        drawer_h = clip(0.18 * under, 0.05, 0.14)
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
            border = clip(0.06 * mw, 0.02, 0.05)
            parts += [
                slab("mirror_frame", (-mw / 2, -hy, work), (mw / 2, -hy + frame_t, sz)),
                slab(
                    "mirror",
                    (-mw / 2 + border, -hy + frame_t, work + border),
                    (mw / 2 - border, -hy + frame_t + 0.004, sz - border),
                ),
            ]
    else:
        ped_w = min(clip(0.25 * sx, 0.15, 0.4), 0.3 * sx) * jitter(rng)
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
            stand_h = clip(0.1 * (sz - work), 0.02, 0.06)
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
                    y_cylinder(-hy + frame_t, -hy + 2 * frame_t, 0.0, cz, rx, rz, FINE_SEGMENTS),
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
                        FINE_SEGMENTS,
                    ),
                ),
            ]
    return floor_to_centre(parts, sz)

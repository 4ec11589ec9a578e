"""Seating: chairs, stools, ottomans, armchairs and sofas.

Built in floor coordinates like the tables (the shared building blocks are in
``shapes.py``). Every seat is a horizontal upward surface; backs rise at -y,
arms sit at +-x, and the front (+y) stays open.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from pair2scene.assets.generators.shapes import (
    FINE_SEGMENTS,
    ROD_SEGMENTS,
    clip,
    corner_legs,
    floor_to_centre,
    jitter,
    lathe,
    min_design_extent,
    ring_of_boxes,
    ring_points,
    rounded_slab,
    sheared,
    slab,
    tapered_box,
    y_cylinder,
    z_cylinder,
)
from pair2scene.assets.mesh import Part, box, box_between, frustum, hull
from pair2scene.assets.registry import register

CHAIR_SEAT_FRACTION = 0.5
"""Seat top over a chair's height: 0.45 m of a 0.9 m dining chair."""
LOUNGE_SEAT_FRACTION = 0.48
"""Seat top over an armchair's or sofa's height: about 0.42 m of a 0.88 m sofa."""
SOFA_SEAT_WIDTH = 0.62
"""m; width of one seat cushion of a sofa, to split the seat into 2 or 3 cushions."""
FOOTREST_MIN_HEIGHT = 0.55
"""m; stools at least this tall (counter and bar stools) get a footrest ring."""


# -- chairs ---------------------------------------------------------------------------
@register("chair", variants=3)
@min_design_extent(0.3)
def chair(
    size: np.ndarray,
    rng: np.random.Generator,
    style: int,
    support_heights: Sequence[float] | None = None,
) -> list[Part]:
    """Chair: four legs whose rear pair rises into back posts around a back panel (0), a
    tubular cantilever frame with a leaning back (1), or an office chair on a five-star
    swivel base (2). The seat top is near half the height; the backrest rises at -y."""
    sx, sy, sz = (float(v) for v in size)
    hx, hy, short = sx / 2, sy / 2, min(sx, sy)
    seat_top = clip(CHAIR_SEAT_FRACTION * jitter(rng, 0.04), 0.35, 0.65) * sz
    seat_t = min(clip(0.05 * sz, 0.02, 0.06) * jitter(rng), 0.2 * seat_top)
    seat_bot = seat_top - seat_t
    if style == 0:
        leg = clip(0.08 * short, 0.02, 0.05) * jitter(rng)
        lx, fy, by = hx - leg / 2, hy - leg / 2, -hy + leg / 2
        bt = clip(0.05 * sy, 0.015, 0.035)  # back panel thickness
        parts = [
            Part("leg_0", tapered_box(-lx, by, 0.0, sz, (leg, leg), (0.8 * leg, 0.8 * leg))),
            Part("leg_1", tapered_box(lx, by, 0.0, sz, (leg, leg), (0.8 * leg, 0.8 * leg))),
            Part("leg_2", tapered_box(lx, fy, 0.0, seat_bot, (leg, leg), (0.7 * leg, 0.7 * leg))),
            Part("leg_3", tapered_box(-lx, fy, 0.0, seat_bot, (leg, leg), (0.7 * leg, 0.7 * leg))),
            slab("seat", (-hx, -hy, seat_bot), (hx, hy, seat_top)),
            slab(
                "back", (-lx, by - bt / 2, seat_top + 0.3 * (sz - seat_top)), (lx, by + bt / 2, sz)
            ),
        ]
        st = 0.6 * leg
        st_z = 0.25 * seat_bot
        for name, x in (("stretcher_left", -lx), ("stretcher_right", lx)):
            parts.append(slab(name, (x - st / 2, by, st_z), (x + st / 2, fy, st_z + st)))
    elif style == 1:
        # cantilever: each side one bent tube (floor runner, front upright, rail under the
        # seat, leaning back tube); nothing holds the seat's rear from below
        r = clip(0.025 * short, 0.007, 0.014)
        fx = hx - 1.5 * r  # frame sits under the seat's side edges
        y_top = -hy + r  # back tube at the top of the chair
        y_rear = -hy + r + clip(0.12 * sy, 0.02, 0.08) * jitter(rng)  # ... at the seat
        z_rail = seat_bot - r
        lean = (y_top - y_rear) / (sz - z_rail)  # dy per dz of the back tubes (< 0)
        bt = clip(0.04 * sy, 0.01, 0.025)
        parts = [rounded_slab("seat", -hx, hx, y_rear - r, hy, seat_bot, seat_top, 0.1 * short)]
        for side, x in (("left", -fx), ("right", fx)):
            foot = ring_points(r, r, z_rail, ROD_SEGMENTS, x, y_rear)
            top = ring_points(r, r, sz, ROD_SEGMENTS, x, y_top)
            parts += [
                Part(f"runner_{side}", y_cylinder(y_rear, hy, x, r, r, r, ROD_SEGMENTS)),
                Part(f"upright_{side}", z_cylinder(x, hy - r, 0.0, seat_bot, r, ROD_SEGMENTS)),
                Part(f"seat_rail_{side}", y_cylinder(y_rear, hy, x, z_rail, r, r, ROD_SEGMENTS)),
                Part(f"back_tube_{side}", hull(np.concatenate([foot, top]))),
            ]
        z0 = seat_top + 0.35 * (sz - seat_top)
        zm = (z0 + sz) / 2
        panel = box((0.0, y_top + lean * (zm - sz) + r + bt / 2, zm), (2 * fx + 2 * r, bt, sz - z0))
        parts.append(Part("back", sheared(panel, lean, zm)))
    else:
        rb = min(hx, hy)  # star radius; one arm points to +y, the others stay inside
        caster_h = clip(0.06 * sz, 0.02, 0.05)
        arm_h = clip(0.05 * sz, 0.015, 0.04)
        arm_w = clip(0.12 * rb, 0.02, 0.05)
        col_r = clip(0.06 * short, 0.012, 0.03)
        cush_t = min(clip(0.09 * sz, 0.03, 0.09), 0.3 * seat_top)
        back_t = clip(0.08 * sy, 0.02, 0.06)
        parts = [
            Part(
                "hub",
                z_cylinder(0.0, 0.0, caster_h, caster_h + 1.6 * arm_h, 2 * col_r, FINE_SEGMENTS),
            )
        ]
        for i in range(5):
            a = np.pi / 2 + 2 * np.pi * i / 5
            c, s = np.cos(a), np.sin(a)
            rot = np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])
            parts.append(
                Part(
                    f"base_arm_{i}",
                    box(
                        (0.5 * rb * c, 0.5 * rb * s, caster_h + arm_h / 2), (rb, arm_w, arm_h), rot
                    ),
                )
            )
            tip = rb - arm_w
            parts.append(
                Part(
                    f"caster_{i}",
                    z_cylinder(
                        tip * c, tip * s, 0.0, caster_h, 0.5 * caster_h + 0.3 * arm_w, ROD_SEGMENTS
                    ),
                )
            )
        mech_h = clip(0.04 * sz, 0.015, 0.04)
        y_back = -hy + back_t  # front face of the backrest at its top
        parts += [
            Part(
                "column",
                z_cylinder(
                    0.0, 0.0, caster_h + arm_h, seat_top - cush_t - mech_h, col_r, ROD_SEGMENTS
                ),
            ),
            slab(
                "mechanism",
                (-0.25 * sx, -0.2 * sy, seat_top - cush_t - mech_h),
                (0.25 * sx, 0.2 * sy, seat_top - cush_t),
            ),
            rounded_slab(
                "seat", -hx, hx, -hy + 1.6 * back_t, hy, seat_top - cush_t, seat_top, 0.2 * short
            ),
        ]
        z0 = seat_top + 0.12 * (sz - seat_top)
        zm = (z0 + sz) / 2
        lean = -clip(0.6 * back_t / (sz - z0), 0.0, 0.25)  # top leans back to y = -hy
        back = rounded_slab(
            "back", -0.9 * hx, 0.9 * hx, y_back - back_t, y_back, z0, sz, 0.15 * short
        )
        parts += [
            Part("back", sheared(back.mesh, lean, sz)),
            slab(
                "spine",
                (-0.08 * sx, y_back - back_t + 0.1 * back_t, seat_top - cush_t - mech_h),
                (0.08 * sx, y_back - 0.2 * back_t - lean * (sz - z0), z0 + 0.1 * (sz - z0)),
            ),
        ]
    return floor_to_centre(parts, sz)


@register("stool", variants=3)
@min_design_extent(0.25)
def stool(
    size: np.ndarray,
    rng: np.random.Generator,
    style: int,
    support_heights: Sequence[float] | None = None,
) -> list[Part]:
    """Stool: round seat on four splayed legs joined by a footrest ring (0), square seat on
    straight legs with stretchers (1), or round seat on a column and disc base, with a
    footrest ring when tall (2). The seat is the top of the box."""
    sx, sy, sz = (float(v) for v in size)
    hx, hy, short = sx / 2, sy / 2, min(sx, sy)
    seat_t = min(clip(0.07 * sz, 0.025, 0.06) * jitter(rng), 0.2 * sz)
    under = sz - seat_t
    tall = sz >= FOOTREST_MIN_HEIGHT
    round_seat = lathe(
        [(0.93, under), (1.0, under + 0.35 * seat_t), (1.0, sz - 0.35 * seat_t), (0.95, sz)], hx, hy
    )
    if style == 0:
        r = clip(0.05 * short, 0.01, 0.022) * jitter(rng)
        f_top, f_foot = 0.55, 0.85  # leg centres as fractions of the seat's radii
        parts = [Part("seat", round_seat)]
        for i, a in enumerate(np.radians([45.0, 135.0, 225.0, 315.0])):
            c, s = np.cos(a), np.sin(a)
            top = ring_points(r, r, under, ROD_SEGMENTS, f_top * hx * c, f_top * hy * s)
            foot = ring_points(
                0.8 * r, 0.8 * r, 0.0, ROD_SEGMENTS, f_foot * hx * c, f_foot * hy * s
            )
            parts.append(Part(f"leg_{i}", hull(np.concatenate([top, foot]))))
        z_ring = (0.32 if tall else 0.3) * under
        f = f_foot + (f_top - f_foot) * z_ring / under
        # ring vertices at 0, 45, 90 ... deg: every other one meets a leg
        parts += ring_of_boxes("footrest", f * hx, f * hy, z_ring, 8, 1.2 * r, 1.2 * r)
    elif style == 1:
        leg = clip(0.1 * short, 0.02, 0.045) * jitter(rng)
        lx, ly = hx - leg / 2 - 0.02 * sx, hy - leg / 2 - 0.02 * sy
        parts = [rounded_slab("seat", -hx, hx, -hy, hy, under, sz, 0.08 * short)]
        parts += corner_legs(lx, ly, 0.0, under, leg, taper=0.85)
        st = 0.6 * leg
        z_st = (0.3 if tall else 0.25) * under
        parts += [
            slab("stretcher_front", (-lx, ly - st / 2, z_st), (lx, ly + st / 2, z_st + st)),
            slab("stretcher_back", (-lx, -ly - st / 2, z_st), (lx, -ly + st / 2, z_st + st)),
            slab(
                "stretcher_left",
                (-lx - st / 2, -ly, z_st + 0.1 * under),
                (-lx + st / 2, ly, z_st + 0.1 * under + st),
            ),
            slab(
                "stretcher_right",
                (lx - st / 2, -ly, z_st + 0.1 * under),
                (lx + st / 2, ly, z_st + 0.1 * under + st),
            ),
        ]
    else:
        col_r = clip(0.08 * short, 0.02, 0.04) * jitter(rng)
        base_h = clip(0.04 * sz, 0.012, 0.03)
        parts = [
            Part("seat", round_seat),
            Part(
                "base",
                frustum(
                    (0.0, 0.0, 0.0),
                    base_h,
                    (0.85 * hx, 0.85 * hy),
                    (0.75 * hx, 0.75 * hy),
                    FINE_SEGMENTS,
                ),
            ),
            Part("column", z_cylinder(0.0, 0.0, base_h, under, col_r, FINE_SEGMENTS)),
            Part(
                "seat_plate",
                frustum(
                    (0.0, 0.0, under - 0.04 * sz), 0.04 * sz, col_r, 0.5 * short, FINE_SEGMENTS
                ),
            ),
        ]
        if tall:
            z_ring, w = 0.35 * sz, clip(0.04 * short, 0.01, 0.02)
            fr = 0.75
            parts += ring_of_boxes("footrest", fr * hx, fr * hy, z_ring, 12, w, w)
            parts += [
                slab(
                    "spoke_x", (-fr * hx, -w / 2, z_ring - w / 2), (fr * hx, w / 2, z_ring + w / 2)
                ),
                slab(
                    "spoke_y", (-w / 2, -fr * hy, z_ring - w / 2), (w / 2, fr * hy, z_ring + w / 2)
                ),
            ]
    return floor_to_centre(parts, sz)


@register("ottoman", variants=2)
@min_design_extent(0.25)
def ottoman(
    size: np.ndarray,
    rng: np.random.Generator,
    style: int,
    support_heights: Sequence[float] | None = None,
) -> list[Part]:
    """Ottoman: an upholstered block with a top cushion on short feet (0), or a round pouf
    bulging at mid height (1). Its flat top is the top of the box."""
    sx, sy, sz = (float(v) for v in size)
    hx, hy, short = sx / 2, sy / 2, min(sx, sy)
    if style == 0:
        foot_h = clip(0.1 * sz, 0.015, 0.07) * jitter(rng)
        cush_t = clip(0.25 * sz, 0.03, 0.12) * jitter(rng)
        e = clip(0.03 * short, 0.005, 0.02)  # body set in under the cushion's edge
        foot = clip(0.08 * short, 0.02, 0.05)
        parts = corner_legs(
            hx - 2 * e - foot / 2,
            hy - 2 * e - foot / 2,
            0.0,
            foot_h + 0.01,
            foot,
            round_legs=True,
            taper=0.7,
        )
        parts += [
            rounded_slab(
                "body", -hx + e, hx - e, -hy + e, hy - e, foot_h, sz - cush_t, 0.08 * short
            ),
            rounded_slab("cushion", -hx, hx, -hy, hy, sz - cush_t, sz, 0.1 * short),
        ]
    else:
        bulge = jitter(rng, 0.04)
        rim = 0.98 * sz  # the body's top; a slightly raised panel makes the flat seat
        profile = [
            (0.85, 0.0),
            (0.96, 0.15 * sz),
            (1.0, 0.45 * sz),
            (0.97, 0.75 * sz),
            (0.9 * bulge, 0.93 * sz),
            (0.8 * bulge, rim),
        ]
        parts = [
            Part("pouf", lathe(profile, hx, hy)),
            Part("top_panel", z_cylinder(0.0, 0.0, rim, sz, (0.6 * hx, 0.6 * hy))),
        ]
    return floor_to_centre(parts, sz)


# -- upholstered: armchairs and sofas -------------------------------------------------
def _upholstered(
    size: np.ndarray,
    rng: np.random.Generator,
    n_seats: int,
    arms: str,
    legs: bool,
    wings: bool = False,
) -> list[Part]:
    """Frame, seat cushions, back cushions and arms of an upholstered seat, floor coords.

    arms: ``"box"``, ``"rolled"`` or ``"none"``; legs: short feet (else a recessed plinth);
    wings: side wings on the back (wingback armchair). Seat cushions ``seat_i`` span the
    width between the arms; the back frame spans the full width at -y up to the top.
    """
    sx, sy, sz = (float(v) for v in size)
    hx, hy, short = sx / 2, sy / 2, min(sx, sy)
    seat_top = clip(LOUNGE_SEAT_FRACTION * jitter(rng, 0.04), 0.35, 0.6) * sz
    arm_top = seat_top + 0.42 * (sz - seat_top) * jitter(rng, 0.05)
    aw = 0.0 if arms == "none" else min(clip(0.12 * sx, 0.07, 0.2), 0.2 * sx) * jitter(rng)
    back_d = min(clip(0.2 * sy, 0.08, 0.22), 0.3 * sy) * jitter(rng)
    cush_t = min(clip(0.15 * sz, 0.05, 0.16), 0.35 * seat_top)
    base_top = seat_top - cush_t
    if legs:
        z0 = min(clip(0.12 * sz, 0.04, 0.15) * jitter(rng), 0.5 * base_top)
        leg = clip(0.05 * short, 0.025, 0.05)
        e = clip(0.03 * short, 0.01, 0.04)
        lx, ly = hx - e - leg / 2, hy - e - leg / 2
        parts = corner_legs(lx, ly, 0.0, z0 + 0.01, leg, round_legs=True, taper=0.6)
        if sx > 1.6:  # long sofas carry a middle pair of feet
            for i, y in enumerate((-ly, ly)):
                parts.append(
                    Part(
                        f"leg_{4 + i}",
                        frustum((0.0, y, 0.0), z0 + 0.01, 0.3 * leg, 0.5 * leg, ROD_SEGMENTS),
                    )
                )
    else:
        z0 = clip(0.05 * sz, 0.015, 0.05)
        e = clip(0.02 * short, 0.01, 0.03)
        parts = [slab("plinth", (-hx + e, -hy + e, 0.0), (hx - e, hy - e, z0 + 0.01))]
    inner0, inner1 = -hx + aw, hx - aw
    parts += [
        slab("back", (-hx, -hy, z0), (hx, -hy + back_d, sz)),
        slab("base", (inner0, -hy + back_d, z0), (inner1, hy, base_top)),
    ]
    if arms != "none":
        for side, (x0, x1) in (("left", (-hx, inner0)), ("right", (inner1, hx))):
            if arms == "box":
                parts.append(slab(f"arm_{side}", (x0, -hy + 0.5 * back_d, z0), (x1, hy, arm_top)))
            else:
                rz = 0.6 * aw  # the roll overhangs the arm's outer face a little
                parts += [
                    slab(
                        f"arm_{side}",
                        (x0 + 0.1 * aw, -hy + 0.5 * back_d, z0),
                        (x1 - 0.1 * aw, hy, arm_top - rz),
                    ),
                    Part(
                        f"arm_{side}_roll",
                        y_cylinder(-hy + 0.5 * back_d, hy, (x0 + x1) / 2, arm_top - rz, aw / 2, rz),
                    ),
                ]
    if wings:
        wy = -hy + 0.45 * sy
        wt = 0.5 * aw  # wings are thinner than the arms, flush with their outer faces
        for side, (x0, x1) in (("left", (-hx, -hx + wt)), ("right", (hx - wt, hx))):
            pts = [
                (x, y, z)
                for x in (x0, x1)
                for y, z in (
                    (-hy, arm_top),
                    (-hy, 0.97 * sz),
                    (wy, arm_top),
                    (wy, arm_top + 0.35 * (sz - arm_top)),
                    (-hy + back_d, 0.97 * sz),
                )
            ]
            parts.append(Part(f"wing_{side}", hull(np.array(pts))))
    gap = 0.004
    xs = np.linspace(inner0, inner1, n_seats + 1)
    bc_d = clip(0.16 * sy, 0.06, 0.18)  # back cushion depth
    bc_top = sz - 0.08 * (sz - seat_top)
    lean = -0.15  # back cushions lean back: dy per dz
    for i in range(n_seats):
        x0, x1 = xs[i] + gap, xs[i + 1] - gap
        parts.append(
            rounded_slab(f"seat_{i}", x0, x1, -hy + back_d, hy, base_top, seat_top, 0.25 * cush_t)
        )
        bc = rounded_slab(
            f"back_cushion_{i}",
            x0,
            x1,
            -hy + back_d,
            -hy + back_d + bc_d,
            seat_top,
            bc_top,
            0.3 * bc_d,
        )
        parts.append(Part(bc.name, sheared(bc.mesh, lean, seat_top)))
    return parts


@register("armchair", variants=3)
@min_design_extent(0.4)
def armchair(
    size: np.ndarray,
    rng: np.random.Generator,
    style: int,
    support_heights: Sequence[float] | None = None,
) -> list[Part]:
    """Armchair: upholstered club chair with box arms on short feet (0), open wooden frame
    with a padded seat and back and thin armrests on posts (1), or a wingback with rolled
    arms on a plinth (2). Seat near 45 % of the height, back at -y, arms at +-x."""
    sx, sy, sz = (float(v) for v in size)
    if style == 0:
        return floor_to_centre(_upholstered(size, rng, 1, "box", legs=True), sz)
    if style == 2:
        return floor_to_centre(_upholstered(size, rng, 1, "rolled", legs=False, wings=True), sz)
    hx, hy, short = sx / 2, sy / 2, min(sx, sy)
    seat_top = clip(LOUNGE_SEAT_FRACTION * jitter(rng, 0.04), 0.35, 0.6) * sz
    arm_top = seat_top + 0.42 * (sz - seat_top) * jitter(rng, 0.05)
    cush_t = min(clip(0.12 * sz, 0.04, 0.12), 0.3 * seat_top)
    leg = clip(0.06 * short, 0.025, 0.05) * jitter(rng)
    arm_w = clip(0.08 * sx, 0.04, 0.09)
    arm_t = clip(0.04 * sz, 0.02, 0.04)
    rail_h = clip(0.08 * sz, 0.03, 0.08)
    seat_bot = seat_top - cush_t
    lean_d = clip(0.12 * sy, 0.04, 0.12)  # how far the back's top sits behind its foot
    lean = -lean_d / (sz - seat_bot)
    lx, fy = hx - arm_w / 2, hy - leg / 2
    ry = -hy + lean_d + leg / 2  # rear legs, under the foot of the back posts
    parts = []
    for side, x in (("left", -lx), ("right", lx)):
        post = tapered_box(x, ry, seat_bot, sz, (leg, leg), (leg, leg))
        parts += [
            Part(
                f"rear_leg_{side}",
                tapered_box(x, ry, 0.0, seat_bot, (leg, leg), (0.7 * leg, 0.7 * leg)),
            ),
            Part(
                f"front_leg_{side}",
                tapered_box(x, fy, 0.0, arm_top - arm_t, (leg, leg), (0.7 * leg, 0.7 * leg)),
            ),
            Part(f"back_post_{side}", sheared(post, lean, seat_bot)),
        ]
    y_arm0 = ry + lean * (arm_top - seat_bot)
    parts += [
        slab("arm_left", (-hx, y_arm0, arm_top - arm_t), (-hx + arm_w, hy, arm_top)),
        slab("arm_right", (hx - arm_w, y_arm0, arm_top - arm_t), (hx, hy, arm_top)),
        slab("seat_frame", (-lx, ry - leg / 2, seat_bot - rail_h), (lx, hy, seat_bot)),
        rounded_slab(
            "seat_0",
            -lx + leg / 2,
            lx - leg / 2,
            ry,
            hy - 0.01 * sy,
            seat_bot,
            seat_top,
            0.25 * cush_t,
        ),
    ]
    back_t = clip(0.1 * sy, 0.04, 0.1)
    back = box_between(
        (-lx + leg / 2, ry - leg / 2, seat_top),
        (lx - leg / 2, ry - leg / 2 + back_t, sz - 0.05 * (sz - seat_top)),
    )
    parts.append(Part("back", sheared(back, lean, seat_bot)))
    return floor_to_centre(parts, sz)


@register("sofa", variants=4)
@min_design_extent(0.4)
def sofa(
    size: np.ndarray,
    rng: np.random.Generator,
    style: int,
    support_heights: Sequence[float] | None = None,
) -> list[Part]:
    """Sofa: box arms on feet with 2-3 seat cushions (0), box arms on a plinth with one
    bench cushion (1), armless on feet with 2-3 cushions (2), or rolled arms on a plinth
    with 2-3 cushions (3). Seat cushions ``seat_i``, back at -y, arms at +-x."""
    sx = float(size[0])
    arms = ("box", "box", "none", "rolled")[style]
    legs = style in (0, 2)
    arm_w = 0.0 if arms == "none" else clip(0.12 * sx, 0.07, 0.2)
    n = 1 if style == 1 else int(clip(round((sx - 2 * arm_w) / SOFA_SEAT_WIDTH), 2, 3))
    return floor_to_centre(_upholstered(size, rng, n, arms, legs), float(size[2]))

"""Kitchen appliances: microwave, toaster, coffee machine.

The microwave's door, window and panel face +y (the panel at -x, on the right of a
person facing it); so do the coffee machine's carafe / portafilter and the toaster's
lever. Parts are convex, built inside [-size/2, size/2] (+z up, +y front, +x right).
"""

from __future__ import annotations

import numpy as np

from pair2scene.assets.generators.shapes import (
    FINE_SEGMENTS,
    beam,
    box_handle,
    in_long_frame,
    lathe,
    rounded_outline,
)
from pair2scene.assets.mesh import (
    Part,
    box_between,
    cylinder,
    frustum,
    prism,
)
from pair2scene.assets.mesh import rod as _rod
from pair2scene.assets.registry import register


@register("microwave", variants=2)
def microwave(size, rng, style, support_heights):
    """A microwave oven: body, door with a recessed window on +y and a control panel at
    -x (the viewer's right). 0 handle bar and a button grid, 1 push-open door with two dials."""
    sx, sy, h = (float(v) for v in size)
    z0, zt = -h / 2, h / 2
    foot_h = float(np.clip(0.03 * h, 0.004, 0.012))
    d = float(np.clip(0.05 * sy, 0.006, 0.02))
    yf = sy / 2 - d
    zb = z0 + foot_h
    parts = [Part("body", box_between((-sx / 2, -sy / 2, zb), (sx / 2, yf, zt)))]
    fx, fy = 0.08 * sx, 0.1 * sy
    for i, (x, y) in enumerate(((-1, -1), (1, -1), (1, 1), (-1, 1))):
        cx, cy = x * (sx / 2 - fx), y * (sy / 2 - d - fy)
        parts.append(
            Part(
                f"foot_{i}",
                box_between(
                    (cx - 0.03 * sx, cy - 0.03 * sy, z0), (cx + 0.03 * sx, cy + 0.03 * sy, zb)
                ),
            )
        )
    m = 0.03 * min(sx, h)
    x_split = sx / 2 - rng.uniform(0.24, 0.28) * sx
    dz0, dz1 = zb + m, zt - m
    dx0, dx1 = -sx / 2 + m, x_split - m / 2
    bw = 0.14 * (dz1 - dz0)
    door_front = yf + 0.55 * d
    parts += [
        Part("door_top", box_between((dx0, yf, dz1 - bw), (dx1, door_front, dz1))),
        Part("door_bottom", box_between((dx0, yf, dz0), (dx1, door_front, dz0 + bw))),
        Part("door_left", box_between((dx0, yf, dz0 + bw), (dx0 + bw, door_front, dz1 - bw))),
        Part(
            "door_right", box_between((dx1 - 1.6 * bw, yf, dz0 + bw), (dx1, door_front, dz1 - bw))
        ),
        Part(
            "window",
            box_between((dx0 + bw, yf, dz0 + bw), (dx1 - 1.6 * bw, yf + 0.15 * d, dz1 - bw)),
        ),
    ]
    px0, px1 = x_split + m / 2, sx / 2 - m
    panel_front = yf + 0.45 * d
    parts.append(Part("panel", box_between((px0, yf, dz0), (px1, panel_front, dz1))))
    pw = px1 - px0
    parts.append(
        Part(
            "display",
            box_between(
                (px0 + 0.12 * pw, yf, dz1 - 0.22 * (dz1 - dz0)),
                (px1 - 0.12 * pw, yf + 0.7 * d, dz1 - 0.08 * (dz1 - dz0)),
            ),
        )
    )
    if style == 0:
        bx, bz = 0.26 * pw, 0.07 * (dz1 - dz0)
        for r in range(4):
            for k in range(2):
                x = px0 + pw * (0.27 + 0.46 * k)
                z = dz1 - (0.34 + 0.12 * r) * (dz1 - dz0)
                parts.append(
                    Part(
                        f"button_{2 * r + k}",
                        box_between(
                            (x - bx / 2, yf, z - bz / 2), (x + bx / 2, yf + 0.75 * d, z + bz / 2)
                        ),
                    )
                )
        hx = dx1 - 0.9 * bw
        parts.append(
            Part(
                "handle",
                box_between(
                    (hx - 0.35 * bw, door_front - 0.001, dz0 + 1.2 * bw),
                    (hx + 0.35 * bw, sy / 2, dz1 - 1.2 * bw),
                ),
            )
        )
    else:
        rd = 0.28 * pw
        for k, fz in enumerate((0.45, 0.72)):
            z = dz1 - fz * (dz1 - dz0)
            parts.append(
                Part(
                    f"dial_{k}",
                    _rod(
                        (px0 + pw / 2, yf, z),
                        (px0 + pw / 2, sy / 2, z),
                        rd,
                        0.9 * rd,
                        FINE_SEGMENTS,
                    ),
                )
            )
        parts.append(
            Part(
                "open_button",
                box_between(
                    (px0 + 0.25 * pw, yf, dz0 + 0.06 * h),
                    (px1 - 0.25 * pw, yf + 0.75 * d, dz0 + 0.14 * h),
                ),
            )
        )
    # built with the panel at +x; mirror so it sits at -x, on the right of a person facing
    # the door, as on real microwaves
    return [Part(p.name, p.mesh.scaled((-1.0, 1.0, 1.0))) for p in parts]


def _toaster(length, width, h, turned, rng, style):
    """Toaster along x (slots along x); lever on the +y long side, or on the +x end when
    ``turned`` (that end becomes the front)."""
    z0, zt = -h / 2, h / 2
    lever_d = float(np.clip(0.1 * min(length, width), 0.008, 0.025))
    x1 = length / 2 - (lever_d if turned else 0.0)
    y1 = width / 2 - (0.0 if turned else lever_d)
    x0, y0 = -length / 2, -width / 2
    slot_depth = rng.uniform(0.16, 0.2) * h
    zs = zt - slot_depth
    rc = (0.3 if style == 0 else 0.06) * (y1 - y0)
    parts = [Part("body", prism(rounded_outline(x0, x1, y0, y1, rc), z0, zs))]
    w = y1 - y0
    slot_w = float(np.clip(0.16 * w, 0.01, 0.045))
    n_rows = 2
    rim = (w - n_rows * slot_w) / (n_rows + 1)
    cap = max(rc, 0.12 * (x1 - x0))
    xs0, xs1 = x0 + cap, x1 - cap
    parts += [
        Part("top_end_0", prism(rounded_outline(x0, xs0 + 0.001, y0, y1, (0, 0, rc, rc)), zs, zt)),
        Part("top_end_1", prism(rounded_outline(xs1 - 0.001, x1, y0, y1, (rc, rc, 0, 0)), zs, zt)),
    ]
    for k in range(n_rows + 1):
        ya = y0 + k * (rim + slot_w)
        parts.append(Part(f"top_rim_{k}", box_between((xs0, ya, zs), (xs1, ya + rim, zt))))
    if style == 1:
        # four-slice: a cross divider splits each slot in two
        parts.append(Part("top_divider", box_between((-0.6 * rim, y0, zs), (0.6 * rim, y1, zt))))
    lever_w = float(np.clip(0.12 * (x1 - x0), 0.012, 0.04))
    lz = z0 + 0.62 * h
    knob_r = 0.35 * lever_d
    if turned:
        parts += [
            Part(
                "lever",
                box_between(
                    (x1 - 0.001, -lever_w / 2, lz), (length / 2, lever_w / 2, lz + 0.06 * h)
                ),
            ),
            Part(
                "knob",
                _rod(
                    (x1 - 0.001, 0, z0 + 0.3 * h),
                    (length / 2, 0, z0 + 0.3 * h),
                    1.6 * knob_r,
                    1.4 * knob_r,
                ),
            ),
        ]
    else:
        xl = x1 - 0.25 * (x1 - x0)
        parts += [
            Part(
                "lever",
                box_between(
                    (xl - lever_w / 2, y1 - 0.001, lz), (xl + lever_w / 2, width / 2, lz + 0.06 * h)
                ),
            ),
            Part(
                "knob",
                _rod(
                    (x0 + 0.25 * (x1 - x0), y1 - 0.001, z0 + 0.35 * h),
                    (x0 + 0.25 * (x1 - x0), width / 2, z0 + 0.35 * h),
                    1.6 * knob_r,
                    1.4 * knob_r,
                ),
            ),
        ]
    return parts


@register("toaster", variants=2)
def toaster(size, rng, style, support_heights):
    """A toaster with open slots on top running along its longer side, lever facing +y:
    0 rounded two-slice, 1 boxy four-slice."""
    return in_long_frame(
        size, lambda length, w, h, turned: _toaster(length, w, h, turned, rng, style)
    )


@register("coffee_machine", variants=2)
def coffee_machine(size, rng, style, support_heights):
    """A coffee machine facing +y: 0 drip machine (base, back tower, overhanging head,
    glass carafe), 1 espresso machine (body, group head, portafilter, drip tray, cup)."""
    sx, sy, h = (float(v) for v in size)
    z0, zt = -h / 2, h / 2
    if style == 0:
        base_h = 0.1 * h
        tower_d = rng.uniform(0.36, 0.42) * sy
        head_h = 0.3 * h
        yt = -sy / 2 + tower_d
        parts = [
            Part("base", box_between((-sx / 2, -sy / 2, z0), (sx / 2, sy / 2, z0 + base_h))),
            Part("tower", box_between((-sx / 2, -sy / 2, z0 + base_h), (sx / 2, yt, zt))),
            Part(
                "head",
                box_between(
                    (-sx / 2, yt - 0.01 * sy, zt - head_h), (sx / 2, sy / 2 - 0.04 * sy, zt)
                ),
            ),
        ]
        free = sy / 2 - yt
        rc = min(0.32 * sx, 0.44 * free)
        cy = yt + free / 2
        zc0 = z0 + base_h
        # the filter basket hangs under the head; the carafe stands below it
        zf = zt - head_h - 0.12 * h
        zc1 = zf - 0.015 * h
        hc = zc1 - zc0
        parts += [
            Part(
                "filter_basket",
                frustum((0, cy, zf), zt - head_h - zf + 0.001, 0.75 * rc, 1.05 * rc, FINE_SEGMENTS),
            ),
            Part(
                "carafe",
                lathe(
                    [
                        (0.92, zc0),
                        (1.0, zc0 + 0.12 * hc),
                        (0.96, zc0 + 0.4 * hc),
                        (0.78, zc0 + 0.72 * hc),
                        (0.5, zc1),
                    ],
                    rc,
                    rc,
                    center=(0, cy),
                    hull_of_rings=False,
                ),
            ),
        ]
        parts += box_handle(
            0.85 * rc,
            1.4 * rc,
            zc0 + 0.2 * hc,
            zc0 + 0.8 * hc,
            0.12 * rc,
            0.1 * rc,
            rounded=False,
            y=cy,
            prefix="carafe_handle",
        )
        parts += [
            Part(
                "switch",
                box_between(
                    (0.25 * sx, sy / 2 - 0.001, z0 + 0.2 * base_h),
                    (0.4 * sx, sy / 2 + 0.005 * sy, z0 + 0.8 * base_h),
                ),
            ),
        ]
        return parts
    body_d = rng.uniform(0.55, 0.62) * sy
    yb = -sy / 2 + body_d
    over_d = 0.17 * sy
    over_h = 0.28 * h
    tray_h = 0.08 * h
    parts = [
        Part("body", box_between((-sx / 2, -sy / 2, z0), (sx / 2, yb, zt))),
        Part(
            "head", box_between((-sx / 2, yb - 0.01 * sy, zt - over_h), (sx / 2, yb + over_d, zt))
        ),
        Part(
            "drip_tray",
            box_between(
                (-0.42 * sx, yb - 0.01 * sy, z0), (0.42 * sx, sy / 2 - 0.03 * sy, z0 + tray_h)
            ),
        ),
    ]
    gy = yb + 0.55 * over_d
    gr = min(0.12 * sx, 0.4 * over_d)
    zg = zt - over_h
    pf_z = zg - 0.07 * h
    parts += [
        Part("group_head", cylinder((0, gy, zg - 0.03 * h + 0.001), gr, 0.06 * h, FINE_SEGMENTS)),
        Part("portafilter", cylinder((0, gy, pf_z), 1.05 * gr, 0.05 * h, FINE_SEGMENTS)),
        Part(
            "portafilter_handle",
            beam(
                (0, gy + 0.8 * gr, pf_z),
                (0, sy / 2, pf_z - 0.04 * h),
                0.35 * gr,
                0.04 * h,
                side=(1, 0, 0),
            ),
        ),
        Part(
            "cup",
            lathe(
                [(0.7, z0 + tray_h), (1.0, z0 + tray_h + 0.14 * h)],
                0.7 * gr,
                0.7 * gr,
                center=(0, gy),
                hull_of_rings=False,
            ),
        ),
        Part(
            "steam_wand",
            _rod(
                (0.36 * sx, yb + 0.4 * over_d, zg),
                (0.36 * sx, yb + 0.8 * over_d, z0 + tray_h + 0.12 * h),
                0.012 * sx,
            ),
        ),
        Part(
            "gauge",
            _rod(
                (-0.28 * sx, yb + over_d - 0.001, zt - 0.45 * over_h),
                (-0.28 * sx, yb + over_d + 0.01 * sy, zt - 0.45 * over_h),
                0.08 * sx,
                0.08 * sx,
                FINE_SEGMENTS,
            ),
        ),
    ]
    return parts

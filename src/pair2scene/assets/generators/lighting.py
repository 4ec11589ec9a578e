"""Lighting: ceiling, floor, wall and table lamps.

Every generator follows the contract of :mod:`pair2scene.assets.registry`: convex parts
inside [-size/2, size/2], +z up, +y front, +x right. A wall lamp hangs on its -y side.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from pair2scene.assets.generators.shapes import (
    FINE_SEGMENTS,
    ROD_SEGMENTS,
    ROUND_SEGMENTS,
    bar,
    clip,
    jitter,
)
from pair2scene.assets.mesh import (
    Part,
    box_between,
    cylinder,
    ellipsoid,
    frustum,
    hull,
    prism,
    rod,
)
from pair2scene.assets.registry import register

ELL_RINGS = 6
"""Latitude rings of a small ellipsoid (the table lamp's joints)."""


@register("ceiling_lamp", variants=3)
def ceiling_lamp(
    size: np.ndarray, rng: np.random.Generator, style: int, support_heights: Sequence[float] | None
) -> list[Part]:
    """Ceiling lamp hanging from a canopy at the top: style 0 a pendant (rod, conical
    shade, bulb), style 1 a flush mount (drum and dome; on a stem when the box is tall),
    style 2 a chandelier (arms with candle lights)."""
    sx, sy, sz = size
    z0, z1 = -sz / 2, sz / 2
    r = np.array([sx / 2, sy / 2])
    rc = min(clip(0.15 * min(sx, sy), 0.03, 0.08), float(r.min()))
    ch = clip(0.04 * sz, 0.01, 0.04, 0.1 * sz)  # canopy height
    rod_r = clip(0.02 * min(sx, sy), 0.003, 0.01, 0.05 * min(sx, sy))
    parts = [Part("canopy", frustum((0.0, 0.0, z1 - ch), ch, 0.7 * rc, rc, ROUND_SEGMENTS))]
    if style == 0:
        bulb = min(clip(0.15 * min(sx, sy), 0.02, 0.06), 0.15 * sz)
        shade_h = min(0.5 * sz, 1.4 * float(r.min())) * jitter(rng, 0.1)
        shade_h = min(shade_h, 0.9 * (sz - ch - bulb))
        zsb = z0 + bulb
        parts += [
            Part(
                "rod",
                bar((0.0, 0.0, zsb + shade_h), (0.0, 0.0, z1 - ch), rod_r, extend0=0.2 * shade_h),
            ),
            Part(
                "shade",
                frustum(
                    (0.0, 0.0, zsb), shade_h, r, r * float(rng.uniform(0.15, 0.3)), ROUND_SEGMENTS
                ),
            ),
            Part(
                "bulb",
                ellipsoid(
                    (0.0, 0.0, zsb + 0.3 * bulb), (bulb, bulb, 1.3 * bulb), segments=ROD_SEGMENTS
                ),
            ),
        ]
        return parts
    if style == 1:
        # drum and dome keep lamp-like proportions; a tall box gets a longer stem instead
        body_h = min(0.9 * (sz - ch), 0.6 * float(min(sx, sy)))
        drum_h = 0.4 * body_h * jitter(rng, 0.1)
        zd = z0 + body_h  # drum top
        dome = ellipsoid(
            (0.0, 0.0, zd - drum_h),
            (r[0], r[1], zd - drum_h - z0),
            rings=8,
            segments=ROUND_SEGMENTS,
        )
        lower = dome.vertices[dome.vertices[:, 2] <= zd - drum_h + 1e-9]
        parts += [
            Part(
                "rod", bar((0.0, 0.0, zd), (0.0, 0.0, z1 - ch), 2.5 * rod_r, extend0=0.2 * drum_h)
            ),
            Part("drum", cylinder((0.0, 0.0, zd - drum_h / 2), r, drum_h, ROUND_SEGMENTS)),
            Part("dome", hull(lower)),
        ]
        return parts
    n_arms = int(rng.integers(5, 7))
    cup_r = min(clip(0.05 * min(sx, sy), 0.012, 0.03), 0.08 * sz)
    zb = z0 + 0.3 * sz  # body centre
    body_r = clip(0.1 * min(sx, sy), 0.02, 0.08)
    arm_z = zb + 0.1 * sz
    candle_h = 0.22 * sz
    flame = 0.8 * cup_r
    parts += [
        Part("rod", bar((0.0, 0.0, zb), (0.0, 0.0, z1 - ch), rod_r)),
        Part(
            "body", ellipsoid((0.0, 0.0, zb), (body_r, body_r, 0.12 * sz), segments=ROUND_SEGMENTS)
        ),
        Part("finial", frustum((0.0, 0.0, z0), zb - z0, 0.0001, 0.5 * body_r, ROD_SEGMENTS)),
    ]
    for k in range(n_arms):
        a = 2 * np.pi * k / n_arms + np.pi / 2
        ex, ey = (r[0] - cup_r) * np.cos(a), (r[1] - cup_r) * np.sin(a)
        parts += [
            Part(f"arm_{k}", bar((0.0, 0.0, zb), (ex, ey, arm_z), 0.7 * rod_r + 0.002)),
            Part(
                f"cup_{k}",
                frustum((ex, ey, arm_z - 0.5 * cup_r), cup_r, 0.4 * cup_r, cup_r, ROD_SEGMENTS),
            ),
            Part(
                f"candle_{k}",
                cylinder(
                    (ex, ey, arm_z + 0.5 * cup_r + candle_h / 2),
                    0.4 * cup_r,
                    candle_h,
                    ROD_SEGMENTS,
                ),
            ),
            Part(
                f"flame_{k}",
                ellipsoid(
                    (ex, ey, arm_z + 0.5 * cup_r + candle_h + flame),
                    (0.6 * flame, 0.6 * flame, flame),
                    rings=6,
                    segments=ROD_SEGMENTS,
                ),
            ),
        ]
    return parts


@register("floor_lamp", variants=3)
def floor_lamp(
    size: np.ndarray, rng: np.random.Generator, style: int, support_heights: Sequence[float] | None
) -> list[Part]:
    """Floor lamp: style 0 a disc base, pole and drum shade, style 1 a tripod with a
    conical shade, style 2 a torchiere (an upturned bowl on a tall pole)."""
    sx, sy, sz = size
    z0, z1 = -sz / 2, sz / 2
    r = np.array([sx / 2, sy / 2])
    pole_r = clip(0.03 * min(sx, sy), 0.008, 0.02)
    base_t = clip(0.02 * sz, 0.012, 0.04)
    if style == 2:
        bowl_h = clip(0.12 * sz, 0.06, 0.6 * float(r.min())) * jitter(rng, 0.1)
        base_r = 0.6 * r * jitter(rng, 0.1)
        return [
            Part("base", frustum((0.0, 0.0, z0), base_t, base_r, 0.85 * base_r, ROUND_SEGMENTS)),
            Part("pole", bar((0.0, 0.0, z0 + base_t), (0.0, 0.0, z1 - 0.6 * bowl_h), pole_r)),
            Part("shade", frustum((0.0, 0.0, z1 - bowl_h), bowl_h, 0.2 * r, r, ROUND_SEGMENTS)),
        ]
    shade_h = clip(0.18 * sz, 0.12, 1.2 * float(r.min())) * jitter(rng, 0.1)
    zsb = z1 - shade_h
    top = float(rng.uniform(0.75, 0.9)) if style == 0 else float(rng.uniform(0.4, 0.55))
    parts = [
        Part("shade", frustum((0.0, 0.0, zsb), shade_h, r, top * r, ROUND_SEGMENTS)),
        Part(
            "finial",
            ellipsoid(
                (0.0, 0.0, z1 - 0.2 * shade_h), (1.5 * pole_r,) * 3, rings=6, segments=ROD_SEGMENTS
            ),
        ),
    ]
    if style == 0:
        base_r = 0.6 * r * jitter(rng, 0.1)
        parts += [
            Part("base", frustum((0.0, 0.0, z0), base_t, base_r, 0.9 * base_r, ROUND_SEGMENTS)),
            Part("pole", bar((0.0, 0.0, z0 + base_t), (0.0, 0.0, z1 - 0.2 * shade_h), pole_r)),
        ]
        return parts
    joint = z0 + 0.4 * sz * jitter(rng, 0.1)
    leg_r = 0.8 * pole_r
    parts.append(Part("pole", bar((0.0, 0.0, joint), (0.0, 0.0, z1 - 0.2 * shade_h), pole_r)))
    for k in range(3):
        a = 2 * np.pi * k / 3 - np.pi / 2
        foot = ((r[0] - leg_r) * np.cos(a), (r[1] - leg_r) * np.sin(a), z0)
        parts.append(Part(f"leg_{k}", bar(foot, (0.0, 0.0, joint), leg_r, extend1=pole_r)))
    return parts


@register("wall_lamp", variants=3)
def wall_lamp(
    size: np.ndarray, rng: np.random.Generator, style: int, support_heights: Sequence[float] | None
) -> list[Part]:
    """Wall lamp (sconce) on a back plate at -y: style 0 an arm up to a cone shade open
    upward, style 1 an arm out to a bell shade hanging down, style 2 a flush half-round
    uplighter."""
    sx, sy, sz = size
    x0, y0, z0 = -size / 2
    x1, y1, z1 = size / 2
    bt = clip(0.1 * sy, 0.006, 0.02, 0.2 * sy)  # back plate thickness
    pw = clip(0.45 * sx, 0.04, 0.12, sx)
    arm_r = clip(0.05 * min(sx, sy), 0.004, 0.012, 0.05 * min(sx, sy, sz))
    if style == 2:
        half = np.linspace(0.0, np.pi, ROUND_SEGMENTS // 2 + 1)
        ry = sy - bt
        shell = np.stack([(sx / 2) * np.cos(half), y0 + bt + ry * np.sin(half)], 1)
        ph = 0.8 * sz * jitter(rng, 0.05)
        return [
            Part("back_plate", box_between((-pw / 2, y0, z0), (pw / 2, y0 + bt, z1))),
            Part("shade", prism(shell, z1 - 0.1 * sz - ph, z1 - 0.1 * sz)),
        ]
    ry = (sy - bt) / 2
    r = np.array([sx / 2, ry])
    yc = y1 - ry
    shade_h = 0.5 * sz * jitter(rng, 0.08)
    ph = 0.55 * sz  # back plate height
    if style == 0:
        za = z0 + 0.25 * sz  # arm leaves the plate here
        zsb = z1 - shade_h
        return [
            Part("back_plate", box_between((-pw / 2, y0, z0), (pw / 2, y0 + bt, z0 + ph))),
            Part("arm", bar((0.0, y0 + bt, za), (0.0, yc, za), arm_r, extend1=arm_r)),
            Part("stem", bar((0.0, yc, za), (0.0, yc, zsb + 2 * arm_r), arm_r)),
            Part("shade", frustum((0.0, yc, zsb), shade_h, 0.3 * r, r, ROUND_SEGMENTS)),
        ]
    za = z1 - 0.2 * sz
    zst = z0 + shade_h  # shade top
    return [
        Part("back_plate", box_between((-pw / 2, y0, z1 - ph), (pw / 2, y0 + bt, z1))),
        Part("arm", bar((0.0, y0 + bt, za), (0.0, yc, za), arm_r, extend1=arm_r)),
        Part("stem", bar((0.0, yc, za), (0.0, yc, zst - 2 * arm_r), arm_r)),
        Part("shade", frustum((0.0, yc, z0), shade_h, r, 0.35 * r, ROUND_SEGMENTS)),
    ]


@register("table_lamp", variants=3)
def table_lamp(size, rng, style, support_heights):
    """Table lamp: round base, bulbous body and tapered shade (0); square base, thin stem and
    drum shade (1); or an articulated desk lamp whose head shines down toward +y (2)."""
    sx, sy, sz = size
    hx, hy, hz = size / 2
    parts: list[Part] = []
    if style in (0, 1):
        shade_h = sz * rng.uniform(0.34, 0.42)
        shade_z0 = hz - shade_h
        stem_r = clip(0.025 * min(sx, sy), 0.003, 0.012)
        if style == 0:
            base_h = clip(0.04 * sz, 0.004, 0.03)
            parts.append(
                Part(
                    "base",
                    cylinder((0, 0, -hz + base_h / 2), (0.5 * hx, 0.5 * hy), base_h, FINE_SEGMENTS),
                )
            )
            body_h = sz * rng.uniform(0.3, 0.38)
            bz = -hz + base_h + body_h / 2
            parts.append(
                Part(
                    "body",
                    ellipsoid(
                        (0.0, 0.0, 0.0), (0.36 * hx, 0.36 * hy, body_h / 2), 8, FINE_SEGMENTS
                    ).transformed(None, (0, 0, bz)),
                )
            )
            stem_z0 = bz + 0.4 * body_h
            shade = frustum(
                (0, 0, shade_z0), shade_h, (hx, hy), (0.62 * hx, 0.62 * hy), FINE_SEGMENTS
            )
        else:
            base_h = clip(0.06 * sz, 0.006, 0.04)
            bw = 0.6 * min(sx, sy)
            parts.append(
                Part(
                    "base",
                    box_between(
                        (-bw / 2, -bw / 2 * sy / max(sx, sy), -hz),
                        (bw / 2, bw / 2 * sy / max(sx, sy), -hz + base_h),
                    ),
                )
            )
            stem_z0 = -hz + base_h - 1e-4
            shade = cylinder((0, 0, shade_z0 + shade_h / 2), (hx, hy), shade_h, FINE_SEGMENTS)
            sock_r = 2.2 * stem_r  # the bulb socket just under the shade
            parts.append(
                Part(
                    "socket",
                    cylinder((0, 0, shade_z0), (sock_r, sock_r), 0.12 * shade_h, ROUND_SEGMENTS),
                )
            )
        parts.append(
            Part(
                "stem",
                cylinder(
                    (0, 0, 0.5 * (stem_z0 + shade_z0 + 0.3 * shade_h)),
                    (stem_r, stem_r),
                    shade_z0 + 0.3 * shade_h - stem_z0,
                    ROD_SEGMENTS,
                ),
            )
        )
        parts.append(Part("shade", shade))
        return parts
    # articulated desk lamp: base at the back, elbow high, head over the front
    base_h = clip(0.05 * sz, 0.006, 0.03)
    rb = min(hx, 0.32 * sy)
    by = -hy + rb
    # an oval base as wide as the box: a wide box gets a wide lamp, not a stretched one
    parts.append(Part("base", cylinder((0, by, -hz + base_h / 2), (hx, rb), base_h, FINE_SEGMENTS)))
    arm_r = clip(0.02 * min(sx, sy, sz), 0.003, 0.01)
    head_r = min(hx, 0.28 * sy)
    head_len = 1.4 * head_r
    direction = np.array([0.0, 0.45, -1.0])
    direction /= np.linalg.norm(direction)
    joint = np.array([0.0, hy - 1.1 * head_r, hz - 0.35 * head_r])
    elbow = np.array([0.0, by + rng.uniform(-0.1, 0.1) * sy, hz - arm_r * 1.5])
    foot = np.array([0.0, by, -hz + base_h])
    parts.append(Part("lower_arm", rod(foot, elbow, arm_r)))
    parts.append(Part("upper_arm", rod(elbow, joint, arm_r)))
    parts.append(
        Part(
            "elbow",
            ellipsoid((0.0, 0.0, 0.0), (1.6 * arm_r,) * 3, ELL_RINGS, ROUND_SEGMENTS).transformed(
                None, elbow
            ),
        )
    )
    parts.append(
        Part(
            "base_joint",
            ellipsoid((0.0, 0.0, 0.0), (2.0 * arm_r,) * 3, ELL_RINGS, ROUND_SEGMENTS).transformed(
                None, foot
            ),
        )
    )
    parts.append(
        Part(
            "head",
            rod(
                joint - 0.15 * head_len * direction,
                joint + head_len * direction,
                0.35 * head_r,
                head_r,
                FINE_SEGMENTS,
            ),
        )
    )
    return parts

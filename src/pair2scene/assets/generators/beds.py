"""Beds and dog beds.

Built in floor coordinates like the tables and seating (z from 0 at the floor to the
box height; the shared building blocks are in ``shapes.py``); the mattress top is a
horizontal upward surface.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from pair2scene.assets.generators.shapes import (
    clip,
    floor_to_centre,
    jitter,
    lathe,
    min_design_extent,
    rounded_slab,
    slab,
    x_cylinder,
    y_cylinder,
)
from pair2scene.assets.mesh import Part, hull
from pair2scene.assets.registry import register

BUNK_MIN_HEIGHT_M = 1.5
"""A bed box at least this tall is a bunk bed: two decks between four posts, a ladder at
the foot. The tallest single beds of the training rooms stand 1.36 m (their headboards);
AI2-THOR's and ProcTHOR's bunk and loft beds 1.58-2.32 m, which a single mattress at
half the height drew as a bed stood on end."""
BUNK_HEADROOM_M = 0.55
"""At least this much free height between the lower mattress and the upper deck."""
MATTRESS_TOP = (0.45, 0.2, 0.78)
"""(a, b, cap): a single bed's mattress top stands a + b x the box height above the floor
(jittered 5 %), at most cap x the height. Fitted on what rests on the training rooms'
beds (153 AI2-THOR and ProcTHOR train beds under 1.5 m, the median base of their objects
other than pillows): it misses their heights by 0.085 m on average and 0.01 m at the
median, where half the box height (the rule before) put the mattress 0.13 m too low at the
median, under everything the data rests on a bed (a 0.9 m bed: 0.63 m against the data's
0.57-0.61, 0.45 before)."""
FITTED_MATTRESS = (0.15, 0.95)
"""Instance fitting (curation): the mattress top goes to the lowest height something
rests at on the source's bed, held in this share of the box height (a pillow the source
spawned higher falls onto it in the physics check; a headboard stays above it)."""


@register("bed", variants=3, fits_support_heights=True)
@min_design_extent(0.4)
def bed(
    size: np.ndarray,
    rng: np.random.Generator,
    style: int,
    support_heights: Sequence[float] | None = None,
) -> list[Part]:
    """Bed: a mattress (the upward surface, at :data:`MATTRESS_TOP`) on a frame, with a
    headboard at -y spanning the full height. Upholstered base on a recessed plinth with a
    padded headboard (0), wooden frame with corner posts and a footboard (1), or a low
    platform wider than the mattress with a slatted headboard (2). A box at least
    :data:`BUNK_MIN_HEIGHT_M` tall is a bunk bed (:func:`_bunk_bed`). ``support_heights``
    (heights above the box bottom where a source's objects rest on it) put the mattress
    top at the lowest of them (:data:`FITTED_MATTRESS`)."""
    sx, sy, sz = (float(v) for v in size)
    if sz >= BUNK_MIN_HEIGHT_M:
        return _bunk_bed(sx, sy, sz, rng, style)
    hx, hy = sx / 2, sy / 2
    a, b, cap = MATTRESS_TOP
    mat_top = min((a + b * sz) * jitter(rng, 0.05), cap * sz)
    if support_heights:
        lo, hi = FITTED_MATTRESS
        mat_top = clip(min(support_heights), lo * sz, hi * sz)
    mat_t = min(clip(0.22 * sz, 0.08, 0.3) * jitter(rng), 0.6 * mat_top)
    frame_top = mat_top - mat_t
    mi = clip(0.015 * sx, 0.005, 0.03)  # mattress inset from the frame's edge
    if style == 0:
        hb_t = clip(0.06 * sy, 0.05, 0.14)
        pi_ = clip(0.05 * min(sx, sy), 0.02, 0.08)
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
        post = clip(0.04 * sx, 0.04, 0.08) * jitter(rng)
        pt = 0.5 * post
        foot_top = min(mat_top + clip(0.12 * sz, 0.04, 0.15), sz)
        rail_h = clip(0.15 * sz, 0.05, 0.2)
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
        rim = clip(0.05 * min(sx, sy), 0.04, 0.12) * jitter(rng)  # platform beyond mattress
        hb_t = clip(0.04 * sy, 0.03, 0.08)
        plat_t = clip(0.35 * frame_top, 0.03, 0.08)
        plinth_in = clip(0.08 * min(sx, sy), 0.05, 0.2)
        slat_top = sz - 0.08 * (sz - mat_top)
        n_slats = int(clip(round(sx / 0.25), 3, 9))
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


def _bunk_bed(sx: float, sy: float, sz: float, rng: np.random.Generator, style: int):
    """Two decks between four full-height posts: a lower mattress near the floor, an upper
    one whose top is the bed's main surface, guard rails around the upper deck and a
    ladder at the foot (+y), on the +x half (style 0 and 2) or the -x half (style 1).
    Head panels close both decks at -y, so the bed reads from above and in a view as
    what it is, and the upper deck's rail leaves the ladder's opening free."""
    hx, hy = sx / 2, sy / 2
    post = clip(0.05 * sx, 0.05, 0.08) * jitter(rng)
    mat_t = clip(0.12 * sz, 0.12, 0.18) * jitter(rng, 0.05)
    deck_t = 0.04
    rail_top = sz - 0.04  # the posts end at the box's top, rails and panels a little under
    guard = clip(0.18 * sz, 0.25, 0.4)  # rail height above the upper mattress
    up_top = rail_top - guard
    lo_bottom = clip(0.12 * sz, 0.18, 0.3)
    lo_top = lo_bottom + deck_t + mat_t
    # the upper deck sits at least the headroom over the lower mattress
    up_top = max(up_top, lo_top + BUNK_HEADROOM_M + deck_t + mat_t)
    up_frame = up_top - mat_t
    px, py = hx - post / 2, hy - post / 2
    inner = (-hx + post, hx - post)
    parts = [
        slab(f"post_{i}", (x - post / 2, y - post / 2, 0.0), (x + post / 2, y + post / 2, sz))
        for i, (x, y) in enumerate(((-px, -py), (px, -py), (px, py), (-px, py)))
    ]
    mi = clip(0.015 * sx, 0.005, 0.03)
    for deck, (bottom, top) in (
        ("lower", (lo_bottom, lo_top)),
        ("upper", (up_frame - deck_t, up_top)),
    ):
        frame_top = bottom + deck_t
        # under the mattress only: no ledge beside it for things to rest on
        parts.append(
            slab(
                f"frame_{deck}",
                (inner[0] + mi, -hy + post, bottom),
                (inner[1] - mi, hy - post, frame_top),
            )
        )
        parts.append(
            rounded_slab(
                "mattress" if deck == "upper" else "mattress_lower",
                inner[0] + mi, inner[1] - mi, -hy + post, hy - post, frame_top, top, 2 * mi,
            )
        )  # fmt: skip
    panel = 0.5 * post
    parts += [
        slab("headboard", (inner[0], -hy, lo_bottom), (inner[1], -hy + panel, lo_top + 0.3)),
        slab(
            "headboard_upper", (inner[0], -hy, up_frame - deck_t), (inner[1], -hy + panel, rail_top)
        ),
        slab("footboard", (inner[0], hy - panel, lo_bottom), (inner[1], hy, lo_top + 0.15)),
    ]
    rail = clip(0.06 * guard, 0.025, 0.05)
    rail_z = (up_top + 0.5 * guard, rail_top - rail)
    for side, x in (("left", -hx), ("right", hx - panel)):
        for k, z in enumerate(rail_z):
            parts.append(
                slab(f"rail_{side}_{k}", (x, -hy + post, z), (x + panel, hy - post, z + rail))
            )
    # the ladder: two stiles at the foot, rungs between, on one half; the upper deck's
    # foot rail covers the other half
    side = -1.0 if style == 1 else 1.0
    width = clip(0.4 * (sx - 2 * post), 0.3, 0.45)
    near = side * (hx - post)
    far = near - side * width
    a, b = sorted((near, far))
    stile = 0.04
    parts += [
        slab("ladder_stile_0", (a, hy - panel, 0.0), (a + stile, hy, rail_top)),
        slab("ladder_stile_1", (b - stile, hy - panel, 0.0), (b, hy, rail_top)),
    ]
    rungs = np.arange(lo_top + 0.3, up_top, 0.3)
    for k, z in enumerate(rungs):
        parts.append(
            slab(f"ladder_rung_{k}", (a + stile, hy - panel, z), (b - stile, hy, z + 0.03))
        )
    lo_x, hi_x = (inner[0], a) if side > 0 else (b, inner[1])
    for k, z in enumerate(rail_z):
        parts.append(slab(f"rail_foot_{k}", (lo_x, hy - panel, z), (hi_x, hy, z + rail)))
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
    base_t = min(clip(0.35 * sz, 0.02, 0.08) * jitter(rng), 0.45 * sz)
    if style == 0:
        w = clip(0.16 * short, 0.03, 0.15) * jitter(rng)  # rim width
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
        rb = clip(0.1 * sy, 0.03, 0.12) * jitter(rng)  # back bolster half-depth
        rs = clip(0.08 * sx, 0.025, 0.1)  # side bolster half-width
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

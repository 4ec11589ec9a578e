"""Fixtures, wall objects and plants.

Bathroom and kitchen fixtures (sinks, toilets, bathtubs, showers, faucets,
stoves and their knobs), wall objects (paintings, mirrors, curtains, blinds,
towel and toilet-paper holders), house plants and vacuum cleaners. Lamps are in
``lighting.py``.

Every generator follows the contract of :mod:`pair2scene.assets.registry`:
convex parts inside [-size/2, size/2], +z up, +y front, +x right. Wall
objects hang on their -y side and face the room with +y. Hollows (basins,
tubs) are a floor plus walls, and round hollows are rings of convex sectors,
so every part stays convex. Each generator designs its parts to span the box
so that ``fit_to_box`` barely rescales them.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from pair2scene.assets.forms import closed_by_walls
from pair2scene.assets.generators.shapes import (
    FINE_SEGMENTS,
    ROD_SEGMENTS,
    ROUND_SEGMENTS,
    bar,
    clip,
    jitter,
    lathe,
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
)
from pair2scene.assets.registry import register

SINK_TALL_M = 0.45
"""A sink box taller than this stands on the floor (pedestal or vanity); a lower one is a
countertop basin (AI2-THOR's sinks are ~0.15 m high, vanities ~0.9 m)."""
SHOWER_HEAD_MIN_DEPTH_M = 0.12
"""Depth behind a shower panel needed to fit a head on its riser."""
SINGLE_BURNER_MAX_M = 0.4
"""A stove footprint smaller than this is one burner (AI2-THOR's StoveBurner is ~0.2 m)."""
STOVE_BODY_MIN_M = 0.25
"""A stove at least this tall gets a body (oven or cabinet) under its cooktop."""
KNOB_TOP_MOUNT_RATIO = 0.7
"""A knob box lower than this fraction of its depth is a top-mounted knob (axis +z);
otherwise the knob sits on a front panel (axis +y)."""
TOWEL_RAIL_PITCH_M = 0.12
"""Vertical spacing of the rails of a towel ladder: one rail per this much height."""
CURTAIN_PLEAT_M = 0.1
"""Width of one pleat of a drawn-closed curtain (gathered panels use ~60% of it)."""
BLIND_SLAT_PITCH_M = 0.045
"""Spacing of venetian slats (typical 50 mm slats, slightly overlapping when closed)."""
BLIND_VANE_PITCH_M = 0.09
"""Spacing of vertical blind vanes (typical 89 mm vanes)."""
MAX_REPEATS = 36
"""Cap on repeated parts (slats, vanes, pleats) to keep an asset under ~60 parts."""

_Z_TO_Y = np.array([[1.0, 0.0, 0.0], [0.0, 0.0, 1.0], [0.0, -1.0, 0.0]])
"""Rotation taking +z to +y and +y to -z: round parts along y; radii are then (r_x, r_z)."""
_Z_TO_X = np.array([[0.0, 0.0, 1.0], [0.0, 1.0, 0.0], [-1.0, 0.0, 0.0]])
"""Rotation taking +z to +x and +x to -z: round parts along x; radii are then (r_z, r_y)."""
_RZ_90 = np.array([[0.0, -1.0, 0.0], [1.0, 0.0, 0.0], [0.0, 0.0, 1.0]])
"""Quarter turn about z: a part built along x then runs along y."""
_HEX_FACES = box((0.0, 0.0, 0.0), (2.0, 2.0, 2.0)).faces
"""Triangles of a box, reused for any hexahedron whose corners follow box() order."""


# -- helpers ------------------------------------------------------------------------
def _path(
    points: Sequence[Sequence[float]],
    radius: float,
    closed: bool = False,
    segments: int = ROD_SEGMENTS,
) -> list[Mesh]:
    """Bars along a polyline (K, 3), each overlapping its neighbours at the bends; a closed
    path also joins the last point to the first."""
    pts = np.asarray(points, dtype=float)
    if closed:
        pts = np.concatenate([pts, pts[:1]])
    lap = 0.5 * radius
    n = len(pts) - 1
    return [
        bar(
            pts[i],
            pts[i + 1],
            radius,
            segments,
            extend0=lap if (closed or i > 0) else 0.0,
            extend1=lap if (closed or i < n - 1) else 0.0,
        )
        for i in range(n)
    ]


def _hexahedron(corners: np.ndarray) -> Mesh:
    """Convex solid from 8 corners (8, 3) in box() order: bottom quad (-x-y, +x-y, +x+y, -x+y),
    then the top quad; every face must be planar and the solid convex."""
    return Mesh(corners, _HEX_FACES)


def _shell(
    cx: float,
    cy: float,
    z0: float,
    z1: float,
    r_top: Sequence[float],
    taper: float,
    wall: float,
    segments: int,
) -> list[Mesh]:
    """Walls of an open elliptic bowl as ``segments`` convex sectors.

    (cx, cy) centre; the outer surface runs from radii taper * r_top at z0 to r_top (2,) at
    z1. The inner surface is ``wall`` smaller along each axis at the top and scaled by the
    same taper below: one scalar taper keeps every sector face planar.
    """
    rt = np.asarray(r_top, dtype=float)
    w = min(wall, 0.9 * float(rt.min()))
    a = np.linspace(0.0, 2.0 * np.pi, segments + 1)
    out = []
    for i in range(segments):
        c = np.cos([a[i], a[i + 1], a[i + 1], a[i]])
        s = np.sin([a[i], a[i + 1], a[i + 1], a[i]])
        # box() order: angle i outer, angle j outer, angle j inner, angle i inner
        shrink = np.array([0.0, 0.0, w, w])
        quads = []
        for f, z in ((taper, z0), (1.0, z1)):
            quads.append(
                np.stack(
                    [cx + f * (rt[0] - shrink) * c, cy + f * (rt[1] - shrink) * s, np.full(4, z)],
                    axis=1,
                )
            )
        out.append(_hexahedron(np.concatenate(quads)))
    return out


def _hollow_box(
    lo: Sequence[float], hi: Sequence[float], wall: float, floor: float, prefix: str
) -> list[Part]:
    """An open-topped box from lo (3,) to hi (3,): a floor and four walls."""
    x0, y0, z0 = lo
    x1, y1, z1 = hi
    w = min(wall, 0.3 * (x1 - x0), 0.3 * (y1 - y0))
    return [
        Part(f"{prefix}_floor", box_between((x0, y0, z0), (x1, y1, z0 + floor))),
        Part(f"{prefix}_wall_back", box_between((x0, y0, z0), (x1, y0 + w, z1))),
        Part(f"{prefix}_wall_front", box_between((x0, y1 - w, z0), (x1, y1, z1))),
        Part(f"{prefix}_wall_left", box_between((x0, y0 + w, z0), (x0 + w, y1 - w, z1))),
        Part(f"{prefix}_wall_right", box_between((x1 - w, y0 + w, z0), (x1, y1 - w, z1))),
    ]


def _round_hollow(
    cx: float,
    cy: float,
    z0: float,
    z1: float,
    r_top: Sequence[float],
    taper: float,
    wall: float,
    floor: float,
    segments: int,
    prefix: str,
) -> list[Part]:
    """An open elliptic bowl, radii r_top (2,) at z1 and taper * r_top at z0: a floor disc and
    a ring of wall sectors."""
    rt = np.asarray(r_top, dtype=float)
    f = taper + (1.0 - taper) * floor / (z1 - z0)
    parts = [Part(f"{prefix}_floor", frustum((cx, cy, z0), floor, taper * rt, f * rt, segments))]
    for i, m in enumerate(_shell(cx, cy, z0, z1, rt, taper, wall, segments)):
        parts.append(Part(f"{prefix}_wall_{i}", m))
    return parts


def _spout(
    x: float, y: float, z_base: float, z_top: float, y_tip: float, radius: float, steps: int = 6
) -> list[Mesh]:
    """A gooseneck: a riser at (x, y) from z_base, arching forward (+y) to y_tip and ending
    in a short downward nozzle. The tube's top touches z_top."""
    ry = (y_tip - y) / 2
    rz = min(ry, 0.6 * (z_top - radius - z_base))
    zc = z_top - radius - rz
    t = np.linspace(0.0, np.pi, steps + 1)
    arc = np.stack([np.full_like(t, x), y + ry * (1 - np.cos(t)), zc + rz * np.sin(t)], 1)
    nozzle = [(x, y_tip, zc - 0.35 * rz)]
    return _path(np.concatenate([[(x, y, z_base)], arc, nozzle]), radius)


def _pleats(
    x_from: float,
    x_to: float,
    y_mid: float,
    depth: float,
    z0: float,
    z1: float,
    pitch: float,
    max_pleats: int,
) -> list[Mesh]:
    """A pleated curtain panel: flattened vertical cylinders alternating front and back
    along x, spanning [x_from, x_to] and y_mid +- depth/2."""
    n = int(np.clip(round((x_to - x_from) / pitch), 2, max_pleats))
    step = (x_to - x_from) / n
    rx = 0.62 * step  # neighbours overlap so the fabric reads as one wavy sheet
    ry = max(0.3 * depth, 1e-4)
    amp = depth / 2 - ry
    out = []
    for k in range(n):
        xk = x_from + (k + 0.5) * step
        yk = y_mid + amp * (1 if k % 2 else -1)
        # the outer pleats keep inside the panel's extent
        r_x = min(rx, xk - x_from, x_to - xk) if k in (0, n - 1) else rx
        out.append(cylinder((xk, yk, (z0 + z1) / 2), (r_x, ry), z1 - z0, ROD_SEGMENTS))
    return out


def _reach(half: np.ndarray, azimuth: float) -> float:
    """Distance from the centre to the side of a box of half extents ``half`` (2,) along
    the horizontal direction ``azimuth`` (radians from +x)."""
    c, s = abs(np.cos(azimuth)), abs(np.sin(azimuth))
    return float(min(half[0] / max(c, 1e-9), half[1] / max(s, 1e-9)))


def _named(prefix: str, meshes: Sequence[Mesh]) -> list[Part]:
    return [Part(f"{prefix}_{i}", m) for i, m in enumerate(meshes)]


# -- sinks, toilets, bathtubs, showers -----------------------------------------------
@register("sink", variants=2)
def sink(
    size: np.ndarray, rng: np.random.Generator, style: int, support_heights: Sequence[float] | None
) -> list[Part]:
    """Sink: a hollow basin with a faucet on a deck at -y; style 0 an oval bowl (on a
    pedestal when tall), style 1 a rectangular basin in a counter (on a vanity when tall)."""
    sx, sy, sz = size
    x0, y0, z0 = -size / 2
    x1, y1, z1 = size / 2
    tall = sz > SINK_TALL_M
    faucet_h = min(0.2, 0.3 * sz) * jitter(rng, 0.1)
    rim = z1 - faucet_h
    depth = clip(0.18 * sz, 0.12, 0.22) if tall else rim - z0
    bottom = rim - depth
    deck = clip(0.22 * sy, 0.05, 0.15, 0.3 * sy) * jitter(rng, 0.1)
    wall = clip(0.06 * min(sx, sy), 0.008, 0.03)
    floor_t = min(1.5 * wall, 0.3 * depth)
    tube = clip(0.08 * deck, 0.005, 0.012)
    parts: list[Part] = []
    if style == 0:
        ry = (y1 - y0 - deck) / 2
        yc = y1 - ry
        taper = float(rng.uniform(0.6, 0.75))
        r_top = np.array([sx / 2, ry])
        parts += _round_hollow(
            0.0, yc, bottom, rim, r_top, taper, wall, floor_t, ROUND_SEGMENTS, "basin"
        )
        # the deck reaches the bowl's outer wall but never its inner cavity
        parts.append(
            Part("deck", box_between((x0, y0, bottom + 0.3 * depth), (x1, yc - ry + wall, rim)))
        )
        tip = yc - ry + 0.5 * ry
        if tall:
            py = yc - 0.25 * ry  # the column stands a little toward the wall
            foot_h = clip(0.04 * sz, 0.02, 0.05, 0.2 * (bottom - z0))
            # elliptic frustums keep one aspect ratio so that their sides stay planar
            rf = r_top * (0.34, 0.42)
            rc = r_top * (0.32, 0.4)
            parts.append(Part("pedestal_foot", frustum((0.0, py, z0), foot_h, rf, 0.88 * rf)))
            parts.append(
                Part(
                    "pedestal", frustum((0.0, py, z0 + foot_h), bottom - z0 - foot_h, 0.65 * rc, rc)
                )
            )
    else:
        ct = clip(0.04 * sz, 0.015, 0.05) if tall else min(0.04, 0.3 * depth)
        hd = clip(0.04 * sy, 0.012, 0.025, 0.05 * sy) if tall else 0.0  # handle depth
        door_t = clip(0.03 * sy, 0.012, 0.02, 0.05 * sy) if tall else 0.0
        front_m = max(clip(0.08 * sy, 0.03, 0.08, 0.15 * sy), 1.2 * (hd + door_t))
        side_m = clip(0.12 * sx, 0.03, 0.12, 0.2 * sx)
        bx0, bx1, by0, by1 = x0 + side_m, x1 - side_m, y0 + deck, y1 - front_m
        parts += _hollow_box((bx0, by0, bottom), (bx1, by1, rim), wall, floor_t, "basin")
        top = (rim - ct, rim)
        parts += [
            Part("counter_back", box_between((x0, y0, top[0]), (x1, by0, top[1]))),
            Part("counter_front", box_between((x0, by1, top[0]), (x1, y1, top[1]))),
            Part("counter_left", box_between((x0, by0, top[0]), (bx0, by1, top[1]))),
            Part("counter_right", box_between((bx1, by0, top[0]), (x1, by1, top[1]))),
        ]
        tip = by0 + 0.3 * (by1 - by0)
        if tall:
            parts += _vanity(size, bottom, rim - ct, deck, (bx0, bx1, by1), hd, door_t)
    # faucet: riser on the deck, gooseneck over the basin, two handles beside it
    fy = y0 + deck / 2
    parts += _named("faucet_spout", _spout(0.0, fy, rim, z1, tip, tube))
    parts.append(
        Part(
            "faucet_base",
            cylinder((0.0, fy, rim + 0.1 * faucet_h), 2.2 * tube, 0.2 * faucet_h, ROD_SEGMENTS),
        )
    )
    hx = min(0.35 * sx, 6 * tube + 0.04)
    for name, s in (("faucet_handle_left", -1), ("faucet_handle_right", 1)):
        parts.append(
            Part(
                name,
                cylinder(
                    (s * hx, fy, rim + 0.15 * faucet_h), 1.6 * tube, 0.3 * faucet_h, ROD_SEGMENTS
                ),
            )
        )
    return parts


def _vanity(
    size: np.ndarray,
    basin_bottom: float,
    counter_bottom: float,
    deck: float,
    basin_front: tuple[float, float, float],
    hd: float,
    door_t: float,
) -> list[Part]:
    """The cabinet under a vanity sink: plinth, carcass, aprons around the basin, doors,
    handles. basin_front: (basin x min, basin x max, basin y max)."""
    x0, y0, z0 = -size / 2
    x1, y1, _ = size / 2
    sx, sy, sz = size
    bx0, bx1, by1 = basin_front
    face = y1 - hd - door_t  # carcass front, behind doors and handles
    kick_h = clip(0.08 * sz, 0.03, 0.1)
    kick_in = clip(0.06 * sy, 0.02, 0.06, 0.1 * sy)
    inset = min(0.01, 0.05 * sx)  # plinth set in from the sides
    parts = [
        Part(
            "plinth", box_between((x0 + inset, y0, z0), (x1 - inset, face - kick_in, z0 + kick_h))
        ),
        Part("cabinet", box_between((x0, y0, z0 + kick_h), (x1, face, basin_bottom))),
        Part("apron_front", box_between((x0, by1, basin_bottom), (x1, face, counter_bottom))),
        Part("apron_back", box_between((x0, y0, basin_bottom), (x1, y0 + deck, counter_bottom))),
        Part("apron_left", box_between((x0, y0, basin_bottom), (bx0, face, counter_bottom))),
        Part("apron_right", box_between((bx1, y0, basin_bottom), (x1, face, counter_bottom))),
    ]
    n = 2 if sx > 0.55 else 1
    gap = min(0.004, 0.02 * sx)  # between doors
    dz0, dz1 = z0 + kick_h + gap, counter_bottom - gap
    for i in range(n):
        dx0, dx1 = x0 + i * sx / n + gap, x0 + (i + 1) * sx / n - gap
        parts.append(Part(f"door_{i}", box_between((dx0, face, dz0), (dx1, face + door_t, dz1))))
        # handles sit by the doors' meeting edge (by the right edge of a single door)
        hx = dx1 - 0.1 * (dx1 - dx0) if (i == 0) else dx0 + 0.1 * (dx1 - dx0)
        hh = min(0.15, 0.25 * (dz1 - dz0))
        hz = dz1 - 0.12 * (dz1 - dz0) - hh / 2
        parts.append(Part(f"handle_{i}", box((hx, y1 - hd / 2, hz), (0.012, hd, hh))))
    return parts


@register("sink_basin", variants=2)
def sink_basin(
    size: np.ndarray, rng: np.random.Generator, style: int, support_heights: Sequence[float] | None
) -> list[Part]:
    """Sink basin alone: an open hollow; style 0 rectangular, style 1 an oval bowl."""
    sx, sy, sz = size
    lo, hi = -size / 2, size / 2
    wall = clip(0.06 * min(sx, sy), 0.006, 0.025) * jitter(rng, 0.1)
    floor_t = min(1.5 * wall, 0.25 * sz)
    if style == 0:
        return _hollow_box(lo, hi, wall, floor_t, "basin")
    r_top = np.array([sx / 2, sy / 2])
    taper = float(rng.uniform(0.55, 0.7))
    return _round_hollow(
        0.0, 0.0, lo[2], hi[2], r_top, taper, wall, floor_t, FINE_SEGMENTS, "basin"
    )


@register("toilet", variants=2)
def toilet(
    size: np.ndarray, rng: np.random.Generator, style: int, support_heights: Sequence[float] | None
) -> list[Part]:
    """Toilet: bowl and seat toward +y, tank at -y; style 0 floor-standing with a tank on
    the bowl, style 1 wall-hung bowl in front of a full-height cistern panel."""
    sx, sy, sz = size
    x0, y0, z0 = -size / 2
    x1, y1, z1 = size / 2
    seat_top = z0 + 0.42 * sz * jitter(rng, 0.04)
    st = clip(0.04 * sz, 0.012, 0.04, 0.05 * sz)  # seat (lid closed) thickness
    seat_bot = seat_top - st
    td = clip(0.22 * sy, 0.08, 0.25, 0.3 * sy) * jitter(rng, 0.08)  # tank depth
    rx = min(0.36 * sx * jitter(rng, 0.05), sx / 2)
    ry = (y1 - (y0 + 0.9 * td)) / 2
    yc = y1 - ry
    r = np.array([rx, ry])
    parts = [Part("seat", cylinder((0.0, yc, seat_bot + st / 2), r, st, ROUND_SEGMENTS))]
    if style == 0:
        zb = z0 + 0.45 * (seat_bot - z0)
        rf = r * (0.5, 0.55)
        parts.append(
            Part("foot", frustum((0.0, yc - 0.2 * ry, z0), zb - z0, rf, 0.85 * rf, ROUND_SEGMENTS))
        )
        bowl_factors = (0.6, 0.88, 0.97)
        lid_o = clip(0.03 * sx, 0.005, 0.015, 0.05 * sx)  # lid overhang
        lid_t = clip(0.03 * sz, 0.01, 0.03, 0.05 * sz)
        btn_h = clip(0.015 * sz, 0.005, 0.015, 0.03 * sz)
        tank_bot = seat_top + clip(0.03 * sz, 0.01, 0.04, 0.05 * sz)
        lid_bot = z1 - btn_h - lid_t
        parts += [
            Part(
                "bowl_back",
                box_between((-0.5 * rx, y0 + 0.25 * td, zb), (0.5 * rx, yc - 0.3 * ry, seat_bot)),
            ),
            Part(
                "tank_base",
                box_between((-0.5 * rx, y0 + 0.25 * td, seat_bot), (0.5 * rx, y0 + td, tank_bot)),
            ),
            Part("tank", box_between((x0 + lid_o, y0, tank_bot), (x1 - lid_o, y0 + td, lid_bot))),
            Part("tank_lid", box_between((x0, y0, lid_bot), (x1, y0 + td + lid_o, z1 - btn_h))),
            Part(
                "flush_button",
                cylinder(
                    (0.0, y0 + td / 2, z1 - btn_h / 2), min(0.15 * td, 0.025), btn_h, ROD_SEGMENTS
                ),
            ),
        ]
    else:
        zb = seat_bot - 0.5 * (seat_bot - z0) * jitter(rng, 0.1)
        bowl_factors = (0.55, 0.88, 0.97)
        plate_z = z0 + 0.78 * sz
        plate = (
            clip(0.35 * sx, 0.08, 0.25),
            clip(0.015 * sy, 0.005, 0.012),
            clip(0.14 * sz, 0.06, 0.16),
        )
        parts += [
            Part(
                "bowl_back",
                box_between(
                    (-0.55 * rx, y0 + 0.9 * td, zb + 0.1 * (seat_bot - zb)),
                    (0.55 * rx, yc - 0.3 * ry, seat_bot),
                ),
            ),
            Part("cistern", box_between((x0, y0, z0), (x1, y0 + td, z1))),
            Part("flush_plate", box((0.0, y0 + td + plate[1] / 2, plate_z), plate)),
        ]
    bowl_profile = zip(bowl_factors, (zb, zb + 0.55 * (seat_bot - zb), seat_bot))
    parts.append(Part("bowl", lathe(bowl_profile, rx, ry, ROUND_SEGMENTS, center=(0.0, yc))))
    return parts


@register("bathtub", variants=2)
def bathtub(
    size: np.ndarray, rng: np.random.Generator, style: int, support_heights: Sequence[float] | None
) -> list[Part]:
    """Bathtub: a hollow tub; style 0 built-in box with a spout at the -x end, style 1
    freestanding oval tub on four feet."""
    sx, sy, sz = size
    x0, y0, z0 = -size / 2
    x1, y1, z1 = size / 2
    if style == 0:
        wall = clip(0.07 * min(sx, sy), 0.04, 0.12) * jitter(rng, 0.1)
        floor_t = clip(0.15 * sz, 0.04, 0.1, 0.3 * sz)
        parts = _hollow_box((x0, y0, z0), (x1, y1, z1), wall, floor_t, "tub")
        r = clip(0.03 * sz, 0.01, 0.02)
        zs = z1 - clip(0.15 * sz, 0.05, 0.1)
        reach = min(0.12, 0.12 * sx)
        parts.append(
            Part("spout", bar((x0 + 0.5 * wall, 0.0, zs), (x0 + wall + reach, 0.0, zs), r))
        )
        return parts
    foot_h = clip(0.12 * sz, 0.04, 0.12, 0.2 * sz) * jitter(rng, 0.1)
    wall = clip(0.05 * min(sx, sy), 0.02, 0.06)
    floor_t = clip(0.1 * sz, 0.03, 0.06, 0.2 * sz)
    r_top = np.array([sx / 2, sy / 2])
    taper = float(rng.uniform(0.78, 0.86))
    r_bot = taper * r_top
    zb = z0 + foot_h
    parts = _round_hollow(0.0, 0.0, zb, z1, r_top, taper, wall, floor_t, FINE_SEGMENTS, "tub")
    fr = clip(0.05 * min(sx, sy), 0.02, 0.05)
    for i, (fx, fy) in enumerate(((-1, -1), (1, -1), (1, 1), (-1, 1))):
        c = (fx * 0.6 * r_bot[0], fy * 0.5 * r_bot[1], z0)
        parts.append(
            Part(f"foot_{i}", frustum(c, foot_h + 0.5 * floor_t, fr, 0.6 * fr, ROD_SEGMENTS))
        )
    return parts


@register("bathtub_basin", variants=2)
def bathtub_basin(
    size: np.ndarray, rng: np.random.Generator, style: int, support_heights: Sequence[float] | None
) -> list[Part]:
    """Bathtub basin alone: the thin inner hollow; style 0 rectangular, style 1 oval."""
    sx, sy, sz = size
    lo, hi = -size / 2, size / 2
    wall = clip(0.025 * min(sx, sy), 0.01, 0.03)
    floor_t = clip(0.06 * sz, 0.01, 0.03, 0.2 * sz)
    if style == 0:
        return _hollow_box(lo, hi, wall, floor_t, "basin")
    r_top = np.array([sx / 2, sy / 2])
    taper = float(rng.uniform(0.8, 0.88))
    return _round_hollow(
        0.0, 0.0, lo[2], hi[2], r_top, taper, wall, floor_t, FINE_SEGMENTS, "basin"
    )


@register("shower", variants=2)
def shower(
    size: np.ndarray, rng: np.random.Generator, style: int, support_heights: Sequence[float] | None
) -> list[Part]:
    """Shower: style 0 glass, style 1 curtain. A box deep in x and y is a cubicle (tray,
    enclosure, head on the -y wall); a thin one is a door panel or a curtain."""
    sx, sy, sz = size
    if closed_by_walls("shower", size):  # the cubicle placement stands in its corner
        return _shower_cubicle(size, rng, style)
    if sy <= sx:
        return _shower_panel(size, rng, style)
    # the thin side is x: build the panel along y (its face then looks toward -x)
    turned = _shower_panel(np.array([sy, sx, sz]), rng, style)
    return [Part(p.name, p.mesh.transformed(_RZ_90)) for p in turned]


def _shower_head(
    x: float, y_wall: float, z_low: float, z_top: float, reach: float, head_r: float, pipe_r: float
) -> list[Part]:
    """Mixer and riser on the wall at y_wall, an arm toward +y and a head facing down."""
    yp = y_wall + pipe_r
    za = z_top - pipe_r
    head_h = 0.25 * head_r
    mixer = (4 * pipe_r, 2.5 * pipe_r, 5 * pipe_r)
    return [
        Part("mixer", box((x, y_wall + mixer[1] / 2, z_low), mixer)),
        Part("riser", bar((x, yp, z_low), (x, yp, za), pipe_r, extend1=pipe_r)),
        Part("arm", bar((x, yp, za), (x, y_wall + reach, za), pipe_r)),
        Part(
            "head",
            frustum(
                (x, y_wall + reach, za - pipe_r - head_h),
                head_h,
                head_r,
                0.5 * head_r,
                ROUND_SEGMENTS,
            ),
        ),
    ]


def _shower_cubicle(size: np.ndarray, rng: np.random.Generator, style: int) -> list[Part]:
    """A corner cubicle: walls at -x and -y; glass panels or a curtain on +x and +y."""
    sx, sy, sz = size
    x0, y0, z0 = -size / 2
    x1, y1, z1 = size / 2
    tray_h = clip(0.04 * sz, 0.03, 0.1, 0.1 * sz) * jitter(rng, 0.1)
    zt = z0 + tray_h
    parts = [Part("tray", box_between((x0, y0, z0), (x1, y1, zt)))]
    if style == 0:
        post = clip(0.02 * min(sx, sy), 0.015, 0.035, 0.1 * sz)
        gt = min(0.01, 0.4 * post)
        g = post / 2  # glass runs along the posts' centre line
        parts += [
            Part("post_front_left", box_between((x0, y1 - post, zt), (x0 + post, y1, z1))),
            Part("post_front_right", box_between((x1 - post, y1 - post, zt), (x1, y1, z1))),
            Part("post_back_right", box_between((x1 - post, y0, zt), (x1, y0 + post, z1))),
            Part("rail_front", box_between((x0 + post, y1 - post, z1 - post), (x1 - post, y1, z1))),
            Part("rail_side", box_between((x1 - post, y0 + post, z1 - post), (x1, y1 - post, z1))),
            Part(
                "glass_front",
                box_between(
                    (x0 + post, y1 - g - gt / 2, zt), (x1 - post, y1 - g + gt / 2, z1 - post)
                ),
            ),
            Part(
                "glass_side",
                box_between(
                    (x1 - g - gt / 2, y0 + post, zt), (x1 - g + gt / 2, y1 - post, z1 - post)
                ),
            ),
        ]
        hx = x0 + 0.62 * sx
        parts.append(
            Part(
                "handle",
                box_between(
                    (hx - 0.01, y1 - g + gt / 2, z0 + 0.4 * sz), (hx + 0.01, y1, z0 + 0.6 * sz)
                ),
            )
        )
        z_head = z1 - post - 0.04 * sz
    else:
        rr = clip(0.012 * min(sx, sy), 0.01, 0.02, 0.05 * sz)
        cd = clip(0.08 * sy, 0.03, 0.08)  # curtain depth (pleat amplitude)
        zr = z1 - rr
        parts += [
            Part(
                "rod_front",
                bar((x0, y1 - cd / 2, zr), (x1 - cd / 2, y1 - cd / 2, zr), rr, extend1=rr),
            ),
            Part(
                "rod_side",
                bar((x1 - cd / 2, y0, zr), (x1 - cd / 2, y1 - cd / 2, zr), rr, extend1=rr),
            ),
        ]
        cover = float(rng.uniform(0.55, 0.75)) * sx  # the curtain is drawn toward +x
        parts += _named(
            "curtain", _pleats(x1 - cover, x1, y1 - cd / 2, cd, zt + 0.03 * sz, zr - rr, 0.08, 16)
        )
        z_head = z1 - 0.08 * sz
    head_r = clip(0.1 * min(sx, sy), 0.05, 0.12)
    pipe_r = clip(0.01 * sz, 0.008, 0.014)
    reach = min(0.3, 0.4 * sy)
    parts += _shower_head(0.0, y0, z0 + 0.45 * sz, z_head, reach, head_r, pipe_r)
    return parts


def _shower_panel(size: np.ndarray, rng: np.random.Generator, style: int) -> list[Part]:
    """A thin shower along x: a framed glass door (style 0) or a curtain on a rod
    (style 1) at the +y side, with a head behind it when the box is deep enough."""
    sx, sy, sz = size
    x0, y0, z0 = -size / 2
    x1, y1, z1 = size / 2
    has_head = sy >= SHOWER_HEAD_MIN_DEPTH_M
    # depth of the frame or curtain band; a curtain with nothing behind it uses the whole box
    pd = min(sy, 0.04) if has_head or style == 0 else sy
    parts: list[Part] = []
    if style == 0:
        post = clip(0.025 * sx, 0.008, 0.03, 0.1 * min(sx, sz))
        sill_h = clip(0.02 * sz, 0.01, 0.03, 0.1 * sz)
        gt = min(0.01, 0.4 * pd)
        yg = y1 - pd / 2
        zs = z0 + sill_h
        parts += [
            Part("sill", box_between((x0, y1 - pd if has_head else y0, z0), (x1, y1, zs))),
            Part("post_left", box_between((x0, y1 - pd, zs), (x0 + post, y1, z1))),
            Part("post_right", box_between((x1 - post, y1 - pd, zs), (x1, y1, z1))),
            Part("rail_top", box_between((x0 + post, y1 - pd, z1 - post), (x1 - post, y1, z1))),
            Part(
                "glass",
                box_between((x0 + post, yg - gt / 2, zs), (x1 - post, yg + gt / 2, z1 - post)),
            ),
        ]
        hx = x0 + 0.75 * sx
        hw = min(0.02, 0.3 * sx)
        parts.append(
            Part(
                "handle",
                box_between(
                    (hx - hw / 2, yg + gt / 2, z0 + 0.4 * sz), (hx + hw / 2, y1, z0 + 0.6 * sz)
                ),
            )
        )
        if not has_head and pd < sy:
            parts.append(Part("sill_back", box_between((x0, y0, z0), (x1, y1 - pd, zs))))
    else:
        rr = clip(0.25 * pd, 0.005, 0.015, 0.05 * sz)
        zr = z1 - rr
        ym = y1 - pd / 2
        end_r = min(2 * rr, pd / 2)
        end_t = min(0.008, 0.05 * sx)  # wall flange thickness
        parts += [
            Part("rod", bar((x0, ym, zr), (x1, ym, zr), rr)),
            Part(
                "rod_end_left",
                cylinder((x0 + end_t / 2, ym, zr), end_r, end_t, ROD_SEGMENTS, _Z_TO_X),
            ),
            Part(
                "rod_end_right",
                cylinder((x1 - end_t / 2, ym, zr), end_r, end_t, ROD_SEGMENTS, _Z_TO_X),
            ),
        ]
        parts += _named(
            "curtain",
            _pleats(x0 + end_t, x1 - end_t, ym, pd, z0, zr - rr, 0.08 * jitter(rng, 0.1), 20),
        )
    if has_head:
        head_r = min(0.08, 0.4 * (sy - pd))
        pipe_r = clip(0.01 * sz, 0.006, 0.012)
        reach = sy - pd - 1.2 * head_r
        parts += _shower_head(-0.25 * sx, y0, z0 + 0.45 * sz, z1 - 0.06 * sz, reach, head_r, pipe_r)
    return parts


# -- small bathroom and kitchen fixtures ---------------------------------------------
@register("towel_holder", variants=2)
def towel_holder(
    size: np.ndarray, rng: np.random.Generator, style: int, support_heights: Sequence[float] | None
) -> list[Part]:
    """Towel holder on the wall at -y: style 0 rails on brackets (one per ~12 cm of height,
    a ladder when tall), style 1 a hanging ring (a double bar when the box is too low and
    wide for a ring)."""
    sx, sy, sz = size
    x0, y0, z0 = -size / 2
    x1, y1, z1 = size / 2
    pt = clip(0.15 * sy, 0.003, 0.01)  # wall plate thickness
    if style == 0 or sz < 0.5 * sx:
        double = style == 1
        n = int(np.clip(round(sz / TOWEL_RAIL_PITCH_M), 1, 4))
        r = clip(0.25 * min(sy, sz / n), 0.003, 0.014) * jitter(rng, 0.1)
        if double:
            r = min(r, (sy - pt) / 8)
        yr = y1 - r
        end = clip(0.1 * sx, 0.01, 0.08)
        zs = [0.0] if n == 1 else list(np.linspace(z0 + r, z1 - r, n))
        parts = [Part(f"rail_{k}", bar((x0, yr, z), (x1, yr, z), r)) for k, z in enumerate(zs)]
        if double:
            yb = yr - 3.5 * r
            parts += [
                Part(f"rail_back_{k}", bar((x0 + 0.5 * r, yb, z), (x1 - 0.5 * r, yb, z), r))
                for k, z in enumerate(zs)
            ]
        # wall plates and standoff arms at each end; a ladder's arms hold its top and bottom
        pr = sz / 2 if n == 1 else min(2.5 * r, 0.3 * sz / n)
        arm_z = [0.0] if n == 1 else [zs[0], zs[-1]]
        for side, xs in (("left", x0 + end), ("right", x1 - end)):
            for k, z in enumerate(arm_z):
                parts.append(
                    Part(
                        f"plate_{side}_{k}",
                        cylinder((xs, y0 + pt / 2, z), min(pr, end), pt, ROD_SEGMENTS, _Z_TO_Y),
                    )
                )
                parts.append(Part(f"arm_{side}_{k}", bar((xs, y0 + pt, z), (xs, yr, z), 0.8 * r)))
            if n > 1:
                parts.append(
                    Part(
                        f"post_{side}",
                        bar((xs, yr, zs[0]), (xs, yr, zs[-1]), r, extend0=r, extend1=r),
                    )
                )
        return parts
    tube = clip(0.05 * min(sx, sz), 0.003, 0.01)
    rr = min(clip(0.2 * min(sx, sz), 0.015, 0.04), sx / 2)
    z_arm = z1 - rr
    y_ring = y1 - tube
    rx, rz = sx / 2 - tube, (z_arm - z0) / 2 - tube
    zc = z0 + tube + rz
    a = np.linspace(0.0, 2.0 * np.pi, ROUND_SEGMENTS, endpoint=False) + np.pi / 2
    ring = np.stack([rx * np.cos(a), np.full_like(a, y_ring), zc + rz * np.sin(a)], 1)
    parts = [
        Part("rosette", cylinder((0.0, y0 + pt / 2, z_arm), rr, pt, ROUND_SEGMENTS, _Z_TO_Y)),
        Part("arm", bar((0.0, y0 + pt, z_arm), (0.0, y_ring, z_arm), 1.3 * tube)),
    ]
    return parts + _named("ring", _path(ring, tube, closed=True))


@register("toilet_paper_hanger", variants=2)
def toilet_paper_hanger(
    size: np.ndarray, rng: np.random.Generator, style: int, support_heights: Sequence[float] | None
) -> list[Part]:
    """Toilet paper holder on the wall at -y: style 0 a hooded holder (back plate, quarter-round
    hood with side cheeks, spindle), style 1 an open arm with the spindle running to +x."""
    sx, sy, sz = size
    x0, y0, z0 = -size / 2
    x1, y1, z1 = size / 2
    pt = clip(0.12 * sy, 0.004, 0.012)
    sr = clip(0.12 * min(sy, sz), 0.004, 0.011) * jitter(rng, 0.1)  # spindle radius
    if style == 0:
        ct = clip(0.06 * min(sx, sz), 0.003, 0.008)  # hood thickness
        zc = z0 + 0.35 * sz  # axis of the quarter-round hood
        ry, rz = sy - pt, z1 - zc
        yw = y0 + pt
        a = np.linspace(0.0, np.pi / 2, 5)
        parts = [Part("back_plate", box_between((x0, y0, z0), (x1, yw, z1)))]
        for i in range(len(a) - 1):
            pts = [
                (x, yw + (ry - k) * np.cos(t), zc + (rz - k) * np.sin(t))
                for x in (x0, x1)
                for t in a[i : i + 2]
                for k in (0.0, ct)
            ]
            parts.append(Part(f"hood_{i}", hull(pts)))
        for name, xe in (("cheek_left", x0), ("cheek_right", x1 - ct)):
            pts = [(x, yw + ry * np.cos(t), zc + rz * np.sin(t)) for x in (xe, xe + ct) for t in a]
            pts += [(xe, yw, zc), (xe + ct, yw, zc)]
            parts.append(Part(name, hull(pts)))
        ys, zs = yw + 0.5 * ry, zc + 0.2 * rz
        parts.append(Part("spindle", bar((x0 + ct, ys, zs), (x1 - ct, ys, zs), sr)))
        return parts
    pw = clip(0.22 * sx, 0.02, 0.06)
    zc = 0.0
    ys = y1 - sr
    xa = x0 + pw / 2
    return [
        Part("wall_plate", box_between((x0, y0, z0), (x0 + pw, y0 + pt, z1))),
        Part("arm", bar((xa, y0 + pt, zc), (xa, ys, zc), 1.2 * sr, extend1=sr)),
        Part("spindle", bar((xa, ys, zc), (x1 - sr, ys, zc), sr)),
        Part("stop", bar((x1 - sr, ys, zc - sr), (x1 - sr, ys, zc + 2.5 * sr), sr)),
    ]


@register("faucet", variants=2)
def faucet(
    size: np.ndarray, rng: np.random.Generator, style: int, support_heights: Sequence[float] | None
) -> list[Part]:
    """Faucet with its spout toward +y: style 0 a gooseneck on a deck plate with two
    handles, style 1 a single-lever mixer (round body, straight spout, lever on top)."""
    sx, sy, sz = size
    x0, y0, z0 = -size / 2
    x1, y1, z1 = size / 2
    tube = clip(0.05 * min(sx * 2, sy, sz), 0.004, 0.014) * jitter(rng, 0.1)
    plate_h = clip(0.06 * sz, 0.004, 0.015)
    kr = min(1.6 * tube, 0.25 * sx)  # handle column radius
    if style == 0:
        pry = clip(0.22 * sy, 1.5 * tube, 0.05)
        yb = y0 + pry
        parts = [
            Part(
                "plate",
                cylinder((0.0, yb, z0 + plate_h / 2), (sx / 2, pry), plate_h, ROUND_SEGMENTS),
            ),
            Part(
                "base",
                cylinder(
                    (0.0, yb, z0 + plate_h + 0.05 * sz), min(2 * tube, pry), 0.1 * sz, ROD_SEGMENTS
                ),
            ),
        ]
        parts += _named("spout", _spout(0.0, yb, z0 + plate_h, z1, y1 - tube, tube))
        if sx > 8 * kr:
            hz = z0 + plate_h + 0.12 * sz
            for name, s in (("left", -1), ("right", 1)):
                hx = s * (sx / 2 - kr)
                parts.append(
                    Part(f"handle_{name}", cylinder((hx, yb, hz), kr, 0.24 * sz, ROD_SEGMENTS))
                )
                parts.append(
                    Part(
                        f"lever_{name}",
                        bar((hx, yb, hz + 0.1 * sz), (hx, yb + 3 * kr, hz + 0.14 * sz), 0.5 * kr),
                    )
                )
        return parts
    br = min(clip(0.15 * sy, 2 * tube, 0.06), sx / 2)  # mixer body radius
    yb = y0 + br
    body_top = z0 + 0.72 * sz
    zs = z0 + 0.55 * sz  # spout height
    lever_r = 0.6 * tube
    parts = [
        Part("plate", box_between((x0, y0, z0), (x1, y0 + 2 * br, z0 + plate_h))),
        Part("body", cylinder((0.0, yb, (z0 + body_top) / 2), br, body_top - z0, ROUND_SEGMENTS)),
        Part(
            "lever",
            bar(
                (0.0, yb, body_top),
                (0.0, yb + 0.35 * (y1 - yb), z1 - lever_r),
                lever_r,
                extend0=lever_r,
            ),
        ),
    ]
    parts += _named(
        "spout",
        _path(
            [(0.0, yb, zs), (0.0, y1 - tube, zs - 0.08 * sz), (0.0, y1 - tube, zs - 0.2 * sz)],
            1.2 * tube,
        ),
    )
    return parts


@register("stove", variants=2)
def stove(
    size: np.ndarray, rng: np.random.Generator, style: int, support_heights: Sequence[float] | None
) -> list[Part]:
    """Stove: a cooktop slab with four burners (a single burner when the footprint is
    small); style 0 gas with grates (over an oven when tall), style 1 flat electric
    rings (over a cabinet when tall)."""
    sx, sy, sz = size
    if max(sx, sy) < SINGLE_BURNER_MAX_M:
        return _single_burner(size, rng, style)
    x0, y0, z0 = -size / 2
    x1, y1, z1 = size / 2
    tall = sz >= STOVE_BODY_MIN_M
    top_h = (
        clip(0.03 * sz, 0.006, 0.03, 0.3 * sz)
        if style == 0
        else clip(0.01 * sz, 0.003, 0.008, 0.1 * sz)
    )
    slab_t = clip(0.05 * sz, 0.02, 0.05) if tall else sz - top_h
    zs = z1 - top_h  # cooktop surface
    knob_r = clip(0.04 * min(sx, sy), 0.012, 0.025)
    knob_d = clip(0.04 * sy, 0.01, 0.025, 0.1 * sy)
    front = y1 - knob_d if not tall or style == 1 else y1  # slab front face
    parts = [Part("cooktop", box_between((x0, y0, zs - slab_t), (x1, front, zs)))]
    # burners on a 2 x 2 grid, shifted back a little where front knobs need room
    sizes = rng.permutation([1.0, 0.8, 0.9, 1.1])
    cell = min(sx, front - y0) / 2
    for k, (gx, gy) in enumerate(((-1, -1), (1, -1), (-1, 1), (1, 1))):
        cx = gx * sx / 4
        cy = (y0 + front) / 2 + gy * (front - y0) / 4
        rb = 0.42 * cell * sizes[k]
        parts += _burner(k, cx, cy, zs, rb, top_h, style)
    if not tall or style == 1:
        # knobs on the slab's front edge (flat cooktop) or its front strip (cabinet)
        zk = zs - slab_t / 2
        kr = min(knob_r, 0.45 * slab_t)
        for k, xk in enumerate(np.linspace(x0 + 0.2 * sx, x1 - 0.2 * sx, 4)):
            parts.append(
                Part(
                    f"knob_{k}",
                    cylinder((xk, front + knob_d / 2, zk), kr, knob_d, ROD_SEGMENTS, _Z_TO_Y),
                )
            )
    if tall:
        parts += _stove_body(size, zs - slab_t, style, knob_r, knob_d)
    return parts


def _burner(
    k: int, cx: float, cy: float, zs: float, rb: float, top_h: float, style: int
) -> list[Part]:
    """One burner on a cooktop surface at height zs: gas ring, cap and grate bars
    (style 0) or a flat electric disc with its ring (style 1); top_h: height used."""
    if style == 0:
        ring_h = 0.35 * top_h
        g = 0.15 * rb  # grate bar width
        return [
            Part(
                f"burner_{k}", cylinder((cx, cy, zs + ring_h / 2), 0.6 * rb, ring_h, ROUND_SEGMENTS)
            ),
            Part(
                f"burner_cap_{k}",
                cylinder((cx, cy, zs + ring_h), 0.3 * rb, 0.5 * top_h, ROUND_SEGMENTS),
            ),
            Part(f"grate_{k}_x", box((cx, cy, zs + top_h - g / 2), (2.2 * rb, g, g))),
            Part(f"grate_{k}_y", box((cx, cy, zs + top_h - g / 2), (g, 2.2 * rb, g))),
        ]
    return [
        Part(f"burner_{k}", cylinder((cx, cy, zs + 0.25 * top_h), rb, 0.5 * top_h, ROUND_SEGMENTS)),
        Part(
            f"burner_ring_{k}",
            cylinder((cx, cy, zs + 0.5 * top_h), 0.7 * rb, top_h, ROUND_SEGMENTS),
        ),
    ]


def _stove_body(
    size: np.ndarray, z_top: float, style: int, knob_r: float, knob_d: float
) -> list[Part]:
    """What stands under a tall cooktop (up to z_top): an oven with door, window, handle,
    drawer and control knobs (style 0) or a base cabinet with two doors (style 1)."""
    sx, sy, sz = size
    x0, y0, z0 = -size / 2
    x1, y1, _ = size / 2
    kick_h = clip(0.08 * sz, 0.03, 0.1)
    hd = clip(0.05 * sy, 0.02, 0.04, 0.1 * sy)  # handle depth
    face = y1 - hd - (knob_d if style == 1 else 0.0)
    door_t = clip(0.02 * sy, 0.008, 0.02, 0.05 * sy)
    body_front = face - door_t
    parts = [
        Part(
            "plinth", box_between((x0, y0, z0), (x1, body_front - min(0.03, 0.2 * sy), z0 + kick_h))
        ),
        Part("body", box_between((x0, y0, z0 + kick_h), (x1, body_front, z_top))),
    ]
    g = min(0.005, 0.02 * sx)  # between fronts
    if style == 0:
        strip = clip(0.12 * (z_top - z0), 0.05, 0.12)  # control strip above the door
        drawer_h = clip(0.15 * (z_top - z0), 0.05, 0.15)
        dz0, dz1 = z0 + kick_h + drawer_h + g, z_top - strip
        wy = face + 0.3 * door_t
        hz = dz1 - 0.08 * (dz1 - dz0)
        hr = min(0.012, 0.3 * hd)
        parts += [
            Part(
                "drawer",
                box_between(
                    (x0 + g, body_front, z0 + kick_h + g), (x1 - g, face, z0 + kick_h + drawer_h)
                ),
            ),
            Part("oven_door", box_between((x0 + g, body_front, dz0), (x1 - g, face, dz1))),
            Part(
                "oven_window",
                box_between(
                    (x0 + 0.18 * sx, face - 0.5 * door_t, dz0 + 0.2 * (dz1 - dz0)),
                    (x1 - 0.18 * sx, wy, dz1 - 0.25 * (dz1 - dz0)),
                ),
            ),
            Part(
                "oven_handle",
                bar((x0 + 0.12 * sx, y1 - hr, hz), (x1 - 0.12 * sx, y1 - hr, hz), hr),
            ),
        ]
        for s, name in ((-1, "left"), (1, "right")):
            parts.append(
                Part(
                    f"handle_mount_{name}",
                    box_between(
                        (s * 0.38 * sx - 0.006, face, hz - 0.006),
                        (s * 0.38 * sx + 0.006, y1 - hr, hz + 0.006),
                    ),
                )
            )
        kr = min(knob_r, 0.4 * strip)
        for k, xk in enumerate(np.linspace(x0 + 0.15 * sx, x1 - 0.15 * sx, 4)):
            parts.append(
                Part(
                    f"knob_{k}",
                    cylinder(
                        (xk, body_front + knob_d / 2, z_top - strip / 2),
                        kr,
                        knob_d,
                        ROD_SEGMENTS,
                        _Z_TO_Y,
                    ),
                )
            )
        return parts
    dz0, dz1 = z0 + kick_h + g, z_top - g
    for i in range(2):
        dx0, dx1 = x0 + i * sx / 2 + g, x0 + (i + 1) * sx / 2 - g
        parts.append(Part(f"door_{i}", box_between((dx0, body_front, dz0), (dx1, face, dz1))))
        hx = dx1 - 0.1 * (dx1 - dx0) if i == 0 else dx0 + 0.1 * (dx1 - dx0)
        hh = min(0.15, 0.25 * (dz1 - dz0))
        parts.append(
            Part(
                f"handle_{i}",
                box((hx, face + hd / 2, dz1 - 0.1 * (dz1 - dz0) - hh / 2), (0.012, hd, hh)),
            )
        )
    return parts


def _single_burner(size: np.ndarray, rng: np.random.Generator, style: int) -> list[Part]:
    """One burner filling the box: drip pan, ring, cap and grate (style 0) or a flat plate
    with two coil rings (style 1)."""
    sx, sy, sz = size
    z0, z1 = -sz / 2, sz / 2
    r = np.array([sx / 2, sy / 2])
    if style == 0:
        g = 0.12 * min(sx, sy) / 2 * jitter(rng, 0.1)
        return [
            Part("pan", cylinder((0.0, 0.0, z0 + 0.15 * sz), r, 0.3 * sz, ROUND_SEGMENTS)),
            Part("burner", cylinder((0.0, 0.0, z0 + 0.45 * sz), 0.5 * r, 0.3 * sz, ROUND_SEGMENTS)),
            Part(
                "burner_cap",
                cylinder((0.0, 0.0, z0 + 0.6 * sz), 0.25 * r, 0.3 * sz, ROUND_SEGMENTS),
            ),
            Part("grate_x", box((0.0, 0.0, z1 - 0.15 * sz), (sx, g, 0.3 * sz))),
            Part("grate_y", box((0.0, 0.0, z1 - 0.15 * sz), (g, sy, 0.3 * sz))),
        ]
    coil = 0.08 * min(sx, sy) / 2
    parts = [
        Part("plate", cylinder((0.0, 0.0, z0 + 0.25 * sz), r, 0.5 * sz, ROUND_SEGMENTS)),
        Part("burner", cylinder((0.0, 0.0, z0 + 0.5 * sz), 0.25 * r, sz, ROUND_SEGMENTS)),
    ]
    for k, f in enumerate((0.85, 0.55)):
        parts += _named(
            f"coil_{k}", _shell(0.0, 0.0, z0 + 0.5 * sz, z1, f * r, 1.0, coil, ROUND_SEGMENTS)
        )
    return parts


@register("stove_knob", variants=2)
def stove_knob(
    size: np.ndarray, rng: np.random.Generator, style: int, support_heights: Sequence[float] | None
) -> list[Part]:
    """Stove knob on a front panel (axis +y) or, in a flat box, on the cooktop (axis +z):
    style 0 a round knob with a grip fin, style 1 a flared skirt knob with a pointer."""
    sx, sy, sz = size
    top_mounted = sz < KNOB_TOP_MOUNT_RATIO * sy
    # build along +z with width w, thickness t and length h, then turn to +y if needed
    w, t, h = (sx, sy, sz) if top_mounted else (sx, sz, sy)
    r = np.array([w / 2, t / 2])
    z0 = -h / 2
    if style == 0:
        base_h = 0.2 * h * jitter(rng, 0.1)
        fin = (0.9 * w, 0.22 * t, h - base_h)
        parts = [
            Part("base", cylinder((0.0, 0.0, z0 + base_h / 2), r, base_h, ROUND_SEGMENTS)),
            Part(
                "knob",
                cylinder(
                    (0.0, 0.0, z0 + base_h + 0.35 * (h - base_h)),
                    0.75 * r,
                    0.7 * (h - base_h),
                    ROUND_SEGMENTS,
                ),
            ),
            Part("grip", box((0.0, 0.0, z0 + base_h + fin[2] / 2), fin)),
        ]
    else:
        skirt_h = 0.35 * h * jitter(rng, 0.1)
        mark_h = 0.08 * h  # the pointer stands proud of the knob's face
        knob_top = z0 + h - mark_h
        parts = [
            Part("skirt", frustum((0.0, 0.0, z0), skirt_h, r, 0.65 * r, ROUND_SEGMENTS)),
            Part(
                "knob",
                frustum(
                    (0.0, 0.0, z0 + skirt_h),
                    knob_top - z0 - skirt_h,
                    0.6 * r,
                    0.5 * r,
                    ROUND_SEGMENTS,
                ),
            ),
            # toward local -y, which is up once the knob is turned onto a front panel
            Part(
                "pointer",
                box_between(
                    (-0.05 * w, -0.45 * t, knob_top - mark_h), (0.05 * w, 0.0, knob_top + mark_h)
                ),
            ),
        ]
    if top_mounted:
        return parts
    return [Part(p.name, p.mesh.transformed(_Z_TO_Y)) for p in parts]


# -- wall objects ---------------------------------------------------------------------
def _frame_bars(lo: np.ndarray, hi: np.ndarray, fw: float, bevel: float) -> list[Part]:
    """Four bars of a rectangular frame in the x-z plane, lo (3,) to hi (3,), bars fw wide;
    the front (+y) of each bar is narrowed by ``bevel`` on its inner edge."""
    x0, y0, z0 = lo
    x1, y1, z1 = hi
    specs = {  # box corners and which corner coordinate moves on the front face
        "frame_top": ((x0, y0, z1 - fw), (x1, y1, z1), 2, +1),
        "frame_bottom": ((x0, y0, z0), (x1, y1, z0 + fw), 2, -1),
        "frame_left": ((x0, y0, z0 + fw), (x0 + fw, y1, z1 - fw), 0, -1),
        "frame_right": ((x1 - fw, y0, z0 + fw), (x1, y1, z1 - fw), 0, +1),
    }
    parts = []
    for name, (a, b, axis, outward) in specs.items():
        c = box_between(a, b).vertices.copy()
        front = c[:, 1] > (a[1] + b[1]) / 2
        inner = np.isclose(c[:, axis], a[axis] if outward > 0 else b[axis])
        c[front & inner, axis] += outward * min(bevel, 0.9 * fw)
        parts.append(Part(name, _hexahedron(c)))
    return parts


@register("painting", variants=3)
def painting(
    size: np.ndarray, rng: np.random.Generator, style: int, support_heights: Sequence[float] | None
) -> list[Part]:
    """Painting hung on its -y side, picture facing +y: style 0 a deep frame around a
    recessed canvas, style 1 a slim frame with a mat, style 2 a frameless canvas."""
    sx, sy, sz = size
    lo, hi = -size / 2, size / 2
    x0, y0, z0 = lo
    x1, y1, z1 = hi
    if style == 2:
        return [Part("canvas", box_between(lo, hi))]
    fw = clip(0.07 * min(sx, sz), 0.01, 0.1, 0.15 * min(sx, sz)) * jitter(rng, 0.15)
    if style == 1:
        fw *= 0.5
    recess = 0.45 * sy
    parts = _frame_bars(lo, hi, fw, 0.3 * fw if style == 0 else 0.0)
    parts.append(
        Part(
            "canvas",
            box_between((x0 + fw / 2, y0, z0 + fw / 2), (x1 - fw / 2, y1 - recess, z1 - fw / 2)),
        )
    )
    if style == 1:
        mw = clip(0.08 * min(sx, sz), 0.01, 0.08, 0.15 * min(sx, sz))  # mat width
        ym = (y1 - 0.15 * sy, y0)
        a0, a1 = x0 + fw, x1 - fw
        b0, b1 = z0 + fw, z1 - fw
        parts += [
            Part("mat_top", box_between((a0, ym[1], b1 - mw), (a1, ym[0], b1))),
            Part("mat_bottom", box_between((a0, ym[1], b0), (a1, ym[0], b0 + mw))),
            Part("mat_left", box_between((a0, ym[1], b0 + mw), (a0 + mw, ym[0], b1 - mw))),
            Part("mat_right", box_between((a1 - mw, ym[1], b0 + mw), (a1, ym[0], b1 - mw))),
        ]
    return parts


@register("mirror", variants=3)
def mirror(
    size: np.ndarray, rng: np.random.Generator, style: int, support_heights: Sequence[float] | None
) -> list[Part]:
    """Mirror hung on its -y side, glass facing +y: style 0 a bevelled rectangular frame,
    style 1 an oval frame, style 2 a frameless glass on a backing board."""
    sx, sy, sz = size
    lo, hi = -size / 2, size / 2
    x0, y0, z0 = lo
    x1, y1, z1 = hi
    fw = clip(0.05 * min(sx, sz), 0.01, 0.07, 0.15 * min(sx, sz)) * jitter(rng, 0.15)
    recess = 0.3 * sy
    if style == 0:
        parts = _frame_bars(lo, hi, fw, 0.5 * fw)
        parts.append(
            Part(
                "glass",
                box_between(
                    (x0 + fw / 2, y0, z0 + fw / 2), (x1 - fw / 2, y1 - recess, z1 - fw / 2)
                ),
            )
        )
        return parts
    if style == 1:
        # ring sectors built along z, then turned so z -> y; local y becomes -z
        rs = np.array([sx / 2, sz / 2])
        ring = _shell(0.0, 0.0, y0, y1, rs, 1.0, fw, FINE_SEGMENTS)
        parts = _named("frame", [m.transformed(_Z_TO_Y) for m in ring])
        glass_d = sy - recess
        parts.append(
            Part(
                "glass",
                cylinder(
                    (0.0, y0 + glass_d / 2, 0.0), rs - fw / 2, glass_d, FINE_SEGMENTS, _Z_TO_Y
                ),
            )
        )
        return parts
    inset = clip(0.03 * min(sx, sz), 0.005, 0.03, 0.1 * min(sx, sz))
    return [
        Part(
            "backing",
            box_between((x0 + inset, y0, z0 + inset), (x1 - inset, y0 + 0.5 * sy, z1 - inset)),
        ),
        Part("glass", box_between((x0, y0 + 0.5 * sy, z0), (x1, y1, z1))),
    ]


@register("curtains", variants=2)
def curtains(
    size: np.ndarray, rng: np.random.Generator, style: int, support_heights: Sequence[float] | None
) -> list[Part]:
    """Curtains: a rod on wall brackets (wall at -y) with finials, and two pleated panels
    hanging to the bottom; style 0 drawn open to the sides, style 1 drawn closed."""
    sx, sy, sz = size
    x0, y0, z0 = -size / 2
    x1, y1, z1 = size / 2
    gap = clip(0.15 * sy, 0.003, 0.04, 0.3 * sy)  # between the fabric and the wall
    fab_d = sy - gap
    ym = y1 - fab_d / 2
    rr = clip(0.15 * fab_d, 0.005, 0.02, 0.05 * sz)
    fr = min(1.8 * rr, fab_d / 2, 0.05 * sx, 0.1 * sz)  # finial radius
    zr = z1 - fr
    xr0, xr1 = x0 + 2 * fr, x1 - 2 * fr
    parts = [
        Part("rod", bar((xr0, ym, zr), (xr1, ym, zr), rr)),
        Part(
            "finial_left",
            ellipsoid((x0 + fr, ym, zr), (fr, fr, fr), rings=6, segments=ROD_SEGMENTS),
        ),
        Part(
            "finial_right",
            ellipsoid((x1 - fr, ym, zr), (fr, fr, fr), rings=6, segments=ROD_SEGMENTS),
        ),
        Part("bracket_left", bar((xr0 + rr, y0, zr), (xr0 + rr, ym, zr), 0.6 * rr)),
        Part("bracket_right", bar((xr1 - rr, y0, zr), (xr1 - rr, ym, zr), 0.6 * rr)),
    ]
    width = xr1 - xr0
    if style == 0:
        panel = width * float(rng.uniform(0.18, 0.28))
        pitch = 0.6 * CURTAIN_PLEAT_M
    else:
        panel = width / 2
        pitch = CURTAIN_PLEAT_M
    per_panel = MAX_REPEATS // 2
    pz = (z0, zr)  # fabric hangs from the rod's axis down to the floor
    parts += _named(
        "panel_left",
        _pleats(xr0, xr0 + panel, ym, fab_d, *pz, pitch * jitter(rng, 0.1), per_panel),
    )
    parts += _named(
        "panel_right",
        _pleats(xr1 - panel, xr1, ym, fab_d, *pz, pitch * jitter(rng, 0.1), per_panel),
    )
    return parts


@register("blinds", variants=3)
def blinds(
    size: np.ndarray, rng: np.random.Generator, style: int, support_heights: Sequence[float] | None
) -> list[Part]:
    """Window blinds under a head rail: style 0 venetian (tilted horizontal slats, ladder
    tapes, pull cord), style 1 vertical vanes, style 2 a roller blind."""
    sx, sy, sz = size
    x0, y0, z0 = -size / 2
    x1, y1, z1 = size / 2
    rail_h = clip(0.12 * sz, 0.01, 0.05, 0.2 * sz)
    zr = z1 - rail_h
    parts = [Part("head_rail", box_between((x0, y0, zr), (x1, y1, z1)))]
    if style == 0:
        tilt = np.radians(rng.uniform(10.0, 35.0))
        t = clip(0.08 * sy, 0.001, 0.003)
        w = max((0.9 * sy - t * np.sin(tilt)) / np.cos(tilt), 2 * t)
        bottom_h = clip(0.06 * sz, 0.006, 0.02)
        span = zr - (z0 + bottom_h)
        n = int(np.clip(span // BLIND_SLAT_PITCH_M, 2, MAX_REPEATS))
        rot = np.array(
            [[1.0, 0.0, 0.0], [0.0, np.cos(tilt), -np.sin(tilt)], [0.0, np.sin(tilt), np.cos(tilt)]]
        )
        for k in range(n):
            zk = z0 + bottom_h + span * (k + 0.5) / n
            parts.append(Part(f"slat_{k}", box((0.0, 0.0, zk), (sx, w, t), rot)))
        parts.append(
            Part("bottom_rail", box_between((x0, -0.45 * sy, z0), (x1, 0.45 * sy, z0 + bottom_h)))
        )
        tape = min(0.01, 0.1 * sx)
        for name, xt in (("left", -0.3 * sx), ("right", 0.3 * sx)):
            parts.append(
                Part(
                    f"ladder_{name}",
                    box_between((xt - tape / 2, -0.5 * t, z0), (xt + tape / 2, 0.5 * t, zr)),
                )
            )
        cr = min(0.002, 0.05 * sy)
        cx = x1 - clip(0.05 * sx, 0.01, 0.05)
        cz = z0 + 0.35 * sz
        parts += [
            Part("cord", bar((cx, y1 - 2 * cr, zr), (cx, y1 - 2 * cr, cz), cr)),
            Part(
                "cord_tassel",
                ellipsoid(
                    (cx, y1 - 2 * cr, cz), (2 * cr, 2 * cr, 5 * cr), rings=6, segments=ROD_SEGMENTS
                ),
            ),
        ]
        return parts
    if style == 1:
        n = int(np.clip(round(sx / BLIND_VANE_PITCH_M), 2, MAX_REPEATS))
        pitch = sx / n
        t = clip(0.05 * sy, 0.001, 0.003)
        vw = 1.05 * pitch
        turn = np.arcsin(np.clip((0.9 * sy - t) / vw, 0.0, np.sin(np.radians(70.0))))
        turn *= jitter(rng, 0.1)
        rot = np.array(
            [[np.cos(turn), -np.sin(turn), 0.0], [np.sin(turn), np.cos(turn), 0.0], [0.0, 0.0, 1.0]]
        )
        hx = (vw * np.cos(turn) + t * np.sin(turn)) / 2  # a turned vane's half width in x
        for k, xk in enumerate(np.linspace(x0 + hx, x1 - hx, n)):
            parts.append(Part(f"vane_{k}", box((xk, 0.0, (z0 + zr) / 2), (vw, t, zr - z0), rot)))
        return parts
    tube_r = min(0.45 * sy, 0.45 * rail_h, 0.03, 0.1 * sz)
    fabric_t = clip(0.05 * sy, 0.0008, 0.002)
    bar_r = min(0.3 * sy, 0.012, 0.1 * sz)
    drop = (zr - z0) * float(rng.uniform(0.55, 1.0))  # how far the blind is pulled down
    zf = zr - drop
    parts += [
        Part(
            "roller",
            cylinder((0.0, 0.0, zr - tube_r), (tube_r, tube_r), 0.98 * sx, ROD_SEGMENTS, _Z_TO_X),
        ),
        Part(
            "fabric",
            box_between(
                (x0 + 0.01 * sx, -fabric_t / 2, zf + bar_r),
                (x1 - 0.01 * sx, fabric_t / 2, zr - tube_r),
            ),
        ),
        Part(
            "bottom_bar",
            cylinder((0.0, 0.0, zf + bar_r), (bar_r, bar_r), 0.98 * sx, ROD_SEGMENTS, _Z_TO_X),
        ),
        Part(
            "chain",
            bar(
                (x1 - 0.02 * sx, y1 - 0.002, zr),
                (x1 - 0.02 * sx, y1 - 0.002, z0),
                min(0.002, 0.05 * sy),
            ),
        ),
    ]
    return parts


# -- floor objects --------------------------------------------------------------------
@register("house_plant", variants=3)
def house_plant(
    size: np.ndarray, rng: np.random.Generator, style: int, support_heights: Sequence[float] | None
) -> list[Part]:
    """House plant in a pot: style 0 broad leaves on stalks fanning out, style 1 a small
    tree (trunk and a crown of leaf balls), style 2 upright blade leaves (a snake plant)."""
    sx, sy, sz = size
    x0, y0, z0 = -size / 2
    x1, y1, z1 = size / 2
    rt = 0.3 * min(sx, sy) * jitter(rng, 0.08)  # pot top radius
    ph = clip(0.3 * sz, 0.05, 3 * rt, 0.4 * sz) * jitter(rng, 0.1)  # pot height
    soil = z0 + ph
    rim_h = 0.15 * ph
    parts = [
        Part("pot", frustum((0.0, 0.0, z0), ph - rim_h, 0.72 * rt, rt, ROUND_SEGMENTS)),
        Part("pot_rim", cylinder((0.0, 0.0, soil - rim_h / 2), 1.08 * rt, rim_h, ROUND_SEGMENTS)),
    ]
    fh = z1 - soil  # foliage height
    half = np.array([sx / 2, sy / 2])
    if style == 2:
        n = int(rng.integers(7, 11))
        leaf_w = 0.12 * min(sx, sy)
        leaf_t = 0.25 * leaf_w
        for k in range(n):
            az = 2 * np.pi * k / n + rng.uniform(-0.2, 0.2)
            if k < 4:  # four leaves lean exactly onto the box sides
                az = k * np.pi / 2
            length = fh if k == 0 else fh * float(rng.uniform(0.6, 0.95))
            base = 0.4 * rt
            reach = _reach(half, az)
            lean = np.arcsin(np.clip((reach - base - leaf_t) / length, 0.0, 0.7))
            if k >= 4:
                lean *= float(rng.uniform(0.4, 0.9))
            d = np.array([np.sin(lean) * np.cos(az), np.sin(lean) * np.sin(az), np.cos(lean)])
            # leaf blade: width across the lean, thin toward the box side it leans to
            u = np.array([-np.sin(az), np.cos(az), 0.0])
            v = np.cross(d, u)
            rot = np.stack([u, v, d], axis=1)
            start = np.array([base * np.cos(az), base * np.sin(az), soil - 0.05 * fh])
            leaf = ellipsoid(
                (0.0, 0.0, 0.0),
                (leaf_w / 2, leaf_t / 2, length / 2),
                rings=6,
                segments=ROD_SEGMENTS,
            )
            parts.append(Part(f"leaf_{k}", leaf.transformed(rot, start + d * length / 2)))
        return parts
    stem_r = clip(0.01 * min(sx, sy), 0.003, 0.01)
    if style == 1:
        # a standard tree: trunk, a ring of four leaf balls touching the box sides, one on top
        crown_z = soil + 0.6 * fh
        trunk_r = clip(0.03 * min(sx, sy), 0.006, 0.03)
        parts.append(Part("trunk", bar((0.0, 0.0, soil - 0.01), (0.0, 0.0, crown_z), trunk_r)))
        top = np.array([0.32 * sx, 0.32 * sy, 0.22 * fh]) * jitter(rng, 0.08)
        parts.append(
            Part("crown_top", ellipsoid((0.0, 0.0, z1 - top[2]), top, segments=ROUND_SEGMENTS))
        )
        for k in range(4):
            a = k * np.pi / 2 + rng.uniform(-0.1, 0.1)
            rk = np.array([0.27 * sx, 0.27 * sy, 0.17 * fh]) * jitter(rng, 0.1)
            c = (
                (half[0] - rk[0]) * np.cos(a),
                (half[1] - rk[1]) * np.sin(a),
                crown_z + rng.uniform(-0.05, 0.05) * fh,
            )
            parts.append(Part(f"crown_{k}", ellipsoid(c, rk, segments=ROUND_SEGMENTS)))
        return parts
    # broad leaves on stalks fanning out from the pot: four touch the box sides, one the top
    n = int(rng.integers(10, 14))
    leaf_w = 0.3 * min(sx, sy)
    for k in range(n):
        az = 2 * np.pi * k / n + rng.uniform(-0.15, 0.15)
        rise = np.radians(rng.uniform(-5.0, 35.0))  # leaf blade above the horizontal
        rho = float(rng.uniform(0.15, 0.35))  # stalk reach, fraction of the half width
        hz = soil + rng.uniform(0.3, 0.8) * fh  # stalk top
        if k < 4:
            az = k * np.pi / 2
        elif k == 4:
            rise, rho = np.radians(50.0), 0.1
        reach = _reach(half, az)
        length = (1.0 - rho) * reach / np.cos(rise)
        if k == 4:
            length = min(length, 0.45 * fh)
        elif k > 4:
            length *= float(rng.uniform(0.6, 0.95))
        d = np.array([np.cos(rise) * np.cos(az), np.cos(rise) * np.sin(az), np.sin(rise)])
        if k == 4:
            hz = z1 - length * d[2]
        stalk = np.array([rho * reach * np.cos(az), rho * reach * np.sin(az), hz])
        u = np.array([-np.sin(az), np.cos(az), 0.0])
        rot = np.stack([u, np.cross(d, u), d], axis=1)
        leaf = ellipsoid(
            (0.0, 0.0, 0.0), (leaf_w / 2, 0.06 * leaf_w, length / 2), rings=6, segments=ROD_SEGMENTS
        )
        parts.append(Part(f"stem_{k}", bar((0.0, 0.0, soil - 0.01), stalk, stem_r)))
        parts.append(Part(f"leaf_{k}", leaf.transformed(rot, stalk + d * length / 2)))
    return parts


@register("vacuum_cleaner", variants=2)
def vacuum_cleaner(
    size: np.ndarray, rng: np.random.Generator, style: int, support_heights: Sequence[float] | None
) -> list[Part]:
    """Vacuum cleaner facing +y: style 0 upright (floor head at +y, body, handle), style 1
    canister (body on wheels at -y, hose, and a wand parked upright when the box is tall)."""
    sx, sy, sz = size
    x0, y0, z0 = -size / 2
    x1, y1, z1 = size / 2
    if style == 0:
        head_d = 0.5 * sy * jitter(rng, 0.08)
        head_h = clip(0.08 * sz, 0.03, 0.1, 0.15 * sz)
        wr = clip(0.08 * sz, 0.025, 0.07, 0.15 * sz)  # rear wheel radius
        ww = clip(0.08 * sx, 0.015, 0.04, 0.15 * sx)
        bw = sx - 2 * ww  # body width between the wheels
        bd = 0.6 * sy
        yb = y0 + bd / 2
        body_top = z0 + 0.62 * sz
        grip_r = clip(0.02 * sz, 0.01, 0.02, 0.05 * sz)
        wedge = np.array(
            [
                [x0, y1 - head_d, z0],
                [x1, y1 - head_d, z0],
                [x1, y1, z0],
                [x0, y1, z0],
                [x0, y1 - head_d, z0 + head_h],
                [x1, y1 - head_d, z0 + head_h],
                [x1, y1, z0 + 0.7 * head_h],
                [x0, y1, z0 + 0.7 * head_h],
            ]
        )
        return [
            Part("floor_head", _hexahedron(wedge)),
            Part(
                "wheel_left",
                cylinder((x0 + ww / 2, y0 + wr, z0 + wr), wr, ww, ROUND_SEGMENTS, _Z_TO_X),
            ),
            Part(
                "wheel_right",
                cylinder((x1 - ww / 2, y0 + wr, z0 + wr), wr, ww, ROUND_SEGMENTS, _Z_TO_X),
            ),
            Part(
                "body",
                frustum(
                    (0.0, yb, z0 + wr),
                    body_top - z0 - wr,
                    (0.5 * bw, bd / 2),
                    (0.41 * bw, 0.41 * bd),
                    ROUND_SEGMENTS,
                ),
            ),
            Part(
                "dust_bin",
                cylinder((0.0, yb + 0.3 * bd, z0 + 0.4 * sz), 0.3 * bw, 0.3 * sz, ROUND_SEGMENTS),
            ),
            Part(
                "handle",
                bar(
                    (0.0, yb, body_top - 0.02),
                    (0.0, yb - 0.1 * bd, z1 - 2 * grip_r),
                    clip(0.012 * sz, 0.008, 0.015, 0.04 * sz),
                ),
            ),
            Part(
                "grip",
                bar(
                    (-0.25 * sx, yb - 0.1 * bd, z1 - grip_r),
                    (0.25 * sx, yb - 0.1 * bd, z1 - grip_r),
                    grip_r,
                ),
            ),
        ]
    bh = clip(0.25 * sz, 0.15, 0.3)  # body height
    wand = sz > 2.2 * bh  # room to park the wand upright; else the hose loops over the body
    if not wand:
        bh = 0.75 * sz
    nozzle_h = clip(0.05 * sz, 0.02, 0.05)
    nozzle_d = min(0.3 * sy, 0.1)
    ww = clip(0.08 * sx, 0.015, 0.04, 0.15 * sx)
    bd = sy - nozzle_d
    yb = y0 + bd / 2
    wr = 0.32 * bh
    hose_r = clip(0.04 * bh, 0.01, 0.02)
    rb = np.array([sx / 2 - ww, bd / 2])
    zs = np.array([0.04, 0.35, 0.75, 1.0]) * bh + z0
    parts = [
        Part(
            "body", lathe(zip((0.85, 1.0, 0.88, 0.5), zs), rb[0], rb[1], ROUND_SEGMENTS, (0.0, yb))
        ),
        Part(
            "wheel_left", cylinder((x0 + ww / 2, y0 + wr, z0 + wr), wr, ww, ROUND_SEGMENTS, _Z_TO_X)
        ),
        Part(
            "wheel_right",
            cylinder((x1 - ww / 2, y0 + wr, z0 + wr), wr, ww, ROUND_SEGMENTS, _Z_TO_X),
        ),
    ]
    hose_start = np.array([0.0, yb + 0.35 * bd, z0 + 0.8 * bh])
    if wand:
        yw = y1 - nozzle_d / 2
        grip = np.array([0.0, yw, z1 - hose_r])
        parts += [
            Part(
                "nozzle", box_between((-0.4 * sx, y1 - nozzle_d, z0), (0.4 * sx, y1, z0 + nozzle_h))
            ),
            Part("wand", bar((0.0, yw, z0 + nozzle_h), grip, hose_r)),
        ]
        sag = np.array([0.0, yb, z0 + bh + 0.3 * (z1 - z0 - bh)])
    else:
        grip = np.array([0.0, y1 - 0.5 * nozzle_d, z0 + nozzle_h])
        parts.append(
            Part(
                "nozzle", box_between((-0.3 * sx, y1 - nozzle_d, z0), (0.3 * sx, y1, z0 + nozzle_h))
            )
        )
        sag = np.array([0.0, y1 - 0.5 * nozzle_d, z1 + 0.3 * (z1 - hose_start[2])])
    t = np.linspace(0.0, 1.0, 6)[:, None]
    hose = (1 - t) ** 2 * hose_start + 2 * t * (1 - t) * sag + t**2 * grip
    parts += _named("hose", _path(hose, hose_r))
    return parts

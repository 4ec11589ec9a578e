"""Storage furniture and its movable parts.

Categories: shelving_unit, tv_stand, dresser, wardrobe, cabinet, counter_top,
fridge, laundry_hamper, safe, cart, garbage_can, and the parts drawer,
cabinet_door and shelf.

Generators build in a frame whose origin is the centre of the box's *bottom*
face (x, y centred, +y the front, z from 0 to the height), because support
heights are measured from the box bottom; :func:`_finish` moves the parts down
by half the height at the end. Each part is one convex primitive, so hollow
bodies (an open shelf bay, an open bin) are assembled from panels. Every
generator puts parts on all six faces of the box so that ``generate``'s fit is
the identity and heights land exactly.

Instance fitting (``fits_support_heights``): the tiered generators turn the
dataset's support heights into board levels with :func:`_levels`. A board
whose upward face is at h spans h - thickness .. h; heights within
``TOP_SNAP_M`` of the top are the top panel itself; heights closer together
than a board thickness collapse into the lower one (an object hovering a few
millimetres settles under gravity, one sunk into a board does not). Bays whose
floor came from a support height stay open at the front, because something
rests there; the other bays of a dresser, cabinet or counter get drawers or
doors.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from pair2scene.assets.forms import SHAPED, form_of
from pair2scene.assets.generators.shapes import ROD_SEGMENTS, ROUND_SEGMENTS, clip, slab
from pair2scene.assets.mesh import Part, box, box_between, cylinder, frustum, hull
from pair2scene.assets.registry import register
from pair2scene.scene.geometry import rot_z

TOP_SNAP_M = 0.05
"""A support height this close below the top is the top panel itself (issue's tolerance)."""
MAX_TOP_M = 0.045
"""Thickest top panel: stays under TOP_SNAP_M so the highest tier board never meets it."""
BOTTOM_SNAP_M = 0.12
"""A support height up to this far above the default bottom board becomes the bottom board
(the base shrinks or grows) instead of leaving a sliver bay just above it."""
MIN_BOARD_M = 0.004
"""Support heights below this rest on the box bottom itself; a thinner board is a sliver."""
TIER_GAP_M = (0.30, 0.40)
"""Range of the default spacing between tiers: one tier every 0.3-0.4 m."""
FILL_GAP_M = 0.6
"""A bookcase gap left taller than this by the support heights gets extra (unfitted) shelves:
a dataset bookcase with books on one shelf still has its other shelves."""
FRONT_GAP_M = 0.004
"""Reveal between neighbouring drawer fronts and doors."""

_Z_TO_Y = np.array([[1.0, 0.0, 0.0], [0.0, 0.0, 1.0], [0.0, -1.0, 0.0]])
"""Rotation taking +z to +y: a cylinder lying along y (knobs, dials)."""
_Z_TO_X = np.array([[0.0, 0.0, 1.0], [0.0, 1.0, 0.0], [-1.0, 0.0, 0.0]])
"""Rotation taking +z to +x: a cylinder lying along x (wheels)."""


# -- small helpers -----------------------------------------------------------------------
def _finish(parts: list[Part], height: float) -> list[Part]:
    """Move parts built with the box bottom at z = 0 to the box-centred frame."""
    shift = np.array([0.0, 0.0, -height / 2])
    return [Part(p.name, p.mesh.transformed(None, shift)) for p in parts]


def _strut(name: str, p0: Sequence[float], p1: Sequence[float], width: float, depth: float) -> Part:
    """A flat bar from p0 (3,) to p1 (3,) lying in an x-z plane: ``width`` across the bar in
    that plane, ``depth`` along y (a cross brace)."""
    p0, p1 = np.asarray(p0, dtype=float), np.asarray(p1, dtype=float)
    d = p1 - p0
    length = float(np.linalg.norm(d))
    u = d / length
    w = np.cross(u, (0.0, 1.0, 0.0))
    rotation = np.stack([u, (0.0, 1.0, 0.0), w], axis=1)
    return Part(name, box((p0 + p1) / 2, (length, depth, width), rotation))


def _knob(name: str, x: float, z: float, radius: float, y0: float, y1: float) -> Part:
    """A round knob standing on a front face at y0, reaching y1."""
    return Part(
        name,
        cylinder((x, (y0 + y1) / 2, z), radius, y1 - y0, segments=ROD_SEGMENTS, rotation=_Z_TO_Y),
    )


# -- tier levels (instance fitting) ------------------------------------------------------
@dataclass(frozen=True)
class _Level:
    """One horizontal board below the top panel."""

    top: float
    """Height of the board's upward face above the box bottom (m)."""
    thickness: float
    fitted: bool
    """True when it comes from a support height: something rests here, keep the bay open."""

    @property
    def bottom(self) -> float:
        return self.top - self.thickness


def _clean_heights(heights: Sequence[float], height: float, board: float) -> list[float]:
    """Support heights that need a board of their own, ascending: drops those on the box
    bottom, those that are the top panel, and those within a board thickness above a kept
    one (the lower one wins)."""
    out: list[float] = []
    for h in sorted(float(h) for h in heights):
        if h < MIN_BOARD_M or h > height - TOP_SNAP_M:
            continue
        if out and h - out[-1] < board:
            continue
        out.append(h)
    return out


def _levels(
    height: float,
    board: float,
    bottom_default: float,
    support_heights: Sequence[float] | None,
    rng: np.random.Generator,
    max_gaps: int = 12,
    min_gaps: int = 1,
) -> list[_Level]:
    """Board levels below the top panel, bottom board first.

    Without support heights the levels spread evenly from ``bottom_default`` (the bottom
    board's upward face) to the top, one gap every ``TIER_GAP_M`` (rng), clamped to
    [min_gaps, max_gaps] gaps (the top panel closes the last gap). With support heights the
    boards land exactly on them (see the module docstring); the lowest becomes the bottom
    board when it lies no more than ``BOTTOM_SNAP_M`` above ``bottom_default``.
    """
    # a squat unit keeps at least half its height above the default bottom board
    bottom_default = min(bottom_default, 0.5 * height)
    if support_heights is None:
        span = height - bottom_default
        n = int(np.clip(round(span / rng.uniform(*TIER_GAP_M)), min_gaps, max_gaps))
        tops = bottom_default + span * np.arange(n) / n
        return [_Level(float(z), min(board, float(z)), False) for z in tops]
    heights = _clean_heights(support_heights, height, board)
    if heights and heights[0] <= bottom_default + BOTTOM_SNAP_M:
        h0 = heights.pop(0)
        # a board that would leave a sliver under it reaches down to the box bottom instead
        levels = [_Level(h0, h0 if h0 - board < MIN_BOARD_M else board, True)]
    else:
        levels = [_Level(bottom_default, min(board, bottom_default), False)]
    return levels + [_Level(h, board, True) for h in heights]


def _fill_gaps(levels: list[_Level], height: float, board: float) -> list[_Level]:
    """``levels`` with evenly spaced extra boards in every gap taller than ``FILL_GAP_M``
    (between upward faces; the last gap ends at the top, ``height``)."""
    tops = [lv.top for lv in levels] + [height]
    out: list[_Level] = []
    for lv, hi in zip(levels, tops[1:]):
        out.append(lv)
        gap = hi - lv.top
        if gap > FILL_GAP_M:
            n = round(gap / np.mean(TIER_GAP_M))
            out += [_Level(lv.top + gap * k / n, board, False) for k in range(1, n)]
    return out


def _bays(levels: Sequence[_Level], ceiling: float) -> list[tuple[float, float, bool]]:
    """(floor, ceiling, open) of the space above each level: from its upward face to the next
    board's underside (the last to ``ceiling``, the top panel's underside)."""
    out = []
    for i, lv in enumerate(levels):
        hi = levels[i + 1].bottom if i + 1 < len(levels) else ceiling
        out.append((lv.top, hi, lv.fitted))
    return out


# -- fronts: drawers, doors, handles -----------------------------------------------------
@dataclass(frozen=True)
class _Front:
    """Depths of a carcass front (y, m): carcass face, front panels, handles."""

    y_carcass: float
    """Carcass front face; front panels start here."""
    y_face: float
    """Front panels' outer face; handles start here."""
    y_handle: float
    """Handles' outer end."""
    grip: float
    """Bar handle cross-section (m)."""

    @staticmethod
    def at(y_handle: float, depth: float) -> _Front:
        """Front of a body ``depth`` deep whose handles reach ``y_handle``."""
        # under 3 cm: a bar handle's top is no place to put anything
        handle = min(clip(0.045 * depth, 0.012, 0.025), 0.15 * depth)
        panel = min(clip(0.035 * depth, 0.01, 0.02), 0.1 * depth)
        return _Front(
            y_handle - handle - panel,
            y_handle - handle,
            y_handle,
            clip(0.5 * handle, 0.008, 0.014),
        )

    def panel(self, name: str, x0: float, x1: float, z0: float, z1: float) -> Part:
        """A front panel in the slot x0..x1, z0..z1, inset by half the reveal all round."""
        g = FRONT_GAP_M / 2
        return slab(name, (x0 + g, self.y_carcass, z0 + g), (x1 - g, self.y_face, z1 - g))

    def drawer(
        self, name: str, x0: float, x1: float, z0: float, z1: float, knobs: bool
    ) -> list[Part]:
        """A drawer front panel in its slot with its pull (see ``pull``)."""
        return [
            self.panel(f"{name}_front", x0, x1, z0, z1),
            *self.pull(name, x0, x1, z0, z1, knobs),
        ]

    def pull(
        self, name: str, x0: float, x1: float, z0: float, z1: float, knobs: bool
    ) -> list[Part]:
        """A centred bar handle, or one or two knobs, on the drawer face x0..x1, z0..z1."""
        parts: list[Part] = []
        w, h = x1 - x0, z1 - z0
        cx, cz = (x0 + x1) / 2, (z0 + z1) / 2
        if knobs:
            r = min(clip(0.1 * h, 0.008, 0.02), 0.2 * w)
            xs = [cx] if w < 0.5 else [x0 + w / 4, x1 - w / 4]
            parts += [
                _knob(f"{name}_knob_{i}", x, cz, r, self.y_face, self.y_handle)
                for i, x in enumerate(xs)
            ]
        else:
            half_len = min(clip(0.18 * w, 0.03, 0.15), 0.4 * w)
            half_t = min(self.grip, 0.4 * h) / 2
            parts.append(
                slab(
                    f"{name}_handle",
                    (cx - half_len, self.y_face, cz - half_t),
                    (cx + half_len, self.y_handle, cz + half_t),
                )
            )
        return parts

    def door(
        self,
        name: str,
        x0: float,
        x1: float,
        z0: float,
        z1: float,
        side: int,
        knob: bool,
        handle_z: float,
    ) -> list[Part]:
        """A door panel with a vertical bar or a knob near its opening edge (``side`` +1:
        right edge, -1: left), centred as near ``handle_z`` as the door allows."""
        parts = [self.panel(name, x0, x1, z0, z1)]
        w, h = x1 - x0, z1 - z0
        margin = min(clip(0.1 * w, 0.025, 0.05), 0.3 * w)
        x = x1 - margin if side > 0 else x0 + margin
        if knob:
            r = min(clip(0.04 * w, 0.01, 0.02), 0.15 * h)
            margin_z = min(0.08, 0.3 * h)
            z = clip(handle_z, z0 + margin_z, z1 - margin_z)
            parts.append(_knob(f"{name}_knob", x, z, r, self.y_face, self.y_handle))
        else:
            half_len = min(clip(0.12 * h, 0.04, 0.2), 0.35 * h)
            margin_z = min(0.05, 0.1 * h) + half_len
            z = clip(handle_z, z0 + margin_z, z1 - margin_z)
            half_t = min(self.grip, 0.3 * w) / 2
            parts.append(
                slab(
                    f"{name}_handle",
                    (x - half_t, self.y_face, z - half_len),
                    (x + half_t, self.y_handle, z + half_len),
                )
            )
        return parts


def _door_sides(n: int) -> list[int]:
    """Opening edge of each of n doors in a row: pairs open from their meeting edges; a lone
    last door opens on its left."""
    return [1 if n == 1 or (i % 2 == 0 and i + 1 < n) else -1 for i in range(n)]


def _splits(lo: float, hi: float, weights: Sequence[float]) -> list[float]:
    """Boundaries (len(weights) + 1,) dividing lo..hi in proportion to weights."""
    w = np.concatenate([[0.0], np.cumsum(weights)])
    return (lo + (hi - lo) * w / w[-1]).tolist()


def _door_row(
    front: _Front,
    prefix: str,
    x0: float,
    x1: float,
    z0: float,
    z1: float,
    n: int,
    knob: bool,
    handle_z: float,
) -> list[Part]:
    xs = _splits(x0, x1, [1.0] * n)
    parts: list[Part] = []
    for i, side in enumerate(_door_sides(n)):
        parts += front.door(f"{prefix}_{i}", xs[i], xs[i + 1], z0, z1, side, knob, handle_z)
    return parts


# -- carcass pieces ----------------------------------------------------------------------
def _tier_boards(
    levels: Sequence[_Level], x0: float, x1: float, y0: float, y1: float
) -> list[Part]:
    """One board per level ("tier_0" is the bottom board)."""
    return [slab(f"tier_{i}", (x0, y0, lv.bottom), (x1, y1, lv.top)) for i, lv in enumerate(levels)]


def _sides(
    x0: float, x1: float, t: float, y0: float, y1: float, z0: float, z1: float
) -> list[Part]:
    return [
        slab("side_left", (x0, y0, z0), (x0 + t, y1, z1)),
        slab("side_right", (x1 - t, y0, z0), (x1, y1, z1)),
    ]


def _corner_legs(
    x0: float, x1: float, y0: float, y1: float, z1: float, thick: float, taper: bool
) -> list[Part]:
    """Four legs from the floor to z1 under the corners of x0..x1, y0..y1: square, or round
    and tapered towards the floor."""
    parts = []
    r = thick / 2
    for i, (sx, sy) in enumerate([(-1, -1), (1, -1), (1, 1), (-1, 1)]):
        cx = x0 + r if sx < 0 else x1 - r
        cy = y0 + r if sy < 0 else y1 - r
        if taper:
            mesh = frustum((cx, cy, 0.0), z1, 0.6 * r, r, segments=ROUND_SEGMENTS)
        else:
            mesh = box_between((cx - r, cy - r, 0.0), (cx + r, cy + r, z1))
        parts.append(Part(f"leg_{i}", mesh))
    return parts


def _board_thickness(w: float, d: float, h: float) -> float:
    """Shelf board thickness: 15-30 mm, thinner for small or flat units."""
    return min(clip(0.05 * min(w, d), 0.012, 0.03), 0.1 * h)


# =======================================================================================
# tiered furniture
# =======================================================================================
@register("shelving_unit", variants=3, fits_support_heights=True)
def shelving_unit(
    size: np.ndarray, rng: np.random.Generator, style: int, support_heights: Sequence[float] | None
) -> list[Part]:
    """Bookcase: tiers between side panels, open at +y; closed back, open frame, or cubbies.

    Styles: 0 side panels, back panel and plinth; 1 open metal-look frame (corner posts,
    full boards, a cross brace at the back); 2 cube storage (side panels, vertical dividers
    in every tier, no back).
    """
    w, d, h = size
    t = _board_thickness(w, d, h) * rng.uniform(0.9, 1.1)
    top_t = min(clip(1.2 * t, 0.015, MAX_TOP_M), 0.1 * h)
    x0, x1, y0, y1 = -w / 2, w / 2, -d / 2, d / 2
    parts: list[Part] = []
    if style == 1:
        post = min(clip(0.06 * min(w, d), 0.02, 0.045), 0.25 * w, 0.25 * d)
        base = clip(0.06 * h, 0.03, 0.12) * rng.uniform(0.8, 1.2)
        levels = _fill_gaps(_levels(h, t, base + t, support_heights, rng), h, t)
        parts += _corner_legs(x0, x1, y0, y1, h, post, taper=False)
        parts += _tier_boards(levels, x0, x1, y0, y1)
        # a diagonal brace across the back, post centre to post centre, reads as "frame"
        yb = y0 + post / 2
        z_lo = max(levels[0].top, post)
        brace = min(0.6 * post, 0.02)
        if h - top_t - z_lo > 4 * brace:  # the square-cut ends stay inside the frame
            parts.append(
                _strut(
                    "brace",
                    (x0 + post / 2, yb, z_lo),
                    (x1 - post / 2, yb, h - top_t),
                    brace,
                    min(0.5 * post, 0.01),
                )
            )
        parts.append(slab("top", (x0, y0, h - top_t), (x1, y1, h)))
        return _finish(parts, h)

    back_t = clip(0.3 * t, 0.004, 0.01) if style == 0 else 0.0
    inset = clip(0.03 * d, 0.004, 0.02)
    plinth = clip(0.04 * h, 0.03, 0.08) * rng.uniform(0.8, 1.2) if style == 0 else 0.0
    levels = _fill_gaps(_levels(h, t, plinth + t, support_heights, rng), h, t)
    xi0, xi1 = x0 + t, x1 - t
    parts += _sides(x0, x1, t, y0, y1, 0.0, h - top_t)
    parts.append(slab("top", (x0, y0, h - top_t), (x1, y1, h)))
    parts += _tier_boards(levels, xi0, xi1, y0 + back_t, y1 - inset)
    if back_t > 0:
        parts.append(slab("back", (xi0, y0, 0.0), (xi1, y0 + back_t, h - top_t)))
    base = levels[0].bottom
    if base > MIN_BOARD_M:
        parts.append(slab("plinth", (xi0, y0 + back_t, 0.0), (xi1, y1 - inset - 0.01 * d, base)))
    if style == 2:
        bays = _bays(levels, h - top_t)
        cols = int(np.clip(round((w - 2 * t) / rng.uniform(*TIER_GAP_M)), 1, 6))
        cols = max(1, min(cols, 36 // len(bays) + 1))  # keeps the part count under 60
        xs = _splits(xi0, xi1, [1.0] * cols)
        for b, (z0, z1, _) in enumerate(bays):
            for c in range(1, cols):
                parts.append(
                    slab(
                        f"divider_{b}_{c}", (xs[c] - t / 2, y0, z0), (xs[c] + t / 2, y1 - inset, z1)
                    )
                )
    return _finish(parts, h)


@register("tv_stand", variants=3, fits_support_heights=True)
def tv_stand(
    size: np.ndarray, rng: np.random.Generator, style: int, support_heights: Sequence[float] | None
) -> list[Part]:
    """Low media unit: a top and 1-2 open tiers.

    Styles: 0 panel console (sides, back, open compartments); 1 leg frame with a lower
    shelf; 2 console on short legs with a drawer band under the top and an open shelf below.
    """
    w, d, h = size
    t = _board_thickness(w, d, h) * rng.uniform(0.9, 1.1)
    top_t = min(clip(1.3 * t, 0.018, MAX_TOP_M), 0.15 * h)
    x0, x1, y0, y1 = -w / 2, w / 2, -d / 2, d / 2
    parts: list[Part] = []
    if style == 1:
        leg = min(clip(0.07 * min(w, d), 0.025, 0.06), 0.3 * d)
        bottom = clip(0.25 * h, 0.06, 0.2) * rng.uniform(0.85, 1.15)
        levels = _levels(h, t, bottom, support_heights, rng, max_gaps=2)
        parts += _corner_legs(x0, x1, y0, y1, h - top_t, leg, taper=False)
        parts += _tier_boards(levels, x0, x1, y0, y1)
        parts.append(slab("top", (x0, y0, h - top_t), (x1, y1, h)))
        return _finish(parts, h)

    front = _Front.at(y1, d)
    back_t = clip(0.3 * t, 0.004, 0.01)
    # the open console runs to the box front; style 2's carcass stops behind its drawer fronts
    y_body = y1 if style == 0 else front.y_carcass
    base = clip(0.06 * h, 0.02, 0.06) if style == 0 else clip(0.2 * h, 0.05, 0.15)
    levels = _levels(h, t, base * rng.uniform(0.85, 1.15) + t, support_heights, rng, max_gaps=2)
    xi0, xi1 = x0 + t, x1 - t
    ceiling = h - top_t
    bays = _bays(levels, ceiling)
    z_side = 0.0 if style == 0 else levels[0].bottom
    parts += _sides(x0, x1, t, y0, y_body, z_side, ceiling)
    parts.append(slab("back", (xi0, y0, z_side), (xi1, y0 + back_t, ceiling)))
    parts += _tier_boards(levels, xi0, xi1, y0 + back_t, y_body)
    parts.append(slab("top", (x0, y0, ceiling), (x1, y1, h)))
    if style == 0:
        if levels[0].bottom > MIN_BOARD_M:
            parts.append(
                slab("plinth", (xi0, y0 + back_t, 0.0), (xi1, y_body - 0.02, levels[0].bottom))
            )
        # vertical dividers split a long console into compartments
        cols = int(np.clip(round(w / rng.uniform(0.5, 0.7)), 1, 4))
        xs = _splits(xi0, xi1, [1.0] * cols)
        for b, (z0, z1, _) in enumerate(bays):
            for c in range(1, cols):
                parts.append(
                    slab(
                        f"divider_{b}_{c}",
                        (xs[c] - t / 2, y0 + back_t, z0),
                        (xs[c] + t / 2, y_body, z1),
                    )
                )
        return _finish(parts, h)

    # style 2: short legs; a drawer band hangs under the top when the top bay is tall enough
    # to keep an open shelf below it
    leg = min(clip(0.05 * min(w, d), 0.02, 0.05), 0.3 * d)
    if levels[0].bottom > MIN_BOARD_M:
        parts += _corner_legs(
            x0 + t, x1 - t, y0, front.y_carcass, levels[0].bottom, leg, taper=True
        )
    z0, z1, _ = bays[-1]
    band = clip(0.3 * (h - levels[0].top), 0.08, 0.16)
    if z1 - z0 >= band + 0.1:
        parts.append(slab("drawer_body", (xi0, y0 + back_t, z1 - band), (xi1, front.y_carcass, z1)))
        cols = int(np.clip(round(w / 0.5), 1, 4))
        xs = _splits(x0, x1, [1.0] * cols)
        for c in range(cols):
            parts += front.drawer(f"drawer_{c}", xs[c], xs[c + 1], z1 - band, z1, knobs=False)
    return _finish(parts, h)


@register("cart", variants=2, fits_support_heights=True)
def cart(
    size: np.ndarray, rng: np.random.Generator, style: int, support_heights: Sequence[float] | None
) -> list[Part]:
    """Kitchen cart: 2-3 tiers on four legs with wheels.

    Styles: 0 metal utility cart (round posts, lipped lower trays, flat top); 1 wooden
    cart (square legs, flat boards, a towel-bar handle on the +x side).
    """
    w, d, h = size
    t = min(clip(0.04 * min(w, d), 0.012, 0.03), 0.08 * h)
    wheel_r = min(clip(0.04 * h, 0.02, 0.045), 0.2 * min(w, d)) * rng.uniform(0.9, 1.1)
    fork = clip(0.5 * wheel_r, 0.01, 0.02)
    bottom = 2 * wheel_r + fork + clip(0.1 * h, 0.04, 0.12) + t
    levels = _levels(h, t, bottom, support_heights, rng, max_gaps=2)
    levels.append(_Level(h, t, False))  # the top tier
    leg_z0 = 2 * wheel_r + fork
    if levels[0].bottom < leg_z0:
        # fitted bottom tier sits low: shrink the casters under it (never below 10 mm wheels)
        wheel_r = max(0.01, (levels[0].bottom - fork) / 2)
        leg_z0 = min(2 * wheel_r + fork, levels[0].bottom)

    x0, x1, y0, y1 = -w / 2, w / 2, -d / 2, d / 2
    handle = min(clip(0.1 * w, 0.04, 0.08), 0.25 * w) if style == 1 else 0.0
    xt1 = x1 - handle
    post = min(clip(0.05 * min(w, d), 0.02, 0.045), 0.2 * w, 0.2 * d)
    wheel_w = clip(0.6 * wheel_r, 0.012, 0.025)
    # legs sit far enough in that the wheels stay inside the box
    ix = max(post / 2, wheel_w / 2)
    iy = max(post / 2, wheel_r)
    corners = [(x0 + ix, y0 + iy), (xt1 - ix, y0 + iy), (xt1 - ix, y1 - iy), (x0 + ix, y1 - iy)]
    parts: list[Part] = []
    for i, (cx, cy) in enumerate(corners):
        if style == 0:
            leg = cylinder(
                (cx, cy, (leg_z0 + h) / 2), post / 2, h - leg_z0, segments=ROUND_SEGMENTS
            )
        else:
            leg = box_between(
                (cx - post / 2, cy - post / 2, leg_z0), (cx + post / 2, cy + post / 2, h)
            )
        parts.append(Part(f"leg_{i}", leg))
        parts.append(
            Part(
                f"wheel_{i}",
                cylinder(
                    (cx, cy, wheel_r), wheel_r, wheel_w, segments=ROUND_SEGMENTS, rotation=_Z_TO_X
                ),
            )
        )
        fw = min(post, 1.2 * wheel_w + 0.006) / 2
        parts.append(
            slab(
                f"caster_{i}",
                (cx - fw, cy - fw, wheel_r),
                (cx + fw, cy + fw, max(leg_z0, wheel_r + 1e-3)),
            )
        )
    for i, lv in enumerate(levels):
        name = "top" if i == len(levels) - 1 else f"tier_{i}"
        parts.append(slab(name, (x0, y0, lv.bottom), (xt1, y1, lv.top)))
        if style == 0 and i < len(levels) - 1:
            gap = levels[i + 1].bottom - lv.top
            lip = min(clip(0.12 * gap, 0.015, 0.05), 0.4 * gap)
            lw = min(0.6 * t, 0.012)
            z0, z1 = lv.top, lv.top + lip
            parts += [
                slab(f"tier_{i}_lip_front", (x0, y1 - lw, z0), (xt1, y1, z1)),
                slab(f"tier_{i}_lip_back", (x0, y0, z0), (xt1, y0 + lw, z1)),
                slab(f"tier_{i}_lip_left", (x0, y0 + lw, z0), (x0 + lw, y1 - lw, z1)),
                slab(f"tier_{i}_lip_right", (xt1 - lw, y0 + lw, z0), (xt1, y1 - lw, z1)),
            ]
    if style == 1:
        r = clip(0.3 * handle, 0.008, 0.016)
        zc = h - r
        arm = min(r, t / 2)
        for i, cy in enumerate((y0 + iy, y1 - iy)):
            parts.append(
                slab(f"handle_arm_{i}", (xt1, cy - arm, zc - arm), (x1 - r, cy + arm, zc + arm))
            )
        parts.append(
            Part(
                "handle",
                cylinder(
                    (x1 - r, 0.0, zc),
                    r,
                    y1 - y0 - 2 * iy + 2 * arm,
                    segments=ROUND_SEGMENTS,
                    rotation=_Z_TO_Y,
                ),
            )
        )
    return _finish(parts, h)


# =======================================================================================
# carcass furniture with fronts
# =======================================================================================
def _closed_carcass(
    parts: list[Part],
    levels: Sequence[_Level],
    ceiling: float,
    x0: float,
    x1: float,
    y0: float,
    front: _Front,
    side_t: float,
    back_t: float,
    z_side: float,
) -> list[tuple[float, float]]:
    """Sides, back, bottom and tier boards of a carcass; a solid body fills every bay that is
    not open (so nothing is placed behind closed fronts). Returns the front slots (z0, z1)
    of the closed bays, each covering its floor board's front edge."""
    yf = front.y_carcass
    parts += _sides(x0, x1, side_t, y0, yf, z_side, ceiling)
    parts.append(slab("back", (x0 + side_t, y0, z_side), (x1 - side_t, y0 + back_t, ceiling)))
    parts += _tier_boards(levels, x0 + side_t, x1 - side_t, y0 + back_t, yf)
    slots = []
    for i, (lv, (z0, z1, is_open)) in enumerate(zip(levels, _bays(levels, ceiling))):
        if is_open or z1 - z0 < 0.02:
            continue
        parts.append(slab(f"body_{i}", (x0 + side_t, y0 + back_t, z0), (x1 - side_t, yf, z1)))
        slots.append((lv.bottom, z1))
    return slots


def _top_front(front: _Front, has_fronts: bool) -> float:
    """Front edge of a dresser or cabinet top: a little past the fronts, or the box front
    when every bay is open (nothing else reaches it then)."""
    return front.y_face + 0.4 * (front.y_handle - front.y_face) if has_fronts else front.y_handle


def _base(
    parts: list[Part],
    style_legs: bool,
    x0: float,
    x1: float,
    y0: float,
    y1: float,
    z_top: float,
    recess: float,
    taper: bool = False,
) -> None:
    """Legs, or a plinth recessed ``recess`` behind y1, from the floor up to z_top."""
    if z_top <= MIN_BOARD_M:
        return
    if style_legs:
        leg = min(clip(0.05 * min(x1 - x0, y1 - y0), 0.025, 0.05), 0.25 * (y1 - y0))
        parts += _corner_legs(x0, x1, y0, y1, z_top, leg, taper=taper)
    else:
        parts.append(slab("plinth", (x0, y0, 0.0), (x1, y1 - recess, z_top)))


@register("dresser", variants=2, fits_support_heights=True)
def dresser(
    size: np.ndarray, rng: np.random.Generator, style: int, support_heights: Sequence[float] | None
) -> list[Part]:
    """Chest of drawers: a carcass with drawer fronts at +y and a top.

    Styles: 0 on a plinth, graduated full-width drawers (the top row split on wide chests),
    bar handles; 1 on tapered legs, drawers in two columns when wide, knobs.
    """
    w, d, h = size
    front = _Front.at(d / 2, d)
    t = _board_thickness(w, d, h)
    top_t = min(clip(0.035 * min(w, d) + 0.01, 0.018, MAX_TOP_M), 0.1 * h)
    overhang = clip(0.012 * w, 0.0, 0.015) * rng.uniform(0.5, 1.0)
    x0, x1, y0 = -w / 2 + overhang, w / 2 - overhang, -d / 2
    legs = style == 1
    base = clip(0.15 * h, 0.08, 0.2) if legs else clip(0.07 * h, 0.03, 0.09)
    base *= rng.uniform(0.85, 1.15)
    levels = _levels(h, t, base + t, support_heights, rng, max_gaps=1)
    ceiling = h - top_t
    parts: list[Part] = []
    slots = _closed_carcass(
        parts,
        levels,
        ceiling,
        x0,
        x1,
        y0,
        front,
        t,
        clip(0.3 * t, 0.004, 0.01),
        0.0 if not legs else levels[0].bottom,
    )
    _base(parts, legs, x0, x1, y0, front.y_carcass, levels[0].bottom, 0.02, taper=True)
    parts.append(slab("top", (-w / 2, y0, ceiling), (w / 2, _top_front(front, bool(slots)), h)))
    row_h = rng.uniform(0.17, 0.24)
    # legs style: a grid of drawer columns; plinth style: only a wide chest's top row splits
    max_cols = (3 if w > 1.6 else 2 if w > 1.0 else 1) if legs else (2 if w > 0.8 else 1)
    k = 0
    for z0, z1 in slots:
        rows = int(np.clip(round((z1 - z0) / row_h), 1, 6))
        rows = min(rows, 12 // max_cols)  # keeps the part count under 60
        weights = [1.0] * rows if legs else [1.0 + 0.12 * i for i in range(rows)]
        zs = _splits(z1, z0, weights)  # from the top down
        for r in range(rows):
            cols = max_cols if legs or r == 0 else 1
            xs = _splits(x0, x1, [1.0] * cols)
            for c in range(cols):
                parts += front.drawer(f"drawer_{k}", xs[c], xs[c + 1], zs[r + 1], zs[r], knobs=legs)
                k += 1
    return _finish(parts, h)


@register("cabinet", variants=2, fits_support_heights=True)
def cabinet(
    size: np.ndarray, rng: np.random.Generator, style: int, support_heights: Sequence[float] | None
) -> list[Part]:
    """Sideboard or cupboard: a top surface and doors at +y.

    Styles: 0 sideboard on legs, a row of doors with knobs; 1 cupboard on a plinth, a row
    of drawers above doors with bar handles.
    """
    w, d, h = size
    front = _Front.at(d / 2, d)
    t = _board_thickness(w, d, h)
    top_t = min(clip(0.035 * min(w, d) + 0.01, 0.018, MAX_TOP_M), 0.1 * h)
    overhang = clip(0.012 * w, 0.0, 0.015) * rng.uniform(0.5, 1.0)
    x0, x1, y0 = -w / 2 + overhang, w / 2 - overhang, -d / 2
    legs = style == 0
    base = clip(0.12 * h, 0.06, 0.2) if legs else clip(0.07 * h, 0.03, 0.1)
    base *= rng.uniform(0.85, 1.15)
    levels = _levels(h, t, base + t, support_heights, rng, max_gaps=1)
    ceiling = h - top_t
    parts: list[Part] = []
    slots = _closed_carcass(
        parts,
        levels,
        ceiling,
        x0,
        x1,
        y0,
        front,
        t,
        clip(0.3 * t, 0.004, 0.01),
        levels[0].bottom if legs else 0.0,
    )
    _base(parts, legs, x0, x1, y0, front.y_carcass, levels[0].bottom, 0.02)
    parts.append(slab("top", (-w / 2, y0, ceiling), (w / 2, _top_front(front, bool(slots)), h)))
    n_doors = int(np.clip(round((x1 - x0) / rng.uniform(0.4, 0.5)), 1, 6))
    for s, (z0, z1) in enumerate(slots):
        handle_z = 1.0 if z1 - z0 > 1.0 else z1  # tall doors: at hand height
        if not legs and z1 - z0 >= 0.45:
            band = clip(0.2 * (z1 - z0), 0.1, 0.18)
            xs = _splits(x0, x1, [1.0] * n_doors)
            for c in range(n_doors):
                parts += front.drawer(
                    f"drawer_{s}_{c}", xs[c], xs[c + 1], z1 - band, z1, knobs=False
                )
            z1 -= band
        parts += _door_row(
            front, f"door_{s}", x0, x1, z0, z1, n_doors, knob=legs, handle_z=handle_z
        )
    return _finish(parts, h)


C_SHARE = 26 / 88
"""Of the shaped counters, the share that are a C (a run along the back and one down each
side); the others are an L (the back and the right side, +x: where the training rooms'
objects stand on them)."""
RUN_DEPTH_M = (0.56, 0.64)
"""Depth of a shaped counter's runs (ProcTHOR's are 2 ft, 0.61 m)."""
SHAPED_COLUMNS = (3, 2)
"""At most this many columns of doors and drawers on a shaped counter's back run and on
each side run: a C stays under 60 parts."""


def _counter_block(
    size: np.ndarray, rng: np.random.Generator, style: int, support_heights: Sequence[float] | None
) -> list[Part]:
    """A counter of any size as one straight run: its top whole (the solid form)."""
    w, d, h = size
    return _finish(_counter_run(w, d, h, rng, style, support_heights), h)


@register("counter_top", variants=3, fits_support_heights=True, solid=_counter_block)
def counter_top(
    size: np.ndarray, rng: np.random.Generator, style: int, support_heights: Sequence[float] | None
) -> list[Part]:
    """Kitchen counter: a base cabinet on a recessed plinth (toe kick) under a top slab
    overhanging at +y; deeper and wider than
    :data:`~pair2scene.assets.forms.SHAPED_COUNTER_M`, an L (a run along
    the back and one down the right side, its doors facing in) or a C (and one down the
    left side too) of such runs, the open floor inside.

    Styles: 0 a drawer above a door in every column; 1 doors only; 2 drawer stacks
    alternating with door columns.
    """
    w, d, h = size
    if form_of("counter_top", size) != SHAPED:
        return _counter_block(size, rng, style, support_heights)
    legs = 2 if rng.random() < C_SHARE else 1
    run = min(rng.uniform(*RUN_DEPTH_M), 0.45 * d, 0.9 * w / (legs + 1))
    seed = int(rng.integers(2**32))  # every run built alike (top, kick, door widths)

    def built(width: float, prefix: str, cols: int, turn, shift) -> list[Part]:
        """A run ``width`` long, its parts named with ``prefix``, turned and moved into
        place."""
        parts = _counter_run(
            width, run, h, np.random.default_rng(seed), style, support_heights, cols
        )
        return [Part(prefix + p.name, p.mesh.transformed(turn, shift)) for p in parts]

    parts = built(w, "back_", SHAPED_COLUMNS[0], None, (0.0, (run - d) / 2, 0.0))
    for side in (1.0, -1.0)[:legs]:  # its front faces the inside, its back the side
        prefix = "right_" if side > 0 else "left_"
        # a side run: from the back run's front to the counter's front
        parts += built(d - run, prefix, SHAPED_COLUMNS[1], rot_z(side * np.pi / 2),
                       (side * (w - run) / 2, run / 2, 0.0))  # fmt: skip
    return _finish(parts, h)


def _counter_run(
    w: float,
    d: float,
    h: float,
    rng: np.random.Generator,
    style: int,
    support_heights: Sequence[float] | None,
    max_cols: int = 8,
) -> list[Part]:
    """One straight counter run, w by d by h, centred on the origin in x and y, its bottom
    at z = 0, its front at +y, with at most ``max_cols`` columns of doors and drawers."""
    top_t = min(clip(0.05 * d, 0.025, MAX_TOP_M), 0.1 * h) * rng.uniform(0.9, 1.1)
    # handles stop just short of the slab's front edge: the overhang protects them
    front = _Front.at(d / 2 - clip(0.01 * d, 0.003, 0.008), d)
    t = _board_thickness(w, d, h)
    x0, x1, y0 = -w / 2, w / 2, -d / 2
    kick = clip(0.11 * h, 0.04, 0.12) * rng.uniform(0.9, 1.1)
    levels = _levels(h, t, kick + t, support_heights, rng, max_gaps=1)
    ceiling = h - top_t
    parts: list[Part] = []
    slots = _closed_carcass(
        parts, levels, ceiling, x0, x1, y0, front, t, clip(0.3 * t, 0.004, 0.01), 0.0
    )
    recess = min(clip(0.1 * d, 0.03, 0.07), 0.3 * (front.y_carcass - y0))
    _base(parts, False, x0 + t, x1 - t, y0, front.y_carcass, levels[0].bottom, recess)
    parts.append(slab("top", (x0, y0, ceiling), (x1, d / 2, h)))
    cols = int(np.clip(round(w / rng.uniform(0.45, 0.6)), 1, max_cols))
    xs = _splits(x0, x1, [1.0] * cols)
    sides = _door_sides(cols)
    for s, (z0, z1) in enumerate(slots):
        band = clip(0.22 * (z1 - z0), 0.1, 0.18)
        for c in range(cols):
            name = f"{s}_{c}"
            stack = style == 2 and c % 2 == 0
            if stack and z1 - z0 >= 0.3:
                rows = int(np.clip(round((z1 - z0) / 0.22), 2, 4))
                zs = _splits(z1, z0, [1.0 + 0.15 * i for i in range(rows)])
                for r in range(rows):
                    parts += front.drawer(
                        f"drawer_{name}_{r}", xs[c], xs[c + 1], zs[r + 1], zs[r], knobs=False
                    )
                continue
            zd = z1
            if style == 0 and z1 - z0 >= band + 0.2:
                parts += front.drawer(
                    f"drawer_{name}", xs[c], xs[c + 1], z1 - band, z1, knobs=False
                )
                zd = z1 - band
            parts += front.door(
                f"door_{name}", xs[c], xs[c + 1], z0, zd, sides[c], knob=False, handle_z=zd
            )
    return parts


@register("wardrobe", variants=3)
def wardrobe(
    size: np.ndarray, rng: np.random.Generator, style: int, support_heights: Sequence[float] | None
) -> list[Part]:
    """Tall closet: doors at +y over a plinth, under a cornice.

    Styles: 0 hinged doors with long bar handles; 1 hinged doors above a row of drawers,
    knobs; 2 two sliding doors overlapping in the middle, with pull strips.
    """
    w, d, h = size
    front = _Front.at(d / 2, d)
    if style == 2:
        # two door planes: the rear door's panel sits a panel thickness further back
        panel = front.y_face - front.y_carcass
        front = _Front(front.y_carcass - panel, front.y_face, front.y_handle, front.grip)
    plinth = min(clip(0.05 * h, 0.04, 0.1), 0.1 * h) * rng.uniform(0.85, 1.15)
    cornice = min(clip(0.025 * h, 0.025, 0.06), 0.1 * h) * rng.uniform(0.85, 1.15)
    overhang = clip(0.01 * w, 0.005, 0.02)
    x0, x1, y0 = -w / 2 + overhang, w / 2 - overhang, -d / 2
    parts: list[Part] = [
        slab("plinth", (x0, y0, 0.0), (x1, front.y_carcass - 0.03, plinth)),
        slab("body", (x0, y0, plinth), (x1, front.y_carcass, h - cornice)),
        slab(
            "top",
            (-w / 2, y0, h - cornice),
            (w / 2, front.y_face + 0.3 * (d / 2 - front.y_face), h),
        ),
    ]
    z0, z1 = plinth, h - cornice
    if style == 2:
        panel = (front.y_face - front.y_carcass) / 2
        overlap = clip(0.04 * w, 0.03, 0.08)
        xm = (x0 + x1) / 2
        rear = _Front(front.y_carcass, front.y_carcass + panel, front.y_handle - panel, front.grip)
        fore = _Front(front.y_carcass + panel, front.y_face, front.y_handle, front.grip)
        parts += rear.door("door_0", x0, xm + overlap / 2, z0, z1, -1, False, 1.1)
        parts += fore.door("door_1", xm - overlap / 2, x1, z0, z1, 1, False, 1.1)
        return _finish(parts, h)
    n_doors = int(np.clip(round((x1 - x0) / rng.uniform(0.45, 0.6)), 1, 5))
    if style == 1:
        band = min(clip(0.14 * h, 0.15, 0.35), 0.3 * h)
        rows = 1 if band < 0.25 else 2
        zs = _splits(z0 + band, z0, [1.0] * rows)
        xs = _splits(x0, x1, [1.0] * min(n_doors, 2))
        for r in range(rows):
            for c in range(len(xs) - 1):
                parts += front.drawer(
                    f"drawer_{r}_{c}", xs[c], xs[c + 1], zs[r + 1], zs[r], knobs=True
                )
        z0 += band
    parts += _door_row(front, "door", x0, x1, z0, z1, n_doors, knob=style == 1, handle_z=1.05)
    return _finish(parts, h)


# =======================================================================================
# appliances and containers
# =======================================================================================
FRIDGE_SPLIT = {0: (0.66, 0.72), 1: (0.30, 0.36), 2: (0.42, 0.48)}
"""Where the doors split, as a share of the height above the kick (styles 0 and 1: the
freezer's floor) or of the width (style 2, side by side: the wall between them)."""


def _fridge_cabinet(
    x0: float,
    x1: float,
    y0: float,
    yf: float,
    h: float,
    kick: float,
    style: int,
    support_heights: Sequence[float] | None,
    rng: np.random.Generator,
) -> tuple[list[Part], float]:
    """The fridge's hollow cabinet, x0..x1, y0..yf (the doors' inner face), floor to h:
    a solid base up to the inner floor, side walls, back, roof, shelves and the freezer
    divider at the doors' split (``FRIDGE_SPLIT``: a shelf, or a wall for style 2).
    Returns the parts and the split (z, or x for style 2) for the doors."""
    w, dd = x1 - x0, yf - y0
    wall = min(clip(0.06 * min(w, dd), 0.025, 0.045), 0.2 * w, 0.2 * dd)
    floor = kick + wall
    roof = h - wall
    shelf = min(clip(0.015 * w, 0.006, 0.012), 0.05 * h)
    xi0, xi1, yi0 = x0 + wall, x1 - wall, y0 + wall
    parts = [
        slab("base", (x0, y0, 0.0), (x1, yf, floor)),
        *_sides(x0, x1, wall, y0, yf, floor, roof),
        slab("back", (xi0, y0, floor), (xi1, yi0, roof)),
        slab("roof", (x0, y0, roof), (x1, yf, h)),
    ]
    levels = _levels(roof + TOP_SNAP_M, shelf, floor, support_heights, rng, max_gaps=8)
    levels = _fill_gaps(levels, roof, shelf)
    boards = [lv for lv in levels if lv.top - lv.thickness >= floor - 1e-9 and lv.top < roof]
    lo, hi = FRIDGE_SPLIT[style]
    if style == 2:
        split = x0 + w * rng.uniform(lo, hi)
        parts.append(slab("divider", (split - wall / 4, yi0, floor), (split + wall / 4, yf, roof)))
    else:
        split = kick + (h - kick) * rng.uniform(lo, hi)
        # the freezer floor, unless a shelf lies near it (no sliver of a bay)
        if all(abs(lv.top - split) > 0.15 for lv in boards) and split + 0.15 < roof:
            boards.append(_Level(split, shelf, False))
    boards.sort(key=lambda lv: lv.top)
    parts += [
        slab(f"shelf_{i}", (xi0, yi0, lv.bottom), (xi1, yf, lv.top))
        for i, lv in enumerate(b for b in boards if b.top > floor + MIN_BOARD_M)
    ]
    return parts, split


@register("fridge", variants=3, fits_support_heights=True)
def fridge(
    size: np.ndarray, rng: np.random.Generator, style: int, support_heights: Sequence[float] | None
) -> list[Part]:
    """Refrigerator: an insulated cabinet with shelves inside, its door split at +y, bar
    handles.

    Styles: 0 freezer door on top; 1 freezer drawer at the bottom; 2 side-by-side doors
    with a dispenser panel.

    The cabinet is hollow behind the closed doors (walls, back, floor and roof are panels):
    the training rooms keep eggs, lettuce and milk inside their fridges (55 of the 67 eggs
    in the ProcTHOR-1k and AI2-THOR val kitchens), so the inside has shelves, fitted to the
    support heights when given (instance fitting, as a bookcase's tiers), else one every
    0.3-0.4 m. The freezer's floor is one more shelf where the doors split.
    """
    w, d, h = size
    handle = min(clip(0.04 * d, 0.02, 0.028), 0.15 * d)  # under 3 cm: no shelf on top
    door_t = min(clip(0.08 * d, 0.025, 0.07), 0.2 * d)
    y_handle = d / 2
    yf = y_handle - handle - door_t
    front = _Front(yf, y_handle - handle, y_handle, min(clip(0.04 * w, 0.018, 0.03), 0.2 * w))
    kick = min(clip(0.05 * h, 0.03, 0.09), 0.1 * h)
    x0, x1, y0 = -w / 2, w / 2, -d / 2
    parts: list[Part] = [
        slab(
            "grille",
            (x0 + 0.05 * w, yf - 0.01, 0.2 * kick),
            (x1 - 0.05 * w, yf + 0.5 * door_t, kick),
        ),
    ]
    cabinet, split = _fridge_cabinet(x0, x1, y0, yf, h, kick, style, support_heights, rng)
    parts += cabinet
    z0, z1 = kick, h
    gap = min(2 * FRONT_GAP_M, 0.02 * h)
    grip = front.grip

    def bar(name: str, x: float, za: float, zb: float) -> Part:
        return slab(name, (x - grip / 2, front.y_face, za), (x + grip / 2, y_handle, zb))

    if style == 2:
        xm = split
        parts += [
            front.panel("door_freezer", x0, xm, z0, z1),
            front.panel("door_fridge", xm, x1, z0, z1),
        ]
        hz0, hz1 = z0 + 0.3 * (z1 - z0), z0 + 0.75 * (z1 - z0)
        xin = min(0.04, 0.15 * (xm - x0))
        parts += [
            bar("handle_freezer", xm - xin, hz0, hz1),
            bar("handle_fridge", xm + xin, hz0, hz1),
        ]
        dz = z0 + 0.55 * (z1 - z0)
        dw = min(0.12, 0.25 * (xm - x0))
        parts.append(
            slab(
                "dispenser",
                ((x0 + xm) / 2 - dw, front.y_face, dz),
                ((x0 + xm) / 2 + dw, front.y_face + 0.4 * handle, dz + min(0.25, 0.15 * h)),
            )
        )
        return _finish(parts, h)
    parts += [
        front.panel("door_upper", x0, x1, split, z1),
        front.panel("door_lower", x0, x1, z0, split),
    ]
    xh = x0 + min(0.05, 0.15 * w)
    if style == 0:
        parts.append(bar("handle_upper", xh, split + gap, split + 0.5 * (z1 - split)))
        parts.append(bar("handle_lower", xh, split - min(0.45, 0.6 * (split - z0)), split - gap))
    else:
        parts.append(bar("handle_upper", xh, split + gap, split + min(0.5, 0.5 * (z1 - split))))
        hw = min(0.3 * w, 0.25)
        zt = split - min(clip(0.08 * (split - z0), 0.03, 0.08), 0.3 * (split - z0))
        gz = min(grip, 0.3 * (split - z0))
        parts.append(slab("handle_lower", (-hw, front.y_face, zt - gz), (hw, y_handle, zt)))
    return _finish(parts, h)


@register("safe", variants=2)
def safe(
    size: np.ndarray, rng: np.random.Generator, style: int, support_heights: Sequence[float] | None
) -> list[Part]:
    """Strongbox: a heavy body with a framed door at +y.

    Styles: 0 combination dial and spoked handle wheel, hinges on the left; 1 keypad and a
    lever handle, on four feet.
    """
    w, d, h = size
    hw = min(clip(0.08 * d, 0.02, 0.06), 0.2 * d)
    door_t = min(clip(0.05 * d, 0.012, 0.04), 0.1 * d)
    y_hw = d / 2
    yf = y_hw - hw - door_t
    yd = yf + door_t
    x0, x1, y0 = -w / 2, w / 2, -d / 2
    feet = clip(0.04 * h, 0.015, 0.04) if style == 1 else 0.0
    m = clip(0.08 * min(w, h), 0.015, 0.06) * rng.uniform(0.9, 1.1)
    parts: list[Part] = [slab("body", (x0, y0, feet), (x1, yf, h))]
    if feet:
        f = clip(0.1 * min(w, d), 0.02, 0.05)  # foot side
        ym = (yf + y0) / 2
        for i, (sx, sy) in enumerate([(-1, -1), (1, -1), (1, 1), (-1, 1)]):
            cx, cy = sx * (w / 2 - f), ym + sy * ((yf - y0) / 2 - f)
            parts.append(
                slab(f"foot_{i}", (cx - f / 2, cy - f / 2, 0.0), (cx + f / 2, cy + f / 2, feet))
            )
    dx0, dx1, dz0, dz1 = x0 + m, x1 - m, feet + m, h - m
    parts.append(slab("door", (dx0, yf, dz0), (dx1, yd, dz1)))
    dw, dh = dx1 - dx0, dz1 - dz0
    cx, cz = (dx0 + dx1) / 2, (dz0 + dz1) / 2
    s = min(dw, dh)
    if style == 0:
        r = 0.14 * s
        parts.append(
            Part(
                "dial",
                cylinder(
                    (cx - 0.15 * dw, (yd + y_hw) / 2, cz + 0.15 * dh),
                    r,
                    y_hw - yd,
                    segments=ROUND_SEGMENTS,
                    rotation=_Z_TO_Y,
                ),
            )
        )
        hub_x, hub_z = cx + 0.2 * dw, cz - 0.15 * dh
        hub_r = 0.04 * s
        parts.append(
            Part(
                "handle_hub",
                cylinder(
                    (hub_x, yd + 0.3 * hw, hub_z),
                    hub_r,
                    0.6 * hw,
                    segments=ROD_SEGMENTS,
                    rotation=_Z_TO_Y,
                ),
            )
        )
        for k in range(3):
            a = np.pi / 2 + 2 * np.pi * k / 3
            tip = (hub_x + 0.18 * s * np.cos(a), 0.0, hub_z + 0.18 * s * np.sin(a))
            spoke = _strut(f"handle_spoke_{k}", (hub_x, 0.0, hub_z), tip, 0.025 * s, 0.4 * hw)
            parts.append(Part(spoke.name, spoke.mesh.transformed(None, (0, y_hw - 0.2 * hw, 0))))
        hinge_r = min(0.5 * m, 0.02)
        for k, z in enumerate((dz0 + 0.2 * dh, dz1 - 0.2 * dh)):
            parts.append(
                Part(
                    f"hinge_{k}",
                    cylinder((dx0, yd - hinge_r, z), hinge_r, 0.12 * dh, segments=ROD_SEGMENTS),
                )
            )
    else:
        kw, kh = 0.2 * s, 0.26 * s
        kx, kz = cx + 0.2 * dw, cz + 0.15 * dh
        parts.append(
            slab(
                "keypad", (kx - kw / 2, yd, kz - kh / 2), (kx + kw / 2, yd + 0.35 * hw, kz + kh / 2)
            )
        )
        lever_z = cz - 0.15 * dh
        parts.append(
            Part(
                "handle_hub",
                cylinder(
                    (kx, yd + 0.5 * hw, lever_z),
                    0.05 * s,
                    hw,
                    segments=ROD_SEGMENTS,
                    rotation=_Z_TO_Y,
                ),
            )
        )
        grip = 0.035 * s
        parts.append(
            slab(
                "handle",
                (kx - 0.3 * s, y_hw - 0.4 * hw, lever_z - grip / 2),
                (kx, y_hw, lever_z + grip / 2),
            )
        )
    return _finish(parts, h)


@register("laundry_hamper", variants=2)
def laundry_hamper(
    size: np.ndarray, rng: np.random.Generator, style: int, support_heights: Sequence[float] | None
) -> list[Part]:
    """Laundry hamper.

    Styles: 0 round (elliptic) tapered basket with a lid and knob; 1 open rectangular
    basket with flared walls and side grips.
    """
    w, d, h = size
    if style == 0:
        lid = clip(0.05 * h, 0.015, 0.04)
        knob = clip(0.05 * h, 0.012, 0.035)
        zb = h - lid - knob
        taper = rng.uniform(0.78, 0.88)
        rt = np.array([0.96 * w / 2, 0.96 * d / 2])
        parts = [
            Part("body", frustum((0.0, 0.0, 0.0), zb, rt * taper, rt)),
            Part("lid", frustum((0.0, 0.0, zb), lid, (w / 2, d / 2), (0.97 * w / 2, 0.97 * d / 2))),
            Part(
                "knob",
                cylinder((0.0, 0.0, h - knob / 2), 0.12 * min(w, d), knob, segments=ROD_SEGMENTS),
            ),
            Part("rim", frustum((0.0, 0.0, zb - 0.04 * h), 0.04 * h, rt * 1.01, rt * 1.01)),
        ]
        return _finish(parts, h)
    grip = clip(0.05 * w, 0.015, 0.03)
    wall = clip(0.03 * min(w, d), 0.006, 0.015)
    tx, ty = w / 2 - grip, d / 2
    taper = rng.uniform(0.82, 0.9)
    bx, by = tx * taper, ty * taper
    parts = [slab("bottom", (-bx, -by, 0.0), (bx, by, wall))]
    for name, sy in (("wall_front", 1), ("wall_back", -1)):
        pts = [
            (sx * x, sy * (y - k), z)
            for sx in (-1, 1)
            for x, y, z in ((bx, by, 0.0), (tx, ty, h))
            for k in (0.0, wall)
        ]
        parts.append(Part(name, hull(pts)))
    for name, sx in (("wall_left", -1), ("wall_right", 1)):
        pts = [
            (sx * (x - k), sy * (y - wall), z)
            for sy in (-1, 1)
            for x, y, z in ((bx, by, 0.0), (tx, ty, h))
            for k in (0.0, wall)
        ]
        parts.append(Part(name, hull(pts)))
        gz = h - clip(0.12 * h, 0.03, 0.08)
        gw = clip(0.25 * d, 0.05, 0.12) / 2
        gh = clip(0.025 * h, 0.01, 0.02)
        xo = sx * tx
        parts.append(
            slab(
                f"grip_{'left' if sx < 0 else 'right'}",
                (min(xo, sx * w / 2), -gw, gz - gh),
                (max(xo, sx * w / 2), gw, gz + gh),
            )
        )
    return _finish(parts, h)


def _tapered_walls(
    rx_bottom: float,
    ry_bottom: float,
    rx_top: float,
    ry_top: float,
    height: float,
    wall: float,
    segments: int = ROUND_SEGMENTS,
) -> list[Part]:
    """Hollow tapered elliptic tube as ``segments`` convex wall pieces, outer radii given."""
    parts = []
    angles = np.linspace(0.0, 2 * np.pi, segments + 1)
    for k in range(segments):
        pts = []
        for a in angles[k : k + 2]:
            c, s = np.cos(a), np.sin(a)
            for rx, ry, z in ((rx_bottom, ry_bottom, 0.0), (rx_top, ry_top, height)):
                pts += [(rx * c, ry * s, z), ((rx - wall) * c, (ry - wall) * s, z)]
        parts.append(Part(f"wall_{k}", hull(pts)))
    return parts


@register("garbage_can", variants=3)
def garbage_can(
    size: np.ndarray, rng: np.random.Generator, style: int, support_heights: Sequence[float] | None
) -> list[Part]:
    """Waste bin, tapered towards the floor.

    Styles: 0 open round bin (hollow); 1 round pedal bin with a domed lid and a pedal at
    +y; 2 rectangular kitchen bin with a lid and a front grip.
    """
    w, d, h = size
    taper = rng.uniform(0.75, 0.85)
    if style == 0:
        wall = clip(0.03 * min(w, d), 0.004, 0.012)
        parts = _tapered_walls(taper * w / 2, taper * d / 2, w / 2, d / 2, h, wall)
        parts.append(
            Part(
                "bottom",
                frustum(
                    (0.0, 0.0, 0.0),
                    min(wall * 1.5, 0.1 * h),
                    (taper * w / 2 - wall, taper * d / 2 - wall),
                    (taper * w / 2 - wall, taper * d / 2 - wall),
                ),
            )
        )
        return _finish(parts, h)
    if style == 1:
        pedal = clip(0.12 * d, 0.02, 0.05)
        lid = clip(0.1 * h, 0.02, 0.06)
        ry = d / 2 - pedal / 2
        cy = -pedal / 2
        zb = h - lid
        top = np.array([w / 2, ry])
        parts = [
            Part("body", frustum((0.0, cy, 0.0), zb, top * max(taper, 0.85), top)),
            Part("lid", frustum((0.0, cy, zb), lid, top, 0.7 * top)),
            slab(
                "pedal",
                (-0.25 * w, cy + ry - pedal, 0.0),
                (0.25 * w, d / 2, clip(0.05 * h, 0.012, 0.03)),
            ),
        ]
        return _finish(parts, h)
    grip = clip(0.06 * d, 0.012, 0.025)
    lid = clip(0.08 * h, 0.02, 0.05)
    zb = h - lid
    ty = (d - grip) / 2
    cy = -grip / 2
    pts = [
        (sx * a, cy + sy * b, z)
        for sx in (-1, 1)
        for sy in (-1, 1)
        for a, b, z in ((taper * w / 2, taper * ty, 0.0), (w / 2, ty, zb))
    ]
    gw = clip(0.3 * w, 0.05, 0.15) / 2
    parts = [
        Part("body", hull(pts)),
        slab("lid", (-w / 2, cy - ty, zb), (w / 2, cy + ty, h)),
        slab("grip", (-gw, cy + ty, zb + 0.2 * lid), (gw, d / 2, h - 0.2 * lid)),
    ]
    return _finish(parts, h)


# =======================================================================================
# parts
# =======================================================================================
@register("drawer", variants=2)
def drawer(
    size: np.ndarray, rng: np.random.Generator, style: int, support_heights: Sequence[float] | None
) -> list[Part]:
    """A drawer: an open-topped box behind a larger front panel with a handle at +y.

    Styles: 0 bar handle; 1 one or two knobs.
    """
    w, d, h = size
    front = _Front.at(d / 2, d)
    overlay = min(clip(0.03 * w, 0.006, 0.02), 0.1 * w)
    lift = min(clip(0.08 * h, 0.004, 0.02), 0.15 * h)
    drop = min(clip(0.15 * h, 0.008, 0.03), 0.2 * h)
    wall = min(clip(0.03 * min(w, d), 0.006, 0.015), 0.1 * w)
    x0, x1 = -w / 2 + overlay, w / 2 - overlay
    y0, y1 = -d / 2, front.y_carcass
    z0, z1 = lift, h - drop * rng.uniform(0.8, 1.0)
    parts = [
        slab("bottom", (x0, y0, z0), (x1, y1, z0 + wall)),
        slab("side_left", (x0, y0, z0), (x0 + wall, y1, z1)),
        slab("side_right", (x1 - wall, y0, z0), (x1, y1, z1)),
        slab("back", (x0 + wall, y0, z0), (x1 - wall, y0 + wall, z1)),
    ]
    # the front panel fills the whole box face: the part is the drawer, not its slot
    parts.append(slab("front", (-w / 2, front.y_carcass, 0.0), (w / 2, front.y_face, h)))
    parts += front.pull("drawer", -w / 2, w / 2, 0.0, h, knobs=style == 1)
    return _finish(parts, h)


@register("cabinet_door", variants=2)
def cabinet_door(
    size: np.ndarray, rng: np.random.Generator, style: int, support_heights: Sequence[float] | None
) -> list[Part]:
    """A cabinet door: a panel whose +y face carries the handle (hinge side at -x).

    Styles: 0 flat slab with a vertical bar handle; 1 shaker door (frame around a recessed
    panel) with a knob.
    """
    w, d, h = size
    grip = clip(0.45 * d, 0.004, 0.03)
    y0, yf = -d / 2, d / 2 - grip
    margin = min(clip(0.1 * w, 0.02, 0.05), 0.25 * w)
    x = w / 2 - margin
    if style == 0:
        half_len = min(clip(0.15 * h, 0.04, 0.2), 0.4 * h)
        half_t = min(clip(0.02 * w, 0.005, 0.009), 0.2 * margin)
        zc = h / 2 + rng.uniform(-0.1, 0.1) * (h / 2 - half_len)
        return _finish(
            [
                slab("panel", (-w / 2, y0, 0.0), (w / 2, yf, h)),
                slab("handle", (x - half_t, yf, zc - half_len), (x + half_t, d / 2, zc + half_len)),
            ],
            h,
        )
    f = min(clip(0.12 * min(w, h), 0.02, 0.07), 0.3 * w, 0.3 * h) * rng.uniform(0.9, 1.1)
    recess = 0.4 * (yf - y0)
    x0, x1 = -w / 2, w / 2
    parts = [
        slab("stile_left", (x0, y0, 0.0), (x0 + f, yf, h)),
        slab("stile_right", (x1 - f, y0, 0.0), (x1, yf, h)),
        slab("rail_bottom", (x0 + f, y0, 0.0), (x1 - f, yf, f)),
        slab("rail_top", (x0 + f, y0, h - f), (x1 - f, yf, h)),
        slab("panel", (x0 + f, y0, f), (x1 - f, yf - recess, h - f)),
        _knob("knob", x1 - f / 2, h / 2, min(clip(0.05 * w, 0.008, 0.018), 0.45 * f), yf, d / 2),
    ]
    return _finish(parts, h)


@register("shelf", variants=2)
def shelf(
    size: np.ndarray, rng: np.random.Generator, style: int, support_heights: Sequence[float] | None
) -> list[Part]:
    """A shelf board: plain, or with a lip at its front and ends; brackets against the wall
    (-y) fill any height below the board.

    Styles: 0 plain board; 1 board with a lip.
    """
    w, d, h = size
    board = min(clip(0.06 * d, 0.012, 0.035), h)
    lip = 0.0
    if style == 1:
        if h < 1.8 * board:  # too flat for a lip above a full board: share the height
            board = 0.5 * h
        lip = min(clip(0.15 * d, 0.012, 0.04), h - board)
    z_board = h - lip  # the board's upward face
    x0, x1, y0, y1 = -w / 2, w / 2, -d / 2, d / 2
    parts = [slab("board", (x0, y0, z_board - board), (x1, y1, z_board))]
    if lip > 0:
        lw = min(clip(0.3 * board, 0.006, 0.012), 0.1 * d)
        parts += [
            slab("lip_front", (x0, y1 - lw, z_board), (x1, y1, h)),
            slab("lip_left", (x0, y0, z_board), (x0 + lw, y1 - lw, h)),
            slab("lip_right", (x1 - lw, y0, z_board), (x1, y1 - lw, h)),
        ]
    below = z_board - board
    if below > 1e-6:
        # triangular brackets: a vertical edge on the wall, a horizontal one under the board
        reach = min(0.75 * d, max(below, 0.3 * d))
        bt = min(clip(0.02 * w, 0.01, 0.02), 0.1 * w)
        inset = min(clip(0.15 * w, 0.03, 0.2), 0.4 * w) * rng.uniform(0.9, 1.0)
        for i, xc in enumerate((x0 + inset, x1 - inset)):
            pts = [
                (xc + sx * bt / 2, y, z)
                for sx in (-1, 1)
                for y, z in ((y0, 0.0), (y0, below), (y0 + reach, below))
            ]
            parts.append(Part(f"bracket_{i}", hull(pts)))
    return _finish(parts, h)

"""Objects mounted on walls: which wall, where on it, and what keeps them off doors,
windows and furniture.

A mounted object (a painting, a mirror, a TV on the wall, curtains) rests on ``wall`` in
its hierarchy; placement tries the room's walls in :func:`mount_order` and draws each
candidate from the layout model in that wall's frame (its support anchor, as the
training tuples have it). :func:`mount` then hangs the drawn box on the wall: turned to
face the room, its back :data:`MOUNT_GAP_M` off the wall, along the wall and in height
where the model put it, kept within the wall and under the ceiling; one the hierarchy
hangs over its anchor (:attr:`~pair2scene.hierarchy.tree.Hierarchy.over`) goes only on
the wall behind that anchor, moved along it to be over it (:func:`hang_over`); one it
hangs across from its anchor (:attr:`~pair2scene.hierarchy.tree.Hierarchy.across`, or
drawn so with the training pairs' share) tries the walls the anchor faces first, and on
them only where the anchor faces it.
:func:`mount_blocked` rejects what would cover a door or a window (curtains and blinds
excepted), hang behind a piece of furniture standing against the wall and reaching above
its bottom (a painting behind a wardrobe), or stand off the wall's ends; collisions with
furniture and the other mounted objects are tested like any candidate's.

A mounted object hangs at the heights its category hung at in the training rooms
(:class:`MountHeights`): the model draws a wall microwave, 10 of whose kind it saw, anywhere
from the floor to the ceiling, and a painting now and then against the ceiling, where the
real ones hang at 1.76 m (0.11 m spread) and 1.64 m (0.31 m); a candidate outside its
category's band is rejected (``off_height``).

Curtains and blinds (:data:`WINDOW_DRESSINGS`) hang at a window: the model knows no
windows, so they are placed by rule, centred on a window nobody dressed yet, hanging from
:data:`DRESSING_ABOVE_M` above its top (:func:`dress_window`). Where furniture stands
below the window or a door is close beside it, they are cut to what the window leaves
them (:func:`fitted_dressing`): ending above the sofa under the window, as sill-length
curtains do, and clear of the door's frame.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from pair2scene.assembly.walls import faced_by, weighted_keys
from pair2scene.curation.stats import CLOSE_WALL_M, HierarchyStats, mean_std
from pair2scene.scene.geometry import OrientedBox
from pair2scene.scene.model import WALL, Opening, Room
from pair2scene.scene.walls import AGAINST_GAP_M, Wall, wall_contact

MOUNT_GAP_M = 0.002
"""A mounted object's back is this far off its wall: touching it (the floating check
allows 1 cm), never through it."""
FLOOR_CLEARANCE_M = 0.05
"""A mounted object's bottom is at least this far above the floor."""
DOOR_MARGIN_M = 0.05
"""Wall kept free beside and above a door's frame."""
DRESSING_ABOVE_M = 0.12
"""Curtains and blinds hang from this far above their window's top (a rod, a cassette);
under the ceiling."""
SILL_COVER_M = 0.15
"""Curtains and blinds cut short above furniture still reach this close to their window's
sill: they cover the window (a sideboard taller than that leaves it undressed)."""
DRESSING_MIN_WIDTH_M = 0.3
"""Narrower than this, curtains cut to fit (:func:`fitted_dressing`) are not hung."""
DRESSING_GAP_M = 0.02
"""Wall left bare between the curtains of two windows of one wall (:func:`dressing_share`,
:func:`fitted_dressing`)."""
BEHIND_DEPTH_M = AGAINST_GAP_M + 0.15
"""A floor object whose back is this close to a wall stands against it: a mounted object
reaching below its top there would be hidden behind it."""
COVER_DEPTH_M = 0.6
"""How far in front of a wall object something stands and still covers it
(:func:`covered_share`): a vase on a sideboard against the wall does, a chair at a table
mid-room does not."""
MAX_COVER = 0.25
"""Most of a wall object's face that what stands in front of it may cover. Of the 1,564
wall objects (curtains and blinds left out) of the AI2-THOR and ProcTHOR-1k bedrooms,
living rooms and kitchens, train and val, 5 were covered more than a quarter
(``pair2scene evaluate``'s walls ``covered``)."""

HEIGHT_MIN_OBJECTS = 5
"""Categories mounted fewer times than this in the training rooms get no height band."""
HEIGHT_SPREAD = 2.0
"""A mounted object's centre may stand this many standard deviations from its category's
mean height..."""
HEIGHT_MARGIN_M = 0.15
"""... plus this margin (m). Of the 1,553 mounted objects of the training rooms, 11 fall
outside their own category's band (5 paintings, 3 televisions, 2 blinds, a towel
holder)."""


@dataclass(frozen=True)
class MountHeights:
    """The band of centre heights above the floor (m) per mounted category, from the
    training rooms (:attr:`~pair2scene.curation.stats.HierarchyStats.mount_height`):
    mean +- (:data:`HEIGHT_SPREAD` standard deviations + :data:`HEIGHT_MARGIN_M`)."""

    bands: dict[str, tuple[float, float]]

    @classmethod
    def from_stats(cls, stats: HierarchyStats) -> MountHeights:
        bands = {}
        for category, per_support in stats.mount_height.items():
            n, total, squares = per_support.get(WALL, (0.0, 0.0, 0.0))
            if n < HEIGHT_MIN_OBJECTS:
                continue
            mean, std = mean_std(n, total, squares)
            reach = HEIGHT_SPREAD * std + HEIGHT_MARGIN_M
            bands[category] = (mean - reach, mean + reach)
        return cls(bands)

    def off_height(self, category: str, box: OrientedBox) -> bool:
        """Whether ``box`` (mounted, of ``category``) hangs outside its category's band
        (False for a category without one)."""
        band = self.bands.get(category)
        return band is not None and not band[0] <= float(box.center[2]) <= band[1]


def wall_openings(wall: Wall, openings) -> list[tuple[float, float, float, float, int]]:
    """(along lo, along hi, z_min, z_max, index) of each of ``openings`` on ``wall``."""
    out = []
    for i, o in enumerate(openings):
        span = wall.span(o.p0, o.p1)
        if span is not None:
            out.append((span[0], span[1], float(o.z_min), float(o.z_max), i))
    return out


def mount_order(
    walls: list[Wall],
    rng: np.random.Generator,
    anchor: OrientedBox | None = None,
    only: int | None = None,
    across: bool = False,
    only_faced: bool = False,
) -> list[Wall]:
    """The walls to try for a mounted object, best first: ``only`` that wall (a hierarchy
    naming it); else, with a functional ``anchor`` (a floor object), the wall it stands
    against (a painting above the bed), then the walls it faces, then the rest; ``across``
    (the object hangs across the room from its anchor: a TV facing the sofa) the walls the
    anchor faces first, then the one it stands against, then the rest, and with
    ``only_faced`` (a hierarchy hanging it there) only the walls it faces, when it faces
    any. Without an anchor, every wall in a random order weighted by length (a long wall
    holds more)."""
    if only is not None:
        return [w for w in walls if w.index == only]
    keys = weighted_keys(rng, [max(w.length, 1e-3) for w in walls])
    order = [walls[i] for i in np.argsort(-keys, kind="stable")]
    if anchor is None:
        return order
    contact = wall_contact(anchor, walls)
    facing = {w.index: faced_by(w, anchor) for w in order}
    behind = [w for w in order if contact is not None and w.index == contact.wall]
    faced = [w for w in order if w not in behind and facing[w.index]]
    first = faced + behind if across else behind + faced
    out = first + [w for w in order if w not in behind and w not in faced]
    return ([w for w in out if facing[w.index]] or out) if only_faced else out


def hang(wall: Wall, along: float, z: float, size: np.ndarray) -> OrientedBox:
    """The box of ``size`` with its back against ``wall``, facing the room, its centre
    ``along`` the wall (from its midpoint) at height ``z``."""
    n = wall.normal
    yaw = float(np.arctan2(n[1], n[0])) - np.pi / 2  # local +y (the front) along n
    xy = wall.midpoint + wall.direction * along + n * (size[1] / 2 + MOUNT_GAP_M)
    return OrientedBox.from_yaw([*xy, z], size, yaw)


def mount(box: OrientedBox, wall: Wall, room_height: float, ceiling_margin: float):
    """A drawn candidate hung on ``wall`` (module docstring): None when the object is
    wider than the wall or taller than the room allows."""
    size = np.asarray(box.size, float)
    half_len = wall.length / 2 - size[0] / 2
    z_lo = FLOOR_CLEARANCE_M + size[2] / 2
    z_hi = room_height - ceiling_margin - size[2] / 2
    if half_len < 0 or z_hi < z_lo:
        return None
    along = float(np.clip(wall.local(box.center[:2])[0], -half_len, half_len))
    z = float(np.clip(box.center[2], z_lo, z_hi))
    return hang(wall, along, z, size)


def hang_over(box: OrientedBox, wall: Wall, anchor: OrientedBox) -> OrientedBox:
    """``box`` (hung on ``wall`` by :func:`mount`) moved along the wall to hang over
    ``anchor``, the floor object standing against it ("a painting above the sofa"): its
    centre as close to where it was drawn as keeps it within the anchor's extent along
    the wall (centred on the anchor when it is wider), and within the wall; its height as
    drawn."""
    size = np.asarray(box.size, float)
    lo, hi = wall.extent(anchor)
    slack = max((hi - lo) / 2 - size[0] / 2, 0.0)
    mid = (lo + hi) / 2
    at = float(np.clip(wall.local(box.center[:2])[0], mid - slack, mid + slack))
    half_len = max(wall.length / 2 - size[0] / 2, 0.0)
    return hang(wall, float(np.clip(at, -half_len, half_len)), float(box.center[2]), size)


def dress_window(
    window: Opening, wall: Wall, size: np.ndarray, room_height: float, ceiling_margin: float
) -> OrientedBox | None:
    """Curtains or blinds of ``size`` hung at ``window`` on ``wall``: centred on it, from
    :data:`DRESSING_ABOVE_M` above its top (under the ceiling); None when the window is
    not on that wall or the room is too low for them."""
    span = wall.span(window.p0, window.p1)
    if span is None:
        return None
    size = np.asarray(size, float)
    top = min(float(window.z_max) + DRESSING_ABOVE_M, room_height - ceiling_margin)
    z = top - size[2] / 2
    if z - size[2] / 2 < FLOOR_CLEARANCE_M - 1e-9:
        z = FLOOR_CLEARANCE_M + size[2] / 2
        if z + size[2] / 2 > room_height - ceiling_margin:
            return None
    half_len = max(wall.length / 2 - size[0] / 2, 0.0)
    along = float(np.clip((span[0] + span[1]) / 2, -half_len, half_len))
    return hang(wall, along, z, size)


def dressing_share(window: Opening, wall: Wall, room: Room) -> tuple[float, float]:
    """(lo, hi) along ``wall`` (from its midpoint) that the curtains or blinds of ``window``
    may cover: up to halfway to the next window on the wall either side, less half of
    :data:`DRESSING_GAP_M` (the whole wall without one), so each window of a wall keeps
    room for its own."""
    span = wall.span(window.p0, window.p1)
    lo, hi = -wall.length / 2, wall.length / 2
    if span is None:
        return lo, hi
    for other in room.windows:
        if other is window:
            continue
        theirs = wall.span(other.p0, other.p1)
        if theirs is None:
            continue
        if theirs[1] <= span[0]:
            lo = max(lo, (theirs[1] + span[0] + DRESSING_GAP_M) / 2)
        elif theirs[0] >= span[1]:
            hi = min(hi, (span[1] + theirs[0] - DRESSING_GAP_M) / 2)
    return lo, hi


def fitted_dressing(
    window: Opening,
    wall: Wall,
    box: OrientedBox,
    room: Room,
    floor_boxes: list[OrientedBox],
    hung: Sequence[OrientedBox] = (),
) -> OrientedBox | None:
    """``box`` (curtains or blinds :func:`dress_window` hung at ``window``) cut to what the
    window leaves them: its bottom above the furniture standing in front of it (at most
    :data:`SILL_COVER_M` above the sill), its sides within the wall's ends (the short wall
    of an L-shaped room) and the window's :func:`dressing_share` of the wall,
    :data:`DOOR_MARGIN_M` clear of a door beside the window and :data:`DRESSING_GAP_M`
    clear of the dressings ``hung`` beside it (still covering the window, at least
    :data:`DRESSING_MIN_WIDTH_M` wide).
    None when nothing needs cutting or no cut fits."""
    span = wall.span(window.p0, window.p1)
    if span is None:
        return None
    size = np.asarray(box.size, float)
    top = float(box.top)
    along = float(wall.local(box.center[:2])[0])
    lo = max(along - size[0] / 2, -wall.length / 2)
    hi = min(along + size[0] / 2, wall.length / 2)
    for a, b, _, z_max, _ in wall_openings(wall, room.doors):
        if box.bottom >= z_max + DOOR_MARGIN_M:
            continue
        if b + DOOR_MARGIN_M > lo and b <= span[0]:  # a door to the left of the window
            lo = b + DOOR_MARGIN_M + 1e-4
        if a - DOOR_MARGIN_M < hi and a >= span[1]:  # and to its right
            hi = a - DOOR_MARGIN_M - 1e-4
    share = dressing_share(window, wall, room)
    lo, hi = max(lo, share[0]), min(hi, share[1])
    for other in hung:
        a, b = wall.extent(other)
        near = wall.local(other.corners()[:, :2])[:, 1].min() < size[1] + DRESSING_GAP_M
        if not near or other.bottom >= top or other.top <= box.bottom:
            continue  # on another wall, or above or below it
        if b + DRESSING_GAP_M > lo and b <= span[0]:  # curtains at the window to the left
            lo = b + DRESSING_GAP_M
        if a - DRESSING_GAP_M < hi and a >= span[1]:  # and to the right
            hi = a - DRESSING_GAP_M
    if lo > span[0] + 1e-9 or hi < span[1] - 1e-9 or hi - lo < DRESSING_MIN_WIDTH_M:
        return None  # a door at the window's very edge: it cannot be covered
    bottom = float(box.bottom)
    depth = size[1] + 2 * MOUNT_GAP_M
    for f in floor_boxes:
        fc = wall.local(f.corners()[:, :2])
        if fc[:, 1].min() >= depth or fc[:, 0].max() <= lo or fc[:, 0].min() >= hi:
            continue
        bottom = max(bottom, float(f.top) + 2 * MOUNT_GAP_M)
    if bottom > float(box.bottom) + 1e-9 and bottom > float(window.z_min) + SILL_COVER_M:
        return None  # (raised by furniture: curtains short of a tall window may hang)
    if bottom <= box.bottom + 1e-9 and hi - lo >= size[0] - 1e-9:
        return None  # the full dressing: nothing to cut
    cut = np.array([hi - lo, size[1], top - bottom])
    return hang(wall, (lo + hi) / 2, (top + bottom) / 2, cut)


def covered_share(
    hung: OrientedBox, wall: Wall, other: OrientedBox, depth: float = COVER_DEPTH_M
) -> float:
    """Share of the face of ``hung`` (its extent along ``wall`` times its height) that
    ``other`` covers, seen from the room: 0 unless ``other`` stands within ``depth`` in
    front of that face."""
    return float(covered_shares(hung, wall, *outlines([other]), depth)[0])


def outlines(boxes: list[OrientedBox]) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """What :func:`covered_shares` takes of ``boxes``: their corners seen from above
    (M, 8, 2), their bottoms and tops (M,)."""
    corners = np.array([b.corners()[:, :2] for b in boxes]).reshape(-1, 8, 2)
    return corners, np.array([b.bottom for b in boxes]), np.array([b.top for b in boxes])


def covered_shares(
    hung: OrientedBox, wall: Wall, corners, bottoms, tops, depth: float = COVER_DEPTH_M
) -> np.ndarray:
    """:func:`covered_share` of many others at once, given by their :func:`outlines`;
    -> (M,)."""
    mine = wall.local(hung.corners()[:, :2])
    theirs = wall.local(np.asarray(corners, float))  # (M, K, 2)
    lo = np.maximum(mine[:, 0].min(), theirs[..., 0].min(-1))
    hi = np.minimum(mine[:, 0].max(), theirs[..., 0].max(-1))
    bottom = np.maximum(hung.bottom, np.asarray(bottoms, float))
    top = np.minimum(hung.top, np.asarray(tops, float))
    near = theirs[..., 1].min(-1) <= mine[:, 1].max() + depth
    face = max(float(np.ptp(mine[:, 0])) * (hung.top - hung.bottom), 1e-12)
    return np.where(near & (hi > lo) & (top > bottom), (hi - lo) * (top - bottom) / face, 0.0)


def crowds(box: OrientedBox, wall: Wall, shown: list[tuple[str, OrientedBox, Wall]]) -> bool:
    """Whether mounted ``box`` on ``wall`` comes within :data:`CLOSE_WALL_M` along the wall
    of another object hung on it (``shown``: (id, box, wall) of the mounted objects
    placed), or overlaps one along it (one above the other)."""
    lo, hi = wall.extent(box)
    for _, other, on in shown:
        if on.index == wall.index:
            a, b = wall.extent(other)
            if max(a - hi, lo - b) < CLOSE_WALL_M:
                return True
    return False


WINDOW_CLEAR_M = 0.05
"""Wall left between a window's frame and an object slid clear of it
(:func:`clear_of_windows`)."""


def clear_of_windows(box: OrientedBox, wall: Wall, room: Room) -> list[OrientedBox]:
    """``box`` (hung on ``wall``) slid along the wall just clear of the windows it covers,
    :data:`WINDOW_CLEAR_M` beside their frames: to the nearer side first, then the farther
    (a slide that lands on a second window goes on past it). Empty when it covers none;
    the slides may leave the wall (the caller's tests say so)."""
    spans = sorted(
        (a, b)
        for a, b, z_min, z_max, _ in wall_openings(wall, room.windows)
        if box.bottom < z_max and box.top > z_min
    )
    lo, hi = wall.extent(box)
    hit = [(a, b) for a, b in spans if hi > a and lo < b]
    if not hit:
        return []
    moves = []
    for side in (-1.0, 1.0):  # past the covered windows' left end, then their right end
        if side < 0:
            shift = hit[0][0] - WINDOW_CLEAR_M - hi
        else:
            shift = hit[-1][1] + WINDOW_CLEAR_M - lo
        for a, b in spans if side > 0 else spans[::-1]:  # and past any window it lands on
            if hi + shift > a - WINDOW_CLEAR_M and lo + shift < b + WINDOW_CLEAR_M:
                shift = (a - WINDOW_CLEAR_M - hi) if side < 0 else (b + WINDOW_CLEAR_M - lo)
        moves.append(shift)
    moves.sort(key=abs)
    along = np.array([*wall.direction, 0.0])
    return [OrientedBox(box.center + m * along, box.size, box.rotation) for m in moves]


def mount_blocked(
    box: OrientedBox, wall: Wall, room: Room, dressing: bool, floor_boxes: list[OrientedBox]
) -> str | None:
    """Why a hung candidate cannot stay (None: it can, as far as the wall goes):
    ``off_wall`` past the wall's ends, ``door`` over a door (or within
    :data:`DOOR_MARGIN_M` of its frame), ``window`` over a window, ``hidden`` behind
    furniture standing against the wall and reaching above its bottom. Curtains and
    blinds (``dressing``) are excepted from the last two: they hang at a window and down
    behind what stands below it."""
    lo, hi = wall.extent(box)
    if lo < -wall.length / 2 - 1e-6 or hi > wall.length / 2 + 1e-6:
        return "off_wall"
    bottom, top = box.bottom, box.top
    for a, b, _, z_max, _ in wall_openings(wall, room.doors):
        if hi > a - DOOR_MARGIN_M and lo < b + DOOR_MARGIN_M and bottom < z_max + DOOR_MARGIN_M:
            return "door"
    if dressing:
        return None
    for a, b, z_min, z_max, _ in wall_openings(wall, room.windows):
        if hi > a and lo < b and bottom < z_max and top > z_min:
            return "window"
    for f in floor_boxes:
        fc = wall.local(f.corners()[:, :2])
        if fc[:, 1].min() > BEHIND_DEPTH_M or f.top <= bottom:
            continue
        if fc[:, 0].max() > lo and fc[:, 0].min() < hi:
            return "hidden"
    return None

"""Rooms to generate into: floor shapes and sizes per room type from the training rooms,
a door, windows, a floor.

The hierarchy statistics of a room type keep every training room's floor polygon and
height (:attr:`~pair2scene.curation.stats.RoomTypeStats.floor_shapes`: rectangles, and
the L-, T- and U-shaped rooms that are a third of ProcTHOR's); :func:`make_room` draws
one large enough for the scene's furniture, turns it a random quarter turn, puts a door
on one of its walls and windows as the training rooms have them (:func:`draw_windows`:
how many, and each one's width, sill and top, drawn from the rooms' own; ProcTHOR-1k val:
1.0-1.4 windows a room). Without shapes (statistics written before they were kept, or
no statistics) the room is a rectangle of :class:`RoomTable`'s bounds (width, depth,
height) of the training rooms, from the support boxes of a 3D-Pairs folder's floor
tuples. The tables of the AI2-THOR + ProcTHOR-1k train rooms ship with the package
(``resources/stats.json``, ``resources/rooms.json``).
"""

from __future__ import annotations

import json
from collections import Counter
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from pair2scene.assembly.sizes import read_size_arrays
from pair2scene.assembly.walls import intervals_minus
from pair2scene.curation.stats import RoomTypeStats, draw_counted
from pair2scene.io.atomic import atomic_write_text
from pair2scene.scene.geometry import polygon_area
from pair2scene.scene.model import FLOOR, Opening, Room
from pair2scene.scene.walls import walls_of

ROOMS_FORMAT = "pair2scene.rooms"
ROOMS_VERSION = 1
DOOR_WIDTH_M = 0.9
DOOR_HEIGHT_M = 2.1
DOOR_CORNER_GAP_M = 0.2
"""A door's edge stays this far from the room's corners (a frame needs the wall)."""
WINDOW_CORNER_GAP_M = 0.3
"""A window's edge stays this far from the room's corners..."""
WINDOW_GAP_M = 0.3
"""... and from a door's or another window's edge."""
CEILING_GAP_M = 0.1
"""A window drawn taller than its room is moved down to end this far below the ceiling
(its sill no lower than the floor: a floor-to-ceiling window)."""
FALLBACK_SIZE = (4.0, 4.0, 2.7)
"""A room type nobody trained on, when the table is empty: a 4 m square room."""
MAX_FLOOR_SHARE = 0.4
"""Share of a room's floor its floor furniture's footprints may cover: rooms are drawn
among the training rooms large enough for the scene's furniture. In the AI2-THOR +
ProcTHOR-1k train rooms the share's 95th / 99th percentiles are 0.38 / 0.44 (bedrooms),
0.35 / 0.40 (living rooms), 0.37 / 0.46 (kitchens), 0.43 / 0.44 (bathrooms). Drawn
independently of the furniture, a third of generated bedrooms (40 seeds) came out above
0.4 and up to 0.72 (three beds in 19 m2): cramped, and those took most of placement's
resamples."""


@dataclass
class RoomTable:
    """Observed room bounds per room type."""

    sizes: dict[str, np.ndarray] = field(default_factory=dict)
    """room type -> (R, 3) (width, depth, height) in metres."""

    @classmethod
    def from_pairs(cls, data, split: str | None = "train") -> RoomTable:
        rows = data.support.id == FLOOR
        if split is not None:
            rows &= data.split == split
        seen: dict[str, dict[str, np.ndarray]] = {}
        for i in np.flatnonzero(rows):
            rtype, scene = str(data.room_type[i]), str(data.scene_id[i])
            seen.setdefault(rtype, {}).setdefault(
                scene, np.round(data.support.box[i, 3:6].astype(float), 2)
            )
        return cls({t: np.stack([s[k] for k in sorted(s)]) for t, s in sorted(seen.items())})

    def draw(self, room_type: str, rng: np.random.Generator, min_area: float = 0.0) -> np.ndarray:
        """(3,) bounds of a training room of ``room_type`` with at least ``min_area`` m2
        of floor (the largest when none has). A composed type's
        (:mod:`pair2scene.hierarchy.room_types`: an office) is one of its base types'
        rooms, each type drawn with its weight in the recipe; any type's when unseen."""
        from pair2scene.hierarchy.room_types import composed_types

        options = self.sizes.get(room_type)
        weights = None
        if options is None or not len(options):
            recipe = composed_types().get(room_type)
            bases = [(self.sizes[b], w) for b, w in (recipe.bases if recipe else ())
                     if len(self.sizes.get(b, ()))]  # fmt: skip
            every = [s for s in self.sizes.values() if len(s)]
            if bases:
                options = np.concatenate([s for s, _ in bases])
                weights = np.concatenate([np.full(len(s), w / len(s)) for s, w in bases])
            elif every:
                options = np.concatenate(every)
            else:
                return np.asarray(FALLBACK_SIZE, dtype=float)
        area = options[:, 0] * options[:, 1]
        if not (area >= min_area).any():
            return options[int(np.argmax(area))].astype(float)
        large = area >= min_area
        options = options[large]
        if weights is None:
            return options[int(rng.integers(len(options)))].astype(float)
        p = weights[large] / weights[large].sum()
        return options[int(rng.choice(len(options), p=p))].astype(float)

    def save(self, path: str | Path) -> None:
        doc = {
            "format": ROOMS_FORMAT,
            "version": ROOMS_VERSION,
            "sizes": {t: s.tolist() for t, s in self.sizes.items()},
        }
        atomic_write_text(Path(path), json.dumps(doc, separators=(",", ":")) + "\n")

    @classmethod
    def load(cls, path: str | Path | None = None) -> RoomTable:
        """A table written by :meth:`save` (None: the bundled one)."""
        return cls(read_size_arrays("rooms", path, "room table"))


def make_room(
    room_type: str,
    rng: np.random.Generator,
    table: RoomTable | None = None,
    furniture_m2: float = 0.0,
    stats: RoomTypeStats | None = None,
    min_windows: int = 0,
    max_windows: int | None = None,
    sized: bool = True,
) -> Room:
    """A room of a training room's shape and height (:func:`draw_floor`; a rectangle of
    ``table``'s sizes when ``stats`` has no shapes), with room for ``furniture_m2`` of
    floor furniture footprint (:data:`MAX_FLOOR_SHARE`) and sized for it as the training
    rooms were (:meth:`RoomTypeStats.share_normal`), one door on a random wall long
    enough for it and the windows of :func:`draw_windows` (none without ``stats``); the
    floor's bounds start at the origin. The windows are drawn after the rest, so a room's
    shape and door do not depend on them; ``min_windows``: at least that many (one for
    each curtains or blinds the room is to hold), as far as its walls have room;
    ``max_windows``: at most that many (a text's "curtains on the windows": no window
    left bare). ``sized`` False: any training room large enough, by count alone, as for a
    text request, whose named objects must all be placed: sized for its furniture, issue
    19's "a living room with a sofa, a painting above the sofa and curtains on the
    windows" lost a curtain in 5 of seeds 0-39 (two windows on one wall, a door or the
    short wall of an L-shaped room beside a window; curtains are cut to fit since:
    :func:`~pair2scene.assembly.mounting.fitted_dressing`) and still loses its painting
    in 2 (the windows take the sofa's wall); drawn by count, none."""
    min_area = furniture_m2 / MAX_FLOOR_SHARE
    if stats is not None and stats.floor_shapes:
        polygon, h = draw_floor(stats.floor_shapes, rng, min_area, furniture_m2,
                                stats.share_normal() if sized else None)  # fmt: skip
    else:
        table = RoomTable.load() if table is None else table
        w, d, h = table.draw(room_type, rng, min_area)
        polygon = np.array([[0.0, 0.0], [w, 0.0], [w, d], [0.0, d]])
    n = len(polygon)
    lengths = np.linalg.norm(np.roll(polygon, -1, axis=0) - polygon, axis=1)
    fits = np.flatnonzero(lengths >= DOOR_WIDTH_M + 2 * DOOR_CORNER_GAP_M)
    # a rectangle's door wall is one of its four, as before shapes were kept
    wall = int(rng.integers(n)) if n == 4 or not len(fits) else int(fits[rng.integers(len(fits))])
    a, b = polygon[wall], polygon[(wall + 1) % n]
    length = float(np.linalg.norm(b - a))
    doors: tuple[Opening, ...] = ()
    if length >= DOOR_WIDTH_M + 2 * DOOR_CORNER_GAP_M:
        room_left = length - DOOR_WIDTH_M - 2 * DOOR_CORNER_GAP_M
        start = DOOR_CORNER_GAP_M + float(rng.uniform(0, room_left))
        u = (b - a) / length
        p0, p1 = a + u * start, a + u * (start + DOOR_WIDTH_M)
        ends = (float(p0[0]), float(p0[1])), (float(p1[0]), float(p1[1]))
        doors = (Opening("door", *ends, 0.0, min(DOOR_HEIGHT_M, float(h)), "door_0"),)
    windows = ()
    if stats is not None:
        windows = draw_windows(polygon, float(h), doors, stats.window_counts,
                               stats.window_shapes, rng, min_windows, max_windows)  # fmt: skip
    return Room(room_type, polygon, float(h), doors, windows)


def draw_floor(
    shapes: Counter[tuple[float, ...]],
    rng: np.random.Generator,
    min_area: float = 0.0,
    furniture_m2: float = 0.0,
    share: tuple[float, float] | None = None,
) -> tuple[np.ndarray, float]:
    """(floor polygon (N, 2) counter-clockwise, height) of a training room drawn from
    ``shapes`` (:attr:`~pair2scene.curation.stats.RoomTypeStats.floor_shapes`) among
    those with at least ``min_area`` m2 of floor (the largest when none has), turned a
    random quarter turn, its bounds starting at the origin.

    Each shape is weighted by how many rooms had it and, given ``share`` (mean and
    standard deviation of the training rooms' log furniture share) and ``furniture_m2``,
    by the normal density of the log share the furniture would cover in it: a bed and a
    nightstand get a bedroom of the size such a bedroom had, not any bedroom at least
    2.5x their footprint (drawn by count alone, 11 % of fit bedrooms and 28 % of fit
    kitchens came out under 0.12 of their floor covered, against 4 % and 9 % of the
    training rooms)."""
    keys = sorted(shapes)
    polys = [np.asarray(k[1:], float).reshape(-1, 2) for k in keys]
    area = np.array([polygon_area(p) for p in polys])
    large = np.flatnonzero(area >= min_area)
    if not len(large):
        i = int(np.argmax(area))
    else:
        p = np.array([shapes[keys[j]] for j in large], float)
        if share is not None and furniture_m2 > 0:
            log_density = -0.5 * ((np.log(furniture_m2 / area[large]) - share[0]) / share[1]) ** 2
            p *= np.exp(log_density - log_density.max())
        i = int(large[rng.choice(len(large), p=p / p.sum())])
    turn = int(rng.integers(4))
    c, s = np.round(np.cos(turn * np.pi / 2)), np.round(np.sin(turn * np.pi / 2))
    poly = polys[i] @ np.array([[c, s], [-s, c]])
    return poly - poly.min(axis=0), float(keys[i][0])


def draw_windows(
    polygon: np.ndarray,
    height: float,
    doors: tuple[Opening, ...],
    counts: Counter[int],
    shapes: Counter[tuple[float, float, float]],
    rng: np.random.Generator,
    at_least: int = 0,
    at_most: int | None = None,
) -> tuple[Opening, ...]:
    """Windows for a room: their number drawn from ``counts`` (windows a room -> rooms),
    each one's (width, sill, top) from ``shapes``, on a wall with a free stretch that wide
    (:data:`WINDOW_CORNER_GAP_M` from the corners, :data:`WINDOW_GAP_M` from doors and the
    other windows), the wall weighted by its free length and the window uniform along
    the stretch; at least ``at_least`` of them and at most ``at_most``. A window with no
    wall left for it is not placed."""
    if not counts or not shapes:
        return ()
    walls = walls_of(np.asarray(polygon, float))
    taken: list[list[tuple[float, float]]] = [[] for _ in walls]  # (lo, hi) from the midpoint
    for door in doors:
        for i, wall in enumerate(walls):
            span = wall.span(door.p0, door.p1)
            if span is not None:
                taken[i].append(span)
    out: list[Opening] = []
    n = max(int(draw_counted(counts, rng)), at_least)
    for k in range(n if at_most is None else min(n, at_most)):
        width, sill, top = draw_counted(shapes, rng)
        if top > height - CEILING_GAP_M:  # a taller room's window: moved down
            sill, top = max(sill - (top - (height - CEILING_GAP_M)), 0.0), height - CEILING_GAP_M
        if top <= sill:
            continue
        free = []
        for i, wall in enumerate(walls):
            half = wall.length / 2 - WINDOW_CORNER_GAP_M
            stretches = [(-half, half)] if half > 0 else []
            for lo, hi in taken[i]:
                stretches = intervals_minus(stretches, lo - WINDOW_GAP_M, hi + WINDOW_GAP_M)
            free += [(i, a, b) for a, b in stretches if b - a >= width]
        if not free:
            continue
        spare = np.array([b - a - width for _, a, b in free]) + 1e-6
        i, a, b = free[int(rng.choice(len(free), p=spare / spare.sum()))]
        start = float(rng.uniform(a, b - width))
        wall = walls[i]
        p0 = wall.midpoint + wall.direction * start
        p1 = wall.midpoint + wall.direction * (start + width)
        taken[i].append((start, start + width))
        ends = (float(p0[0]), float(p0[1])), (float(p1[0]), float(p1[1]))
        out.append(Opening("window", *ends, float(sill), float(top), f"window_{k}"))
    return tuple(out)

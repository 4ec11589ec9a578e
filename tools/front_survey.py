"""Where each category's front points, measured from the corpora, and the fix.

pair2scene's convention: an object's local +y is its front (the side it faces).
The Unity adapters map Unity's local forward (+z) to our +y, which is right for
most AI2-THOR assets but not all. This module measures, per source and
category, where the front really points with independent cues that need no
knowledge of the asset:

- ``wall``: furniture standing with a side within :data:`WALL_CONTACT_M` of a
  wall has its back against it, so its front is the wall's inward normal;
- ``partner``: a chair faces the table it stands at, a desk faces its chair,
  a sofa its coffee table (the nearest partner within :data:`PARTNER_GAP_M`);
- ``faces``: a sofa or armchair faces the room's TV, a TV faces the sofa;
- ``support``: a TV or laptop faces the way the furniture it stands on faces,
  and ``carries``: a TV stand faces the way its TV faces;
- ``drawers``: a dresser's drawers (AI2-THOR's parts) sit at its front;
- ``pillows``: a bed's pillows lie at its head, so its front points away from them.

Each cue gives a direction in the floor plane per object. The object's local
frame, turned by each of the four yaw offsets (0, 90, 180, 270 degrees about
local z), puts its +y within 45 degrees of exactly one offset's direction: the
counts of these offsets over a (source, category, cue) are the measurement
(:func:`observe`, :func:`measure`). Corrections are fitted from them
(:func:`suggest_offsets`) into ``FRONT_YAW_OFFSET_DEG`` (per category) and
``FRONT_YAW_OFFSET_BY_ASSET_DEG`` (per asset, where an asset is modelled
unlike its category); the adapters apply them once, through ``turn_front``
(both live in ``pair2scene.data.orientation``, the run-time half).
``python tools/front_survey.py`` prints the figures, checks the tables
against the data and writes ``docs/front_convention.md``.
"""

from __future__ import annotations

import argparse
import re
import sys
from collections import Counter, defaultdict
from collections.abc import Iterable, Sequence
from dataclasses import dataclass
from enum import Enum
from pathlib import Path

import numpy as np

from pair2scene.categories import SuperCategory
from pair2scene.data.orientation import (
    FRONT_YAW_OFFSET_BY_ASSET_DEG,
    FRONT_YAW_OFFSET_DEG,
    OFFSETS_DEG,
    front_offset_deg,
    turn_front,
)
from pair2scene.scene.geometry import OrientedBox
from pair2scene.scene.model import FLOOR, Scene, SceneObject

# -- cue geometry -----------------------------------------------------------------------------

UPRIGHT_TOL_DEG = 20.0
"""Only objects whose local z is within this of world up have a yaw to measure
(a book lying on its side does not)."""
WALL_CONTACT_M = 0.3
"""An object whose footprint comes this close to a wall stands against it."""
WALL_OVERLAP_M = 0.1
"""... provided its footprint runs along the wall segment for at least this much."""
SQUARE_TOL_DEG = 20.0
"""The wall cue needs the box square to the wall: an angled box has no face against it."""
PARALLEL_COS = 0.9
"""Two walls whose normals differ by more than ~25 degrees meet at a corner."""
CORNER_M = 0.6
"""An object also within this of a second, crossing wall stands in a corner:
which of the two walls its back is against is unknown, so it gives no cue."""
PARTNER_GAP_M = 0.5
"""A chair belongs to the table whose footprint is at most this far from its own."""
MIN_DIRECTION_M = 0.05
"""A cue direction shorter than this (pillows at the bed's centre) says nothing."""
ITHOR_WALL_BAND_M = (-0.3, 0.6)
"""iTHOR floors extend ~0.3 m under the walls, so walls are taken at the objects'
extent; a side of the extent farther than this band from the floor's edge has
no object against its wall (a doorway, an open side) and gives no wall."""
ITHOR_ROOM = re.compile(r"ai2thor/FloorPlan\d+")
"""iTHOR rooms; RoboTHOR apartments have inner walls that no floor polygon shows."""


def front_quadrant(rotation: np.ndarray, direction: np.ndarray) -> int:
    """Index into :data:`OFFSETS_DEG` of the yaw offset whose turned +y lies within
    45 degrees of ``direction``.

    rotation : (3, 3) the object's frame; direction : (2,) world xy.
    """
    return int(np.round(_local_angle_deg(rotation, direction) / 90.0)) % 4


def _local_angle_deg(rotation: np.ndarray, direction: np.ndarray) -> float:
    """Angle of ``direction`` (2,) from local +y, counter-clockwise about local z."""
    r = np.asarray(rotation, dtype=float)
    d = np.asarray(direction, dtype=float)
    return float(np.degrees(np.arctan2(-(r[:2, 0] @ d), r[:2, 1] @ d)))


def square_error_deg(rotation: np.ndarray, direction: np.ndarray) -> float:
    """How far (degrees) ``direction`` (2,) is from the nearest local axis of ``rotation``."""
    a = _local_angle_deg(rotation, direction)
    return abs(a - 90.0 * np.round(a / 90.0))


def is_upright(box: OrientedBox) -> bool:
    return bool(box.rotation[2, 2] >= np.cos(np.radians(UPRIGHT_TOL_DEG)))


def footprint(box: OrientedBox) -> np.ndarray:
    """(4, 2) xy corners of an upright box's bottom face."""
    return box.corners()[:4, :2]


def _plan_axes(box: OrientedBox) -> tuple[np.ndarray, np.ndarray]:
    """Unit (2,) directions of the box's local x and y in the floor plane."""
    ax, ay = box.rotation[:2, 0], box.rotation[:2, 1]
    return ax / np.linalg.norm(ax), ay / np.linalg.norm(ay)


def reach(box: OrientedBox, direction: np.ndarray) -> float:
    """How far an upright box's footprint extends from its centre along ``direction`` (2,)."""
    ax, ay = _plan_axes(box)
    h = box.half_size[:2]
    return float(abs(direction @ ax) * h[0] + abs(direction @ ay) * h[1])


def toward_box(point: np.ndarray, box: OrientedBox) -> tuple[np.ndarray, float]:
    """Unit direction (2,) from ``point`` (2,) to the nearest point of ``box``'s
    footprint, and the distance (negative inside: then the direction points
    inward across the nearest edge, as for a chair tucked under a table)."""
    ax, ay = _plan_axes(box)
    h = box.half_size[:2]
    q = np.asarray(point, dtype=float) - box.center[:2]
    u = np.array([q @ ax, q @ ay])
    if np.all(np.abs(u) <= h):
        margin = h - np.abs(u)
        i = int(np.argmin(margin))
        local = np.zeros(2)
        local[i] = -1.0 if u[i] >= 0 else 1.0
        return local[0] * ax + local[1] * ay, -float(margin[i])
    v = np.clip(u, -h, h) - u
    dist = float(np.linalg.norm(v))
    return (v[0] * ax + v[1] * ay) / dist, dist


@dataclass(frozen=True)
class Wall:
    """A wall seen from above: a segment with the room on its left."""

    start: np.ndarray
    """(2,) first end point."""
    tangent: np.ndarray
    """(2,) unit direction along the wall."""
    length: float
    normal: np.ndarray
    """(2,) unit normal pointing into the room."""


def polygon_walls(polygon: np.ndarray) -> list[Wall]:
    """The walls of a counter-clockwise floor polygon (N, 2)."""
    p = np.asarray(polygon, dtype=float)
    walls = []
    for a, b in zip(p, np.roll(p, -1, axis=0)):
        t = b - a
        length = float(np.linalg.norm(t))
        if length > 1e-6:
            t = t / length
            walls.append(Wall(a, t, length, np.array([-t[1], t[0]])))
    return walls


def room_walls(scene: Scene) -> list[Wall]:
    """The walls of a scene's room, where they are known.

    ProcTHOR floor polygons are the rooms' inner wall faces. AI2-THOR's iTHOR
    floor rectangles run under the walls, so each side is pulled in to the
    extent of the objects and windows when that lies within
    :data:`ITHOR_WALL_BAND_M` of it, and dropped otherwise. RoboTHOR apartments
    have none (their floor is only the objects' extent around several rooms).
    """
    if scene.source != "ai2thor":
        return polygon_walls(scene.room.floor_polygon)
    if not ITHOR_ROOM.fullmatch(scene.id) or not scene.objects:
        return []
    poly = scene.room.floor_polygon
    lo, hi = poly.min(0), poly.max(0)
    pts = [footprint(o.box) for o in scene.objects]
    pts += [np.array([w.p0, w.p1]) for w in scene.room.windows]
    elo, ehi = np.concatenate(pts).min(0), np.concatenate(pts).max(0)
    rect = np.array([[elo[0], elo[1]], [ehi[0], elo[1]], [ehi[0], ehi[1]], [elo[0], ehi[1]]])
    # polygon_walls(rect) runs along y = elo, x = ehi, y = ehi, x = elo
    inset = (elo[1] - lo[1], hi[0] - ehi[0], hi[1] - ehi[1], elo[0] - lo[0])
    low, high = ITHOR_WALL_BAND_M
    return [w for w, d in zip(polygon_walls(rect), inset) if low <= d <= high]


def wall_gap(box: OrientedBox, wall: Wall) -> float | None:
    """Distance from an upright box's footprint to ``wall`` (negative when it pokes
    through), or None when the footprint does not run along the segment."""
    return _footprint_gap(footprint(box), wall)


def _footprint_gap(corners: np.ndarray, wall: Wall) -> float | None:
    """:func:`wall_gap` of a footprint given by its (4, 2) corners."""
    c = corners - wall.start
    u = c @ wall.tangent
    if min(u.max(), wall.length) - max(u.min(), 0.0) < WALL_OVERLAP_M:
        return None
    return float((c @ wall.normal).min())


# -- cues -------------------------------------------------------------------------------------


class Cue(str, Enum):
    WALL = "wall"
    """Back against the nearest wall: the front is the wall's inward normal."""
    PARTNER = "partner"
    """Faces the nearby object it is used with (a chair its table)."""
    FACES = "faces"
    """Faces a partner across the room (a sofa the TV)."""
    SUPPORT = "support"
    """Faces the way the furniture it stands on faces (a TV on a TV stand)."""
    DRAWERS = "drawers"
    """Drawers and doors open at the front: it points from the centre to them."""
    CARRIES = "carries"
    """Faces the way the TV standing on it faces (a TV stand)."""
    PILLOWS = "pillows"
    """Pillows lie at a bed's head: the front points away from them."""


# Which categories each cue speaks for: what the object is for, not what the
# data shows. Others are measured by the wall cue too (the survey) but have no
# front to check: round tables, plants, bowls...
WALL_BACKED = frozenset(
    {
        "bed", "dresser", "wardrobe", "tv_stand", "shelving_unit", "desk", "fridge",
        "counter_top", "sink", "toilet", "painting", "mirror", "television", "sofa",
        "armchair", "side_table", "cabinet", "microwave", "coffee_machine", "toaster",
    }
)  # fmt: skip
"""Categories that stand or hang with their back to a wall."""
PARTNERS: dict[str, tuple[str, ...]] = {
    "chair": ("dining_table", "desk", "counter_top"),
    "stool": ("counter_top", "dining_table", "desk"),
    "desk": ("chair",),
    "sofa": ("coffee_table",),
    "armchair": ("coffee_table",),
}
"""category -> what it faces at close range (the nearest within PARTNER_GAP_M)."""
FACES: dict[str, tuple[str, ...]] = {
    "sofa": ("television",),
    "armchair": ("television",),
    "television": ("sofa",),
}
"""category -> what it faces across the room (the nearest one)."""
SUPPORT_FOLLOWERS = frozenset({"television", "laptop", "monitor", "desktop_computer"})
"""Categories that face the way their support faces."""
FRONTED_SUPPORTS = frozenset(
    {"tv_stand", "desk", "dresser", "side_table", "counter_top", "shelving_unit", "cabinet"}
)
"""Supports with a front of their own (a dining table has none)."""
DRAWER_HOSTS = frozenset({"dresser", "side_table", "cabinet", "tv_stand"})
"""Categories whose drawers and doors sit at the front (a desk's sit in side pedestals)."""
FRONT_PARTS = frozenset({"drawer", "cabinet_door"})
DRAWER_OFFSET = 0.2
"""The parts' centroid must sit at least this fraction of the half-size off
centre along one axis to show a side (drawers filling a whole cube do not)."""
CARRIERS: dict[str, tuple[str, ...]] = {"tv_stand": ("television",)}
"""category -> what stands on it facing the same way (the support cue reversed)."""
PILLOW_HOSTS = frozenset({"bed"})
"""Categories whose pillows mark their back."""


@dataclass(frozen=True)
class Observation:
    """One cue's verdict on one object."""

    source: str
    scene_id: str
    object_id: str
    category: str
    asset_id: str | None
    cue: Cue
    direction: np.ndarray
    """(2,) unit world xy direction the object's front should point."""
    quadrant: int
    """Index into OFFSETS_DEG of the yaw offset that would make +y point that way."""


_SURVEYED = frozenset(
    {SuperCategory.LARGE_FURNITURE, SuperCategory.FIXTURE, SuperCategory.WALL_OBJECT,
     SuperCategory.SMALL_OBJECT}
)  # fmt: skip
"""Super-categories the survey runs the wall cue on (not parts of furniture)."""

_DECLARED: dict[Cue, frozenset[str]] = {
    Cue.WALL: WALL_BACKED,
    Cue.PARTNER: frozenset(PARTNERS),
    Cue.FACES: frozenset(FACES),
    Cue.SUPPORT: SUPPORT_FOLLOWERS,
    Cue.DRAWERS: DRAWER_HOSTS,
    Cue.CARRIES: frozenset(CARRIERS),
    Cue.PILLOWS: PILLOW_HOSTS,
}


def wall_direction(box: OrientedBox, walls: Sequence[Wall]) -> np.ndarray | None:
    """(2,) inward normal of the wall ``box`` stands against, or None when it
    stands against none, in a corner (two walls: which is its back is unknown)
    or at an angle to it."""
    near = []
    corners = footprint(box)
    for w in walls:
        g = _footprint_gap(corners, w)
        if g is not None and g <= CORNER_M:
            near.append((g, w))
    if not near:
        return None
    near.sort(key=lambda gw: gw[0])
    gap, nearest = near[0]
    normal = nearest.normal
    if gap > WALL_CONTACT_M or any(abs(w.normal @ normal) < PARALLEL_COS for _, w in near[1:]):
        return None
    if square_error_deg(box.rotation, normal) > SQUARE_TOL_DEG:
        return None
    return normal


def partner_direction(obj: SceneObject, candidates: Iterable[SceneObject]) -> np.ndarray | None:
    """(2,) direction from ``obj`` toward the nearest candidate, when their
    footprints are within PARTNER_GAP_M; else None.

    The direction is the normal of the larger one's edge facing the smaller
    one: from a chair to the table edge it stands at, or out of a desk's edge
    toward its chair (not toward the chair's centre, which may sit off to the
    desk's side).
    """
    best: tuple[np.ndarray, float] | None = None
    for x in candidates:
        if x.id == obj.id or not is_upright(x.box):
            continue
        small, large, sign = (obj, x, 1.0) if _area(obj) <= _area(x) else (x, obj, -1.0)
        d, dist = toward_box(small.box.center[:2], large.box)
        gap = dist - reach(small.box, d)
        if best is None or gap < best[1]:
            best = (sign * d, gap)
    return best[0] if best is not None and best[1] <= PARTNER_GAP_M else None


def _area(obj: SceneObject) -> float:
    return float(obj.box.size[0] * obj.box.size[1])


def faces_direction(obj: SceneObject, candidates: Iterable[SceneObject]) -> np.ndarray | None:
    """(2,) direction from ``obj``'s centre to the nearest candidate's centre."""
    best: np.ndarray | None = None
    for x in candidates:
        d = x.box.center[:2] - obj.box.center[:2]
        if x.id != obj.id and (best is None or np.linalg.norm(d) < np.linalg.norm(best)):
            best = d
    if best is None or np.linalg.norm(best) < MIN_DIRECTION_M:
        return None
    return best / np.linalg.norm(best)


def pillows_direction(host: SceneObject, pillows: Sequence[SceneObject]) -> np.ndarray | None:
    """(2,) direction from the centroid of the pillows resting on ``host`` to its centre."""
    if not pillows:
        return None
    d = host.box.center[:2] - np.mean([p.box.center[:2] for p in pillows], axis=0)
    n = np.linalg.norm(d)
    return d / n if n >= MIN_DIRECTION_M else None


def _has_asset(obj: SceneObject) -> bool:
    return obj.asset is not None and obj.asset.id is not None


def front_direction(obj: SceneObject, source: str, raw: bool = False) -> np.ndarray:
    """(2,) unit world xy direction of ``obj``'s front; for a ``raw`` (uncorrected)
    object, of its front as the correction tables would turn it."""
    box = obj.box
    if raw:
        box = turn_front(
            box, front_offset_deg(source, obj.category, obj.asset.id if obj.asset else None)
        )
    ay = box.rotation[:2, 1]
    return ay / np.linalg.norm(ay)


def drawers_direction(host: SceneObject, parts: Sequence[SceneObject]) -> np.ndarray | None:
    """(2,) direction from ``host``'s centre to the side its parts sit at, when
    their centroid lies clearly off centre along one local horizontal axis."""
    if not parts:
        return None
    local = host.box.to_local(np.array([p.box.center for p in parts])).mean(axis=0)
    rel = local[:2] / np.maximum(host.box.half_size[:2], 1e-9)
    i = int(np.argmax(np.abs(rel)))
    if abs(rel[i]) < DRAWER_OFFSET:
        return None
    d = host.box.rotation[:2, i] * np.sign(rel[i])
    return d / np.linalg.norm(d)


def observe(scene: Scene, survey: bool = False, raw: bool = False) -> list[Observation]:
    """Every cue's verdict on every upright object of ``scene``.

    survey : also apply the wall cue to categories it does not speak for.
    raw : the scene was loaded without the front correction: the support and
    carries cues then read the partner's front through the correction tables,
    so that a TV is judged against its stand's true front, not its raw frame.
    """
    objs = scene.by_id()
    walls = room_walls(scene)
    by_cat: dict[str, list[SceneObject]] = defaultdict(list)
    for o in scene.objects:
        by_cat[o.category].append(o)
    out: list[Observation] = []

    def add(o: SceneObject, cue: Cue, d: np.ndarray | None) -> None:
        if d is None:
            return
        out.append(
            Observation(
                scene.source or "",
                scene.id,
                o.id,
                o.category,
                o.asset.id if o.asset else None,
                cue,
                d,
                front_quadrant(o.box.rotation, d),
            )
        )

    for o in scene.objects:
        if not is_upright(o.box):
            continue
        cat = o.category
        if walls and (cat in WALL_BACKED or (survey and o.super in _SURVEYED)):
            add(o, Cue.WALL, wall_direction(o.box, walls))
        if cat in PARTNERS:
            cands = [x for c in PARTNERS[cat] for x in by_cat[c]]
            add(o, Cue.PARTNER, partner_direction(o, cands))
        if cat in FACES:
            add(o, Cue.FACES, faces_direction(o, [x for c in FACES[cat] for x in by_cat[c]]))
        sup = objs.get(o.support) if o.support not in (None, FLOOR) else None
        # a support's frame only means something when it is a known asset's: the
        # frames of AI2-THOR's built-in fixtures point anywhere
        if sup is not None and is_upright(sup.box) and _has_asset(sup) and _has_asset(o):
            if cat in SUPPORT_FOLLOWERS and sup.category in FRONTED_SUPPORTS:
                add(o, Cue.SUPPORT, front_direction(sup, scene.source or "", raw))
            if cat in CARRIERS.get(sup.category, ()):
                add(sup, Cue.CARRIES, front_direction(o, scene.source or "", raw))
        if cat in DRAWER_HOSTS:
            parts = [p for c in FRONT_PARTS for p in by_cat[c] if p.part_of == o.id]
            add(o, Cue.DRAWERS, drawers_direction(o, parts))
        if cat in PILLOW_HOSTS:
            add(
                o,
                Cue.PILLOWS,
                pillows_direction(o, [p for p in by_cat["pillow"] if p.support == o.id]),
            )
    return out


def observe_all(
    scenes: Iterable[Scene], survey: bool = False, raw: bool = False
) -> list[Observation]:
    """:func:`observe` over many scenes."""
    return [ob for s in scenes for ob in observe(s, survey=survey, raw=raw)]


# -- measurement ------------------------------------------------------------------------------

MIN_SAMPLES = 10
"""A (source, category, cue) with fewer readings is reported, not checked, and
does not vote for corrections."""
AGREEMENT_BAR = 0.8
"""After correction, every checked (source, category, cue) agrees at least this often."""

_OFF_AXIS = "the partner across the room is often off to one side (misses: 90 degrees, not 180)"
_RANDOM_YAW = "ProcTHOR turns small objects on their support at random"
_STOOL = "stools are nearly symmetric: people sit at them from any side"
UNRELIABLE_CUES: dict[tuple[str, str, Cue], str] = {
    ("ai2thor", "armchair", Cue.FACES): _OFF_AXIS,
    ("ai2thor", "sofa", Cue.FACES): _OFF_AXIS,
    ("ai2thor", "television", Cue.FACES): _OFF_AXIS,
    ("procthor", "armchair", Cue.FACES): _OFF_AXIS,
    ("procthor", "sofa", Cue.FACES): _OFF_AXIS,
    ("procthor", "television", Cue.FACES): _OFF_AXIS,
    ("procthor", "sofa", Cue.WALL): (
        "ProcTHOR turns sofas to face the TV stand, often with an arm against a wall"
    ),
    ("procthor", "bed", Cue.PILLOWS): "ProcTHOR scatters pillows over the whole bed",
    ("procthor", "laptop", Cue.SUPPORT): _RANDOM_YAW,
    ("procthor", "microwave", Cue.WALL): _RANDOM_YAW,
    ("procthor", "toaster", Cue.WALL): _RANDOM_YAW,
    ("procthor", "coffee_machine", Cue.WALL): _RANDOM_YAW,
    ("ai2thor", "stool", Cue.PARTNER): _STOOL,
    ("procthor", "stool", Cue.PARTNER): _STOOL,
    ("ai2thor", "shelving_unit", Cue.WALL): (
        "open shelving units look the same from both sides: one asset stands at 0 and 180"
    ),
}
"""(source, category, cue) -> why that cue says nothing about that category's
front. Such rows are reported, neither checked nor voting; the ``same asset``
column of the report (how often one asset agrees with itself) backs each reason."""

BELOW_BAR: dict[tuple[str, str, Cue], str] = {
    ("ai2thor", "bed", Cue.PILLOWS): (
        "iTHOR's Bed_4, Bed_5, Bed_6 and Bed_18_2 keep their headboard at -y, on one reading"
        " each (too few to turn an asset), and RoboTHOR lays the pillows at the foot of 7 of"
        " its 37 beds (one asset either way)"
    ),
    ("ai2thor", "side_table", Cue.WALL): (
        "side tables stand side-on to a wall (beside a bed or sofa) as often as back to"
        " it; the drawer cue puts every keyed side table at 0"
    ),
    ("ai2thor", "laptop", Cue.SUPPORT): (
        "laptops stand turned on desks and dressers: the misses spread over 90, 180 and 270"
    ),
}
"""(source, category, cue) -> why a cue that does speak for the category (it
votes) still stays under AGREEMENT_BAR after the correction: the test exempts
exactly these rows."""


@dataclass(frozen=True)
class Agreement:
    """How one cue judges one category of one source: a count per yaw offset."""

    source: str
    category: str
    cue: Cue
    counts: tuple[int, int, int, int]
    """Readings that put the front at each offset of OFFSETS_DEG."""
    keyed: bool = True
    """False for objects without an asset id (AI2-THOR parts, built-in fixtures,
    RoboTHOR prefabs): the tables cannot address them one by one."""

    @property
    def n(self) -> int:
        return sum(self.counts)

    def fraction(self, offset_deg: int = 0) -> float:
        """Share of readings that put the front at ``offset_deg``; 0 without readings."""
        return self.counts[OFFSETS_DEG.index(offset_deg)] / self.n if self.n else 0.0

    @property
    def best_offset_deg(self) -> int:
        return OFFSETS_DEG[int(np.argmax(self.counts))]

    @property
    def key(self) -> tuple[str, str, Cue]:
        return self.source, self.category, self.cue

    @property
    def status(self) -> str:
        """``checked``, or why not: ``survey`` (the cue does not speak for the
        category), ``no asset id``, ``unreliable``, ``too few``, ``below bar``."""
        if self.category not in _DECLARED[self.cue]:
            return "survey"
        if not self.keyed:
            return "no asset id"
        if self.key in UNRELIABLE_CUES:
            return "unreliable"
        if self.n < MIN_SAMPLES:
            return "too few"
        if self.key in BELOW_BAR:
            return "below bar"
        return "checked"


def measure(observations: Iterable[Observation]) -> list[Agreement]:
    """Readings grouped by (source, category, cue, has an asset id), sorted."""
    counts: dict[tuple[str, str, Cue, bool], list[int]] = defaultdict(lambda: [0, 0, 0, 0])
    for ob in observations:
        counts[(ob.source, ob.category, ob.cue, ob.asset_id is not None)][ob.quadrant] += 1
    return [
        Agreement(src, cat, cue, (c[0], c[1], c[2], c[3]), keyed)
        for (src, cat, cue, keyed), c in sorted(
            counts.items(), key=lambda kv: (kv[0][0], not kv[0][3], kv[0][1], kv[0][2].value)
        )
    ]


def self_consistency(observations: Iterable[Observation]) -> dict[tuple, tuple[float, int]]:
    """How often an asset's readings agree with that asset's most common one.

    Per (source, category, cue) over assets with at least two readings:
    (share, number of readings). A reliable cue on consistently modelled assets
    scores near 1 whatever the correction; a noisy cue, or a source that turns
    objects at random, scores low.
    """
    per: dict[tuple, dict[str, list[int]]] = defaultdict(lambda: defaultdict(lambda: [0] * 4))
    for ob in observations:
        if ob.asset_id is not None:
            per[(ob.source, ob.category, ob.cue)][ob.asset_id][ob.quadrant] += 1
    out = {}
    for key, assets in per.items():
        multi = [c for c in assets.values() if sum(c) >= 2]
        n = sum(sum(c) for c in multi)
        if n:
            out[key] = (sum(max(c) for c in multi) / n, n)
    return out


# -- fitting the tables -----------------------------------------------------------------------

MIN_ASSET_SAMPLES = 2
"""An asset overrides its category only on at least this many readings: one
reading of a cue that errs 5-20% of the time must not turn an asset."""
CUE_RELIABILITY = 0.9
"""Chance that one reading of a cue is right (else it is wrong at any of the
other three offsets alike), where the cue's self-consistency is not measurable."""
RELIABILITY_RANGE = (0.5, 0.95)
"""A cue's measured self-consistency, clipped to this, is its reliability: never
so sure that two readings outweigh any category, never below a coin flip."""


@dataclass
class _Evidence:
    """The votes for one (source, category)."""

    counts: np.ndarray
    """(4,) readings per offset over all its voting cues: the category's prior."""
    assets: dict[str, list[tuple[int, float]]]
    """asset id -> its readings as (offset index, reliability of the cue)."""


def _voters(raw_observations: Iterable[Observation]) -> list[Observation]:
    """Readings that vote: a declared, reliable cue with at least MIN_SAMPLES
    readings of the category, on an object with an asset id."""
    obs = [
        ob
        for ob in raw_observations
        if ob.asset_id is not None
        and ob.category in _DECLARED[ob.cue]
        and (ob.source, ob.category, ob.cue) not in UNRELIABLE_CUES
    ]
    n = Counter((ob.source, ob.category, ob.cue) for ob in obs)
    return [ob for ob in obs if n[(ob.source, ob.category, ob.cue)] >= MIN_SAMPLES]


def _evidence(voters: Sequence[Observation]) -> dict[tuple[str, str], _Evidence]:
    consistency = self_consistency(voters)
    low, high = RELIABILITY_RANGE
    out: dict[tuple[str, str], _Evidence] = {}
    for ob in voters:
        ev = out.setdefault(
            (ob.source, ob.category), _Evidence(np.zeros(4, int), defaultdict(list))
        )
        share = consistency.get((ob.source, ob.category, ob.cue), (CUE_RELIABILITY, 0))[0]
        ev.counts[ob.quadrant] += 1
        ev.assets[ob.asset_id].append((ob.quadrant, float(np.clip(share, low, high))))
    return out


def category_offset_index(ev: _Evidence) -> int:
    """The offset index of a category: the one that, with its assets' own
    overrides, agrees with most readings, i.e. the most common reading of the
    assets too little seen to override (of all readings if there are none);
    0 on fewer than MIN_SAMPLES readings or a tie with 0."""
    if ev.counts.sum() < MIN_SAMPLES:
        return 0
    pool = np.zeros(4, int)
    for readings in ev.assets.values():
        if len(readings) < MIN_ASSET_SAMPLES:
            for k, _ in readings:
                pool[k] += 1
    if not pool.any():
        pool = ev.counts
    return int(np.argmax(pool))  # argmax takes the first of a tie: 0 wins it


def asset_offset_index(
    counts: np.ndarray, readings: Sequence[tuple[int, float]], k_cat: int
) -> int:
    """The offset index of one asset: its category's ``k_cat``, unless at least
    MIN_ASSET_SAMPLES readings of its own make another more probable.

    counts : (4,) the category's readings per offset, the prior (Laplace-smoothed);
    readings : the asset's (offset index, reliability) readings, each right with
    its reliability and else wrong at any other offset alike.
    """
    if len(readings) < MIN_ASSET_SAMPLES:
        return k_cat
    score = np.log((np.asarray(counts, float) + 1.0) / (np.sum(counts) + 4.0))
    for k, r in readings:
        reading = np.full(4, np.log((1.0 - r) / 3.0))
        reading[k] = np.log(r)
        score = score + reading
    return int(np.argmax(score))


def suggest_offsets(
    raw_observations: Iterable[Observation],
) -> tuple[dict[str, dict[str, int]], dict[str, dict[str, int]]]:
    """The correction tables the measurements call for, from uncorrected scenes.

    Per (source, category): :func:`category_offset_index`, kept where not 0.
    Per asset: :func:`asset_offset_index`, kept where it differs from its
    category's. Each cue counts as reliable as its self-consistency. Returns
    (by category, by asset) shaped like FRONT_YAW_OFFSET_DEG.
    """
    cat_table: dict[str, dict[str, int]] = defaultdict(dict)
    asset_table: dict[str, dict[str, int]] = defaultdict(dict)
    for (src, cat), ev in sorted(_evidence(_voters(raw_observations)).items()):
        k_cat = category_offset_index(ev)
        if k_cat:
            cat_table[src][cat] = OFFSETS_DEG[k_cat]
        for asset, readings in sorted(ev.assets.items()):
            k = asset_offset_index(ev.counts, readings, k_cat)
            if k != k_cat:
                asset_table[src][asset] = OFFSETS_DEG[k]
    return dict(cat_table), dict(asset_table)


def held_out_agreement(raw_observations: Iterable[Observation]) -> dict[tuple, float]:
    """Per voting (source, category, cue): how often a reading agrees with the
    correction fitted without it (leave one reading out; cue reliabilities kept).

    The after-correction agreement counts the very readings the tables were
    fitted on; this is what an unseen object of a known category can expect.
    """
    evidence = _evidence(_voters(raw_observations))
    hits: dict[tuple, list[bool]] = defaultdict(list)
    for (src, cat), ev in evidence.items():
        for asset, readings in ev.assets.items():
            for i, (k, _) in enumerate(readings):
                others = readings[:i] + readings[i + 1 :]
                counts = ev.counts.copy()
                counts[k] -= 1
                rest = _Evidence(counts, {**ev.assets, asset: others})
                k_fit = asset_offset_index(counts, others, category_offset_index(rest))
                hits[(src, cat, asset, i)].append(k_fit == k)
    # back to cues: an asset's readings are listed in the voters' order
    out: dict[tuple, list[bool]] = defaultdict(list)
    seen: Counter[tuple] = Counter()
    for ob in _voters(raw_observations):
        i = seen[(ob.source, ob.category, ob.asset_id)]
        seen[(ob.source, ob.category, ob.asset_id)] += 1
        out[(ob.source, ob.category, ob.cue)] += hits[(ob.source, ob.category, ob.asset_id, i)]
    return {k: float(np.mean(v)) for k, v in out.items()}


# -- report -----------------------------------------------------------------------------------


@dataclass(frozen=True)
class FrontRow:
    """One (source, category, cue, has an asset id): its agreement before and after."""

    before: Agreement
    """Measured on the adapters' raw Unity-forward frames."""
    after: Agreement | None
    """Measured on the corrected scenes (None: the cue saw no object there)."""
    consistency: tuple[float, int] | None
    """:func:`self_consistency` of the raw readings, where an asset has two."""
    held_out: float | None
    """:func:`held_out_agreement`, for voting rows."""

    @property
    def status(self) -> str:
        """The before-row's status, or ``FAILS`` for a checked row under the bar."""
        st = self.before.status
        if st == "checked" and (self.after is None or self.after.fraction(0) < AGREEMENT_BAR):
            return "FAILS"
        return st

    @property
    def reason(self) -> str:
        """Why an ``unreliable`` or ``below bar`` row is not held to the bar."""
        table = {"unreliable": UNRELIABLE_CUES, "below bar": BELOW_BAR}.get(self.status, {})
        return table.get(self.before.key, "")


@dataclass
class FrontReport:
    """Both Unity sources measured raw and corrected."""

    rows: list[FrontRow]
    raw: list[Observation]
    """Readings of the raw scenes with supports' fronts read through the tables:
    what :func:`suggest_offsets` takes."""
    asset_category: dict[tuple[str, str], str]
    """(source, asset id) -> category, to file asset overrides under their category."""

    def row(self, source: str, category: str, cue: Cue, keyed: bool = True) -> FrontRow | None:
        for r in self.rows:
            if r.before.key == (source, category, cue) and r.before.keyed == keyed:
                return r
        return None


def load_unity_scenes(
    procthor: str | Path, correct_front: bool = True, progress: bool = False
) -> list[Scene]:
    """Every AI2-THOR room (from the cache) and every ProcTHOR room of ``procthor``
    (a ``.jsonl.gz`` file or a folder of them), corrected or raw."""
    from pair2scene.data.ai2thor import load_ai2thor
    from pair2scene.data.procthor import load_procthor

    scenes = load_ai2thor(progress=progress, correct_front=correct_front).scenes
    return scenes + load_procthor(procthor, progress=progress, correct_front=correct_front).scenes


def build_report(raw_scenes: Sequence[Scene], fixed_scenes: Sequence[Scene]) -> FrontReport:
    """Measure the same scenes loaded raw (``correct_front=False``) and corrected."""
    before = observe_all(raw_scenes, survey=True)
    after = measure(observe_all(fixed_scenes, survey=True))
    through_tables = observe_all(raw_scenes, raw=True)
    consistency = self_consistency(before)
    held_out = held_out_agreement(through_tables)
    fixed = {(a.key, a.keyed): a for a in after}
    rows = [
        FrontRow(
            b,
            fixed.get((b.key, b.keyed)),
            consistency.get(b.key) if b.keyed else None,
            held_out.get(b.key) if b.keyed else None,
        )
        for b in measure(before)
    ]
    assets = {
        (s.source or "", o.asset.id): o.category
        for s in raw_scenes
        for o in s.objects
        if o.asset is not None and o.asset.id is not None
    }
    return FrontReport(rows, through_tables, assets)


def front_report(procthor: str | Path, progress: bool = False) -> FrontReport:
    """Load AI2-THOR and ProcTHOR raw and corrected and measure them."""
    return build_report(
        load_unity_scenes(procthor, correct_front=False, progress=progress),
        load_unity_scenes(procthor, correct_front=True, progress=progress),
    )


def _pct(x: float | None) -> str:
    return "-" if x is None else f"{100 * x:.0f}%"


def _fix(report: FrontReport, source: str, category: str) -> str:
    n = sum(
        1
        for asset in FRONT_YAW_OFFSET_BY_ASSET_DEG.get(source, {})
        if report.asset_category.get((source, asset)) == category
    )
    fix = str(FRONT_YAW_OFFSET_DEG.get(source, {}).get(category, 0))
    return fix + (f" +{n} asset{'s' if n > 1 else ''}" if n else "")


ROW_COLUMNS = (
    "source", "category", "cue", "n", "+y before", "raw mode", "same asset", "fix", "after",
    "held out", "status",
)  # fmt: skip


def format_rows(report: FrontReport, rows: Sequence[FrontRow], markdown: bool = False) -> str:
    """Rows as an aligned text table, or a markdown one (see ROW_COLUMNS).

    n: readings; +y before: share that puts the raw +y at the cue; raw mode:
    the offset most readings call for (its share); same asset: self-consistency;
    fix: the category's offset and how many assets override it; after: share on
    the corrected scenes; held out: the same, leaving each reading out of the fit.
    """
    body = []
    for r in rows:
        b, a = r.before, r.after
        body.append(
            [
                b.source if b.keyed else f"{b.source} (no asset id)",
                b.category,
                b.cue.value,
                str(b.n),
                _pct(b.fraction(0)),
                f"{b.best_offset_deg} ({_pct(b.fraction(b.best_offset_deg))})",
                _pct(r.consistency[0]) if r.consistency else "-",
                _fix(report, b.source, b.category) if b.keyed else "-",
                _pct(a.fraction(0) if a is not None else None),
                _pct(r.held_out),
                r.status + (f": {r.reason}" if r.reason else ""),
            ]
        )
    if markdown:
        lines = ["| " + " | ".join(ROW_COLUMNS) + " |", "|" + "---|" * len(ROW_COLUMNS)]
        return "\n".join(lines + ["| " + " | ".join(row) + " |" for row in body])
    widths = [max(len(x) for x in col) for col in zip(ROW_COLUMNS, *body)]
    fmt = "  ".join(f"{{:<{w}}}" for w in widths[:-1]) + "  {}"
    return "\n".join(fmt.format(*row) for row in [ROW_COLUMNS, *body])


DOC_INTRO = """\
# The front convention, taken from the data

pair2scene's object frame has +y at the object's **front**: the side it faces
(a chair's seat opening, a sofa's seat side, a bed's foot end with the headboard
at -y, a TV's screen). The Unity adapters map an asset's local forward (Unity
+z) to +y; this page measures where the front of each category really points in
AI2-THOR and ProcTHOR, and records the corrections the adapters apply
(`pair2scene.data.orientation`). It is written by `python tools/front_survey.py`.

## Method

Each cue gives, per object, the direction its front should point in the floor
plane; none looks at the asset itself:

| cue | categories | the front points |
|---|---|---|
| wall | {wall} | away from the wall it stands against |
| partner | {partner} | to the partner it is used with, within {gap:.1f} m |
| faces | {faces} | to the nearest partner across the room (a sofa to the TV) |
| support | {support} | the way the furniture it stands on faces |
| carries | {carries} | the way the TV on it faces |
| drawers | {drawers} | from its centre to its drawers and doors (AI2-THOR's parts) |
| pillows | {pillows} | away from the pillows on it |

Wall cue: the object's footprint comes within {contact:.1f} m of the wall, no
crossing wall is within {corner:.1f} m (in a corner the back could be either
side) and the box is square to the wall within {square:.0f} degrees. Partner
cue: the direction is the normal of the larger one's edge facing the smaller
one (a chair to its table's edge; out of a desk's edge toward its chair).

Walls: ProcTHOR's floor polygons are the rooms' inner wall faces. AI2-THOR's
iTHOR floor rectangles run ~0.3 m under the walls, so each side is pulled in to
the extent of the room's objects and windows where that lies within
{band} m of it (else that side gives no wall); RoboTHOR's apartments are
left out (their floor is only the objects' extent around several rooms).

For every object a cue reaches, the object's frame turned by each yaw offset
(0, 90, 180, 270 degrees about local z; 90 makes the old -x the front) puts its
+y within 45 degrees of the cue's direction for exactly one offset: the counts
per offset over a (source, category, cue) are the measurement.

Corrections are fitted on the raw frames (`load_*(correct_front=False)`), from
the readings of declared cues that are not listed as unreliable and have at
least {min_samples} readings of the category, on objects with an asset id:

- per category: the offset that, with the asset overrides below, agrees with
  the most readings (the most common reading of the assets seen too rarely to
  override); kept where not 0;
- per asset: the most probable offset given the category's readings as prior
  and at least {min_asset} readings of its own, each cue taken as reliable as
  its self-consistency (clipped to {rel}); kept where it differs.

The adapters apply them once (`turn_front`): R' = R @ Rz(offset), and the
x and y sizes swap for 90 and 270, so the box covers the same space (the same
corner set: the OBB test of the AI2-THOR adapter is unchanged).

A (source, category, cue) with at least {min_samples} readings is **checked**:
after the correction at least {bar:.0f}% of its readings must agree
(`tests/data/test_front_survey.py`), except the rows listed as below the bar, each
with its reason. Columns: n readings; +y before: share with the raw +y at the
cue; raw mode: the offset most raw readings call for; same asset: how often
an asset's readings agree with each other (a reliable cue on consistently
modelled assets is near 100% whatever the correction); fix: the category's
offset, and how many of its assets override it; after: share on the corrected
scenes; held out: the same with each reading left out of the fit (what an
unseen object can expect).
"""


DOC_FINDINGS = """
What the figures below show:

- ProcTHOR needs no correction: every reliable cue puts its fronts at Unity
  +z on 98-100% of the readings, and an asset agrees with itself as often.
- AI2-THOR's designed rooms model some assets the other way round: iTHOR's
  beds (Bed_1 ... Bed_30) have their headboard at Unity +z (pillows and walls
  agree), while ProcTHOR's copies of the same asset ids and RoboTHOR's own beds
  do not; five of iTHOR's nine TV stands face Unity -z. Each iTHOR asset
  appears in one room, so these are single-room verdicts: the held-out column
  shows that an unseen TV stand is a coin flip.
- AI2-THOR objects without an asset id cannot be corrected by these tables:
  RoboTHOR chair prefabs (Chair_1a4601b6, Chair_481a5010, Chair_516032bd...)
  face local +x or -x, and iTHOR's bathroom mirrors, counters and sinks are
  baked with an identity rotation, their front along whatever world axis.
"""


def write_doc(report: FrontReport, path: str | Path) -> Path:
    """Write the markdown page (method, tables, figures) to ``path``."""
    fmt = {
        "wall": ", ".join(sorted(WALL_BACKED)),
        "partner": ", ".join(f"{k} -> {'/'.join(v)}" for k, v in PARTNERS.items()),
        "faces": ", ".join(f"{k} -> {'/'.join(v)}" for k, v in FACES.items()),
        "support": ", ".join(sorted(SUPPORT_FOLLOWERS))
        + " on "
        + ", ".join(sorted(FRONTED_SUPPORTS)),
        "carries": ", ".join(f"{k} (with a {'/'.join(v)})" for k, v in CARRIERS.items()),
        "drawers": ", ".join(sorted(DRAWER_HOSTS)),
        "pillows": ", ".join(sorted(PILLOW_HOSTS)),
        "contact": WALL_CONTACT_M,
        "corner": CORNER_M,
        "square": SQUARE_TOL_DEG,
        "gap": PARTNER_GAP_M,
        "band": f"[{ITHOR_WALL_BAND_M[0]}, {ITHOR_WALL_BAND_M[1]}]",
        "min_samples": MIN_SAMPLES,
        "min_asset": MIN_ASSET_SAMPLES,
        "rel": f"[{RELIABILITY_RANGE[0]}, {RELIABILITY_RANGE[1]}]",
        "bar": 100 * AGREEMENT_BAR,
    }
    parts = [DOC_INTRO.format(**fmt)]
    parts.append("## The corrections\n")
    lines = ["| source | category or asset | offset (deg) |", "|---|---|---|"]
    for src in sorted(FRONT_YAW_OFFSET_DEG):
        for cat, off in sorted(FRONT_YAW_OFFSET_DEG[src].items()):
            lines.append(f"| {src} | category `{cat}` | {off} |")
        for asset, off in sorted(FRONT_YAW_OFFSET_BY_ASSET_DEG.get(src, {}).items()):
            cat = report.asset_category.get((src, asset), "?")
            lines.append(f"| {src} | asset `{asset}` ({cat}) | {off} |")
    parts.append("\n".join(lines) + "\n\nEverything else keeps offset 0.\n" + DOC_FINDINGS)
    declared = [r for r in report.rows if r.before.status != "survey"]
    keyed = [r for r in declared if r.before.keyed]
    parts.append("## Categories with a front, per cue\n")
    parts.append(format_rows(report, keyed, markdown=True) + "\n")
    parts.append(
        "## Objects without an asset id (AI2-THOR)\n\n"
        "Parts, built-in fixtures and some RoboTHOR prefabs carry no asset id: their\n"
        "frames cannot be corrected one by one, and many are baked with an identity\n"
        "rotation (iTHOR's bathroom mirrors are thin along x). Not checkable.\n"
    )
    unkeyed = [r for r in declared if not r.before.keyed and r.before.n >= MIN_SAMPLES]
    parts.append(format_rows(report, unkeyed, markdown=True) + "\n")
    survey = [
        r
        for r in report.rows
        if r.before.status == "survey" and r.before.keyed and r.before.n >= MIN_SAMPLES
    ]
    parts.append(
        "## Survey: the wall cue on categories without a declared front\n\n"
        "Round tables, plants, bins, bowls... have no front to check; a high share\n"
        "here only says the source turns them like the wall (ProcTHOR stands most\n"
        "objects with their local -y to the wall, and small objects square to it).\n"
    )
    lines = ["| source | category | n | mode (share) |", "|---|---|---|---|"]
    for r in survey:
        b = r.before
        lines.append(
            f"| {b.source} | {b.category} | {b.n} | "
            f"{b.best_offset_deg} ({_pct(b.fraction(b.best_offset_deg))}) |"
        )
    parts.append("\n".join(lines) + "\n")
    out = Path(path)
    out.parent.mkdir(parents=True, exist_ok=True)
    out.write_text("\n".join(parts), encoding="utf-8")
    return out


def tables_match(report: FrontReport) -> list[str]:
    """Differences between the correction tables and what the measurements call for."""
    cat, asset = suggest_offsets(report.raw)
    problems = []
    for name, have, want in (
        ("FRONT_YAW_OFFSET_DEG", FRONT_YAW_OFFSET_DEG, cat),
        ("FRONT_YAW_OFFSET_BY_ASSET_DEG", FRONT_YAW_OFFSET_BY_ASSET_DEG, asset),
    ):
        for src in sorted(set(have) | set(want)):
            h, w = have.get(src, {}), want.get(src, {})
            for key in sorted(set(h) | set(w)):
                if h.get(key) != w.get(key):
                    problems.append(
                        f"{name}[{src!r}][{key!r}]: table {h.get(key)}, data {w.get(key)}"
                    )
    return problems


def main(argv: Sequence[str] | None = None) -> int:
    parser = argparse.ArgumentParser(
        prog="python tools/front_survey.py",
        description="Measure where each category's front points in AI2-THOR and ProcTHOR, "
        "before and after the adapters' correction, and write the doc.",
    )
    parser.add_argument(
        "--procthor",
        default="../shared/data/procthor-1k",
        help="ProcTHOR .jsonl.gz file or folder (default: %(default)s)",
    )
    parser.add_argument(
        "--doc", default="docs/front_convention.md", help="markdown output (default: %(default)s)"
    )
    parser.add_argument("--no-doc", action="store_true", help="only print the table")
    parser.add_argument("--all", action="store_true", help="also print survey rows")
    args = parser.parse_args(argv)
    from pair2scene.errors import UserError

    try:
        report = front_report(args.procthor)
    except UserError as e:
        print(f"error: {e}", file=sys.stderr)
        return 2
    rows = [r for r in report.rows if args.all or r.before.status != "survey"]
    print(format_rows(report, rows))
    problems = tables_match(report)
    failing = [r for r in report.rows if r.status == "FAILS"]
    for p in problems:
        print(f"table differs from the data: {p}")
    for r in failing:
        b = r.before
        print(f"under the {AGREEMENT_BAR:.0%} bar: {b.source} {b.category} {b.cue.value}")
    if not args.no_doc:
        print(f"wrote {write_doc(report, args.doc)}")
    return 1 if problems or failing else 0


if __name__ == "__main__":
    sys.exit(main())

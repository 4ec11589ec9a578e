"""Scene completion (``--keep partial.json``): fixed objects, the rest filled in around them.

The partial scene is a scene.json (the contract in README, "scene.json", with its limits:
:func:`pair2scene.io.scene_json.read_scene`): its room is the room and its objects stay
exactly where they are. A malformed file is a one-line error; so is one with more than
:data:`MAX_KEPT_OBJECTS` objects to keep.

A user's kept layout is theirs: it is kept as given, and what pair2scene notices about it
becomes a note (in the scene's and the summary's ``notes``), never a refusal:

- kept objects that intersect each other (at mesh level, deeper than placement's
  tolerance): one note per pair, with the depth (:func:`overlap_notes`);
- a kept object outside the room (its footprint beyond the floor polygon, or above the
  ceiling), under the floor, or floating (nothing under it: neither the floor nor another
  kept object; objects on or against a wall, wall objects and objects hung from the
  ceiling excepted): one note per object,
  naming each reason (:func:`placement_notes`).

Only what is added must be collision-free: added objects are placed against the kept ones
(and the room) as against any placed object.

A partial scene of room type ``other`` (a room no source type fits) is filled by the
statistics' ``other`` rooms when they have some; otherwise by the trained room type whose
rooms hold the kept objects' categories most often (``apartment``, the multi-purpose type,
when nothing kept tells), with a note. Any other room type the statistics cannot fill is a
one-line error naming the ones they can.

The hierarchy drawn for the room is merged with them (:func:`merge_keep`): a kept object
stands in for a hierarchy node of its category on the same support (the user's bed is the
bed; the pillows drawn for the bed go on it), so nothing is doubled; kept objects the
hierarchy did not ask for simply stay. Rooms parts and structure in the file (walls,
drawers) are not objects to keep and are left out, with a note.
"""

from __future__ import annotations

from dataclasses import dataclass, replace
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from pair2scene.assembly.collision import TOLERANCES, MeshWorld, Shape, Tolerances, obb_overlaps
from pair2scene.assets.identity import asset_seed
from pair2scene.assets.mesh import Asset
from pair2scene.categories import SuperCategory, super_category
from pair2scene.errors import UserError
from pair2scene.hierarchy.tree import Hierarchy, Node
from pair2scene.scene.model import FLOOR, Room, Scene, SceneObject, on_wall

if TYPE_CHECKING:
    from pair2scene.curation.stats import HierarchyStats

RESTING_M = 0.01
"""An object with no support in the file whose bottom is this near the floor stands on it."""
MAX_KEPT_OBJECTS = 500
"""Objects a partial scene may have to keep: the most a scene may be asked for
(:data:`pair2scene.hierarchy.synthesis.MAX_OBJECTS_LIMIT`); beyond it, building their
assets and checking them against each other would run for minutes."""
MAX_OVERLAP_NOTES = 20
"""Overlapping pairs of kept objects named one by one; more are counted in one note."""
MAX_MEASURED_PAIRS = 2000
"""Pairs of kept objects whose boxes overlap measured at mesh level at most (a few seconds);
further ones are counted in one note."""
OUTSIDE_M = 0.05
"""m; a kept object's footprint reaching farther than this beyond the floor polygon, or its
top this far above the ceiling, is outside the room."""
UNDER_FLOOR_M = 0.02
"""m; a kept object whose bottom is lower than this below the floor is under the floor."""
FLOATING_M = 0.05
"""m; a kept object whose bottom is higher than this above whatever is under it (the floor
or another kept object) floats."""
CEILING_HUNG = frozenset({"ceiling_lamp"})
"""Categories that hang from the ceiling: never floating."""
OTHER_ROOM = "other"
"""The room type of rooms no source type fits (:class:`pair2scene.categories.RoomType`)."""
FALLBACK_ROOM = "apartment"
"""The trained type an ``other`` room is filled as when no kept object tells: a
multi-purpose space."""


@dataclass(frozen=True)
class Kept:
    """A partial scene read and checked once: its objects, their assets, the notes."""

    scene: Scene
    assets: dict[str, Asset]
    notes: list[str]


def load_keep(path: str | Path, stats: HierarchyStats | None = None) -> Kept:
    """Read the partial scene and build its objects' assets; what is odd about the kept
    layout (overlaps, objects outside the room, under the floor or floating) is noted.
    ``stats``: the statistics the scene will be filled from (None: the bundled ones),
    which decide what an ``other`` room becomes."""
    scene, notes = read_keep(path, stats)
    assets = keep_assets(scene)
    notes += overlap_notes(scene, assets)
    return Kept(scene, assets, notes)


def read_keep(path: str | Path, stats: HierarchyStats | None = None) -> tuple[Scene, list[str]]:
    """The partial scene (objects to keep only) and notes on what was left out, on where
    kept objects are and on the room type it is filled as."""
    from pair2scene.io.scene_json import read_scene

    scene = read_scene(path)
    keep, notes = [], []
    for o in scene.objects:
        if super_category(o.category) in (SuperCategory.STRUCTURE, SuperCategory.PART):
            notes.append(f"--keep: {o.id} ({o.category}) is not an object to keep; left out")
            continue
        support = o.support
        if support is None and o.box.bottom <= RESTING_M:
            support = FLOOR
        keep.append(replace(o, support=support))
    if len(keep) > MAX_KEPT_OBJECTS:
        raise UserError(
            f"{path}: {len(keep)} objects to keep, more than the {MAX_KEPT_OBJECTS} a scene "
            "may hold"
        )
    room, note = keep_room_type(scene.room, keep, stats)
    if note is not None:
        notes.append(note)
    notes += placement_notes(room, keep)
    ids = {o.id for o in keep}
    keep = [o if o.support in (None, FLOOR) or o.support in ids else replace(o, support=None)
            for o in keep]  # fmt: skip
    return replace(scene, room=room, objects=keep), notes


def keep_room_type(
    room: Room, keep: list[SceneObject], stats: HierarchyStats | None = None
) -> tuple[Room, str | None]:
    """``room`` as it is filled: an ``other`` room the statistics have no rooms of becomes
    the trained type whose rooms hold the kept categories most often (module docstring),
    with a note saying so; any other room is returned as it is (None: no note)."""
    from pair2scene.hierarchy.room_types import resolve

    if resolve(room.type) != OTHER_ROOM:
        return room, None
    if stats is None:
        from pair2scene.hierarchy.synthesis import load_stats

        stats = load_stats()
    trained = {t: rs for t, rs in sorted(stats.room_types.items()) if rs.rooms and rs.layouts}
    if OTHER_ROOM in trained:
        return replace(room, type=OTHER_ROOM), None
    if not trained:
        raise UserError(f"room type {room.type!r}: the statistics have no rooms to fill it with")
    from pair2scene.curation.stats import split_member

    kept = {o.category for o in keep}
    scores: dict[str, float] = {}
    held: dict[str, list[str]] = {}
    for rtype, rs in trained.items():
        share: dict[str, float] = {}  # kept category -> share of the rooms holding it
        for member, hist in sorted(rs.furniture_counts().items()):
            category = split_member(member)[0]
            if category in kept:
                held_by = 1.0 - hist.get(0, 0) / rs.rooms
                share[category] = max(share.get(category, 0.0), held_by)
        scores[rtype] = sum(share.values())
        held[rtype] = sorted(c for c, v in share.items() if v > 0)
    best = max(scores.values())
    if best > 0:
        tied = [t for t, s in scores.items() if s == best]
        rtype = FALLBACK_ROOM if FALLBACK_ROOM in tied else tied[0]
        cats = held[rtype]
        shown = ", ".join(cats[:8]) + (f" and {len(cats) - 8} more" if len(cats) > 8 else "")
        why = f"the type whose rooms most often hold the kept {shown}"
    else:
        rtype = (
            FALLBACK_ROOM
            if FALLBACK_ROOM in trained
            else max(trained, key=lambda t: trained[t].rooms)
        )
        kind = "the multi-purpose type" if rtype == FALLBACK_ROOM else "the most common type"
        why = f"no kept object tells the type; {kind}"
    note = (
        f"--keep: the statistics have no {OTHER_ROOM!r} rooms (they have "
        f"{', '.join(trained)}); the room is filled as room type {rtype!r} ({why})"
    )
    return replace(room, type=rtype), note


def keep_assets(scene: Scene) -> dict[str, Asset]:
    """Each object's procedural asset at its box's size: the exact one when its asset
    reference has the generator's seed (scenes pair2scene wrote), otherwise one of its
    style (when given) seeded by its id."""
    from pair2scene.assets.registry import generate

    out = {}
    for o in scene.objects:
        ref = o.asset if o.asset is not None and o.asset.source == "procedural" else None
        if ref is not None and ref.seed is not None:
            out[o.id] = generate(o.category, o.box.size, ref.seed)
            continue
        rng = np.random.default_rng(asset_seed(o.id, 0))
        out[o.id] = generate(o.category, o.box.size, rng, style=None if ref is None else ref.style)
    return out


def overlap_notes(
    scene: Scene, assets: dict[str, Asset], tolerances: Tolerances = TOLERANCES
) -> list[str]:
    """One note per pair of kept objects that intersect deeper than ``tolerances.touch``
    (at mesh level, as placement measures), the first :data:`MAX_OVERLAP_NOTES` named and
    measured (at most :data:`MAX_MEASURED_PAIRS` measured), any further pair whose boxes
    overlap counted in one more note."""
    objs = scene.objects
    if len(objs) < 2:
        return []
    centers = np.stack([o.box.center for o in objs])
    halves = np.stack([o.box.half_size for o in objs])
    rots = np.stack([o.box.rotation for o in objs])
    hits = obb_overlaps(centers, halves, rots, centers, halves, rots, tolerances.box_margin)
    pairs = np.argwhere(np.triu(hits, k=1))
    world = MeshWorld(tolerances)
    shapes: dict[int, Shape] = {}

    def shape(i: int) -> Shape:
        if i not in shapes:
            shapes[i] = Shape(assets[objs[i].id])
            shapes[i].set_pose(objs[i].box.rotation, objs[i].box.center)
        return shapes[i]

    notes, unmeasured, measured = [], 0, 0
    for i, j in pairs.tolist():
        if len(notes) >= MAX_OVERLAP_NOTES or measured >= MAX_MEASURED_PAIRS:
            unmeasured += 1
            continue
        measured += 1
        depth = world.penetration(shape(i), shape(j))
        if depth > tolerances.touch:
            notes.append(
                f"--keep: kept objects {objs[i].id} and {objs[j].id} intersect "
                f"({depth * 100:.1f} cm deep); kept as given"
            )
    if unmeasured:
        notes.append(
            f"--keep: {unmeasured} more pairs of kept objects may intersect (their boxes "
            "do); kept as given"
        )
    return notes


def placement_notes(room: Room, keep: list[SceneObject]) -> list[str]:
    """One note per kept object outside the room, under the floor or floating (module
    docstring; :data:`OUTSIDE_M`, :data:`UNDER_FLOOR_M`, :data:`FLOATING_M`)."""
    if not keep:
        return []
    lows, highs = zip(*(o.box.aabb() for o in keep), strict=True)
    lo, hi = np.stack(lows), np.stack(highs)
    poly = np.asarray(room.floor_polygon, dtype=float)
    notes = []
    for k, o in enumerate(keep):
        reasons = []
        footprint = o.box.corners()[:, :2]
        beyond = _beyond_polygon(footprint, poly)
        if beyond > OUTSIDE_M:
            reasons.append(f"stands outside the room ({_cm(beyond)} beyond its floor)")
        if hi[k, 2] > room.height + OUTSIDE_M:
            reasons.append(f"rises {_cm(hi[k, 2] - room.height)} through the ceiling")
        if lo[k, 2] < -UNDER_FLOOR_M:
            reasons.append(f"reaches {_cm(-lo[k, 2])} under the floor")
        gap = _gap_below(k, keep, lo, hi, room)
        if gap is not None and gap[0] > FLOATING_M:
            reasons.append(f"floats {_cm(gap[0])} above {gap[1]} with nothing under it")
        if reasons:
            notes.append(f"--keep: {o.id} ({o.category}) {', '.join(reasons)}; kept as given")
    return notes


def _gap_below(
    k: int, keep: list[SceneObject], lo: np.ndarray, hi: np.ndarray, room: Room
) -> tuple[float, str] | None:
    """How far object ``k``'s bottom is above the highest thing under it (the floor or a
    kept object whose footprint overlaps its own), and what that is; None when it hangs
    (on a wall, a wall object, against a wall, from the ceiling) or rests in or on another
    kept object."""
    o = keep[k]
    if on_wall(o.support) or o.super is SuperCategory.WALL_OBJECT:
        return None
    at_ceiling = abs(hi[k, 2] - room.height) <= OUTSIDE_M
    if o.category in CEILING_HUNG or (at_ceiling and o.super is not SuperCategory.LARGE_FURNITURE):
        return None  # hung from the ceiling
    bottom = lo[k, 2]
    if bottom <= FLOATING_M:
        return None
    footprint = o.box.corners()[:, :2]
    if _edge_distances(footprint, np.asarray(room.floor_polygon, dtype=float)).min() <= OUTSIDE_M:
        return None  # against a wall: mounted on it (a wall cabinet, a TV)
    over = np.all((lo[:, :2] < hi[k, :2]) & (hi[:, :2] > lo[k, :2]), axis=1)
    over[k] = False
    if np.any(over & (lo[:, 2] <= bottom) & (hi[:, 2] >= bottom - FLOATING_M)):
        return None  # on or inside another kept object
    below = over & (hi[:, 2] < bottom)
    if not below.any():
        return float(bottom), "the floor"
    j = int(np.argmax(np.where(below, hi[:, 2], -np.inf)))
    return float(bottom - hi[j, 2]), keep[j].id


def _edge_distances(points: np.ndarray, polygon: np.ndarray) -> np.ndarray:
    """(N,) distance of each of ``points`` (N, 2) to the nearest edge of ``polygon``."""
    p = points[:, None, :]  # (N, 1, 2)
    a, b = polygon, np.roll(polygon, -1, axis=0)  # edges a -> b, (M, 2)
    ab = b - a
    t = np.clip(np.einsum("kmd,md->km", p - a, ab) / np.maximum((ab * ab).sum(1), 1e-12), 0, 1)
    nearest = a + t[..., None] * ab
    return np.sqrt(((p - nearest) ** 2).sum(-1)).min(axis=1)


def _beyond_polygon(points: np.ndarray, polygon: np.ndarray) -> float:
    """How far the farthest of ``points`` (N, 2) outside ``polygon`` (M, 2) is from it
    (0 when all are inside)."""
    from pair2scene.scene.geometry import points_in_polygon

    outside = ~points_in_polygon(points, polygon)
    if not outside.any():
        return 0.0
    return float(_edge_distances(points[outside], polygon).max())


def _cm(m: float) -> str:
    return f"{m * 100:.0f} cm" if m < 1 else f"{m:.2f} m"


def merge_keep(hierarchy: Hierarchy, keep: list[SceneObject]) -> tuple[Hierarchy, set[str]]:
    """The hierarchy with kept objects standing in for nodes of their category on the same
    support (their ids taken over), and the set of node ids that are kept objects."""
    kept_ids = {o.id for o in keep}
    rename: dict[str, str] = {}
    used: set[str] = set()
    for item in hierarchy.sequence():
        node = item.dependent
        support = rename.get(item.support, item.support)
        for o in keep:
            if o.id not in used and o.category == node.category and o.support == support:
                rename[node.id] = o.id
                used.add(o.id)
                break
    taken = kept_ids | {n.id for n in hierarchy.nodes}
    for n in hierarchy.nodes:  # a drawn node whose id a kept object has: a fresh id
        if n.id not in rename and n.id in kept_ids:
            k = 0
            while f"{n.category}_{k}" in taken:
                k += 1
            rename[n.id] = f"{n.category}_{k}"
            taken.add(rename[n.id])

    def new(i: str | None) -> str | None:
        return None if i is None else rename.get(i, i)

    merged = Hierarchy(
        hierarchy.room_type,
        [Node(new(n.id), n.category) for n in hierarchy.nodes],
        {new(k): new(v) for k, v in hierarchy.support.items()},
        {new(k): new(v) for k, v in hierarchy.functional.items()},
        list(hierarchy.notes),
        {new(k) for k in hierarchy.over},
        {new(k) for k in hierarchy.across},
    )
    return merged, set(used)

"""Relation tuples of curated scenes: ``<dependent, support anchor, optional functional anchor>``.

Each :class:`PairTuple` keeps, for every member, what the model and the point-cloud
cache need to rebuild it (id, category, asset reference, world box), plus the
dependent's box in the support anchor's canonical frame (architecture.md: the
anchor's box mapped to [-1, 1]^3; the floor's box is the room's bounds) and, when
there is a functional anchor, in that anchor's frame too (the architecture's open
question on floor-supported tuples with a functional anchor).
"""

from __future__ import annotations

from collections import Counter
from dataclasses import dataclass
from enum import Enum

from pair2scene.categories import SuperCategory
from pair2scene.scene.geometry import OrientedBox
from pair2scene.scene.model import FLOOR, WALL, AssetRef, Scene, SceneObject, wall_index
from pair2scene.scene.walls import Wall, wall_contact, walls_of


class RelationKind(str, Enum):
    """What places the dependent. Defined here once; the dataset stores the values."""

    FLOOR = "floor"
    """Resting on the floor, no functional anchor: large furniture placed relative to the room."""
    SUPPORT = "support"
    """Resting on an object or mounted on a wall, no functional anchor."""
    FUNCTIONAL = "functional"
    """Has a functional anchor (on any support, the floor included)."""


RELATION_KINDS: tuple[str, ...] = tuple(k.value for k in RelationKind)

SKIPPED_SUPER_CATEGORIES = (SuperCategory.STRUCTURE, SuperCategory.PART)
"""Never dependents: structure is the room itself; parts (drawers, cabinet doors) move
with the object they belong to and are generated with it, not placed. Both may still
be anchors (a spoon resting in a drawer keeps the drawer as its support)."""


@dataclass(frozen=True)
class Member:
    """One object of a tuple (or the floor)."""

    id: str
    """Object id, or ``floor``."""
    category: str
    asset: AssetRef | None
    """None for the floor (its geometry is the room) and for objects without one."""
    box: OrientedBox
    """World box; for the floor, the room's bounds."""


@dataclass(frozen=True)
class PairTuple:
    """One relation tuple with everything needed to train on it."""

    source: str
    scene_id: str
    split: str | None
    room_type: str
    kind: RelationKind
    dependent: Member
    support: Member
    functional: Member | None
    canonical: OrientedBox
    """The dependent's box in the support anchor's canonical frame."""
    canonical_functional: OrientedBox | None
    """The dependent's box in the functional anchor's canonical frame (None without one)."""
    wall: Member | None = None
    """For a floor object standing against a wall (:func:`~pair2scene.scene.walls.wall_contact`:
    a face within 0.15 m of it, parallel within 15 degrees): that wall, its box the wall's
    frame (:meth:`~pair2scene.scene.walls.Wall.frame`: x along the wall, y into the room,
    z up), its id ``wall_<edge index>``. A third anchor beside the support and the
    functional anchor (a nightstand: the floor, the bed, the wall behind both)."""
    canonical_wall: OrientedBox | None = None
    """The dependent's box in the wall's frame (None without a wall)."""


def floor_member(scene: Scene) -> Member:
    """The floor as a tuple member: its box is the room's bounds."""
    return Member(FLOOR, "floor", None, scene.room.bounds)


def _member(obj: SceneObject) -> Member:
    return Member(obj.id, obj.category, obj.asset, obj.box)


def wall_member(wall: Wall, height: float) -> Member:
    """A wall as a tuple member: its box is the wall's frame (the support of a mounted
    object, the third anchor of a floor object against it)."""
    return Member(f"wall_{wall.index}", WALL, None, wall.frame(height))


def wall_anchor(scene: Scene, obj: SceneObject, walls: list[Wall] | None = None) -> Member | None:
    """The wall ``obj`` stands against (a floor object only), as a member; None without."""
    if obj.support != FLOOR:
        return None
    walls = walls_of(scene.room.floor_polygon) if walls is None else walls
    contact = wall_contact(obj.box, walls)
    if contact is None:
        return None
    wall = next(w for w in walls if w.index == contact.wall)
    return wall_member(wall, scene.room.height)


def scene_tuples(
    scene: Scene,
    exclude_floor_only: bool = False,
    source: str | None = None,
    skipped: Counter[str] | None = None,
) -> list[PairTuple]:
    """One tuple per placed object of ``scene``, in the scene's object order.

    Objects without a support, structure and parts are not dependents (see
    SKIPPED_SUPER_CATEGORIES), nor objects built into another (``part_of`` naming an
    object of the scene: a faucet of a sink, pair2scene.data.fixtures).
    exclude_floor_only : leave out ``floor`` tuples (floor support, no functional
    anchor), as the method does for noisy sources.
    source : the name stored in each tuple (default ``scene.source``).
    skipped : when given, counts why objects gave no tuple.
    """
    skipped = Counter() if skipped is None else skipped
    by_id = scene.by_id()
    floor = floor_member(scene)
    walls = walls_of(scene.room.floor_polygon)
    out = []
    for obj in scene.objects:
        if obj.super in SKIPPED_SUPER_CATEGORIES:
            skipped[obj.super.value] += 1
            continue
        if obj.part_of is not None and obj.part_of in by_id:
            # built into another object (a faucet of a sink, a burner of a counter)
            skipped["part of another object"] += 1
            continue
        if obj.support is None:
            skipped["no support"] += 1
            continue
        if obj.support == FLOOR:
            support = floor
        elif wall_index(obj.support) is not None:
            wall = next((w for w in walls if w.index == wall_index(obj.support)), None)
            if wall is None:
                skipped["wall support not in the room"] += 1
                continue
            support = wall_member(wall, scene.room.height)
        elif obj.support in by_id:
            support = _member(by_id[obj.support])
        else:
            skipped["support not in scene"] += 1
            continue
        functional = None
        if obj.functional_anchor is not None:
            anchor = by_id.get(obj.functional_anchor)
            if anchor is None:
                skipped["functional anchor not in scene (kept without)"] += 1
            else:
                functional = _member(anchor)
        if functional is not None:
            kind = RelationKind.FUNCTIONAL
        elif support.id == FLOOR:
            kind = RelationKind.FLOOR
        else:
            kind = RelationKind.SUPPORT
        if exclude_floor_only and kind is RelationKind.FLOOR:
            skipped["floor-only excluded"] += 1
            continue
        wall = wall_anchor(scene, obj, walls)
        out.append(
            PairTuple(
                source=source or scene.source or "unknown",
                scene_id=scene.id,
                split=scene.split,
                room_type=scene.room.type,
                kind=kind,
                dependent=_member(obj),
                support=support,
                functional=functional,
                canonical=obj.box.in_frame_of(support.box),
                canonical_functional=(
                    None if functional is None else obj.box.in_frame_of(functional.box)
                ),
                wall=wall,
                canonical_wall=None if wall is None else obj.box.in_frame_of(wall.box),
            )
        )
    return out

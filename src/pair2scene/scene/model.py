"""Typed scene model: objects, rooms, scenes and relation tuples."""

from __future__ import annotations

from dataclasses import dataclass, field, replace
from typing import Literal

import numpy as np

from pair2scene.categories import SuperCategory, super_category
from pair2scene.scene.geometry import OrientedBox, points_in_polygon, polygon_area

FLOOR = "floor"
"""Support id of the floor: the root of every support tree."""
WALL = "wall"
"""Support of a wall-mounted object (a painting, a mirror, curtains, a mounted TV) whose
wall is not chosen yet: a hierarchy's node, for which placement picks the wall. A placed
object names its wall, ``wall:<i>`` (:func:`wall_support`). Also the category of a wall
as a relation-tuple member."""
_WALL_PREFIX = WALL + ":"


def wall_support(index: int) -> str:
    """The support id of an object mounted on wall ``index``: ``wall:<index>``, the index
    of the wall's edge in the room's floor polygon (edge i runs from vertex i to i + 1,
    :class:`~pair2scene.scene.walls.Wall`)."""
    return f"{_WALL_PREFIX}{int(index)}"


def wall_index(support: str | None) -> int | None:
    """The wall index of a ``wall:<i>`` support id; None for anything else (``wall``
    itself included: no wall chosen yet)."""
    if not isinstance(support, str) or not support.startswith(_WALL_PREFIX):
        return None
    tail = support[len(_WALL_PREFIX) :]
    plain = tail.isascii() and tail.isdigit() and (tail == "0" or not tail.startswith("0"))
    return int(tail) if plain else None


def on_wall(support: str | None) -> bool:
    """Whether a support id is a wall: ``wall`` (not chosen yet) or ``wall:<i>``."""
    return support == WALL or wall_index(support) is not None


def is_root(support: str | None) -> bool:
    """Whether a support id is a root of the support tree: the floor or a wall."""
    return support == FLOOR or on_wall(support)


@dataclass(frozen=True)
class AssetRef:
    """Where an object's geometry comes from."""

    source: str
    """``procedural``, ``ai2thor``, ``3dfuture``, ``user``..."""
    id: str | None = None
    """The source's asset id (AI2-THOR assetId, 3D-FUTURE jid...)."""
    style: int | None = None
    """Variant index for procedural assets."""
    seed: int | None = None
    """Seed of a procedural asset's generator (``pair2scene.assets.registry.generate``):
    with the category and the box's size it rebuilds the exact mesh the scene was made
    with, so a scene.json read back is evaluated on the shapes that were placed."""

    def to_dict(self) -> dict:
        out = {"source": self.source, "id": self.id, "style": self.style}
        if self.seed is not None:  # (older files have no seed)
            out["seed"] = self.seed
        return out


@dataclass(frozen=True)
class SceneObject:
    id: str
    category: str
    """Canonical category name (pair2scene.categories)."""
    box: OrientedBox
    asset: AssetRef | None = None
    support: str | None = None
    """``floor``, ``wall:<i>`` (mounted on the room's wall i, :func:`wall_support`), the id
    of the supporting object, or None when not known yet."""
    functional_anchor: str | None = None
    source_label: str | None = None
    """The label the source used, before mapping."""
    source_support: str | None = None
    """The support the source itself annotated (ground truth for curation checks)."""
    part_of: str | None = None
    """For parts (drawers, shelves of a unit): the object they belong to."""

    @property
    def super(self) -> SuperCategory:
        return super_category(self.category)

    def with_box(self, box: OrientedBox) -> SceneObject:
        return replace(self, box=box)


@dataclass(frozen=True)
class Opening:
    """A door or window: a segment of a wall seen from above, and its height range."""

    kind: Literal["door", "window"]
    p0: tuple[float, float]
    p1: tuple[float, float]
    z_min: float = 0.0
    z_max: float = 2.1
    id: str | None = None

    @property
    def width(self) -> float:
        return float(np.hypot(self.p1[0] - self.p0[0], self.p1[1] - self.p0[1]))


@dataclass(frozen=True)
class Room:
    type: str
    """A RoomType value, or a free string for text-described rooms."""
    floor_polygon: np.ndarray
    """(N, 2) counter-clockwise, metres, floor at z = 0."""
    height: float = 2.7
    doors: tuple[Opening, ...] = ()
    windows: tuple[Opening, ...] = ()

    def __post_init__(self) -> None:
        poly = np.array(self.floor_polygon, dtype=float)
        if poly.ndim != 2 or poly.shape[1] != 2 or len(poly) < 3:
            raise ValueError(f"floor_polygon must be (N>=3, 2), got {poly.shape}")
        if polygon_area(poly) < 0:
            poly = poly[::-1].copy()
        poly.setflags(write=False)
        object.__setattr__(self, "floor_polygon", poly)

    @property
    def area(self) -> float:
        return polygon_area(self.floor_polygon)

    @property
    def bounds(self) -> OrientedBox:
        """The floor's box: the room's xy bounds from z = 0 to the ceiling."""
        lo, hi = self.floor_polygon.min(0), self.floor_polygon.max(0)
        center = [(lo[0] + hi[0]) / 2, (lo[1] + hi[1]) / 2, self.height / 2]
        return OrientedBox(np.array(center), np.array([*(hi - lo), self.height]))

    def contains_xy(self, points: np.ndarray) -> np.ndarray:
        """(N,) bool: 2D points (N, 2) over the floor."""
        return points_in_polygon(points, self.floor_polygon)


@dataclass(frozen=True)
class RelationTuple:
    """``<dependent, support anchor, optional functional anchor>``, by object id."""

    dependent: str
    support: str
    functional: str | None = None


@dataclass
class Scene:
    id: str
    room: Room
    objects: list[SceneObject] = field(default_factory=list)
    source: str | None = None
    """``ai2thor``, ``procthor``, ``3dfront``, ``generated``..."""
    split: str | None = None
    stats: dict = field(default_factory=dict)
    """Free-form per-scene figures (counts, timings, warnings); written to scene.json."""

    def __post_init__(self) -> None:
        ids = [o.id for o in self.objects]
        if len(set(ids)) != len(ids):
            dup = sorted({i for i in ids if ids.count(i) > 1})
            raise ValueError(f"duplicate object ids: {dup}")

    def by_id(self) -> dict[str, SceneObject]:
        return {o.id: o for o in self.objects}

    def get(self, object_id: str) -> SceneObject:
        for o in self.objects:
            if o.id == object_id:
                return o
        raise KeyError(object_id)

    def children(self, support_id: str) -> list[SceneObject]:
        return [o for o in self.objects if o.support == support_id]

    def support_edges(self) -> list[tuple[str, str]]:
        """(child, parent) for every object resting on another object (not the floor, not
        a wall)."""
        return [(o.id, o.support) for o in self.objects if not is_root(o.support or FLOOR)]

    def tuples(self) -> list[RelationTuple]:
        """One relation tuple per object with a known support, in file order."""
        return [
            RelationTuple(o.id, o.support, o.functional_anchor)
            for o in self.objects
            if o.support is not None
        ]

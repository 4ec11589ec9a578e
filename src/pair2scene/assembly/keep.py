"""Scene completion (``--keep partial.json``): fixed objects, the rest filled in around them.

The partial scene is a scene.json (the contract in architecture.md): its room is the room
and its objects stay exactly where they are. Its objects must not intersect (checked at
mesh level, with the same tolerance as placement); a malformed file or overlapping objects
is a one-line error.

The hierarchy drawn for the room is merged with them (:func:`merge_keep`): a kept object
stands in for a hierarchy node of its category on the same support (the user's bed is the
bed; the pillows drawn for the bed go on it), so nothing is doubled; kept objects the
hierarchy did not ask for simply stay. Rooms parts and structure in the file (walls,
drawers) are not objects to keep and are left out, with a note.
"""

from __future__ import annotations

import itertools
from dataclasses import dataclass, replace
from pathlib import Path

import numpy as np

from pair2scene.assembly.collision import TOLERANCES, MeshWorld, Shape, Tolerances, obb_overlaps
from pair2scene.assets.identity import asset_seed
from pair2scene.assets.mesh import Asset
from pair2scene.categories import SuperCategory, super_category
from pair2scene.errors import UserError
from pair2scene.hierarchy.tree import Hierarchy, Node
from pair2scene.scene.model import FLOOR, Scene, SceneObject

RESTING_M = 0.01
"""An object with no support in the file whose bottom is this near the floor stands on it."""


@dataclass(frozen=True)
class Kept:
    """A partial scene read and checked once: its objects, their assets, the notes."""

    scene: Scene
    assets: dict[str, Asset]
    notes: list[str]


def load_keep(path: str | Path) -> Kept:
    """Read the partial scene, build its objects' assets, and refuse intersecting ones."""
    scene, notes = read_keep(path)
    assets = keep_assets(scene)
    check_overlaps(scene, assets, str(path))
    return Kept(scene, assets, notes)


def read_keep(path: str | Path) -> tuple[Scene, list[str]]:
    """The partial scene (objects to keep only) and notes on what was left out."""
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
    ids = {o.id for o in keep}
    keep = [o if o.support in (None, FLOOR) or o.support in ids else replace(o, support=None)
            for o in keep]  # fmt: skip
    return replace(scene, objects=keep), notes


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


def check_overlaps(
    scene: Scene, assets: dict[str, Asset], where: str, tolerances: Tolerances = TOLERANCES
) -> None:
    """Raise a one-line error naming the first two kept objects that intersect."""
    objs = scene.objects
    if len(objs) < 2:
        return
    centers = np.stack([o.box.center for o in objs])
    halves = np.stack([o.box.half_size for o in objs])
    rots = np.stack([o.box.rotation for o in objs])
    hits = obb_overlaps(centers, halves, rots, centers, halves, rots, tolerances.box_margin)
    world = MeshWorld(tolerances)
    shapes = []
    for o in objs:
        shape = Shape(assets[o.id])
        shape.set_pose(o.box.rotation, o.box.center)
        shapes.append(shape)
    for i, j in itertools.combinations(range(len(objs)), 2):
        if hits[i, j]:
            depth = world.penetration(shapes[i], shapes[j])
            if depth > tolerances.touch:
                raise UserError(
                    f"{where}: kept objects {objs[i].id} and {objs[j].id} intersect "
                    f"({depth * 100:.1f} cm deep); move one of them"
                )


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
    )
    return merged, set(used)

"""Sequential placement with rejection sampling: a hierarchy and the layout model -> a scene.

For each tuple of the hierarchy's sequence (every anchor placed before its dependents):

1. the dependent's size is drawn from the training sizes (:class:`SizeTable`) and its
   procedural asset built (seeded by the object id and the scene seed);
2. one forward pass of the layout model gives the mixture; ``batches x candidates`` boxes
   are drawn at once (conditioned on the asset's size) and turned upright (yaw kept);
3. candidates are tried in the order drawn. Each is dropped onto the surface beneath it
   (:func:`rest_on_surfaces`; the floor for floor tuples, whose footprint must lie in the
   room) and rejected when it is carried by nothing, reaches the ceiling, blocks the
   door's swing, or collides: a vectorised oriented-box test against every placed object
   names the possible contacts, and fcl tests the convex parts of those (contact within
   :attr:`Tolerances.touch` is resting, not colliding);
4. the first valid candidate is placed; after ``batches x candidates`` rejections the
   object is dropped with the reason, and so is everything that rests on it.

Nothing here can loop: every object costs at most one forward pass and a bounded number
of candidates. Same seed, same model, same hierarchy: the same scene.
"""

from __future__ import annotations

import time
from dataclasses import dataclass, field

import numpy as np

from pair2scene.assembly.collision import TOLERANCES, MeshWorld, Shape, Tolerances, obb_overlaps
from pair2scene.assembly.rest import dropped, on_floor, rest_on_surfaces
from pair2scene.assembly.sizes import SizeTable
from pair2scene.assets.mesh import Asset
from pair2scene.curation.physics import asset_seed
from pair2scene.hierarchy.tree import Hierarchy
from pair2scene.scene.geometry import OrientedBox, yaw_to_matrix
from pair2scene.scene.model import FLOOR, AssetRef, Room, Scene, SceneObject


@dataclass(frozen=True)
class AssemblyConfig:
    """How hard placement tries, and how it draws."""

    candidates: int = 32
    """Candidates drawn per batch (all from the one forward pass)."""
    batches: int = 8
    """Batches before an object is dropped: at most ``candidates x batches`` tries."""
    temperature: float = 0.8
    """Sampling temperature: below 1 favours the model's confident modes."""
    door_clearance_m: float = 0.8
    """Depth in front of (and behind) a door that floor objects must leave free."""
    ceiling_margin_m: float = 0.05
    """Objects must end this far below the ceiling."""
    snap_yaw_deg: float = 10.0
    """A drawn yaw within this of the support's axes (every 90 degrees) is snapped onto
    them: three quarters of the training objects are aligned with their support (beds with
    walls, books with shelves), while the logistic samples spread around those modes."""
    tolerances: Tolerances = TOLERANCES


@dataclass
class AssemblyStats:
    """What placing one scene took."""

    requested: int = 0
    placed: int = 0
    resamples: list[int] = field(default_factory=list)
    """Per placed object: candidates rejected before the accepted one."""
    dropped: list[dict] = field(default_factory=list)
    """``{"id", "category", "reason"}`` per object not placed."""
    seconds: dict[str, float] = field(default_factory=dict)
    """model, assets, collision (rest, broad and narrow phase), total."""

    @property
    def acceptance_rate(self) -> float:
        return self.placed / self.requested if self.requested else 1.0

    @property
    def resamples_per_object(self) -> float:
        return float(np.mean(self.resamples)) if self.resamples else 0.0

    def to_dict(self) -> dict:
        return {
            "objects_requested": self.requested,
            "objects_placed": self.placed,
            "acceptance_rate": round(self.acceptance_rate, 4),
            "resamples_per_object": round(self.resamples_per_object, 4),
            "dropped": self.dropped,
            "seconds": {k: round(v, 4) for k, v in self.seconds.items()},
        }


@dataclass
class Placement:
    """A placed scene, what it took, and the assets its objects were placed as (the GLB
    export and physics need the very same meshes)."""

    scene: Scene
    stats: AssemblyStats
    assets: dict[str, Asset]
    """object id -> its asset (local frame; the object's box poses it)."""


@dataclass
class _Placed:
    box: OrientedBox
    asset: Asset


def upright(box: OrientedBox, reference_yaw: float = 0.0, snap_deg: float = 0.0) -> OrientedBox:
    """The box turned upright about its centre, its yaw kept (from the x axis's heading);
    a yaw within ``snap_deg`` of ``reference_yaw`` + k * 90 degrees is snapped onto it."""
    x = box.rotation[:, 0]
    yaw = float(np.arctan2(x[1], x[0])) if np.hypot(x[0], x[1]) > 1e-6 else 0.0
    if snap_deg > 0:
        quarter = np.pi / 2
        k = np.round((yaw - reference_yaw) / quarter)
        snapped = reference_yaw + k * quarter
        if abs(yaw - snapped) <= np.radians(snap_deg):
            yaw = float(snapped)
    return OrientedBox(box.center, box.size, yaw_to_matrix(yaw))


def door_boxes(room: Room, depth: float, height: float) -> list[OrientedBox]:
    """The free space in front of and behind each door (``depth`` each way)."""
    out = []
    for door in room.doors:
        p0, p1 = np.asarray(door.p0, float), np.asarray(door.p1, float)
        along = p1 - p0
        width = float(np.linalg.norm(along))
        if width < 1e-6:
            continue
        yaw = float(np.arctan2(along[1], along[0]))
        mid = (p0 + p1) / 2
        out.append(OrientedBox.from_yaw([*mid, height / 2], [width, 2 * depth, height], yaw))
    return out


def _stack(boxes: list[OrientedBox]) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    if not boxes:
        return np.zeros((0, 3)), np.zeros((0, 3)), np.zeros((0, 3, 3))
    return (
        np.stack([b.center for b in boxes]),
        np.stack([b.half_size for b in boxes]),
        np.stack([b.rotation for b in boxes]),
    )


class Placer:
    """Places hierarchies into rooms with a layout model (see the module docstring)."""

    def __init__(self, model, sizes: SizeTable | None = None, config: AssemblyConfig | None = None):
        self.model = model
        self.sizes = SizeTable.load() if sizes is None else sizes
        self.config = config or AssemblyConfig()

    def place(
        self, hierarchy: Hierarchy, room: Room, seed: int = 0, scene_id: str = "scene"
    ) -> Placement:
        import torch

        from pair2scene.assets.registry import generate
        from pair2scene.model.api import Anchor, PlacementQuery

        cfg = self.config
        start = time.perf_counter()
        timer = {"model": 0.0, "assets": 0.0, "collision": 0.0}
        generator = torch.Generator().manual_seed(seed)
        stats = AssemblyStats(requested=len(hierarchy))
        world = MeshWorld(cfg.tolerances)
        placed: dict[str, _Placed] = {}
        objects: list[SceneObject] = []
        bounds = room.bounds
        doors = _stack(door_boxes(room, cfg.door_clearance_m, room.height))
        n = cfg.candidates * cfg.batches

        for item in hierarchy.sequence():
            node = item.dependent
            if item.support != FLOOR and item.support not in placed:
                stats.dropped.append(
                    {"id": node.id, "category": node.category,
                     "reason": f"its support {item.support} was dropped"}
                )  # fmt: skip
                continue
            t0 = time.perf_counter()
            obj_rng = np.random.default_rng(asset_seed(node.id, seed))
            size = self.sizes.draw(node.category, obj_rng)
            asset = generate(node.category, size, obj_rng)
            timer["assets"] += time.perf_counter() - t0

            if item.support == FLOOR:
                support = Anchor.floor(bounds)
            else:
                sp = placed[item.support]
                support = Anchor(sp.asset.category, sp.box, asset=sp.asset)
            functional = None
            if item.functional is not None and item.functional in placed:
                fp = placed[item.functional]
                functional = Anchor(fp.asset.category, fp.box, asset=fp.asset)
            query = PlacementQuery(node.category, asset.size, support, functional, bounds,
                                   asset=asset)  # fmt: skip
            t0 = time.perf_counter()
            boxes = self.model.sample(query, n, cfg.temperature, generator)
            timer["model"] += time.perf_counter() - t0

            t0 = time.perf_counter()
            ref_yaw = 0.0 if item.support == FLOOR else placed[item.support].box.yaw
            shape = Shape(asset)
            ids = list(placed)  # fixed while this object's candidates are tried
            others = _stack([placed[i].box for i in ids])
            accepted = None
            for index, vec in enumerate(boxes):
                drawn = upright(OrientedBox.from_vector(vec), ref_yaw, cfg.snap_yaw_deg)
                box = OrientedBox(drawn.center, asset.size, drawn.rotation)  # the asset's own
                box = self._rest(box, item.support, placed, room)
                if box is None or box.top > room.height - cfg.ceiling_margin_m:
                    continue
                center, half, rot = box.center[None], box.half_size[None], box.rotation[None]
                if item.support == FLOOR and len(doors[0]):
                    if obb_overlaps(center, half, rot, *doors, cfg.tolerances.box_margin).any():
                        continue
                hits = obb_overlaps(center, half, rot, *others, cfg.tolerances.box_margin)[0]
                near = [ids[j] for j in np.flatnonzero(hits)]
                if near:
                    shape.set_pose(box.rotation, box.center)
                    if world.colliding(shape, near):
                        continue
                accepted = (index, box)
                break
            timer["collision"] += time.perf_counter() - t0
            if accepted is None:
                stats.dropped.append(
                    {"id": node.id, "category": node.category,
                     "reason": f"no valid placement among {n} candidates"}
                )  # fmt: skip
                continue
            index, box = accepted
            shape.set_pose(box.rotation, box.center)
            world.add(node.id, shape)
            placed[node.id] = _Placed(box, asset)
            stats.resamples.append(index)
            objects.append(
                SceneObject(
                    node.id, node.category, box,
                    AssetRef(asset.source, asset.asset_id, asset.style),
                    support=item.support,
                    functional_anchor=item.functional if item.functional in placed else None,
                )
            )  # fmt: skip
        stats.placed = len(objects)
        stats.seconds = {**timer, "total": time.perf_counter() - start}
        scene = Scene(scene_id, room, objects, source="pair2scene", stats=stats.to_dict())
        return Placement(scene, stats, {oid: p.asset for oid, p in placed.items()})

    @staticmethod
    def _rest(box: OrientedBox, support: str, placed: dict, room: Room) -> OrientedBox | None:
        """The candidate dropped onto what carries it, or None."""
        if support == FLOOR:
            box = dropped(box, 0.0)
            return box if on_floor(box, room.floor_polygon) else None
        sp = placed[support]
        z = rest_on_surfaces(sp.asset, sp.box, box)
        return None if z is None else dropped(box, z)

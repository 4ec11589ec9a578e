"""From relation tuples to the layout model's inputs: clouds, boxes, targets, Jacobians.

The one place that turns 3D-Pairs tuples (training, scoring) or live anchors (generation)
into what :class:`~pair2scene.model.layout.LayoutPredictor` reads, so both paths agree.

Model frame (what the network predicts in)
------------------------------------------
The stored target is the dependent's box in the support anchor's canonical frame
(:meth:`OrientedBox.in_frame_of`: centred, rotation removed, divided by the anchor's
half-size). A thin support breaks that scale: AI2-THOR counter tops are 1.7 cm slabs,
so an object on one has a canonical height in the hundreds. The network therefore
predicts in the *model frame*, the canonical frame with each anchor half-size floored
at :data:`MIN_ANCHOR_HALF_M`::

    f_i = h_i / max(h_i, MIN_ANCHOR_HALF_M)        per axis, h = support half-size (m)
    y = (f * centre, log(f * size), 6D)            stored x = (centre, size, 6D)

``f`` is 1 for every support thicker than 10 cm along an axis (the room, tables, beds),
so the model frame is the canonical frame there. Scores stay densities of the stored
vector: ``log p_x = log p_y + sum(log f) - sum(log size)`` (:attr:`TupleArrays.log_jacobian`).

``global`` predicts the dependent's *world* box ``w = (centre, log size, 6D)`` from the
room; the stored canonical vector is a linear map of the world one (centre and size
divided by the support's half-size ``h`` after removing its rotation), so
``log p_x = log p_w - sum(log world size) + 2 sum(log h)``.

Anchor frames (issue 18)
------------------------
With :attr:`LayoutConfig.anchor_frames` a tuple is predicted in the frame of the anchor
that governs it (:func:`~pair2scene.curation.frames.frame_choice`), not always its support's:

- a floor object standing against a wall (the tuple's ``wall_box``): the wall's frame,
  x along the wall (in units of its half-length), y metres into the room, z the room's
  height; "back to the wall, facing in" is one narrow mode there;
- else a floor object with a functional anchor: the anchor's *footprint frame*
  (:func:`~pair2scene.curation.frames.footprint_frame`: its centre, yaw and width/depth,
  z the room's height), so
  "a chair in front of the table, facing it" is local to the table;
- else its support's frame, as before.

In a functional anchor's frame the rotation is taken relative to the *bearing* of the
anchor (:func:`to_bearing`): turned about z so that +y points from the dependent's centre
to the anchor's. Chairs stand on every side of a table, each facing it: as absolute yaws
in the table's frame that is four (position, yaw) modes a per-dimension mixture has to
couple, relative to the bearing it is one yaw (measured: raw draws of the model without
it faced the table 26 % of the time, the per-pair Gaussian with full covariances 89 %).
The map is a rotation of the 6D part by an angle that depends on the centre only, so its
Jacobian is 1.

The support anchor (the room) joins as an anchor box in that frame, the functional
anchor too. Scores stay densities of the stored canonical vector: from the stored
support frame to another frame is an affine map with a constant Jacobian (centre:
``prod(h_support) / prod(h_frame)``; size: the same per axis; rotation: a rotation), so
``log p_x = log p_y + sum(log f) + sum(log h_s) - sum(log h_f) - sum(log size)`` with
``f`` the frame's model-frame factor.

Geometry
--------
Each member's cloud is sampled from its procedural asset (the same seed per object id
as the curation's physics check, and the shelf tiers fitted to where the tuples' objects
rest), in the object's local frame, normalised by its box
(:func:`~pair2scene.model.pointmae.normalise_points`). The floor's geometry is the room:
its floor rectangle and its four walls (:func:`room_points`), so "against a wall" is
visible to the encoder.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from pair2scene.assets.identity import asset_seed
from pair2scene.assets.mesh import Asset
from pair2scene.assets.pointcloud import sample_asset
from pair2scene.categories import UNKNOWN
from pair2scene.curation.dataset import CATEGORY_VOCAB, PairsDataset
from pair2scene.curation.frames import (
    FRAME_FUNCTIONAL,
    FRAME_SUPPORT,
    canonical_to_frame,
    tuple_frames,
)
from pair2scene.model.config import (
    BOX_DIM,
    FUNCTIONAL,
    MIN_ANCHOR_HALF_M,
    MIN_HALF_DIAGONAL,
    MIN_TARGET_SIZE,
    SUPPORT,
    LayoutVariant,
)
from pair2scene.progress import track
from pair2scene.scene.geometry import OrientedBox
from pair2scene.scene.model import FLOOR, WALL

if TYPE_CHECKING:  # torch is imported by what trains or scores, not by generation
    import torch

    from pair2scene.model.layout import LayoutBatch

CANONICAL_EPS = 1e-9
"""The floor :meth:`OrientedBox.in_frame_of` puts on half-sizes (its ``eps``)."""
CLOUD_SEED = 0
"""Seed of the surface sampling of every member's cloud (the asset has its own seed)."""
_CAT_INDEX = {c: i for i, c in enumerate(CATEGORY_VOCAB)}
_UNIT_CUBE = np.array([0, 0, 0, 2, 2, 2, 1, 0, 0, 0, 1, 0], dtype=np.float32)


def category_index(name: str) -> int:
    """Row of ``name`` in :data:`CATEGORY_VOCAB` (``unknown`` for names not in it)."""
    return _CAT_INDEX.get(name, _CAT_INDEX[UNKNOWN])


# -- the model frame ----------------------------------------------------------------------


def frame_factor(support_size: np.ndarray) -> np.ndarray:
    """f = h / max(h, MIN_ANCHOR_HALF_M) per axis: (..., 3) support sizes (m) -> (..., 3)."""
    half = np.maximum(0.5 * np.asarray(support_size, dtype=np.float64), CANONICAL_EPS)
    return half / np.maximum(half, MIN_ANCHOR_HALF_M)


def to_model_frame(canonical: np.ndarray, factor: np.ndarray) -> np.ndarray:
    """Stored canonical boxes (..., 12) (centre, size, 6D) -> model-frame boxes, same layout."""
    out = np.array(canonical, dtype=np.float64)
    out[..., 0:3] *= factor
    out[..., 3:6] *= factor
    return out


def from_model_frame(boxes: np.ndarray, factor: np.ndarray) -> np.ndarray:
    """Inverse of :func:`to_model_frame`: (..., 12) model-frame boxes -> canonical boxes."""
    out = np.array(boxes, dtype=np.float64)
    out[..., 0:3] /= factor
    out[..., 3:6] /= factor
    return out


def target_of(boxes: np.ndarray) -> np.ndarray:
    """Box vectors (..., 12) (centre, size, 6D) -> model targets (centre, log size, 6D)."""
    out = np.array(boxes, dtype=np.float64)
    out[..., 3:6] = np.log(np.maximum(out[..., 3:6], MIN_TARGET_SIZE))
    return out


def box_of(target: np.ndarray) -> np.ndarray:
    """Model targets or samples (..., 12) -> box vectors (centre, size, 6D); the 6D part is
    left as drawn (:meth:`OrientedBox.from_vector` orthonormalises it)."""
    out = np.array(target, dtype=np.float64)
    out[..., 3:6] = np.exp(out[..., 3:6])
    return out


# -- anchor frames ------------------------------------------------------------------------


def bearing_yaw(center: np.ndarray) -> np.ndarray:
    """(...,) yaw whose +y axis points from ``center`` (..., >=2, metres in the anchor's
    frame, the anchor at the origin) to the anchor; 0 at the anchor's centre."""
    c = np.asarray(center, np.float64)
    near = np.hypot(c[..., 0], c[..., 1]) < 1e-6
    return np.where(near, 0.0, np.arctan2(c[..., 0], -c[..., 1]))


def _turn_6d(boxes: np.ndarray, yaw: np.ndarray) -> np.ndarray:
    out = np.array(boxes, dtype=np.float64)
    cos, sin = np.cos(yaw)[..., None], np.sin(yaw)[..., None]
    for k in (6, 9):
        x, y = out[..., k : k + 1].copy(), out[..., k + 1 : k + 2].copy()
        out[..., k : k + 1] = cos * x - sin * y
        out[..., k + 1 : k + 2] = sin * x + cos * y
    return out


def to_bearing(canonical: np.ndarray, half: np.ndarray) -> np.ndarray:
    """Boxes (..., 12) in a functional anchor's frame (canonical, the anchor's half-size
    ``half`` (..., 3)) with the rotation taken relative to the anchor's bearing (the
    module docstring)."""
    yaw = bearing_yaw(np.asarray(canonical)[..., :2] * np.asarray(half)[..., :2])
    return _turn_6d(canonical, -yaw)


def from_bearing(boxes: np.ndarray, half: np.ndarray) -> np.ndarray:
    """Inverse of :func:`to_bearing`."""
    yaw = bearing_yaw(np.asarray(boxes)[..., :2] * np.asarray(half)[..., :2])
    return _turn_6d(boxes, yaw)


# -- geometry -----------------------------------------------------------------------------


def room_points(size: Sequence[float], n: int, rng: np.random.Generator | int) -> np.ndarray:
    """``n`` points on a room's floor and four walls, area-weighted: (n, 3), centred frame.

    size : (3,) the room's bounds (x, y, height); the ceiling is left open, as a top view
    of a room would show it.
    """
    rng = rng if isinstance(rng, np.random.Generator) else np.random.default_rng(rng)
    sx, sy, sz = (max(float(v), 1e-3) for v in size)
    hx, hy, hz = sx / 2, sy / 2, sz / 2
    areas = np.array([sx * sy, sx * sz, sx * sz, sy * sz, sy * sz])
    face = rng.choice(5, size=n, p=areas / areas.sum())
    u, v = rng.uniform(-1, 1, n), rng.uniform(-1, 1, n)
    pts = np.empty((n, 3))
    pts[:, 0], pts[:, 1], pts[:, 2] = u * hx, v * hy, -hz  # floor
    for f, y in ((1, -hy), (2, hy)):  # back and front walls
        m = face == f
        pts[m] = np.stack([u[m] * hx, np.full(m.sum(), y), v[m] * hz], 1)
    for f, x in ((3, -hx), (4, hx)):  # left and right walls
        m = face == f
        pts[m] = np.stack([np.full(m.sum(), x), u[m] * hy, v[m] * hz], 1)
    return pts


def wall_points(size: Sequence[float], n: int, rng: np.random.Generator | int) -> np.ndarray:
    """``n`` points on a wall and the floor in front of it, area-weighted: (n, 3) in the
    wall's frame (:meth:`~pair2scene.scene.walls.Wall.frame`: the wall is the plane y = 0,
    x along it, the room at y > 0, the floor at z = -height / 2)."""
    rng = rng if isinstance(rng, np.random.Generator) else np.random.default_rng(rng)
    sx, sy, sz = (max(float(v), 1e-3) for v in size)
    on_wall = rng.random(n) < sz / (sz + sy / 2)
    u, v = rng.uniform(-0.5, 0.5, n), rng.uniform(0.0, 1.0, n)
    pts = np.empty((n, 3))
    pts[:, 0] = u * sx
    pts[:, 1] = np.where(on_wall, 0.0, v * sy / 2)
    pts[:, 2] = np.where(on_wall, (v - 0.5) * sz, -sz / 2)
    return pts


def normalised(points: np.ndarray, size: Sequence[float]) -> np.ndarray:
    """A local-frame cloud (N, 3) normalised by its box ``size`` (3,): (N, 3) float32;
    :func:`~pair2scene.model.pointmae.normalise_points` in float64 numpy."""
    size = np.asarray(size, dtype=np.float64)
    half_diag = max(0.5 * float(np.sqrt((size * size).sum())), MIN_HALF_DIAGONAL)
    return (np.asarray(points, dtype=np.float64) / half_diag).astype(np.float32)


def asset_cloud(asset: Asset, n: int, seed: int = CLOUD_SEED) -> np.ndarray:
    """The normalised cloud (n, 3) float32 of an asset (outer surface, local frame)."""
    pts, _ = sample_asset(asset, n, np.random.default_rng(seed))
    return normalised(pts, asset.size)


def room_cloud(size: Sequence[float], n: int, seed: int = CLOUD_SEED) -> np.ndarray:
    """The normalised cloud (n, 3) float32 of a room of bounds ``size`` (the floor's)."""
    return normalised(room_points(size, n, seed), size)


def wall_cloud(size: Sequence[float], n: int, seed: int = CLOUD_SEED) -> np.ndarray:
    """The normalised cloud (n, 3) float32 of a wall whose frame has ``size``."""
    return normalised(wall_points(size, n, seed), size)


@dataclass(frozen=True)
class CloudSpec:
    """What one member's cloud is made from (hashable: equal specs share a cloud)."""

    category: str
    size: tuple[float, float, float]
    """Box size (m); for the floor, the room's bounds."""
    seed: int
    """Asset seed (:func:`~pair2scene.assets.identity.asset_seed` of the object id, as
    the curation's physics check draws it)."""
    support_heights: tuple[float, ...] = ()
    """Heights above the bottom where the data's objects rest on it (shelf tiers)."""
    room: bool = False
    """The floor: the room's floor and walls instead of an asset."""

    def cloud(self, n: int) -> np.ndarray:
        """(n, 3) float32 normalised cloud."""
        if self.room:
            return room_cloud(self.size, n)
        if self.category == WALL:  # the support of a mounted object: its wall's frame
            return wall_cloud(self.size, n)
        from pair2scene.assets.registry import generate

        heights = list(self.support_heights) or None
        category = self.category if self.category in _CAT_INDEX else UNKNOWN
        asset = generate(category, self.size, np.random.default_rng(self.seed),
                         support_heights=heights)  # fmt: skip
        return asset_cloud(asset, n)


# -- tuples -> arrays ---------------------------------------------------------------------


@dataclass
class TupleArrays:
    """The layout model's inputs for N tuples, as numpy arrays (see layout.py's docstring).

    Members: 0 dependent, 1 support anchor (``global``: the room), 2 functional anchor.
    """

    categories: np.ndarray
    """(N, 3) int64 category rows (0 where absent)."""
    scales: np.ndarray
    """(N, 3, 3) float32 member box sizes (m); 1 where absent."""
    anchor_boxes: np.ndarray
    """(N, 2, 12) float32 anchors' boxes in the model frame (``global``: row 0 the room's
    world box), stored layout (centre, size, 6D); 0 where absent."""
    member_mask: np.ndarray
    """(N, 3) bool."""
    cloud_index: np.ndarray
    """(N, 3) int64 row of each member's cloud in the cloud table; -1 absent or none."""
    target: np.ndarray
    """(N, 12) float32 model target (centre, log size, 6D) in the model frame."""
    log_jacobian: np.ndarray
    """(N,) float64: log p(stored canonical vector) = log p(target) + log_jacobian."""
    factor: np.ndarray
    """(N, 3) float64 model-frame factor f of each tuple's support (1 for ``global``)."""
    size_log_jacobian: np.ndarray
    """(N,) float64: log p(stored canonical size) = log p(target size dims) + this
    (``-sum(log size)``: the target's size is the log of the stored one times a constant)."""
    frames: np.ndarray | None = None
    """(N,) int64 frame kind of each tuple (:func:`~pair2scene.curation.frames.frame_choice`);
    None: the support's."""
    frame_sizes: np.ndarray | None = None
    """(N, 3) float32 size of each tuple's frame box (m); None: the support's."""

    def __len__(self) -> int:
        return len(self.categories)

    def batch(
        self,
        rows: np.ndarray,
        tokens: torch.Tensor | None = None,
        centers: torch.Tensor | None = None,
        points: torch.Tensor | None = None,
        with_target: bool = True,
    ) -> LayoutBatch:
        """The tuples ``rows`` as a :class:`LayoutBatch`.

        tokens, centers : (C, G, D), (C, G, 3) the cloud table's cached encoder output;
        points : (C, N, 3) the raw normalised clouds (an encoder that trains needs them).
        """
        import torch

        from pair2scene.model.layout import LayoutBatch

        idx = torch.from_numpy(np.maximum(self.cloud_index[rows], 0))  # (B, 3)
        batch = LayoutBatch(
            categories=torch.from_numpy(self.categories[rows]),
            scales=torch.from_numpy(self.scales[rows]),
            anchor_boxes=torch.from_numpy(self.anchor_boxes[rows]),
            member_mask=torch.from_numpy(self.member_mask[rows]),
            target=torch.from_numpy(self.target[rows]) if with_target else None,
        )
        if self.frames is not None:
            batch.frames = torch.from_numpy(self.frames[rows])
            batch.frame_sizes = torch.from_numpy(self.frame_sizes[rows])
        if tokens is not None:
            batch.point_tokens = tokens[idx]  # (B, 3, G, D)
            batch.point_centers = centers[idx]  # (B, 3, G, 3)
        elif points is not None:
            batch.points = points[idx]  # (B, 3, N, 3)
        return batch


@dataclass
class Features:
    """The inputs of a set of tuples and the clouds they refer to."""

    arrays: TupleArrays
    clouds: list[CloudSpec]
    """The cloud table: ``arrays.cloud_index`` points into it."""


def _bottoms(boxes: np.ndarray) -> np.ndarray:
    """World z of the bottom of boxes (N, 12) (centre, size, 6D): (N,)."""
    from pair2scene.scene.geometry import sixd_to_matrix

    rot = sixd_to_matrix(boxes[:, 6:12].astype(np.float64))  # (N, 3, 3)
    extent = 0.5 * (np.abs(rot[:, 2, :]) * boxes[:, 3:6]).sum(-1)  # (N,) half height
    return boxes[:, 2] - extent


def room_boxes(data: PairsDataset) -> dict[str, np.ndarray]:
    """scene id -> the room's world box (12,): the support box of its floor tuples, or
    the extent of its boxes when no tuple rests on the floor."""
    out: dict[str, np.ndarray] = {}
    floor_rows = np.flatnonzero(data.support.id == FLOOR)
    for i in floor_rows:
        out.setdefault(str(data.scene_id[i]), data.support.box[i].astype(np.float64))
    for scene in set(data.scene_id.tolist()) - set(out):
        rows = data.scene_id == scene
        boxes = np.concatenate([data.dependent.box[rows], data.support.box[rows]])
        corners = np.concatenate([b.corners() for b in map(OrientedBox.from_vector, boxes)])
        lo, hi = corners.min(0), corners.max(0)
        lo[2] = 0.0
        out[scene] = np.concatenate([(lo + hi) / 2, hi - lo, _UNIT_CUBE[6:]]).astype(np.float64)
    return out


def _support_heights(data: PairsDataset) -> dict[tuple[str, str], tuple[float, ...]]:
    """(scene, support id) -> sorted distinct heights above the support's bottom where the
    tuples' dependents rest on it (rounded to 1 mm)."""
    dep_bottom = _bottoms(data.dependent.box)
    sup_bottom = _bottoms(data.support.box)
    heights: dict[tuple[str, str], set[float]] = {}
    for i in np.flatnonzero(data.support.id != FLOOR):
        key = (str(data.scene_id[i]), str(data.support.id[i]))
        heights.setdefault(key, set()).add(round(float(dep_bottom[i] - sup_bottom[i]), 3))
    return {k: tuple(sorted(v)) for k, v in heights.items()}


def dataset_features(
    data: PairsDataset,
    variant: LayoutVariant | str,
    with_clouds: bool = True,
    anchor_frames: bool = False,
) -> Features:
    """Inputs of every tuple of ``data`` for ``variant`` (see the module docstring);
    ``anchor_frames``: each tuple in its governing anchor's frame (ignored by
    ``global``)."""
    variant = LayoutVariant(variant)
    n = len(data)
    is_global = variant is LayoutVariant.GLOBAL
    rooms = room_boxes(data) if is_global else {}
    heights = _support_heights(data) if with_clouds else {}
    names = data.categories
    members = (data.dependent, data.support, data.functional)

    categories = np.zeros((n, 3), np.int64)
    scales = np.ones((n, 3, 3), np.float32)
    mask = np.zeros((n, 3), bool)
    for m, arr in enumerate(members):
        present = arr.category >= 0
        mask[:, m] = present
        rows = np.flatnonzero(present)
        categories[rows, m] = [category_index(names[c]) for c in arr.category[rows]]
        scales[rows, m] = arr.box[rows, 3:6]
    anchor_boxes = np.zeros((n, 2, BOX_DIM), np.float32)

    sup_box = data.support.box.astype(np.float64)
    frames = frame_sizes = None
    if is_global:
        room = np.stack([rooms[str(s)] for s in data.scene_id]) if n else np.zeros((0, 12))
        categories[:, SUPPORT] = category_index(FLOOR)
        scales[:, SUPPORT] = room[:, 3:6]
        mask[:, FUNCTIONAL] = False
        anchor_boxes[:, 0] = room
        factor = np.ones((n, 3))
        dep = data.dependent.box.astype(np.float64)
        target = target_of(dep)
        half = np.maximum(0.5 * sup_box[:, 3:6], CANONICAL_EPS)
        log_jac = -np.log(np.maximum(dep[:, 3:6], MIN_TARGET_SIZE)).sum(1)
        log_jac += 2 * np.log(half).sum(1)
    elif anchor_frames:
        frames, frame_box = tuple_frames(data)
        frame_sizes = frame_box[:, 3:6].astype(np.float32)
        factor = frame_factor(frame_box[:, 3:6])
        anchor_boxes[:, 0] = to_model_frame(np.broadcast_to(_UNIT_CUBE, (n, 12)), factor)
        canonical = data.canonical.astype(np.float64)
        own = canonical.copy()  # the dependent in its frame (the stored one: the support's)
        part_jac = np.zeros(n)  # sum log h_support - sum log h_frame
        moved = np.flatnonzero(frames != FRAME_SUPPORT)
        if len(moved):
            pair = (sup_box[moved], frame_box[moved])
            own[moved], part_jac[moved] = canonical_to_frame(canonical[moved], *pair)
            room = canonical_to_frame(np.broadcast_to(_UNIT_CUBE, (len(moved), 12)), *pair)[0]
            anchor_boxes[moved, 0] = to_model_frame(room, factor[moved])
        bearing = np.flatnonzero(frames == FRAME_FUNCTIONAL)
        own[bearing] = to_bearing(own[bearing], 0.5 * frame_box[bearing, 3:6])
        for i in np.flatnonzero(mask[:, FUNCTIONAL]):
            frame = OrientedBox.from_vector(frame_box[i])
            func = OrientedBox.from_vector(data.functional.box[i].astype(np.float64))
            anchor_boxes[i, 1] = to_model_frame(func.in_frame_of(frame).to_vector(), factor[i])
        target = target_of(to_model_frame(own, factor))
        log_jac = np.log(factor).sum(1) + part_jac
        log_jac -= np.log(np.maximum(canonical[:, 3:6], MIN_TARGET_SIZE)).sum(1)
    else:
        factor = frame_factor(sup_box[:, 3:6])
        anchor_boxes[:, 0] = to_model_frame(np.broadcast_to(_UNIT_CUBE, (n, 12)), factor)
        func_rows = np.flatnonzero(mask[:, FUNCTIONAL])
        for i in func_rows:
            sup = OrientedBox.from_vector(sup_box[i])
            func = OrientedBox.from_vector(data.functional.box[i].astype(np.float64))
            anchor_boxes[i, 1] = to_model_frame(func.in_frame_of(sup).to_vector(), factor[i])
        canonical = data.canonical.astype(np.float64)
        target = target_of(to_model_frame(canonical, factor))
        log_jac = np.log(factor).sum(1)
        log_jac -= np.log(np.maximum(canonical[:, 3:6], MIN_TARGET_SIZE)).sum(1)

    cloud_index = np.full((n, 3), -1, np.int64)
    specs: dict[CloudSpec, int] = {}
    if with_clouds and variant is not LayoutVariant.CLASS_ONLY:
        for i in range(n):
            scene = str(data.scene_id[i])
            for m, arr in enumerate(members):
                if not mask[i, m]:
                    continue
                if m == SUPPORT and is_global:
                    spec = CloudSpec(FLOOR, _size3(rooms[scene][3:6]), 0, room=True)
                elif arr.id[i] == FLOOR:
                    spec = CloudSpec(FLOOR, _size3(arr.box[i, 3:6]), 0, room=True)
                elif names[arr.category[i]] == WALL:
                    spec = CloudSpec(WALL, _size3(arr.box[i, 3:6]), 0)
                else:
                    oid = str(arr.id[i])
                    spec = CloudSpec(
                        names[arr.category[i]],
                        _size3(arr.box[i, 3:6]),
                        asset_seed(oid),
                        heights.get((scene, oid), ()),
                    )
                cloud_index[i, m] = specs.setdefault(spec, len(specs))
    arrays = TupleArrays(
        categories=categories,
        scales=scales,
        anchor_boxes=anchor_boxes,
        member_mask=mask,
        cloud_index=cloud_index,
        target=target.astype(np.float32),
        log_jacobian=log_jac,
        factor=factor,
        size_log_jacobian=-np.log(
            np.maximum(data.canonical[:, 3:6].astype(np.float64), MIN_TARGET_SIZE)
        ).sum(1),
        frames=frames,
        frame_sizes=frame_sizes,
    )
    return Features(arrays, list(specs))


def _size3(size: np.ndarray) -> tuple[float, float, float]:
    # Rounded to 0.1 mm so that float32 noise never splits one object into two clouds.
    s = np.round(np.asarray(size, dtype=np.float64), 4)
    return (float(s[0]), float(s[1]), float(s[2]))


def build_clouds(specs: Sequence[CloudSpec], n_points: int, progress: bool = False) -> np.ndarray:
    """The normalised clouds of ``specs``: (C, n_points, 3) float32."""
    out = np.zeros((len(specs), n_points, 3), np.float32)
    for i, spec in enumerate(track(specs, "building clouds", enabled=progress)):
        out[i] = spec.cloud(n_points)
    return out


def encode_clouds(
    encoder: torch.nn.Module,
    clouds: np.ndarray | torch.Tensor,
    batch_size: int = 64,
    progress: bool = False,
) -> tuple[torch.Tensor, torch.Tensor]:
    """Encoder tokens and group centres of clouds (C, N, 3): ((C, G, D), (C, G, 3)).

    Deterministic (farthest point sampling starts at point 0); the encoder runs in eval
    mode and is left in the mode it was in.
    """
    import torch

    was_training = encoder.training
    if was_training:  # (eval() walks every module: not for each of a scene's clouds)
        encoder.eval()
    clouds = torch.as_tensor(clouds)
    tokens, centers = [], []
    starts = range(0, len(clouds), batch_size)
    for s in track(starts, "encoding clouds", enabled=progress):
        with torch.no_grad():
            t, c = encoder(clouds[s : s + batch_size])
        tokens.append(t)
        centers.append(c)
    if was_training:
        encoder.train()
    if not tokens:
        width = encoder.config.width
        g = encoder.config.n_groups
        return torch.zeros(0, g, width), torch.zeros(0, g, 3)
    return torch.cat(tokens), torch.cat(centers)

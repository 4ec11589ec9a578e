"""Collision tests for placement: a vectorised oriented-box broad phase, an fcl narrow phase.

- :func:`obb_overlaps` tests N candidate boxes against M placed boxes at once with the
  separating axis theorem (15 axes per pair: 3 + 3 face normals and 9 edge cross
  products), in numpy. Boxes are shrunk by a margin first, so boxes that merely touch
  (a mug on a table, books side by side) do not overlap.
- :class:`MeshWorld` keeps one persistent python-fcl collision object per convex part of
  every placed asset (procedural assets are unions of convex parts, so concave furniture
  collides as itself: a chair tucked between a table's legs is free). A candidate is
  posed with ``setTransform`` and tested against the parts of the objects the broad phase
  named; contacts shallower than :attr:`Tolerances.touch` count as touching, not
  colliding.
"""

from __future__ import annotations

import math
from collections.abc import Iterable
from dataclasses import dataclass

import numpy as np

from pair2scene.assets.mesh import Asset
from pair2scene.errors import UserError
from pair2scene.scene.geometry import convex_hull_2d

MAX_TOLERANCE_M = 0.005
"""Largest contact tolerance and broad-phase margin :class:`Tolerances` accepts: the
penetration `pair2scene evaluate` counts as an intersection."""


@dataclass(frozen=True)
class Tolerances:
    """Collision tolerances (metres), with the reason for each."""

    touch: float = 2e-3
    """Penetration up to this is contact, not collision: objects rest on and lean against
    each other, and a gravity drop lands exactly on a surface, where float noise in a
    convex-convex test reports ~1e-6 m overlaps."""
    box_margin: float = 2e-4
    """Broad phase: boxes are shrunk by this on every side before the overlap test, so that
    a box dropped exactly onto another's top is not a candidate pair (float noise). Kept
    far below ``touch``: a larger shrink hides thin objects (a 1 mm CD under a book)."""
    thin_fraction: float = 0.25
    """For a thin object the contact tolerance is at most this share of the thinner
    object's smallest extent: 2 mm of overlap is contact for books, but a credit card
    2 mm inside a book is in it."""

    def __post_init__(self) -> None:
        # A larger tolerance would let placement keep what `evaluate` counts as
        # intersecting (COLLISION_DEPTH_M, 5 mm): collisions passed off as contact.
        bounds = {"touch": MAX_TOLERANCE_M, "box_margin": MAX_TOLERANCE_M, "thin_fraction": 1.0}
        for name, top in bounds.items():
            value = getattr(self, name)
            if not (math.isfinite(value) and 0 <= value <= top):
                flag = "--assembly.tolerances." + name.replace("_", "-")
                raise UserError(f"{flag} must be in 0 .. {top}, got {value}")


TOLERANCES = Tolerances()

AABB_SLACK = 1e-6
"""m added to every axis-aligned bound before the cheap pre-tests (boxes in
:func:`obb_overlaps`, convex parts in :class:`MeshWorld`): far below any tolerance, far
above float rounding, so the pre-tests never drop a pair the exact tests would keep."""
PART_SLACK = 1e-5
"""m; convex parts whose bounds are farther apart than this are never handed to fcl
(its GJK reports no contact beyond its own ~1e-6 tolerance)."""


def _fcl():
    try:
        import fcl
    except ImportError as exc:  # pragma: no cover - depends on the environment
        raise UserError("mesh collision needs python-fcl: pip install python-fcl") from exc
    return fcl


def obb_overlaps(
    centers_a: np.ndarray,
    halves_a: np.ndarray,
    rots_a: np.ndarray,
    centers_b: np.ndarray,
    halves_b: np.ndarray,
    rots_b: np.ndarray,
    margin: float = 0.0,
) -> np.ndarray:
    """Whether each of N boxes overlaps each of M boxes: (N, M) bool.

    centers : (N, 3) / (M, 3); halves : half-sizes (N, 3) / (M, 3), each shrunk by
    ``margin`` (floored at 0); rots : (N, 3, 3) / (M, 3, 3), columns the local axes in
    world coordinates. Exact for boxes (separating axis theorem); degenerate cross-product
    axes (parallel edges) are skipped, which is exact too since their planes are among the
    face normals.
    """
    return BoxSet(centers_b, halves_b, rots_b, margin).overlaps(centers_a, halves_a, rots_a)


class BoxSet:
    """M boxes stacked for :func:`obb_overlaps`, kept to test candidate after candidate
    against them (placement's placed objects and door zones): their shrunk half-sizes and
    axis-aligned extents are worked out once."""

    def __init__(
        self, centers: np.ndarray, halves: np.ndarray, rots: np.ndarray, margin: float = 0.0
    ) -> None:
        self.margin = margin
        self.centers = np.asarray(centers, float).reshape(-1, 3)
        self.halves = np.maximum(np.asarray(halves, float).reshape(-1, 3) - margin, 0.0)
        self.rots = np.asarray(rots, float).reshape(-1, 3, 3)
        # Half extent along world axis i: sum_j |R_ij| h_j.
        self.extents = np.einsum("mij,mj->mi", np.abs(self.rots), self.halves) + AABB_SLACK

    def __len__(self) -> int:
        return len(self.centers)

    @classmethod
    def growing(cls, margin: float = 0.0, capacity: int = 64) -> BoxSet:
        """An empty set to :meth:`add` boxes to one at a time (placement's placed objects:
        each new object is tested against all before it, and restacking them all for each
        one made the work grow with the square of the objects)."""
        out = cls(np.zeros((0, 3)), np.zeros((0, 3)), np.zeros((0, 3, 3)), margin)
        out._rows = {
            "centers": np.zeros((capacity, 3)), "halves": np.zeros((capacity, 3)),
            "rots": np.zeros((capacity, 3, 3)), "extents": np.zeros((capacity, 3)),
        }  # fmt: skip
        return out

    def add(self, center: np.ndarray, half: np.ndarray, rot: np.ndarray) -> None:
        """Keep one more box (a set made by :meth:`growing`): the same rows as a set made
        of all the boxes at once."""
        row = BoxSet(center, half, rot, self.margin)
        m = len(self.centers)
        if m == len(self._rows["centers"]):  # full: twice the room
            self._rows = {k: np.concatenate([v, np.zeros_like(v)]) for k, v in self._rows.items()}
        for name in self._rows:
            self._rows[name][m] = getattr(row, name)[0]
        self.centers, self.halves, self.rots, self.extents = (
            self._rows[name][: m + 1] for name in ("centers", "halves", "rots", "extents")
        )

    def snapshot(self) -> BoxSet:
        """The boxes kept so far, as a set of their own that later :meth:`add` calls leave
        as it is (it shares their rows)."""
        out = BoxSet.__new__(BoxSet)
        out.margin = self.margin
        out.centers, out.halves, out.rots, out.extents = (
            self.centers,
            self.halves,
            self.rots,
            self.extents,
        )
        return out

    def overlaps(self, centers: np.ndarray, halves: np.ndarray, rots: np.ndarray) -> np.ndarray:
        """(N, M) whether each of N boxes (shrunk by the same margin) overlaps each kept
        one."""
        ca = np.asarray(centers, float).reshape(-1, 3)
        ha = np.maximum(np.asarray(halves, float).reshape(-1, 3) - self.margin, 0.0)
        ra = np.asarray(rots, float).reshape(-1, 3, 3)
        n, m = len(ca), len(self.centers)
        out = np.zeros((n, m), bool)
        if n == 0 or m == 0:
            return out
        # Axis-aligned bounds first: boxes whose bounds are apart cannot overlap, so the
        # 15-axis test runs only on the pairs near each other, a number that grows with
        # the objects, not with their square.
        ea = np.einsum("nij,nj->ni", np.abs(ra), ha) + AABB_SLACK
        cb, eb = self.centers, self.extents
        near = (np.abs(cb[None] - ca[:, None]) <= ea[:, None] + eb[None]).all(-1)
        i, j = np.nonzero(near)
        if len(i):
            out[i, j] = _sat_overlap(ca[i], ha[i], ra[i], cb[j], self.halves[j], self.rots[j])
        return out


def _sat_overlap(ca, ha, ra, cb, hb, rb) -> np.ndarray:
    """(K,) whether box pair k (centres (K, 3), half-sizes (K, 3), rotations (K, 3, 3))
    overlaps: the separating axis theorem on 15 axes a pair."""
    k = len(ca)
    axes_a = ra.transpose(0, 2, 1)  # rows: a's axes
    axes_b = rb.transpose(0, 2, 1)
    axes = np.empty((k, 15, 3))
    axes[:, :3], axes[:, 3:6] = axes_a, axes_b
    # a's axis i x b's axis j at row 6 + 3 i + j: np.cross's products and differences,
    # without its checks and axis moves (a third of this test's time)
    x = axes[:, 6:].reshape(k, 3, 3, 3)
    a, b = axes_a[:, :, None, :], axes_b[:, None, :, :]
    for c, (i, j) in enumerate(((1, 2), (2, 0), (0, 1))):
        np.multiply(a[..., i], b[..., j], out=x[..., c])
        x[..., c] -= a[..., j] * b[..., i]
    norm = np.sqrt(np.add.reduce(axes * axes, axis=-1))  # np.linalg.norm's sums
    valid = norm > 1e-9
    axes = axes / np.where(valid, norm, 1.0)[..., None]
    d = cb - ca  # (K, 3)
    dist = np.abs(np.einsum("pkc,pc->pk", axes, d))  # (K, 15)
    # Projected radius of a box on axis L: sum_i h_i |L . axis_i|.
    proj_a = np.einsum("pkc,pic->pki", axes, axes_a)
    proj_b = np.einsum("pkc,pic->pki", axes, axes_b)
    rad = (np.abs(proj_a) * ha[:, None, :]).sum(-1)
    rad += (np.abs(proj_b) * hb[:, None, :]).sum(-1)
    separated = valid & (dist > rad)
    return ~separated.any(axis=1)


def _convex_geometry(fcl, vertices: np.ndarray, faces: np.ndarray):
    flat = np.hstack([np.full((len(faces), 1), 3), faces]).ravel().astype(np.int32)
    return fcl.Convex(np.ascontiguousarray(vertices, dtype=np.float64), len(faces), flat)


def _outline(vertices: np.ndarray) -> np.ndarray:
    """(K, 2) counter-clockwise convex outline of points' xy (their bounding rectangle
    when the projection is flat: a panel seen edge-on)."""
    xy = np.asarray(vertices, float)[:, :2]
    hull = convex_hull_2d(xy)
    if len(hull) >= 3:
        return np.asarray(hull)
    (x0, y0), (x1, y1) = xy.min(0) - 1e-6, xy.max(0) + 1e-6
    return np.array([[x0, y0], [x1, y0], [x1, y1], [x0, y1]])


def _edge_normals(outline: np.ndarray) -> np.ndarray:
    """(K, 2) unit outward normals of a counter-clockwise outline's edges, both ways
    round (a move may go either way along a separating axis). A point at a time in
    Python (an outline has a handful), with numpy's arithmetic: the same bits."""
    pts = outline.tolist()
    out = []
    for (x0, y0), (x1, y1) in zip(pts, pts[1:] + pts[:1]):
        nx, ny = y1 - y0, -(x1 - x0)
        length = math.sqrt(nx * nx + ny * ny)
        if length > 1e-9:
            out.append((nx / length, ny / length))
    normals = np.array(out, dtype=float).reshape(-1, 2)
    return np.concatenate([normals, -normals])


CLEAR_GAP = 2e-3
"""m a clearing move leaves between the outlines it separates."""


def clearing_move(pairs: list[tuple[np.ndarray, np.ndarray]], gap: float = CLEAR_GAP) -> np.ndarray:
    """The shortest horizontal move (3,) of the first outline of every pair that leaves
    it ``gap`` clear of the second: pairs of convex counter-clockwise outlines (K, 2).
    Along a direction d (among the outlines' edge normals: the separating axis theorem's
    candidates), a pair is clear once min(mine . d) + t >= max(theirs . d); every pair at
    once needs the largest such t; the direction needing the smallest is taken. Zero for
    no pairs."""
    index: dict[int, int] = {}  # outline id -> its place among the distinct outlines
    outlines: list[np.ndarray] = []
    for pair in pairs:
        for p in pair:
            if id(p) not in index:
                index[id(p)] = len(outlines)
                outlines.append(p)
    normals = [_edge_normals(p) for p in outlines]
    mine = [index[id(m)] for m, _ in pairs]
    theirs = [index[id(t)] for _, t in pairs]
    return _clearing(outlines, normals, mine, theirs, gap)


def _clearing(
    outlines: list[np.ndarray],
    normals: list[np.ndarray],
    mine: list[int],
    theirs: list[int],
    gap: float,
) -> np.ndarray:
    """:func:`clearing_move` of pairs (outlines[mine[k]], outlines[theirs[k]]), each
    outline given once with its edge normals, in the order the pairs first name them
    (the order of the candidate directions, so that a tie is broken as it always was)."""
    if not mine:
        return np.zeros(3)
    directions = np.concatenate(normals)
    # The parts of a piece of furniture mostly share its yaw, so their outlines share
    # edge directions: each distinct one is kept once, where it first came (a repeated
    # direction needs the same move, so the first of the smallest is the same vector).
    distinct = dict.fromkeys(map(tuple, directions.tolist()))
    if len(distinct) < len(directions):
        directions = np.array(list(distinct), dtype=float).reshape(-1, 2)
    sizes = [len(o) for o in outlines]
    starts = np.cumsum([0, *sizes[:-1]])
    along = np.concatenate(outlines) @ directions.T  # every point on every direction
    highs = np.maximum.reduceat(along, starts, axis=0)  # (outlines, directions)
    lows = np.minimum.reduceat(along, starts, axis=0)
    need = (highs[theirs] - lows[mine]).max(0)
    best = int(np.argmin(need))
    return np.array([*(directions[best] * (need[best] + gap)), 0.0])


class Shape:
    """The fcl geometry of one asset (one convex object per part), posed as a whole."""

    def __init__(self, asset: Asset) -> None:
        _fcl()  # (the one-line error without python-fcl, on construction as before)
        self.asset = asset
        counts = [len(p.mesh.vertices) for p in asset.parts]
        self._vertices = np.concatenate([p.mesh.vertices for p in asset.parts]) if counts else None
        self._starts = np.cumsum([0, *counts[:-1]])
        self.rotation, self.translation = np.eye(3), np.zeros(3)
        # Each part's fcl object is built when a narrow-phase test first needs it (most
        # parts never meet another object's bounds); posed when asked for after a move.
        self._objects: list = [None] * len(asset.parts)
        self._transform = None  # this pose's fcl transform, made when first needed
        self._posed_objects: set[int] = set()  # parts whose fcl object has this pose
        self._outlines: list[np.ndarray | None] = [None] * len(asset.parts)
        self._posed: dict[int, np.ndarray] = {}  # this pose's world footprints, by part
        self._normals: dict[int, np.ndarray] = {}  # their edge normals, by part
        self._bounds: np.ndarray | None = None  # this pose's part bounds

    def set_pose(self, rotation: np.ndarray, translation: np.ndarray) -> None:
        """Place the asset's local frame: world = rotation @ local + translation."""
        self.rotation = np.asarray(rotation, float)
        self.translation = np.asarray(translation, float)
        self._posed, self._normals, self._bounds = {}, {}, None
        self._transform = None
        self._posed_objects = set()

    def fcl_object(self, part: int):
        """The fcl collision object of one part (its convex hull, as fcl takes a mesh), in
        this pose."""
        fcl = _fcl()
        obj = self._objects[part]
        if obj is None:
            mesh = self.asset.parts[part].mesh
            obj = self._objects[part] = fcl.CollisionObject(
                _convex_geometry(fcl, mesh.vertices, mesh.faces)
            )
        if part not in self._posed_objects:
            if self._transform is None:
                self._transform = fcl.Transform(self.rotation, self.translation)
            obj.setTransform(self._transform)
            self._posed_objects.add(part)
        return obj

    def part_bounds(self) -> np.ndarray:
        """(P, 2, 3) world min and max corners of each part in this pose."""
        if self._bounds is None:
            if self._vertices is None:
                self._bounds = np.zeros((0, 2, 3))
            else:
                world = self._vertices @ self.rotation.T + self.translation
                lo = np.minimum.reduceat(world, self._starts)
                hi = np.maximum.reduceat(world, self._starts)
                self._bounds = np.stack([lo, hi], axis=1)
        return self._bounds

    def footprint(self, part: int) -> np.ndarray:
        """(K, 2) world xy of the convex outline of one part's projection on the floor,
        counter-clockwise (objects stand upright: the outline turns with their yaw)."""
        hit = self._posed.get(part)
        if hit is not None:
            return hit
        if abs(self.rotation[2, 2] - 1.0) > 1e-9:  # tilted: the outline changes shape
            world = self.asset.parts[part].mesh.vertices @ self.rotation.T
            xy = _outline(world) + self.translation[:2]
        else:
            if self._outlines[part] is None:
                self._outlines[part] = _outline(self.asset.parts[part].mesh.vertices)
            xy = self._outlines[part] @ self.rotation[:2, :2].T + self.translation[:2]
        self._posed[part] = xy
        return xy

    def footprint_normals(self, part: int) -> np.ndarray:
        """:func:`_edge_normals` of :meth:`footprint` (kept while the pose is: a placed
        object's are asked for by every candidate pushed out of it)."""
        hit = self._normals.get(part)
        if hit is None:
            hit = self._normals[part] = _edge_normals(self.footprint(part))
        return hit


def _near_parts(a: Shape, b: Shape) -> tuple[np.ndarray, np.ndarray]:
    """Indices (i, j) of the part pairs of two posed shapes whose bounds meet (within
    :data:`PART_SLACK`), in the order of a loop over a's parts, then b's: only these can
    touch or penetrate."""
    pa, pb = a.part_bounds(), b.part_bounds()
    near = (
        (pa[:, None, 0] <= pb[None, :, 1] + PART_SLACK)
        & (pb[None, :, 0] <= pa[:, None, 1] + PART_SLACK)
    ).all(-1)
    return np.nonzero(near)


def face_axis_depth(a: Shape, i: int, b: Shape, j: int) -> float:
    """The least overlap of part ``i`` of ``a`` and part ``j`` of ``b`` (posed; each as its
    convex hull, as fcl takes it) along the face normals of both: moving one that far
    along that normal separates them, so their penetration depth is at most this. 0 when
    one of the normals separates them; infinite (no bound) when neither part has a face
    of non-zero area."""
    parts = []
    for shape, k in ((a, i), (b, j)):
        mesh = shape.asset.parts[k].mesh
        world = mesh.vertices @ shape.rotation.T + shape.translation
        tri = world[mesh.faces]
        normals = np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0])
        length = np.sqrt(np.add.reduce(normals * normals, axis=-1))
        parts.append((world, normals[length > 1e-12] / length[length > 1e-12, None]))
    (wa, na), (wb, nb) = parts
    axes = np.concatenate([na, nb])
    if not len(axes):
        return np.inf
    pa, pb = wa @ axes.T, wb @ axes.T
    overlap = np.minimum(pa.max(0), pb.max(0)) - np.maximum(pa.min(0), pb.min(0))
    return max(float(overlap.min()), 0.0)


class MeshWorld:
    """Placed objects as persistent fcl objects, queried by candidate shapes."""

    def __init__(self, tolerances: Tolerances = TOLERANCES) -> None:
        self.tol = tolerances
        self.shapes: dict[str, Shape] = {}
        self._recent: tuple = (None, None, {})  # (candidate, its pose, {pair: deep pairs})

    def add(self, object_id: str, shape: Shape) -> None:
        """Keep ``shape`` (already posed) as object ``object_id``."""
        self.shapes[object_id] = shape
        self._recent = (None, None, {})

    def remove(self, object_id: str) -> None:
        self.shapes.pop(object_id, None)
        self._recent = (None, None, {})

    def penetration(self, a: Shape, b: Shape, tight: bool = False) -> float:
        """Deepest penetration (m) between two posed shapes; 0 when apart.

        ``tight``: each colliding part pair's depth is also bounded by
        :func:`face_axis_depth`. fcl's EPA returns the depth along the direction it
        converged to, which on thin parts may not be the shortest way out: a pen's clip
        on a plate's rim (a ``beyond`` living room) read 1.8 mm or 9.7 mm as the plate's
        size moved by 5e-7 m, in about equal shares, while a move of 1.8 mm along a face
        normal separates them. Both are upper bounds of the true depth, so the smaller
        is too. The evaluation measures with it; placement keeps the plain depth (it
        only makes placement stricter)."""
        fcl = _fcl()
        request = fcl.CollisionRequest(num_max_contacts=1, enable_contact=True)
        deepest = 0.0
        for i, j in zip(*_near_parts(a, b)):
            result = fcl.CollisionResult()
            if fcl.collide(a.fcl_object(i), b.fcl_object(j), request, result):
                depth = max((c.penetration_depth for c in result.contacts), default=0.0)
                if tight and depth > deepest:
                    depth = min(depth, face_axis_depth(a, i, b, j))
                deepest = max(deepest, depth)
        return deepest

    def push_out(self, candidate: Shape, against: Iterable[str]) -> np.ndarray:
        """The shortest horizontal move (3,) that takes the posed candidate clear of every
        part of ``against`` it penetrates beyond the contact tolerance (2 mm past
        touching); zero when it penetrates none.

        Objects rest on surfaces, so only a sideways move frees one. Each penetrating pair
        of convex parts overlaps in height, so separating their footprints (projections
        on the floor, :func:`clearing_move`) separates them. A candidate sunk into an
        object from above thus has to leave its footprint: a long move, which placement's
        repair limit turns down, where a shallow sideways overlap costs a short one. The
        move may meet a third object; the caller tests again."""
        index: dict[tuple, int] = {}  # (object id or None, part) -> place in outlines
        outlines: list[np.ndarray] = []
        normals: list[np.ndarray] = []
        mine: list[int] = []
        theirs: list[int] = []
        for oid in against:
            other = self.shapes.get(oid)
            if other is None:
                continue
            for i, j in self._deep_pairs(candidate, oid):
                for key, shape, part, into in ((None, candidate, i, mine), (oid, other, j, theirs)):
                    k = index.get((key, part))
                    if k is None:
                        k = index[(key, part)] = len(outlines)
                        outlines.append(shape.footprint(part))
                        normals.append(shape.footprint_normals(part))
                    into.append(k)
        return _clearing(outlines, normals, mine, theirs, CLEAR_GAP)

    def colliding(self, candidate: Shape, against: Iterable[str]) -> list[str]:
        """The ids among ``against`` whose parts penetrate the posed candidate by more than
        :attr:`Tolerances.touch`."""
        return [oid for oid in against if oid in self.shapes and self._deep_pairs(candidate, oid)]

    def _deep_pairs(self, candidate: Shape, oid: str) -> list[tuple[int, int]]:
        """The part pairs (candidate's, object ``oid``'s) that penetrate beyond the pair's
        contact tolerance, in :func:`_near_parts` order. Kept for the candidate's current
        pose: placement asks :meth:`colliding`, then :meth:`push_out` the same pairs."""
        pose = (candidate.rotation.tobytes(), candidate.translation.tobytes())
        if self._recent[0] is not candidate or self._recent[1] != pose:
            self._recent = (candidate, pose, {})
        other = self.shapes[oid]
        key = (oid, id(other), other.rotation.tobytes(), other.translation.tobytes())
        memo = self._recent[2]
        hit = memo.get(key)
        if hit is not None:
            return hit
        fcl = _fcl()
        request = fcl.CollisionRequest(num_max_contacts=1, enable_contact=True)
        touch = self.touch_between(candidate, other)
        deep = []
        for i, j in zip(*_near_parts(candidate, other)):
            result = fcl.CollisionResult()
            if fcl.collide(candidate.fcl_object(i), other.fcl_object(j), request, result) and any(
                c.penetration_depth > touch for c in result.contacts
            ):
                deep.append((int(i), int(j)))
        memo[key] = deep
        return deep

    def touch_between(self, a: Shape, b: Shape) -> float:
        """The contact tolerance of a pair: :attr:`Tolerances.touch`, less for thin ones."""
        thinnest = float(min(a.asset.size.min(), b.asset.size.min()))
        return min(self.tol.touch, self.tol.thin_fraction * thinnest)

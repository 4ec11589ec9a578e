"""Triangle meshes and convex primitives, in plain numpy.

Every primitive here is a closed, convex, outward-oriented triangle mesh: the
generators compose assets from them, so each asset's parts are convex by
construction (MuJoCo collides meshes by their convex hulls). Faces are
counter-clockwise seen from outside.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, field
from functools import cached_property

import numpy as np

from pair2scene.scene.geometry import polygon_area

ArrayLike = np.typing.ArrayLike

CONVEX_TOL = 1e-6
"""m; a vertex this far in front of a face plane still counts as convex (rounding)."""
DEFAULT_SEGMENTS = 16
"""Sides of a round primitive: smooth enough to read as round in a 256 px view."""


@dataclass(frozen=True, eq=False)
class Mesh:
    vertices: np.ndarray
    """(V, 3) float64."""
    faces: np.ndarray
    """(F, 3) int64, counter-clockwise seen from outside."""

    def __post_init__(self) -> None:
        v = np.asarray(self.vertices, dtype=np.float64).reshape(-1, 3)
        f = np.asarray(self.faces, dtype=np.int64).reshape(-1, 3)
        object.__setattr__(self, "vertices", v)
        object.__setattr__(self, "faces", f)

    # -- measures -------------------------------------------------------------
    @property
    def bounds(self) -> np.ndarray:
        """(2, 3) min and max corners."""
        return np.stack([self.vertices.min(0), self.vertices.max(0)])

    @cached_property
    def triangles(self) -> np.ndarray:
        """(F, 3, 3) vertex coordinates per face."""
        return self.vertices[self.faces]

    @cached_property
    def face_areas(self) -> np.ndarray:
        """(F,) area of each face."""
        t = self.triangles
        return 0.5 * np.linalg.norm(np.cross(t[:, 1] - t[:, 0], t[:, 2] - t[:, 0]), axis=1)

    @cached_property
    def face_normals(self) -> np.ndarray:
        """(F, 3) unit normals (zero for degenerate faces)."""
        t = self.triangles
        n = np.cross(t[:, 1] - t[:, 0], t[:, 2] - t[:, 0])
        norm = np.linalg.norm(n, axis=1, keepdims=True)
        return np.divide(n, norm, out=np.zeros_like(n), where=norm > 0)

    @property
    def area(self) -> float:
        return float(self.face_areas.sum())

    @property
    def volume(self) -> float:
        """Signed volume (positive for closed outward meshes)."""
        t = self.triangles
        return float(np.einsum("ij,ij->i", t[:, 0], np.cross(t[:, 1], t[:, 2])).sum() / 6.0)

    def is_watertight(self) -> bool:
        """Every directed edge appears once and its reverse once: closed and consistently
        oriented (after merging coincident vertices)."""
        if len(self.faces) == 0:
            return False
        _, inverse = np.unique(np.round(self.vertices, 9), axis=0, return_inverse=True)
        f = inverse.reshape(-1)[self.faces]
        edges = np.concatenate([f[:, [0, 1]], f[:, [1, 2]], f[:, [2, 0]]])
        edges = edges[edges[:, 0] != edges[:, 1]]
        directed = {tuple(e) for e in edges.tolist()}
        if len(directed) != len(edges):
            return False
        return all((b, a) in directed for a, b in directed)

    def is_convex(self, tol: float = CONVEX_TOL) -> bool:
        """No vertex lies in front of any face's plane (closed outward meshes)."""
        n = self.face_normals
        d = np.einsum("ij,ij->i", n, self.triangles[:, 0])
        return bool(np.all(self.vertices @ n.T - d <= tol))

    # -- transforms -------------------------------------------------------------
    def transformed(
        self, rotation: ArrayLike | None = None, translation: ArrayLike | None = None
    ) -> Mesh:
        """Rotate (3, 3) then translate (3,)."""
        v = self.vertices
        if rotation is not None:
            v = v @ np.asarray(rotation, dtype=float).T
        if translation is not None:
            v = v + np.asarray(translation, dtype=float)
        return Mesh(v, self.faces)

    def scaled(self, scale: ArrayLike, about: ArrayLike = (0.0, 0.0, 0.0)) -> Mesh:
        """Scale per axis (3,) (or uniformly) about a point. Negative scales flip faces."""
        s = np.broadcast_to(np.asarray(scale, dtype=float), (3,))
        c = np.asarray(about, dtype=float)
        faces = self.faces if np.prod(np.sign(s)) > 0 else self.faces[:, ::-1]
        return Mesh((self.vertices - c) * s + c, faces)

    @staticmethod
    def concat(meshes: Sequence[Mesh]) -> Mesh:
        """One mesh holding all of ``meshes`` (no boolean union)."""
        if not meshes:
            return Mesh(np.zeros((0, 3)), np.zeros((0, 3), dtype=np.int64))
        offsets = np.cumsum([0] + [len(m.vertices) for m in meshes[:-1]])
        v = np.concatenate([m.vertices for m in meshes])
        f = np.concatenate([m.faces + o for m, o in zip(meshes, offsets)])
        return Mesh(v, f)


@dataclass(frozen=True, eq=False)
class Part:
    """A named convex piece of an asset (a leg, a tier, a seat)."""

    name: str
    mesh: Mesh


@dataclass(frozen=True, eq=False)
class Asset:
    """A mesh that fills a box: local frame centred on the box, +z up, +y front."""

    category: str
    size: np.ndarray
    """(3,) full extent along local x, y, z; the mesh's bounds are exactly +-size/2."""
    parts: tuple[Part, ...]
    style: int = 0
    source: str = "procedural"
    """``procedural``, ``box`` (fallback: a labelled box), ``user`` or ``3dfuture``."""
    asset_id: str | None = None
    """Id in the source (a user file name, a 3D-FUTURE jid)."""
    extra: dict = field(default_factory=dict)
    """Generator facts placement may use, e.g. ``{"tier_heights": [...]}``."""

    @property
    def is_fallback(self) -> bool:
        return self.source == "box"

    @cached_property
    def mesh(self) -> Mesh:
        return Mesh.concat([p.mesh for p in self.parts])


def axis_aligned_box(mesh: Mesh, tol: float) -> tuple[np.ndarray, np.ndarray] | None:
    """(centre (3,), half size (3,)) if ``mesh`` is an axis-aligned box (8 distinct
    vertices, each within ``tol`` of the bounds), else None: simulators collide such a
    part as a box primitive, faster than a mesh."""
    v = mesh.vertices
    if len(v) != 8:
        return None
    lo, hi = v.min(0), v.max(0)
    on_bounds = (np.abs(v - lo) <= tol) | (np.abs(v - hi) <= tol)
    if not on_bounds.all() or len(np.unique(np.round(v, 9), axis=0)) != 8:
        return None
    return (lo + hi) / 2, (hi - lo) / 2


# -- primitives ---------------------------------------------------------------------
_BOX_FACES = np.array(
    [
        [0, 2, 1], [0, 3, 2],  # bottom (z-)
        [4, 5, 6], [4, 6, 7],  # top (z+)
        [0, 1, 5], [0, 5, 4],  # y-
        [1, 2, 6], [1, 6, 5],  # x+
        [2, 3, 7], [2, 7, 6],  # y+
        [3, 0, 4], [3, 4, 7],  # x-
    ]
)  # fmt: skip


def box(center: ArrayLike, size: ArrayLike, rotation: ArrayLike | None = None) -> Mesh:
    """Axis-aligned (then rotated) box: centre (3,), full size (3,)."""
    h = np.asarray(size, dtype=float) / 2
    corners = np.array(
        [[-1, -1, -1], [1, -1, -1], [1, 1, -1], [-1, 1, -1],
         [-1, -1, 1], [1, -1, 1], [1, 1, 1], [-1, 1, 1]], dtype=float
    ) * h  # fmt: skip
    return Mesh(corners, _BOX_FACES).transformed(rotation, center)


def box_between(lo: ArrayLike, hi: ArrayLike) -> Mesh:
    """Axis-aligned box from its min (3,) and max (3,) corners."""
    lo, hi = np.asarray(lo, dtype=float), np.asarray(hi, dtype=float)
    return box((lo + hi) / 2, hi - lo)


def _ring(rx: float, ry: float, z: float, segments: int) -> np.ndarray:
    a = np.linspace(0, 2 * np.pi, segments, endpoint=False)
    return np.stack([rx * np.cos(a), ry * np.sin(a), np.full(segments, z)], axis=1)


def frustum(
    center_bottom: ArrayLike,
    height: float,
    r_bottom: float | Sequence[float],
    r_top: float | Sequence[float],
    segments: int = DEFAULT_SEGMENTS,
    rotation: ArrayLike | None = None,
) -> Mesh:
    """Elliptic frustum along +z from ``center_bottom``; radii (rx, ry) or one value.
    A zero top radius gives a cone. Rotation is applied about ``center_bottom``.
    The two ends must have the same rx/ry aspect (or the top be a cone): otherwise
    the side quads are not planar and the mesh is not convex; use :func:`hull`."""
    rb = np.broadcast_to(np.asarray(r_bottom, dtype=float), (2,))
    rt = np.broadcast_to(np.asarray(r_top, dtype=float), (2,))
    n = segments
    bottom = _ring(rb[0], rb[1], 0.0, n)
    faces = []
    if np.all(rt > 0):
        top = _ring(rt[0], rt[1], height, n)
        v = np.concatenate([bottom, top, [[0, 0, 0], [0, 0, height]]])
        cb, ct = 2 * n, 2 * n + 1
        for i in range(n):
            j = (i + 1) % n
            faces += [[i, j, n + j], [i, n + j, n + i], [cb, j, i], [ct, n + i, n + j]]
    else:
        v = np.concatenate([bottom, [[0, 0, 0], [0, 0, height]]])
        cb, apex = n, n + 1
        for i in range(n):
            j = (i + 1) % n
            faces += [[i, j, apex], [cb, j, i]]
    return Mesh(v, np.array(faces)).transformed(rotation, center_bottom)


def cylinder(
    center: ArrayLike,
    radius: float | Sequence[float],
    height: float,
    segments: int = DEFAULT_SEGMENTS,
    rotation: ArrayLike | None = None,
) -> Mesh:
    """Cylinder along +z centred at ``center`` (before ``rotation`` about the centre)."""
    m = frustum((0.0, 0.0, -height / 2), height, radius, radius, segments)
    return m.transformed(rotation, center)


def align_z(direction: ArrayLike) -> np.ndarray:
    """(3, 3) rotation taking +z onto ``direction`` (3,) along the shortest arc."""
    d = np.asarray(direction, dtype=float)
    d = d / np.linalg.norm(d)
    v = np.array([-d[1], d[0], 0.0])  # z x d
    c = d[2]
    if np.linalg.norm(v) < 1e-12:
        return np.eye(3) if c > 0 else np.diag([1.0, -1.0, -1.0])
    vx = np.array([[0.0, -v[2], v[1]], [v[2], 0.0, -v[0]], [-v[1], v[0], 0.0]])
    return np.eye(3) + vx + vx @ vx / (1.0 + c)


def rod(
    p0: ArrayLike, p1: ArrayLike, r0: float, r1: float | None = None, segments: int = 8
) -> Mesh:
    """A round rod (a frustum with radii r0 -> r1) from point p0 (3,) to point p1 (3,)."""
    a, b = np.asarray(p0, dtype=float), np.asarray(p1, dtype=float)
    d = b - a
    return frustum(
        a, float(np.linalg.norm(d)), r0, r0 if r1 is None else r1, segments, rotation=align_z(d)
    )


def ellipsoid(
    center: ArrayLike,
    radii: float | Sequence[float],
    rings: int = 8,
    segments: int = DEFAULT_SEGMENTS,
) -> Mesh:
    """UV ellipsoid with semi-axes ``radii`` (3,)."""
    r = np.broadcast_to(np.asarray(radii, dtype=float), (3,))
    verts = [[0.0, 0.0, -1.0]]
    for k in range(1, rings):
        phi = -np.pi / 2 + np.pi * k / rings
        verts += _ring(np.cos(phi), np.cos(phi), np.sin(phi), segments).tolist()
    verts.append([0.0, 0.0, 1.0])
    v = np.array(verts) * r
    faces = []
    n, top = segments, len(verts) - 1
    for i in range(n):
        faces.append([0, 1 + (i + 1) % n, 1 + i])
    for k in range(rings - 2):
        a, b = 1 + k * n, 1 + (k + 1) * n
        for i in range(n):
            j = (i + 1) % n
            faces += [[a + i, a + j, b + j], [a + i, b + j, b + i]]
    last = 1 + (rings - 2) * n
    for i in range(n):
        faces.append([top, last + i, last + (i + 1) % n])
    return Mesh(v, np.array(faces)).transformed(None, center)


def prism(polygon: ArrayLike, z0: float, z1: float) -> Mesh:
    """Extrude a convex 2D polygon (N, 2), counter-clockwise, from z0 to z1."""
    p = np.asarray(polygon, dtype=float)
    if polygon_area(p) < 0:
        p = p[::-1]
    n = len(p)
    v = np.concatenate([np.c_[p, np.full(n, z0)], np.c_[p, np.full(n, z1)]])
    faces = []
    for i in range(1, n - 1):
        faces += [[0, i + 1, i], [n, n + i, n + i + 1]]
    for i in range(n):
        j = (i + 1) % n
        faces += [[i, j, n + j], [i, n + j, n + i]]
    return Mesh(v, np.array(faces))


def hull(points: ArrayLike) -> Mesh:
    """Convex hull of points (N, 3), outward-oriented (e.g. a wedge, a sloped back)."""
    from scipy.spatial import ConvexHull

    pts = np.asarray(points, dtype=float)
    h = ConvexHull(pts)
    faces = h.simplices.copy()
    # orient each face along its outward hull-equation normal
    t = pts[faces]
    n = np.cross(t[:, 1] - t[:, 0], t[:, 2] - t[:, 0])
    flip = np.einsum("ij,ij->i", n, h.equations[:, :3]) < 0
    faces[flip] = faces[flip][:, ::-1]
    used, inverse = np.unique(faces, return_inverse=True)
    return Mesh(pts[used], inverse.reshape(-1, 3))

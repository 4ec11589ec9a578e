"""Support surfaces: the upward, horizontal places on an asset where things can rest.

Method, in the asset's local frame (+z up):

1. Faces whose normal points up within ``normal_tol`` are grouped by height.
2. Each height group gets a rectilinear grid over its faces. The grid lines pass
   through every vertex x (and y) of those faces and of the parts that could
   cover them, then are subdivided down to a resolution, so box-shaped
   furniture is outlined exactly and round shapes to within a cell.
3. A cell belongs to a surface when its centre lies on one of the group's faces,
   is not inside another part, and has at least ``MIN_CLEARANCE_M`` of free
   height above it. Both tests cast a vertical ray from the cell centre against
   every convex part, clipping the ray by the part's face planes (exact, and
   free of the double hits a ray-triangle test has on shared edges).
4. 4-connected free cells form regions; a region's outline (and holes) follow
   the cell edges and are simplified; regions too small, too narrow or too low
   are dropped.

The rays of a level's grid are clipped by a part all at once, over the block of
the grid under it, and only where the part can still lower a clearance; each
value is computed with the same floating-point operations as one ray clipped on
its own (:func:`clearance_above`), so the results are the same to the bit.

Parts are the asset's convex parts, or the connected components of a bare
:class:`~pair2scene.assets.mesh.Mesh`. A component that is not convex is treated
as its convex hull (so its own concave pockets read as solid): every asset built
from ``mesh.py`` primitives, and every library asset, has convex parts.
"""

from __future__ import annotations

import math
import weakref
from dataclasses import dataclass, field
from functools import cached_property

import numpy as np

from pair2scene.assets.mesh import CONVEX_TOL, Asset, Mesh
from pair2scene.scene.geometry import points_in_polygon, polygon_area

NORMAL_TOL_DEG = 10.0
"""A face tilted up to this far from horizontal still holds things: a seat tilted back
a few degrees holds a cushion, and anything with friction above 0.18 stays put."""
HEIGHT_TOL_M = 0.005
"""Up faces within this height of each other form one level (rounding, a slight slope)."""
MIN_AREA_M2 = 0.002
"""Smaller regions are dropped: about 4.5 cm square, smaller than a coaster."""
MIN_CLEARANCE_M = 0.03
"""Cells with less free height above are dropped: under a lying book's height a gap is a
seam between parts, not a place to put something."""
MIN_WIDTH_M = 0.03
"""A region must be this wide both ways somewhere: narrower holds nothing steadily (the
rim of a bowl, a chair's rail, the edge of a frame)."""
CLEARANCE_PERCENTILE = 5.0
"""A region's clearance is this (area-weighted) percentile of its cells' free heights:
what nearly all of it offers, not spoiled by one corner under an overhang."""
GRID_CELLS = 128
"""Cells across a level's longer side: under 1 cm for furniture up to 1.28 m."""
MIN_CELL_M = 0.001
"""Grid lines closer than this are merged; no cell is made smaller by subdivision."""
MAX_GRID_LINES = 1024
"""Per axis; beyond this (very many distinct vertex coordinates) the grid is uniform."""
LIFT_M = 1e-4
"""Cell centres are lifted this far above their face before the vertical ray is cast:
above coordinate rounding, far below any real gap."""
PLANE_TOL = 1e-7
"""m; a point this close to a part's side plane counts as on it."""
CHUNK_ELEMENTS = 2_000_000
"""Cells x planes (or triangles) processed at once: temporary arrays stay ~16 MB each."""
SIDE_NZ = 1e-12
"""A face plane whose normal has |n_z| at most this is vertical (a side of the part)."""
SMALL_BLOCK = 4096
"""Planes x grid lines up to which a part's planes are evaluated all alike on every line:
sparing work there costs more bookkeeping than it saves."""
TILE = 8
"""Grid lines per side of the tiles on which only the planes that can bound a part's top
(or bottom) there are evaluated (:func:`_tiled_envelope`)."""
TILED_MIN_PLANES = 8
"""Parts with fewer slanted top (or bottom) planes have them all evaluated everywhere."""
ROUNDING_BOUND = 1e-12
"""Bound on the rounding error of a plane's height ``(d - x n_x - y n_y) / n_z`` on a vertical
line, relative to ``(|d| + |x n_x| + |y n_y|) / |n_z|``: over 2000 times the real bound
(4.6e-16). A plane is set aside on a tile only when farther than this from the result."""


@dataclass(frozen=True, eq=False)
class SupportSurface:
    """A horizontal region on which things can rest, in the asset's local frame."""

    z: float
    """Height in the asset's local frame (the box is centred at the origin)."""
    polygon: np.ndarray
    """(N, 2) counter-clockwise outline in local xy."""
    area: float
    """m^2 of free surface (holes excluded)."""
    clearance: float
    """Free height above the surface inside the asset (to the next part above); inf if
    open to the sky."""
    holes: tuple[np.ndarray, ...] = field(default=())
    """Each (H, 2), clockwise: places inside the outline that are covered or missing
    (a sink cut into a counter, the basin inside a bathtub's rim)."""

    def contains(self, xy: np.ndarray) -> np.ndarray:
        """(M,) bool: which points (M, 2) lie on the surface (inside the outline, outside
        every hole)."""
        xy = np.asarray(xy, dtype=float).reshape(-1, 2)
        inside = points_in_polygon(xy, self.polygon)
        for h in self.holes:
            inside &= ~points_in_polygon(xy, h)
        return inside


# -- convex parts ------------------------------------------------------------------
@dataclass(frozen=True, eq=False)
class ConvexPart:
    """A convex part as half-spaces ``normals @ x <= offsets`` plus its bounds."""

    normals: np.ndarray
    """(P, 3) unit outward face normals (duplicates removed)."""
    offsets: np.ndarray
    """(P,) plane offsets."""
    bounds: np.ndarray
    """(2, 3) min and max corners."""
    vertices: np.ndarray
    """(V, 3) the part's vertices (grid lines are drawn through them)."""

    @cached_property
    def _kinds(self) -> tuple[Planes, Planes, Planes]:
        """The planes facing up, facing down and vertical (|n_z| <= SIDE_NZ), in any order
        (they are only reduced over)."""
        rows = np.column_stack([self.normals, self.offsets])
        nz = self.normals[:, 2]
        kind = np.where(nz > SIDE_NZ, 0, np.where(nz < -SIDE_NZ, 1, 2))
        along = (rows[:, 0] != 0) + 2 * (rows[:, 1] != 0)  # the index in ALONG
        key = 4 * kind + along
        ends = np.cumsum(np.bincount(key, minlength=12))
        rows = rows[np.argsort(key, kind="stable")]
        groups = np.split(rows, ends[:-1])
        starts = np.concatenate([[0], ends[3:-1:4]])
        return tuple(
            (rows[starts[k] : ends[4 * k + 3]], tuple(groups[4 * k : 4 * k + 4])) for k in range(3)
        )

    @cached_property
    def _floor(self) -> float:
        """Height of its horizontal bottom face as :func:`_grid_interval` computes it (-inf
        without one): no vertical line enters the part lower."""
        flat = self._kinds[1][1][0]
        return float((flat[:, 3] / flat[:, 2]).max()) if len(flat) else -math.inf


Planes = tuple[np.ndarray, tuple[np.ndarray, ...]]
"""Planes as rows (P, 4) (n_x, n_y, n_z, d), and the same rows in four arrays: n_x = n_y = 0,
only n_y = 0, only n_x = 0, and neither zero. A vertical line's slack ``d - x n_x - y n_y``
on the planes of each depends on no grid coordinate, on x only, on y only, and on both
(:data:`ALONG`)."""
ALONG = ("", "x", "y", "xy")
"""The grid axes along which the slack of each of the four arrays of :data:`Planes` varies."""

_PLANE_RECORD = np.dtype([(f"f{i}", np.float64) for i in range(4)])
"""A plane row (n_x, n_y, n_z, d) as one record, the way ``np.unique(axis=0)`` sorts rows."""

_PARTS: weakref.WeakKeyDictionary[Mesh, ConvexPart | None] = weakref.WeakKeyDictionary()


def convex_part(mesh: Mesh) -> ConvexPart | None:
    """Half-spaces of ``mesh`` (of its convex hull if it is not convex); None when the mesh
    has no faces, or is not convex and has no volume. Computed once per mesh object: an
    asset's support surfaces and its point cloud visit the same parts."""
    if mesh not in _PARTS:
        _PARTS[mesh] = _convex_part(mesh, mesh.triangles, mesh.face_normals, mesh.face_areas)
    return _PARTS[mesh]


def convex_parts(mesh_or_asset: Mesh | Asset) -> list[ConvexPart]:
    """:func:`convex_part` of each of :func:`part_meshes` that has one, in order."""
    meshes = part_meshes(mesh_or_asset)
    return _convex_parts(meshes, *_face_data(mesh_or_asset, meshes)) if meshes else []


def _face_data(mesh_or_asset: Mesh | Asset, meshes: list[Mesh]) -> tuple[np.ndarray, ...]:
    """Triangles (F, 3, 3), unit normals (F, 3) and areas (F,) of the faces of ``meshes``
    (the parts of ``mesh_or_asset``), in order. An asset's are its whole mesh's: the same
    values (each face's are computed on their own), computed for all parts at once."""
    if isinstance(mesh_or_asset, Asset):
        whole = mesh_or_asset.mesh
        return whole.triangles, whole.face_normals, whole.face_areas
    return (
        np.concatenate([m.triangles for m in meshes]),
        np.concatenate([m.face_normals for m in meshes]),
        np.concatenate([m.face_areas for m in meshes]),
    )


def _convex_parts(
    meshes: list[Mesh], tris: np.ndarray, normals: np.ndarray, areas: np.ndarray
) -> list[ConvexPart]:
    """:func:`convex_part` of each mesh that has one, given the meshes' face data in order
    (:func:`_face_data`)."""
    out = []
    end = 0
    for m in meshes:
        start, end = end, end + len(m.faces)
        if m not in _PARTS:
            _PARTS[m] = _convex_part(m, tris[start:end], normals[start:end], areas[start:end])
        if _PARTS[m] is not None:
            out.append(_PARTS[m])
    return out


def _convex_part(
    mesh: Mesh, tris: np.ndarray, normals: np.ndarray, areas: np.ndarray
) -> ConvexPart | None:
    """:func:`convex_part` given the mesh's triangles, face normals and face areas."""
    if len(mesh.faces) == 0:
        return None
    d = np.einsum("ij,ij->i", normals, tris[:, 0])
    if (mesh.vertices @ normals.T - d <= CONVEX_TOL).all():  # Mesh.is_convex
        keep = areas > 0
        n = normals[keep]
        d = np.einsum("ij,ij->i", n, tris[keep, 0])
    else:
        from scipy.spatial import ConvexHull, QhullError

        try:
            eq = ConvexHull(mesh.vertices).equations
        except (QhullError, ValueError):
            return None
        n, d = eq[:, :3], -eq[:, 3]
    if len(n) == 0:
        return None
    planes = _unique_rows(np.concatenate([n, d[:, None]], axis=1).round(9))
    v = mesh.vertices
    return ConvexPart(planes[:, :3], planes[:, 3], np.array([v.min(0), v.max(0)]), v)


def _unique_rows(planes: np.ndarray) -> np.ndarray:
    """``np.unique(planes, axis=0)`` of (P, 4) rows (sorting ``planes`` in place), without
    its overhead: the same steps (the rows as records, the same sort, the first of each run
    of equal rows), so of rows equal up to a zero's sign the same one is kept."""
    rows = np.ascontiguousarray(planes).view(_PLANE_RECORD).ravel()
    rows.sort()
    planes = rows.view(np.float64).reshape(-1, 4)
    keep = np.empty(len(planes), dtype=bool)
    keep[:1] = True
    keep[1:] = np.logical_or.reduce(planes[1:] != planes[:-1], axis=1)  # field by field
    return planes[keep]


def components(mesh: Mesh) -> list[Mesh]:
    """Connected components of ``mesh`` by shared vertex indices (no welding), in order of
    their first face: a concatenation of primitives comes apart into the primitives."""
    from scipy.sparse import coo_matrix
    from scipy.sparse.csgraph import connected_components

    nv, f = len(mesh.vertices), mesh.faces
    if len(f) == 0:
        return []
    rows = np.concatenate([f[:, 0], f[:, 1]])
    cols = np.concatenate([f[:, 1], f[:, 2]])
    graph = coo_matrix((np.ones(len(rows)), (rows, cols)), shape=(nv, nv))
    _, label = connected_components(graph, directed=False)
    face_label = label[f[:, 0]]
    _, first = np.unique(face_label, return_index=True)
    out = []
    for lab in face_label[np.sort(first)]:
        faces = f[face_label == lab]
        used, inverse = np.unique(faces, return_inverse=True)
        out.append(Mesh(mesh.vertices[used], inverse.reshape(-1, 3)))
    return out


def part_meshes(mesh_or_asset: Mesh | Asset) -> list[Mesh]:
    """The convex pieces of an asset (its parts) or of a bare mesh (its components)."""
    if isinstance(mesh_or_asset, Asset):
        return [p.mesh for p in mesh_or_asset.parts]
    return components(mesh_or_asset)


def _vertical_interval(part: ConvexPart, xy: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Where the vertical line through each point (M, 2) crosses ``part``: heights lo, hi
    (M,); lo > hi where the line misses it."""
    n, d = part.normals, part.offsets
    s = d - xy[:, :1] * n[:, 0] - xy[:, 1:] * n[:, 1]  # (M, P): n_z * t <= s on the line
    nz = n[:, 2]
    up, down = nz > SIDE_NZ, nz < -SIDE_NZ
    side = ~(up | down)
    t = s / np.where(side, 1.0, nz)
    hi = np.where(up, t, np.inf).min(1)
    lo = np.where(down, t, -np.inf).max(1)
    lo[(side & (s < -PLANE_TOL)).any(1)] = np.inf
    return lo, hi


def clearance_above(parts: list[ConvexPart], points: np.ndarray) -> np.ndarray:
    """(M,) free height above each point (M, 3) among ``parts``: 0 inside a part, inf when
    nothing is above. A point on a part's top face is not inside that part."""
    points = np.asarray(points, dtype=float).reshape(-1, 3)
    out = np.full(len(points), np.inf)
    z0 = points[:, 2] + LIFT_M
    for part in parts:
        (x0, y0, _), (x1, y1, z1) = part.bounds
        # only points under the part's footprint and below its top can meet it
        idx = np.flatnonzero(
            (points[:, 0] >= x0 - PLANE_TOL)
            & (points[:, 0] <= x1 + PLANE_TOL)
            & (points[:, 1] >= y0 - PLANE_TOL)
            & (points[:, 1] <= y1 + PLANE_TOL)
            & (z0 < z1)
        )
        chunk = max(1, CHUNK_ELEMENTS // len(part.offsets))
        for a in range(0, len(idx), chunk):
            i = idx[a : a + chunk]
            lo, hi = _vertical_interval(part, points[i, :2])
            hit = lo <= hi
            gap = np.where(hit & (lo >= z0[i]), lo - points[i, 2], np.inf)
            gap[hit & (lo < z0[i]) & (hi > z0[i])] = 0.0  # the point is inside the part
            out[i] = np.minimum(out[i], gap)
    return out


def _slack(rows: np.ndarray, x: np.ndarray, y: np.ndarray, along: str = "xy") -> np.ndarray:
    """The slack ``s = d - x n_x - y n_y`` of planes (P, 4) on the vertical lines through the
    grid (x[i], y[j]) (a line keeps to a plane where ``n_z z <= s``): (P, ny, nx), computed
    as :func:`_vertical_interval` does. Along fewer axes (:data:`ALONG`) for planes whose
    n_x or n_y is zero, that term left out, (P, 1 or ny, 1 or nx): the values are the same
    (x * 0 is a zero), but perhaps for a zero's sign, which no comparison sees and no kept
    difference carries."""
    d = rows[:, 3:]
    if along == "":
        return d[:, :, None]
    if along == "x":
        return (d - x * rows[:, :1])[:, None, :]
    if along == "y":
        return (d - y * rows[:, 1:2])[:, :, None]
    return (d - x * rows[:, :1])[:, None, :] - (y * rows[:, 1:2])[:, :, None]


def _grid_interval(part: ConvexPart, x: np.ndarray, y: np.ndarray) -> tuple[np.ndarray, ...]:
    """:func:`_vertical_interval` of the vertical lines through the grid (x[i], y[j]) (x
    (nx,), y (ny,)): lo, hi (ny, nx). On a larger grid, a plane's slack is computed only
    along the axes it varies along (a box's sides along one)."""
    up, down, (rows, split) = part._kinds
    hi = _envelope(up, x, y, np.minimum, np.inf)
    lo = _envelope(down, x, y, np.maximum, -np.inf)
    pieces = zip(split, ALONG) if len(rows) * lo.size > SMALL_BLOCK else [(rows, "xy")]
    for planes, along in pieces:
        if len(planes):
            miss = np.logical_or.reduce(_slack(planes, x, y, along) < -PLANE_TOL, axis=0)
            np.copyto(lo, np.inf, where=miss)
    return lo, hi


def _envelope(planes: Planes, x: np.ndarray, y: np.ndarray, reduce: np.ufunc, empty: float):
    """The lowest (``reduce`` np.minimum) or highest (np.maximum) height ``s / n_z`` at which
    the vertical lines through the grid (x[i], y[j]) meet the (non-vertical) planes: (ny,
    nx); ``empty`` where there are none."""
    rows, split = planes
    if not len(rows):
        return np.full((len(y), len(x)), empty)
    if len(rows) * len(x) * len(y) <= SMALL_BLOCK:
        return reduce.reduce(_slack(rows, x, y) / rows[:, 2, None, None], axis=0)
    out = np.full((len(y), len(x)), empty)
    if len(split[3]):
        reduce(out, _tiled_envelope(split[3], x, y, reduce), out=out)
    for part, along in zip(split[:3], ALONG):
        if len(part):
            height = _slack(part, x, y, along) / part[:, 2, None, None]
            reduce(out, reduce.reduce(height, axis=0), out=out)
    return out


def _tiled_envelope(rows: np.ndarray, x: np.ndarray, y: np.ndarray, reduce: np.ufunc):
    """:func:`_envelope` of slanted planes (P, 4) (rows n_x, n_y, n_z, d; neither n_x nor
    n_y zero), with the same values: each tile of TILE x TILE lines reduces over only the
    planes that can give its result. The exact height of a plane is linear, so lies
    between its values at the tile's corners; the computed heights (at the corners too)
    are within ROUNDING_BOUND of the exact ones. A plane whose range so widened lies
    wholly beyond another's (above it, for the lowest) never gives the result there."""
    ny, nx = len(y), len(x)
    n_x, n_y, n_z, d = (rows[:, k, None] for k in range(4))  # each (P, 1)
    if len(rows) < TILED_MIN_PLANES or max(nx, ny) <= TILE:
        return reduce.reduce(_slack(rows, x, y) / n_z[:, :, None], axis=0)
    tx, ty = -(-nx // TILE), -(-ny // TILE)
    # each tile's lines, the grid's last line repeated to fill the last tile
    xt = x[np.minimum(np.arange(tx * TILE), nx - 1)].reshape(tx, TILE)
    yt = y[np.minimum(np.arange(ty * TILE), ny - 1)].reshape(ty, TILE)
    # the heights at the tiles' corners, each (P, ty, tx)
    along_x = [(d - xt[:, k] * n_x)[:, None, :] for k in (0, -1)]
    along_y = [(yt[:, k] * n_y)[:, :, None] for k in (0, -1)]
    corners = [(a - b) / n_z[:, :, None] for a in along_x for b in along_y]
    scale = np.abs(d) + np.abs(x).max() * np.abs(n_x) + np.abs(y).max() * np.abs(n_y)
    err = (ROUNDING_BOUND * scale / np.abs(n_z))[:, :, None]
    low = np.minimum(np.minimum(*corners[:2]), np.minimum(*corners[2:])) - err
    high = np.maximum(np.maximum(*corners[:2]), np.maximum(*corners[2:])) + err
    if reduce is np.minimum:
        can = low <= high.min(0)
    else:
        can = high >= low.max(0)
    tile, p = np.nonzero(can.reshape(len(rows), -1).T)  # by tile; every tile has one
    r, c = np.divmod(tile, tx)
    s = (d[p] - xt[c] * n_x[p])[:, None, :] - (yt[r] * n_y[p])[:, :, None]
    first = np.flatnonzero(np.concatenate([[True], tile[1:] != tile[:-1]]))
    out = reduce.reduceat(s / n_z[p][:, :, None], first, axis=0)  # (tiles, TILE, TILE)
    return out.reshape(ty, tx, TILE, TILE).transpose(0, 2, 1, 3).reshape(ty * TILE, -1)[:ny, :nx]


def _grid_clearance(parts: list[ConvexPart], x: np.ndarray, y: np.ndarray, z: np.ndarray):
    """:func:`clearance_above` of the grid points (x[i], y[j], z[j, i]): (ny, nx); x (nx,)
    and y (ny,) ascending, inf where z is nan. The same values, each part's worked out
    only on the block of the grid under its footprint (one block, as x and y ascend), cut
    down to the points where it can lower the result: not those already with a gap no
    higher than the part's floor (the lowest parts go first, to skip the ones above)."""
    out = np.full(z.shape, np.inf)
    z0 = z + LIFT_M
    for part in sorted(parts, key=lambda p: p.bounds[0, 2]):
        (x0, y0, _), (x1, y1, z1) = part.bounds.tolist()
        i0, i1 = np.searchsorted(x, x0 - PLANE_TOL), np.searchsorted(x, x1 + PLANE_TOL, "right")
        j0, j1 = np.searchsorted(y, y0 - PLANE_TOL), np.searchsorted(y, y1 + PLANE_TOL, "right")
        if i0 >= i1 or j0 >= j1:
            continue
        zb, z0b, block = z[j0:j1, i0:i1], z0[j0:j1, i0:i1], out[j0:j1, i0:i1]
        # a point inside a part stays so; one below the floor, with a gap no higher, too
        can = (z0b < z1) & (block > 0) & ((z0b >= part._floor) | (block > part._floor - zb))
        j = np.logical_or.reduce(can, axis=1).nonzero()[0] + j0
        i = np.logical_or.reduce(can, axis=0).nonzero()[0] + i0
        if len(i) == 0:
            continue
        cols = slice(i[0], i[-1] + 1)
        chunk = max(1, CHUNK_ELEMENTS // (len(part.offsets) * (i[-1] + 1 - i[0])))
        for a in range(j[0], j[-1] + 1, chunk):
            rows = slice(a, min(a + chunk, j[-1] + 1))
            zb, z0b, block = z[rows, cols], z0[rows, cols], out[rows, cols]
            lo, hi = _grid_interval(part, x[cols], y[rows])
            hit = (z0b < z1) & (lo <= hi)  # nan (no face) is never below
            np.minimum(block, lo - zb, out=block, where=hit & (lo >= z0b))
            np.copyto(block, 0.0, where=hit & (lo < z0b) & (hi > z0b))  # inside the part
    return out


# -- the surfaces ----------------------------------------------------------------------
def support_surfaces(
    mesh_or_asset: Mesh | Asset,
    min_area: float = MIN_AREA_M2,
    normal_tol: float = NORMAL_TOL_DEG,
    min_clearance: float = MIN_CLEARANCE_M,
    min_width: float = MIN_WIDTH_M,
) -> list[SupportSurface]:
    """The support surfaces of an asset (or of a mesh of convex components), sorted by z.

    normal_tol : degrees from horizontal an up face may tilt.
    """
    meshes = part_meshes(mesh_or_asset)
    if not meshes:
        return []
    tris, normals, areas = _face_data(mesh_or_asset, meshes)
    parts = _convex_parts(meshes, tris, normals, areas)
    up = (normals[:, 2] > math.cos(math.radians(normal_tol))) & (areas > 0)
    tris, normals, areas = tris[up], normals[up], areas[up]
    if len(tris) == 0:
        return []
    zc = tris[:, :, 2].mean(1)
    order = np.argsort(zc, kind="stable")
    breaks = np.flatnonzero(np.diff(zc[order]) > HEIGHT_TOL_M) + 1
    bounds = np.array([p.bounds for p in parts]).reshape(-1, 2, 3)
    out: list[SupportSurface] = []
    for group in np.split(order, breaks):
        if areas[group].sum() < min_area:  # the free union can only be smaller
            continue
        out += _level_surfaces(
            tris[group], normals[group], parts, bounds, min_area, min_clearance, min_width
        )
    out.sort(key=lambda s: (s.z, -s.area))
    return out


_CACHE: weakref.WeakKeyDictionary[Asset, list[SupportSurface]] = weakref.WeakKeyDictionary()


def surfaces_of(asset: Asset) -> list[SupportSurface]:
    """:func:`support_surfaces` with default settings, computed once per asset object,
    and once per asset geometry on a machine: an asset built of parts has its surfaces
    kept in the surface store under the cache folder
    (:mod:`~pair2scene.assets.surface_store`), read back to the bit."""
    found = _CACHE.get(asset)
    if found is None:
        found = _stored_surfaces(asset) if asset.parts else support_surfaces(asset)
        _CACHE[asset] = found
    return found


def _stored_surfaces(asset: Asset) -> list[SupportSurface]:
    from pair2scene.assets.pointcloud import mesh_digest
    from pair2scene.assets.surface_store import default_store

    store, key = default_store(), mesh_digest(asset)
    found = store.get(key)
    if found is None:
        found = support_surfaces(asset)
        store.put(key, found)
    return found


def _level_surfaces(
    tris: np.ndarray,
    normals: np.ndarray,
    parts: list[ConvexPart],
    bounds: np.ndarray,
    min_area: float,
    min_clearance: float,
    min_width: float,
) -> list[SupportSurface]:
    """Surfaces of one height level: up faces ``tris`` (K, 3, 3) with unit ``normals``;
    ``bounds`` (P, 2, 3) are the parts' bounds."""
    from scipy import ndimage

    lo, hi = tris[:, :, :2].min((0, 1)), tris[:, :, :2].max((0, 1))
    if float((hi - lo).min()) * (1 + 1e-12) < min_width - 1e-9:
        # no run of cells is as wide (:func:`_wide_cells`): its length is at most the
        # grid's extent, summed with a relative error under 1.2e-13 (1024 lines at most)
        return []
    zmin = tris[:, :, 2].min()
    # only parts reaching above this level and overlapping it in xy can cover it
    reach = (
        (bounds[:, 1, 2] > zmin + LIFT_M)
        & np.all(bounds[:, 0, :2] < hi, axis=1)
        & np.all(bounds[:, 1, :2] > lo, axis=1)
    )
    near = [parts[k] for k in np.flatnonzero(reach)]
    max_cell = max(float((hi - lo).max()) / GRID_CELLS, MIN_CELL_M)
    extra = np.concatenate([p.vertices[:, :2] for p in near]) if near else np.zeros((0, 2))
    coords = np.concatenate([tris[:, :, :2].reshape(-1, 2), extra])
    xs = _grid_lines(coords[:, 0], lo[0], hi[0], max_cell)
    ys = _grid_lines(coords[:, 1], lo[1], hi[1], max_cell)
    cx, cy = (xs[1:] + xs[:-1]) / 2, (ys[1:] + ys[:-1]) / 2
    wx, wy = np.diff(xs), np.diff(ys)
    # rows of the grid run along y; z is nan off the faces
    z = _height_on_faces(cx, cy, tris, normals)
    clear = np.where(np.isnan(z), -1.0, _grid_clearance(near, cx, cy, z))
    free = clear >= min_clearance
    if not free.any():
        return []
    labels, count = ndimage.label(free)  # 4-connected by default
    cell_area = np.outer(wy, wx)
    wide = None

    out = []
    # each region within its bounding block: its cells in the same (row-major) order
    for k, (rows, cols) in enumerate(ndimage.find_objects(labels), start=1):
        mask = labels[rows, cols] == k
        a = cell_area[rows, cols][mask]
        area = float(a.sum())
        if area < min_area:
            continue
        if wide is None:
            wide = _wide_cells(free, wx, wy, min_width)
        if not wide[rows, cols][mask].any():
            continue
        loops = _trace(
            mask, xs[cols.start : cols.stop + 1], ys[rows.start : rows.stop + 1], max_cell
        )
        signed = [polygon_area(p) for p in loops]
        outer = int(np.argmax(signed))
        holes = tuple(p for p, s in zip(loops, signed) if s < 0)
        out.append(
            SupportSurface(
                z=float(np.average(z[rows, cols][mask], weights=a)),
                polygon=loops[outer],
                area=area,
                clearance=_weighted_percentile(clear[rows, cols][mask], a, CLEARANCE_PERCENTILE),
                holes=holes,
            )
        )
    return out


def _grid_lines(coords: np.ndarray, lo: float, hi: float, max_cell: float) -> np.ndarray:
    """Sorted grid lines from lo to hi through the given coordinates, no gap > max_cell."""
    c = np.unique(np.clip(coords, lo, hi))
    c = np.unique(np.concatenate([[lo], c, [hi]])).tolist()
    keep = [c[0]]
    for v in c[1:]:  # merge lines closer than a minimal cell
        if v - keep[-1] >= MIN_CELL_M:
            keep.append(v)
    if hi - keep[-1] < MIN_CELL_M:
        keep[-1] = hi
    c = np.asarray(keep)
    pieces = np.maximum(np.ceil(np.diff(c) / max_cell - 1e-9).astype(int), 1)
    if pieces.sum() + 1 > MAX_GRID_LINES:
        return np.linspace(lo, hi, int(np.ceil((hi - lo) / max_cell)) + 1)
    # each gap a..b in m pieces, as np.linspace(a, b, m + 1)[1:] has them: a + k (b - a) / m,
    # b itself last (the gaps are at least MIN_CELL_M: the step is never zero)
    ends = np.cumsum(pieces)
    k = np.arange(1, pieces.sum() + 1) - np.repeat(ends - pieces, pieces)
    lines = np.repeat((c[1:] - c[:-1]) / pieces, pieces) * k + np.repeat(c[:-1], pieces)
    lines[ends - 1] = c[1:]
    return np.concatenate([c[:1], lines])


def _height_on_faces(
    cx: np.ndarray, cy: np.ndarray, tris: np.ndarray, normals: np.ndarray
) -> np.ndarray:
    """(ny, nx) height of the highest face (K, 3, 3) over each grid cell centre (cx (nx,),
    cy (ny,)); nan where no face is."""
    out = np.full((len(cy), len(cx)), -np.inf)
    lo, hi = tris[:, :, :2].min(1), tris[:, :, :2].max(1)
    # each triangle only visits the block of cells under its bounding box
    i0, i1 = np.searchsorted(cx, lo[:, 0] - 1e-9), np.searchsorted(cx, hi[:, 0] + 1e-9)
    j0, j1 = np.searchsorted(cy, lo[:, 1] - 1e-9), np.searchsorted(cy, hi[:, 1] + 1e-9)
    a, b, q = tris[:, 0], tris[:, 1], tris[:, 2]
    dets = (b[:, 0] - a[:, 0]) * (q[:, 1] - a[:, 1]) - (q[:, 0] - a[:, 0]) * (b[:, 1] - a[:, 1])
    k = np.flatnonzero((i1 > i0) & (j1 > j0) & (dets != 0))
    faces = zip(*(v[k].tolist() for v in (i0, i1, j0, j1, tris, dets, normals)))
    column = cy[:, None]
    for i0k, i1k, j0k, j1k, ((ax, ay, az), (bx, by, _), (qx, qy, _)), det, n in faces:
        nx, ny, nz = n
        x, y = cx[i0k:i1k], column[j0k:j1k]
        # barycentric coordinates of the cell centres in the projected triangle
        qx_x, qy_y = qx - x, qy - y
        u = (bx - x) * qy_y
        u -= qx_x * (by - y)
        u /= det
        v = qx_x * (ay - y)
        v -= (ax - x) * qy_y
        v /= det
        inside = u >= -1e-9
        inside &= v >= -1e-9
        w = np.subtract(1, u, out=u)
        w -= v
        inside &= w >= -1e-9
        if nx == 0 and ny == 0 and az != 0:
            z = az  # a level face: az less a zero is az (only a zero az could change sign)
        else:
            z = nx * (x - ax) + ny * (y - ay)
            z /= nz
            z = np.subtract(az, z, out=z)
        block = out[j0k:j1k, i0k:i1k]
        np.maximum(block, z, out=block, where=inside)
    out[np.isinf(out)] = np.nan
    return out


def _in_long_run(mask: np.ndarray, widths: np.ndarray, least: float) -> np.ndarray:
    """(R, C) which True cells lie in a run of True cells along their row at least
    ``least`` long (m), the run's cell widths (C,) summed in order."""
    start = mask.copy()
    start[:, 1:] &= ~mask[:, :-1]
    run = np.cumsum(start, axis=None).reshape(mask.shape)  # one id per run, row-major
    w = np.broadcast_to(widths, mask.shape)
    length = np.bincount(run[mask], weights=w[mask], minlength=run[-1, -1] + 1)
    return (length >= least)[run] & mask


def _wide_cells(mask: np.ndarray, wx: np.ndarray, wy: np.ndarray, min_width: float) -> np.ndarray:
    """(R, C) True cells whose row run and column run are both at least ``min_width``; a
    region is wide enough where it has one (a run lies within one region)."""
    along_x = _in_long_run(mask, wx, min_width - 1e-9)
    along_y = _in_long_run(np.ascontiguousarray(mask.T), wy, min_width - 1e-9).T
    return along_x & along_y


def _trace(mask: np.ndarray, xs: np.ndarray, ys: np.ndarray, simplify: float) -> list[np.ndarray]:
    """Boundary loops of a cell mask (ny, nx) on grid lines xs (nx+1,), ys (ny+1,): each
    (N, 2), outer loops counter-clockwise, holes clockwise."""
    ny, nx = mask.shape
    m = np.zeros((ny + 2, nx + 2), dtype=bool)
    m[1:-1, 1:-1] = mask
    # lattice vertex (i, j) is (xs[i], ys[j]), numbered j * w + i; cell (row j, col i) spans
    # i..i+1, j..j+1; each boundary side is walked with the cell on its left
    # (counter-clockwise): the sides of each kind in row-major order of their cells
    w = nx + 1
    sides = (
        (m[:-2, 1:-1], 0, 1),  # below (row j-1) empty: (i, j) -> (i+1, j)
        (m[1:-1, 2:], 1, 1 + w),  # right empty
        (m[2:, 1:-1], 1 + w, w),  # above empty
        (m[1:-1, :-2], w, 0),  # left empty
    )
    cells = [np.flatnonzero(mask & ~beside) for beside, _, _ in sides]
    corner = [k + k // nx for k in cells]  # the cell's lattice vertex (i, j)
    tail = np.concatenate([k + a for k, (_, a, _) in zip(corner, sides)])
    head = np.concatenate([k + b for k, (_, _, b) in zip(corner, sides)])
    order = np.argsort(tail, kind="stable")
    one = tail[order][1:] != tail[order][:-1]
    paths = _cycles(tail, head, order) if one.all() else _walk(tail, head, order, one, w)
    loops = []
    for idx in paths:
        pts = np.column_stack([xs[idx % w], ys[idx // w]])
        loops.append(_simplify_ring(_drop_collinear(pts), simplify))
    return loops


def _cycles(tail: np.ndarray, head: np.ndarray, order: np.ndarray) -> list[np.ndarray]:
    """The loops of boundary sides ``tail -> head`` (E,) when one side leaves each vertex
    (``order`` sorts ``tail``): each loop's vertices from the tail of its first side in the
    given order of sides, the loops in the order of their first sides, as :func:`_walk`
    finds them. Pointer doubling: each side's loop's first side, then its place in it."""
    n = len(tail)
    ahead = order[np.searchsorted(tail[order], head)]  # the side out of each side's head
    side = np.arange(n)
    rounds = max(1, (n - 1).bit_length())  # 2**rounds sides reach round any loop
    first, step = side, ahead
    for _ in range(rounds):
        first, step = np.minimum(first, first[step]), step[step]
    behind = np.empty_like(ahead)
    behind[ahead] = side
    starts = first == side
    place, step = (~starts).astype(np.intp), np.where(starts, side, behind)
    for _ in range(rounds):
        place, step = place + place[step], step[step]
    walk = np.lexsort((place, first))
    return np.split(tail[walk], np.flatnonzero(starts[walk])[1:])


def _walk(
    tail: np.ndarray, head: np.ndarray, order: np.ndarray, one: np.ndarray, w: int
) -> list[np.ndarray]:
    """The loops of boundary sides ``tail -> head`` (E,) on a lattice w vertices wide, each
    as its vertices: from the first vertex (in the order of their first side out) with a
    side left, until back there. At most two sides leave a vertex (two cells touching at
    a corner), taken in the given order; arriving there, the one turning left is taken,
    which keeps the cells apart (``order`` sorts ``tail``; ``one``: which of its
    neighbours in that order differ)."""
    first = np.concatenate([[True], one])
    nxt = dict(zip(tail[order[first]].tolist(), head[order[first]].tolist()))
    second = dict(zip(tail[order[~first]].tolist(), head[order[~first]].tolist()))
    starts = tail[np.sort(order[first])].tolist()
    left = {1: w, w: -1, -1: -w, -w: 1}  # the step turned left, by step
    paths = []
    k = 0
    while True:  # from the first vertex with a side left, as long as there is one
        while k < len(starts) and starts[k] not in nxt:
            k += 1
        if k == len(starts):
            return paths
        start = starts[k]
        path = [start]
        cur, step = start, 0
        while True:
            if cur not in second:
                new = nxt.pop(cur)
            elif step and nxt[cur] - cur != left[step] and second[cur] - cur == left[step]:
                new = second.pop(cur)  # a pinch: turn left
            else:
                new = nxt[cur]
                nxt[cur] = second.pop(cur)
            step, cur = new - cur, new
            if cur == start:
                break
            path.append(cur)
        paths.append(np.asarray(path))


def _drop_collinear(p: np.ndarray) -> np.ndarray:
    """Remove vertices (N, 2) of a closed ring that lie on a straight run."""
    ahead = np.diff(p, axis=0, append=p[:1])  # p[i + 1] - p[i], round the ring
    behind = np.concatenate([ahead[-1:], ahead[:-1]])  # p[i] - p[i - 1]
    cross = behind[:, 0] * ahead[:, 1] - behind[:, 1] * ahead[:, 0]
    keep = np.abs(cross) > 1e-15
    return p[keep] if keep.sum() >= 3 else p


def _simplify_ring(p: np.ndarray, tol: float) -> np.ndarray:
    """Douglas-Peucker on a closed ring (N, 2): smooths the staircase of a round edge."""
    if len(p) <= 4:
        return p
    far = int(np.argmax(np.linalg.norm(p - p[0], axis=1)))
    a = _simplify_open(p[: far + 1], tol)
    b = _simplify_open(np.concatenate([p[far:], p[:1]]), tol)
    out = np.concatenate([a[:-1], b[:-1]])
    return out if len(out) >= 3 else p


def _simplify_open(p: np.ndarray, tol: float) -> np.ndarray:
    """Douglas-Peucker on an open polyline (N, 2); the distances in Python floats (the same
    double arithmetic: most pieces are a few points, too few for numpy to pay)."""
    xs, ys = p[:, 0].tolist(), p[:, 1].tolist()
    keep = np.zeros(len(p), dtype=bool)
    keep[[0, -1]] = True
    stack = [(0, len(p) - 1)]
    while stack:
        i, j = stack.pop()
        if j <= i + 1:
            continue
        x0, y0 = xs[i], ys[i]
        dx, dy = xs[j] - x0, ys[j] - y0
        norm = np.hypot(dx, dy)
        far, k = -1.0, -1  # the first farthest point
        for m in range(i + 1, j):
            if norm > 0:
                dist = abs((xs[m] - x0) * dy - (ys[m] - y0) * dx) / norm
            else:
                dist = np.hypot(xs[m] - x0, ys[m] - y0)
            if dist > far:
                far, k = dist, m
        if far > tol:
            keep[k] = True
            stack += [(i, k), (k, j)]
    return p[keep]


def _weighted_percentile(values: np.ndarray, weights: np.ndarray, q: float) -> float:
    order = np.argsort(values)
    cum = np.cumsum(weights[order])
    k = int(np.searchsorted(cum, q / 100 * cum[-1]))
    return float(values[order[min(k, len(values) - 1)]])

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

Parts are the asset's convex parts, or the connected components of a bare
:class:`~pair2scene.assets.mesh.Mesh`. A component that is not convex is treated
as its convex hull (so its own concave pockets read as solid): every asset built
from ``mesh.py`` primitives, and every library asset, has convex parts.
"""

from __future__ import annotations

import math
import weakref
from collections import defaultdict
from dataclasses import dataclass, field

import numpy as np

from pair2scene.assets.mesh import Asset, Mesh

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
        inside = _point_in_polygon(xy, self.polygon)
        for h in self.holes:
            inside &= ~_point_in_polygon(xy, h)
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


def convex_part(mesh: Mesh) -> ConvexPart | None:
    """Half-spaces of ``mesh`` (of its convex hull if it is not convex); None when the mesh
    has no faces, or is not convex and has no volume."""
    if len(mesh.faces) == 0:
        return None
    if mesh.is_convex():
        keep = mesh.face_areas > 0
        n = mesh.face_normals[keep]
        d = np.einsum("ij,ij->i", n, mesh.triangles[keep, 0])
    else:
        from scipy.spatial import ConvexHull, QhullError

        try:
            eq = ConvexHull(mesh.vertices).equations
        except (QhullError, ValueError):
            return None
        n, d = eq[:, :3], -eq[:, 3]
    if len(n) == 0:
        return None
    planes = np.unique(np.round(np.c_[n, d], 9), axis=0)
    return ConvexPart(planes[:, :3], planes[:, 3], mesh.bounds, mesh.vertices)


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
    up, down = nz > 1e-12, nz < -1e-12
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
    parts = [p for p in (convex_part(m) for m in meshes) if p is not None]
    if not meshes:
        return []
    tris = np.concatenate([m.triangles for m in meshes])  # (F, 3, 3)
    normals = np.concatenate([m.face_normals for m in meshes])
    areas = np.concatenate([m.face_areas for m in meshes])
    up = (normals[:, 2] > math.cos(math.radians(normal_tol))) & (areas > 0)
    tris, normals, areas = tris[up], normals[up], areas[up]
    if len(tris) == 0:
        return []
    zc = tris[:, :, 2].mean(1)
    order = np.argsort(zc, kind="stable")
    breaks = np.flatnonzero(np.diff(zc[order]) > HEIGHT_TOL_M) + 1
    out: list[SupportSurface] = []
    for group in np.split(order, breaks):
        if areas[group].sum() < min_area:  # the free union can only be smaller
            continue
        out += _level_surfaces(
            tris[group], normals[group], parts, min_area, min_clearance, min_width
        )
    out.sort(key=lambda s: (s.z, -s.area))
    return out


_CACHE: weakref.WeakKeyDictionary[Asset, list[SupportSurface]] = weakref.WeakKeyDictionary()


def surfaces_of(asset: Asset) -> list[SupportSurface]:
    """:func:`support_surfaces` with default settings, computed once per asset object."""
    found = _CACHE.get(asset)
    if found is None:
        found = support_surfaces(asset)
        _CACHE[asset] = found
    return found


def _level_surfaces(
    tris: np.ndarray,
    normals: np.ndarray,
    parts: list[ConvexPart],
    min_area: float,
    min_clearance: float,
    min_width: float,
) -> list[SupportSurface]:
    """Surfaces of one height level: up faces ``tris`` (K, 3, 3) with unit ``normals``."""
    from scipy import ndimage

    lo, hi = tris[:, :, :2].min((0, 1)), tris[:, :, :2].max((0, 1))
    zmin = tris[:, :, 2].min()
    # only parts reaching above this level and overlapping it in xy can cover it
    near = [
        p
        for p in parts
        if p.bounds[1, 2] > zmin + LIFT_M
        and np.all(p.bounds[0, :2] < hi)
        and np.all(p.bounds[1, :2] > lo)
    ]
    max_cell = max(float((hi - lo).max()) / GRID_CELLS, MIN_CELL_M)
    extra = np.concatenate([p.vertices[:, :2] for p in near]) if near else np.zeros((0, 2))
    coords = np.concatenate([tris[:, :, :2].reshape(-1, 2), extra])
    xs = _grid_lines(coords[:, 0], lo[0], hi[0], max_cell)
    ys = _grid_lines(coords[:, 1], lo[1], hi[1], max_cell)
    cx, cy = (xs[1:] + xs[:-1]) / 2, (ys[1:] + ys[:-1]) / 2
    wx, wy = np.diff(xs), np.diff(ys)
    gx, gy = np.meshgrid(cx, cy)  # (ny, nx): rows run along y
    centres = np.c_[gx.ravel(), gy.ravel()]

    z = _height_on_faces(cx, cy, tris, normals).ravel()  # (M,), nan off the faces
    on = np.flatnonzero(~np.isnan(z))
    clear = np.full(len(centres), -1.0)
    clear[on] = clearance_above(near, np.c_[centres[on], z[on]])
    free = (clear >= min_clearance).reshape(len(cy), len(cx))
    labels, count = ndimage.label(free)  # 4-connected by default
    cell_area = np.outer(wy, wx)
    flat_z, flat_clear = z.reshape(free.shape), clear.reshape(free.shape)

    out = []
    for k in range(1, count + 1):
        mask = labels == k
        a = cell_area[mask]
        area = float(a.sum())
        if area < min_area or not _wide_enough(mask, wx, wy, min_width):
            continue
        loops = _trace(mask, xs, ys, simplify=max_cell)
        signed = [_signed_area(p) for p in loops]
        outer = int(np.argmax(signed))
        holes = tuple(p for p, s in zip(loops, signed) if s < 0)
        out.append(
            SupportSurface(
                z=float(np.average(flat_z[mask], weights=a)),
                polygon=loops[outer],
                area=area,
                clearance=_weighted_percentile(flat_clear[mask], a, CLEARANCE_PERCENTILE),
                holes=holes,
            )
        )
    return out


def _grid_lines(coords: np.ndarray, lo: float, hi: float, max_cell: float) -> np.ndarray:
    """Sorted grid lines from lo to hi through the given coordinates, no gap > max_cell."""
    c = np.unique(np.clip(coords, lo, hi))
    c = np.unique(np.concatenate([[lo], c, [hi]]))
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
    lines = [c[:1]] + [np.linspace(a, b, m + 1)[1:] for a, b, m in zip(c[:-1], c[1:], pieces)]
    return np.concatenate(lines)


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
    for k in np.flatnonzero((i1 > i0) & (j1 > j0)):
        (ax, ay, az), (bx, by, _), (qx, qy, _) = tris[k]
        det = (bx - ax) * (qy - ay) - (qx - ax) * (by - ay)
        if det == 0:
            continue
        x, y = cx[None, i0[k] : i1[k]], cy[j0[k] : j1[k], None]
        # barycentric coordinates of the cell centres in the projected triangle
        u = ((bx - x) * (qy - y) - (qx - x) * (by - y)) / det
        v = ((qx - x) * (ay - y) - (ax - x) * (qy - y)) / det
        inside = (u >= -1e-9) & (v >= -1e-9) & (1 - u - v >= -1e-9)
        n = normals[k]
        z = az - (n[0] * (x - ax) + n[1] * (y - ay)) / n[2]
        block = out[j0[k] : j1[k], i0[k] : i1[k]]
        np.maximum(block, np.where(inside, z, -np.inf), out=block)
    out[np.isinf(out)] = np.nan
    return out


def _run_lengths(mask: np.ndarray, widths: np.ndarray) -> np.ndarray:
    """(R, C) length (m) of the run of True cells along each row holding each cell."""
    start = mask & ~np.pad(mask, ((0, 0), (1, 0)))[:, :-1]
    run = np.cumsum(start.ravel()).reshape(mask.shape)  # one id per run, row-major
    w = np.broadcast_to(widths, mask.shape)
    length = np.bincount(run[mask], weights=w[mask], minlength=run.max() + 1)
    return np.where(mask, length[run], 0.0)


def _wide_enough(mask: np.ndarray, wx: np.ndarray, wy: np.ndarray, min_width: float) -> bool:
    """Some cell's row run and column run are both at least ``min_width``."""
    along_x = _run_lengths(mask, wx)
    along_y = _run_lengths(mask.T, wy).T
    return bool(np.any((along_x >= min_width - 1e-9) & (along_y >= min_width - 1e-9)))


def _trace(mask: np.ndarray, xs: np.ndarray, ys: np.ndarray, simplify: float) -> list[np.ndarray]:
    """Boundary loops of a cell mask (ny, nx) on grid lines xs (nx+1,), ys (ny+1,): each
    (N, 2), outer loops counter-clockwise, holes clockwise."""
    m = np.pad(mask, 1)
    inner = m[1:-1, 1:-1]
    r, c = np.nonzero(inner)
    edges: dict[tuple[int, int], list[tuple[int, int]]] = defaultdict(list)
    # lattice vertex (i, j) is (xs[i], ys[j]); cell (row j, col i) spans i..i+1, j..j+1;
    # each boundary side is walked with the cell on its left (counter-clockwise)
    sides = (
        (~m[r, c + 1], (0, 0), (1, 0)),  # below (row j-1) empty
        (~m[r + 1, c + 2], (1, 0), (1, 1)),  # right empty
        (~m[r + 2, c + 1], (1, 1), (0, 1)),  # above empty
        (~m[r + 1, c], (0, 1), (0, 0)),  # left empty
    )
    for sel, (ax, ay), (bx, by) in sides:
        for i, j in zip(c[sel].tolist(), r[sel].tolist()):
            edges[(i + ax, j + ay)].append((i + bx, j + by))
    loops = []
    while edges:
        start = next(iter(edges))
        path = [start]
        cur, prev_dir = start, None
        while True:
            outs = edges[cur]
            if len(outs) == 1 or prev_dir is None:
                nxt = outs.pop(0)
            else:  # a pinch (cells touching at a corner): turn left, keep them apart
                left = (-prev_dir[1], prev_dir[0])
                idx = next(
                    (q for q, e in enumerate(outs) if (e[0] - cur[0], e[1] - cur[1]) == left), 0
                )
                nxt = outs.pop(idx)
            if not outs:
                del edges[cur]
            prev_dir = (nxt[0] - cur[0], nxt[1] - cur[1])
            cur = nxt
            if cur == start:
                break
            path.append(cur)
        idx = np.asarray(path)
        pts = np.c_[xs[idx[:, 0]], ys[idx[:, 1]]]
        loops.append(_simplify_ring(_drop_collinear(pts), simplify))
    return loops


def _drop_collinear(p: np.ndarray) -> np.ndarray:
    """Remove vertices (N, 2) of a closed ring that lie on a straight run."""
    prev, nxt = np.roll(p, 1, 0), np.roll(p, -1, 0)
    cross = (p[:, 0] - prev[:, 0]) * (nxt[:, 1] - p[:, 1]) - (p[:, 1] - prev[:, 1]) * (
        nxt[:, 0] - p[:, 0]
    )
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
    keep = np.zeros(len(p), dtype=bool)
    keep[[0, -1]] = True
    stack = [(0, len(p) - 1)]
    while stack:
        i, j = stack.pop()
        if j <= i + 1:
            continue
        d = p[j] - p[i]
        q = p[i + 1 : j] - p[i]
        norm = np.hypot(*d)
        dist = (
            np.abs(q[:, 0] * d[1] - q[:, 1] * d[0]) / norm
            if norm > 0
            else np.hypot(q[:, 0], q[:, 1])
        )
        k = int(np.argmax(dist))
        if dist[k] > tol:
            keep[i + 1 + k] = True
            stack += [(i, i + 1 + k), (i + 1 + k, j)]
    return p[keep]


def _signed_area(p: np.ndarray) -> float:
    x, y = p[:, 0], p[:, 1]
    return float(0.5 * (np.dot(x, np.roll(y, -1)) - np.dot(y, np.roll(x, -1))))


def _weighted_percentile(values: np.ndarray, weights: np.ndarray, q: float) -> float:
    order = np.argsort(values)
    cum = np.cumsum(weights[order])
    k = int(np.searchsorted(cum, q / 100 * cum[-1]))
    return float(values[order][min(k, len(values) - 1)])


def _point_in_polygon(xy: np.ndarray, poly: np.ndarray) -> np.ndarray:
    """(M,) even-odd test of points (M, 2) against a ring (N, 2)."""
    a, b = poly, np.roll(poly, -1, 0)
    x, y = xy[:, :1], xy[:, 1:]
    crosses = (a[:, 1] > y) != (b[:, 1] > y)
    with np.errstate(divide="ignore", invalid="ignore"):
        xint = a[:, 0] + (y - a[:, 1]) * (b[:, 0] - a[:, 0]) / (b[:, 1] - a[:, 1])
    return (np.count_nonzero(crosses & (x < xint), axis=1) % 2) == 1

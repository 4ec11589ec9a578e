"""Support surfaces are the same, to the bit, as those of the plain reference below.

The reference is the straightforward form of the method (one triangle, one part, one
region at a time; every ray clipped by every plane of a part); ``surfaces.py`` arranges
the same floating-point operations to do much less work. Any change there that moves a
single bit of a height, an outline or a clearance fails here.
"""

from __future__ import annotations

import math
from collections import defaultdict

import numpy as np
import pytest
from scipy import ndimage

from pair2scene.assets import surfaces as S
from pair2scene.assets.mesh import Asset, Mesh, Part, box, cylinder, ellipsoid, frustum
from pair2scene.assets.registry import generate
from pair2scene.assets.typical_sizes import typical_size

CASES = [
    ("shelving_unit", 0, 1.0, 3),
    ("dining_table", 1, 1.0, 3),
    ("bed", 0, 1.0, 3),
    ("sofa", 2, 1.3, 3),
    ("chair", 2, 1.0, 3),
    ("house_plant", 1, 1.0, 3),
    ("teddy_bear", 1, 0.7, 3),
    ("bowl", 0, 1.0, 3),
    ("fridge", 1, 1.0, 3),
    ("counter_top", 0, 1.0, 3),
    ("desk", 1, 1.4, 3),
    ("armchair", 2, 1.0, 3),
    ("decor", 0, 1.0, 3),
    ("stool", 2, 0.7, 3),
    ("ceiling_lamp", 0, 1.0, 3),
    ("vacuum_cleaner", 0, 1.0, 13),
    ("tilted", 0, 1.0, 0),
]
"""(category, style, scale of its typical size, seed): boxes, round and slanted parts, fans
of thin triangles, holes, overhangs."""


def _asset(category: str, style: int, scale: float, seed: int) -> Asset:
    if category == "tilted":
        return _tilted()
    size = np.array(typical_size(category).size) * scale
    return generate(category, size, rng=seed, style=style)


def _tilted() -> Asset:
    """A seat tilted back 4 degrees, a round stool top and a shelf hanging over both."""
    a = math.radians(4)
    rot = np.array([[1, 0, 0], [0, math.cos(a), -math.sin(a)], [0, math.sin(a), math.cos(a)]])
    parts = [
        Part("seat", box((0.0, 0.0, 0.2), (0.5, 0.45, 0.05), rotation=rot)),
        Part("stool", cylinder((0.55, 0.1, 0.15), 0.18, 0.3, segments=24)),
        Part("shelf", box((0.3, 0.25, 0.45), (0.6, 0.2, 0.03))),
    ]
    lo, hi = Mesh.concat([p.mesh for p in parts]).bounds
    return Asset("chair", hi - lo, tuple(parts))


# -- the reference -----------------------------------------------------------------------
def ref_convex_part(mesh: Mesh) -> S.ConvexPart | None:
    if len(mesh.faces) == 0:
        return None
    if mesh.is_convex():
        keep = mesh.face_areas > 0
        n = mesh.face_normals[keep]
        d = np.einsum("ij,ij->i", n, mesh.triangles[keep, 0])
    else:
        from scipy.spatial import ConvexHull

        eq = ConvexHull(mesh.vertices).equations
        n, d = eq[:, :3], -eq[:, 3]
    planes = np.unique(np.round(np.c_[n, d], 9), axis=0)
    return S.ConvexPart(planes[:, :3], planes[:, 3], mesh.bounds, mesh.vertices)


def ref_support_surfaces(mesh_or_asset: Mesh | Asset) -> list[S.SupportSurface]:
    meshes = S.part_meshes(mesh_or_asset)
    parts = [p for p in (ref_convex_part(m) for m in meshes) if p is not None]
    tris = np.concatenate([m.triangles for m in meshes])
    normals = np.concatenate([m.face_normals for m in meshes])
    areas = np.concatenate([m.face_areas for m in meshes])
    up = (normals[:, 2] > math.cos(math.radians(S.NORMAL_TOL_DEG))) & (areas > 0)
    tris, normals, areas = tris[up], normals[up], areas[up]
    zc = tris[:, :, 2].mean(1)
    order = np.argsort(zc, kind="stable")
    out = []
    for group in np.split(order, np.flatnonzero(np.diff(zc[order]) > S.HEIGHT_TOL_M) + 1):
        if areas[group].sum() >= S.MIN_AREA_M2:
            out += ref_level(tris[group], normals[group], parts)
    out.sort(key=lambda s: (s.z, -s.area))
    return out


def ref_level(tris, normals, parts) -> list[S.SupportSurface]:
    lo, hi = tris[:, :, :2].min((0, 1)), tris[:, :, :2].max((0, 1))
    zmin = tris[:, :, 2].min()
    near = [
        p
        for p in parts
        if p.bounds[1, 2] > zmin + S.LIFT_M
        and np.all(p.bounds[0, :2] < hi)
        and np.all(p.bounds[1, :2] > lo)
    ]
    max_cell = max(float((hi - lo).max()) / S.GRID_CELLS, S.MIN_CELL_M)
    extra = np.concatenate([p.vertices[:, :2] for p in near]) if near else np.zeros((0, 2))
    coords = np.concatenate([tris[:, :, :2].reshape(-1, 2), extra])
    xs = ref_grid_lines(coords[:, 0], lo[0], hi[0], max_cell)
    ys = ref_grid_lines(coords[:, 1], lo[1], hi[1], max_cell)
    cx, cy = (xs[1:] + xs[:-1]) / 2, (ys[1:] + ys[:-1]) / 2
    wx, wy = np.diff(xs), np.diff(ys)
    gx, gy = np.meshgrid(cx, cy)
    centres = np.c_[gx.ravel(), gy.ravel()]
    z = ref_height_on_faces(cx, cy, tris, normals).ravel()
    on = np.flatnonzero(~np.isnan(z))
    clear = np.full(len(centres), -1.0)
    clear[on] = S.clearance_above(near, np.c_[centres[on], z[on]])  # one ray at a time
    free = (clear >= S.MIN_CLEARANCE_M).reshape(len(cy), len(cx))
    labels, count = ndimage.label(free)
    cell_area = np.outer(wy, wx)
    flat_z, flat_clear = z.reshape(free.shape), clear.reshape(free.shape)
    out = []
    for k in range(1, count + 1):
        mask = labels == k
        a = cell_area[mask]
        area = float(a.sum())
        along_x = ref_run_lengths(mask, wx)
        along_y = ref_run_lengths(mask.T, wy).T
        wide = np.any((along_x >= S.MIN_WIDTH_M - 1e-9) & (along_y >= S.MIN_WIDTH_M - 1e-9))
        if area < S.MIN_AREA_M2 or not wide:
            continue
        loops = ref_trace(mask, xs, ys, max_cell)
        signed = [ref_signed_area(p) for p in loops]
        values, order = flat_clear[mask], np.argsort(flat_clear[mask])
        cum = np.cumsum(a[order])
        k5 = int(np.searchsorted(cum, S.CLEARANCE_PERCENTILE / 100 * cum[-1]))
        out.append(
            S.SupportSurface(
                z=float(np.average(flat_z[mask], weights=a)),
                polygon=loops[int(np.argmax(signed))],
                area=area,
                clearance=float(values[order][min(k5, len(values) - 1)]),
                holes=tuple(p for p, s in zip(loops, signed) if s < 0),
            )
        )
    return out


def ref_grid_lines(coords, lo, hi, max_cell):
    c = np.unique(np.clip(coords, lo, hi))
    c = np.unique(np.concatenate([[lo], c, [hi]]))
    keep = [c[0]]
    for v in c[1:]:
        if v - keep[-1] >= S.MIN_CELL_M:
            keep.append(v)
    if hi - keep[-1] < S.MIN_CELL_M:
        keep[-1] = hi
    c = np.asarray(keep)
    pieces = np.maximum(np.ceil(np.diff(c) / max_cell - 1e-9).astype(int), 1)
    if pieces.sum() + 1 > S.MAX_GRID_LINES:
        return np.linspace(lo, hi, int(np.ceil((hi - lo) / max_cell)) + 1)
    lines = [c[:1]] + [np.linspace(a, b, m + 1)[1:] for a, b, m in zip(c[:-1], c[1:], pieces)]
    return np.concatenate(lines)


def ref_height_on_faces(cx, cy, tris, normals):
    out = np.full((len(cy), len(cx)), -np.inf)
    lo, hi = tris[:, :, :2].min(1), tris[:, :, :2].max(1)
    i0, i1 = np.searchsorted(cx, lo[:, 0] - 1e-9), np.searchsorted(cx, hi[:, 0] + 1e-9)
    j0, j1 = np.searchsorted(cy, lo[:, 1] - 1e-9), np.searchsorted(cy, hi[:, 1] + 1e-9)
    for k in np.flatnonzero((i1 > i0) & (j1 > j0)):
        (ax, ay, az), (bx, by, _), (qx, qy, _) = tris[k]
        det = (bx - ax) * (qy - ay) - (qx - ax) * (by - ay)
        if det == 0:
            continue
        x, y = cx[None, i0[k] : i1[k]], cy[j0[k] : j1[k], None]
        u = ((bx - x) * (qy - y) - (qx - x) * (by - y)) / det
        v = ((qx - x) * (ay - y) - (ax - x) * (qy - y)) / det
        inside = (u >= -1e-9) & (v >= -1e-9) & (1 - u - v >= -1e-9)
        n = normals[k]
        z = az - (n[0] * (x - ax) + n[1] * (y - ay)) / n[2]
        block = out[j0[k] : j1[k], i0[k] : i1[k]]
        np.maximum(block, np.where(inside, z, -np.inf), out=block)
    out[np.isinf(out)] = np.nan
    return out


def ref_run_lengths(mask, widths):
    start = mask & ~np.pad(mask, ((0, 0), (1, 0)))[:, :-1]
    run = np.cumsum(start.ravel()).reshape(mask.shape)
    w = np.broadcast_to(widths, mask.shape)
    length = np.bincount(run[mask], weights=w[mask], minlength=run.max() + 1)
    return np.where(mask, length[run], 0.0)


def ref_trace(mask, xs, ys, simplify):
    m = np.pad(mask, 1)
    r, c = np.nonzero(m[1:-1, 1:-1])
    edges = defaultdict(list)
    sides = (
        (~m[r, c + 1], (0, 0), (1, 0)),
        (~m[r + 1, c + 2], (1, 0), (1, 1)),
        (~m[r + 2, c + 1], (1, 1), (0, 1)),
        (~m[r + 1, c], (0, 1), (0, 0)),
    )
    for sel, (ax, ay), (bx, by) in sides:
        for i, j in zip(c[sel].tolist(), r[sel].tolist()):
            edges[(i + ax, j + ay)].append((i + bx, j + by))
    loops = []
    while edges:
        start = next(iter(edges))
        path, cur, prev = [start], start, None
        while True:
            outs = edges[cur]
            if len(outs) == 1 or prev is None:
                nxt = outs.pop(0)
            else:
                left = (-prev[1], prev[0])
                q = next(
                    (q for q, e in enumerate(outs) if (e[0] - cur[0], e[1] - cur[1]) == left), 0
                )
                nxt = outs.pop(q)
            if not outs:
                del edges[cur]
            prev, cur = (nxt[0] - cur[0], nxt[1] - cur[1]), nxt
            if cur == start:
                break
            path.append(cur)
        idx = np.asarray(path)
        loops.append(
            ref_simplify_ring(ref_drop_collinear(np.c_[xs[idx[:, 0]], ys[idx[:, 1]]]), simplify)
        )
    return loops


def ref_drop_collinear(p):
    prev, nxt = np.roll(p, 1, 0), np.roll(p, -1, 0)
    cross = (p[:, 0] - prev[:, 0]) * (nxt[:, 1] - p[:, 1]) - (p[:, 1] - prev[:, 1]) * (
        nxt[:, 0] - p[:, 0]
    )
    keep = np.abs(cross) > 1e-15
    return p[keep] if keep.sum() >= 3 else p


def ref_simplify_ring(p, tol):
    if len(p) <= 4:
        return p
    far = int(np.argmax(np.linalg.norm(p - p[0], axis=1)))
    a = ref_simplify_open(p[: far + 1], tol)
    b = ref_simplify_open(np.concatenate([p[far:], p[:1]]), tol)
    out = np.concatenate([a[:-1], b[:-1]])
    return out if len(out) >= 3 else p


def ref_simplify_open(p, tol):
    keep = np.zeros(len(p), dtype=bool)
    keep[[0, -1]] = True
    stack = [(0, len(p) - 1)]
    while stack:
        i, j = stack.pop()
        if j <= i + 1:
            continue
        d, q = p[j] - p[i], p[i + 1 : j] - p[i]
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


def ref_signed_area(p):
    x, y = p[:, 0], p[:, 1]
    return float(0.5 * (np.dot(x, np.roll(y, -1)) - np.dot(y, np.roll(x, -1))))


# -- comparisons ---------------------------------------------------------------------------
def same_bits(a: np.ndarray, b: np.ndarray) -> bool:
    return a.dtype == b.dtype and a.shape == b.shape and a.tobytes() == b.tobytes()


def assert_same_surfaces(got: list[S.SupportSurface], want: list[S.SupportSurface]) -> None:
    assert len(got) == len(want)
    for s, t in zip(got, want):
        for name in ("z", "area", "clearance"):  # repr tells -0.0 from 0.0
            assert repr(getattr(s, name)) == repr(getattr(t, name)), name
        assert same_bits(s.polygon, t.polygon)
        assert len(s.holes) == len(t.holes)
        assert all(same_bits(h, k) for h, k in zip(s.holes, t.holes))


def assert_same_part(got: S.ConvexPart, want: S.ConvexPart) -> None:
    for name in ("normals", "offsets", "bounds", "vertices"):
        assert same_bits(getattr(got, name), getattr(want, name)), name


@pytest.mark.parametrize("case", CASES)
def test_surfaces_match_the_reference(case):
    want = ref_support_surfaces(_asset(*case))
    assert_same_surfaces(S.support_surfaces(_asset(*case)), want)


def test_surfaces_of_a_bare_mesh_match_the_reference():
    for case in CASES[:4]:
        mesh = _asset(*case).mesh  # its parts are its components
        assert_same_surfaces(S.support_surfaces(mesh), ref_support_surfaces(mesh))


@pytest.mark.parametrize("case", CASES[::3])
def test_convex_parts_match_the_reference(case):
    want = [ref_convex_part(p.mesh) for p in _asset(*case).parts]
    # from the asset's whole mesh, and from each part's own mesh
    got = S.convex_parts(_asset(*case))
    one = [S.convex_part(p.mesh) for p in _asset(*case).parts]
    assert len(got) == len(one) == len(want)
    for a, b, c in zip(got, one, want):
        assert_same_part(a, c)
        assert_same_part(b, c)


def _random_parts(rng: np.random.Generator, n: int) -> list[S.ConvexPart]:
    """Boxes (some turned), cylinders, cones and ellipsoids, stacked over a 1 m square."""
    meshes = []
    for _ in range(n):
        c = np.r_[rng.uniform(-0.4, 0.4, 2), rng.uniform(0.0, 0.3)]
        turn = rng.uniform(0, 2 * np.pi)
        rot = np.array(
            [[np.cos(turn), -np.sin(turn), 0], [np.sin(turn), np.cos(turn), 0], [0, 0, 1]]
        )
        kind = rng.integers(4)
        if kind == 0:
            meshes.append(
                box(c, rng.uniform(0.05, 0.6, 3), rotation=rot if rng.random() < 0.5 else None)
            )
        elif kind == 1:
            meshes.append(cylinder(c, rng.uniform(0.05, 0.4), rng.uniform(0.02, 0.3), segments=32))
        elif kind == 2:
            meshes.append(
                frustum(c, rng.uniform(0.05, 0.3), rng.uniform(0.1, 0.4), 0.0, segments=24)
            )
        else:
            meshes.append(ellipsoid(c, rng.uniform(0.05, 0.4, 3)))
    return [ref_convex_part(m) for m in meshes]


@pytest.mark.parametrize("width", [0.0299, 0.03, 0.0300001, 0.031])
def test_a_top_about_the_least_width_matches_the_reference(width):
    parts = [Part("top", box((0, 0, 0), (width, 0.2, 0.02))), Part("leg", box((0, 0, -0.2), 0.02))]
    lo, hi = Mesh.concat([p.mesh for p in parts]).bounds
    asset = Asset("stool", hi - lo, tuple(parts))
    assert_same_surfaces(S.support_surfaces(asset), ref_support_surfaces(asset))


def test_grid_clearance_matches_one_ray_at_a_time():
    """Points below, between and inside overlapping parts; a fifth of them off the faces."""
    rng = np.random.default_rng(5)
    for _ in range(150):
        parts = _random_parts(rng, rng.integers(1, 8))
        nx, ny = rng.integers(10, 130, 2)
        x = np.sort(rng.uniform(-0.6, 0.6, nx))
        y = np.sort(rng.uniform(-0.6, 0.6, ny))
        z = rng.uniform(-0.3, 0.4, (ny, nx))
        z[rng.random((ny, nx)) < 0.2] = np.nan
        got = S._grid_clearance(parts, x, y, z)
        gx, gy = np.meshgrid(x, y)
        on = ~np.isnan(z)
        want = S.clearance_above(parts, np.c_[gx[on], gy[on], z[on]])
        assert same_bits(got[on], want)
        assert np.all(np.isinf(got[~on]))


def test_trace_matches_the_reference_on_random_masks():
    rng = np.random.default_rng(2)
    for _ in range(300):
        ny, nx = rng.integers(1, 30, 2)
        mask = rng.random((ny, nx)) < rng.uniform(0.2, 0.9)  # holes, pinches
        xs = np.cumsum(rng.uniform(0.001, 0.02, nx + 1))
        ys = np.cumsum(rng.uniform(0.001, 0.02, ny + 1))
        if mask.any():
            got, want = S._trace(mask, xs, ys, 0.01), ref_trace(mask, xs, ys, 0.01)
            assert len(got) == len(want)
            assert all(same_bits(a, b) for a, b in zip(got, want))


def test_unique_rows_is_np_unique():
    rng = np.random.default_rng(0)
    for n in (1, 5, 12, 17, 40, 200):
        rows = rng.choice([-1.0, -0.5, -0.0, 0.0, 0.25, 1.0], size=(n, 4))
        assert same_bits(S._unique_rows(rows.copy()), np.unique(rows, axis=0))

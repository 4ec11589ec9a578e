"""Surface sampling and the point-cloud disk cache."""

from __future__ import annotations

import time

import numpy as np
import pytest
from numpy.random import default_rng

from pair2scene.assets.mesh import Asset, Mesh, Part, box, box_between
from pair2scene.assets.pointcloud import (
    BURIED_TOL_M,
    DEFAULT_POINTS,
    PointCloudCache,
    asset_point_cloud,
    cache_key,
    sample_asset,
    sample_surface,
)
from pair2scene.assets.registry import generate
from pair2scene.assets.surfaces import convex_part
from pair2scene.assets.typical_sizes import typical_size


def two_boxes() -> Mesh:
    # a 1 m cube (area 6) and a 0.1 m cube (area 0.06), far apart
    return Mesh.concat([box((0, 0, 0), (1, 1, 1)), box((3, 0, 0), (0.1, 0.1, 0.1))])


def table() -> Asset:
    top = box_between((-0.5, -0.3, 0.33), (0.5, 0.3, 0.37))
    legs = [
        box_between(
            (sx * 0.45 - 0.03, sy * 0.25 - 0.03, -0.37), (sx * 0.45 + 0.03, sy * 0.25 + 0.03, 0.35)
        )  # legs run into the top
        for sx in (-1, 1)
        for sy in (-1, 1)
    ]
    parts = (Part("top", top),) + tuple(Part(f"leg{i}", m) for i, m in enumerate(legs))
    return Asset("coffee_table", np.array([1.0, 0.6, 0.74]), parts)


def test_sample_surface_deterministic_and_seeded():
    m = two_boxes()
    p1, n1 = sample_surface(m, 500, 7)
    p2, n2 = sample_surface(m, 500, np.random.default_rng(7))
    assert np.array_equal(p1, p2) and np.array_equal(n1, n2)
    p3, _ = sample_surface(m, 500, 8)
    assert not np.array_equal(p1, p3)
    assert p1.shape == (500, 3) and n1.shape == (500, 3)


def test_area_weighting():
    p, _ = sample_surface(two_boxes(), 20000, 0)
    small = np.count_nonzero(p[:, 0] > 2)
    assert small / len(p) == pytest.approx(0.06 / 6.06, abs=0.003)


def test_points_on_surface_normals_unit_outward():
    p, n = sample_surface(box((0, 0, 0), (1, 2, 3)), 2000, 1)
    assert np.allclose(np.linalg.norm(n, axis=1), 1)
    assert np.all(np.einsum("ij,ij->i", n, p) > 0)  # outward from the centre
    # every point lies on the face its normal belongs to
    half = np.array([0.5, 1.0, 1.5])
    assert np.allclose(np.abs(np.einsum("ij,ij->i", n, p)), np.abs(n) @ half)


def test_asset_points_skip_buried_faces():
    a = table()
    p, n = sample_asset(a, 4000, 0)
    assert p.shape == (4000, 3)
    top_inside = (
        (np.abs(p[:, 0]) < 0.5 - 1e-6)
        & (np.abs(p[:, 1]) < 0.3 - 1e-6)
        & (p[:, 2] > 0.33 + 1e-6)
        & (p[:, 2] < 0.37 - 1e-6)
    )
    assert not top_inside.any()  # the legs' ends inside the top slab are not sampled
    assert np.allclose(np.linalg.norm(n, axis=1), 1)


def ref_sample_surface(mesh: Mesh, n: int, rng: np.random.Generator):
    areas = mesh.face_areas
    cdf = np.cumsum(areas) / float(areas.sum())
    face = np.minimum(np.searchsorted(cdf, rng.random(n), side="right"), len(areas) - 1)
    uv = rng.random((n, 2))
    flip = uv.sum(1) > 1
    uv[flip] = 1 - uv[flip]
    t = mesh.triangles[face]
    return t[:, 0] + uv[:, :1] * (t[:, 1] - t[:, 0]) + uv[:, 1:] * (t[:, 2] - t[:, 0]), (
        mesh.face_normals[face]
    )


def ref_sample_asset(asset: Asset, n: int, rng: np.random.Generator):
    """The plain form of sample_asset: one part at a time, each from its own mesh."""
    parts = [c for c in (convex_part(p.mesh) for p in asset.parts) if c is not None]
    pts, nrm = np.zeros((0, 3)), np.zeros((0, 3))
    while len(pts) < n:
        p, q = ref_sample_surface(asset.mesh, 2 * (n - len(pts)), rng)
        buried = np.zeros(len(p), dtype=bool)
        for part in parts:
            lo, hi = part.bounds
            idx = np.flatnonzero(np.all((p > lo) & (p < hi), axis=1) & ~buried)
            if len(idx):
                depth = (p[idx] @ part.normals.T - part.offsets).max(1)
                buried[idx[depth < -BURIED_TOL_M]] = True
        pts, nrm = np.concatenate([pts, p[~buried]]), np.concatenate([nrm, q[~buried]])
    return pts[:n], nrm[:n]


@pytest.mark.parametrize("category,style", [("shelving_unit", 0), ("chair", 2), ("bowl", 1)])
def test_asset_points_match_the_plain_form(category, style):
    """The same points to the bit: sampling is arranged for speed, not changed."""
    size = np.array(typical_size(category).size)
    got = sample_asset(generate(category, size, rng=1, style=style), 3000, 7)
    want = ref_sample_asset(generate(category, size, rng=1, style=style), 3000, default_rng(7))
    for a, b in zip(got, want):
        assert a.shape == b.shape and a.tobytes() == b.tobytes()


def test_render_mesh_is_sampled_when_present():
    a = table()
    render = box((0, 0, 0), (1.0, 0.6, 0.74))
    b = Asset(
        a.category, a.size, a.parts, source="user", asset_id="t.obj", extra={"render_mesh": render}
    )
    p, _ = sample_asset(b, 500, 0)
    assert np.allclose(np.abs(p).max(0), [0.5, 0.3, 0.37])
    assert cache_key(a, 500, 0) != cache_key(b, 500, 0)


def test_cache_hit_identical_and_read_only(tmp_path):
    cache = PointCloudCache(tmp_path)
    a = table()
    p1, n1 = cache.get(a, 256, seed=3)
    assert p1.dtype == np.float32 and p1.shape == (256, 3)
    assert not p1.flags.writeable
    files = list(tmp_path.rglob("*.npy"))
    assert len(files) == 1
    # from disk (a fresh cache, no memory) and from memory
    p2, n2 = PointCloudCache(tmp_path).get(a, 256, seed=3)
    assert np.array_equal(p1, p2) and np.array_equal(n1, n2)
    assert cache.get(a, 256, seed=3)[0] is p1
    # a rebuilt asset object with the same geometry hits the same file
    assert np.array_equal(asset_point_cloud(table(), 256, 3, cache=cache)[0], p1)
    p4, _ = cache.get(a, 256, seed=4)
    assert not np.array_equal(p1, p4)


def test_key_follows_geometry_and_size():
    a = table()
    moved = Asset(
        a.category,
        a.size,
        (Part("top", a.parts[0].mesh.transformed(translation=(0, 0, 1e-6))),) + a.parts[1:],
    )
    assert cache_key(a, 64, 0) != cache_key(moved, 64, 0)
    assert cache_key(a, 64, 0) != cache_key(a, 65, 0)
    assert cache_key(a, 64, 0) == cache_key(table(), 64, 0)


@pytest.mark.parametrize("damage", ["garbage", "truncate", "wrong_shape"])
def test_corrupt_file_is_rebuilt(tmp_path, damage):
    a = table()
    p1, _ = PointCloudCache(tmp_path).get(a, 128, 0)
    (path,) = tmp_path.rglob("*.npy")
    if damage == "garbage":
        path.write_bytes(b"not a numpy file")
    elif damage == "truncate":
        path.write_bytes(path.read_bytes()[:200])
    else:
        np.save(path, np.zeros((3, 6), np.float32))
    p2, _ = PointCloudCache(tmp_path).get(a, 128, 0)
    assert np.array_equal(p1, p2)
    assert np.load(path).shape == (128, 6)


def test_disk_hit_is_fast(tmp_path):
    cache = PointCloudCache(tmp_path, memory_entries=0)
    a = table()
    cache.get(a, DEFAULT_POINTS)
    times = []
    for _ in range(20):
        t = time.perf_counter()
        cache.get(a, DEFAULT_POINTS)
        times.append(time.perf_counter() - t)
    assert np.median(times) < 0.010

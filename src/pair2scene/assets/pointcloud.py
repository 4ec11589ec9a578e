"""Surface point clouds of assets (the geometry the encoder sees), with a disk cache.

An asset's cloud is sampled from its *outer* surface: the convex parts of a
procedural asset overlap (a tier's end inside a side panel, legs running into a
table top), and points on a face buried inside another part are dropped. An
asset that carries a render mesh (``asset.extra["render_mesh"]``: user and
3D-FUTURE meshes) is sampled from that mesh as it is.

Cache files are ``<root>/<key[:2]>/<key>.npy``: one (n, 6) float32 array, points
then unit normals, in the asset's local frame. The key hashes everything the
cloud depends on, the mesh bytes included, so a changed generator never serves
stale points.
"""

from __future__ import annotations

import contextlib
import hashlib
import os
import weakref
from collections import OrderedDict
from collections.abc import Callable
from pathlib import Path
from typing import TypeVar

import numpy as np

from pair2scene.assets.mesh import Asset, Mesh
from pair2scene.assets.surfaces import ConvexPart, convex_parts
from pair2scene.io.atomic import atomic_open
from pair2scene.paths import cache_dir, process_wide

T = TypeVar("T")

DEFAULT_POINTS = 2048
"""Points per cloud for training and generation (Point-MAE groups of 32 fit 64 times)."""
PAPER_POINTS = 8192
"""Points per cloud in the paper's setting."""
CACHE_FORMAT = 1
"""Bump when the sampling changes: part of every key, so old files are never read."""
MEMORY_ENTRIES = 128
"""Clouds kept in memory: 128 x 2048 points x 24 bytes is 6 MB."""
BURIED_TOL_M = 1e-5
"""A point deeper than this inside another part is buried; points on a contact face
(a part resting on another) are kept."""
MAX_DRAWS = 64
"""Rounds of rejection sampling before giving up on exterior-only points (never reached
for real assets: each round draws twice the points still missing)."""


def sample_surface(
    mesh: Mesh, n: int, rng: np.random.Generator | int
) -> tuple[np.ndarray, np.ndarray]:
    """``n`` points uniform over the surface area of ``mesh`` and their face normals.

    Returns points (n, 3) and unit normals (n, 3), float64 (outward for outward meshes).
    Same seed (or generator state), same points.
    """
    rng = rng if isinstance(rng, np.random.Generator) else np.random.default_rng(rng)
    areas = mesh.face_areas
    total = float(areas.sum())
    if n < 0:
        raise ValueError(f"sample_surface: n must be >= 0, got {n}")
    if not total > 0:
        raise ValueError("sample_surface: the mesh has no surface area")
    cdf = np.cumsum(areas) / total
    face = np.minimum(np.searchsorted(cdf, rng.random(n), side="right"), len(areas) - 1)
    uv = rng.random((n, 2))
    flip = uv[:, 0] + uv[:, 1] > 1  # fold the unit square onto the triangle
    np.subtract(1, uv, out=uv, where=flip[:, None])
    t = mesh.triangles
    a = t[face, 0]
    pts = a + uv[:, :1] * (t[face, 1] - a) + uv[:, 1:] * (t[face, 2] - a)
    return pts, mesh.face_normals[face]


def sample_asset(
    asset: Asset, n: int, rng: np.random.Generator | int
) -> tuple[np.ndarray, np.ndarray]:
    """``n`` points (n, 3) and unit normals (n, 3) on the asset's outer surface.

    Uses ``asset.extra["render_mesh"]`` when present; otherwise the parts, dropping
    points buried inside another part.
    """
    rng = rng if isinstance(rng, np.random.Generator) else np.random.default_rng(rng)
    render = asset.extra.get("render_mesh")
    if isinstance(render, Mesh) or len(asset.parts) == 1:
        return sample_surface(render if isinstance(render, Mesh) else asset.mesh, n, rng)
    parts = convex_parts(asset)
    mesh = asset.mesh
    pts, nrm = np.zeros((0, 3)), np.zeros((0, 3))
    for _ in range(MAX_DRAWS):
        if len(pts) >= n:
            break
        p, q = sample_surface(mesh, 2 * (n - len(pts)), rng)
        keep = ~_buried(parts, p)
        pts, nrm = np.concatenate([pts, p[keep]]), np.concatenate([nrm, q[keep]])
    if len(pts) < n:  # pathological: nearly all area buried; fill up with plain samples
        p, q = sample_surface(mesh, n - len(pts), rng)
        pts, nrm = np.concatenate([pts, p]), np.concatenate([nrm, q])
    return pts[:n], nrm[:n]


def _buried(parts: list[ConvexPart], points: np.ndarray) -> np.ndarray:
    """(M,) whether each point (M, 3) lies strictly inside any of the convex parts."""
    out = np.zeros(len(points), dtype=bool)
    if not parts:
        return out
    lo, hi = np.array([p.bounds for p in parts]).transpose(1, 2, 0)[..., None]  # (3, K, 1)
    # (K, M): the points strictly inside each part's bounds
    near = np.ones((len(parts), len(points)), dtype=bool)
    for axis, c in enumerate(points.T):
        near &= c > lo[axis]
        near &= c < hi[axis]
    for part, inside in zip(parts, near):
        idx = np.flatnonzero(inside & ~out)
        if len(idx):
            depth = (points[idx] @ part.normals.T - part.offsets).max(1)
            out[idx[depth < -BURIED_TOL_M]] = True
    return out


# -- the cache ---------------------------------------------------------------------
_DIGESTS: weakref.WeakKeyDictionary[Asset, str] = weakref.WeakKeyDictionary()


def mesh_digest(asset: Asset) -> str:
    """Hex digest of the asset's geometry (every part, and the render mesh if any);
    computed once per asset object."""
    found = _DIGESTS.get(asset)
    if found is None:
        h = hashlib.blake2b(digest_size=16)
        meshes = [p.mesh for p in asset.parts]
        render = asset.extra.get("render_mesh")
        if isinstance(render, Mesh):
            meshes.append(render)
        for m in meshes:
            h.update(np.int64([len(m.vertices), len(m.faces)]).tobytes())
            h.update(np.ascontiguousarray(m.vertices, dtype="<f8").tobytes())
            h.update(np.ascontiguousarray(m.faces, dtype="<i8").tobytes())
        found = h.hexdigest()
        _DIGESTS[asset] = found
    return found


def cache_key(asset: Asset, n: int, seed: int) -> str:
    """Hex key of the cloud of ``n`` points drawn with ``seed`` from ``asset``."""
    size = np.round(np.asarray(asset.size, dtype=float) * 1e4).astype(np.int64)  # 0.1 mm
    meta = (
        CACHE_FORMAT,
        asset.source,
        asset.asset_id,
        asset.category,
        int(asset.style),
        tuple(size.tolist()),
        int(n),
        int(seed),
        mesh_digest(asset),
    )
    return hashlib.blake2b(repr(meta).encode(), digest_size=20).hexdigest()


class PointCloudCache:
    """Asset point clouds on disk, with a small in-memory LRU in front.

    root : folder of the cache files; default ``pair2scene.paths.cache_dir() /
    "pointclouds"``. memory_entries : clouds kept in memory (0: none).
    A cache file that cannot be read back as the expected array is deleted and rebuilt.
    """

    def __init__(self, root: Path | None = None, memory_entries: int = MEMORY_ENTRIES) -> None:
        self.root = Path(root) if root is not None else cache_dir() / "pointclouds"
        self.memory_entries = memory_entries
        self._memory: OrderedDict[str, tuple[np.ndarray, np.ndarray]] = OrderedDict()

    def path(self, key: str) -> Path:
        return self.root / key[:2] / f"{key}.npy"

    def get(
        self, asset: Asset, n: int = DEFAULT_POINTS, seed: int = 0
    ) -> tuple[np.ndarray, np.ndarray]:
        """Points (n, 3) and unit normals (n, 3), float32 and read-only, in the asset's
        local frame; sampled with ``seed`` on a miss."""
        key = cache_key(asset, n, seed)
        found = self._memory.get(key)
        if found is not None:
            self._memory.move_to_end(key)
            return found
        path = self.path(key)
        data = self._load(path, n)
        if data is None:
            pts, nrm = sample_asset(asset, n, np.random.default_rng(seed))
            data = np.concatenate([pts, nrm], axis=1).astype(np.float32)
            with atomic_open(path, "wb") as fh:
                np.save(fh, data, allow_pickle=False)
        data.setflags(write=False)
        out = (data[:, :3], data[:, 3:])
        if self.memory_entries > 0:
            self._memory[key] = out
            while len(self._memory) > self.memory_entries:
                self._memory.popitem(last=False)
        return out

    def clear_memory(self) -> None:
        self._memory.clear()

    @staticmethod
    def _load(path: Path, n: int) -> np.ndarray | None:
        """The cached (n, 6) float32 array, or None (missing; corrupt files are deleted)."""
        return load_cached(path, (n, 6))


def read_cache_file(path: Path, accept: Callable[[np.ndarray], T]) -> T | None:
    """``accept`` of the array a cache file holds, or None: missing, or unreadable, or
    refused (``accept`` raised ValueError): the file is then deleted, to be rebuilt."""
    try:
        return accept(np.load(path, allow_pickle=False))
    except FileNotFoundError:
        return None
    except (OSError, ValueError, EOFError):
        with contextlib.suppress(OSError):
            os.unlink(path)
        return None


def load_cached(path: Path, shape: tuple[int, ...]) -> np.ndarray | None:
    """The finite float32 array of ``shape`` a cache file holds, or None: missing, or
    not such an array (unreadable, another shape: the file is deleted, to be rebuilt)."""

    def accept(data: np.ndarray) -> np.ndarray:
        if (
            isinstance(data, np.ndarray)
            and data.dtype == np.float32
            and data.shape == tuple(shape)
            and np.isfinite(data).all()
        ):
            return data
        raise ValueError("not the cached array")

    return read_cache_file(path, accept)


def default_cache() -> PointCloudCache:
    """The process-wide cache under the current :func:`pair2scene.paths.cache_dir`."""
    return process_wide("pointclouds", PointCloudCache)


def asset_point_cloud(
    asset: Asset, n: int = DEFAULT_POINTS, seed: int = 0, cache: PointCloudCache | None = None
) -> tuple[np.ndarray, np.ndarray]:
    """Points (n, 3) and unit normals (n, 3) (float32, read-only) of ``asset`` through
    ``cache`` (default: :func:`default_cache`)."""
    return (cache or default_cache()).get(asset, n, seed)

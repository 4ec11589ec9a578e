"""Support surfaces of assets on disk, so that no process works out a known asset's twice.

Finding where things can rest on an asset (:func:`~pair2scene.assets.surfaces.support_surfaces`)
casts a grid of vertical rays through its parts, about 10 ms for a piece of furniture on
2 cores, and generation meets the same assets run after run (a finite asset library:
:attr:`~pair2scene.assembly.place.AssemblyConfig.asset_library`). The store keeps each
asset's surfaces, exactly as they were computed, under

    <root>/<code digest>/<key[:2]>/<key>.npy

``root`` is ``pair2scene.paths.cache_dir() / "surfaces"``. The code digest hashes the
source of the modules that compute surfaces (``surfaces.py`` and the polygon helpers of
``scene/geometry.py``) and :data:`STORE_FORMAT`, so a change to how surfaces are found
never reads what the old code stored. ``key`` hashes the asset's geometry
(:func:`~pair2scene.assets.pointcloud.mesh_digest`: every part's vertices and faces).

A file holds one flat float64 array (:func:`encode`): the surfaces' count, then per
surface its height, area, clearance (inf when open above), outline length and holes'
lengths, then the coordinates. The values are the computed ones to the bit, so a scene
comes out the same whether its surfaces were read or computed. A file that does not
decode is deleted and computed again; files are written to a temporary name and renamed,
so an interrupted run leaves none half-written.
"""

from __future__ import annotations

import contextlib
import hashlib
from functools import cache
from pathlib import Path

import numpy as np

from pair2scene.assets.pointcloud import read_cache_file
from pair2scene.io.atomic import atomic_open, remove_stale_temporaries
from pair2scene.paths import cache_dir, process_wide

STORE_FORMAT = 1
"""Bump when what a file holds changes: part of the folder's digest."""
MAX_VALUES = 1_000_000
"""A file longer than this is not one this store wrote (a few thousand values at most)."""


@cache
def code_digest() -> str:
    """Hex digest of :data:`STORE_FORMAT` and the source of the code that finds surfaces."""
    from pair2scene.assets import surfaces
    from pair2scene.scene import geometry

    h = hashlib.blake2b(digest_size=12)
    h.update(f"{STORE_FORMAT}".encode())
    for module in (surfaces, geometry):
        h.update(Path(module.__file__).read_bytes())
    return h.hexdigest()


def encode(found) -> np.ndarray:
    """Surfaces (a list of :class:`~pair2scene.assets.surfaces.SupportSurface`) as one
    flat float64 array."""
    head: list[float] = [float(len(found))]
    coords: list[np.ndarray] = []
    for s in found:
        head += [s.z, s.area, s.clearance, float(len(s.polygon)), float(len(s.holes))]
        head += [float(len(h)) for h in s.holes]
        coords += [s.polygon, *s.holes]
    flat = [np.asarray(c, np.float64).reshape(-1) for c in coords]
    return np.concatenate([np.array(head, np.float64), *flat])


def decode(data: np.ndarray):
    """:func:`encode`'s inverse; ValueError when ``data`` is not such an array (every value
    finite but the clearances, which may be inf)."""
    from pair2scene.assets.surfaces import SupportSurface

    if not (isinstance(data, np.ndarray) and data.dtype == np.float64 and data.ndim == 1):
        raise ValueError("not a flat float64 array")
    if len(data) > MAX_VALUES:
        raise ValueError("longer than this store writes")
    pos = 0

    def take(n: int) -> np.ndarray:
        nonlocal pos
        if n < 0 or pos + n > len(data):
            raise ValueError("truncated")
        pos += n
        return data[pos - n : pos]

    def finite(values: np.ndarray) -> np.ndarray:
        if not np.isfinite(values).all():
            raise ValueError("non-finite values")
        return values

    def count(v: float) -> int:
        if not np.isfinite(v) or v != int(v) or v < 0:
            raise ValueError("a count that is not a count")
        return int(v)

    n = count(take(1)[0])
    rows = []
    for _ in range(n):
        z, area, clearance, n_poly, n_holes = take(5)
        finite(np.array([z, area]))
        if np.isnan(clearance):
            raise ValueError("non-finite values")
        holes = [count(v) for v in take(count(n_holes))]
        rows.append((z, area, clearance, count(n_poly), holes))
    out = []
    for z, area, clearance, n_poly, holes in rows:
        polygon = finite(take(2 * n_poly)).reshape(-1, 2).copy()
        hole_arrays = tuple(finite(take(2 * k)).reshape(-1, 2).copy() for k in holes)
        out.append(SupportSurface(float(z), polygon, float(area), float(clearance), hole_arrays))
    if pos != len(data):
        raise ValueError("trailing values")
    return out


class SurfaceStore:
    """Surfaces by asset key, in the folder of the current code."""

    def __init__(self, root: Path | None = None) -> None:
        self.root = Path(root) if root is not None else cache_dir() / "surfaces"
        self.folder = self.root / code_digest()

    def path(self, key: str) -> Path:
        return self.folder / key[:2] / f"{key}.npy"

    def get(self, key: str):
        """The surfaces stored under ``key``, or None (missing; a file that does not
        decode is deleted)."""
        return read_cache_file(self.path(key), decode)

    def put(self, key: str, found) -> None:
        """Store an asset's surfaces, first removing what a killed process left of
        writing them; an unwritable cache folder only costs the next process the work."""
        path = self.path(key)
        remove_stale_temporaries(path.parent, path.name)
        with contextlib.suppress(OSError), atomic_open(path, "wb") as fh:
            np.save(fh, encode(found), allow_pickle=False)


def default_store() -> SurfaceStore:
    """The process-wide store under the current :func:`pair2scene.paths.cache_dir`."""
    return process_wide("surfaces", SurfaceStore)

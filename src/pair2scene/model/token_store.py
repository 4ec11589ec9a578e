"""Point-MAE tokens of assets on disk, so that no process encodes a known asset twice.

Generation draws its objects from a finite asset library (each observed size of a
category has one mesh: :attr:`~pair2scene.assembly.place.AssemblyConfig.asset_library`),
so the same assets come back scene after scene, and encoding an asset's cloud is most of
the layout model's time (about 5 ms a cloud, some 20 new clouds a fit bedroom). The
store keeps each asset's tokens and group centres, as the encoder computed them, under

    <root>/<encoder digest>/<key[:2]>/<key>.npy

``root`` is ``pair2scene.paths.cache_dir() / "tokens"``; the encoder digest hashes the
encoder's weights and the cloud's point count (another checkpoint never reads these
tokens); ``key`` is :func:`~pair2scene.assets.pointcloud.cache_key` of the asset, which
hashes its category, style, size and mesh bytes. A file holds one (G, D + 3) float32
array, the tokens then the centres, the very bits the encoder gave: a scene comes out
the same whether its tokens were read or computed. A file that cannot be read back as
that array is deleted and computed again; files are written to a temporary name and
renamed, so an interrupted run leaves none half-written (and the next write of that asset
removes the temporary file a killed one left).
"""

from __future__ import annotations

import contextlib
import hashlib
from collections.abc import Mapping
from pathlib import Path

import numpy as np

from pair2scene.assets.pointcloud import load_cached
from pair2scene.io.atomic import atomic_open, remove_stale_temporaries
from pair2scene.paths import cache_dir

STORE_FORMAT = 1
"""Bump when what a file holds changes: part of every folder's digest."""


def encoder_digest(state: Mapping[str, np.ndarray], n_points: int) -> str:
    """Hex digest of an encoder's weights (its state dict, keys sorted) and point count."""
    h = hashlib.blake2b(digest_size=12)
    h.update(f"{STORE_FORMAT}:{int(n_points)}".encode())
    for key in sorted(state):
        value = np.ascontiguousarray(state[key], dtype="<f4")
        h.update(key.encode())
        h.update(np.int64(value.shape).tobytes())
        h.update(value.tobytes())
    return h.hexdigest()


class TokenStore:
    """Tokens (G, D) and centres (G, 3) float32 by asset key, in one encoder's folder."""

    def __init__(self, digest: str, root: Path | None = None) -> None:
        self.folder = (Path(root) if root is not None else cache_dir() / "tokens") / digest

    def path(self, key: str) -> Path:
        return self.folder / key[:2] / f"{key}.npy"

    def get(self, key: str, shape: tuple[int, int]) -> tuple[np.ndarray, np.ndarray] | None:
        """(tokens, centres) stored under ``key`` for tokens of ``shape`` (G, D), or None
        (missing; an unreadable or mis-shaped file is deleted)."""
        g, d = shape
        data = load_cached(self.path(key), (g, d + 3))
        if data is None:
            return None
        return np.ascontiguousarray(data[:, :d]), np.ascontiguousarray(data[:, d:])

    def put(self, key: str, tokens: np.ndarray, centers: np.ndarray) -> None:
        """Store an asset's tokens (G, D) and centres (G, 3), first removing what a killed
        process left of writing them; an unwritable cache folder only costs the next
        process the encoding."""
        path = self.path(key)
        remove_stale_temporaries(path.parent, path.name)
        data = np.concatenate([tokens, centers], axis=1).astype(np.float32, copy=False)
        with contextlib.suppress(OSError), atomic_open(path, "wb") as fh:
            np.save(fh, data, allow_pickle=False)

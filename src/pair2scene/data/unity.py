"""Unity (AI2-THOR, ProcTHOR) to pair2scene coordinates, in one place.

Unity is y-up and left-handed; pair2scene is z-up and right-handed. Swapping
y and z (the matrix S below) is a reflection, so it turns the left-handed
frame into a right-handed one: world (X, Y, Z) = (x, z, y). The same swap maps
an asset's local axes (right x, up y, forward z) to ours (right x, front y,
up z), so a Unity rotation R becomes S @ R @ S, a proper rotation.

Unity composes Euler angles (degrees) as z first, then x, then y: R = Ry Rx Rz.
Both facts are checked against AI2-THOR's own oriented-box corner points in
the test suite.
"""

from __future__ import annotations

import json
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from pair2scene.errors import UserError
from pair2scene.scene.geometry import OrientedBox, euler_to_matrix

SWAP_YZ = np.array([[1.0, 0.0, 0.0], [0.0, 0.0, 1.0], [0.0, 1.0, 0.0]])
UNITY_EULER_ORDER = "zxy"

MIN_SIZE = 1e-3
"""m; flat parts (a poster, a light switch) still get a box with some thickness."""
AABB_SOLVE_MAX_COND = 50.0
"""Beyond this condition number of |R| (yaw near 45 deg) the AABB cannot be
unmixed into a local size; keep the AABB extents instead."""


def vec(p: dict) -> np.ndarray:
    """A Unity {"x", "y", "z"} dict (position or size) -> pair2scene (3,)."""
    return SWAP_YZ @ np.array([p["x"], p["y"], p["z"]], dtype=float)


def points(corners: list) -> np.ndarray:
    """Unity points (N, 3) as lists -> pair2scene (N, 3)."""
    return np.asarray(corners, dtype=float) @ SWAP_YZ.T


def rotation(euler_deg: dict) -> np.ndarray:
    """Unity Euler angles in degrees {"x", "y", "z"} -> pair2scene rotation (3, 3)."""
    angles = np.radians([euler_deg["x"], euler_deg["y"], euler_deg["z"]])
    return SWAP_YZ @ euler_to_matrix(angles, UNITY_EULER_ORDER) @ SWAP_YZ


def box(center: dict, size: dict, euler_deg: dict) -> OrientedBox:
    """A Unity box (world centre, unrotated local size, Euler angles) -> OrientedBox."""
    return OrientedBox(vec(center), np.maximum(vec(size), MIN_SIZE), rotation(euler_deg))


def size_from_aabb(aabb_size: np.ndarray, rot: np.ndarray) -> np.ndarray:
    """Local size (3,) of a box with rotation ``rot`` (3, 3) whose world AABB has
    extents ``aabb_size`` (3,): solves |R| @ size = aabb_size, exact for boxes."""
    a = np.abs(rot)
    if np.linalg.cond(a) > AABB_SOLVE_MAX_COND:
        return np.maximum(aabb_size, MIN_SIZE)
    return np.maximum(np.linalg.solve(a, aabb_size), MIN_SIZE)


def fit_box_to_corners(corners: np.ndarray, rot: np.ndarray) -> OrientedBox:
    """The tightest box with rotation ``rot`` (3, 3) around world points (N, 3)."""
    local = corners @ rot
    lo, hi = local.min(0), local.max(0)
    return OrientedBox(rot @ ((lo + hi) / 2), np.maximum(hi - lo, MIN_SIZE), rot)


@dataclass(frozen=True)
class AssetInfo:
    object_type: str
    size: np.ndarray
    """(3,) unrotated local size in pair2scene axes (right, front, up)."""


class AssetDatabase:
    """ProcTHOR's asset-database.json: unrotated size and type per assetId."""

    def __init__(self, assets: dict[str, AssetInfo]) -> None:
        self.assets = assets

    @classmethod
    def load(cls, path: str | Path) -> AssetDatabase:
        try:
            raw = json.loads(Path(path).read_text(encoding="utf-8"))
            assets = {
                a["assetId"]: AssetInfo(a["objectType"], vec(a["boundingBox"]))
                for group in raw.values()
                for a in group
            }
        except (OSError, ValueError, KeyError, TypeError, AttributeError) as e:
            raise UserError(f"{path}: not a readable asset database ({e})") from None
        return cls(assets)

    def get(self, asset_id: str | None) -> AssetInfo | None:
        return self.assets.get(asset_id) if asset_id else None

    def __len__(self) -> int:
        return len(self.assets)

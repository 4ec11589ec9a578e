"""A synthetic corpus for model tests: small rooms with a desk, a mug, a chair and a sofa."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from pair2scene.curation.dataset import write_pairs
from pair2scene.curation.tuples import scene_tuples
from pair2scene.scene.geometry import OrientedBox
from pair2scene.scene.model import FLOOR, Room, Scene, SceneObject


def make_scene(i: int, rng: np.random.Generator) -> Scene:
    """A room with a desk, a mug on it, a chair at it and a sofa; jittered by rng."""
    room = Room("bedroom", np.array([[0, 0], [5, 0], [5, 4], [0, 4]], float))
    yaw = float(rng.choice([0.0, np.pi / 2]))
    cx, cy = rng.uniform(1.5, 3.5), rng.uniform(1.5, 2.5)
    desk = OrientedBox.from_yaw([cx, cy, 0.375], [1.2, 0.6, 0.75], yaw)
    mug = OrientedBox.from_yaw(
        [cx + rng.normal(0, 0.1), cy + rng.normal(0, 0.05), 0.8], [0.1, 0.1, 0.1], yaw
    )
    chair = OrientedBox.from_yaw([cx, cy - 0.7, 0.45], [0.5, 0.5, 0.9])
    sofa = OrientedBox.from_yaw([1.0, 3.5, 0.4], [2.0, 0.9, 0.8] * rng.uniform(0.9, 1.1, 3))
    objects = [
        SceneObject("desk_0", "desk", desk, None, FLOOR),
        SceneObject("mug_0", "mug", mug, None, "desk_0"),
        SceneObject("chair_0", "chair", chair, None, FLOOR, functional_anchor="desk_0"),
        SceneObject("sofa_0", "sofa", sofa, None, FLOOR),
    ]
    split = "val" if i % 4 == 3 else "train"
    return Scene(f"s{i}", room, objects, source=["ai2thor", "procthor"][(i // 4) % 2], split=split)


def write_synthetic_pairs(root: Path, scenes: int = 24, seed: int = 0, shard_size: int = 40):
    """A 3D-Pairs folder of ``scenes`` synthetic rooms (every 4th one val) in ``root``."""
    rng = np.random.default_rng(seed)
    tuples = [t for i in range(scenes) for t in scene_tuples(make_scene(i, rng))]
    write_pairs(tuples, root, shard_size=shard_size)
    return root

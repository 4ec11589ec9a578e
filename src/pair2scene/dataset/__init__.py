"""Datasets of scenes at scale (``pair2scene dataset``): a deterministic plan of scenes in
shards (:mod:`~pair2scene.dataset.plan`), shards written whole with digests and an index
(:mod:`~pair2scene.dataset.shards`), and the executors that make them, local processes or
Ray actors (:mod:`~pair2scene.dataset.executors`).

>>> from pair2scene.dataset import DatasetConfig, run_dataset
>>> config = DatasetConfig(mix=(("bedroom", 0.5), ("kitchen", 0.5)), num=20, shard_size=10)
>>> summary = run_dataset("OUT", config, jobs=2)      # doctest: +SKIP
"""

from pair2scene.dataset.executors import RunSummary, run_dataset
from pair2scene.dataset.plan import DatasetConfig, PlannedScene, plan_scenes, plan_shards
from pair2scene.dataset.verify import verify_dataset

__all__ = [
    "DatasetConfig",
    "PlannedScene",
    "RunSummary",
    "plan_scenes",
    "plan_shards",
    "run_dataset",
    "verify_dataset",
]

"""Datasets of scenes at scale (``pair2scene dataset``): a deterministic plan of scenes in
shards (:mod:`~pair2scene.dataset.plan`), shards written whole with digests and an index
(:mod:`~pair2scene.dataset.shards`), and the executors that make them, local processes or
Ray actors (:mod:`~pair2scene.dataset.executors`).

>>> from pair2scene.dataset import DatasetConfig, run_dataset
>>> config = DatasetConfig(mix=(("bedroom", 0.5), ("kitchen", 0.5)), num=20, shard_size=10)
>>> summary = run_dataset("OUT", config, jobs=2)      # doctest: +SKIP
"""

from __future__ import annotations

import importlib
from typing import TYPE_CHECKING

from pair2scene.dataset.plan import DatasetConfig, PlannedScene, plan_scenes, plan_shards

if TYPE_CHECKING:
    from pair2scene.dataset.executors import RunSummary, run_dataset
    from pair2scene.dataset.verify import verify_dataset

_LAZY = {"RunSummary": "executors", "run_dataset": "executors", "verify_dataset": "verify"}
"""Names whose modules load on first use: every command's start imports the CLI, which
needs only the plan (the executors cost ~0.15 s to import)."""


def __getattr__(name: str):
    if name in _LAZY:
        return getattr(importlib.import_module(f"pair2scene.dataset.{_LAZY[name]}"), name)
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


__all__ = [
    "DatasetConfig",
    "PlannedScene",
    "RunSummary",
    "plan_scenes",
    "plan_shards",
    "run_dataset",
    "verify_dataset",
]

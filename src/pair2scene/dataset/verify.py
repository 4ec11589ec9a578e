"""``pair2scene dataset verify OUT``: recheck every shard of a dataset against its digests.

A shard is ``missing`` (no index: never made, or its run was killed) or ``corrupt`` (its
index does not list the planned scenes, a file is missing, or a file's sha256 differs
from the one its index recorded); the rest are whole.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path

from pair2scene.dataset.plan import plan_shards
from pair2scene.dataset.shards import INDEX, read_manifest, shard_name, shard_problem


@dataclass
class VerifyReport:
    """What :func:`verify_dataset` found."""

    shards: int
    """Shards in the plan."""
    scenes: int
    """Scenes in the plan."""
    problems: dict[str, str] = field(default_factory=dict)
    """Shard name -> what is wrong with it (missing, corrupt: ...)."""
    index: bool = False
    """Whether OUT/index.jsonl exists."""

    @property
    def clean(self) -> bool:
        return not self.problems

    def lines(self) -> list[str]:
        out = [f"{name}: {problem}" for name, problem in self.problems.items()]
        missing = sum(p == "missing" for p in self.problems.values())
        corrupt = len(self.problems) - missing
        out.append(
            f"{self.shards - len(self.problems)} of {self.shards} shards whole "
            f"({self.scenes} scenes planned); {missing} missing, {corrupt} corrupt"
            + ("" if self.index else f"; no {INDEX} yet")
        )
        return out


def verify_dataset(out: str | Path) -> VerifyReport:
    """Check every shard of the dataset in ``out`` (a one-line UserError if ``out`` is not
    a dataset)."""
    out = Path(out)
    config, _ = read_manifest(out)
    plan = plan_shards(config)
    report = VerifyReport(len(plan), config.num, index=(out / INDEX).is_file())
    for i, items in enumerate(plan):
        problem = shard_problem(out, config, i, items)
        if problem is not None:
            report.problems[shard_name(i)] = problem
    return report

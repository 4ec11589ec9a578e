"""Throughput of ``pair2scene dataset``: scenes per minute with 1 and 2 workers.

Run from the repository root, on an idle machine::

    python benchmarks/dataset_throughput.py [--scenes 60] [--shard-size 10] [--no-write]

Each run makes a fresh dataset of ``--scenes`` fit rooms (bedroom, kitchen, living room
in equal shares; json, glb and png per scene) with the local executor at ``--jobs`` 1 and
2, and with Ray at 1 and 2 actors when Ray is installed. The time is the whole run's
wall time, worker start and model loading included (the 1-worker local run makes the
shards in this process, its model loaded before the clock starts). The ratio is the
2-worker rate over the 1-worker rate of the same executor.

Writes the figures into ``docs/benchmarks.md`` under ``## Dataset throughput``.
"""

from __future__ import annotations

import argparse
import datetime as dt
import shutil
import sys
import tempfile
import time
from pathlib import Path

from _docs import machine, replace_section

ROOT = Path(__file__).resolve().parents[1]
DOC = ROOT / "docs" / "benchmarks.md"
SECTION = "## Dataset throughput"
MIX = (("bedroom", 1 / 3), ("kitchen", 1 / 3), ("living_room", 1 / 3))
"""The room types of the benchmark dataset, equal shares."""
WORKERS = (1, 2)
"""Worker counts compared."""


def rate(tmp: Path, executor: str, jobs: int, scenes: int, shard_size: int) -> float:
    """Scenes per minute of one fresh dataset run."""
    from pair2scene.dataset import DatasetConfig, run_dataset

    config = DatasetConfig(mix=MIX, num=scenes, shard_size=shard_size)
    out = tmp / f"{executor}-{jobs}"
    t0 = time.perf_counter()
    summary = run_dataset(out, config, executor=executor, jobs=jobs, progress=False)
    seconds = time.perf_counter() - t0
    shutil.rmtree(out)
    assert summary.scenes == scenes
    return 60.0 * scenes / seconds


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--scenes", type=int, default=60)
    ap.add_argument("--shard-size", type=int, default=10)
    ap.add_argument("--no-write", action="store_true", help="Print only; leave the docs.")
    args = ap.parse_args()
    from pair2scene.dataset.executors import _generator

    _generator()  # (the 1-worker local run uses this process's model)
    executors = ["local"]
    try:
        import ray

        executors.append("ray")
    except ImportError:
        ray = None
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        for executor in executors:
            if executor == "ray":
                ray.init(address="local", num_cpus=max(WORKERS), include_dashboard=False,
                         log_to_driver=False)  # fmt: skip
            try:
                rates = {j: rate(Path(tmp), executor, j, args.scenes, args.shard_size)
                         for j in WORKERS}  # fmt: skip
            finally:
                if executor == "ray":
                    ray.shutdown()
            rows.append((executor, rates))
            print(executor, {j: round(r, 1) for j, r in rates.items()}, file=sys.stderr)
    lines = [
        SECTION,
        "",
        f"`python benchmarks/dataset_throughput.py --scenes {args.scenes} --shard-size "
        f"{args.shard_size}`, {dt.date.today().isoformat()}; {machine()}.",
        "",
        "Fit rooms (bedroom, kitchen, living room in equal shares), json + glb + png per "
        "scene; wall time of the whole run, worker start and model loading included.",
        "",
        "| executor | 1 worker (scenes/min) | 2 workers (scenes/min) | ratio |",
        "|---|---|---|---|",
    ]
    for executor, rates in rows:
        lines.append(
            f"| {executor} | {rates[1]:.1f} | {rates[2]:.1f} | {rates[2] / rates[1]:.2f} |"
        )
    local = dict(rows)["local"]
    per_core = max(local[1], local[2] / 2)  # scenes a minute one core makes
    lines += [
        "",
        f"Projected for 1,000,000 fit rooms at this rate: {1e6 / per_core / 60:,.0f} "
        f"core-hours ({per_core:.1f} scenes a minute a core, the better of the local "
        f"runs): {1e6 / per_core / 60 / 32:,.1f} hours on one 32-core node, "
        f"{1e6 / per_core / 60 / 512:,.1f} on 16 of them.",
    ]
    text = "\n".join(lines) + "\n"
    print(text)
    if not args.no_write:
        replace_section(DOC, SECTION, text)
        print(f"wrote {DOC.relative_to(ROOT)} ({SECTION})", file=sys.stderr)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())

"""Throughput of ``pair2scene dataset``: scenes per minute with 1 and 2 workers.

Run from the repository root, on an idle machine::

    python benchmarks/dataset_throughput.py [--scenes 120] [--shard-size 5] [--repeats 3]
                                            [--no-write]

Each run makes a fresh dataset of ``--scenes`` fit rooms (bedroom, kitchen, living room
in equal shares; json, glb and png per scene) with the local executor at ``--jobs`` 1 and
2, and with Ray at 1 and 2 actors when Ray is installed; the four runs are repeated
``--repeats`` times, interleaved, and each figure is the median. Two rates per run:

- whole run: scenes over the run's wall time, worker start and model loading included
  (the 1-worker local run makes the shards in this process, whose model is loaded before
  the clock starts);
- steady: scenes after the first over the time after the first scene, the rate a long
  run (a million rooms) settles at once its workers are up.

The ratio is the 2-worker rate over the 1-worker rate of the same executor.

Writes the figures into ``docs/benchmarks.md`` under ``## Dataset throughput``.
"""

from __future__ import annotations

import argparse
import datetime as dt
import shutil
import statistics
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


def rate(tmp: Path, executor: str, jobs: int, scenes: int, shard_size: int) -> tuple[float, float]:
    """(whole-run, steady) scenes per minute of one fresh dataset run."""
    from pair2scene.dataset import DatasetConfig, run_dataset

    config = DatasetConfig(mix=MIX, num=scenes, shard_size=shard_size)
    out = tmp / f"{executor}-{jobs}"
    t0 = time.perf_counter()
    summary = run_dataset(out, config, executor=executor, jobs=jobs, progress=False)
    seconds = time.perf_counter() - t0
    shutil.rmtree(out)
    assert summary.scenes == scenes
    steady = 60.0 * (scenes - 1) / (summary.seconds - summary.first_scene_seconds)
    return 60.0 * scenes / seconds, steady


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--scenes", type=int, default=120)
    ap.add_argument("--shard-size", type=int, default=5)
    ap.add_argument("--repeats", type=int, default=3)
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
    runs: dict[tuple[str, int], list[tuple[float, float]]] = {}
    with tempfile.TemporaryDirectory() as tmp:
        for rep in range(args.repeats):
            for executor in executors:
                if executor == "ray":
                    ray.init(address="local", num_cpus=max(WORKERS), include_dashboard=False,
                             log_to_driver=False)  # fmt: skip
                try:
                    for j in WORKERS:
                        r = rate(Path(tmp), executor, j, args.scenes, args.shard_size)
                        runs.setdefault((executor, j), []).append(r)
                        print(f"run {rep + 1}: {executor} x{j}: whole {r[0]:.1f}, steady "
                              f"{r[1]:.1f} scenes/min", file=sys.stderr)  # fmt: skip
                finally:
                    if executor == "ray":
                        ray.shutdown()

    def med(executor: str, jobs: int, k: int) -> float:
        return statistics.median(r[k] for r in runs[executor, jobs])

    lines = [
        SECTION,
        "",
        f"`python benchmarks/dataset_throughput.py --scenes {args.scenes} --shard-size "
        f"{args.shard_size} --repeats {args.repeats}`, {dt.date.today().isoformat()}; "
        f"{machine()}.",
        "",
        f"Fit rooms (bedroom, kitchen, living room in equal shares), json + glb + png per "
        f"scene, {args.scenes} scenes a run; medians of {args.repeats} runs, interleaved. "
        "*Whole run*: the run's wall time, worker start and model loading included (the "
        "1-worker local run makes its shards in the benchmark's process, whose model is "
        "loaded before the clock starts). *Steady*: scenes after the first over the time "
        "after the first scene, the rate a long run settles at.",
        "",
        "| executor | rate | 1 worker (scenes/min) | 2 workers (scenes/min) | ratio |",
        "|---|---|---|---|---|",
    ]
    for executor in executors:
        for k, label in ((1, "steady"), (0, "whole run")):
            one, two = med(executor, 1, k), med(executor, 2, k)
            lines.append(f"| {executor} | {label} | {one:.1f} | {two:.1f} | {two / one:.2f} |")
    per_core = max(med("local", 1, 1), med("local", 2, 1) / 2)  # scenes a minute a core
    lines += [
        "",
        "The whole-run figures of the 2-worker runs pay their workers' start once (spawn, "
        "torch import and model load, in parallel) and a last shard made by one worker "
        "while the other has none left; over a long run both shrink to nothing, which is "
        "the steady rate.",
        "",
        f"Projected for 1,000,000 fit rooms at the steady rate: {1e6 / per_core / 60:,.0f} "
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

"""Curation benchmark: the full curation of AI2-THOR + ProcTHOR train, and loading 3D-Pairs.

Run from the repository root::

    python benchmarks/curation.py [--procthor PATH] [--workers N] [--runs 5] [--no-write]

Prints its figures and writes them, with the machine they were taken on, into
``docs/benchmarks.md`` under ``## Curation`` (that section only; the rest of the
file is kept).

- full curation: ``pair2scene.curation.pipeline.curate`` on ``ai2thor`` and
  ``procthor:PATH`` (default ``../shared/data/procthor-1k/train.jsonl.gz``), physics
  on, offline functional proposer, into a fresh temporary folder: one run (it takes
  minutes), wall time end to end including loading the sources, with the per-stage
  times summed over scenes (across worker processes) from the report. The load average
  before the run is printed too: the figure is only as good as the machine was idle.
- loading: 50,000 synthetic tuples written with ``write_pairs`` (4,096 per shard),
  then ``load_pairs`` (sha256 checks on) timed ``--runs`` times after one warm-up
  call; the median is kept.
"""

from __future__ import annotations

import argparse
import datetime as dt
import os
import shlex
import statistics
import sys
import tempfile
import time
from pathlib import Path

import numpy as np
from _docs import machine

ROOT = Path(__file__).resolve().parents[1]
DOC = ROOT / "docs" / "benchmarks.md"
SECTION = "## Curation"
PROCTHOR_TRAIN = ROOT.parent / "shared" / "data" / "procthor-1k" / "train.jsonl.gz"
LOAD_TUPLES = 50_000
OBJECTS_PER_ROOM = 25
"""Synthetic rooms hold about as many objects as ProcTHOR's (~23)."""


def load_average() -> str:
    try:
        return f"{os.getloadavg()[0]:.2f}"
    except OSError:
        return "n/a"


def bench_full(procthor: Path, workers: int | None) -> dict:
    from pair2scene.curation.pipeline import CurateConfig, curate

    with tempfile.TemporaryDirectory() as tmp:
        config = CurateConfig(
            sources=("ai2thor", f"procthor:{procthor}"),
            out=Path(tmp) / "pairs",
            workers=workers,
            fresh=True,
        )
        load = load_average()
        t0 = time.perf_counter()
        report = curate(config, progress=True)
        seconds = time.perf_counter() - t0
    doc = report.to_dict()
    return {"seconds": seconds, "load": load, "doc": doc}


def synthetic_tuples(n: int, seed: int = 0) -> list:
    """``n`` tuples from synthetic rooms (a table with things on it, furniture around)."""
    from pair2scene.curation.tuples import scene_tuples
    from pair2scene.scene.geometry import OrientedBox
    from pair2scene.scene.model import FLOOR, AssetRef, Room, Scene, SceneObject

    rng = np.random.default_rng(seed)
    furniture = ["sofa", "armchair", "dresser", "bed", "side_table", "tv_stand", "desk"]
    small = ["book", "mug", "vase", "laptop", "bowl", "plate", "remote_control", "candle"]
    out: list = []
    i = 0
    while len(out) < n:
        room = Room("living_room", np.array([[0, 0], [6, 0], [6, 5], [0, 5]], float))
        table = OrientedBox.from_yaw([3, 2.5, 0.375], [1.4, 0.9, 0.75], rng.uniform(-3, 3))
        objects = [SceneObject("dining_table_0", "dining_table", table,
                               AssetRef("ai2thor", "Dining_Table_7_1"), FLOOR)]  # fmt: skip
        for k in range(OBJECTS_PER_ROOM - 1):
            if k % 3 == 0:
                cat = furniture[int(rng.integers(len(furniture)))]
                center = [rng.uniform(0.5, 5.5), rng.uniform(0.5, 4.5), 0.4]
                box = OrientedBox.from_yaw(center, [0.9, 0.8, 0.8], rng.uniform(-3, 3))
                sup, fa = FLOOR, ("dining_table_0" if k % 2 else None)
            else:
                cat = small[int(rng.integers(len(small)))]
                center = [3 + rng.uniform(-0.5, 0.5), 2.5 + rng.uniform(-0.3, 0.3), 0.8]
                box = OrientedBox.from_yaw(center, [0.15, 0.15, 0.1], rng.uniform(-3, 3))
                sup, fa = "dining_table_0", None
            asset = AssetRef("ai2thor", f"{cat.title()}_{int(rng.integers(40))}_1")
            objects.append(SceneObject(f"{cat}_{k}", cat, box, asset, sup, fa))
        scene = Scene(f"synthetic/train/{i}/room|{i % 7}", room, objects, "procthor", "train")
        out.extend(scene_tuples(scene))
        i += 1
    return out[:n]


def bench_load(runs: int) -> dict:
    from pair2scene.curation.dataset import load_pairs, write_pairs

    tuples = synthetic_tuples(LOAD_TUPLES)
    with tempfile.TemporaryDirectory() as tmp:
        manifest = write_pairs(tuples, tmp)
        size = sum(f.stat().st_size for f in Path(tmp).rglob("*") if f.is_file())
        t0 = time.perf_counter()
        first = len(load_pairs(tmp))
        first_s = time.perf_counter() - t0
        assert first == LOAD_TUPLES
        times = []
        for _ in range(runs):
            t0 = time.perf_counter()
            load_pairs(tmp)
            times.append(time.perf_counter() - t0)
    return {
        "median_s": statistics.median(times),
        "first_s": first_s,
        "shards": len(manifest["shards"]),
        "mb": size / 1e6,
        "runs": runs,
    }


def _source_line(name: str, s: dict) -> str:
    sec = s["seconds"]
    stages = ", ".join(
        f"{stage} {sec.get(f'{stage}_s', 0.0):.0f} s"
        for stage in ("support", "physics", "functional")
    )
    return (
        f"{name}: {s['rooms']} rooms, {s['objects']} objects, load {sec['load_s']:.1f} s, "
        f"curation {sec['wall_s']:.0f} s wall (stage times summed over scenes: {stages})"
    )


def section(full: dict | None, load: dict, command: str) -> str:
    lines = [
        SECTION,
        "",
        f"Measured {dt.date.today().isoformat()} with `{command}` on {machine()}.",
        "",
        "| figure | value |",
        "|---|---|",
    ]
    if full is not None:
        doc = full["doc"]
        srcs = doc["sources"]
        per = "; ".join(_source_line(name, s) for name, s in srcs.items())
        ev = doc["support_eval"].get("ai2thor")
        f1 = (
            "-" if ev is None else f"{ev['f1']:.3f} (P {ev['precision']:.3f}, R {ev['recall']:.3f})"
        )
        drops = ", ".join(f"{n} {100 * s['drop_rate']:.1f}%" for n, s in srcs.items())
        lines += [
            f"| full curation, AI2-THOR + ProcTHOR train, physics on | {full['seconds']:.0f} s "
            f"end to end, one run, {doc['counts']['tuples']} tuples "
            f"(load average {full['load']} before the run) |",
            f"| per source | {per} |",
            f"| support F1 on AI2-THOR | {f1} |",
            f"| physics drop rate | {drops} |",
        ]
    lines += [
        f"| loading 50k tuples (`load_pairs`) | {1000 * load['median_s']:.0f} ms median of "
        f"{load['runs']} (first call {1000 * load['first_s']:.0f} ms); {load['shards']} shards, "
        f"{load['mb']:.1f} MB, sha256 checked |",
        "",
    ]
    return "\n".join(lines)


def write_section(doc: Path, text: str) -> None:
    """Replace this script's section of ``doc`` with ``text`` (benchmarks/_docs.py)."""
    from _docs import replace_section

    replace_section(doc, SECTION, text)


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--procthor", type=Path, default=PROCTHOR_TRAIN, help="ProcTHOR file.")
    parser.add_argument("--workers", type=int, default=None, help="Worker processes.")
    parser.add_argument("--runs", type=int, default=5, help="Timed load runs (>= 5).")
    parser.add_argument("--load-only", action="store_true", help="Skip the full curation.")
    parser.add_argument("--no-write", action="store_true", help=f"Do not touch {DOC.name}.")
    parser.add_argument("--doc", type=Path, default=DOC, help="Markdown file to update.")
    args = parser.parse_args(argv)
    sys.path.insert(0, str(ROOT / "src"))
    script = Path(sys.argv[0]).resolve()
    shown = script.relative_to(ROOT) if script.is_relative_to(ROOT) else script
    command = "python " + shlex.join([str(shown), *sys.argv[1:]])

    full = None if args.load_only else bench_full(args.procthor, args.workers)
    load = bench_load(max(args.runs, 5))
    text = section(full, load, command)
    print(text)
    if not args.no_write:
        write_section(args.doc, text)
        print(f"wrote the {SECTION!r} section of {args.doc}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())

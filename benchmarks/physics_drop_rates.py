"""Physical validation benchmark: drop rate per source and time per scene.

Run from the repository root::

    python benchmarks/physics_drop_rates.py [--procthor PATH] [--limit N] [--top 12]

Runs :func:`pair2scene.curation.physics.validate_physics` with its default
configuration on every AI2-THOR room (all splits) and on the ProcTHOR train split
(default ``../shared/data/procthor-1k/train.jsonl.gz``), one process, one core,
and prints a markdown table (objects, dropped by the simulation, dropped as
dependents, drop rate, seconds per scene) and the most frequent reasons. Prints
only: the figures are folded into ``docs/benchmarks.md`` by hand.
"""

from __future__ import annotations

import argparse
import os
import platform
import sys
import time
from collections import Counter
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from pair2scene.curation.physics import PhysicsConfig, validate_physics
from pair2scene.data.sources import load_source

DEFAULT_PROCTHOR = Path(__file__).resolve().parents[2] / "shared/data/procthor-1k/train.jsonl.gz"
DEPENDENT_PREFIXES = ("rests on dropped", "part of dropped")
"""Reasons of objects dropped because of another object, not their own motion."""


@dataclass
class SourceFigures:
    name: str
    scenes: int = 0
    objects: int = 0
    direct: int = 0
    dependents: int = 0
    seconds: list[float] = field(default_factory=list)
    reasons: Counter = field(default_factory=Counter)
    """(category, reason kind) -> count, for objects dropped by their own motion."""
    notes: int = 0

    @property
    def dropped(self) -> int:
        return self.direct + self.dependents

    def row(self) -> str:
        s = np.array(self.seconds) if self.seconds else np.zeros(1)
        rate = self.dropped / max(self.objects, 1)
        return (
            f"| {self.name} | {self.scenes} | {self.objects} | {self.direct} | "
            f"{self.dependents} | {100 * rate:.1f}% | {np.median(s):.2f} | "
            f"{np.percentile(s, 95):.2f} | {s.max():.2f} | {s.sum():.0f} |"
        )


def measure(name: str, source: str, split: str | None, limit: int | None) -> SourceFigures:
    corpus = load_source(source, split=split)
    scenes = corpus.scenes[:limit] if limit else corpus.scenes
    fig = SourceFigures(name)
    config = PhysicsConfig()
    for scene in scenes:
        out = validate_physics(scene, config=config)
        cats = {o.id: o.category for o in scene.objects}
        fig.scenes += 1
        fig.objects += len(scene.objects)
        fig.seconds.append(out.seconds)
        fig.notes += bool(out.notes)
        for oid, reason in out.dropped.items():
            if reason.startswith(DEPENDENT_PREFIXES):
                fig.dependents += 1
            else:
                fig.direct += 1
                fig.reasons[(cats[oid], reason.split()[0].rstrip(":"))] += 1
        print(f"  {name}: {fig.scenes}/{len(scenes)}", end="\r", file=sys.stderr)
    print(file=sys.stderr)
    return fig


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--procthor", type=Path, default=DEFAULT_PROCTHOR)
    ap.add_argument("--limit", type=int, default=None, help="scenes per source (default all)")
    ap.add_argument("--top", type=int, default=12, help="reasons listed per source")
    args = ap.parse_args(argv)

    t0 = time.perf_counter()
    figures = [measure("AI2-THOR (all 195 rooms)", "ai2thor", None, args.limit)]
    if args.procthor.exists():
        figures.append(measure("ProcTHOR-1k train", f"procthor:{args.procthor}", None, args.limit))
    else:
        print(f"skipping ProcTHOR: {args.procthor} not found", file=sys.stderr)
    wall = time.perf_counter() - t0

    cfg = PhysicsConfig()
    print(
        f"Physical validation, {platform.python_version()}, {os.cpu_count()} CPUs, one core "
        f"used; thresholds {cfg.max_translation_m} m / {cfg.max_rotation_deg} deg, "
        f"depenetration {cfg.max_depenetration_m} m, settle {cfg.settle_seconds} s at "
        f"{cfg.timestep * 1000:.0f} ms steps."
    )
    print()
    print(
        "| source | scenes | objects | dropped (own motion) | dropped (dependents) | "
        "drop rate | s/scene median | p95 | max | total s |"
    )
    print("|---|---|---|---|---|---|---|---|---|---|")
    for f in figures:
        print(f.row())
    print()
    for f in figures:
        top = ", ".join(f"{c} {r} {n}" for (c, r), n in f.reasons.most_common(args.top))
        print(f"- {f.name}: most frequent (category, reason): {top}")
        if f.notes:
            print(f"  - {f.notes} scenes with notes (partial results)")
    print(f"\nwall time (loading included): {wall:.0f} s")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())

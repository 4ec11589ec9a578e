"""Scene-generation benchmark: the issue's targets for ``pair2scene generate``.

Run from the repository root::

    python benchmarks/generate.py [--scenes 20] [--threads N] [--no-write]

Generates ``--scenes`` bedrooms in ``fit`` mode and as many ``beyond`` bedrooms
(``--max-objects 80``), seeds 0 .. scenes-1, with the bundled model in this process (the
model is loaded once, before timing: the per-scene time is what ``summary.json``
reports), and measures on every scene, independently of placement's own checks:

- mesh-level collision rate: share of objects whose meshes intersect another's by more
  than 5 mm (:func:`pair2scene.metrics.physical.intersecting`);
- floating: objects that, lowered by 1 cm, touch neither the floor nor their support;
- acceptance rate, resamples per object (candidates rejected before the accepted one),
  seconds per scene (median), peak memory of the process (RSS, model included).

Writes the figures, with the machine, into ``docs/benchmarks.md`` under
``## Scene generation`` (that section only).
"""

from __future__ import annotations

import argparse
import datetime as dt
import json
import resource
import statistics
import sys
import time
from pathlib import Path

import numpy as np
from _docs import machine, replace_section

ROOT = Path(__file__).resolve().parents[1]
DOC = ROOT / "docs" / "benchmarks.md"
SECTION = "## Scene generation"
TARGETS = {"fit_seconds": 1.0, "beyond_seconds": 6.0, "beyond_objects": 60, "peak_gb": 1.5,
           "acceptance": 0.85, "resamples": 0.2, "collision_rate": 0.01, "floating": 0}  # fmt: skip


def run(p2s, mode: str, scenes: int, max_objects: int | None) -> dict:
    from pair2scene.metrics.physical import physical_report

    rows = []
    for seed in range(scenes):
        t0 = time.perf_counter()
        g = p2s.generate(room="bedroom", seed=seed, mode=mode, max_objects=max_objects)
        wall = time.perf_counter() - t0
        phys = physical_report(g.scene, g.assets, simulate=False)
        rows.append({
            "seconds": wall,
            "objects": g.stats.objects_placed,
            "acceptance": g.stats.acceptance_rate,
            "resamples": g.stats.assembly.resamples_per_object,
            "collision_rate": phys["collision_rate"],
            "floating": len(phys["floating"]),
            "rejections": g.stats.assembly.rejections,
        })  # fmt: skip
        print(f"{mode} {seed}: {rows[-1]}", file=sys.stderr)
    rej: dict[str, int] = {}
    for r in rows:
        for k, v in r["rejections"].items():
            rej[k] = rej.get(k, 0) + v
    return {
        "scenes": scenes,
        "median_seconds": statistics.median(r["seconds"] for r in rows),
        "mean_seconds": float(np.mean([r["seconds"] for r in rows])),
        "objects": float(np.mean([r["objects"] for r in rows])),
        "min_objects": min(r["objects"] for r in rows),
        "acceptance": float(np.mean([r["acceptance"] for r in rows])),
        "resamples": float(np.mean([r["resamples"] for r in rows])),
        "median_resamples": statistics.median(r["resamples"] for r in rows),
        "collision_rate": float(np.mean([r["collision_rate"] for r in rows])),
        "floating": int(sum(r["floating"] for r in rows)),
        "rejections": rej,
    }


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--scenes", type=int, default=20)
    ap.add_argument("--threads", type=int, default=None)
    ap.add_argument("--no-write", action="store_true")
    args = ap.parse_args()

    from pair2scene import Pair2Scene
    from pair2scene.generate import set_threads

    set_threads(args.threads)
    p2s = Pair2Scene.from_pretrained()
    p2s.generate(room="bedroom", seed=10_000)  # warm-up: imports, first clouds
    fit = run(p2s, "fit", args.scenes, None)
    beyond = run(p2s, "beyond", args.scenes, 80)
    peak_gb = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024**2
    print(json.dumps({"fit": fit, "beyond": beyond, "peak_gb": peak_gb}, indent=1))
    if args.no_write:
        return 0

    def mark(ok: bool) -> str:
        return "met" if ok else "**not met**"

    t = TARGETS
    lines = [
        SECTION,
        "",
        f"`python benchmarks/generate.py --scenes {args.scenes}` on {machine()}, "
        f"{dt.date.today().isoformat()}; bedrooms, seeds 0-{args.scenes - 1}, bundled model.",
        "",
        "| what | fit | beyond (--max-objects 80) | target | |",
        "|---|---|---|---|---|",
        f"| seconds per scene, median (mean) | {fit['median_seconds']:.2f} "
        f"({fit['mean_seconds']:.2f}) | {beyond['median_seconds']:.2f} "
        f"({beyond['mean_seconds']:.2f}) | <= {t['fit_seconds']:.0f} s fit, "
        f"<= {t['beyond_seconds']:.0f} s beyond | "
        f"{mark(fit['median_seconds'] <= 1 and beyond['median_seconds'] <= 6)} |",
        f"| objects per scene (fewest) | {fit['objects']:.1f} ({fit['min_objects']}) | "
        f"{beyond['objects']:.1f} ({beyond['min_objects']}) | >= 60 beyond | "
        f"{mark(beyond['min_objects'] >= t['beyond_objects'])} |",
        f"| acceptance rate | {fit['acceptance']:.3f} | {beyond['acceptance']:.3f} | "
        f">= 0.85 fit | {mark(fit['acceptance'] >= t['acceptance'])} |",
        f"| resamples per object, mean (median scene) | {fit['resamples']:.2f} "
        f"({fit['median_resamples']:.2f}) | {beyond['resamples']:.2f} "
        f"({beyond['median_resamples']:.2f}) | <= 0.2 fit | "
        f"{mark(fit['resamples'] <= t['resamples'])} |",
        f"| mesh collision rate (objects intersecting another by > 5 mm) | "
        f"{fit['collision_rate']:.4f} | {beyond['collision_rate']:.4f} | <= 0.01 | "
        f"{mark(max(fit['collision_rate'], beyond['collision_rate']) <= 0.01)} |",
        f"| floating objects (not touching their support within 1 cm), all scenes | "
        f"{fit['floating']} | {beyond['floating']} | 0 | "
        f"{mark(fit['floating'] + beyond['floating'] == 0)} |",
        f"| peak memory of the process (RSS, both runs, model included) | "
        f"{peak_gb:.2f} GB | | <= 1.5 GB | {mark(peak_gb <= t['peak_gb'])} |",
        "",
        f"Rejected candidates by reason, fit: {fit['rejections']}; beyond: "
        f"{beyond['rejections']} (dropped objects' 256 candidates included).",
    ]
    replace_section(DOC, SECTION, "\n".join(lines))
    print(f"wrote {DOC.relative_to(ROOT)} ({SECTION})", file=sys.stderr)
    return 0


if __name__ == "__main__":
    np.seterr(all="ignore")
    sys.exit(main())

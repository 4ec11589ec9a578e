"""Asset benchmark: procedural generation, cached point clouds, rendering.

Run from the repository root::

    python benchmarks/assets.py [--seeds 3] [--runs 5] [--no-write]

Prints its figures and writes them, with the machine they were taken on, into
``docs/benchmarks.md`` under ``## Assets`` (that section only; the rest of the
file is kept).

- generation: every registered category at its typical size, for a few seeds;
  each (category, seed) is generated once to warm up, then timed ``--runs``
  times and its median kept. Reports the median over all of them and the
  slowest categories (median over their seeds).
- point clouds: ``PointCloudCache(root).get(asset, n=2048, seed=0)`` on a
  filled cache (the first call per asset fills it and is reported apart);
  "not available" while that module is not written yet.
- rendering: the whole asset contact sheet, and single 512 x 512 frames of 50
  meshes in both views.
"""

from __future__ import annotations

import argparse
import datetime as dt
import shlex
import statistics
import sys
import tempfile
import time
from dataclasses import dataclass
from functools import partial
from pathlib import Path

import numpy as np
from _docs import machine, median_seconds

ROOT = Path(__file__).resolve().parents[1]
DOC = ROOT / "docs" / "benchmarks.md"
SECTION = "## Assets"
SLOWEST = 5
"""How many of the slowest categories to name."""
POINTS = 2048
"""Point-cloud size the model encoder takes."""
POINTCLOUD_ASSETS = 8
"""Assets whose cached point cloud is looked up (lookups do not depend on the category)."""
FRAME_MESHES = 50
FRAME_PX = 512


@dataclass
class GenerationFigures:
    categories: int
    seeds: int
    runs: int
    median_ms: float
    slowest: list[tuple[str, float]]
    """(category, median ms over its seeds), slowest first."""


def bench_generation(seeds: int, runs: int) -> GenerationFigures:
    from pair2scene.assets.registry import generate, generators
    from pair2scene.assets.typical_sizes import asset_categories, typical_size

    names = [c for c in asset_categories() if c in generators()]
    per_case, per_category = [], {}
    for name in names:
        size = typical_size(name).size
        medians = [median_seconds(partial(generate, name, size, rng=s), runs) for s in range(seeds)]
        per_case += medians
        per_category[name] = statistics.median(medians) * 1e3
    slowest = sorted(per_category.items(), key=lambda kv: -kv[1])[:SLOWEST]
    median_ms = statistics.median(per_case) * 1e3 if per_case else float("nan")
    return GenerationFigures(len(names), seeds, runs, median_ms, slowest)


def bench_pointclouds(runs: int) -> str:
    """One line: warm lookup and first-call times, or why there are none."""
    try:
        from pair2scene.assets.pointcloud import PointCloudCache
    except (ImportError, AttributeError):
        return "not available"
    from pair2scene.assets.registry import generate, generators
    from pair2scene.assets.typical_sizes import asset_categories, typical_size

    names = [c for c in asset_categories() if c in generators()][:POINTCLOUD_ASSETS]
    if not names:
        return "not available (no procedural categories yet)"
    assets = [generate(n, typical_size(n).size, rng=0) for n in names]
    with tempfile.TemporaryDirectory() as root:
        cache = PointCloudCache(root)
        first = []
        for a in assets:
            t0 = time.perf_counter()
            cache.get(a, n=POINTS, seed=0)
            first.append(time.perf_counter() - t0)
        # A disk hit as a new process sees it: no in-memory copy, a freshly generated
        # asset (so its mesh digest is recomputed), the file read back from disk.
        disk = PointCloudCache(root, memory_entries=0)
        fresh = [generate(n, typical_size(n).size, rng=0) for n in names]
        warm = [median_seconds(lambda a=a: disk.get(a, n=POINTS, seed=0), runs) for a in fresh]
    return (
        f"cached lookup from disk {statistics.median(warm) * 1e3:.3f} ms median "
        f"(first call, sampling and storing: {statistics.median(first) * 1e3:.1f} ms; "
        f"n={POINTS}, {len(assets)} assets, median of {runs} runs)"
    )


def bench_render(runs: int) -> tuple[str, str, str]:
    """(sheet line, frame line, renderer) ."""
    from pair2scene.assets.mesh import box, cylinder
    from pair2scene.assets.sheet import asset_sheet
    from pair2scene.render import render_meshes, renderer_info

    with tempfile.TemporaryDirectory() as tmp:
        res = asset_sheet(Path(tmp) / "sheet.png", seed=0)
    w, h = res.image_size
    sheet = (
        f"{res.seconds:.2f} s for {len(res.categories)} categories "
        f"({len(res.box_fallback)} box fallback), {w}x{h} px: generation "
        f"{res.timings.get('generate', 0):.2f} s, rendering (two views a category) "
        f"{res.timings.get('render', 0):.2f} s, the rest composing and PNG encoding"
    )
    rng = np.random.default_rng(0)
    meshes = [box(rng.uniform(-3, 3, 3), rng.uniform(0.2, 1.0, 3)) for _ in range(40)]
    meshes += [cylinder(rng.uniform(-3, 3, 3), 0.2, 0.6) for _ in range(FRAME_MESHES - 40)]
    colors = [tuple(int(c) for c in rng.integers(60, 230, 3)) for _ in meshes]
    times = {
        view: median_seconds(lambda v=view: render_meshes(meshes, colors, v, FRAME_PX), runs)
        for view in ("top", "three_quarter")
    }
    frame = (
        f"top {times['top'] * 1e3:.1f} ms, 3/4 {times['three_quarter'] * 1e3:.1f} ms "
        f"({FRAME_MESHES} meshes, {FRAME_PX}x{FRAME_PX}, outlined, median of {runs})"
    )
    return sheet, frame, renderer_info()


def section(gen: GenerationFigures, pointcloud: str, render: tuple[str, str, str],
            command: str) -> str:  # fmt: skip
    sheet, frame, renderer = render
    slow = ", ".join(f"{name} {ms:.2f} ms" for name, ms in gen.slowest) or "-"
    lines = [
        SECTION,
        "",
        f"Measured {dt.date.today().isoformat()} with `{command}` on {machine()}; "
        f"renderer: {renderer}.",
        "",
        "| figure | value |",
        "|---|---|",
        f"| procedural asset, median time | {gen.median_ms:.2f} ms "
        f"({gen.categories} categories x {gen.seeds} seeds, warm, median of {gen.runs} runs "
        "each) |",
        f"| slowest categories | {slow} |",
        f"| point cloud (`PointCloudCache.get`) | {pointcloud} |",
        f"| asset contact sheet | {sheet} |",
        f"| one rendered frame | {frame} |",
        "",
    ]
    return "\n".join(lines)


def write_section(doc: Path, text: str) -> None:
    """Replace this script's section of ``doc`` with ``text`` (benchmarks/_docs.py)."""
    sys.path.insert(0, str(ROOT / "src"))
    from _docs import replace_section

    replace_section(doc, SECTION, text)


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seeds", type=int, default=3, help="Seeds per category.")
    parser.add_argument("--runs", type=int, default=5, help="Timed runs per case (>= 5).")
    parser.add_argument("--no-write", action="store_true", help=f"Do not touch {DOC.name}.")
    parser.add_argument("--doc", type=Path, default=DOC, help="Markdown file to update.")
    args = parser.parse_args(argv)
    runs = max(args.runs, 5)
    script = Path(sys.argv[0]).resolve()
    shown = script.relative_to(ROOT) if script.is_relative_to(ROOT) else script
    command = "python " + shlex.join([str(shown), *sys.argv[1:]])

    gen = bench_generation(args.seeds, runs)
    pointcloud = bench_pointclouds(runs)
    render = bench_render(runs)
    text = section(gen, pointcloud, render, command)
    print(text)
    print(f"pointcloud: {pointcloud}")
    if not args.no_write:
        write_section(args.doc, text)
        print(f"wrote the {SECTION!r} section of {args.doc}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())

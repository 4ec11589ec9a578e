"""Generator benchmark: median generation time of every category, grouped by family module.

Run from the repository root::

    python benchmarks/generators.py [--seeds 3] [--runs 5] [--family tables]

Every registered category is built at its typical size for each style variant and
seed: once to warm up, then ``--runs`` times; the table shows, per category, the median
over all those runs (ms), the slowest style and the part count. Nothing is written;
``benchmarks/assets.py`` reports the overall median into docs/benchmarks.md.
"""

from __future__ import annotations

import argparse
import statistics
import sys
from functools import partial
from pathlib import Path

from _docs import median_seconds

ROOT = Path(__file__).resolve().parents[1]


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seeds", type=int, default=3)
    parser.add_argument("--runs", type=int, default=5)
    parser.add_argument("--family", help="only this generator module (e.g. tables, food)")
    args = parser.parse_args()
    sys.path.insert(0, str(ROOT / "src"))
    from pair2scene.assets.registry import generate, generators
    from pair2scene.assets.typical_sizes import typical_size

    rows = []
    for cat, gen in sorted(generators().items(), key=lambda kv: (kv[1].fn.__module__, kv[0])):
        family = gen.fn.__module__.rsplit(".", 1)[-1]
        if args.family and family != args.family:
            continue
        size = typical_size(cat).size
        per_style = [
            [1e3 * median_seconds(partial(generate, cat, size, rng=seed, style=style), args.runs)
             for seed in range(args.seeds)]
            for style in range(gen.variants)
        ]  # fmt: skip
        medians = [statistics.median(t) for t in per_style]
        parts = len(generate(cat, size, rng=0, style=0).parts)
        median = statistics.median([t for ts in per_style for t in ts])
        slowest = max(range(gen.variants), key=lambda s: medians[s])
        rows.append((family, cat, median, slowest, medians[slowest], parts))

    print(f"median of {args.runs} runs after a warm-up, {args.seeds} seeds, every style")
    header = ("family", "category", "median ms", "slowest style (ms)", "parts")
    print("{:12s} {:22s} {:>9s} {:>19s} {:>5s}".format(*header))
    for family, cat, median, slowest, slow_ms, parts in rows:
        print(f"{family:12s} {cat:22s} {median:9.2f} {slowest:>10d} ({slow_ms:6.2f}) {parts:5d}")
    if rows:
        print(f"{len(rows)} categories, median {statistics.median(r[2] for r in rows):.2f} ms")


if __name__ == "__main__":
    main()

"""By which half of its functional anchor each floor object stands, in generated rooms
and in the training statistics.

Run from the repository root::

    python benchmarks/anchor_halves.py FOLDER [FOLDER ...] [--stats STATS_JSON]

FOLDER: a ``pair2scene generate --num N --out FOLDER`` output. Per (dependent, anchor)
pair, over the floor objects whose anchor does not face them: how many stand by the
anchor's back half (their centre behind its middle, in its frame) of how many. With
``--stats`` (a curated ``stats.json``; default the bundled one), the same count of the
training rooms (``HierarchyStats.func_geometry``'s ``behind`` sum). Prints a markdown
table; docs/model.md ("By which half of its anchor") quotes it.
"""

from __future__ import annotations

import argparse
from collections import Counter
from pathlib import Path


def counts(folder: Path) -> Counter:
    """(dependent, anchor, "n" | "behind") -> count over the folder's scenes."""
    from pair2scene.io.scene_json import read_scene
    from pair2scene.scene.model import FLOOR
    from pair2scene.scene.relations import by_back_half, faces

    out: Counter = Counter()
    for path in sorted(folder.glob("*/scene.json")):
        scene = read_scene(path)
        by_id = scene.by_id()
        for o in scene.objects:
            anchor = by_id.get(o.functional_anchor) if o.functional_anchor else None
            if anchor is None or o.support != FLOOR or faces(anchor.box, o.box):
                continue
            key = (o.category, anchor.category)
            out[key + ("n",)] += 1
            out[key + ("behind",)] += int(by_back_half(o.box, anchor.box))
    return out


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("folders", type=Path, nargs="+")
    ap.add_argument("--stats", type=Path, default=None)
    args = ap.parse_args()
    from pair2scene.curation.stats import HierarchyStats
    from pair2scene.resources import table_path

    text = (args.stats or table_path("hierarchy_stats")).read_text()
    table = HierarchyStats.from_json(text).func_geometry
    found = [counts(f) for f in args.folders]
    pairs = sorted({k[:2] for c in found for k in c})
    names = " | ".join(f.name for f in args.folders)
    print(f"| pair | {names} | training rooms |")
    print("|---|" + "---|" * (len(args.folders) + 1))
    for dep, anchor in pairs:
        cells = [f"{c[(dep, anchor, 'behind')]} / {c[(dep, anchor, 'n')]}" for c in found]
        sums = table.get(dep, {}).get(anchor)
        train = "-"
        if sums is not None and len(sums) > 5:
            train = f"{sums[5]:.0f} / {sums[0] - sums[2]:.0f}"
        print(f"| {dep} -> {anchor} | {' | '.join(cells)} | {train} |")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())

"""Time to write a 20-object room in every format (issue 23: under a second on 2 cores).

Run from the repository root::

    python benchmarks/export_time.py [--scenes 5] [--no-write]

For ``--scenes`` bedrooms of 20 objects (seeds 0..n-1, ``mode="beyond", max_objects=20``), each
format of :data:`pair2scene.io.export.FORMATS` is written alone (median over the scenes)
and then all together with :func:`pair2scene.io.export.write_scene_folder` (the scene
folder, written atomically). USD is left out when usd-core is not installed.

Writes the figures into ``docs/benchmarks.md`` under ``## Export time`` (that section
only).
"""

from __future__ import annotations

import argparse
import datetime as dt
import importlib.util
import statistics
import sys
import tempfile
import time
from pathlib import Path

from _docs import machine, replace_section

ROOT = Path(__file__).resolve().parents[1]
DOC = ROOT / "docs" / "benchmarks.md"
SECTION = "## Export time"
OBJECTS = 20


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--scenes", type=int, default=5)
    ap.add_argument("--no-write", action="store_true")
    args = ap.parse_args()

    from pair2scene import Pair2Scene
    from pair2scene.generate import set_threads
    from pair2scene.io.export import FORMATS, write_scene_folder

    set_threads()
    p2s = Pair2Scene.from_pretrained()
    names = [f for f in FORMATS if f != "usd" or importlib.util.find_spec("pxr")]
    each: dict[str, list[float]] = {n: [] for n in names}
    whole, objects = [], []
    with tempfile.TemporaryDirectory() as d:
        tmp = Path(d)
        p2s.generate(room="bedroom", seed=10_000, mode="beyond", max_objects=OBJECTS)  # warm
        for seed in range(args.scenes + 1):
            r = p2s.generate(room="bedroom", seed=seed, mode="beyond", max_objects=OBJECTS)
            for n in names:
                form = FORMATS[n]
                t0 = time.perf_counter()
                form.write(tmp / f"{seed}_{n}" / form.entry, r.scene, r.assets, "small")
                if seed:  # the first round warms the writers' imports
                    each[n].append(time.perf_counter() - t0)
            t0 = time.perf_counter()
            write_scene_folder(tmp / f"all{seed}", r.scene, r.assets, names)
            if seed:
                whole.append(time.perf_counter() - t0)
                objects.append(len(r.scene.objects))
    lines = [
        SECTION,
        "",
        f"`python benchmarks/export_time.py --scenes {args.scenes}` on {machine()}, "
        f"{dt.date.today().isoformat()}: beyond bedrooms of {OBJECTS} objects "
        f"({min(objects)}{'' if min(objects) == max(objects) else f'-{max(objects)}'} placed), "
        "each format written alone, then all "
        "of them as one scene folder; median of the scenes, warm process.",
        "",
        "| format | what it writes | seconds per scene |",
        "|---|---|---|",
        *(f"| {n} | `{FORMATS[n].entry}{'/' if FORMATS[n].folder else ''}` | "
          f"{statistics.median(each[n]):.3f} |" for n in names),
        f"| **all ({', '.join(names)})** | the scene folder | "
        f"**{statistics.median(whole):.3f}** (target < 1 s) |",
    ]  # fmt: skip
    if "usd" not in names:
        lines += ["", "usd-core is not installed here: USD left out."]
    text = "\n".join(lines)
    print(text)
    if not args.no_write:
        replace_section(DOC, SECTION, text)
        print(f"wrote {DOC.relative_to(ROOT)} ({SECTION})", file=sys.stderr)
    return 0


if __name__ == "__main__":
    sys.exit(main())

"""Two source trees side by side on warm fit bedrooms: interleaved runs, medians.

Run from the repository root, on an idle machine::

    git worktree add /tmp/before <commit>
    python benchmarks/compare_warm.py /tmp/before/src src [--rounds 4] [--scenes 10]

Each round runs one fresh process per tree, in turn (A, B, A, B, ...): the process loads
the bundled model, makes one bedroom to warm up, then ``--scenes`` fit bedrooms (seeds
0..N-1), each generated and its folder written (scene.json, GLB, top view, viewer page).
Printed per tree: the medians over the rounds of each process's median seconds to
generate, to write the folder, and both. Interleaving puts both trees under the same
drift of a shared machine; compare the trees' figures, not either with a figure taken at
another time. Prints only; docs/benchmarks.md quotes it by hand.
"""

from __future__ import annotations

import argparse
import json
import statistics
import subprocess
import sys
from pathlib import Path

_RUN = r"""
import json, statistics, sys, tempfile, time
from pathlib import Path
sys.path.insert(0, SOURCE)
from pair2scene import Pair2Scene
from pair2scene.generate import set_threads
from pair2scene.io.export import write_scene_folder

set_threads()
p2s = Pair2Scene.from_pretrained()
p2s.generate(room="bedroom", seed=10_000)
out = Path(tempfile.mkdtemp())
made, written = [], []
for seed in range(SCENES):
    t0 = time.perf_counter()
    r = p2s.generate(room="bedroom", seed=seed)
    t1 = time.perf_counter()
    write_scene_folder(out / str(seed), r.scene, r.assets)
    made.append(t1 - t0)
    written.append(time.perf_counter() - t1)
both = [a + b for a, b in zip(made, written)]
print(json.dumps([statistics.median(x) for x in (made, written, both)]))
"""


def run(source: str, scenes: int) -> list[float]:
    """[generate, write, both] median seconds of one fresh process on ``source``."""
    code = _RUN.replace("SOURCE", repr(str(Path(source).resolve()))).replace("SCENES", str(scenes))
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True)
    if done.returncode:
        sys.exit(f"{source}: failed\n{done.stderr[-800:]}")
    return json.loads(done.stdout.strip().splitlines()[-1])


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("a", help="the first tree's package folder (holding pair2scene/)")
    ap.add_argument("b", help="the second tree's")
    ap.add_argument("--rounds", type=int, default=4)
    ap.add_argument("--scenes", type=int, default=10)
    a = ap.parse_args()
    if a.rounds < 1 or a.scenes < 1:
        sys.exit("--rounds and --scenes must be at least 1")
    for tree in (a.a, a.b):
        if not (Path(tree) / "pair2scene").is_dir():
            sys.exit(f"{tree}: no pair2scene package there")
    results: dict[str, list[list[float]]] = {a.a: [], a.b: []}
    for _ in range(a.rounds):
        for tree in (a.a, a.b):
            results[tree].append(run(tree, a.scenes))
    for tree, rows in results.items():
        gen, write, both = (statistics.median(col) for col in zip(*rows))
        print(f"{tree}: generate {gen:.3f} s, write {write:.3f} s, both {both:.3f} s")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())

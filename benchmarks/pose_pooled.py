"""Pose MMD over more rooms than docs/results.md's 30: how much a 30-room figure can tell.

Run from the repository root, with ``../shared`` beside it (the ProcTHOR val rooms are part
of the reference)::

    python benchmarks/pose_pooled.py --pairs PAIRS [--blocks 4] [--scenes 30]
        [--rooms bedroom living_room kitchen] [--work WORK] [--jobs 2] [--no-write]

For ours (fit) and the per-pair Gaussian (fitted on PAIRS' train split, as in
docs/results.md), each room type, the script generates ``blocks`` sets of ``scenes`` rooms
(seeds 0 .. blocks x scenes - 1, one ``pair2scene generate --seed S --num N`` a block, the
commands side by side) and reports the pose MMD against the AI2-THOR + ProcTHOR-1k val rooms
of each block and of all blocks pooled (:func:`pair2scene.metrics.distribution.pose_mmd`,
the measure of docs/results.md). A last row measures real rooms the same way: the AI2-THOR +
ProcTHOR-1k train rooms of the type (the ones the model and the Gaussian learnt from), in a
seeded order, cut in blocks of the same size: how far the val rooms lie from the train
rooms by this measure, whatever a method learns. A second table gives each wall category's
share of all objects (``evaluate``'s ``wall_share/<category>``, issue 19) in the val rooms,
the train rooms and ours (fit) pooled. WORK keeps the scenes; a second run only generates
what is missing. The tables go into docs/results.md's Discussion, replacing the ones this
script wrote before (between its markers).
"""

from __future__ import annotations

import argparse
import subprocess
import sys
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

from results import DOC, PROCTHOR_VAL, ROOMS, methods

from curation import PROCTHOR_TRAIN

BEGIN, END = "<!-- pose-pooled -->", "<!-- /pose-pooled -->"
COMPARED = ("ours (fit)", "gaussian")
"""The methods of docs/results.md measured here (:func:`results.methods`' names)."""
TRAIN_ROW = "real train rooms"
"""The row of the train rooms, cut in blocks like the generated ones."""
TRAIN_ORDER_SEED = 0
"""Seeds the order the train rooms are cut in (AI2-THOR's come first as loaded)."""


def block_folder(work: Path, method: str, room: str, seed: int) -> Path:
    return work / method / f"{room}_{seed}"


def generate(args: list[str], out: Path) -> None:
    """One block, unless its folder holds a summary already (a finished run)."""
    if (out / "summary.json").is_file():
        return
    cmd = [sys.executable, "-m", "pair2scene", "generate", *args, "--threads", "1",
           "--out", str(out)]  # fmt: skip
    subprocess.run(cmd, check=True, stdout=subprocess.DEVNULL)


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("--pairs", type=Path, required=True, help="pair2scene curate folder")
    p.add_argument("--blocks", type=int, default=4)
    p.add_argument("--scenes", type=int, default=30, help="rooms a block")
    p.add_argument("--rooms", nargs="+", default=list(ROOMS))
    p.add_argument("--work", type=Path, default=Path("/tmp/p2s-pose-pooled"))
    p.add_argument("--jobs", type=int, default=2)
    p.add_argument("--no-write", action="store_true", help="print the table only")
    a = p.parse_args()

    from pair2scene.evaluate import load_reference, load_scene_folder
    from pair2scene.io.atomic import atomic_write_text
    from pair2scene.metrics.distribution import pose_mmd

    described = methods(a.pairs, Path())  # (no model variant is run here)
    compared = {name: described[name][0] for name in COMPARED}
    jobs = []
    for name, extra in compared.items():
        for room in a.rooms:
            for b in range(a.blocks):
                seed = b * a.scenes
                args = ["--room", room, "--num", str(a.scenes), "--seed", str(seed), *extra]
                jobs.append((args, block_folder(a.work, name.split()[0], room, seed)))
    with ThreadPoolExecutor(a.jobs) as pool:
        list(pool.map(lambda job: generate(*job), jobs))

    lines = [
        f"| pose MMD, {a.blocks} x {a.scenes} rooms | "
        + " | ".join(f"{r}: blocks | pooled" for r in a.rooms)
        + " |",
        "|---|" + "---|---|" * len(a.rooms),
    ]
    references = {
        r: load_reference(["ai2thor:val", f"procthor:{PROCTHOR_VAL}"], [r]) for r in a.rooms
    }
    trains = {r: load_reference(["ai2thor:train", f"procthor:{PROCTHOR_TRAIN}"], [r])
              for r in a.rooms}  # fmt: skip
    pooled_sets: dict[str, dict[str, list]] = {}
    for name in (*compared, TRAIN_ROW):
        cells = []
        for room in a.rooms:
            if name == TRAIN_ROW:
                blocks = train_blocks(trains[room], a.blocks, a.scenes)
            else:
                blocks = [
                    load_scene_folder(block_folder(a.work, name.split()[0], room, b * a.scenes))
                    for b in range(a.blocks)
                ]
            each = [pose_mmd(references[room], scenes)["mean"] for scenes in blocks]
            pooled_sets.setdefault(name, {})[room] = [s for scenes in blocks for s in scenes]
            pooled = pose_mmd(references[room], pooled_sets[name][room])["mean"]
            cells += [" / ".join(f"{v:.3f}" for v in each), f"{pooled:.3f}"]
        lines.append(f"| {name} | " + " | ".join(cells) + " |")
    lines += ["", *wall_share_table(references, trains, pooled_sets[COMPARED[0]])]
    table = "\n".join(lines)
    print(table)
    if a.no_write:
        return
    text = DOC.read_text()
    if BEGIN in text and END in text:
        head, rest = text.split(BEGIN, 1)
        text = head + BEGIN + "\n" + table + "\n" + END + rest.split(END, 1)[1]
    else:
        print(f"docs/results.md has no {BEGIN} ... {END} markers: table not written")
        return
    atomic_write_text(DOC, text)


def train_blocks(rooms: list, blocks: int, scenes: int) -> list[list]:
    """``blocks`` blocks of ``scenes`` of the train ``rooms``, in a seeded order (fewer or
    shorter where the rooms run out)."""
    import numpy as np

    order = np.random.default_rng(TRAIN_ORDER_SEED).permutation(len(rooms))
    picked = [rooms[i] for i in order[: blocks * scenes]]
    return [picked[k : k + scenes] for k in range(0, len(picked), scenes)]


def wall_share_table(references: dict, trains: dict, ours: dict) -> list[str]:
    """Lines of a table: each wall category's share of all objects (count / objects) in
    the val rooms, the train rooms and ours pooled, per room type."""
    from pair2scene.metrics.wall_objects import wall_report

    def cell(report: dict, key: str) -> str:
        row = report.get(key)
        if row is None:
            return "-"
        n, total = row["count"]
        return f"{row['rate']:.4f} ({n}/{total})"

    lines = [
        "| wall category's share of all objects | real val rooms | real train rooms | "
        f"ours (fit), {len(next(iter(ours.values())))} rooms |",
        "|---|---|---|---|",
    ]
    for room in references:
        reports = [wall_report(x) for x in (references[room], trains[room], ours[room])]
        keys = sorted({k for r in reports for k in r if k.startswith("wall_share/")})
        for key in keys:
            lines.append(f"| {room}: {key.split('/', 1)[1]} | "
                         + " | ".join(cell(r, key) for r in reports) + " |")  # fmt: skip
    return lines


if __name__ == "__main__":
    main()

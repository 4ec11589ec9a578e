"""The method's "3D-FRONT only" experiment, for users who have 3D-FRONT.

Run from the repository root, with your own copy of 3D-FRONT (its terms forbid
redistribution: nothing of it is committed here)::

    python benchmarks/front3d.py --houses PATH/3D-FRONT [--work W] [--scenes 200]
        [--room bedroom --room living_room] [--epochs 10] [--workers 2] [--doc docs/front3d.md]

``PATH/3D-FRONT`` is a folder of house JSON files; the categories come from
``model_info.json`` in it or in ``../3D-FUTURE-model/`` (3D-FUTURE's list, or the
3D-FRONT toolbox's model id -> category mapping), and the models' own extents from
``3D-FUTURE-model/<jid>/raw_model.obj`` when that folder is there. The steps, each the
command a user would type, each timed:

1. ``pair2scene curate --source 3dfront:HOUSES --out W/pairs`` (rooms split 80/20 by a
   hash of their id; the statistics and the training tuples come from the train rooms);
2. ``pair2scene train --data W/pairs --out W/model --epochs E``;
3. ``pair2scene generate --room R --mode fit|beyond --num S --stats W/pairs/stats.json
   --model W/model`` for every room type;
4. ``pair2scene evaluate --scenes ... --reference 3dfront:HOUSES:val`` against the
   held-back rooms of that type: FID and KID on top views (the paper's protocol, 200
   scenes), SCA, category KL, collisions and floating objects.

Writes W/front3d.md (and ``--doc`` when given): the figures and the time of each step.
Every step resumes: rerun the same command after an interruption.
"""

from __future__ import annotations

import argparse
import json
import subprocess
import sys
import time
from pathlib import Path

from _docs import machine

MODES = ("fit", "beyond")
FIGURES = (
    ("fid", "FID", "{:.1f}"),
    ("kid", "KID x1e3", "{:.1f}"),
    ("sca", "SCA", "{:.2f}"),
    ("category_kl", "category KL", "{:.3f}"),
    ("collision_rate", "collisions / object", "{:.3f}"),
    ("floating_rate", "floating / object", "{:.3f}"),
    ("objects_per_scene", "objects / scene", "{:.1f}"),
)


def run(cmd: list[str], log: Path, needed: bool = True) -> float | None:
    """Run a pair2scene command (output to ``log``); its wall time. On failure: exits
    when the step is ``needed``, else prints the reason and returns None."""
    print("$ pair2scene " + " ".join(cmd), flush=True)
    t0 = time.perf_counter()
    with log.open("w", encoding="utf-8") as fh:
        code = subprocess.run([sys.executable, "-m", "pair2scene", *cmd], stdout=fh,
                              stderr=subprocess.STDOUT).returncode  # fmt: skip
    if code:
        tail = log.read_text(encoding="utf-8", errors="replace").strip().splitlines()[-3:]
        message = f"failed ({code}): pair2scene {' '.join(cmd)}\n" + "\n".join(tail)
        if needed:
            sys.exit(message)
        print(message, flush=True)
        return None
    return time.perf_counter() - t0


def figure(report: dict, key: str) -> float | None:
    """A figure of an evaluate report, wherever its section keeps it."""
    if key in report and isinstance(report[key], int | float):
        return float(report[key])
    for value in report.values():
        if isinstance(value, dict) and isinstance(value.get(key), int | float):
            return float(value[key])
    return None


def main(argv: list[str] | None = None) -> None:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--houses", type=Path, required=True, help="Folder of 3D-FRONT house JSONs.")
    p.add_argument("--work", type=Path, default=Path("front3d-work"))
    p.add_argument("--room", action="append", help="Room types (default bedroom, living_room).")
    p.add_argument("--scenes", type=int, default=200, help="Scenes per room type and mode.")
    p.add_argument("--epochs", type=int, default=10)
    p.add_argument("--preset", default="cpu")
    p.add_argument("--workers", type=int, default=2, help="Processes for curation.")
    p.add_argument("--doc", type=Path, help="Also write the table to this markdown file.")
    a = p.parse_args(argv)
    if not a.houses.is_dir():
        sys.exit(f"--houses {a.houses}: no such folder")
    rooms = a.room or ["bedroom", "living_room"]
    w = a.work
    (w / "logs").mkdir(parents=True, exist_ok=True)
    src = f"3dfront:{a.houses.resolve()}"
    times: dict[str, float] = {}

    pairs, model = w / "pairs", w / "model"
    curate = ["curate", "--source", src, "--out", str(pairs), "--workers", str(a.workers)]
    times["curate"] = run(curate, w / "logs" / "curate.log")
    train = ["train", "--data", str(pairs), "--out", str(model), "--preset", a.preset,
             "--epochs", str(a.epochs)]  # fmt: skip
    times["train"] = run(train, w / "logs" / "train.log")
    rows = []
    for room in rooms:
        for mode in MODES:
            gen = w / "scenes" / mode / room
            key = f"{mode}/{room}"
            seconds = run(
                ["generate", "--room", room, "--mode", mode, "--num", str(a.scenes),
                 "--stats", str(pairs / "stats.json"), "--model", str(model),
                 "--out", str(gen), "--threads", "1"],
                w / "logs" / f"generate_{mode}_{room}.log", needed=False,
            )  # fmt: skip
            if seconds is None:  # a room type the train rooms lack
                rows.append((room, mode, {"note": "no train rooms of this type"}))
                continue
            times[f"generate {key}"] = seconds
            out = w / "eval" / f"{mode}_{room}.json"
            out.parent.mkdir(parents=True, exist_ok=True)
            seconds = run(
                ["evaluate", "--scenes", str(gen), "--reference", f"{src}:val",
                 "--out", str(out)],
                w / "logs" / f"evaluate_{mode}_{room}.log", needed=False,
            )  # fmt: skip
            if seconds is None:
                rows.append((room, mode, {"note": "no val rooms of this type"}))
                continue
            times[f"evaluate {key}"] = seconds
            rows.append((room, mode, json.loads(out.read_text(encoding="utf-8"))))

    lines = [
        "## 3D-FRONT only",
        "",
        f"`python benchmarks/front3d.py --houses {a.houses} --scenes {a.scenes} "
        f"--epochs {a.epochs}`; {machine()}.",
        "",
        "| room | mode | scenes | reference rooms | "
        + " | ".join(name for _, name, _ in FIGURES) + " |",
        "|---|---|---|---|" + "---|" * len(FIGURES),
    ]  # fmt: skip
    for room, mode, report in rows:
        cells = []
        for key, _, fmt in FIGURES:
            value = figure(report, key)
            cells.append("-" if value is None else fmt.format(value))
        if "note" in report:
            cells = [report["note"]] + ["-"] * (len(FIGURES) - 1)
        lines.append(f"| {room} | {mode} | {report.get('n_generated', '-')} | "
                     f"{report.get('n_reference', '-')} | " + " | ".join(cells) + " |")  # fmt: skip
    lines += ["", "| step | seconds |", "|---|---|"]
    lines += [f"| {step} | {sec:.0f} |" for step, sec in times.items()]
    text = "\n".join(lines) + "\n"
    (w / "front3d.md").write_text(text, encoding="utf-8")
    if a.doc is not None:
        from _docs import replace_section

        replace_section(a.doc, "## 3D-FRONT only", text.rstrip("\n"))
    print(text)


if __name__ == "__main__":
    main()

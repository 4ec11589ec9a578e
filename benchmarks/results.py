"""docs/results.md: every method and baseline, generated and evaluated by one harness.

Run from the repository root, with ``../shared`` beside it (the ProcTHOR val rooms are part
of the reference)::

    python benchmarks/results.py --pairs PAIRS --variants VARIANTS [--scenes 30]
        [--rooms bedroom living_room kitchen] [--work WORK] [--jobs 2] [--train-missing]
        [--no-write]

PAIRS is a ``pair2scene curate`` folder (the Gaussian baseline is fitted on its train
split); VARIANTS holds ``class-only``, ``no-pretrain`` and ``global`` checkpoints from
``pair2scene train --variant ...`` (``--train-missing`` trains a missing one first;
otherwise it is skipped and named in the doc).

For every method and room type the script runs ``pair2scene generate`` (seeds 0 ..
scenes-1, ``--threads 1``, ``--jobs`` commands side by side) and ``pair2scene evaluate``
against the AI2-THOR val rooms and the ProcTHOR-1k val rooms of that type, both resumable
(WORK keeps the scenes and reports: a second run only does what is missing). The tables
replace docs/results.md.
"""

from __future__ import annotations

import argparse
import datetime as dt
import json
import subprocess
import sys
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

from _docs import machine

ROOT = Path(__file__).resolve().parents[1]
DOC = ROOT / "docs" / "results.md"
PROCTHOR_VAL = ROOT.parent / "shared" / "data" / "procthor-1k" / "val.jsonl.gz"
ROOMS = ("bedroom", "living_room", "kitchen")
DISCUSSION = "## Discussion"
VARIANTS = ("class-only", "no-pretrain", "global")


def methods(pairs: Path, variants: Path) -> dict[str, tuple[list[str], str]]:
    """name -> (generate arguments, what it is)."""
    out = {
        "ours (fit)": ([], "the method, bundled model, `--mode fit`"),
        "ours (beyond)": (["--mode", "beyond"], "the method, `--mode beyond` (80 objects)"),
        "random": (
            ["--model", "random"],
            "uniform positions and yaws (the null model: no anchor frames), same rejection "
            "and gravity",
        ),
        "gaussian": (
            ["--model", f"gaussian:{pairs}"],
            "per-pair Gaussian mixtures (issue 5), in the learned model's anchor frames",
        ),
    }
    for v in VARIANTS:
        out[v] = (["--model", str(variants / v)], f"model variant `{v}`")
    out["no rejection"] = (["--ablation", "no-rejection"], "ours, first candidate accepted")
    out["no gravity"] = (["--ablation", "no-gravity"], "ours, predicted heights kept")
    return out


def slug(name: str) -> str:
    return "".join(c if c.isalnum() else "-" for c in name).strip("-").replace("--", "-")


def run(cmd: list[str], log: Path) -> int:
    with open(log, "a", encoding="utf-8") as fh:
        fh.write(" ".join(cmd) + "\n")
        fh.flush()
        return subprocess.run(cmd, stdout=fh, stderr=subprocess.STDOUT).returncode


def cell(name: str, args: list[str], room: str, a: argparse.Namespace) -> dict | None:
    """Generate and evaluate one method on one room type; the report, or None."""
    folder = a.work / slug(name) / room
    folder.mkdir(parents=True, exist_ok=True)
    log = folder.parent / f"{room}.log"
    report = folder.parent / f"{room}.report.json"
    exe = [sys.executable, "-m", "pair2scene"]
    if not report.is_file():
        gen = [*exe, "generate", "--room", room, "--num", str(a.scenes), "--threads", "1",
               "--out", str(folder), "--json", *args]  # fmt: skip
        if run(gen, log) != 0:
            print(f"{name} / {room}: generate failed, see {log}", file=sys.stderr)
            return None
        ref = ["--reference", "ai2thor:val", "--reference", f"procthor:{PROCTHOR_VAL}"]
        ev = [*exe, "evaluate", "--scenes", str(folder), *ref, "--out", str(report), "--json",
              "--threads", "1"]  # fmt: skip
        if run(ev, log) != 0:
            print(f"{name} / {room}: evaluate failed, see {log}", file=sys.stderr)
            return None
    print(f"{name} / {room}: done", file=sys.stderr)
    return json.loads(report.read_text(encoding="utf-8"))


COLUMNS = (
    ("collision_rate", "coll.", "{:.3f}"), ("floating_rate", "float.", "{:.3f}"),
    ("stability", "stab.", "{:.3f}"), ("acceptance_rate", "accept.", "{:.2f}"),
    ("resamples_per_object", "resampl.", "{:.2f}"), ("objects_per_scene", "objects", "{:.1f}"),
    ("seconds_per_scene", "s/scene", "{:.2f}"), ("category_kl", "KL", "{:.3f}"),
    ("pose_mmd", "pose MMD", "{:.3f}"), ("sca", "SCA", "{:.3f}"), ("fid", "FID", "{:.1f}"),
    ("kid", "KID x1e-3", "{:.1f}"),
)  # fmt: skip


def table(rows: dict[str, dict | None]) -> list[str]:
    head = "| method | " + " | ".join(c[1] for c in COLUMNS) + " |"
    lines = [head, "|" + "---|" * (len(COLUMNS) + 1)]
    for name, rep in rows.items():
        if rep is None:
            lines.append(f"| {name} | " + " | ".join("n/a" for _ in COLUMNS) + " |")
            continue
        vals = [("-" if rep.get(k) is None else f.format(rep[k])) for k, _, f in COLUMNS]
        lines.append(f"| {name} | " + " | ".join(vals) + " |")
    return lines


LAYOUT = (
    ("layout", "against_wall", "against wall"),
    ("layout", "in_corner", "in a corner"),
    ("layout", "chairs_facing_table", "chairs at table"),
    ("layout", "tables_with_a_chair", "tables with a chair"),
    ("layout", "tables_seating_four", "tables seating 4+"),
    ("layout", "sofas_facing_tv", "sofa faces TV"),
    ("layout", "sofas_with_coffee_table", "coffee table at sofa"),
    ("layout", "nightstands_at_bed_head", "nightstand at bed"),
    ("layout", "floor_overlaps", "over/under another"),
    ("layout", "floor_askew", "turned off the walls"),
    ("layout", "floor_isolated", "alone mid-room"),
    ("layout", "rooms_sparse", "rooms sparse"),
    ("layout", "rooms_crowded", "rooms crowded"),
    ("navigation", "reachable_free_floor", "reachable floor"),
    ("navigation", "rooms_reachable_0.97", "rooms >= 0.97"),
    ("navigation", "objects_reachable", "fronts reachable"),
    ("navigation", "doors_clear", "doors clear"),
    ("walls", "wall_objects_per_room", "wall objects / room"),
    ("walls", "covered", "wall objects covered"),
    ("walls", "windows_per_room", "windows / room"),
)
"""The realism measures real rooms get too (evaluate's ``layout``, ``navigation`` and
``walls`` sections): one table per room type, the reference rooms first."""


def _rate(stat: dict | None) -> str:
    if not stat or stat.get("rate") is None:
        return "-"
    return f"{stat['rate']:.2f}"


def layout_table(rows: dict[str, dict | None]) -> list[str]:
    """The measures of :data:`LAYOUT` (reference rooms first), then the against-wall rate
    per category (the furniture real rooms put against a wall)."""
    reports = {name: rep for name, rep in rows.items() if rep is not None}
    if not reports:
        return []
    first = next(iter(reports.values()))
    head = "| rooms | " + " | ".join(c[2] for c in LAYOUT) + " |"
    lines = [head, "|" + "---|" * (len(LAYOUT) + 1)]

    def row(name: str, side: str, rep: dict) -> str:
        vals = [_rate(rep.get(sec, {}).get(key, {}).get(side)) for sec, key, _ in LAYOUT]
        return f"| {name} | " + " | ".join(vals) + " |"

    lines.append(row("real (reference)", "reference", first))
    lines += [row(name, "generated", rep) for name, rep in reports.items()]
    against = {k.split("/", 1)[1]: v for k, v in first.get("layout", {}).items()
               if k.startswith("against_wall/")}  # fmt: skip
    lines += _category_table("against a wall", against, lambda r: {
        k.split("/", 1)[1]: v for k, v in r.get("layout", {}).items()
        if k.startswith("against_wall/")}, first, reports)  # fmt: skip
    lines += _category_table("in a corner", first.get("layout", {}).get(
        "in_corner_by_category", {}), lambda r: r.get("layout", {}).get(
        "in_corner_by_category", {}), first, reports)  # fmt: skip
    return lines


def _category_table(title: str, rows: dict, of, first: dict, reports: dict) -> list[str]:
    """One rate per category (columns) for the real rooms and each method (rows); ``of``
    gives a report's category -> {"generated", "reference"} stats. Categories no room
    had are left out."""
    cats = [c for c in rows if any((of(r).get(c, {}).get(side) or {}).get("rate") is not None
                                   for r in reports.values()
                                   for side in ("generated", "reference"))]  # fmt: skip
    if not cats:
        return []

    def cat_row(name: str, side: str, rep: dict) -> str:
        return f"| {name} | " + " | ".join(_rate(of(rep).get(c, {}).get(side)) for c in cats) + " |"

    return ["", f"| {title} | " + " | ".join(cats) + " |", "|" + "---|" * (len(cats) + 1),
            cat_row("real (reference)", "reference", first),
            *(cat_row(name, "generated", rep) for name, rep in reports.items())]  # fmt: skip


CATEGORY_GROUPS = ("against_wall_other", "in_corner_by_category")
"""Groups of per-category rows in evaluate's layout section, left out of :func:`tests_table`."""


def tests_table(rep: dict | None, method: str = "ours (fit)") -> list[str]:
    """``method`` against the real rooms, row by row of evaluate's realism sections (the
    against-wall and in-corner rates of every category left out when neither side has
    one): the counts and the two-sided exact test of one rate for both
    (:mod:`pair2scene.metrics.significance`, worked out from the counts, so a report
    written before the tests were added reads the same)."""
    from pair2scene.evaluate import PER_ROOM, SECTIONS
    from pair2scene.metrics.significance import compare, p_label, rows_of, stat_label

    if rep is None:
        return []
    lines = [f"| measure | real | {method} | differ? |", "|---|---|---|---|"]

    differ = []
    for sec in SECTIONS:
        # (the per-category tables above hold the categories' rows)
        for name, row in rows_of(rep.get(sec, {}), skip=CATEGORY_GROUPS):
            gen, ref = row["generated"], row["reference"]
            if (gen or {}).get("rate") is None and (ref or {}).get("rate") is None:
                continue
            p = compare(gen, ref, name in PER_ROOM)["p_value"]
            if p is not None and p < 0.05:
                differ.append(name)
            lines.append(f"| {name} | {stat_label(ref)} | {stat_label(gen)} | {p_label(p)} |")
    lines += ["", f"Rows of {method} that differ from the real rooms beyond these rooms' noise "
              f"(p < 0.05): {', '.join(differ) if differ else 'none'}."]  # fmt: skip
    return lines


def sheet(room: str, names: list[str], a: argparse.Namespace, per_row: int = 6) -> str | None:
    """docs/results_<room>.png: a row of top views (what FID, KID and SCA see) for the real
    rooms and for each method; the file name, or None when nothing was generated."""
    import numpy as np

    from pair2scene.evaluate import _counted_only, load_reference, load_scene_folder
    from pair2scene.metrics.topview import contact_sheet, topview

    rows = [load_reference(["ai2thor:val", f"procthor:{PROCTHOR_VAL}"], [room])[:per_row]]
    for name in names:
        folder = a.work / slug(name) / room
        if folder.is_dir():
            rows.append(load_scene_folder(folder)[:per_row])
    if len(rows) < 2:
        return None
    images = [topview(_counted_only(s), 160) for row in rows for s in row]
    out = DOC.parent / f"results_{room}.png"
    contact_sheet(np.stack(images), cols=per_row).save(out)
    return out.name


def variant_epochs(variants: Path) -> str:
    """How long each variant of ``variants`` trained: "`global` 40 epochs (best 38)", or
    "`no-pretrain` 1 of the preset's 2 epochs" for a run stopped early. The checkpoint's
    config.json is written at each best epoch; the epochs run are in its training state
    (``train_state.json``), when kept."""
    parts = []
    for v in VARIANTS:
        try:
            training = json.loads((variants / v / "config.json").read_text())["training"]
            planned, best = int(training["epochs"]), int(training["best_epoch"])
        except (OSError, ValueError, KeyError, TypeError):
            continue
        try:
            state = json.loads((variants / v / "train_state.json").read_text())
            done = len(state["history"])
        except (OSError, ValueError, KeyError, TypeError):
            done = len(training.get("history", ())) or best
        of = "" if done == planned else f" of the preset's {planned}"
        parts.append(f"`{v}` {done}{of} epochs" + (f" (best {best})" if best != done else ""))
    return ", ".join(parts) or "no variant checkpoints"


def write_doc(results: dict, described: dict, a: argparse.Namespace, skipped: list[str]) -> None:
    from pair2scene.io.atomic import atomic_write_text

    manifest = json.loads((a.pairs / "manifest.json").read_text())
    tuples = f"3D-Pairs v{manifest['version']}, {manifest['count']:,} tuples"
    from pair2scene.model.checkpoint import CONFIG_FILE, DEFAULT_DIR

    seen = json.loads((DEFAULT_DIR / CONFIG_FILE).read_text())["training"]["data"]
    bundled = seen["train_tuples"] + seen["val_tuples"]
    trained = (
        "the bundled model was trained on them, 40 epochs"
        if bundled == manifest["count"]
        else f"the bundled model was trained on the {bundled:,} of an earlier curation, 40 epochs"
    )
    lines = [
        "# Results",
        "",
        f"`python benchmarks/results.py --pairs PAIRS --variants VARIANTS --scenes {a.scenes}` "
        f"on {machine()}, {dt.date.today().isoformat()}. Each cell: {a.scenes} generated rooms "
        "(seeds 0..N-1) evaluated by `pair2scene evaluate` against the AI2-THOR val rooms and "
        "the ProcTHOR-1k val rooms of the same type. PAIRS is `pair2scene curate --source "
        "ai2thor --source procthor:train.jsonl.gz --source procthor:val.jsonl.gz --out PAIRS` "
        f"({tuples}; {trained}); "
        "VARIANTS holds `pair2scene train --variant V` checkpoints, trained on the same PAIRS "
        "(`pair2scene train --data PAIRS --out VARIANTS/V --variant V`, as `--train-missing` "
        f"does; the cpu preset; {variant_epochs(a.variants)}).",
        "",
        "Columns: mesh-level collision rate and floating rate (share of objects; lower is "
        "better), stability (share of simulated objects that move < 2 cm in 2 s of MuJoCo; "
        "higher is better), acceptance rate and resamples per object (placement), objects and "
        "seconds per scene (2 CPU cores, one scene at a time per process, two processes side "
        "by side), category KL(reference || generated) (ATISS; lower is better), pose MMD "
        "(squared MMD of relative poses over the 10 most frequent anchor/dependent pairs; "
        "0 best, 2 worst), SCA (a CNN telling real from generated top views; 0.5 is ideal), "
        "FID and KID on 256 x 256 semantic top views (DiffuScene protocol; lower is better).",
        "",
        "Methods: " + "; ".join(f"**{k}**: {v}" for k, v in described.items()) + ".",
        "",
    ]
    if skipped:
        lines += [f"Not run (checkpoint missing): {', '.join(skipped)}.", ""]
    for room in a.rooms:
        rows = {name: results.get((name, room)) for name in described}
        n_ref = next((r["n_reference"] for r in rows.values() if r), None)
        lines += [f"## {room.replace('_', ' ').capitalize()}s", ""]
        if n_ref is not None:
            lines += [f"Reference: {n_ref} real rooms.", ""]
        lines += table(rows) + [""]
        realism = layout_table(rows)
        if realism:
            lines += [
                "Realism measures, computed alike for the real rooms and every method "
                "(`pair2scene evaluate`'s layout, navigation and walls sections; rates, "
                "the mean reachable share of the free floor, and wall objects and windows "
                "per room):",
                "",
                *realism,
                "",
            ]
        tests = tests_table(rows.get("ours (fit)"))
        if tests:
            lines += [
                "Ours (fit) against the real rooms, measure by measure, with the counts "
                "behind each rate and a two-sided exact test of one rate for both "
                "(Fisher's for shares, Poisson rates for counts per room; each counted "
                "object taken as independent; `pair2scene evaluate` prints the same "
                "column). A large p says these rooms cannot tell the two rates apart, not "
                "that they are equal:",
                "",
                *tests,
                "",
            ]
        picture = sheet(room, [n for n in described if rows.get(n)], a)
        if picture is not None:
            lines += [f"Top views, one row each: real rooms, then "
                      f"{', '.join(n for n in described if rows.get(n))}:", "",
                      f"![{room} top views]({picture})", ""]  # fmt: skip
    # The hand-written discussion (what the figures mean) survives a rerun.
    old = DOC.read_text(encoding="utf-8") if DOC.exists() else ""
    at = old.find(DISCUSSION)
    if at >= 0:
        lines += [old[at:].rstrip()]
    atomic_write_text(DOC, "\n".join(lines).rstrip() + "\n")


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--pairs", type=Path, required=True)
    ap.add_argument("--variants", type=Path, required=True)
    ap.add_argument("--scenes", type=int, default=30)
    ap.add_argument("--rooms", nargs="+", default=list(ROOMS))
    ap.add_argument("--methods", nargs="+", default=None, help="names to run (default: all)")
    ap.add_argument("--work", type=Path, default=Path("/tmp/p2s-results"))
    ap.add_argument("--jobs", type=int, default=2)
    ap.add_argument("--train-missing", action="store_true",
                    help="train a missing variant first (cpu preset, ~15-45 min each)")  # fmt: skip
    ap.add_argument("--no-write", action="store_true")
    a = ap.parse_args()

    every = methods(a.pairs, a.variants)
    chosen = {k: v for k, v in every.items() if a.methods is None or k in a.methods}
    for k in VARIANTS:
        if k in chosen and a.train_missing and not (a.variants / k / "config.json").is_file():
            cmd = [sys.executable, "-m", "pair2scene", "train", "--data", str(a.pairs),
                   "--out", str(a.variants / k), "--variant", k]  # fmt: skip
            print(" ".join(cmd), file=sys.stderr)
            subprocess.run(cmd, check=False)
    skipped = [k for k in VARIANTS
               if k in chosen and not (a.variants / k / "config.json").is_file()]  # fmt: skip
    for k in skipped:
        chosen.pop(k)
    jobs = [(name, args, room) for room in a.rooms for name, (args, _) in chosen.items()]
    results: dict[tuple[str, str], dict | None] = {}
    with ThreadPoolExecutor(max_workers=a.jobs) as pool:
        futures = {pool.submit(cell, n, args, room, a): (n, room) for n, args, room in jobs}
        for fut, key in futures.items():
            results[key] = fut.result()
    described = {k: v[1] for k, v in chosen.items()}
    for room in a.rooms:
        print(f"\n{room}")
        print("\n".join(table({n: results.get((n, room)) for n in described})))
    if not a.no_write:
        write_doc(results, described, a, skipped)
        print(f"\nwrote {DOC}")
    return 0


if __name__ == "__main__":
    sys.exit(main())

"""Functional distillation against hand labels: precision, recall and F1.

Run from the repository root::

    python benchmarks/functional_validation.py [--procthor DIR] [--no-write]

Reads the hand labels ``docs/functional_labels.json`` (rooms of the AI2-THOR
and ProcTHOR val splits, each with its (anchor, dependent) pairs), loads the
same rooms through the adapters, runs
``distill_functional(scene, proposer, use_k_check=...)`` on each with and
without the k-check, and compares the pairs it sets (``functional_anchor``,
object id) with the labels: micro precision, recall and F1 over every pair of
every labelled room, overall and per source, in the form of the Pair2Scene
validation table. A pair counts only with the right direction (anchor and
dependent); the reversed ones are counted apart.

Proposers:

- ``offline``: ``OfflineProposer()``, the shipped commonsense pair table;
- ``offline, corpus pairs``: ``OfflineProposer(table=[], stats=...)``, only the
  category pairs ``CorpusPairStats`` finds consistent in the *train* splits of
  both sources (no label and no val room is seen);
- an LLM proposer needs an endpoint, which this machine does not have.

Writes ``docs/functional_validation.md`` (the whole file) with the command,
the date and the tables; ``--no-write`` only prints.
"""

from __future__ import annotations

import argparse
import datetime as dt
import json
import shlex
import sys
from collections import Counter
from collections.abc import Callable, Iterable
from dataclasses import dataclass, field
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
LABELS = ROOT / "docs" / "functional_labels.json"
DOC = ROOT / "docs" / "functional_validation.md"
PROCTHOR_DIR = ROOT.parent / "shared" / "data" / "procthor-1k"
FORMAT = "pair2scene.functional_labels"
SOURCES = ("ai2thor", "procthor")
TOP = 8
"""How many category pairs to name among the misses and the false alarms."""

Pair = tuple[str, str]
"""(anchor id, dependent id)."""


# -- labels and rooms ----------------------------------------------------------------------


@dataclass(frozen=True)
class LabelledRoom:
    room: str
    source: str
    pairs: frozenset[Pair]


def load_labels(path: Path = LABELS) -> list[LabelledRoom]:
    data = json.loads(path.read_text(encoding="utf-8"))
    if data.get("format") != FORMAT or data.get("version") != 1:
        raise SystemExit(f"{path}: not a {FORMAT} version 1 file")
    return [
        LabelledRoom(r["room"], r["source"], frozenset((a, d) for a, d in r["pairs"]))
        for r in data["rooms"]
    ]


def load_scenes(split: str, procthor_dir: Path) -> dict:
    """scene id -> Scene, for both sources' ``split``."""
    from pair2scene.data.sources import load_source

    corpora = [
        load_source("ai2thor", split=split),
        load_source(f"procthor:{procthor_dir / f'{split}.jsonl.gz'}", split=split),
    ]
    return {s.id: s for c in corpora for s in c.scenes}


# -- scoring -------------------------------------------------------------------------------


@dataclass
class Score:
    correct: int = 0
    predicted: int = 0
    labelled: int = 0
    reversed: int = 0
    """Predicted pairs whose reverse is labelled (counted wrong)."""

    def add(self, predicted: set[Pair], labelled: Iterable[Pair]) -> None:
        labelled = set(labelled)
        self.correct += len(predicted & labelled)
        self.predicted += len(predicted)
        self.labelled += len(labelled)
        self.reversed += len({(d, a) for a, d in predicted} & labelled)

    @property
    def precision(self) -> float | None:
        return self.correct / self.predicted if self.predicted else None

    @property
    def recall(self) -> float | None:
        return self.correct / self.labelled if self.labelled else None

    @property
    def f1(self) -> float | None:
        p, r = self.precision, self.recall
        if p is None or r is None:
            return None
        return 2 * p * r / (p + r) if p + r else 0.0


@dataclass
class Run:
    """One proposer with or without the k-check over every labelled room."""

    proposer: str
    k_check: bool
    overall: Score = field(default_factory=Score)
    by_source: dict[str, Score] = field(default_factory=lambda: {s: Score() for s in SOURCES})
    misses: Counter[tuple[str, str]] = field(default_factory=Counter)
    """(anchor category, dependent category) of labelled pairs not predicted."""
    false_alarms: Counter[tuple[str, str]] = field(default_factory=Counter)
    """... of predicted pairs not labelled."""


def predicted_pairs(scene) -> set[Pair]:
    """(functional_anchor, id) of every object that has a functional anchor."""
    return {(o.functional_anchor, o.id) for o in scene.objects if o.functional_anchor}


def evaluate(
    name: str,
    proposer,
    use_k_check: bool,
    labels: list[LabelledRoom],
    scenes: dict,
) -> Run:
    from pair2scene.curation.functional import distill_functional

    run = Run(name, use_k_check)
    for room in labels:
        scene = scenes[room.room]
        predicted = predicted_pairs(distill_functional(scene, proposer, use_k_check=use_k_check))
        run.overall.add(predicted, room.pairs)
        run.by_source[room.source].add(predicted, room.pairs)
        category = {o.id: o.category for o in scene.objects}
        for a, d in room.pairs - predicted:
            run.misses[category[a], category[d]] += 1
        for a, d in predicted - room.pairs:
            run.false_alarms[category[a], category[d]] += 1
    return run


def proposers(train: Callable[[], dict]) -> list[tuple[str, object, str]]:
    """(name, proposer, note) for every proposer this machine can run."""
    from pair2scene.curation.functional import CorpusPairStats, OfflineProposer

    table = OfflineProposer()
    stats = CorpusPairStats.fit(train().values())
    corpus = OfflineProposer(table=[], stats=stats)
    pairs = ", ".join(f"{r.anchor} <- {r.dependent}" for r in corpus.rules) or "none"
    return [
        ("offline", table, f"`OfflineProposer()`: the shipped table, {len(table.rules)} rows"),
        (
            "offline, corpus pairs",
            corpus,
            "`OfflineProposer(table=[], stats=CorpusPairStats.fit(train))`: the category pairs "
            f"consistent in the train splits of both sources ({pairs})",
        ),
    ]


# -- report --------------------------------------------------------------------------------


def pct(value: float | None) -> str:
    return "n/a" if value is None else f"{100 * value:.1f}"


def row(cells: Iterable[object]) -> str:
    return "| " + " | ".join(str(c) for c in cells) + " |"


def score_cells(s: Score) -> list[str]:
    return [pct(s.precision), pct(s.recall), pct(s.f1), str(s.predicted), str(s.labelled)]


HEAD = ["precision", "recall", "F1", "pairs predicted", "pairs labelled"]


def label_summary(labels: list[LabelledRoom], scenes: dict) -> list[str]:
    rooms = Counter(r.source for r in labels)
    pairs = Counter()
    kinds: Counter[tuple[str, str]] = Counter()
    room_types: Counter[str] = Counter()
    for r in labels:
        pairs[r.source] += len(r.pairs)
        scene = scenes[r.room]
        room_types[scene.room.type] += 1
        category = {o.id: o.category for o in scene.objects}
        for a, d in r.pairs:
            kinds[category[a], category[d]] += 1
    lines = [
        f"{len(labels)} rooms, {sum(pairs.values())} labelled pairs: "
        + ", ".join(f"{s} {rooms[s]} rooms / {pairs[s]} pairs" for s in SOURCES)
        + "; room types "
        + ", ".join(f"{t} {n}" for t, n in sorted(room_types.items()))
        + ".",
        "",
        "Labelled pairs by (anchor <- dependent) category: "
        + ", ".join(f"{a} <- {d} {n}" for (a, d), n in kinds.most_common())
        + ".",
    ]
    return lines


def report(
    runs: list[Run],
    notes: list[tuple[str, str]],
    labels: list[LabelledRoom],
    scenes: dict,
    command: str,
) -> str:
    lines = [
        "# Functional distillation against hand labels",
        "",
        "Issue 4: the distilled functional relations compared with pairs labelled by hand,",
        "in the form of the Pair2Scene validation table (proposer alone, and proposer +",
        "k-check). Written by `benchmarks/functional_validation.py`; do not edit by hand.",
        "",
        f"- command: `{command}`",
        f"- date: {dt.date.today().isoformat()}",
        "- labels: `docs/functional_labels.json` (rooms of the val splits; the rules the",
        "  labeller followed are in the file, with a note per room for the unclear calls)",
        "- scoring: micro over every (anchor, dependent) pair of every labelled room; a",
        "  predicted pair is right only with the right anchor and the right direction;",
        "  rooms without a labelled pair still count their predictions",
        "",
        *label_summary(labels, scenes),
        "",
        "## Validation table",
        "",
        row(["proposer", "k-check", *HEAD]),
        row(["---"] * (2 + len(HEAD))),
    ]
    for r in runs:
        lines.append(row([r.proposer, "yes" if r.k_check else "no", *score_cells(r.overall)]))
    lines += ["", "Proposers:", ""]
    lines += [f"- {name}: {note}" for name, note in notes]
    lines += [
        "- an LLM proposer (`LLMProposer`) needs an OpenAI-compatible endpoint; none is",
        "  reachable here, so it has no row.",
        "",
        "## Per source",
        "",
        row(["source", "proposer", "k-check", *HEAD]),
        row(["---"] * (3 + len(HEAD))),
    ]
    for source in SOURCES:
        for r in runs:
            s = r.by_source[source]
            lines.append(row([source, r.proposer, "yes" if r.k_check else "no", *score_cells(s)]))
    lines += ["", "## Where they differ", ""]
    for r in runs:
        check = "with" if r.k_check else "without"
        lines.append(
            f"- {r.proposer}, {check} the k-check: {r.overall.reversed} predicted pair(s) "
            "labelled the other way round; missed "
            + _top(r.misses)
            + "; predicted but not labelled "
            + _top(r.false_alarms)
            + "."
        )
    return "\n".join(lines) + "\n"


def _top(counts: Counter[tuple[str, str]]) -> str:
    if not counts:
        return "none"
    items = [f"{a} <- {d} {n}" for (a, d), n in counts.most_common(TOP)]
    rest = sum(counts.values()) - sum(n for _, n in counts.most_common(TOP))
    return ", ".join(items) + (f", other {rest}" if rest else "")


# -- main ----------------------------------------------------------------------------------


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--labels", type=Path, default=LABELS)
    parser.add_argument("--procthor", type=Path, default=PROCTHOR_DIR, help="procthor-1k folder")
    parser.add_argument("--no-write", action="store_true", help="print, do not write the doc")
    args = parser.parse_args(argv)

    labels = load_labels(args.labels)
    scenes = load_scenes("val", args.procthor)
    missing = [r.room for r in labels if r.room not in scenes]
    if missing:
        raise SystemExit(f"labelled rooms not in the val splits: {missing}")

    runs: list[Run] = []
    notes = []
    for name, proposer, note in proposers(lambda: load_scenes("train", args.procthor)):
        notes.append((name, note))
        for use_k_check in (False, True):
            runs.append(evaluate(name, proposer, use_k_check, labels, scenes))

    command = "python benchmarks/functional_validation.py" + "".join(
        f" {shlex.quote(a)}" for a in (argv if argv is not None else sys.argv[1:])
    )
    text = report(runs, notes, labels, scenes, command.replace(" --no-write", ""))
    print(text)
    if not args.no_write:
        DOC.write_text(text, encoding="utf-8")
        print(f"wrote {DOC.relative_to(ROOT)}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())

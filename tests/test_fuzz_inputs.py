"""Fuzzing the command line with malformed input (issue 21).

Seeded cases of every kind a user can get wrong: options (seeds, counts, limits, threads,
output paths), scene.json files (for ``validate`` and ``generate --keep``), hierarchy
files (``hierarchy --file``), statistics files (``--stats``), descriptions (``--text``)
and checkpoint folders (``--model``). Each case runs ``pair2scene.cli.main`` in this
process and must end in exit code 0, or 2 with exactly one ``error:`` line on stderr (its
last: a progress line may come first);
never an exception, a traceback, a hang (:data:`CASE_SECONDS`) or debris (a temporary
folder or file left in its output folder).

The default run takes :data:`DEFAULT_CASES` cases (under a minute); ``-m slow`` runs
:data:`SLOW_CASES`, including the expensive kinds (``generate --keep`` and
``generate --model``), and prints a table of outcomes per kind (docs/reliability.md).
"""

from __future__ import annotations

import contextlib
import io
import json
import os
import shutil
import string
import time
from collections import Counter
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import pytest

from pair2scene.cli import main

ROOT = Path(__file__).resolve().parent
SCENE = ROOT / "fixtures" / "scenes" / "valid_bedroom.json"
DEFAULT_CASES = 150
SLOW_CASES = 2000
CASE_SECONDS = 60.0
"""A case taking longer than this is a hang."""

GARBAGE_NUMBERS = [
    -1, 0, 1, 2**31, 2**63, 2**64, 2**70, -(2**70), 1e308, -1e308, 1e-320, 0.5, -0.0,
    float("nan"), float("inf"), float("-inf"), 1180591620717411303424,
]  # fmt: skip
INVALID_NUMBERS = [-1, 2**70, -(2**70), 1e308, float("nan"), float("inf"), 0.5,
                   1180591620717411303424]  # fmt: skip
"""Values no count, seed or thread option takes: a default run never starts a real
generation (the slow run does, with :data:`GARBAGE_NUMBERS`)."""
GARBAGE_TEXT = ["", " ", "-1", "1e999", "nan", "none", "\x00", "é" * 50, "x" * 5000, "../..",
                "/proc/self/x", "\n", "[]", "{}", "bed\nroom"]  # fmt: skip


@dataclass
class Case:
    kind: str
    argv: list[str]
    out: Path | None = None
    """The case's output folder, checked for debris afterwards."""
    scratch: Path | None = None
    """A folder the case needed (a copied checkpoint), removed afterwards."""


def _garbage(rng: np.random.Generator):
    """A JSON value of a wrong kind or out of range."""
    pick = int(rng.integers(9))
    if pick == 0:
        return GARBAGE_NUMBERS[int(rng.integers(len(GARBAGE_NUMBERS)))]
    if pick == 1:
        return GARBAGE_TEXT[int(rng.integers(len(GARBAGE_TEXT)))]
    if pick == 2:
        return None
    if pick == 3:
        return bool(rng.integers(2))
    if pick == 4:
        return []
    if pick == 5:
        return {"a": 1}
    if pick == 6:
        return [float(x) for x in rng.normal(0, 10.0 ** rng.integers(0, 300), rng.integers(1, 5))]
    if pick == 7:
        return "".join(rng.choice(list(string.printable), int(rng.integers(1, 40))))
    return int(rng.integers(-(2**31), 2**31))


def _paths(doc, prefix=()):
    """Every (path, value) of a JSON document."""
    yield prefix, doc
    if isinstance(doc, dict):
        for k, v in doc.items():
            yield from _paths(v, (*prefix, k))
    elif isinstance(doc, list):
        for i, v in enumerate(doc):
            yield from _paths(v, (*prefix, i))


def _set(doc, path, value):
    if not path:
        return value
    node = doc
    for key in path[:-1]:
        node = node[key]
    node[path[-1]] = value
    return doc


def _delete(doc, path):
    node = doc
    for key in path[:-1]:
        node = node[key]
    del node[path[-1]]
    return doc


def mutate_json(doc, rng: np.random.Generator) -> bytes:
    """A malformed copy of ``doc`` as bytes: a value replaced or deleted, a list
    repeated, the text truncated or nested deep, binary bytes."""
    doc = json.loads(json.dumps(doc))
    paths = [p for p, _ in _paths(doc) if p]
    how = int(rng.integers(10))
    if how <= 3 and paths:
        path = paths[int(rng.integers(len(paths)))]
        doc = _set(doc, path, _garbage(rng))
    elif how == 4 and paths:
        _delete(doc, paths[int(rng.integers(len(paths)))])
    elif how == 5:
        lists = [p for p, v in _paths(doc) if isinstance(v, list) and v]
        if lists:
            path = lists[int(rng.integers(len(lists)))]
            node = doc
            for key in path:
                node = node[key]
            node.extend(node * int(rng.integers(2, 200)))
    elif how == 6:
        text = json.dumps(doc)
        return text[: int(rng.integers(len(text)))].encode()
    elif how == 7:
        depth = int(rng.choice([100, 10_000, 200_000]))
        return ("[" * depth + "]" * depth).encode()
    elif how == 8:
        return bytes(rng.integers(0, 256, int(rng.integers(1, 4096)), dtype=np.uint8))
    text = json.dumps(doc, allow_nan=True)
    return text.encode()


class Fuzzer:
    """Seeded cases; files they need are written under ``tmp``."""

    def __init__(self, tmp: Path, seed: int, slow: bool) -> None:
        self.tmp, self.rng, self.slow = tmp, np.random.default_rng(seed), slow
        self.scene = json.loads(SCENE.read_text())
        self.hierarchy = None
        self.n = 0
        kinds: list[tuple[str, Callable[[], Case], float]] = [
            ("options", self.options, 3.0),
            ("scene.json", self.scene_json, 2.0),
            ("hierarchy file", self.hierarchy_file, 1.5),
            ("stats file", self.stats_file, 1.0),
            ("text", self.text, 1.5),
        ]
        if slow:
            kinds += [("keep", self.keep, 0.6), ("checkpoint", self.checkpoint, 0.4)]
        self.kinds = kinds

    def path(self, suffix: str = "") -> Path:
        self.n += 1
        return self.tmp / f"case{self.n:05d}{suffix}"

    def next(self) -> Case:
        w = np.array([k[2] for k in self.kinds])
        kind = self.kinds[int(self.rng.choice(len(self.kinds), p=w / w.sum()))]
        return kind[1]()

    def _number(self, invalid_only: bool = False) -> str:
        pool = INVALID_NUMBERS if invalid_only else GARBAGE_NUMBERS
        return str(pool[int(self.rng.integers(len(pool)))])

    def options(self) -> Case:
        out = self.path()
        bad = {f: self._number for f in ("--seed", "--num", "--max-objects", "--threads")}
        command = self.rng.choice(["hierarchy", "generate", "evaluate", "assets-sheet"])
        argv: list[str]
        if command == "hierarchy":
            argv = ["hierarchy", "--room", "bedroom", "--llm", "never"]
            flags = ["--seed", "--max-objects", "--mode"]
        elif command == "generate":
            argv = ["generate", "--room", "bedroom", "--out", str(out)]
            flags = ["--seed", "--num", "--max-objects", "--threads", "--out"]
        elif command == "evaluate":
            argv = ["evaluate", "--scenes", str(self.tmp / "no-scenes"), "--out", str(out)]
            flags = ["--threads", "--seed", "--out"]
        else:
            argv = ["assets", "sheet", "--out", str(out / "sheet.png")]
            flags = ["--out"]
        flag = str(self.rng.choice(flags))
        if flag == "--out":
            blocker = self.path(".file")
            blocker.write_text("x")
            value = str(
                self.rng.choice(["", str(blocker / "sub"), "/proc/pair2scene", str(self.tmp)])
            )
        elif flag == "--mode":
            value = str(self.rng.choice(["", "fitt", "BEYOND", "-1"]))
        else:
            value = bad[flag](command == "generate" and not self.slow)
        if flag in argv:  # replace its value
            i = argv.index(flag)
            argv[i + 1] = value
        else:
            argv += [flag, value]
        if command == "generate" and flag not in ("--num",):
            argv += ["--num", "1"]
        return Case("options", argv, out)

    def scene_json(self) -> Case:
        f = self.path(".json")
        f.write_bytes(mutate_json(self.scene, self.rng))
        return Case("scene.json", ["validate", str(f)])

    def keep(self) -> Case:
        f, out = self.path(".json"), self.path()
        f.write_bytes(mutate_json(self.scene, self.rng))
        return Case("keep", ["generate", "--keep", str(f), "--out", str(out), "--num", "1",
                             "--llm", "never"], out)  # fmt: skip

    def hierarchy_file(self) -> Case:
        if self.hierarchy is None:
            buf = io.StringIO()
            with contextlib.redirect_stdout(buf):
                assert main(["hierarchy", "--room", "bedroom", "--json", "--llm", "never"]) == 0
            self.hierarchy = json.loads(buf.getvalue())
        f = self.path(".json")
        f.write_bytes(mutate_json(self.hierarchy, self.rng))
        return Case("hierarchy file", ["hierarchy", "--file", str(f), "--llm", "never"])

    def stats_file(self) -> Case:
        f = self.path(".json")
        doc = {"format": "pair2scene.hierarchy_stats", "version": 1, "rooms": {}}
        f.write_bytes(mutate_json(doc, self.rng))
        return Case("stats file", ["hierarchy", "--room", "bedroom", "--stats", str(f),
                                   "--llm", "never"])  # fmt: skip

    def text(self) -> Case:
        words = ["a", "bed", "-5", "0", "beds", "no", "two", "1e9", "chairs", "on", "the",
                 "table", "painting", "above", "wall", "windows", "curtains", "999999",
                 "\u202e", "🛏", "and", ",", ".", "every", "each"]  # fmt: skip
        n = int(self.rng.choice([0, 1, 5, 30, 3000]))
        text = " ".join(self.rng.choice(words, n)) if n else ""
        return Case("text", ["hierarchy", "--text", text, "--llm", "never"])

    def checkpoint(self) -> Case:
        import pair2scene.model

        bundled = Path(pair2scene.model.__file__).parent / "default"
        folder, out = self.path("-model"), self.path()
        shutil.copytree(bundled, folder)
        cfg = json.loads((folder / "config.json").read_text())
        if self.rng.random() < 0.7:
            (folder / "config.json").write_bytes(mutate_json(cfg, self.rng))
        else:
            data = (folder / "model.safetensors").read_bytes()
            cut = int(self.rng.integers(len(data)))
            (folder / "model.safetensors").write_bytes(data[:cut])
        return Case("checkpoint", ["generate", "--room", "bedroom", "--model", str(folder),
                                   "--out", str(out), "--num", "1"], out, folder)  # fmt: skip


def run_case(case: Case) -> tuple[str, str]:
    """(outcome, detail): ``ok`` (exit 0), ``refused`` (exit 2 with one error line) or
    what went wrong."""
    err, out = io.StringIO(), io.StringIO()
    t0 = time.perf_counter()
    try:
        with contextlib.redirect_stderr(err), contextlib.redirect_stdout(out):
            code = main(case.argv)
    except BaseException as e:  # noqa: BLE001  (what the test is looking for)
        return "exception", f"{type(e).__name__}: {str(e)[:200]}"
    seconds = time.perf_counter() - t0
    text = err.getvalue()
    lines = [line for line in text.splitlines() if line.strip()]
    if "Traceback" in text:
        return "traceback", text[-300:]
    if seconds > CASE_SECONDS:
        return "hang", f"{seconds:.0f} s"
    if case.out is not None and case.out.parent.exists():
        debris = [p.name for p in case.out.parent.glob(f"{case.out.name}*/.*")]
        debris += [p.name for p in case.out.glob(".*")] if case.out.is_dir() else []
        if debris:
            return "debris", ", ".join(debris[:3])
    if code == 0:
        return "ok", ""
    errors = [line for line in lines if line.startswith("error:")]
    if code == 2 and len(errors) == 1 and lines[-1] == errors[0]:
        return "refused", ""  # (a progress line may come before it)
    return f"exit {code}", " | ".join(lines)[:300]


def fuzz(tmp: Path, cases: int, seed: int, slow: bool) -> tuple[Counter, list]:
    fuzzer = Fuzzer(tmp, seed, slow)
    outcomes: Counter = Counter()
    bad = []
    for _ in range(cases):
        case = fuzzer.next()
        outcome, detail = run_case(case)
        if case.scratch is not None:
            shutil.rmtree(case.scratch, ignore_errors=True)
        outcomes[(case.kind, outcome)] += 1
        if outcome not in ("ok", "refused"):
            bad.append((case.kind, outcome, case.argv, detail))
    return outcomes, bad


def _table(outcomes: Counter) -> str:
    kinds = sorted({k for k, _ in outcomes})
    rows = [
        "| kind | cases | ok (exit 0) | refused (exit 2, one line) | other |",
        "|---|---|---|---|---|",
    ]
    for k in kinds:
        n = sum(v for (kk, _), v in outcomes.items() if kk == k)
        ok, ref = outcomes[(k, "ok")], outcomes[(k, "refused")]
        rows.append(f"| {k} | {n} | {ok} | {ref} | {n - ok - ref} |")
    return "\n".join(rows)


def test_fuzz_default(tmp_path):
    outcomes, bad = fuzz(tmp_path, DEFAULT_CASES, seed=0, slow=False)
    assert not bad, bad[:5]
    assert sum(outcomes.values()) == DEFAULT_CASES


@pytest.mark.slow
def test_fuzz_long(tmp_path):
    seed = int(os.environ.get("PAIR2SCENE_FUZZ_SEED", "1"))
    cases = int(os.environ.get("PAIR2SCENE_FUZZ_CASES", str(SLOW_CASES)))
    t0 = time.perf_counter()
    outcomes, bad = fuzz(tmp_path, cases, seed=seed, slow=True)
    print(f"\n{cases} cases, seed {seed}, {time.perf_counter() - t0:.0f} s\n{_table(outcomes)}")
    assert not bad, bad[:5]

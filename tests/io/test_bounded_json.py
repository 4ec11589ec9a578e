"""Every JSON a user gives is read within bounds (issue 21): size, UTF-8, JSON, nesting
depth and finite numbers, each a one-line error; hierarchy files within their limits."""

from __future__ import annotations

import json
import time

import pytest

from clitools import run_cli
from pair2scene.cli import main
from pair2scene.curation.stats import HierarchyStats
from pair2scene.errors import UserError
from pair2scene.hierarchy.build import read_hierarchy
from pair2scene.hierarchy.tree import (
    MAX_NODES,
    MAX_SUPPORT_DEPTH,
    Hierarchy,
    HierarchyError,
    Node,
)
from pair2scene.io.jsondoc import (
    MAX_JSON_DEPTH,
    JsonFileError,
    parse_json,
    read_json_document,
    read_json_file,
)
from pair2scene.scene.model import FLOOR

DEEP = "[" * 200_000 + "]" * 200_000
BINARY = bytes(range(256)) * 64


def one_line(err: str) -> str:
    lines = err.splitlines()
    assert len(lines) == 1 and lines[0].startswith("error: "), err
    assert "Traceback" not in err
    return lines[0]


def nested(depth: int) -> str:
    return "[" * depth + "]" * depth


# -- the reader ------------------------------------------------------------------------
def test_deep_nesting_is_refused_fast(tmp_path):
    path = tmp_path / "deep.json"
    path.write_text(DEEP)
    start = time.perf_counter()
    with pytest.raises(JsonFileError, match=f"nested deeper than {MAX_JSON_DEPTH} levels") as e:
        read_json_file(path, "hierarchy")
    assert time.perf_counter() - start < 10.0  # bounded work (seconds on a slow, busy CI)
    assert e.value.field == "(json)" and str(e.value).startswith(f"{path}: ")


def test_depth_limit_is_exact():
    assert parse_json(nested(MAX_JSON_DEPTH), "x") is not None
    assert parse_json('{"a": ' * 63 + "1" + "}" * 63, "x") is not None
    for text in (nested(MAX_JSON_DEPTH + 1), '{"a": ' * 65 + "1" + "}" * 65, nested(900)):
        with pytest.raises(JsonFileError, match="nested deeper than 64"):
            parse_json(text, "x")


def test_binary_file_is_refused(tmp_path):
    path = tmp_path / "binary.json"
    path.write_bytes(BINARY)
    with pytest.raises(JsonFileError, match=r"not UTF-8 text \(byte 128\)") as e:
        read_json_file(path, "statistics")
    assert e.value.field == "(file)"


def test_size_limit_is_checked_before_reading(tmp_path):
    path = tmp_path / "big.json"
    path.write_text(json.dumps({"a": list(range(1000))}))
    with pytest.raises(JsonFileError, match="over the 100 bytes a statistics file may have"):
        read_json_file(path, "statistics", max_bytes=100)
    assert read_json_file(path, "statistics")["a"][-1] == 999


@pytest.mark.parametrize(
    "text, where",
    [
        ('{"a": [1, NaN]}', "a[1]"),
        ('{"a": {"b c": Infinity}}', "a['b c']"),
        ("[-Infinity]", "[0]"),
        ('{"x": 1e999}', "x"),
        ("NaN", "(top level)"),
    ],
)
def test_numbers_must_be_finite(text, where):
    with pytest.raises(JsonFileError, match="is not a finite number") as e:
        parse_json(text, "f.json")
    assert f": {where} is not" in str(e.value)
    parse_json(text, "f.json", finite=False)  # (readers that check numbers themselves)


@pytest.mark.parametrize(
    "raw, problem",
    [
        (b"", "is empty"),
        (b" \n", "is empty"),
        (b'{"a": ', "not valid JSON"),
        (b"[" + b"7" * 5000 + b"]", "not valid JSON"),
        (b"\xef\xbb\xbf{}", "not valid JSON"),
    ],
)
def test_other_bad_files_are_one_line(tmp_path, raw, problem):
    path = tmp_path / "f.json"
    path.write_bytes(raw)
    with pytest.raises(JsonFileError, match=problem) as e:
        read_json_file(path, "hierarchy")
    assert "\n" not in str(e.value)


def test_missing_and_folder(tmp_path):
    with pytest.raises(JsonFileError, match="no such file") as e:
        read_json_file(tmp_path / "nope.json", "hierarchy")
    assert e.value.missing
    with pytest.raises(JsonFileError, match="is a directory"):
        read_json_file(tmp_path, "hierarchy")


def test_documents_and_statistics_use_the_bounded_reader(tmp_path):
    deep, binary = tmp_path / "deep.json", tmp_path / "binary.json"
    deep.write_text(DEEP)
    binary.write_bytes(BINARY)
    for path in (deep, binary):
        with pytest.raises(UserError, match="not readable JSON"):
            read_json_document(path, "pair2scene.summary", 1)
        with pytest.raises(UserError, match=str(path)):
            HierarchyStats.from_file(path)
    with pytest.raises(UserError, match="nested deeper"):
        HierarchyStats.from_json(DEEP, "stats.json")
    with pytest.raises(UserError, match="no such file"):
        read_json_document(tmp_path / "nope.json", "pair2scene.summary", 1, "no such file")


# -- hierarchy files -------------------------------------------------------------------
def hierarchy_doc(h: Hierarchy) -> dict:
    return h.to_dict(mode="fit", seed=0)


def test_hierarchy_file_limits(tmp_path):
    many = Hierarchy("bedroom")
    for _ in range(MAX_NODES):
        many.add("book", FLOOR)
    start = time.perf_counter()
    doc = hierarchy_doc(many)
    assert len(Hierarchy.from_dict(doc)) == MAX_NODES  # the limit itself: fine, and fast
    assert time.perf_counter() - start < 10.0  # bounded work (seconds on a slow, busy CI)
    doc["nodes"].append({"id": "extra", "category": "book"})
    with pytest.raises(HierarchyError, match=f"more than the {MAX_NODES}"):
        Hierarchy.from_dict(doc)

    stack = Hierarchy("bedroom")
    below = FLOOR
    for _ in range(MAX_SUPPORT_DEPTH + 1):
        below = stack.add("book", below).id
    with pytest.raises(HierarchyError, match=f"at most {MAX_SUPPORT_DEPTH} may"):
        stack.validate()
    stack.nodes.pop()
    stack.support.pop(below)
    stack.validate()

    long = Hierarchy("bedroom", [Node("b" * 201, "book")], {"b" * 201: FLOOR})
    with pytest.raises(HierarchyError, match="201 characters, more than 200"):
        Hierarchy.from_dict(hierarchy_doc(long))
    doc = hierarchy_doc(Hierarchy("bedroom", [Node("b", "book")], {"b": FLOOR}))
    doc["nodes"][0]["id"] = {"a": 1}
    with pytest.raises(HierarchyError, match="malformed hierarchy"):
        Hierarchy.from_dict(doc)


def test_hierarchy_file_reader_is_bounded(tmp_path):
    path = tmp_path / "deep.json"
    path.write_text(DEEP)
    with pytest.raises(UserError, match="nested deeper"):
        read_hierarchy(path)


def test_cli_hierarchy_file_bad_input_is_one_line(tmp_path, capsys):
    deep, binary = tmp_path / "deep.json", tmp_path / "binary.json"
    deep.write_text(DEEP)
    binary.write_bytes(BINARY)
    proc = run_cli("hierarchy", "--file", str(deep), cwd=tmp_path, timeout=120)
    assert proc.returncode == 2, proc.stderr
    assert "nested deeper than 64 levels" in one_line(proc.stderr)
    assert main(["hierarchy", "--file", str(binary)]) == 2
    assert "not UTF-8" in one_line(capsys.readouterr().err)


def test_cli_stats_binary_is_one_line(tmp_path, capsys):
    binary = tmp_path / "binary.json"
    binary.write_bytes(BINARY)
    code = main(["hierarchy", "--room", "bedroom", "--stats", str(binary)])
    err = capsys.readouterr().err
    assert code == 2 and "not UTF-8" in one_line(err)

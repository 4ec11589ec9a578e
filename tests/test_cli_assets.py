"""``pair2scene assets list`` and ``pair2scene assets sheet``."""

from __future__ import annotations

import json

import pytest
from PIL import Image

from clitools import run_cli
from pair2scene.categories import CATEGORIES, is_structure
from pair2scene.cli import main

ASSET_CATEGORIES = [c.name for c in CATEGORIES if not is_structure(c.name)]


def test_list_json_subprocess(tmp_path):
    proc = run_cli("assets", "list", "--json", cwd=tmp_path)
    assert proc.returncode == 0, proc.stderr
    doc = json.loads(proc.stdout)
    entries, counts = doc["assets"], doc["counts"]
    assert [e["category"] for e in entries] == ASSET_CATEGORIES
    assert counts["categories"] == len(entries)
    assert counts["procedural"] + counts["box_fallback"] == counts["categories"]
    assert counts["box_fallback"] == sum(e["box_fallback"] for e in entries)
    for e in entries:
        assert (e["module"] is None) == e["box_fallback"]
        assert e["variants"] >= 1 and len(e["typical_size"]) == 3
        assert e["size_source"] in {"ai2thor", "procthor", "hand"}


def test_list_table_and_subset(capsys):
    assert main(["assets", "list", "--categories", "bed,mug"]) == 0
    out = capsys.readouterr().out.splitlines()
    assert out[0].startswith("category")
    assert [line.split()[0] for line in out[2:4]] == ["bed", "mug"]
    assert out[-1].startswith("2 categories:")


def test_sheet_on_three_categories(tmp_path, capsys):
    out = tmp_path / "sub" / "sheet.png"
    assert main(["assets", "sheet", "--out", str(out), "--categories", "bed,mug,painting"]) == 0
    assert "3 categories" in capsys.readouterr().out
    with Image.open(out) as img:
        img.verify()
    with Image.open(out) as img:
        assert img.format == "PNG" and img.width > 300 and img.height > 150
    assert [p.name for p in out.parent.iterdir()] == ["sheet.png"]  # no temporary left


@pytest.mark.parametrize(
    "argv, expected",
    [
        (["assets", "sheet", "--categories", "nope"], "not an asset category: nope"),
        (["assets", "list", "--categories", "bed,floor"], "not an asset category: floor"),
        (["assets", "sheet", "--seed", "x"], "--seed"),
    ],
    ids=["unknown", "structure", "bad-seed"],
)
def test_bad_input_is_one_line_exit_2(argv, expected, tmp_path, capsys):
    assert main([*argv, "--out", str(tmp_path / "s.png")] if argv[1] == "sheet" else argv) == 2
    out, err = capsys.readouterr()
    lines = err.splitlines()
    assert len(lines) == 1, err
    assert lines[0].startswith("error: ") and expected in lines[0]
    assert not (tmp_path / "s.png").exists()


def test_bad_category_subprocess(tmp_path):
    proc = run_cli("assets", "sheet", "--out", "s.png", "--categories", "nope", cwd=tmp_path)
    assert proc.returncode == 2
    assert proc.stderr.splitlines() == [
        "error: not an asset category: nope (see 'pair2scene assets list')"
    ]
    assert proc.stdout == "" and not (tmp_path / "s.png").exists()

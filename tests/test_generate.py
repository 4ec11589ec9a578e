"""The main job: pair2scene generate and the Pair2Scene API (bundled model)."""

from __future__ import annotations

import json

import pytest

from clitools import run_cli

pytest.importorskip("torch")

from pair2scene import Pair2Scene  # noqa: E402
from pair2scene.errors import UserError  # noqa: E402
from pair2scene.generate import generate_scenes  # noqa: E402
from pair2scene.io.scene_json import read_scene  # noqa: E402


@pytest.fixture(scope="module")
def p2s():
    return Pair2Scene.from_pretrained()


def test_api_generates_a_seeded_scene(p2s):
    a = p2s.generate(room="bedroom", seed=3)
    b = p2s.generate(room="Bedroom", seed=3)
    assert a.scene.id == "bedroom_0003" and len(a.scene.objects) > 0
    assert [o.box.to_vector().tolist() for o in a.scene.objects] == [
        o.box.to_vector().tolist() for o in b.scene.objects
    ]
    ids = {o.id for o in a.scene.objects}
    for o in a.scene.objects:
        assert o.support == "floor" or o.support in ids
        assert o.functional_anchor is None or o.functional_anchor in ids
    assert a.stats["objects_placed"] == len(a.scene.objects)
    assert set(a.assets) == ids


def test_text_scene(p2s):
    g = p2s.generate(
        text="a bedroom with two nightstands and a lamp on each nightstand", llm="never"
    )
    cats = [o.category for o in g.scene.objects]
    assert g.scene.room.type == "bedroom" and "bed" in cats


def test_cli_writes_folders_summary_and_resumes(tmp_path):
    out = tmp_path / "out"
    proc = run_cli("generate", "--room", "bedroom", "--num", "2", "--seed", "7", "--out", str(out),
                   "--json")  # fmt: skip
    assert proc.returncode == 0, proc.stderr
    summary = json.loads(proc.stdout)
    assert [s["id"] for s in summary["scenes"]] == ["bedroom_0007", "bedroom_0008"]
    assert summary["totals"]["scenes"] == 2
    for sid in ("bedroom_0007", "bedroom_0008"):
        folder = out / sid
        assert sorted(p.name for p in folder.iterdir()) == ["bev.png", "scene.glb", "scene.json"]
        scene = read_scene(folder / "scene.json")
        assert scene.stats["objects_placed"] == len(scene.objects)
    before = (out / "bedroom_0007" / "scene.json").read_bytes()
    proc = run_cli("generate", "--room", "bedroom", "--num", "2", "--seed", "7", "--out", str(out))
    assert proc.returncode == 0 and (out / "bedroom_0007" / "scene.json").read_bytes() == before
    again = tmp_path / "again"
    proc = run_cli("generate", "--room", "bedroom", "--seed", "7", "--out", str(again))
    assert proc.returncode == 0
    assert (again / "bedroom_0007" / "scene.json").read_bytes() == before  # same seed, same file


def test_bad_requests_are_one_line_errors(tmp_path):
    for args, msg in [
        (["--room", "garage"], "unknown room type"),
        (["--room", "bedroom", "--text", "a bed"], "exactly one"),
        (["--room", "bedroom", "--num", "0"], "--num"),
        (["--room", "bedroom", "--model", str(tmp_path)], "config.json: missing"),
        (["--text", "xyzzy", "--llm", "never"], "no room type and no known object"),
    ]:
        proc = run_cli("generate", *args, "--out", str(tmp_path / "o"))
        assert proc.returncode == 2 and msg in proc.stderr, (args, proc.stderr)
        assert proc.stderr.count("\n") == 1 and "Traceback" not in proc.stderr
    (tmp_path / "other").mkdir()
    generate_scenes(tmp_path / "other", room="kitchen", progress=False)
    with pytest.raises(UserError, match="another request"):
        generate_scenes(tmp_path / "other", room="bedroom", progress=False)

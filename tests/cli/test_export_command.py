"""Scene folders with the simulator formats, and ``pair2scene export`` for scenes
written earlier."""

from __future__ import annotations

import importlib.util
import json

import pytest
from tests.clitools import run_cli
from tests.io.test_export import small_scene

from pair2scene.errors import UserError
from pair2scene.io.export import (
    ExportConfig,
    export_scene,
    stale_scene_folders,
    write_scene_folder,
)

HAS_USD = importlib.util.find_spec("pxr") is not None


def test_formats_are_checked_and_json_is_always_written():
    assert ExportConfig().format_list() == ("json", "glb", "png", "html")
    assert ExportConfig("mjcf").format_list() == ("json", "mjcf")
    with pytest.raises(UserError, match="unknown obj"):
        ExportConfig("glb,obj").format_list()
    with pytest.raises(UserError, match="--dynamic"):
        ExportConfig(dynamic="some").format_list()


def test_a_folder_with_every_format_and_its_leftovers_are_recognised(tmp_path):
    scene, assets = small_scene()
    formats = ("json", "mjcf", "urdf", *(("usd",) if HAS_USD else ()))
    folder = write_scene_folder(tmp_path / "s0", scene, assets, formats, "all")
    names = sorted(p.name for p in folder.iterdir())
    assert names == sorted(["scene.json", "mjcf", "urdf", *(["scene.usdc"] if HAS_USD else [])])
    assert (folder / "mjcf" / "scene.xml").is_file()
    assert (folder / "urdf" / "scene.urdf").is_file()
    # what a killed write leaves (a hidden copy of such a folder) is found as stale...
    left = tmp_path / ".s1.abc123"
    folder.rename(left)
    (left / ".urdf.xyz789").mkdir()
    assert stale_scene_folders(tmp_path) == [left]
    # ...but not a hidden folder holding anything else
    (left / "notes.txt").write_text("mine")
    assert stale_scene_folders(tmp_path) == []


def test_export_adds_formats_beside_scene_json(tmp_path):
    scene, assets = small_scene()
    folder = write_scene_folder(tmp_path / "s0", scene, assets, ("json",))
    before = (folder / "scene.json").read_bytes()
    export_scene(folder, ["mjcf", "html"])
    assert (folder / "mjcf" / "scene.xml").is_file() and (folder / "scene.html").is_file()
    assert (folder / "scene.json").read_bytes() == before


def test_export_command_on_an_output_folder_and_its_errors(tmp_path):
    scene, assets = small_scene()
    out = tmp_path / "out"
    for sid in ("a", "b"):
        write_scene_folder(out / sid, scene, assets, ("json", "png"))
    done = run_cli("export", str(out), "--formats", "mjcf,html")
    assert done.returncode == 0, done.stderr
    for sid in ("a", "b"):
        assert (out / sid / "mjcf" / "scene.xml").is_file()
    assert "a/scene.html" in (out / "index.html").read_text()
    bad = run_cli("export", str(out), "--formats", "fbx")
    assert bad.returncode == 2 and bad.stderr.count("\n") == 1 and "unknown fbx" in bad.stderr
    missing = run_cli("export", str(tmp_path / "nothing"))
    assert missing.returncode == 2 and "no such file" in missing.stderr
    empty = tmp_path / "empty"
    empty.mkdir()
    assert run_cli("export", str(empty)).returncode == 2
    broken = tmp_path / "broken"
    broken.mkdir()
    (broken / "scene.json").write_text(json.dumps({"format": "nope"}))
    done = run_cli("export", str(broken))
    assert done.returncode == 2 and done.stderr.count("\n") == 1

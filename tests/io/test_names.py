"""Scene ids as file and folder names."""

from __future__ import annotations

from pathlib import Path

import pytest

from pair2scene.evaluate import scene_files
from pair2scene.io.names import MAX_NAME, safe_name, scene_folder


@pytest.mark.parametrize("sid", ["bedroom_0003", "text_0000", "FloorPlan1.v2", "a-b"])
def test_safe_ids_are_kept(sid):
    assert safe_name(sid) == sid


@pytest.mark.parametrize(
    "sid", ["procthor/val/3/room|2", "..", ".", "", "-rf", "a b", "x" * 300, "c:\\d", "ü/ß"]
)
def test_other_ids_become_one_portable_component(sid):
    name = safe_name(sid)
    assert "/" not in name and "\\" not in name and name not in (".", "..", "")
    assert not name.startswith((".", "-")) and len(name) <= MAX_NAME + 9
    assert name.isascii() and Path(name).name == name
    assert safe_name(sid) == name  # stable


def test_ids_that_differ_only_in_unsafe_characters_stay_apart():
    assert safe_name("procthor/val/3") != safe_name("procthor_val_3")
    assert safe_name("a/b") != safe_name("a|b")


def test_a_source_id_names_one_folder(tmp_path):
    folder = scene_folder(tmp_path, "procthor/val/3/room|2")
    assert folder.parent == tmp_path
    assert folder.name.startswith("procthor_val_3_room_2-")


def test_evaluate_finds_nested_scenes_but_not_interrupted_writes(tmp_path):
    (tmp_path / "a").mkdir()
    (tmp_path / "a" / "scene.json").write_text("{}")
    (tmp_path / "procthor" / "val" / "3").mkdir(parents=True)  # an older writer's nesting
    (tmp_path / "procthor" / "val" / "3" / "scene.json").write_text("{}")
    (tmp_path / ".a.x1y2").mkdir()  # an interrupted write's temporary folder
    (tmp_path / ".a.x1y2" / "scene.json").write_text("{}")
    names = [p.relative_to(tmp_path).as_posix() for p in scene_files(tmp_path)]
    assert names == ["a/scene.json", "procthor/val/3/scene.json"]

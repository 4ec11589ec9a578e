"""Your own data, end to end: a folder of scene.json files -> curate -> train -> generate
with your statistics and model -> evaluate against your rooms (issue 20)."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from clitools import run_cli
from pair2scene.data.sources import load_source
from pair2scene.errors import UserError
from pair2scene.evaluate import load_scene_folder
from pair2scene.io.scene_json import read_scene

torch = pytest.importorskip("torch")


def _set_split(scene_json: Path, split: str | None) -> None:
    doc = json.loads(scene_json.read_text())
    doc["split"] = split
    scene_json.write_text(json.dumps(doc))


@pytest.fixture(scope="module")
def own_rooms(tmp_path_factory) -> Path:
    """Eight bedrooms in the scene.json format (written by generate: a stand-in for rooms
    of your own), two of them marked val."""
    folder = tmp_path_factory.mktemp("own") / "rooms"
    proc = run_cli("generate", "--room", "bedroom", "--num", "8", "--out", str(folder), "--json")
    assert proc.returncode == 0, proc.stderr
    for i in (0, 1):
        _set_split(folder / f"bedroom_000{i}" / "scene.json", "val")
    return folder


def test_a_scene_folder_is_a_source_with_the_files_splits(own_rooms):
    corpus = load_source(f"scenes:{own_rooms}")
    assert len(corpus.scenes) == 8 and corpus.source == f"scenes:{own_rooms}"
    splits = {s.id: s.split for s in corpus.scenes}
    assert splits["bedroom_0000"] == splits["bedroom_0001"] == "val"
    assert set(splits.values()) <= {"train", "val"}  # the others: by a hash of the id
    assert sum(corpus.report.mapped_labels.values()) == sum(len(s.objects) for s in corpus.scenes)
    val = load_source(f"scenes:{own_rooms}", split="val").scenes
    assert {s.id for s in val} == {i for i, s in splits.items() if s == "val"}
    again = load_source(f"scenes:{own_rooms}")
    assert [s.split for s in again.scenes] == [s.split for s in corpus.scenes]


def test_a_bad_scene_folder_is_one_line(own_rooms, tmp_path):
    with pytest.raises(UserError, match="no such folder"):
        load_source(f"scenes:{tmp_path / 'nope'}")
    with pytest.raises(UserError, match="needs a path"):
        load_source("scenes")
    twin = tmp_path / "twin"
    for name in ("a", "b"):  # two files, one scene id
        (twin / name).mkdir(parents=True)
        text = (own_rooms / "bedroom_0002" / "scene.json").read_text()
        (twin / name / "scene.json").write_text(text)
    with pytest.raises(UserError, match="'bedroom_0002' is also"):
        load_source(f"scenes:{twin}")
    proc = run_cli("data", "stats", f"scenes:{tmp_path / 'nope'}")
    assert proc.returncode == 2 and "no such folder" in proc.stderr
    assert "Traceback" not in proc.stderr


@pytest.mark.slow  # (CI runs the slow tests too: .ci/run)
def test_curate_train_generate_evaluate_on_your_own_rooms(own_rooms, tmp_path):
    from pair2scene.model.pointmae import PointMAEConfig, PointMAEEncoder
    from pair2scene.model.pretrain import save_encoder

    proc = run_cli("data", "stats", f"scenes:{own_rooms}")
    assert proc.returncode == 0, proc.stderr
    assert "rooms       8  bedroom 8" in proc.stdout
    pairs = tmp_path / "pairs"
    proc = run_cli("curate", "--source", f"scenes:{own_rooms}", "--out", str(pairs))
    assert proc.returncode == 0, proc.stderr
    encoder = tmp_path / "encoder"
    save_encoder(PointMAEEncoder(PointMAEConfig.tiny(), torch.Generator().manual_seed(0)), encoder)
    model = tmp_path / "model"
    proc = run_cli("train", "--data", str(pairs), "--out", str(model), "--preset", "tiny",
                   "--encoder", str(encoder), "--epochs", "1", "--json")  # fmt: skip
    assert proc.returncode == 0, proc.stderr
    out = tmp_path / "generated"
    stats = pairs / "stats.json"
    proc = run_cli("generate", "--room", "bedroom", "--num", "2", "--stats", str(stats),
                   "--model", str(model), "--out", str(out), "--json")  # fmt: skip
    assert proc.returncode == 0, proc.stderr
    assert json.loads(proc.stdout)["request"]["stats"] == str(stats)

    theirs = {o.category for s in load_scene_folder(own_rooms) for o in s.objects}
    generated = load_scene_folder(out)
    assert generated and all(s.objects for s in generated)
    assert {o.category for s in generated for o in s.objects} <= theirs
    report = tmp_path / "report.json"
    proc = run_cli("evaluate", "--scenes", str(out), "--reference", str(own_rooms),
                   "--out", str(report), "--no-simulate", "--no-images")  # fmt: skip
    assert proc.returncode == 0, proc.stderr
    assert json.loads(report.read_text())["n_reference"] == 8

    # a room type your data does not have is one line, naming those it has
    proc = run_cli("generate", "--room", "kitchen", "--stats", str(stats), "--out",
                   str(tmp_path / "k"))  # fmt: skip
    assert proc.returncode == 2 and "the statistics know: bedroom" in proc.stderr
    proc = run_cli("generate", "--room", "bedroom", "--stats", str(tmp_path / "no.json"),
                   "--out", str(tmp_path / "n"))  # fmt: skip
    assert proc.returncode == 2 and "no such file" in proc.stderr
    assert read_scene(out / "bedroom_0000" / "scene.json").room.type == "bedroom"

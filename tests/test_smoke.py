"""The whole method end to end on tiny data, on CPU, in well under a minute:
curate the committed ProcTHOR houses -> train the tiny model a few steps ->
generate scenes with that checkpoint -> evaluate them. Each step is the library
function its CLI command calls, so a break anywhere between them shows up here."""

from __future__ import annotations

import json
import math

import pytest

torch = pytest.importorskip("torch")

from pair2scene.curation.dataset import load_pairs  # noqa: E402
from pair2scene.curation.pipeline import CurateConfig, curate  # noqa: E402
from pair2scene.evaluate import HEADLINE, evaluate  # noqa: E402
from pair2scene.generate import generate_scenes  # noqa: E402
from pair2scene.io.scene_json import read_scene  # noqa: E402
from pair2scene.model.checkpoint import CONFIG_FILE, WEIGHTS_FILE  # noqa: E402
from pair2scene.model.pointmae import PointMAEConfig, PointMAEEncoder  # noqa: E402
from pair2scene.model.pretrain import save_encoder  # noqa: E402
from pair2scene.model.train import TrainConfig, train  # noqa: E402

# Figures the evaluation must produce without images and simulation (the slow parts):
# FID/KID/SCA need rendered top views, stability needs MuJoCo runs.
PHYSICAL = ("collision_rate", "floating_rate", "acceptance_rate", "objects_per_scene")


def test_curate_train_generate_evaluate(fixtures, tmp_path):
    houses = fixtures / "procthor"  # 3 train living rooms, 4 val kitchens

    # curate: support, physics and the offline functional table, as `pair2scene curate`
    pairs = tmp_path / "pairs"
    report = curate(
        CurateConfig(sources=(f"procthor:{houses}",), out=pairs, workers=1), progress=False
    )
    assert [s.rooms for s in report.sources] == [7]
    data = load_pairs(pairs)
    assert len(data) == report.tuples > 50
    assert (pairs / "stats.json").is_file()

    # train: the tiny preset for a few steps on a random-weight encoder (pre-training
    # is not what this checks; its interface is)
    encoder = tmp_path / "encoder"
    save_encoder(PointMAEEncoder(PointMAEConfig.tiny(), torch.Generator().manual_seed(0)), encoder)
    ckpt = tmp_path / "model"
    config = TrainConfig(preset="tiny", encoder=str(encoder), epochs=1, max_steps=4)
    result = train(config, pairs, ckpt, progress=False)
    assert (ckpt / WEIGHTS_FILE).is_file() and (ckpt / CONFIG_FILE).is_file()
    assert all(math.isfinite(h["val_nll"]) for h in result.history)

    # generate with that checkpoint, as `pair2scene generate --model CKPT`
    scenes = tmp_path / "scenes"
    summary = generate_scenes(
        scenes, room="living_room", num=2, model=str(ckpt), llm="never", progress=False
    )
    assert list(summary.scenes) == ["living_room_0000", "living_room_0001"]
    for sid in summary.scenes:
        scene = read_scene(scenes / sid / "scene.json")  # validates the contract
        assert scene.room.type == "living_room"
        assert len(scene.objects) > 0

    # evaluate against the fixture's real living rooms, without images and simulation
    out = tmp_path / "report.json"
    doc = evaluate(
        scenes, [f"procthor:{houses}"], out, simulate=False, images=False, progress=False
    )
    assert json.loads(out.read_text()) == doc
    assert doc["n_generated"] == 2 and doc["n_reference"] >= 3
    assert set(HEADLINE) <= set(doc)
    for key in (*PHYSICAL, "category_kl", "pose_mmd"):
        assert doc[key] is not None and math.isfinite(doc[key]), key
    assert doc["collision_rate"] == 0.0
    assert doc["objects_per_scene"] > 0

"""Point-MAE pre-training: the asset clouds, the schedule, the saved files."""

from __future__ import annotations

import dataclasses
import json

import numpy as np
import pytest

torch = pytest.importorskip("torch")
pytest.importorskip("safetensors")

from pair2scene.categories import CATEGORIES, is_structure  # noqa: E402
from pair2scene.errors import UserError  # noqa: E402
from pair2scene.model.pointmae import PointMAEConfig, PointMAEEncoder  # noqa: E402
from pair2scene.model.pretrain import (  # noqa: E402
    CONFIG_FILE,
    ENCODER_FILE,
    PretrainConfig,
    augment,
    build_clouds,
    learning_rate,
    load_encoder,
    pretrain,
    pretrain_categories,
    save_encoder,
)

TINY = PointMAEConfig.tiny()


def test_default_categories_are_every_non_structure_category():
    cats = pretrain_categories()
    assert cats == [c.name for c in CATEGORIES if not is_structure(c.name)]
    assert "chair" in cats and "wall" not in cats and "floor" not in cats
    with pytest.raises(UserError, match="no procedural generator"):
        pretrain_categories(["chair", "wall"])


def test_build_clouds_normalises_by_the_box_and_splits_by_seed():
    train = build_clouds(["chair", "mug"], 0, 3, 256, 0.3, seed=0)
    assert train.points.shape == (6, 256, 3) and train.points.dtype == np.float32
    assert train.categories == ("chair",) * 3 + ("mug",) * 3
    assert np.linalg.norm(train.points, axis=-1).max() <= 1 + 1e-5  # inside the unit ball
    assert 0.01 < train.half_diagonals[3] < 0.2 < 0.3 < train.half_diagonals[0] < 1.0  # mug, chair
    again = build_clouds(["chair", "mug"], 0, 3, 256, 0.3, seed=0)
    assert np.array_equal(train.points, again.points)
    val = build_clouds(["chair", "mug"], 3, 1, 256, 0.3, seed=0)
    assert not any(np.allclose(val.points[0], p) for p in train.points[:3])
    # adding a category leaves the others' assets unchanged
    more = build_clouds(["bed", "chair", "mug"], 0, 3, 256, 0.3, seed=0)
    assert np.array_equal(more.points[3:], train.points)


def test_augment_shuffles_points_and_mirrors_x():
    g = torch.Generator().manual_seed(0)
    batch = torch.rand(8, 50, 3, generator=g)
    out = augment(batch, torch.Generator().manual_seed(1), mirror=False)
    for b in range(8):  # the same set of points, another order
        assert torch.equal(out[b][out[b][:, 0].argsort()], batch[b][batch[b][:, 0].argsort()])
    assert not torch.equal(out, batch)
    mirrored = augment(batch, torch.Generator().manual_seed(1), mirror=True)
    flipped = (mirrored[:, :, 0] < 0).all(dim=1)  # batch x is in [0, 1)
    assert 0 < int(flipped.sum()) < 8
    torch.testing.assert_close(mirrored[:, :, 1:], out[:, :, 1:])
    torch.testing.assert_close(mirrored[:, :, 0].abs(), out[:, :, 0])


def test_learning_rate_warms_up_then_decays_to_zero():
    cfg = PretrainConfig(model=TINY, steps=110, lr=1e-3, warmup_steps=10)
    assert learning_rate(0, cfg) == pytest.approx(1e-4)
    assert learning_rate(9, cfg) == pytest.approx(1e-3)
    assert learning_rate(10, cfg) == pytest.approx(1e-3)
    assert learning_rate(60, cfg) == pytest.approx(0.5e-3)
    assert learning_rate(110, cfg) == pytest.approx(0.0, abs=1e-12)


def test_save_and_load_encoder_round_trip(tmp_path):
    enc = PointMAEEncoder(TINY, torch.Generator().manual_seed(0)).eval()
    save_encoder(enc, tmp_path, pretrain={"note": "test"})
    doc = json.loads((tmp_path / CONFIG_FILE).read_text())
    assert doc["format"] == "pair2scene.pointmae" and doc["model"]["width"] == TINY.width
    loaded = load_encoder(tmp_path)
    assert loaded.config == TINY and not loaded.training
    clouds = torch.rand(2, TINY.n_points, 3, generator=torch.Generator().manual_seed(1))
    with torch.no_grad():
        assert torch.equal(loaded(clouds)[0], enc(clouds)[0])


def test_load_encoder_errors_are_user_errors(tmp_path):
    with pytest.raises(UserError, match="missing"):
        load_encoder(tmp_path)
    (tmp_path / CONFIG_FILE).write_text('{"format": "something else"}')
    with pytest.raises(UserError, match="format"):
        load_encoder(tmp_path)
    save_encoder(PointMAEEncoder(TINY), tmp_path)
    (tmp_path / ENCODER_FILE).write_bytes(b"not safetensors")
    with pytest.raises(UserError, match="safetensors"):
        load_encoder(tmp_path)
    save_encoder(PointMAEEncoder(dataclasses.replace(TINY, width=16, heads=2)), tmp_path / "b")
    doc = json.loads((tmp_path / "b" / CONFIG_FILE).read_text())
    doc["model"]["width"] = 32
    (tmp_path / "b" / CONFIG_FILE).write_text(json.dumps(doc))
    with pytest.raises(UserError, match="do not fit"):
        load_encoder(tmp_path / "b")


def test_tiny_pretrain_writes_reproducible_weights_and_learns(tmp_path):
    cfg = dataclasses.replace(PretrainConfig.tiny(), steps=12, eval_every=6)
    a = pretrain(cfg, tmp_path / "a", progress=False)
    b = pretrain(cfg, tmp_path / "b", progress=False)
    assert a.encoder_path.read_bytes() == b.encoder_path.read_bytes()
    assert a.train_losses == b.train_losses and len(a.train_losses) == 12
    assert [s for s, _ in a.val_losses] == [0, 6, 12]
    assert a.val_losses[-1][1] < a.val_losses[0][1]
    assert (a.n_train, a.n_val) == (9, 3)
    doc = json.loads(a.config_path.read_text())
    assert doc["pretrain"]["config"]["steps"] == 12
    assert doc["pretrain"]["categories"] == ["chair", "mug", "bed"]
    assert "half-diagonal" in doc["normalisation"]
    tokens, centers = load_encoder(tmp_path / "a")(torch.zeros(1, 64, 3) + torch.rand(1, 64, 3))
    assert tokens.shape == (1, TINY.n_groups, TINY.width) and centers.shape == (1, 16, 3)


def test_interrupted_pretraining_resumes_to_the_same_weights(tmp_path, monkeypatch):
    import pair2scene.model.pretrain as pretrain_mod

    cfg = dataclasses.replace(PretrainConfig.tiny(), steps=12, eval_every=4)
    full = pretrain(cfg, tmp_path / "full", progress=False)
    real_save = pretrain_mod.save_training_state
    calls = []

    def save_then_stop(*args, **kwargs):
        real_save(*args, **kwargs)
        calls.append(1)
        if len(calls) == 1:
            raise KeyboardInterrupt

    monkeypatch.setattr(pretrain_mod, "save_training_state", save_then_stop)
    with pytest.raises(KeyboardInterrupt):
        pretrain(cfg, tmp_path / "cut", progress=False)
    assert json.loads((tmp_path / "cut" / "pretrain_state.json").read_text())["step"] == 4
    resumed = pretrain(cfg, tmp_path / "cut", progress=False)
    assert resumed.encoder_path.read_bytes() == full.encoder_path.read_bytes()
    assert resumed.train_losses == full.train_losses and resumed.val_losses == full.val_losses
    assert not (tmp_path / "cut" / "pretrain_state.json").exists()
    other = dataclasses.replace(cfg, steps=8)
    calls.clear()
    with pytest.raises(KeyboardInterrupt):
        pretrain(other, tmp_path / "other", progress=False)
    with pytest.raises(UserError, match="another pre-training run"):
        pretrain(cfg, tmp_path / "other", progress=False)

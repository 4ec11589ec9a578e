"""Training, checkpoints, resume, from_pretrained and sampling, on the tiny preset (seconds)."""

from __future__ import annotations

import json

import numpy as np
import pytest

torch = pytest.importorskip("torch")

from clitools import run_cli  # noqa: E402
from pair2scene.curation.dataset import load_pairs  # noqa: E402
from pair2scene.errors import UserError  # noqa: E402
from pair2scene.model import from_pretrained  # noqa: E402
from pair2scene.model import train as train_mod  # noqa: E402
from pair2scene.model.api import Anchor, PlacementQuery  # noqa: E402
from pair2scene.model.checkpoint import CONFIG_FILE, WEIGHTS_FILE, load_checkpoint  # noqa: E402
from pair2scene.model.pointmae import PointMAEConfig, PointMAEEncoder  # noqa: E402
from pair2scene.model.pretrain import save_encoder  # noqa: E402
from pair2scene.model.scoring import load_model, score, select_rows  # noqa: E402
from pair2scene.model.train import TrainConfig, train  # noqa: E402
from pair2scene.scene.geometry import OrientedBox  # noqa: E402
from synthetic_pairs import write_synthetic_pairs  # noqa: E402


@pytest.fixture(scope="module")
def pairs_dir(tmp_path_factory):
    return write_synthetic_pairs(tmp_path_factory.mktemp("pairs"))


@pytest.fixture(scope="module")
def tiny_encoder(tmp_path_factory):
    """A tiny-preset encoder (random weights: training only needs its interface)."""
    folder = tmp_path_factory.mktemp("encoder")
    save_encoder(PointMAEEncoder(PointMAEConfig.tiny(), torch.Generator().manual_seed(0)), folder)
    return folder


@pytest.fixture(scope="module")
def trained(tmp_path_factory, pairs_dir, tiny_encoder):
    out = tmp_path_factory.mktemp("run")
    cfg = TrainConfig(preset="tiny", encoder=str(tiny_encoder), epochs=3)
    return train(cfg, pairs_dir, out, progress=False)


def test_tiny_training_learns_and_writes_a_checkpoint(trained):
    out = trained.out_dir
    assert (out / WEIGHTS_FILE).is_file() and (out / CONFIG_FILE).is_file()
    assert [h["epoch"] for h in trained.history] == [1, 2, 3]
    vals = [h["val_nll"] for h in trained.history]
    assert all(np.isfinite(vals))
    assert vals[-1] < vals[0]  # it learns something in 3 tiny epochs
    doc = json.loads((out / CONFIG_FILE).read_text())
    assert doc["variant"] == "full" and doc["preset"] == "tiny"
    assert doc["training"]["best_epoch"] == trained.best_epoch
    assert doc["training"]["val_nll"] == pytest.approx(trained.best_val_nll)


def test_the_checkpoint_holds_the_pair_table_of_the_train_tuples_only(trained, pairs_dir):
    from safetensors.numpy import load_file

    from pair2scene.curation.dataset import CATEGORY_VOCAB
    from pair2scene.model.features import dataset_features
    from pair2scene.model.pair_prior import pair_centre_table
    from pair2scene.model.train import _split_rows, _subset

    doc = json.loads((trained.out_dir / CONFIG_FILE).read_text())
    assert doc["layout"]["pair_prior"] is True  # the default
    data = load_pairs(pairs_dir)
    arrays = dataset_features(data, "full", anchor_frames=True).arrays
    train_rows = _subset(arrays, _split_rows(data, "train"))
    want = pair_centre_table(
        train_rows.categories, train_rows.frames, train_rows.target, len(CATEGORY_VOCAB)
    )
    got = load_file(str(trained.out_dir / WEIGHTS_FILE))["pair_centre"]
    assert want.any()  # the synthetic corpus has pairs with enough tuples
    np.testing.assert_array_equal(got, want)
    everything = pair_centre_table(arrays.categories, arrays.frames, arrays.target, len(want))
    assert not np.array_equal(everything, want)  # the val tuples would move it
    assert doc["layout"]["pair_turns"] is True  # the default, as the bundled model
    assert "pair_turn" in load_file(str(trained.out_dir / WEIGHTS_FILE))


def test_no_pair_turns_writes_no_yaw_turn_table(tmp_path, pairs_dir, tiny_encoder):
    from safetensors.numpy import load_file

    cfg = TrainConfig(preset="tiny", encoder=str(tiny_encoder), max_steps=1, pair_turns=False)
    run = train(cfg, pairs_dir, tmp_path, progress=False)
    assert json.loads((run.out_dir / CONFIG_FILE).read_text())["layout"]["pair_turns"] is False
    assert "pair_turn" not in load_file(str(run.out_dir / WEIGHTS_FILE))
    assert from_pretrained(run.out_dir).net._pair_turn is None


def test_pair_turns_without_yaw_turns_is_a_user_error():
    with pytest.raises(UserError, match="--pair-turns needs yaw turns"):
        TrainConfig(preset="tiny", pair_turns=True, yaw_modes=1).resolved_preset()


def test_pair_turns_by_default_wherever_there_are_turns_to_share():
    assert TrainConfig(preset="tiny").resolved_preset().layout.pair_turns
    assert TrainConfig(preset="tiny", yaw_modes=2).resolved_preset().layout.pair_turns
    one = TrainConfig(preset="tiny", yaw_modes=1).resolved_preset().layout  # the paper's head
    assert not one.pair_turns and one.mixture.yaw_modes == 1
    assert not TrainConfig(preset="tiny", pair_turns=False).resolved_preset().layout.pair_turns


def test_pair_modes_without_the_pair_table_is_a_user_error():
    with pytest.raises(UserError, match="--pair-modes refines the pair table"):
        TrainConfig(preset="tiny", pair_modes=True, pair_prior=False).resolved_preset()


def _turn_table(rows, layout):
    from pair2scene.model.pair_prior import pair_turn_table

    return pair_turn_table(
        rows.categories, rows.frames, rows.target[:, 6:8], layout["n_categories"],
        layout["mixture"]["yaw_modes"],
    )  # fmt: skip


def _mode_table(rows, layout):
    from pair2scene.model.pair_prior import pair_mode_table

    return pair_mode_table(
        rows.categories, rows.frames, rows.target, layout["n_categories"],
        layout["mixture"]["num_components"],
    )  # fmt: skip


@pytest.mark.parametrize(
    ("option", "tensor", "table"),
    [("pair_turns", "pair_turn", _turn_table), ("pair_modes", "pair_mode", _mode_table)],
    ids=["turns", "modes"],
)
def test_a_pair_table_option_puts_the_train_tuples_table_in_the_checkpoint(
    tmp_path, pairs_dir, tiny_encoder, option, tensor, table
):
    from safetensors.numpy import load_file

    from pair2scene.model.features import dataset_features
    from pair2scene.model.train import _split_rows, _subset

    cfg = TrainConfig(preset="tiny", encoder=str(tiny_encoder), max_steps=1, **{option: True})
    run = train(cfg, pairs_dir, tmp_path, progress=False)
    doc = json.loads((run.out_dir / CONFIG_FILE).read_text())
    assert doc["layout"][option] is True
    data = load_pairs(pairs_dir)
    arrays = dataset_features(data, "full", anchor_frames=True).arrays
    want = table(_subset(arrays, _split_rows(data, "train")), doc["layout"])
    assert want.any()  # the synthetic corpus has pairs with enough tuples
    np.testing.assert_array_equal(load_file(str(run.out_dir / WEIGHTS_FILE))[tensor], want)
    model = from_pretrained(run.out_dir)  # and generation reads it
    assert getattr(model.net, f"_{tensor}") is not None


def test_score_of_the_checkpoint_is_the_training_val_nll(trained, pairs_dir):
    model = from_pretrained(trained.out_dir)
    result = score(model, pairs_dir, "val")
    assert result.n == 24
    assert result.nll == pytest.approx(trained.best_val_nll, rel=1e-5, abs=1e-4)
    assert score(load_model(str(trained.out_dir)), pairs_dir).nll == pytest.approx(result.nll)
    # the placement given the size: log p(x) - log p(size), from the same forward pass
    val = load_pairs(pairs_dir)
    val = select_rows(val, val.split == "val")
    lp, lps = model.log_prob(val), model.log_prob_size(val)
    assert result.nll_given_size == pytest.approx(float(np.mean(lps - lp)), rel=1e-9)
    assert np.isfinite(lps).all()
    # and by relation kind: each kind's tuples alone, weighted back to the whole
    kinds = np.array([val.kinds[k] for k in val.kind.tolist()])
    per_kind = result.given_size_per_kind
    assert set(per_kind) == set(kinds.tolist()) and len(per_kind) > 1
    for kind, group in per_kind.items():
        assert group.n == int((kinds == kind).sum())
        assert group.nll == pytest.approx(float(np.mean((lps - lp)[kinds == kind])), rel=1e-9)
    total = sum(g.nll * g.n for g in per_kind.values()) / result.n
    assert total == pytest.approx(result.nll_given_size, rel=1e-9)
    assert result.to_dict()["given_size_per_kind"].keys() == per_kind.keys()


def test_same_seed_same_weights(trained, pairs_dir, tiny_encoder, tmp_path):
    cfg = TrainConfig(preset="tiny", encoder=str(tiny_encoder), epochs=3)
    train(cfg, pairs_dir, tmp_path, progress=False)
    a = (trained.out_dir / WEIGHTS_FILE).read_bytes()
    assert (tmp_path / WEIGHTS_FILE).read_bytes() == a


def test_resume_after_interruption_gives_the_same_model(
    trained, pairs_dir, tiny_encoder, tmp_path, monkeypatch
):
    save_state = train_mod._save_state
    calls = []

    def interrupt_after_first_epoch(*args, **kwargs):
        save_state(*args, **kwargs)
        calls.append(1)
        if len(calls) == 1:
            raise KeyboardInterrupt

    monkeypatch.setattr(train_mod, "_save_state", interrupt_after_first_epoch)
    cfg = TrainConfig(preset="tiny", encoder=str(tiny_encoder), epochs=3)
    with pytest.raises(KeyboardInterrupt):
        train(cfg, pairs_dir, tmp_path, progress=False)
    assert json.loads((tmp_path / "train_state.json").read_text())["epoch"] == 0
    result = train(cfg, pairs_dir, tmp_path, progress=False)
    assert [h["epoch"] for h in result.history] == [1, 2, 3]
    assert (tmp_path / WEIGHTS_FILE).read_bytes() == (trained.out_dir / WEIGHTS_FILE).read_bytes()


def test_another_run_in_the_same_folder_is_refused(trained, pairs_dir, tiny_encoder):
    cfg = TrainConfig(preset="tiny", encoder=str(tiny_encoder), epochs=3, seed=5)
    with pytest.raises(UserError, match="another training run"):
        train(cfg, pairs_dir, trained.out_dir, progress=False)


@pytest.mark.parametrize("variant", ["class-only", "global", "no-pretrain"])
def test_every_variant_trains_and_scores(variant, pairs_dir, tiny_encoder, tmp_path):
    cfg = TrainConfig(preset="tiny", variant=variant, encoder=str(tiny_encoder), epochs=1)
    result = train(cfg, pairs_dir, tmp_path, progress=False)
    model = from_pretrained(tmp_path)
    assert model.variant.value == variant
    assert score(model, pairs_dir).nll == pytest.approx(result.best_val_nll, rel=1e-5, abs=1e-4)


def test_encoder_of_another_preset_is_a_user_error(pairs_dir, tmp_path, tiny_encoder):
    cfg = TrainConfig(preset="cpu", encoder=str(tiny_encoder), epochs=1)
    with pytest.raises(UserError, match="not the 'cpu' preset's"):
        train(cfg, pairs_dir, tmp_path, progress=False)
    with pytest.raises(UserError, match="unknown variant"):
        train(TrainConfig(preset="tiny", variant="nope"), pairs_dir, tmp_path, progress=False)
    with pytest.raises(UserError, match="unknown preset"):
        train(TrainConfig(preset="huge"), pairs_dir, tmp_path, progress=False)


# -- checkpoints ------------------------------------------------------------------------


def _copy(src, dst):
    dst.mkdir(exist_ok=True)
    for name in (CONFIG_FILE, WEIGHTS_FILE):
        (dst / name).write_bytes((src / name).read_bytes())
    return dst


def test_corrupt_or_truncated_checkpoints_are_one_line_errors(trained, tmp_path):
    good = trained.out_dir
    weights = (good / WEIGHTS_FILE).read_bytes()

    truncated = _copy(good, tmp_path / "truncated")
    (truncated / WEIGHTS_FILE).write_bytes(weights[: len(weights) // 2])
    with pytest.raises(UserError, match="not a readable safetensors file"):
        load_checkpoint(truncated)

    garbage = _copy(good, tmp_path / "garbage")
    (garbage / WEIGHTS_FILE).write_bytes(b"\x00" * 64)
    with pytest.raises(UserError, match="not a readable safetensors file"):
        load_checkpoint(garbage)

    missing = _copy(good, tmp_path / "missing")
    (missing / WEIGHTS_FILE).unlink()
    with pytest.raises(UserError, match="missing"):
        load_checkpoint(missing)

    bad_json = _copy(good, tmp_path / "bad_json")
    (bad_json / CONFIG_FILE).write_text("{not json")
    with pytest.raises(UserError, match="not readable JSON"):
        load_checkpoint(bad_json)

    other = _copy(good, tmp_path / "other")
    doc = json.loads((other / CONFIG_FILE).read_text())
    (other / CONFIG_FILE).write_text(json.dumps({**doc, "format": "something.else"}))
    with pytest.raises(UserError, match="format is not"):
        load_checkpoint(other)

    resized = _copy(good, tmp_path / "resized")
    doc["layout"]["width"] = 64
    (resized / CONFIG_FILE).write_text(json.dumps(doc))
    with pytest.raises(UserError, match="do not fit the config"):
        load_checkpoint(resized)

    broken = _copy(good, tmp_path / "broken")
    doc = json.loads((good / CONFIG_FILE).read_text())
    del doc["layout"]["mixture"]
    (broken / CONFIG_FILE).write_text(json.dumps(doc))
    with pytest.raises(UserError, match="bad model config"):
        load_checkpoint(broken)


def test_cli_reports_a_truncated_checkpoint_in_one_line(trained, pairs_dir, tmp_path):
    bad = _copy(trained.out_dir, tmp_path / "bad")
    w = (bad / WEIGHTS_FILE).read_bytes()
    (bad / WEIGHTS_FILE).write_bytes(w[:100])
    proc = run_cli("score", "--model", str(bad), "--data", str(pairs_dir))
    assert proc.returncode == 2
    assert proc.stderr.startswith("error: ") and proc.stderr.count("\n") == 1
    assert "Traceback" not in proc.stderr


@pytest.mark.slow  # (CI runs the slow tests too: .ci/run)
def test_cli_train_then_score(pairs_dir, tiny_encoder, tmp_path):
    out = tmp_path / "run"
    args = ["--data", str(pairs_dir), "--out", str(out), "--preset", "tiny"]
    proc = run_cli("train", *args, "--encoder", str(tiny_encoder), "--epochs", "1", "--json")
    assert proc.returncode == 0, proc.stderr
    trained = json.loads(proc.stdout)
    proc = run_cli("score", "--model", str(out), "--data", str(pairs_dir), "--json")
    assert proc.returncode == 0, proc.stderr
    assert json.loads(proc.stdout)["nll"] == pytest.approx(trained["val_nll"], rel=1e-5)
    proc = run_cli("train", *args, "--variant", "sideways")
    assert proc.returncode == 2 and "unknown variant" in proc.stderr


def test_cli_pretrain_tiny(tmp_path):
    proc = run_cli("pretrain", "--preset", "tiny", "--steps", "2", "--out", str(tmp_path), "--json")
    assert proc.returncode == 0, proc.stderr
    assert (tmp_path / "encoder.safetensors").is_file() and (tmp_path / "pointmae.json").is_file()
    assert json.loads(proc.stdout)["steps"] == 2


# -- sampling ---------------------------------------------------------------------------


def _query(model_dir, pairs_dir):
    data = load_pairs(pairs_dir)
    desk = OrientedBox.from_yaw([2.0, 2.0, 0.375], [1.2, 0.6, 0.75], np.pi / 2)
    room = OrientedBox.from_yaw([2.5, 2.0, 1.25], [5.0, 4.0, 2.5])
    assert len(data) > 0
    return PlacementQuery("mug", [0.1, 0.1, 0.1], Anchor("desk", desk), room=room)


def test_sampling_is_seeded_and_keeps_the_asset_size(trained, pairs_dir):
    model = from_pretrained(trained.out_dir)
    q = _query(trained.out_dir, pairs_dir)
    a = model.sample(q, n=256, temperature=0.8, generator=np.random.default_rng(3))
    b = model.sample(q, n=256, temperature=0.8, generator=np.random.default_rng(3))
    assert a.shape == (256, 12) and np.array_equal(a, b)
    np.testing.assert_allclose(a[:, 3:6], 0.1, rtol=1e-5)
    rot = np.stack([a[:, 6:9], a[:, 9:12]], -1)  # columns orthonormal
    gram = np.einsum("nij,nik->njk", rot, rot)
    np.testing.assert_allclose(gram, np.broadcast_to(np.eye(2), gram.shape), atol=1e-6)
    free = model.sample(q, n=64, keep_size=False, generator=np.random.default_rng(3))
    assert not np.allclose(free[:, 3:6], 0.1)


def test_sampling_with_functional_anchor_and_floor(trained):
    model = from_pretrained(trained.out_dir)
    room = OrientedBox.from_yaw([2.5, 2.0, 1.25], [5.0, 4.0, 2.5])
    desk = OrientedBox.from_yaw([2.0, 2.0, 0.375], [1.2, 0.6, 0.75])
    q = PlacementQuery(
        "chair", [0.5, 0.5, 0.9], Anchor.floor(room), functional=Anchor("desk", desk)
    )
    params, factors = model.distribution([q, q])
    assert params.loc.shape == (2, 4 * 4, 12) and factors.shape == (2, 3)  # K x yaw turns
    boxes = model.sample(q, n=8, generator=np.random.default_rng(0))
    assert np.isfinite(boxes).all()


def test_the_numpy_distribution_is_the_torch_networks(trained):
    # Placement draws from numpy twins of the weights (no torch at generation time): the
    # mixtures they give are the torch predictor's on the same inputs, to float32 rounding.
    from pair2scene.model.layout import LayoutBatch

    model = from_pretrained(trained.out_dir)
    room = OrientedBox.from_yaw([2.5, 2.0, 1.25], [5.0, 4.0, 2.5])
    desk = OrientedBox.from_yaw([2.0, 2.0, 0.375], [1.2, 0.6, 0.75], 0.3)
    queries = [
        PlacementQuery(
            "chair", [0.5, 0.5, 0.9], Anchor.floor(room), functional=Anchor("desk", desk)
        ),
        PlacementQuery("mug", [0.1, 0.1, 0.1], Anchor("desk", desk)),
    ]
    params, _ = model.distribution(queries)
    inputs, _ = model._query_batch(queries)
    batch = LayoutBatch(**{k: torch.from_numpy(v) for k, v in inputs.items()})
    with torch.no_grad():
        want, _ = model.predictor(batch)
    for got, ref in zip(params, want, strict=True):
        assert np.allclose(got, ref.numpy(), rtol=1e-4, atol=1e-4)


# -- the bundled default ----------------------------------------------------------------


def test_bundled_default_model_loads_scores_and_samples(pairs_dir):
    from pair2scene.model.checkpoint import DEFAULT_DIR, DEFAULT_ENCODER_DIR

    size = sum(p.stat().st_size for p in DEFAULT_DIR.rglob("*") if p.is_file())
    assert size <= 25 * 2**20
    model = from_pretrained()
    assert model.variant.value == "full" and model.checkpoint.preset == "cpu"
    assert model.checkpoint.meta["val_nll"] < -30  # what docs/model.md reports
    # the bundled encoder is the one inside the model
    from pair2scene.model.pretrain import load_encoder

    enc = load_encoder(DEFAULT_ENCODER_DIR).state_dict()
    inside = model.encoder.state_dict()
    assert all(torch.equal(enc[k], inside[k]) for k in enc)
    result = score(model, pairs_dir, "val")
    assert np.isfinite(result.nll) and result.nll_given_size is not None
    room = OrientedBox.from_yaw([2.5, 2.0, 1.25], [5.0, 4.0, 2.5])
    q = PlacementQuery("bed", [1.6, 2.1, 0.6], Anchor.floor(room))
    boxes = model.sample(q, n=64, temperature=0.7, generator=np.random.default_rng(0))
    inside_room = (np.abs(boxes[:, :2] - [2.5, 2.0]) < [2.5, 2.0]).all(1)
    assert inside_room.mean() > 0.8  # a trained model puts beds in the room
    np.testing.assert_allclose(boxes[:, 2], 0.3, atol=0.05)  # resting on the floor


def test_a_region_confines_the_draws_to_it_exactly():
    """``PlacementQuery.region``: every candidate's centre over it, the reported mass the
    share of unconfined candidates over it, and the confined candidates distributed as
    the unconfined ones that fall over it (what rejection would keep)."""
    from dataclasses import replace

    from scipy import stats

    model = from_pretrained()
    room = OrientedBox.from_yaw([2.5, 2.0, 1.25], [5.0, 4.0, 2.5])
    region = OrientedBox.from_yaw([2.5, 2.0, 1.25], [4.0, 3.0, 2.5])
    free_q = PlacementQuery("dresser", [1.2, 0.5, 0.9], Anchor.floor(room))
    q = replace(free_q, region=region)
    free = model.sample(free_q, n=20_000, temperature=0.8, generator=np.random.default_rng(0))
    over = (np.abs(free[:, :2] - [2.5, 2.0]) <= [2.0, 1.5]).all(1)
    boxes, mass = model.draw(q, n=4000, temperature=0.8, generator=np.random.default_rng(1))
    assert (np.abs(boxes[:, :2] - [2.5, 2.0]) <= [2.0 + 1e-9, 1.5 + 1e-9]).all()
    assert 0.3 < over.mean() < 0.995
    assert mass == pytest.approx(
        over.mean(), abs=4 * np.sqrt(over.mean() * (1 - over.mean()) / len(free)) + 1e-3
    )
    for j in range(2):
        assert stats.ks_2samp(boxes[:, j], free[over, j]).pvalue > 1e-3

"""Scoring: the contract (density of the stored vector), score(), load_model(), the CLI."""

from __future__ import annotations

import json

import numpy as np
import pytest
from scipy import stats

from pair2scene.cli import app, main
from pair2scene.cli.model import score_command
from pair2scene.curation.dataset import PairsDataset, load_pairs
from pair2scene.errors import UserError
from pair2scene.model.baseline import GaussianBaseline, GaussianConfig
from pair2scene.model.scoring import (
    Scorer,
    load_model,
    log_prob_from_log_size,
    score,
    select_rows,
    to_log_size,
)
from synthetic_pairs import write_synthetic_pairs


@pytest.fixture(scope="module")
def pairs_dir(tmp_path_factory):
    """A 3D-Pairs folder written by the real writer: 24 scenes, 18 train and 6 val."""
    return write_synthetic_pairs(tmp_path_factory.mktemp("pairs"))


class Constant:
    """A model of known density: log p = -1.5 for every tuple."""

    def log_prob(self, data: PairsDataset) -> np.ndarray:
        return np.full(len(data), -1.5)


@pytest.fixture(scope="module")
def cli():
    """The CLI with ``score`` registered as pair2scene.cli will register it."""
    if not any(c.name == "score" for c in app.registered_commands):
        app.command("score")(score_command)
    return main


def test_dataset_has_splits(pairs_dir):
    data = load_pairs(pairs_dir)
    assert len(data) == 96
    assert int((data.split == "val").sum()) == 24


def test_score_of_a_known_density(pairs_dir):
    assert isinstance(Constant(), Scorer)
    result = score(Constant(), pairs_dir, "val")
    assert result.n == 24 and result.nll == 1.5 and result.median_nll == 1.5
    assert {k: g.n for k, g in result.per_kind.items()} == {
        "floor": 12, "functional": 6, "support": 6
    }  # fmt: skip
    assert {k: g.n for k, g in result.per_source.items()} == {"ai2thor": 12, "procthor": 12}
    assert all(g.nll == 1.5 for g in result.per_kind.values())
    doc = result.to_dict()
    assert doc["nll"] == 1.5 and doc["n"] == 24 and doc["nonfinite"] == 0


def test_nonfinite_density_is_reported(pairs_dir):
    class Zero:
        def log_prob(self, data):
            lp = np.zeros(len(data))
            lp[0] = -np.inf
            return lp

    result = score(Zero(), pairs_dir, "val")
    assert result.nonfinite == 1 and result.nll == np.inf
    assert result.to_dict()["nll"] is None
    with pytest.raises(ValueError, match="shape"):
        score(type("Bad", (), {"log_prob": lambda self, d: np.zeros(3)})(), pairs_dir, "val")


def test_log_size_jacobian_matches_lognormal():
    # a standard normal on log size is a log-normal on size: scipy's density of the size
    size = np.array([[0.05, 0.5, 2.0], [1.0, 3.0, 0.2]])
    lp_log = stats.norm.logpdf(np.log(size)).sum(axis=1)
    want = stats.lognorm(s=1.0).logpdf(size).sum(axis=1)
    np.testing.assert_allclose(log_prob_from_log_size(lp_log, size), want, rtol=1e-12)
    x = np.zeros((2, 12))
    x[:, 3:6] = size
    np.testing.assert_allclose(to_log_size(x)[:, 3:6], np.log(size))
    assert np.array_equal(to_log_size(x)[:, :3], x[:, :3])


def test_gaussian_scores_val_and_beats_a_broad_density(pairs_dir):
    data = load_pairs(pairs_dir)
    model = load_model("gaussian", data)
    assert isinstance(model, GaussianBaseline)
    result = score(model, data, "val")
    assert result.n == 24 and np.isfinite(result.nll) and result.nonfinite == 0
    # the same numbers as the model's own log_prob on the val rows
    val = select_rows(data, data.split == "val")
    assert result.nll == pytest.approx(-model.log_prob(val).mean(), rel=1e-12)
    # fitted on train only: the same model as one fitted on a dataset without the val rows
    train_only = select_rows(data, data.split == "train")
    assert np.array_equal(GaussianBaseline.fit(train_only, None).log_prob(val), model.log_prob(val))
    # a broad standard normal on all 12 numbers is much worse
    broad = stats.norm.logpdf(val.canonical.astype(float)).sum(axis=1)
    assert result.nll < -broad.mean() - 10.0


def test_select_rows_keeps_every_field(pairs_dir):
    data = load_pairs(pairs_dir)
    rows = np.array([5, 0, 7])
    sub = select_rows(data, rows)
    assert len(sub) == 3
    for i, j in enumerate(rows):
        a, b = sub.tuple(i), data.tuple(int(j))
        assert (a.scene_id, a.split, a.kind, a.dependent.id) == (
            b.scene_id, b.split, b.kind, b.dependent.id
        )  # fmt: skip
        assert a.canonical.allclose(b.canonical)


def test_load_model_errors(tmp_path, pairs_dir):
    with pytest.raises(UserError, match="config.json: missing"):
        load_model(str(tmp_path))  # a folder that is no checkpoint
    with pytest.raises(UserError, match="no such file"):
        load_model(str(tmp_path / "missing.json"))
    with pytest.raises(UserError, match="no 'test' tuples"):
        score(Constant(), pairs_dir, "test")


def test_saved_baseline_scores_identically(tmp_path, pairs_dir):
    data = load_pairs(pairs_dir)
    model = GaussianBaseline.fit(data, "train", GaussianConfig(seed=1))
    model.save(tmp_path / "b.json")
    loaded = load_model(str(tmp_path / "b.json"))
    assert score(loaded, data).nll == score(model, data).nll


def test_cli_prints_json(cli, pairs_dir, tmp_path, capsys):
    saved = tmp_path / "baseline.json"
    args = ["score", "--model", "gaussian", "--data", str(pairs_dir), "--split", "val", "--json"]
    assert cli([*args, "--save-baseline", str(saved)]) == 0
    doc = json.loads(capsys.readouterr().out)
    assert doc["n"] == 24 and isinstance(doc["nll"], float)
    assert doc["model"] == "gaussian" and set(doc["per_kind"]) == {"floor", "functional", "support"}
    want = score(GaussianBaseline.fit(load_pairs(pairs_dir)), pairs_dir, "val").nll
    assert doc["nll"] == want
    # the saved baseline gives the same number
    assert cli(["score", "--model", str(saved), "--data", str(pairs_dir), "--json"]) == 0
    assert json.loads(capsys.readouterr().out)["nll"] == want
    # --no-anchor-frames: the baseline in the support's frame only
    assert cli([*args, "--no-anchor-frames"]) == 0
    plain = GaussianBaseline.fit(
        load_pairs(pairs_dir), "train", GaussianConfig(anchor_frames=False)
    )
    assert json.loads(capsys.readouterr().out)["nll"] == score(plain, pairs_dir, "val").nll != want


def test_cli_fits_the_baseline_on_another_folder(cli, pairs_dir, tmp_path, capsys):
    """--fit-on: the Gaussian of one 3D-Pairs folder's train split scores another's val."""
    other = write_synthetic_pairs(tmp_path / "other", scenes=16, seed=7)
    args = ["score", "--model", "gaussian", "--data", str(pairs_dir), "--json"]
    assert cli([*args, "--fit-on", str(other)]) == 0
    got = json.loads(capsys.readouterr().out)["nll"]
    assert got == score(GaussianBaseline.fit(load_pairs(other)), pairs_dir, "val").nll
    assert got != score(GaussianBaseline.fit(load_pairs(pairs_dir)), pairs_dir, "val").nll
    learned = ["score", "--data", str(pairs_dir), "--fit-on", str(other)]
    assert cli(learned) == 2 and "--fit-on needs --model gaussian" in capsys.readouterr().err


def test_cli_user_errors(cli, tmp_path, pairs_dir, capsys):
    for args in (
        ["score", "--model", "gaussian", "--data", str(tmp_path / "nowhere")],
        ["score", "--data", str(pairs_dir), "--model", str(tmp_path)],  # not a checkpoint
        ["score", "--model", "gaussian", "--data", str(pairs_dir), "--split", "test"],
    ):
        assert cli(args) == 2
        err = capsys.readouterr().err
        assert err.startswith("error: ") and len(err.strip().splitlines()) == 1


def test_pipeline_fixture_scores(tmp_path, fixtures):
    """The real curation pipeline on the 3-room ProcTHOR fixture (train only)."""
    from pair2scene.curation.pipeline import CurateConfig, curate

    out = tmp_path / "pairs"
    source = f"procthor:{fixtures / 'procthor' / 'train.jsonl.gz'}"
    curate(CurateConfig(sources=(source,), out=out, physics=False, workers=1))
    data = load_pairs(out)
    assert set(data.split.tolist()) == {"train"}
    result = score(load_model("gaussian", data), data, "train")
    assert result.n == len(data) == 64 and np.isfinite(result.nll)  # 7 of them paintings
    on_walls = data.categories.index("wall")
    assert (data.support.category == on_walls).sum() == 7

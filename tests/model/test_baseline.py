"""Gaussian-mixture baseline: EM, back-off, interpolation, the log-size Jacobian, JSON."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest
from scipy import stats

from pair2scene.errors import UserError
from pair2scene.model.baseline import (
    LEVELS,
    GaussianBaseline,
    GaussianConfig,
    GaussianMixture,
    fit_mixture,
)


def boxes(rng: np.random.Generator, n: int, centre: float, spread: float = 0.1) -> np.ndarray:
    """(n, 12) canonical boxes: centre ~ N(centre, spread), positive sizes, upright
    yaw ~ N(0, spread)."""
    x = np.empty((n, 12))
    x[:, :3] = rng.normal(centre, spread, (n, 3))
    x[:, 3:6] = np.exp(rng.normal(-1.0, spread, (n, 3)))
    yaw = rng.normal(0.0, spread, n)
    c, s, z = np.cos(yaw), np.sin(yaw), np.zeros(n)
    x[:, 6:] = np.stack([c, s, z, -s, c, z], axis=1)
    return x


def keyed_data(seed: int = 0):
    """40 mugs on tables near centre 0, 25 pens on tables near 2, 6 lamps on desks near
    -2 (rare), 30 chairs at desks on the floor near 1."""
    rng = np.random.default_rng(seed)
    parts = [
        (boxes(rng, 40, 0.0), "mug", "dining_table", ""),
        (boxes(rng, 25, 2.0), "pen", "dining_table", ""),
        (boxes(rng, 6, -2.0), "lamp", "desk", ""),
        (boxes(rng, 30, 1.0), "chair", "floor", "desk"),
    ]
    x = np.concatenate([p[0] for p in parts])
    dep = [p[1] for p in parts for _ in range(len(p[0]))]
    sup = [p[2] for p in parts for _ in range(len(p[0]))]
    func = [p[3] for p in parts for _ in range(len(p[0]))]
    return x, dep, sup, func


def test_em_recovers_two_clusters():
    rng = np.random.default_rng(1)
    a = rng.normal([-3.0, 0.0], 0.5, (300, 2))
    b = rng.normal([3.0, 1.0], 0.5, (100, 2))
    x = np.concatenate([a, b])
    config = GaussianConfig(components=2, min_per_component=5, covariance="full", reg=1e-6)
    mix = fit_mixture(x, config, np.random.default_rng(0))
    order = np.argsort(mix.means[:, 0])
    # well separated: EM lands on each cluster's own sample statistics
    np.testing.assert_allclose(mix.means[order], [a.mean(axis=0), b.mean(axis=0)], atol=1e-6)
    np.testing.assert_allclose(mix.means[order], [[-3.0, 0.0], [3.0, 1.0]], atol=0.15)
    np.testing.assert_allclose(mix.weights[order], [0.75, 0.25], atol=1e-6)
    np.testing.assert_allclose(
        mix.covariances[order][0], np.cov(a.T, bias=True) + 1e-6 * np.eye(2), atol=1e-6
    )
    # same seed, same mixture, bit for bit
    again = fit_mixture(x, config, np.random.default_rng(0))
    assert np.array_equal(again.means, mix.means)


def test_mixture_density_matches_scipy():
    w = np.array([0.3, 0.7])
    mu = np.array([[0.0, 1.0], [2.0, -1.0]])
    cov = np.array([[[1.0, 0.3], [0.3, 0.5]], [[0.2, 0.0], [0.0, 2.0]]])
    x = np.array([[0.1, 0.2], [1.5, -0.5], [5.0, 5.0]])
    want = np.log(
        w[0] * stats.multivariate_normal(mu[0], cov[0]).pdf(x)
        + w[1] * stats.multivariate_normal(mu[1], cov[1]).pdf(x)
    )
    np.testing.assert_allclose(GaussianMixture(w, mu, cov).log_prob(x), want, rtol=1e-12)
    diag = GaussianMixture(w, mu, cov[:, [0, 1], [0, 1]])
    want_diag = np.log(
        sum(w[k] * stats.multivariate_normal(mu[k], np.diag(cov[k].diagonal())).pdf(x)
            for k in range(2))
    )  # fmt: skip
    np.testing.assert_allclose(diag.log_prob(x), want_diag, rtol=1e-12)


def test_component_count_follows_data():
    rng = np.random.default_rng(0)
    config = GaussianConfig(components=4, min_per_component=10)
    assert fit_mixture(rng.normal(size=(15, 3)), config, rng).n_components == 1
    assert fit_mixture(rng.normal(size=(400, 3)), config, rng).n_components == 4
    # ten copies of one point: one component, floored, finite
    one = fit_mixture(np.ones((10, 3)), GaussianConfig(components=4, min_per_component=1), rng)
    assert np.isfinite(one.log_prob(np.ones((1, 3)))).all()


def test_backoff_levels_by_count():
    x, dep, sup, func = keyed_data()
    model = GaussianBaseline.fit_arrays(x, dep, sup, func, GaussianConfig(min_count=20))
    assert set(model.mixtures) == set(LEVELS)
    assert sorted(model.mixtures["sup_dep_func"]) == [
        ("dining_table", "mug", "none"), ("dining_table", "pen", "none"),
        ("floor", "chair", "desk"),
    ]  # fmt: skip
    assert ("lamp",) not in model.mixtures["dep"]  # 6 lamps < 20
    level, keys = model.resolve(dep, sup, func)
    counts = {name: int((level == j).sum()) for j, name in enumerate(LEVELS)}
    assert counts == {"sup_dep_func": 95, "sup_dep": 0, "dep": 0, "global": 6}
    # an unseen functional anchor backs off to (support, dependent); an unseen category
    # to global
    level, keys = model.resolve(["chair", "sofa"], ["floor", "floor"], ["bed", ""])
    assert [LEVELS[j] for j in level] == ["sup_dep", "global"]
    assert keys == [("floor", "chair"), ()]


@pytest.mark.parametrize("covariance", ["diag", "full"])
def test_matching_key_beats_global(covariance):
    x, dep, sup, func = keyed_data()
    model = GaussianBaseline.fit_arrays(
        x, dep, sup, func, GaussianConfig(min_count=20, covariance=covariance)
    )
    lp = model.log_prob_arrays(x, dep, sup, func)
    assert np.isfinite(lp).all()
    y = x.copy()
    y[:, 3:6] = np.log(y[:, 3:6])  # the baseline's own space (log_size, the default)
    lp_global = model.mixtures["global"][()].log_prob(y) - np.log(x[:, 3:6]).sum(axis=1)
    mugs = np.array(dep) == "mug"
    assert lp[mugs].mean() > lp_global[mugs].mean() + 5.0
    # a mug box placed where the pens go is less likely as a mug than as a pen
    pen_box = x[np.array(dep) == "pen"][:1]
    as_mug = model.log_prob_arrays(pen_box, ["mug"], ["dining_table"], [""])
    as_pen = model.log_prob_arrays(pen_box, ["pen"], ["dining_table"], [""])
    assert as_pen[0] > as_mug[0] + 10.0
    # far from everything: small but finite
    far = model.log_prob_arrays(np.full((1, 12), 50.0), ["mug"], ["dining_table"], [""])
    assert np.isfinite(far).all() and far[0] < lp.min()


def test_interpolation_is_the_documented_formula():
    x, dep, sup, func = keyed_data()
    lam = 0.25
    model = GaussianBaseline.fit_arrays(
        x, dep, sup, func, GaussianConfig(min_count=20, smoothing=lam, log_size=False)
    )
    q = x[:3]  # three mugs: levels sup_dep_func, sup_dep, dep and global all fitted
    m = model.mixtures
    p = {
        level: np.exp(m[level][key].log_prob(q))
        for level, key in (
            ("sup_dep_func", ("dining_table", "mug", "none")),
            ("sup_dep", ("dining_table", "mug")),
            ("dep", ("mug",)),
            ("global", ()),
        )
    }
    want = (1 - lam) * p["sup_dep_func"] + lam * (
        (1 - lam) * p["sup_dep"] + lam * ((1 - lam) * p["dep"] + lam * p["global"])
    )
    got = model.log_prob_arrays(q, dep[:3], sup[:3], func[:3])
    np.testing.assert_allclose(got, np.log(want), rtol=1e-12)
    # smoothing 0: the finest fitted key alone
    hard = GaussianBaseline.fit_arrays(
        x, dep, sup, func, GaussianConfig(min_count=20, smoothing=0.0, log_size=False)
    )
    np.testing.assert_allclose(
        hard.log_prob_arrays(q, dep[:3], sup[:3], func[:3]),
        hard.mixtures["sup_dep_func"][("dining_table", "mug", "none")].log_prob(q),
        rtol=1e-12,
    )


def test_log_size_adds_the_jacobian():
    x, dep, sup, func = keyed_data()
    model = GaussianBaseline.fit_arrays(x, dep, sup, func, GaussianConfig(smoothing=0.0))
    y = x.copy()
    y[:, 3:6] = np.log(x[:, 3:6])
    mix = model.mixtures["sup_dep_func"][("dining_table", "mug", "none")]
    want = mix.log_prob(y[:40]) - np.log(x[:40, 3:6]).sum(axis=1)
    np.testing.assert_allclose(model.log_prob_arrays(x[:40], dep[:40], sup[:40], func[:40]), want)


def test_marginal_is_the_sub_gaussian_and_integrates_the_rest_out():
    w = np.array([0.3, 0.7])
    mu = np.array([[0.0, 1.0], [2.0, -1.0]])
    cov = np.array([[[1.0, 0.3], [0.3, 0.5]], [[0.2, 0.0], [0.0, 2.0]]])
    x = np.array([[0.4], [1.7]])
    want = np.log(
        w[0] * stats.norm(0.0, 1.0).pdf(x[:, 0]) + w[1] * stats.norm(2.0, 0.2**0.5).pdf(x[:, 0])
    )
    np.testing.assert_allclose(GaussianMixture(w, mu, cov).marginal([0]).log_prob(x), want)
    # numerically: integrating the full density over dim 1 gives the marginal
    grid = np.linspace(-15, 15, 20001)
    full = GaussianMixture(w, mu, cov)
    dens = np.exp(full.log_prob(np.stack([np.full_like(grid, 0.4), grid], 1)))
    assert np.trapezoid(dens, grid) == pytest.approx(np.exp(want[0]), rel=1e-6)


def test_size_marginal_with_the_log_size_jacobian():
    x, dep, sup, func = keyed_data()
    model = GaussianBaseline.fit_arrays(x, dep, sup, func, GaussianConfig(smoothing=0.0))
    mix = model.mixtures["sup_dep_func"][("dining_table", "mug", "none")].marginal([3, 4, 5])
    want = mix.log_prob(np.log(x[:40, 3:6])) - np.log(x[:40, 3:6]).sum(axis=1)
    got = model.log_prob_arrays(x[:40], dep[:40], sup[:40], func[:40], dims=[3, 4, 5])
    np.testing.assert_allclose(got, want)


def test_json_round_trip_is_identical(tmp_path):
    x, dep, sup, func = keyed_data()
    for config in (GaussianConfig(min_count=20), GaussianConfig(covariance="full", seed=3)):
        model = GaussianBaseline.fit_arrays(x, dep, sup, func, config)
        path = tmp_path / "baseline.json"
        model.save(path)
        loaded = GaussianBaseline.load(path)
        assert loaded.config == model.config
        assert np.array_equal(
            loaded.log_prob_arrays(x, dep, sup, func), model.log_prob_arrays(x, dep, sup, func)
        )


def test_bad_baseline_files(tmp_path):
    with pytest.raises(UserError, match="no such file"):
        GaussianBaseline.load(tmp_path / "missing.json")
    bad = tmp_path / "bad.json"
    bad.write_text('{"format": "something else"}')
    with pytest.raises(UserError, match="not a valid"):
        GaussianBaseline.load(bad)


def test_config_is_checked():
    with pytest.raises(ValueError, match="covariance"):
        GaussianConfig(covariance="spherical")
    with pytest.raises(ValueError, match="reg"):
        GaussianConfig(reg=0.0)
    with pytest.raises(ValueError, match="smoothing"):
        GaussianConfig(smoothing=1.0)
    assert math.isclose(GaussianConfig().reg, 2e-6)


# -- anchor frames (issue 18) -------------------------------------------------------------


@pytest.fixture(scope="module")
def pairs(tmp_path_factory):
    from pair2scene.curation.dataset import load_pairs
    from synthetic_pairs import write_synthetic_pairs

    return load_pairs(write_synthetic_pairs(tmp_path_factory.mktemp("pairs")))


def _affine(fn, x: np.ndarray, h: float = 1e-6) -> tuple[np.ndarray, np.ndarray]:
    """(J, fn(x)) of fn at x, J by central differences."""
    jac = np.stack([(fn(x + h * e) - fn(x - h * e)) / (2 * h) for e in np.eye(len(x))], 1)
    return jac, fn(x)


def test_anchor_frames_score_densities_of_the_stored_vector(pairs):
    """Wall and functional frames: the boxes in the frame, the Jacobians against finite
    differences, and the score against the mixture pushed back to the stored vector."""
    from pair2scene.model.baseline import (
        FRAME_FUNCTIONAL,
        FRAME_SUPPORT,
        FRAME_WALL,
        canonical_to_frame,
        framed_tuples,
        tuple_frames,
    )
    from pair2scene.scene.geometry import OrientedBox

    kinds, frames = tuple_frames(pairs)
    assert {FRAME_WALL, FRAME_FUNCTIONAL, FRAME_SUPPORT} <= set(kinds.tolist())
    framed = framed_tuples(pairs, anchor_frames=True)
    config = GaussianConfig(smoothing=0.0, log_size=False, covariance="full", min_count=5)
    model = GaussianBaseline.fit(pairs, "train", config)
    lp, lps = model.log_prob(pairs), model.log_prob_size(pairs)
    for kind in (FRAME_WALL, FRAME_FUNCTIONAL):
        for i in np.flatnonzero(kinds == kind)[:3]:
            sup, frame = pairs.support.box[i : i + 1], frames[i : i + 1]
            xi = pairs.canonical[i].astype(np.float64)

            def fn(v, sup=sup, frame=frame):
                return canonical_to_frame(v[None], sup, frame)[0][0]

            jac, y = _affine(fn, xi)
            np.testing.assert_allclose(y, framed.x[i])
            assert framed.log_jacobian[i] == pytest.approx(np.linalg.slogdet(jac)[1], abs=1e-6)
            size_jac = jac[3:6, 3:6]
            assert framed.size_log_jacobian[i] == pytest.approx(
                np.linalg.slogdet(size_jac)[1], abs=1e-6
            )
            # the same box as the dependent's world box seen from the frame
            dep = OrientedBox.from_vector(pairs.dependent.box[i])
            want = dep.in_frame_of(OrientedBox.from_vector(frames[i])).to_vector()
            np.testing.assert_allclose(y, want, atol=1e-4)
            # the fitted mixture in the frame, pushed back through x = J^-1 (y - b):
            # its density at the stored vector is what log_prob returns
            mix = model.mixture_for(framed.dependent[i], framed.support[i], framed.functional[i])
            inv = np.linalg.inv(jac)
            b = y - jac @ xi
            back = GaussianMixture(
                mix.weights,
                (mix.means - b) @ inv.T,
                np.einsum("ij,kjl,ml->kim", inv, mix.covariances, inv),
            )
            assert lp[i] == pytest.approx(float(back.log_prob(xi[None])[0]), abs=1e-6)
            size_back = back.marginal([3, 4, 5])
            assert lps[i] == pytest.approx(float(size_back.log_prob(xi[None, 3:6])[0]), abs=1e-6)
    # the wall-framed and the room-framed sofa never share a mixture
    assert ("floor@wall", "sofa") in model.mixtures["sup_dep"]
    assert ("@wall",) in model.mixtures["global"] and () in model.mixtures["global"]
    framed_supports = {k[0] for k in model.mixtures["sup_dep"] if "@" in k[0]}
    assert framed_supports == {"floor@wall", "floor@functional"}


def test_anchor_frames_are_the_learned_models(pairs):
    """The baseline models every tuple in the frame the learned model's features put it."""
    pytest.importorskip("torch")
    from pair2scene.model.baseline import framed_tuples
    from pair2scene.model.features import dataset_features

    learned = dataset_features(pairs, "full", with_clouds=False, anchor_frames=True).arrays
    np.testing.assert_array_equal(framed_tuples(pairs, True).kinds, learned.frames)


def test_without_anchor_frames_nothing_changes(pairs):
    from pair2scene.model.baseline import dataset_keys
    from pair2scene.model.scoring import split_of

    val = split_of(pairs, "val")
    model = GaussianBaseline.fit(pairs, "train", GaussianConfig(anchor_frames=False))
    # the numbers of the baseline before anchor frames existed (commit 8dbef10)
    assert model.log_prob(val).sum() == pytest.approx(1365.5904949263306, rel=1e-7)
    assert model.log_prob_size(val).sum() == pytest.approx(362.95983983488395, rel=1e-7)
    # ... and its path: stored canonical vectors under category keys
    train = pairs.split == "train"
    keys = [np.array(k, dtype=object)[train].tolist() for k in dataset_keys(pairs)]
    old = GaussianBaseline.fit_arrays(pairs.canonical[train], *keys, model.config)
    np.testing.assert_array_equal(
        model.log_prob(val), old.log_prob_arrays(val.canonical, *dataset_keys(val))
    )
    # with anchor frames the support-framed mugs keep their keys and their boxes
    framed = GaussianBaseline.fit(pairs, "train")
    assert framed.config.anchor_frames and GaussianConfig().anchor_frames
    f = framed.framed(val)
    mugs = np.array(f.dependent) == "mug"
    np.testing.assert_array_equal(f.x[mugs], val.canonical[mugs].astype(np.float64))
    assert (f.log_jacobian[mugs] == 0).all()


def test_baselines_saved_before_anchor_frames_load_without_them(tmp_path, pairs):
    model = GaussianBaseline.fit(pairs, "train")
    path = tmp_path / "b.json"
    model.save(path)
    loaded = GaussianBaseline.load(path)
    assert loaded.config.anchor_frames
    np.testing.assert_array_equal(loaded.log_prob(pairs), model.log_prob(pairs))
    old = GaussianBaseline.fit(pairs, "train", GaussianConfig(anchor_frames=False)).to_dict()
    del old["config"]["anchor_frames"]
    path.write_text(json.dumps(old))
    assert not GaussianBaseline.load(path).config.anchor_frames


def test_a_frame_never_seen_in_training_is_the_supports(pairs):
    """Fitted on data without walls (3D-Pairs v1), tuples and queries against a wall are
    modelled in their support's frame, not drawn from mixtures of another frame."""
    import dataclasses

    from pair2scene.model.baseline import FRAME_FUNCTIONAL, FRAME_SUPPORT, FRAME_WALL
    from pair2scene.scene.geometry import OrientedBox

    no_walls = dataclasses.replace(pairs, wall_index=np.full(len(pairs), -1, np.int32))
    model = GaussianBaseline.fit(no_walls, "train")
    assert model.frames == {FRAME_SUPPORT, FRAME_FUNCTIONAL}
    assert GaussianBaseline.fit(pairs, "train").frames == {0, 1, 2}
    assert FRAME_WALL not in set(model.framed(pairs).kinds.tolist())
    assert np.isfinite(model.log_prob(pairs)).all()
    i = int(np.flatnonzero(pairs.wall_index >= 0)[0])
    room = OrientedBox.from_vector(pairs.support.box[i])
    wall = OrientedBox.from_vector(pairs.wall_box[i])
    assert model.frame_for(room, True, wall, None) == (FRAME_SUPPORT, room)

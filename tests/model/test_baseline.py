"""Gaussian-mixture baseline: EM, back-off, interpolation, the log-size Jacobian, JSON."""

from __future__ import annotations

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

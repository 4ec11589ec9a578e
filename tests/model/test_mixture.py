"""Mixture of logistics: density against scipy, loss, sampler, box target encoding."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy import special, stats

torch = pytest.importorskip("torch")

from pair2scene.model.mixture import (  # noqa: E402
    BOX_DIM,
    EntropyRegulariser,
    MixtureConfig,
    MixtureParams,
    Window,
    box_vector_from_target,
    decode_target,
    encode_target,
    entropy_of_weights,
    log_prob,
    loss,
    mixture_params_from_head,
    mode,
    rotation_from_6d,
    rotation_to_6d,
    sample,
    soft_clamp,
    target_from_box_vector,
    window_log_mass,
)
from pair2scene.scene.geometry import OrientedBox, sixd_to_matrix  # noqa: E402


def random_params(
    seed: int, b: int, k: int, d: int, dtype: torch.dtype = torch.float64
) -> MixtureParams:
    g = torch.Generator().manual_seed(seed)
    return MixtureParams(
        logits=torch.randn(b, k, generator=g, dtype=dtype),
        loc=torch.randn(b, k, d, generator=g, dtype=dtype) * 2.0,
        log_scale=torch.rand(b, k, d, generator=g, dtype=dtype) * 2.0 - 1.5,
    )


def scipy_mixture_logpdf(params: MixtureParams, x: torch.Tensor) -> np.ndarray:
    """The reference: per-dimension scipy logpdf, summed, mixed with log-softmax weights."""
    logits, loc, log_scale = (t.numpy() for t in params)
    log_w = logits - special.logsumexp(logits, axis=-1, keepdims=True)  # (B, K)
    comp = stats.logistic.logpdf(x.numpy()[:, None, :], loc=loc, scale=np.exp(log_scale))
    return special.logsumexp(log_w + comp.sum(axis=-1), axis=-1)  # (B,)


def random_rotations(seed: int, n: int) -> torch.Tensor:
    """(n, 3, 3) proper rotations from the QR of Gaussian matrices."""
    q, r = np.linalg.qr(np.random.default_rng(seed).normal(size=(n, 3, 3)))
    q = q * np.sign(np.diagonal(r, axis1=-2, axis2=-1))[:, None, :]
    q[np.linalg.det(q) < 0, :, 0] *= -1
    return torch.from_numpy(q)


# -- density ---------------------------------------------------------------------------
def test_log_prob_single_component_is_scipy_logistic_summed_over_dims():
    params = random_params(0, b=16, k=1, d=BOX_DIM)
    x = torch.randn(16, BOX_DIM, generator=torch.Generator().manual_seed(1), dtype=torch.float64)
    x = x * 3.0
    expected = stats.logistic.logpdf(
        x.numpy(), loc=params.loc[:, 0].numpy(), scale=params.log_scale[:, 0].exp().numpy()
    ).sum(axis=-1)
    got = log_prob(params, x)
    assert got.shape == (16,)
    np.testing.assert_allclose(got.numpy(), expected, rtol=0, atol=1e-5)


def test_log_prob_three_components_matches_manual_scipy_mixture():
    params = random_params(2, b=32, k=3, d=BOX_DIM)
    x = torch.randn(32, BOX_DIM, generator=torch.Generator().manual_seed(3), dtype=torch.float64)
    np.testing.assert_allclose(
        log_prob(params, x).numpy(), scipy_mixture_logpdf(params, x), rtol=0, atol=1e-5
    )


def test_log_prob_far_tail_matches_scipy():
    """Points hundreds of scales away: the naive exp-based formula would give -inf."""
    params = random_params(4, b=8, k=3, d=4)
    x = torch.linspace(-2000.0, 2000.0, 32, dtype=torch.float64).reshape(8, 4)
    got = log_prob(params, x)
    assert torch.isfinite(got).all()
    np.testing.assert_allclose(got.numpy(), scipy_mixture_logpdf(params, x), rtol=1e-10)


def test_log_prob_float32_close_to_float64():
    params = random_params(5, b=32, k=4, d=BOX_DIM)
    x = torch.randn(32, BOX_DIM, generator=torch.Generator().manual_seed(6), dtype=torch.float64)
    p32 = MixtureParams(*(t.float() for t in params))
    got = log_prob(p32, x.float())
    assert got.dtype == torch.float32
    np.testing.assert_allclose(got.double().numpy(), log_prob(params, x).numpy(), atol=1e-4)


def test_log_prob_integrates_to_one_in_1d():
    params = MixtureParams(
        logits=torch.tensor([[0.3, -0.5]], dtype=torch.float64),
        loc=torch.tensor([[[-1.0], [2.0]]], dtype=torch.float64),
        log_scale=torch.tensor([[[math.log(0.3)], [math.log(0.8)]]], dtype=torch.float64),
    )
    grid = torch.linspace(-60.0, 60.0, 200_001, dtype=torch.float64)
    pdf = log_prob(
        MixtureParams(*(t.expand(grid.numel(), *t.shape[1:]) for t in params)), grid[:, None]
    ).exp()
    assert torch.trapezoid(pdf, grid).item() == pytest.approx(1.0, abs=1e-8)


def test_log_prob_leading_batch_dims():
    params = random_params(7, b=6, k=3, d=5)
    x = torch.randn(6, 5, generator=torch.Generator().manual_seed(8), dtype=torch.float64)
    nested = MixtureParams(*(t.reshape(2, 3, *t.shape[1:]) for t in params))
    np.testing.assert_array_equal(
        log_prob(nested, x.reshape(2, 3, 5)).numpy(), log_prob(params, x).reshape(2, 3).numpy()
    )


def test_gradients_finite_at_extreme_values():
    cfg = MixtureConfig()
    raw = torch.randn(8, cfg.head_dim, generator=torch.Generator().manual_seed(9)) * 1e4
    raw.requires_grad_(True)
    params = mixture_params_from_head(raw, cfg.num_components, cfg.dim, yaw_modes=cfg.yaw_modes)
    x = torch.full((8, cfg.dim), 1e6)
    x[::2] = -1e6
    x[1] = 0.0
    total, parts = loss(params, x, entropy_weight=0.1)
    total.backward()
    assert torch.isfinite(total)
    assert torch.isfinite(parts.nll) and torch.isfinite(parts.entropy)
    assert torch.isfinite(raw.grad).all()
    assert raw.grad.abs().sum() > 0


def test_gradient_at_component_centre_is_zero_in_loc():
    """|z| is not differentiable at 0, but the log density is flat there: grad must be 0."""
    loc = torch.zeros(1, 1, 3, dtype=torch.float64, requires_grad=True)
    params = MixtureParams(
        torch.zeros(1, 1, dtype=torch.float64), loc, torch.zeros(1, 1, 3, dtype=torch.float64)
    )
    log_prob(params, torch.zeros(1, 3, dtype=torch.float64)).sum().backward()
    assert torch.equal(loc.grad, torch.zeros_like(loc))


# -- head ------------------------------------------------------------------------------
def test_params_from_head_layout_and_shapes():
    k, d = 2, 3
    raw = torch.arange(k * (1 + 2 * d), dtype=torch.float64).reshape(1, -1) * 0.1  # (1, 14)
    raw = raw.expand(5, -1)
    params = mixture_params_from_head(raw, k, d, min_log_scale=-7.0, max_log_scale=5.0)
    assert params.logits.shape == (5, k)
    assert params.loc.shape == (5, k, d) and params.log_scale.shape == (5, k, d)
    np.testing.assert_allclose(params.logits[0].numpy(), [0.0, 0.1])
    np.testing.assert_allclose(params.loc[0].numpy(), [[0.2, 0.3, 0.4], [0.5, 0.6, 0.7]])
    # log scales 0.8 .. 1.3 go through the soft clamp: within exp(-(5 - v)) of themselves
    v = np.array([[0.8, 0.9, 1.0], [1.1, 1.2, 1.3]])
    expected = 5.0 - np.log1p(np.exp(5.0 - (-7.0 + np.log1p(np.exp(v + 7.0)))))
    np.testing.assert_allclose(params.log_scale[0].numpy(), expected, rtol=1e-12)
    assert np.all(np.abs(expected - v) < np.exp(-(5.0 - v)))
    with pytest.raises(ValueError, match="expected K"):
        mixture_params_from_head(raw[:, :-1], k, d)


def test_soft_clamp_bounds_and_gradient():
    x = torch.tensor(
        [-1e4, -50.0, -7.0, 0.0, 5.0, 50.0, 1e4], dtype=torch.float64, requires_grad=True
    )
    y = soft_clamp(x, -7.0, 5.0)
    assert (y >= -7.0 - 1e-5).all() and (y <= 5.0).all()
    assert y[0].item() == pytest.approx(-7.0, abs=1e-5)
    assert y[-1].item() == pytest.approx(5.0, abs=1e-12)
    assert y[3].item() == pytest.approx(0.0, abs=1e-2)  # ~identity in the middle
    assert torch.all(torch.diff(y) >= 0)  # monotone
    y.sum().backward()
    assert torch.isfinite(x.grad).all()
    assert (x.grad[1:-1] > 0).all()  # past a bound the gradient is small, not 0


def test_config_head_dim():
    assert MixtureConfig().head_dim == 4 * (1 + 2 * 12 + 4) == 116
    assert MixtureConfig(yaw_modes=1).head_dim == 4 * (1 + 2 * 12) == 100
    assert MixtureConfig(num_components=3, dim=2, yaw_modes=1).head_dim == 15
    with pytest.raises(ValueError, match="yaw_modes"):
        MixtureConfig(num_components=3, dim=2)
    with pytest.raises(ValueError, match="yaw_modes"):
        MixtureConfig(yaw_modes=3)


# -- entropy and loss ------------------------------------------------------------------
def test_entropy_known_values():
    logits = torch.tensor(
        [
            [0.0, 0.0, 0.0, 0.0],  # uniform
            [0.0, -1e4, -1e4, -1e4],  # one component
            [math.log(0.5), math.log(0.25), math.log(0.25), -1e4],
            [5.0, 5.0, 5.0, 5.0],  # shift-invariant
        ],
        dtype=torch.float64,
    )
    params = MixtureParams(logits, torch.zeros(4, 4, 1), torch.zeros(4, 4, 1))
    np.testing.assert_allclose(
        entropy_of_weights(params).numpy(),
        [math.log(4), 0.0, 1.5 * math.log(2), math.log(4)],
        atol=1e-12,
    )


def test_loss_known_value_and_sign():
    params = random_params(10, b=6, k=4, d=3)
    x = torch.randn(6, 3, generator=torch.Generator().manual_seed(11), dtype=torch.float64)
    nll = -log_prob(params, x).mean()
    h = entropy_of_weights(params).mean()
    bonus, parts = loss(params, x, entropy_weight=0.5)
    penalty, _ = loss(params, x, 0.5, EntropyRegulariser.PENALTY)
    assert parts.nll.item() == pytest.approx(nll.item(), abs=1e-12)
    assert parts.entropy.item() == pytest.approx(h.item(), abs=1e-12)
    assert bonus.item() == pytest.approx((nll - 0.5 * h).item(), abs=1e-12)
    assert penalty.item() == pytest.approx((nll + 0.5 * h).item(), abs=1e-12)
    assert loss(params, x, 0.5, "penalty")[0].item() == pytest.approx(penalty.item())
    assert set(parts._asdict()) == {"nll", "entropy"}
    assert not parts.nll.requires_grad


@pytest.mark.parametrize(
    ("regulariser", "entropy_goes"),
    [(EntropyRegulariser.BONUS, "up"), (EntropyRegulariser.PENALTY, "down")],
)
def test_entropy_regulariser_direction(regulariser, entropy_goes):
    """Identical components make the NLL blind to the weights: only the regulariser moves them."""
    logits = torch.tensor([[1.0, 0.0, -0.5, -1.0]], dtype=torch.float64, requires_grad=True)
    params = MixtureParams(
        logits, torch.zeros(1, 4, 2, dtype=torch.float64), torch.zeros(1, 4, 2, dtype=torch.float64)
    )
    x = torch.tensor([[0.3, -0.2]], dtype=torch.float64)
    total, parts = loss(params, x, entropy_weight=1.0, regulariser=regulariser)
    total.backward()
    stepped = MixtureParams(logits.detach() - 0.1 * logits.grad, params.loc, params.log_scale)
    h_after = entropy_of_weights(stepped).item()
    assert (h_after > parts.entropy.item()) == (entropy_goes == "up")


# -- sampling --------------------------------------------------------------------------
def test_sample_shape_and_seeded_reproducibility():
    params = random_params(12, b=5, k=4, d=BOX_DIM)
    a = sample(params, 7, generator=torch.Generator().manual_seed(0))
    b = sample(params, 7, generator=torch.Generator().manual_seed(0))
    c = sample(params, 7, generator=torch.Generator().manual_seed(1))
    assert a.shape == (5, 7, BOX_DIM) and a.dtype == torch.float64
    assert torch.equal(a, b)
    assert not torch.equal(a, c)
    nested = MixtureParams(*(t.reshape(5, 1, *t.shape[1:]) for t in params))
    assert sample(nested, 3, generator=torch.Generator().manual_seed(0)).shape == (5, 1, 3, 12)


def test_sample_single_component_moments_and_distribution():
    loc = torch.tensor([[[1.5, -3.0]]], dtype=torch.float64).expand(2, 1, 2).clone()
    loc[1] = torch.tensor([[0.0, 10.0]])
    scale = torch.tensor([[[0.5, 2.0]], [[0.05, 1.0]]], dtype=torch.float64)  # (2, 1, 2)
    params = MixtureParams(torch.zeros(2, 1, dtype=torch.float64), loc, scale.log())
    n = 100_000
    x = sample(params, n, generator=torch.Generator().manual_seed(13))  # (2, n, 2)
    mean, var = x.mean(dim=1), x.var(dim=1)
    analytic_var = scale[:, 0] ** 2 * math.pi**2 / 3
    analytic_sd = analytic_var.sqrt()
    # 5 standard errors of the mean; the sample variance's relative sd is sqrt(3.2/n)
    assert torch.all((mean - loc[:, 0]).abs() < 5 * analytic_sd / math.sqrt(n))
    np.testing.assert_allclose(var.numpy(), analytic_var.numpy(), rtol=5 * math.sqrt(3.2 / n))
    for b in range(2):
        for j in range(2):
            ks = stats.kstest(x[b, :, j].numpy(), stats.logistic(loc[b, 0, j], scale[b, 0, j]).cdf)
            assert ks.pvalue > 1e-3


@pytest.mark.parametrize("temperature", [1.0, 0.5])
def test_component_choice_follows_tempered_weights(temperature):
    w = np.array([0.2, 0.3, 0.5])
    params = MixtureParams(
        logits=torch.tensor(np.log(w))[None],  # (1, 3)
        loc=torch.tensor([[[0.0], [100.0], [200.0]]], dtype=torch.float64),
        log_scale=torch.full((1, 3, 1), math.log(0.1), dtype=torch.float64),
    )
    n = 20_000
    x = sample(params, n, temperature, generator=torch.Generator().manual_seed(14))[0, :, 0]
    counts = np.bincount(np.rint(x.numpy() / 100.0).astype(int), minlength=3)
    assert counts.sum() == n and counts.size == 3
    expected = w ** (1 / temperature) / np.sum(w ** (1 / temperature))
    assert stats.chisquare(counts, expected * n).pvalue > 1e-3


def test_low_temperature_concentrates_at_mode():
    params = random_params(15, b=4, k=4, d=BOX_DIM)
    m = mode(params)  # (4, 12)
    heaviest = params.logits.argmax(dim=-1)
    np.testing.assert_array_equal(m.numpy(), params.loc[torch.arange(4), heaviest].numpy())
    cold = sample(params, 500, temperature=1e-3, generator=torch.Generator().manual_seed(16))
    assert (cold - m[:, None]).abs().max() < 0.1
    warm = sample(params, 500, temperature=1.0, generator=torch.Generator().manual_seed(16))
    assert (warm - m[:, None]).abs().max() > 1.0
    exact = sample(params, 3, temperature=0.0)
    assert torch.equal(exact, m[:, None].expand(4, 3, BOX_DIM))


def test_temperature_scales_spread():
    params = MixtureParams(
        torch.zeros(1, 1, dtype=torch.float64),
        torch.zeros(1, 1, 1, dtype=torch.float64),
        torch.zeros(1, 1, 1, dtype=torch.float64),
    )
    g = torch.Generator().manual_seed(17)
    full = sample(params, 4000, 1.0, generator=g)
    half = sample(params, 4000, 0.5, generator=torch.Generator().manual_seed(17))
    # same uniforms, one component: the draws are exactly the T=1 draws times T
    torch.testing.assert_close(half, 0.5 * full)


def _two_modes() -> MixtureParams:
    """Two 2D components, one mostly inside [-1, 1]^2, one mostly beyond x = 1."""
    return MixtureParams(
        logits=torch.tensor([[0.3, -0.2]], dtype=torch.float64),
        loc=torch.tensor([[[0.2, -0.4], [2.5, 0.3]]], dtype=torch.float64),
        log_scale=torch.tensor([[[-0.8, -1.0], [-0.2, -1.2]]], dtype=torch.float64),
    )


@pytest.mark.parametrize("temperature", [1.0, 0.7])
def test_windowed_draws_are_the_unconfined_draws_that_fall_inside(temperature):
    """A window gives the distribution rejection sampling would accept: compared, dim by
    dim, with unconfined draws filtered to the window; and its mass is the share of
    unconfined draws inside it."""
    params = _two_modes()
    window = Window([0, 1], torch.tensor([[-1.0, -1.0]]), torch.tensor([[1.0, 1.0]]))
    free = sample(params, 200_000, temperature, torch.Generator().manual_seed(3))[0].numpy()
    inside = free[(np.abs(free) <= 1.0).all(1)]
    confined = sample(params, 20_000, temperature, torch.Generator().manual_seed(4), window)
    confined = confined[0].numpy()
    assert (np.abs(confined) <= 1.0).all()
    for j in range(2):
        assert stats.ks_2samp(confined[:, j], inside[:, j]).pvalue > 1e-3
    share = len(inside) / len(free)
    mass = float(window_log_mass(params, window, temperature).exp())
    assert 0.2 < share < 0.9
    assert abs(mass - share) < 4 * math.sqrt(share * (1 - share) / len(free))


def test_a_window_far_in_a_tail_is_drawn_without_losing_precision():
    """A window 30 scales out (mass ~1e-13) still gives draws inside it, spread over it
    (the CDF near 1 has no digits left: the right tail is drawn mirrored)."""
    params = MixtureParams(
        torch.zeros(1, 1, dtype=torch.float64),
        torch.zeros(1, 1, 1, dtype=torch.float64),
        torch.zeros(1, 1, 1, dtype=torch.float64),
    )
    for low, high in [(30.0, 31.0), (-31.0, -30.0)]:
        window = Window([0], torch.tensor([[low]]), torch.tensor([[high]]))
        x = sample(params, 4000, 1.0, torch.Generator().manual_seed(5), window)[0, :, 0].numpy()
        assert np.isfinite(x).all() and (x >= low).all() and (x <= high).all()
        # the truncated density is ~exp(-(|x| - 30)): |x| - 30 has mean 1 - 1 / (e - 1)
        assert 0.40 < (np.abs(x) - 30).mean() < 0.44
        mass = float(window_log_mass(params, window))
        assert mass == pytest.approx(math.log(math.exp(-30) - math.exp(-31)), rel=1e-6)


def test_an_empty_window_draws_unconfined():
    """A window with no extent (high below low: a room narrower than the object) has no
    mass; its draws are the unconfined ones, rejected as they would be without it."""
    params = random_params(19, b=2, k=3, d=2)
    window = Window([0], torch.tensor([[1.0], [0.5]]), torch.tensor([[0.0], [0.5]]))
    assert torch.isinf(window_log_mass(params, window)).all()
    free = sample(params, 50, 1.0, torch.Generator().manual_seed(6))
    torch.testing.assert_close(
        sample(params, 50, 1.0, torch.Generator().manual_seed(6), window), free
    )


def test_sample_rejects_bad_arguments():
    params = random_params(18, b=1, k=2, d=2)
    with pytest.raises(ValueError, match="temperature"):
        sample(params, 3, temperature=-1.0)
    with pytest.raises(ValueError, match="n must"):
        sample(params, 0)


# -- box target ------------------------------------------------------------------------
def test_rotation_from_6d_matches_numpy_geometry():
    sixd = torch.randn(64, 6, generator=torch.Generator().manual_seed(19), dtype=torch.float64)
    np.testing.assert_allclose(
        rotation_from_6d(sixd).numpy(), sixd_to_matrix(sixd.numpy()), atol=1e-12
    )


def test_encode_decode_round_trip():
    n = 50
    g = torch.Generator().manual_seed(20)
    center = torch.randn(n, 3, generator=g, dtype=torch.float64)
    size = torch.rand(n, 3, generator=g, dtype=torch.float64) * 2.0 + 0.01
    rotation = random_rotations(21, n)
    x = encode_target(center, size, rotation)
    assert x.shape == (n, 12)
    np.testing.assert_allclose(x[:, 3:6].numpy(), np.log(size.numpy()))
    c, s, r = decode_target(x)
    torch.testing.assert_close(c, center)
    torch.testing.assert_close(s, size)
    torch.testing.assert_close(r, rotation)
    torch.testing.assert_close(rotation_to_6d(rotation), x[:, 6:])


def test_target_from_stored_box_vector():
    """The 3D-Pairs arrays hold OrientedBox.to_vector (raw size): the bridge takes the log."""
    box = OrientedBox.from_yaw([0.2, -0.5, 0.1], [0.4, 0.3, 0.05], yaw=0.7)
    stored = torch.from_numpy(box.to_vector())
    x = target_from_box_vector(stored)
    c, s, r = (t.numpy() for t in decode_target(x))
    assert OrientedBox(c, s, r).allclose(box, atol=1e-12)
    back = OrientedBox.from_vector(box_vector_from_target(x).numpy())
    assert back.allclose(box, atol=1e-12)
    zero = target_from_box_vector(torch.zeros(12, dtype=torch.float64))
    assert torch.isfinite(zero).all()


def test_decoded_samples_are_valid_boxes():
    params = random_params(22, b=3, k=4, d=BOX_DIM)
    x = sample(params, 100, generator=torch.Generator().manual_seed(23))
    center, size, rotation = decode_target(x)
    assert center.shape == (3, 100, 3) and size.shape == (3, 100, 3)
    assert rotation.shape == (3, 100, 3, 3)
    assert (size > 0).all()
    eye = torch.eye(3, dtype=torch.float64).expand_as(rotation)
    torch.testing.assert_close(rotation.transpose(-1, -2) @ rotation, eye)
    torch.testing.assert_close(torch.linalg.det(rotation), torch.ones(3, 100, dtype=torch.float64))


def test_rotation_offset_is_invertible_with_unit_jacobian_and_exact_for_upright():
    from pair2scene.model.mixture import rotation_offset

    g = torch.Generator().manual_seed(0)
    x = torch.randn(5, 12, generator=g, dtype=torch.float64)
    y = x - rotation_offset(x)
    torch.testing.assert_close(y + rotation_offset(y), x)
    jac = torch.autograd.functional.jacobian(lambda v: v - rotation_offset(v), x[0])
    assert torch.linalg.det(jac).item() == pytest.approx(1.0)
    yaw = torch.rand(7, generator=g, dtype=torch.float64) * 6.28
    c, s, z = torch.cos(yaw), torch.sin(yaw), torch.zeros(7, dtype=torch.float64)
    upright = torch.cat([torch.randn(7, 6, generator=g, dtype=torch.float64),
                         torch.stack([c, s, z, -s, c, z], 1)], 1)  # fmt: skip
    residual = upright - rotation_offset(upright)
    torch.testing.assert_close(residual[:, 9:12], torch.zeros(7, 3, dtype=torch.float64))

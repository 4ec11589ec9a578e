"""Right-angle yaw modes of the mixture head (:func:`mixture.turned_components`)."""

from __future__ import annotations

import math

import pytest
import torch

from pair2scene.model.mixture import (
    BOX_DIM,
    MixtureConfig,
    MixtureParams,
    entropy_of_weights,
    log_prob,
    mixture_params_from_head,
    sample,
    turned_components,
)


def _upright(yaw: torch.Tensor) -> torch.Tensor:
    """(N,) yaws -> (N, 12) targets of an upright unit box at the origin (residual base)."""
    x = torch.zeros(yaw.shape[0], BOX_DIM, dtype=torch.float64)
    x[:, 6], x[:, 7] = yaw.cos(), yaw.sin()
    return x


def _one_component(yaw: float, scale: float = 0.01) -> MixtureParams:
    loc = _upright(torch.tensor([yaw], dtype=torch.float64))[:, None]  # (1, 1, 12)
    log_scale = torch.full((1, 1, BOX_DIM), math.log(scale), dtype=torch.float64)
    log_scale[..., 6] = math.log(scale / 2)  # unequal x / y scales: they must swap
    return MixtureParams(torch.zeros(1, 1, dtype=torch.float64), loc, log_scale)


def test_each_copy_is_the_component_turned_by_a_quarter():
    params = _one_component(0.3)
    turned = turned_components(params, torch.zeros(1, 1, 4, dtype=torch.float64))
    assert turned.loc.shape == (1, 4, BOX_DIM)
    for q in range(4):
        expect = _upright(torch.tensor([0.3 + q * math.pi / 2], dtype=torch.float64))[0]
        torch.testing.assert_close(turned.loc[0, q], expect, atol=1e-12, rtol=0)
    # Scales of the turned pair swap on odd quarter turns, stay on even ones.
    sx, sy = params.log_scale[0, 0, 6], params.log_scale[0, 0, 7]
    assert [turned.log_scale[0, q, 6].item() for q in range(4)] == [sx, sy, sx, sy]
    assert [turned.log_scale[0, q, 7].item() for q in range(4)] == [sy, sx, sy, sx]
    # Dims that do not turn are shared.
    keep = [0, 1, 2, 3, 4, 5, 8, 11]
    torch.testing.assert_close(turned.loc[0, :, keep], params.loc[0, :, keep].expand(4, -1))


def test_weights_are_the_component_weight_split_by_the_turn_softmax():
    gen = torch.Generator().manual_seed(0)
    k, q = 3, 4
    base = MixtureParams(
        torch.randn(2, k, generator=gen),
        torch.randn(2, k, 12, generator=gen),
        torch.randn(2, k, 12, generator=gen),
    )
    turn = torch.randn(2, k, q, generator=gen)
    turned = turned_components(base, turn)
    w = torch.softmax(turned.logits, -1).reshape(2, k, q)
    torch.testing.assert_close(w.sum(-1), torch.softmax(base.logits, -1))
    torch.testing.assert_close(w / w.sum(-1, keepdim=True), torch.softmax(turn, -1))
    # The entropy term sees the K components, not the K * Q copies.
    torch.testing.assert_close(entropy_of_weights(turned, group=q), entropy_of_weights(base))


def test_uniform_turns_give_a_density_invariant_under_quarter_turns():
    params = _one_component(0.2, scale=0.05)
    turned = turned_components(params, torch.zeros(1, 1, 4, dtype=torch.float64))
    yaw = torch.linspace(-math.pi, math.pi, 37, dtype=torch.float64)
    here = log_prob(MixtureParams(*(t.expand(37, *t.shape[1:]) for t in turned)), _upright(yaw))
    there = log_prob(
        MixtureParams(*(t.expand(37, *t.shape[1:]) for t in turned)), _upright(yaw + math.pi / 2)
    )
    torch.testing.assert_close(here, there)
    # Without the turns the same component scores the turned yaw far lower.
    at_mode = _upright(torch.tensor([0.2 + math.pi / 2], dtype=torch.float64))
    assert log_prob(params, at_mode) < log_prob(turned, at_mode) - 50


def test_samples_fall_on_the_four_axes_in_the_turn_proportions():
    params = _one_component(0.0, scale=0.001)
    share = torch.tensor([0.1, 0.2, 0.3, 0.4], dtype=torch.float64)
    turned = turned_components(params, share.log()[None, None])
    x = sample(turned, 20000, generator=torch.Generator().manual_seed(1))[0]
    yaw = torch.atan2(x[:, 7], x[:, 6])
    quarter = torch.round(yaw / (math.pi / 2)).long() % 4
    assert (yaw - torch.round(yaw / (math.pi / 2)) * math.pi / 2).abs().max() < 0.05
    got = torch.bincount(quarter, minlength=4).double() / len(quarter)
    torch.testing.assert_close(got, share, atol=0.015, rtol=0)


def test_head_layout_with_and_without_turns():
    for q in (1, 2, 4):
        cfg = MixtureConfig(num_components=3, yaw_modes=q)
        raw = torch.randn(5, cfg.head_dim, generator=torch.Generator().manual_seed(q))
        params = mixture_params_from_head(raw, 3, BOX_DIM, yaw_modes=q)
        assert params.loc.shape == (5, 3 * q, BOX_DIM)
        assert torch.isfinite(params.logits).all()
        torch.testing.assert_close(
            torch.logsumexp(torch.log_softmax(params.logits, -1), -1),
            torch.zeros(5),
            atol=1e-6,
            rtol=0,
        )
    with pytest.raises(ValueError, match="K\\*\\(1\\+2D\\+Q\\)"):
        mixture_params_from_head(torch.zeros(1, 100), 4, BOX_DIM, yaw_modes=4)


def test_half_turns_flip_the_yaw():
    params = _one_component(0.4)
    turned = turned_components(params, torch.zeros(1, 1, 2, dtype=torch.float64))
    expect = _upright(torch.tensor([0.4 + math.pi], dtype=torch.float64))[0]
    torch.testing.assert_close(turned.loc[0, 1], expect, atol=1e-12, rtol=0)
    torch.testing.assert_close(turned.log_scale[0, 1], params.log_scale[0, 0])


def test_old_checkpoint_configs_load_without_turns():
    from pair2scene.model.checkpoint import layout_config_from_dict, layout_config_to_dict
    from pair2scene.model.layout import LayoutConfig

    doc = layout_config_to_dict(LayoutConfig())
    del doc["mixture"]["yaw_modes"]
    assert layout_config_from_dict(doc).mixture.yaw_modes == 1
    assert LayoutConfig().mixture.yaw_modes == 4

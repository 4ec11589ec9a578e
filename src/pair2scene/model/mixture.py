"""Mixture of logistics over the dependent's box: the layout model's output distribution.

The layout head predicts, per relation tuple, a mixture of K logistics (the paper
uses K = 4) over a D-dimensional vector, D = 12 for a box. Within a component
the D dimensions are independent (diagonal), each a continuous logistic with
its own location and scale:

    p(x) = sum_k w_k prod_d Logistic(x_d; mu_kd, s_kd),   w = softmax(logits)

Everything here is a small standalone function over tensors with any leading
batch shape ``(...)``; the shapes below write it as ``(B, ...)``.

Target convention (owned here; the dataset, the model and assembly use it)
---------------------------------------------------------------------------
The 12-d vector the mixture models is the dependent's box in the support
anchor's canonical frame (architecture.md), as

    x = (centre (3), log size (3), 6D rotation (6))

- centre: canonical-frame centre (the anchor is the cube [-1, 1]^3);
- log size: natural log of the canonical-frame full size. Canonical sizes are
  ratios (dependent size / anchor half-size) that span orders of magnitude (a
  pen on a desk ~0.05, a bed in a room ~0.5); in log space an error means the
  same relative error for both, and every sample decodes to a positive size;
- 6D rotation: the first two columns of the canonical-frame rotation,
  concatenated (column 0 then column 1), as :func:`pair2scene.scene.geometry.matrix_to_6d`;
  decoded by Gram-Schmidt (:func:`rotation_from_6d`).

Beware: :meth:`OrientedBox.to_vector` and the 3D-Pairs shard arrays
(``canonical``, ``*_box``) hold the *size*, not its log. Convert with
:func:`target_from_box_vector` / :func:`box_vector_from_target`, or build the
target from parts with :func:`encode_target` / :func:`decode_target`.

Head layout
-----------
:func:`mixture_params_from_head` reads a flat head output ``(B, K * (1 + 2D) + K * Q)``
as ``[logits (K) | loc (K*D) | log-scale (K*D) | turn logits (K*Q)]``, each block
component-major (component k's D values are contiguous); the last block is absent
for Q = 1.

Right-angle yaw modes
---------------------
Objects stand at right angles to what they stand on: 92 % of the upright objects on
furniture in the training tuples are within 2 degrees of one of their support's four
axes, and which of the four is nearly independent of where the object stands (a mug,
a book, a lamp on a desk). A diagonal logistic over ``(cos t, sin t)`` holds one such
yaw per component, so K components had to split between position modes and yaws,
and the fitted yaw scales came out broad (the per-dimension NLL of the cos / sin
dims on val support tuples: -0.42 / -0.61 nats against the per-pair Gaussian's
-3.85 / -3.78, ``benchmarks/support_nats.py``). With ``yaw_modes`` Q > 1 each
component comes in Q copies, its yaw turned by ``q * 360 / Q`` degrees
(``q = 0..Q-1``), with their own weights (softmax of the turn logits) and everything
else shared: the rotation dims (c0_x, c0_y) and the upright residual (dims 9, 10)
turn as 2D vectors, their scales swap for odd quarter turns. The result is a plain
mixture of K * Q diagonal logistics (:func:`turned_components`), so densities,
sampling, conditioning and windows are unchanged; only the entropy term is taken
over the K components' total weights (a spread of turns is not a spread of modes).

Entropy regulariser
-------------------
The training loss is ``NLL -/+ entropy_weight * H(w)`` with ``H`` the entropy of
the mixture weights. The default sign is a *bonus* (the loss subtracts
``lambda * H``, so minimising it keeps the weights spread): maximum likelihood
alone tends to starve components early in training (a component that wins no
data gets no gradient and its weight keeps falling), and placement is
genuinely multimodal (a chair on either side of a desk, a lamp on either
nightstand side), which the sampler can only reproduce if several components
stay alive. The bonus is bounded (``H <= log K``), so it cannot dominate the
NLL, and at a small weight it only decides between solutions the NLL is
indifferent to. The *penalty* sign (``+ lambda * H``) is the other reading of
"an entropy regulariser": it makes each prediction commit to few components
(sharper, more decisive samples at the risk of dropping modes); it is kept as
a config choice so the two can be compared on val NLL and sample diversity.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import NamedTuple

import torch
import torch.nn.functional as F
from torch import Tensor

from pair2scene.model.config import (  # noqa: F401  (re-exported)
    BOX_DIM,
    CONDITIONED_LOG_SCALE,
    GRAM_SCHMIDT_EPS,
    MAX_ABS_LOCATION,
    MIN_TARGET_SIZE,
    ROTATION_PAIRS,
    EntropyRegulariser,
    InvalidDistribution,
    MixtureConfig,
    check_draw,
)


class MixtureParams(NamedTuple):
    """Parameters of a batch of diagonal logistic mixtures."""

    logits: Tensor
    """(B, K) unnormalised log mixture weights."""
    loc: Tensor
    """(B, K, D) locations mu."""
    log_scale: Tensor
    """(B, K, D) log scales log s."""


class LossParts(NamedTuple):
    """The terms of :func:`loss`, detached, for logging (``._asdict()`` gives a dict)."""

    nll: Tensor
    """() mean negative log-likelihood in nats."""
    entropy: Tensor
    """() mean entropy of the mixture weights in nats."""


# -- head -> parameters --------------------------------------------------------------
def soft_clamp(x: Tensor, low: float, high: float) -> Tensor:
    """Smoothly bound ``x`` to about ``(low, high)``; close to the identity inside it.

    ``high - softplus(high - (low + softplus(x - low)))``: unlike a hard clamp the
    gradient never vanishes exactly, so a head pushed past a bound can come back.
    Inside the bounds it differs from ``x`` by about exp(-distance to the nearer
    bound) (0.02 at 4 units), so a head initialised near 0 starts at log scale ~0.
    The result lies in ``(low - log1p(exp(low - high)), high)``: ``low`` up to
    6e-6 for the default bounds.
    """
    return high - F.softplus(high - (low + F.softplus(x - low)))


def mixture_params_from_head(
    raw: Tensor,
    k: int,
    d: int = BOX_DIM,
    min_log_scale: float = -7.0,
    max_log_scale: float = 5.0,
    yaw_modes: int = 1,
) -> MixtureParams:
    """Split a flat head output into mixture parameters.

    raw : (B, K * (1 + 2D) [+ K * Q]) laid out ``[logits (K) | loc (K*D) | log-scale
    (K*D) | turn logits (K*Q), Q > 1 only]``. The log scales pass through
    :func:`soft_clamp` to ``[min_log_scale, max_log_scale]``; logits and locations are
    used as they are. For Q > 1 the result has K * Q components
    (:func:`turned_components`).
    """
    turns = yaw_modes if yaw_modes > 1 else 0
    if raw.shape[-1] != k * (1 + 2 * d + turns):
        raise ValueError(
            f"head output has {raw.shape[-1]} values, expected K*(1+2D+Q) = "
            f"{k * (1 + 2 * d + turns)} for K={k}, D={d}, Q={yaw_modes}"
        )
    batch = raw.shape[:-1]
    logits, loc, log_scale, turn = raw.split([k, k * d, k * d, k * turns], dim=-1)
    loc = loc.reshape(*batch, k, d)  # (B, K, D)
    log_scale = log_scale.reshape(*batch, k, d)  # (B, K, D)
    params = MixtureParams(logits, loc, soft_clamp(log_scale, min_log_scale, max_log_scale))
    if turns:
        params = turned_components(params, turn.reshape(*batch, k, turns))
    return params


def turned_components(params: MixtureParams, turn_logits: Tensor) -> MixtureParams:
    """Each of K components in Q copies, its yaw turned by ``q * 360 / Q`` degrees.

    params : K components over the 12-d box; turn_logits : (B, K, Q). Returns K * Q
    components, component-major (copy ``k * Q + q`` is component k turned q times), with
    log weights ``log w_k + log softmax(turn_logits_k)_q``: a normalised mixture whose
    weights per component sum to the component's.
    """
    q = turn_logits.shape[-1]
    logits = F.log_softmax(params.logits, -1)[..., None] + F.log_softmax(turn_logits, -1)
    loc = params.loc.unsqueeze(-2).repeat_interleave(q, dim=-2)  # (B, K, Q, D)
    log_scale = params.log_scale.unsqueeze(-2).repeat_interleave(q, dim=-2)
    angle = torch.arange(q, device=loc.device, dtype=loc.dtype) * (2 * math.pi / q)
    cos, sin = angle.cos().round(decimals=12), angle.sin().round(decimals=12)  # (Q,)
    swap = (torch.arange(q, device=loc.device) * 4 // q) % 2 == 1  # odd quarter turns
    loc, log_scale = loc.clone(), log_scale.clone()
    for x, y in ROTATION_PAIRS:
        mx, my = params.loc[..., x, None], params.loc[..., y, None]  # (B, K, 1)
        loc[..., x] = cos * mx - sin * my
        loc[..., y] = sin * mx + cos * my
        sx, sy = params.log_scale[..., x, None], params.log_scale[..., y, None]
        log_scale[..., x] = torch.where(swap, sy, sx)
        log_scale[..., y] = torch.where(swap, sx, sy)
    batch, k = params.logits.shape[:-1], params.logits.shape[-1]
    d = params.loc.shape[-1]
    return MixtureParams(
        logits.reshape(*batch, k * q),
        loc.reshape(*batch, k * q, d),
        log_scale.reshape(*batch, k * q, d),
    )


# -- density -------------------------------------------------------------------------
def logistic_log_pdf(x: Tensor, loc: Tensor, log_scale: Tensor) -> Tensor:
    """Elementwise log density of Logistic(loc, exp(log_scale)) at ``x`` (broadcast).

    log p = -z - log s - 2 softplus(-z) with z = (x - mu) / s; the density is
    symmetric in z, so it is evaluated at -|z| where nothing overflows or cancels.
    """
    a = ((x - loc) * torch.exp(-log_scale)).abs()
    return -a - 2.0 * F.softplus(-a) - log_scale


def log_prob(params: MixtureParams, x: Tensor) -> Tensor:
    """Log density of each mixture at its point: x (B, D) -> (B,)."""
    log_comp = logistic_log_pdf(x.unsqueeze(-2), params.loc, params.log_scale)  # (B, K, D)
    log_comp = log_comp.sum(dim=-1)  # (B, K)
    return torch.logsumexp(F.log_softmax(params.logits, dim=-1) + log_comp, dim=-1)


def entropy_of_weights(params: MixtureParams, group: int = 1) -> Tensor:
    """Entropy (nats) of the mixture weights: (B,); 0 for one component, log K uniform.

    group : consecutive components counted as one (the Q turned copies of a component,
    :func:`turned_components`): the entropy of their summed weights."""
    log_w = F.log_softmax(params.logits, dim=-1)
    if group > 1:
        log_w = torch.logsumexp(log_w.unflatten(-1, (-1, group)), dim=-1)
    return -(log_w.exp() * log_w).sum(dim=-1)


def loss(
    params: MixtureParams,
    x: Tensor,
    entropy_weight: float = 0.0,
    regulariser: EntropyRegulariser = EntropyRegulariser.BONUS,
    group: int = 1,
) -> tuple[Tensor, LossParts]:
    """Mean NLL of ``x`` (B, D) plus the entropy term; returns (scalar loss, parts).

    BONUS: ``nll - entropy_weight * H``; PENALTY: ``nll + entropy_weight * H``, with H
    the batch-mean entropy of the mixture weights (see the module docstring), of each
    ``group`` consecutive components' total (:func:`entropy_of_weights`).
    """
    nll = -log_prob(params, x).mean()
    entropy = entropy_of_weights(params, group).mean()
    sign = -1.0 if EntropyRegulariser(regulariser) is EntropyRegulariser.BONUS else 1.0
    total = nll + sign * entropy_weight * entropy
    return total, LossParts(nll.detach(), entropy.detach())


# -- the upright-rotation base ----------------------------------------------------------
def rotation_offset(x: Tensor) -> Tensor:
    """(..., 12) box targets -> (..., 12) offsets: ``e_z x c0`` on the second rotation column
    (dims 9, 10: ``(-c0_y, c0_x)``), zero elsewhere.

    For an upright object (the vast majority: every yaw of a chair, a bed, a mug) the 6D
    rotation is ``c0 = (cos t, sin t, 0)``, ``c1 = (-sin t, cos t, 0)``: the second column
    is fixed by the first, but a diagonal mixture cannot express that for yaws between its
    components' modes. The mixture therefore models ``y = x - rotation_offset(x)``; the map
    only shifts c1 by a function of c0 (unchanged), so it is invertible with a unit
    Jacobian (``x = y + rotation_offset(y)``) and densities of y are densities of x. Tilted
    objects keep a non-zero residual, modelled like any other number.
    """
    out = torch.zeros_like(x)
    out[..., 9] = -x[..., 7]
    out[..., 10] = x[..., 6]
    return out


# -- conditioning --------------------------------------------------------------------
def condition(params: MixtureParams, dims: Sequence[int], values: Tensor) -> MixtureParams:
    """The mixture conditioned on ``x[dims] = values``, over all D dims (exact).

    Within a component the dims are independent, so conditioning only reweights the
    components by how well each explains the given values: ``logits_k + log p_k(values)``.
    The given dims' locations are set to the values and their scales to the floor of a
    float, so samples reproduce them (to within ~1e-30).

    values : (B, len(dims)) in the target's units (a size goes in as its log).
    """
    dims = list(dims)
    loc = params.loc.clone()
    log_scale = params.log_scale.clone()
    given = values.unsqueeze(-2)  # (B, 1, d)
    log_fit = logistic_log_pdf(given, params.loc[..., dims], params.log_scale[..., dims])
    logits = params.logits + log_fit.sum(-1)  # (B, K)
    loc[..., dims] = given.expand_as(loc[..., dims])
    log_scale[..., dims] = CONDITIONED_LOG_SCALE
    return MixtureParams(logits, loc, log_scale)


# -- sampling ------------------------------------------------------------------------
def check_params(params: MixtureParams) -> None:
    """Raise :class:`InvalidDistribution` unless every mixture can be drawn from: its
    locations finite and within :data:`MAX_ABS_LOCATION`, its log scales finite (a scale
    of exp(-inf) = 0 or inf is none), its weights ``softmax(logits)`` finite (NaN or +inf
    logits, or all of a row's at -inf, are no distribution; single -inf logits are zero
    weights and fine). One reduction per tensor and one host sync in the normal case."""
    logits, loc, log_scale = params
    weights = torch.softmax(logits.detach(), dim=-1)
    ok = (loc.detach().abs() <= MAX_ABS_LOCATION).all()  # False for NaN and inf too
    ok &= torch.isfinite(log_scale.detach()).all() & torch.isfinite(weights).all()
    if bool(ok):
        return
    if not torch.isfinite(weights).all():
        raise InvalidDistribution("mixture weights are not finite")
    if not torch.isfinite(loc).all():
        raise InvalidDistribution("non-finite locations")
    if not (loc.abs() <= MAX_ABS_LOCATION).all():
        far = float(loc.detach().abs().max())
        raise InvalidDistribution(f"a location of {far:.3g}, beyond {MAX_ABS_LOCATION:g}")
    raise InvalidDistribution("non-finite or zero scales")


def mode(params: MixtureParams) -> Tensor:
    """Location of the heaviest component: (B, D).

    Deterministic stand-in for the mixture's mode (exact when the components are
    well separated); what :func:`sample` returns at temperature 0.
    """
    k = params.logits.argmax(dim=-1)  # (B,)
    d = params.loc.shape[-1]
    index = k[..., None, None].expand(*k.shape, 1, d)  # (B, 1, D)
    return params.loc.gather(-2, index).squeeze(-2)


class Window(NamedTuple):
    """An axis-aligned box over some of the mixture's dims: ``low <= x[dims] <= high``."""

    dims: Sequence[int]
    low: Tensor
    """(B, len(dims)) lower bounds, one row per mixture."""
    high: Tensor
    """(B, len(dims)) upper bounds (>= low)."""


def _mirrored(a: Tensor, b: Tensor) -> tuple[Tensor, Tensor, Tensor]:
    """Standardised intervals [a, b] moved off the right tail: where a > 0 the interval
    is mirrored to [-b, -a], where sigmoid keeps its digits (near 1 it has none).
    Returns (mirrored, lo, hi)."""
    right = a > 0
    return right, torch.where(right, -b, a), torch.where(right, -a, b)


def _log_interval(a: Tensor, b: Tensor) -> Tensor:
    """log(sigmoid(b) - sigmoid(a)) elementwise for a <= b, accurate in both tails."""
    _, lo, hi = _mirrored(a, b)
    log_hi, log_lo = F.logsigmoid(hi), F.logsigmoid(lo)
    diff = (log_lo - log_hi).clamp_max(0.0)
    return log_hi + torch.log((-torch.expm1(diff)).clamp_min(0.0))


def _window_terms(params: MixtureParams, window: Window, temperature: float):
    """The window in each component's standardised units, a and b (..., K, len(dims)),
    and each component's log mass in it (..., K); returned as float64."""
    dims = list(window.dims)
    loc = params.loc[..., dims]
    scale = params.log_scale[..., dims].exp() * temperature
    low = window.low.to(loc.dtype).unsqueeze(-2)
    high = torch.maximum(window.high.to(loc.dtype), window.low.to(loc.dtype)).unsqueeze(-2)
    a, b = ((low - loc) / scale).double(), ((high - loc) / scale).double()
    return a, b, _log_interval(a, b).sum(-1)


def window_log_mass(params: MixtureParams, window: Window, temperature: float = 1.0) -> Tensor:
    """Log probability that a draw at ``temperature`` (see :func:`sample`) falls in the
    window: (B,) float64 (-inf where it cannot)."""
    log_mass = _window_terms(params, window, temperature)[2]
    log_w = torch.log_softmax(params.logits.double() / temperature, dim=-1)
    return torch.logsumexp(log_w + log_mass, dim=-1)


def sample(
    params: MixtureParams,
    n: int,
    temperature: float = 1.0,
    generator: torch.Generator | None = None,
    window: Window | None = None,
) -> Tensor:
    """Draw ``n`` candidates from each mixture: -> (B, n, D).

    The temperature T sharpens both levels: components are drawn with weights
    softmax(logits / T) (proportional to w^(1/T)) and each logistic's scale is
    multiplied by T. T = 1 is the learned distribution; T -> 0 concentrates on the
    heaviest component's location, and T = 0 returns exactly :func:`mode`.
    Logistics are drawn by the inverse CDF, mu + T s log(u / (1 - u)). The
    ``generator`` must live on the parameters' device.

    window : draws confined to it, from the (tempered) mixture restricted to it, exactly
    the draws that would remain of unconfined ones after discarding those outside:
    each component is weighted by its mass in the window as well, and each windowed dim
    drawn by the inverse CDF of its logistic truncated to the interval. A mixture with
    no mass in its window (none in float64) draws as if it had none. Ignored at T = 0.

    Parameters no draw can come from (:func:`check_params`), or draws that come out
    non-finite, raise :class:`InvalidDistribution` (a :class:`~pair2scene.errors.UserError`:
    the checkpoint is broken), never torch's own error.
    """
    check_draw(temperature, n)
    check_params(params)
    logits, loc, log_scale = params
    batch, (k, d) = logits.shape[:-1], loc.shape[-2:]
    if temperature == 0:
        return mode(params).unsqueeze(-2).expand(*batch, n, d).clone()

    # torch.multinomial takes at most 2 dims: flatten the batch to M rows.
    tempered = logits.reshape(-1, k) / temperature
    if window is not None:
        a, b, log_mass = _window_terms(params, window, temperature)
        m = len(window.dims)
        a, b, log_mass = a.reshape(-1, k, m), b.reshape(-1, k, m), log_mass.reshape(-1, k)
        empty = torch.isinf(torch.logsumexp(tempered.double() + log_mass, -1))  # (M,)
        # A row with no mass in its window is drawn unconfined: its bounds are opened.
        log_mass = torch.where(empty[:, None], 0.0, log_mass)
        a = torch.where(empty[:, None, None], -math.inf, a)
        b = torch.where(empty[:, None, None], math.inf, b)
        tempered = (tempered.double() + log_mass).to(tempered.dtype)
    probs = torch.softmax(tempered, dim=-1)  # (M, K)
    if not torch.isfinite(probs).all():  # finite logits / T can still overflow
        raise InvalidDistribution(f"mixture weights are not finite at temperature {temperature}")
    comp = torch.multinomial(probs, n, replacement=True, generator=generator)  # (M, n)
    index = comp.unsqueeze(-1).expand(-1, -1, d)  # (M, n, D)
    mu = loc.reshape(-1, k, d).gather(1, index)  # (M, n, D)
    scale = log_scale.reshape(-1, k, d).gather(1, index).exp() * temperature  # (M, n, D)
    u = torch.rand(mu.shape, generator=generator, dtype=mu.dtype, device=mu.device)
    u = u.clamp_min(torch.finfo(mu.dtype).tiny)  # rand is in [0, 1): only 0 needs care
    z = torch.log(u) - torch.log1p(-u)
    if window is not None:
        dims = list(window.dims)
        pick = comp.unsqueeze(-1).expand(-1, -1, len(dims))
        z[..., dims] = _truncated_logistic(
            a.gather(1, pick), b.gather(1, pick), u[..., dims].double()
        ).to(z.dtype)
    x = mu + scale * z
    if not torch.isfinite(x).all():
        raise InvalidDistribution(f"non-finite draws at temperature {temperature}")
    return x.reshape(*batch, n, d)  # (B, n, D)


def _truncated_logistic(a: Tensor, b: Tensor, u: Tensor) -> Tensor:
    """Standard logistic draws truncated to [a, b] by the inverse CDF at ``u`` in [0, 1)
    (drawn on the :func:`_mirrored` interval and mirrored back)."""
    right, lo, hi = _mirrored(a, b)
    p_lo, p_hi = torch.sigmoid(lo), torch.sigmoid(hi)
    p = (p_lo + u * (p_hi - p_lo)).clamp(torch.finfo(u.dtype).tiny, 1.0 - 1e-16)
    z = (torch.log(p) - torch.log1p(-p)).clamp(lo, hi)
    return torch.where(right, -z, z)


# -- box vector <-> (centre, size, rotation) -----------------------------------------
def rotation_from_6d(sixd: Tensor, eps: float = GRAM_SCHMIDT_EPS) -> Tensor:
    """Gram-Schmidt a 6D vector (first two columns) to a rotation: (..., 6) -> (..., 3, 3).

    Torch twin of :func:`pair2scene.scene.geometry.sixd_to_matrix` (same columns, same
    eps): differentiable, and any 6D a sampler produces maps to a proper rotation
    unless its two halves are parallel.
    """
    a, b = sixd[..., :3], sixd[..., 3:6]
    c0 = a / a.norm(dim=-1, keepdim=True).clamp_min(eps)
    b = b - (c0 * b).sum(dim=-1, keepdim=True) * c0
    c1 = b / b.norm(dim=-1, keepdim=True).clamp_min(eps)
    c2 = torch.linalg.cross(c0, c1, dim=-1)
    return torch.stack([c0, c1, c2], dim=-1)  # (..., 3, 3) columns


def rotation_to_6d(rotation: Tensor) -> Tensor:
    """First two columns of a rotation, concatenated: (..., 3, 3) -> (..., 6)."""
    return torch.cat([rotation[..., :, 0], rotation[..., :, 1]], dim=-1)


def encode_target(center: Tensor, size: Tensor, rotation: Tensor) -> Tensor:
    """Canonical-frame box -> model target (..., 12): centre, log size, 6D rotation.

    center : (..., 3); size : (..., 3) full extent, clamped to :data:`MIN_TARGET_SIZE`;
    rotation : (..., 3, 3).
    """
    log_size = size.clamp_min(MIN_TARGET_SIZE).log()
    return torch.cat([center, log_size, rotation_to_6d(rotation)], dim=-1)


def decode_target(x: Tensor) -> tuple[Tensor, Tensor, Tensor]:
    """Model target or sample (..., 12) -> (centre (..., 3), size (..., 3), rotation (..., 3, 3)).

    Size is exp(log size), so always positive; the rotation is the Gram-Schmidt of
    the 6D part, so always proper even for raw samples.
    """
    return x[..., :3], x[..., 3:6].exp(), rotation_from_6d(x[..., 6:12])


def target_from_box_vector(vec: Tensor) -> Tensor:
    """Stored box vector (centre, size, 6D) (..., 12) -> model target (..., 12).

    The stored layout is :meth:`OrientedBox.to_vector`'s, as in the 3D-Pairs shards.
    """
    log_size = vec[..., 3:6].clamp_min(MIN_TARGET_SIZE).log()
    return torch.cat([vec[..., :3], log_size, vec[..., 6:12]], dim=-1)


def box_vector_from_target(x: Tensor) -> Tensor:
    """Model target or sample (..., 12) -> box vector (centre, size, 6D) (..., 12).

    The 6D part is orthonormalised, so :meth:`OrientedBox.from_vector` reads it as is.
    """
    center, size, rotation = decode_target(x)
    return torch.cat([center, size, rotation_to_6d(rotation)], dim=-1)

"""Point-MAE: the geometry encoder of the layout model, and its masked-autoencoder pre-training.

Pure PyTorch (no CUDA extensions), after Pang et al., "Masked Autoencoders for
Point Cloud Self-supervised Learning" (ECCV 2022):

1. grouping: farthest point sampling picks G group centres from the N points,
   and each centre's k nearest points, relative to the centre, form its group;
2. a mini-PointNet embeds each group into one token of width D;
3. a pre-norm transformer encodes the tokens; a positional embedding (an MLP
   of the group centres) is added before every block, as in Point-MAE;
4. pre-training masks a random 60 % of the groups, encodes only the visible
   ones, and a light decoder reconstructs the masked groups' points from mask
   tokens placed at the masked centres (Chamfer-L2).

The layout model consumes :class:`PointMAEEncoder`: ``encoder(points (B, N, 3))
-> (tokens (B, G, D), centers (B, G, 3))``.

Input normalisation (owned here; pre-training and the layout model both use it)
------------------------------------------------------------------------------
The encoder sees a cloud in the object's local frame, translated so that the
object's box centre is the origin and divided by the box's half-diagonal
``|size| / 2`` (:func:`normalise_points`). The box then fits the unit sphere
exactly (its corners lie on it), so every point lies in the unit ball,
whatever the object's size. The scale is uniform, so aspect ratios (a flat
plate versus a tall bottle) stay visible to the encoder; orientation is kept
too (+y is the front), since the layout depends on it. The absolute size is
*not* in the tokens: the layout model takes it as a separate input (the box
size, or :func:`normalise_points`' returned half-diagonal). Using the box, not
the cloud's own bounds, makes the normalisation known before any point is
sampled and identical for every cloud of the same asset.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import partial

import numpy as np
import torch
import torch.nn as nn
import torch.nn.functional as F
from torch import Tensor

from pair2scene.model.config import MIN_HALF_DIAGONAL, PointMAEConfig  # noqa: F401


# -- normalisation ---------------------------------------------------------------------
def normalise_points(
    points: Tensor, size: Tensor, center: Tensor | None = None
) -> tuple[Tensor, Tensor]:
    """Map a cloud into the unit ball by its box (see the module docstring).

    points : (..., N, 3) in the object's local frame, metres.
    size : (..., 3) full box extent along local x, y, z.
    center : (..., 3) box centre in the same frame; default the origin (an asset's
        local frame is centred on its box).
    Returns the normalised points (..., N, 3) and the half-diagonal (...,) used.
    """
    half_diag = (0.5 * torch.linalg.vector_norm(size, dim=-1)).clamp_min(MIN_HALF_DIAGONAL)
    if center is not None:
        points = points - center.unsqueeze(-2)
    return points / half_diag[..., None, None], half_diag


# -- grouping --------------------------------------------------------------------------
@torch.no_grad()
def farthest_point_sample(
    points: Tensor, m: int, generator: torch.Generator | None = None
) -> Tensor:
    """Indices of ``m`` points chosen by farthest point sampling, per cloud.

    points : (B, N, 3). The first pick is point 0 (deterministic) or, given a
    ``generator``, a random point per cloud; each next pick is the point farthest
    from all picked so far (ties: the lowest index). Returns idx (B, m) int64.
    """
    b, n, _ = points.shape
    if not 0 < m <= n:
        raise ValueError(f"farthest_point_sample: need 0 < m <= N, got m={m}, N={n}")
    if generator is None:
        first = torch.zeros(b, dtype=torch.long, device=points.device)
    else:
        first = torch.randint(n, (b,), generator=generator, device=generator.device)
        first = first.to(points.device)
    if points.device.type == "cpu":
        return _farthest_on_cpu(points.detach().numpy(), m, first.numpy())
    idx = torch.empty(b, m, dtype=torch.long, device=points.device)
    dist = torch.full((b, n), float("inf"), dtype=points.dtype, device=points.device)
    rows = torch.arange(b, device=points.device)
    current = first
    for i in range(m):
        idx[:, i] = current
        d = ((points - points[rows, current].unsqueeze(1)) ** 2).sum(-1)  # (B, N)
        dist = torch.minimum(dist, d)
        current = dist.argmax(dim=1)
    return idx


def _farthest_on_cpu(points: np.ndarray, m: int, first: np.ndarray) -> Tensor:
    """:func:`farthest_point_sample` in numpy, the same picks (the same float32 sums, in
    the same order: (dx^2 + dy^2) + dz^2; the lowest index of a tie): each of the m steps
    is a handful of numpy calls, where torch's per-call cost made a cloud's 32 steps
    3-12x slower (one cloud / a batch of 64)."""
    b, n, _ = points.shape
    x, y, z = (np.ascontiguousarray(points[:, :, k]) for k in range(3))  # (B, N) each
    idx = np.empty((b, m), dtype=np.int64)
    dist = np.full((b, n), np.inf, dtype=points.dtype)
    rows = np.arange(b)
    current = first.astype(np.int64)
    for i in range(m):
        idx[:, i] = current
        d = (x - x[rows, current][:, None]) ** 2 + (y - y[rows, current][:, None]) ** 2
        d += (z - z[rows, current][:, None]) ** 2
        np.minimum(dist, d, out=dist)
        current = dist.argmax(axis=1)
    return torch.from_numpy(idx)


def gather_points(points: Tensor, idx: Tensor) -> Tensor:
    """points (B, N, C), idx (B, *S) -> (B, *S, C)."""
    b, c = points.shape[0], points.shape[-1]
    flat = idx.reshape(b, -1)  # (B, S)
    out = torch.gather(points, 1, flat.unsqueeze(-1).expand(-1, -1, c))  # (B, S, C)
    return out.reshape(*idx.shape, c)


def knn_indices(points: Tensor, centers: Tensor, k: int) -> Tensor:
    """Indices (B, G, k) of the ``k`` points (B, N, 3) nearest each centre (B, G, 3),
    nearest first."""
    d = torch.cdist(centers, points)  # (B, G, N)
    return d.topk(k, dim=-1, largest=False, sorted=True).indices


def knn_group(points: Tensor, centers: Tensor, k: int) -> Tensor:
    """The ``k`` nearest points of each centre, relative to it: (B, G, k, 3), nearest first.

    points : (B, N, 3); centers : (B, G, 3).
    """
    idx = knn_indices(points, centers, k)
    return gather_points(points, idx) - centers.unsqueeze(2)


# -- loss ------------------------------------------------------------------------------
def chamfer_l2(a: Tensor, b: Tensor) -> Tensor:
    """Chamfer-L2 between matching point sets, averaged over the sets: (B,).

    a : (B, M, k, 3), b : (B, M, k', 3): M pairs of sets per batch row. Per pair,
    the mean squared distance from each point of ``a`` to its nearest in ``b``
    plus the same from ``b`` to ``a`` (Point-MAE's ChamferDistanceL2).
    """
    d = ((a.unsqueeze(3) - b.unsqueeze(2)) ** 2).sum(-1)  # (B, M, k, k')
    per_set = d.min(dim=3).values.mean(-1) + d.min(dim=2).values.mean(-1)  # (B, M)
    return per_set.mean(-1)


# -- building blocks -------------------------------------------------------------------
def _pool(f: Tensor, keepdim: bool = False) -> Tensor:
    """Max over a group's points (dim 2). Without gradients ``amax``: the same values,
    without the indices ``max`` also finds (10x the cost at inference); with them
    ``max``, whose gradient goes to one point of a tie, as the bundled model was
    trained."""
    if f.requires_grad:
        return f.max(dim=2, keepdim=keepdim).values
    return f.amax(dim=2, keepdim=keepdim)


class MiniPointNet(nn.Module):
    """Embeds each group of points into one token (Point-MAE's two-stage PointNet).

    Stage 1: shared MLP per point, then max-pool a group feature; stage 2: each
    point's feature concatenated with its group feature, another shared MLP,
    max-pool. Layer norm instead of Point-MAE's batch norm, so a token does not
    depend on what else is in the batch (train and eval behave the same).
    """

    def __init__(self, out_dim: int, hidden: int) -> None:
        super().__init__()
        self.first = nn.Sequential(
            nn.Linear(3, hidden), nn.LayerNorm(hidden), nn.GELU(), nn.Linear(hidden, 2 * hidden)
        )
        self.second = nn.Sequential(
            nn.Linear(4 * hidden, 4 * hidden),
            nn.LayerNorm(4 * hidden),
            nn.GELU(),
            nn.Linear(4 * hidden, out_dim),
        )

    def forward(self, groups: Tensor) -> Tensor:
        """groups (B, G, k, 3) -> tokens (B, G, out_dim)."""
        f = self.first(groups)  # (B, G, k, 2h)
        g = _pool(f, keepdim=True).expand_as(f)  # (B, G, k, 2h)
        f = self.second(torch.cat([f, g], dim=-1))  # (B, G, k, D)
        return _pool(f)


class SelfAttention(nn.Module):
    def __init__(self, width: int, heads: int, dropout: float) -> None:
        super().__init__()
        self.heads = heads
        self.qkv = nn.Linear(width, 3 * width)
        self.proj = nn.Linear(width, width)
        self.dropout = dropout

    def forward(self, x: Tensor) -> Tensor:
        b, t, d = x.shape
        q, k, v = self.qkv(x).split(d, dim=2)
        q = q.view(b, t, self.heads, d // self.heads).transpose(1, 2)  # (B, nh, T, hs)
        k = k.view(b, t, self.heads, d // self.heads).transpose(1, 2)  # (B, nh, T, hs)
        v = v.view(b, t, self.heads, d // self.heads).transpose(1, 2)  # (B, nh, T, hs)
        p = self.dropout if self.training else 0.0
        y = F.scaled_dot_product_attention(q, k, v, dropout_p=p)  # (B, nh, T, hs)
        y = y.transpose(1, 2).reshape(b, t, d)  # (B, T, D)
        return self.proj(y)


class Block(nn.Module):
    """Pre-norm transformer block: x + attn(ln(x)), then x + mlp(ln(x))."""

    def __init__(self, width: int, heads: int, mlp_ratio: float, dropout: float) -> None:
        super().__init__()
        hidden = int(width * mlp_ratio)
        self.ln_1 = nn.LayerNorm(width)
        self.attn = SelfAttention(width, heads, dropout)
        self.ln_2 = nn.LayerNorm(width)
        self.mlp = nn.Sequential(
            nn.Linear(width, hidden), nn.GELU(), nn.Linear(hidden, width), nn.Dropout(dropout)
        )

    def forward(self, x: Tensor) -> Tensor:
        x = x + self.attn(self.ln_1(x))
        return x + self.mlp(self.ln_2(x))


class Transformer(nn.Module):
    """Blocks with the positional embedding added before each (Point-MAE), then a layer norm."""

    def __init__(self, width: int, depth: int, heads: int, mlp_ratio: float, dropout: float):
        super().__init__()
        self.blocks = nn.ModuleList(Block(width, heads, mlp_ratio, dropout) for _ in range(depth))
        self.ln_f = nn.LayerNorm(width)

    def forward(self, x: Tensor, pos: Tensor) -> Tensor:
        """x, pos (B, T, D) -> (B, T, D)."""
        for block in self.blocks:
            x = block(x + pos)
        return self.ln_f(x)


def positional_mlp(hidden: int, width: int) -> nn.Module:
    return nn.Sequential(nn.Linear(3, hidden), nn.GELU(), nn.Linear(hidden, width))


INIT_STD = 0.02
"""Std of the truncated-normal initial weights (Point-MAE, after timm's ViT)."""


def _init_weights(module: nn.Module, generator: torch.Generator | None = None) -> None:
    """Truncated-normal linear weights and zero biases, as Point-MAE; use with ``apply``."""
    if isinstance(module, nn.Linear):
        nn.init.trunc_normal_(module.weight, std=INIT_STD, generator=generator)
        if module.bias is not None:
            nn.init.zeros_(module.bias)
    elif isinstance(module, nn.LayerNorm):
        nn.init.ones_(module.weight)
        nn.init.zeros_(module.bias)


# -- encoder ---------------------------------------------------------------------------
class PointMAEEncoder(nn.Module):
    """Normalised cloud -> one token per group, and the group centres.

    generator : draws the initial weights (same generator state, same weights); None
    uses torch's default generator.
    """

    def __init__(self, config: PointMAEConfig, generator: torch.Generator | None = None) -> None:
        super().__init__()
        self.config = config
        c = config
        self.embed = MiniPointNet(c.width, c.pointnet_hidden)
        self.pos_embed = positional_mlp(c.pos_hidden, c.width)
        self.transformer = Transformer(c.width, c.depth, c.heads, c.mlp_ratio, c.dropout)
        self.apply(partial(_init_weights, generator=generator))

    @property
    def width(self) -> int:
        """D, the width of the output tokens."""
        return self.config.width

    def group(self, points: Tensor) -> tuple[Tensor, Tensor]:
        """points (B, N, 3) -> groups (B, G, k, 3) relative to their centres, centers (B, G, 3).

        Deterministic: farthest point sampling starts at point 0 of each cloud.
        """
        if points.ndim != 3 or points.shape[-1] != 3:
            raise ValueError(f"points must be (B, N, 3), got {tuple(points.shape)}")
        idx = farthest_point_sample(points, self.config.n_groups)
        centers = gather_points(points, idx)  # (B, G, 3)
        return knn_group(points, centers, self.config.group_size), centers

    def encode(self, groups: Tensor, centers: Tensor, mask: Tensor | None = None) -> Tensor:
        """Tokens of the groups (B, G, k, 3) at ``centers`` (B, G, 3).

        mask : optional (B, G) bool, True where a group is hidden; every row must hide
        the same number of groups. Returns (B, G, D), or (B, V, D) for the V visible
        groups of each row in group order when masked.
        """
        x = self.embed(groups)  # (B, G, D)
        pos = self.pos_embed(centers)  # (B, G, D)
        if mask is not None:
            b, _, d = x.shape
            visible = ~mask
            n_visible = visible.sum(dim=1)
            if bool((n_visible != n_visible[0]).any()):
                raise ValueError("mask must hide the same number of groups in every row")
            x = x[visible].reshape(b, -1, d)  # (B, V, D)
            pos = pos[visible].reshape(b, -1, d)  # (B, V, D)
        return self.transformer(x, pos)

    def forward(self, points: Tensor, mask: Tensor | None = None) -> tuple[Tensor, Tensor]:
        """points (B, N, 3), normalised (:func:`normalise_points`) ->
        (tokens (B, G, D), centers (B, G, 3)).

        With ``mask`` (B, G) bool (True: hidden), only the visible groups are encoded
        and both outputs hold those: (B, V, D) and (B, V, 3).
        """
        groups, centers = self.group(points)
        tokens = self.encode(groups, centers, mask)
        if mask is not None:
            centers = centers[~mask].reshape(centers.shape[0], -1, 3)  # (B, V, 3)
        return tokens, centers


def random_mask(
    batch: int, n_groups: int, n_masked: int, generator: torch.Generator | None,
    device: torch.device | str = "cpu",
) -> Tensor:  # fmt: skip
    """(B, G) bool with exactly ``n_masked`` True per row, uniformly at random.

    The draw happens on the generator's device, then moves to ``device``, so a CPU
    generator gives the same mask whatever device the model runs on.
    """
    gen_device = generator.device if generator is not None else torch.device("cpu")
    noise = torch.rand(batch, n_groups, generator=generator, device=gen_device)
    rank = noise.argsort(dim=1).argsort(dim=1)  # (B, G) rank of each group's noise
    return (rank < n_masked).to(device)


@dataclass(frozen=True)
class MAEOutput:
    """What :meth:`PointMAE.forward` returns besides the loss (detached)."""

    chamfer: Tensor
    """(B,) Chamfer-L2 of each cloud's masked groups (the loss is its mean)."""
    mask: Tensor
    """(B, G) bool, True for the masked groups."""
    predicted: Tensor
    """(B, M, k, 3) reconstructed masked groups, relative to their centres."""
    target: Tensor
    """(B, M, k, 3) true masked groups, relative to their centres."""


# -- masked autoencoder ----------------------------------------------------------------
class PointMAE(nn.Module):
    """The encoder plus a light decoder that reconstructs masked groups (pre-training only).

    generator : draws the initial weights, as for :class:`PointMAEEncoder`.
    """

    def __init__(self, config: PointMAEConfig, generator: torch.Generator | None = None) -> None:
        super().__init__()
        if config.n_masked < 1 or config.n_masked >= config.n_groups:
            raise ValueError(
                f"mask_ratio {config.mask_ratio} of {config.n_groups} groups must mask "
                "at least one and leave at least one visible"
            )
        self.config = config
        c = config
        self.encoder = PointMAEEncoder(c, generator)
        self.mask_token = nn.Parameter(torch.zeros(c.width))
        self.decoder_pos_embed = positional_mlp(c.pos_hidden, c.width)
        self.decoder = Transformer(
            c.width, c.decoder_depth, c.decoder_heads, c.mlp_ratio, c.dropout
        )
        self.head = nn.Linear(c.width, 3 * c.group_size)
        init = partial(_init_weights, generator=generator)
        for part in (self.decoder_pos_embed, self.decoder, self.head):
            part.apply(init)
        nn.init.trunc_normal_(self.mask_token, std=INIT_STD, generator=generator)

    def forward(
        self, points: Tensor, generator: torch.Generator | None = None
    ) -> tuple[Tensor, MAEOutput]:
        """points (B, N, 3), normalised -> (loss (), details).

        Masks ``n_masked`` random groups per cloud (drawn with ``generator``), encodes
        the visible ones, decodes mask tokens at the masked centres and scores the
        reconstruction with Chamfer-L2 against the true groups.
        """
        c = self.config
        groups, centers = self.encoder.group(points)  # (B, G, k, 3), (B, G, 3)
        b, g = centers.shape[:2]
        mask = random_mask(b, g, c.n_masked, generator, points.device)  # (B, G)
        visible = self.encoder.encode(groups, centers, mask)  # (B, V, D)

        m = c.n_masked
        masked_centers = centers[mask].reshape(b, m, 3)  # (B, M, 3)
        visible_centers = centers[~mask].reshape(b, g - m, 3)  # (B, V, 3)
        order = torch.cat([visible_centers, masked_centers], dim=1)  # (B, G, 3) visible first
        pos = self.decoder_pos_embed(order)  # (B, G, D)
        x = torch.cat([visible, self.mask_token.expand(b, m, -1)], dim=1)  # (B, G, D)
        x = self.decoder(x, pos)[:, -m:]  # (B, M, D)
        predicted = self.head(x).reshape(b, m, c.group_size, 3)  # (B, M, k, 3)

        target = groups[mask].reshape(b, m, c.group_size, 3)  # (B, M, k, 3)
        per_cloud = chamfer_l2(predicted, target)
        details = MAEOutput(per_cloud.detach(), mask, predicted.detach(), target)
        return per_cloud.mean(), details


def count_parameters(module: nn.Module) -> int:
    return sum(p.numel() for p in module.parameters())


__all__ = [
    "MAEOutput",
    "MiniPointNet",
    "PointMAE",
    "PointMAEConfig",
    "PointMAEEncoder",
    "chamfer_l2",
    "count_parameters",
    "farthest_point_sample",
    "gather_points",
    "knn_group",
    "knn_indices",
    "normalise_points",
    "random_mask",
]

"""The Point-MAE encoder's eval-mode forward in numpy, without torch.

Scene generation encodes ~30 clouds per scene, and importing torch costs more than the
encoding. :class:`NumpyPointMAE` computes what ``PointMAEEncoder(config).eval()`` computes
under ``torch.no_grad`` (:mod:`pair2scene.model.pointmae`), from the encoder's own state
dict as numpy arrays, in float32:

1. grouping: the same farthest point sampling picks (point 0 first, the same float32
   sums, ties to the lowest index), so the same centres; each centre's k nearest points
   ranked by the squared distances as ``torch.cdist`` rounds them
   (:func:`squared_distances`), so the same groups;
2. the mini-PointNet, in chunks of groups small enough to stay in the CPU cache;
3. the transformer: the positional MLP of the centres added before every pre-norm block,
   then the final layer norm.

The mini-PointNet's (B G k, 4h) activations are the bulk of the work, so its layers are
rearranged (equal in exact arithmetic: only float32 rounding differs) to save matmuls and
passes over them:

- its second Linear over ``[point feature f, group max of f]`` is split in two: the group
  part is computed once per group, not once per point, and the point part is merged with
  the Linear that made f (one (h, 4h) matmul instead of (h, 2h) then (2h, 4h));
- a layer norm right after a Linear gets inputs whose mean over the channels is zero
  already: the Linear's weight columns and bias are centred once, at load;
- GELU is exact (erf), with erf from Abramowitz & Stegun 7.1.28, absolute error < 3e-7
  (GELU within 9e-7 of the true value; torch's float32 GELU is within 4e-7): numpy has no
  erf, and ``scipy.special.erf`` takes ~20 ns a value, more than the matmul it follows.
  It returns 2 GELU(x), the 1/2 moved into the Linear that follows (exact: a power of 2).

Tokens agree with torch's within ~1e-5. A group can hold other points only where two
distinct points lie at the same float32 distance at its edge, about once in 1e5 groups of
a sampled surface (none in 163 room, wall and asset clouds): torch ranks the square roots
(MKL's, within an ulp of the true ones, so two distances an ulp apart can tie) and
``topk`` breaks ties by its selection algorithm (a heap or introselect, by version and
k / N), where :func:`knn_indices` takes the lowest index.
"""

from __future__ import annotations

from collections.abc import Mapping

import numpy as np

from pair2scene.model.checkpoint import encoder_shapes
from pair2scene.model.config import LAYER_NORM_EPS, PointMAEConfig

Pair = tuple[np.ndarray, np.ndarray]
"""A layer's (weight, bias)."""


CHUNK_VALUES = 1 << 17
"""Values of the mini-PointNet's widest activation (points x 4h) computed at once: 512 kB,
so its passes run in the L2 cache; bigger chunks fall out of it, smaller ones pay more
per-call overhead than they save."""

# Abramowitz & Stegun 7.1.28: erf(z) = 1 - (1 + a1 z + ... + a6 z^6)^-16 for z >= 0, here
# with z = |x| / sqrt 2 folded into the coefficients (a_i / sqrt(2)^i).
_ERF_COEFFICIENTS = tuple(
    np.float32(a / np.sqrt(2.0) ** i)
    for i, a in enumerate(
        (0.0705230784, 0.0422820123, 0.0092705272, 0.0001520143, 0.0002765672, 0.0000430638),
        start=1,
    )
)


# -- grouping --------------------------------------------------------------------------
def farthest_point_sample(points: np.ndarray, m: int) -> np.ndarray:
    """Indices (B, m) int64 of ``m`` points of each cloud (B, N, 3) float32 by farthest
    point sampling from point 0: each next pick is the point farthest from all picked so
    far (ties: the lowest index). The float32 sums of ``pointmae._farthest_on_cpu``, in
    its order (dx^2 + dy^2) + dz^2, so the same picks."""
    b, n, _ = points.shape
    coords = np.ascontiguousarray(points.transpose(2, 0, 1))  # (3, B, N)
    diff = np.empty_like(coords)
    d = np.empty((b, n), dtype=np.float32)
    dist = np.full((b, n), np.inf, dtype=np.float32)
    idx = np.empty((b, m), dtype=np.int64)
    rows = np.arange(b)
    current = np.zeros(b, dtype=np.int64)
    for i in range(m):
        idx[:, i] = current
        np.subtract(coords, coords[:, rows, current][..., None], out=diff)
        np.multiply(diff, diff, out=diff)
        np.add(diff[0], diff[1], out=d)
        d += diff[2]
        np.minimum(dist, d, out=dist)
        current = dist.argmax(axis=1)
    return idx


def squared_distances(centers: np.ndarray, points: np.ndarray) -> np.ndarray:
    """Squared distances (B, G, N) float32 of centres (B, G, 3) to points (B, N, 3),
    rounded as ``torch.cdist`` rounds them before its square root.

    cdist (above 25 points) takes the matmul expansion ``[-2c, |c|^2, 1] . [p, 1, |p|^2]``,
    which MKL sums in order with fused multiply-adds, then clamps at 0. A fused step is
    exact in float64 (a float32 product has 48 bits), then rounded once to float32; the
    last two terms are plain float32 additions. Ranking by these, not by the true
    distances, keeps torch's group members where two points are nearly equidistant from
    a centre. (Bit for bit with torch 2.13's MKL from 12 centres a batch on; fewer go
    through kernels that sum some rows in another order.)
    """
    c_norm = (centers[..., 0] ** 2 + centers[..., 1] ** 2) + centers[..., 2] ** 2  # (B, G)
    p_norm = (points[..., 0] ** 2 + points[..., 1] ** 2) + points[..., 2] ** 2  # (B, N)
    minus_2c = -2 * centers  # exact
    d = minus_2c[..., 0, None] * points[:, None, :, 0]  # (B, G, N)
    wide = np.empty(d.shape, dtype=np.float64)
    for i in (1, 2):
        np.multiply(
            minus_2c[..., i, None].astype(np.float64), points[:, None, :, i], out=wide
        )  # (B, G, N), exact
        wide += d
        np.copyto(d, wide, casting="same_kind")  # one rounding
    d += c_norm[..., None]
    d += p_norm[:, None]
    return np.maximum(d, 0, out=d)


def knn_indices(points: np.ndarray, centers: np.ndarray, k: int) -> np.ndarray:
    """Indices (B, G, k) of the ``k`` points (B, N, 3) nearest each centre (B, G, 3),
    in index order (not nearest first: the encoder max-pools, so only membership counts).
    Ties at the k-th distance go to the lowest indices."""
    d = squared_distances(centers, points)  # (B, G, N)
    kth = np.partition(d, k - 1, axis=-1)[..., k - 1]  # (B, G)
    inside = d <= kth[..., None]  # (B, G, N)
    surplus = inside.sum(axis=-1) - k  # (B, G): ties at the edge beyond the k-th
    for row in zip(*np.nonzero(surplus)):  # rare: drop the highest-index ties
        edge = np.flatnonzero(d[row] == kth[row])
        inside[row][edge[len(edge) - surplus[row] :]] = False
    b, g, n = d.shape
    return np.nonzero(inside.reshape(b * g, n))[1].reshape(b, g, k)


# -- layers ----------------------------------------------------------------------------
def _layer_norm(x: np.ndarray, weight: np.ndarray, bias: np.ndarray) -> np.ndarray:
    """``nn.LayerNorm`` over the last axis of ``x`` (..., C) float32, in place."""
    mean = np.add.reduce(x, axis=-1, keepdims=True)
    mean *= np.float32(1 / x.shape[-1])
    x -= mean
    return _scale_centred(x, weight, bias)


def _scale_centred(x: np.ndarray, weight: np.ndarray, bias: np.ndarray) -> np.ndarray:
    """The rest of a layer norm of ``x`` (..., C) float32 whose mean over the last axis
    is zero already: divide by the standard deviation, then the affine map. In place."""
    var = np.einsum("...i,...i->...", x, x)  # (...,)
    var *= np.float32(1 / x.shape[-1])
    var += np.float32(LAYER_NORM_EPS)
    x *= (1 / np.sqrt(var, out=var))[..., None]
    x *= weight
    x += bias
    return x


def _twice_gelu(x: np.ndarray) -> np.ndarray:
    """2 GELU(x) = x (1 + erf(x / sqrt 2)) = x + |x| erf(|x| / sqrt 2) of ``x`` float32,
    in place: the exact (erf) GELU of ``nn.GELU()``, doubled (see the module docstring)."""
    a = np.abs(x)
    *rest, last = _ERF_COEFFICIENTS
    q = a * last
    for coefficient in reversed(rest):
        q += coefficient
        q *= a
    q += 1
    with np.errstate(over="ignore", under="ignore"):  # |x| > ~19: erfc ~ 1e-38, or 0
        for _ in range(4):
            np.multiply(q, q, out=q)  # q^16
        np.reciprocal(q, out=q)  # erfc(|x| / sqrt 2)
    np.subtract(1, q, out=q)
    q *= a
    x += q
    return x


def _attention(x: np.ndarray, qkv_w: np.ndarray, qkv_b: np.ndarray, heads: int) -> np.ndarray:
    """Multi-head softmax attention of tokens (B, T, D): (B, T, D), before the output
    projection. ``qkv_w`` (D, 3D) is the transposed qkv weight: q, k, v in that order."""
    b, t, d = x.shape
    qkv = x @ qkv_w  # (B, T, 3D)
    qkv += qkv_b
    q, k, v = qkv.reshape(b, t, 3, heads, d // heads).transpose(2, 0, 3, 1, 4)  # (B, H, T, hs)
    s = q @ k.transpose(0, 1, 3, 2)  # (B, H, T, T)
    s *= np.float32(1 / np.sqrt(d // heads))
    s -= s.max(axis=-1, keepdims=True)
    np.exp(s, out=s)
    s /= s.sum(axis=-1, keepdims=True)
    return (s @ v).transpose(0, 2, 1, 3).reshape(b, t, d)  # (B, T, D)


# -- the encoder -----------------------------------------------------------------------
class NumpyPointMAE:
    """Eval-mode ``PointMAEEncoder`` forward in numpy (float32): normalised clouds
    (B, N, 3) -> (tokens (B, G, D), centers (B, G, 3)).

    config : the encoder's :class:`PointMAEConfig`.
    state : its ``state_dict()`` as numpy arrays, keys as the encoder names them (no
        prefix, see :func:`encoder_state`); other keys are ignored. Raises ValueError
        naming the first missing or mis-shaped key.
    """

    def __init__(self, config: PointMAEConfig, state: Mapping[str, np.ndarray]) -> None:
        self.config = config
        arrays: dict[str, np.ndarray] = {}
        for key, shape in encoder_shapes(config).items():
            if key not in state:
                raise ValueError(f"Point-MAE encoder state: missing {key!r}")
            value = np.asarray(state[key])
            if value.shape != shape:
                raise ValueError(
                    f"Point-MAE encoder state: {key!r} has shape {value.shape}, expected {shape}"
                )
            arrays[key] = value.astype(np.float64)

        def linear(name: str, scale: float = 1.0) -> Pair:
            """(W^T (in, out), b (out,)) float64 of a Linear: x @ W^T + b; ``scale``
            takes a preceding GELU's 1/2."""
            return scale * arrays[f"{name}.weight"].T, arrays[f"{name}.bias"]

        def centred(w: np.ndarray, b: np.ndarray) -> Pair:
            """A Linear (W^T, b) whose every output has mean 0 over the channels, for
            the layer norm that follows: the same layer norm outputs."""
            return w - w.mean(axis=1, keepdims=True), b - b.mean()

        def single(x: np.ndarray) -> np.ndarray:
            return np.ascontiguousarray(x, dtype=np.float32)

        def singles(pair: Pair) -> Pair:
            return single(pair[0]), single(pair[1])

        def norm(name: str) -> Pair:
            return single(arrays[f"{name}.weight"]), single(arrays[f"{name}.bias"])

        self._first = singles(centred(*linear("embed.first.0")))  # (3, h), (h,)
        self._first_norm = norm("embed.first.1")
        # The point feature f = g w2 + b2 (g: stage 1's GELU output) feeds second.0
        # twice: as itself, [f, .] J = g (w2 J_f) + b2 J_f; and through its group max,
        # max(g w2) + b2 (a bias commutes with the max), [., max] J = max(g w2) J_m +
        # b2 J_m. Both b2 terms join second.0's bias.
        w2, b2 = linear("embed.first.3", scale=0.5)  # (h, 2h), (2h,)
        joint, joint_b = centred(*linear("embed.second.0"))  # (4h, 4h), (4h,)
        j_f, j_m = joint[: w2.shape[1]], joint[w2.shape[1] :]  # (2h, 4h) each
        self._group_feature = single(w2)  # (h, 2h)
        self._second = (single(w2 @ j_f), single(j_m), single(joint_b + b2 @ (j_f + j_m)))
        self._second_norm = norm("embed.second.1")
        self._second_out = singles(linear("embed.second.3", scale=0.5))  # (4h, D), (D,)
        self._pos = (singles(linear("pos_embed.0")), singles(linear("pos_embed.2", 0.5)))
        self._blocks = [
            (
                norm(f"{block}.ln_1"),
                singles(linear(f"{block}.attn.qkv")),
                singles(linear(f"{block}.attn.proj")),
                norm(f"{block}.ln_2"),
                singles(linear(f"{block}.mlp.0")),
                singles(linear(f"{block}.mlp.2", 0.5)),
            )
            for block in (f"transformer.blocks.{i}" for i in range(config.depth))
        ]
        self._ln_f = norm("transformer.ln_f")

    def __call__(self, clouds: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """clouds (B, N, 3), normalised (``pointmae.normalise_points``), N at least the
        group count and size -> (tokens (B, G, D), centers (B, G, 3)), float32."""
        c = self.config
        clouds = np.asarray(clouds, dtype=np.float32)
        if clouds.ndim != 3 or clouds.shape[-1] != 3:
            raise ValueError(f"clouds must be (B, N, 3), got {clouds.shape}")
        need = max(c.n_groups, c.group_size)
        if clouds.shape[1] < need:
            raise ValueError(
                f"clouds need at least {need} points ({c.n_groups} groups of "
                f"{c.group_size}), got {clouds.shape[1]}"
            )
        b = len(clouds)
        centers = clouds[np.arange(b)[:, None], farthest_point_sample(clouds, c.n_groups)]
        idx = knn_indices(clouds, centers, c.group_size)  # (B, G, k)
        groups = clouds[np.arange(b)[:, None, None], idx] - centers[:, :, None]  # (B, G, k, 3)
        tokens = self._embed(groups.reshape(b * c.n_groups, c.group_size, 3))
        return self._transformer(tokens.reshape(b, c.n_groups, c.width), centers), centers

    def _embed(self, groups: np.ndarray) -> np.ndarray:
        """The mini-PointNet: groups (M, k, 3) -> tokens (M, D), in cache-sized chunks."""
        m, k, _ = groups.shape
        w_out, b_out = self._second_out
        tokens = np.empty((m, w_out.shape[1]), dtype=np.float32)
        step = max(1, CHUNK_VALUES // (k * w_out.shape[0]))
        for s in range(0, m, step):
            tokens[s : s + step] = self._embed_chunk(groups[s : s + step])
        tokens += b_out  # after the max-pool: a bias commutes with it
        return tokens

    def _embed_chunk(self, groups: np.ndarray) -> np.ndarray:
        """Groups (M, k, 3) -> tokens (M, D) without the last bias."""
        m, k, _ = groups.shape
        w1, b1 = self._first
        g = groups.reshape(m * k, 3) @ w1  # (M k, h)
        g += b1
        g = _twice_gelu(_scale_centred(g, *self._first_norm))
        group_max = (g @ self._group_feature).reshape(m, k, -1).max(axis=1)  # (M, 2h)
        w_point, w_group, b = self._second
        group_part = group_max @ w_group  # (M, 4h)
        group_part += b
        x = (g @ w_point).reshape(m, k, -1)  # (M, k, 4h)
        x += group_part[:, None]
        x = _twice_gelu(_scale_centred(x, *self._second_norm))
        return (x.reshape(m * k, -1) @ self._second_out[0]).reshape(m, k, -1).max(axis=1)

    def _transformer(self, x: np.ndarray, centers: np.ndarray) -> np.ndarray:
        """Tokens (B, G, D) at centres (B, G, 3) -> encoded tokens (B, G, D)."""
        (p1_w, p1_b), (p2_w, p2_b) = self._pos
        hidden = centers @ p1_w
        hidden += p1_b
        pos = _twice_gelu(hidden) @ p2_w  # (B, G, D)
        pos += p2_b
        heads = self.config.heads
        for ln_1, qkv, (proj_w, proj_b), ln_2, (m1_w, m1_b), (m2_w, m2_b) in self._blocks:
            x = x + pos
            x += _attention(_layer_norm(x.copy(), *ln_1), *qkv, heads) @ proj_w
            x += proj_b
            hidden = _layer_norm(x.copy(), *ln_2) @ m1_w
            hidden += m1_b
            x += _twice_gelu(hidden) @ m2_w
            x += m2_b
        return _layer_norm(x, *self._ln_f)


def encoder_state(
    state: Mapping[str, np.ndarray], prefix: str = "point_encoder."
) -> dict[str, np.ndarray]:
    """The entries of a whole model's state dict (a layout predictor's, whose encoder is
    ``point_encoder``) whose key starts with ``prefix``, the prefix stripped: what
    :class:`NumpyPointMAE` takes."""
    return {key[len(prefix) :]: value for key, value in state.items() if key.startswith(prefix)}


__all__ = [
    "CHUNK_VALUES",
    "NumpyPointMAE",
    "encoder_state",
    "farthest_point_sample",
    "knn_indices",
    "squared_distances",
]

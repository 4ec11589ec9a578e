"""The layout predictor's forward pass and the mixture's sampling functions in numpy.

Scene generation runs one forward pass of a batch of one per object it places, then
draws a few hundred candidates from the mixture. In torch that costs an import of
3.4 s per process and ~48 us of per-operation overhead on each of the ~43 tiny matrix
products of a pass; these numpy twins need neither (this module imports no torch, only
numpy, :mod:`scipy.special` and the torch-free :mod:`pair2scene.model.config` and
:mod:`~pair2scene.model.checkpoint`).

- :class:`NumpyPredictor` is :class:`~pair2scene.model.layout.LayoutPredictor` in eval
  mode fed cached point tokens (``point_tokens`` / ``point_centers``; the point encoder
  is not part of it), from the predictor's ``state_dict`` as numpy arrays. It computes
  in float32 and agrees with the torch predictor to float32 rounding.
- :func:`condition`, :func:`window_log_mass`, :func:`sample` (with :class:`Window`,
  :func:`check_params`, :func:`mode`) are :mod:`pair2scene.model.mixture`'s functions
  of the same names over :class:`MixtureArrays`, with the same semantics, errors and
  float64 steps. Draws come from a ``numpy.random.Generator`` instead of a
  ``torch.Generator``: the same distribution, not the same numbers.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from typing import NamedTuple

import numpy as np
from scipy.special import expit, log_expit, ndtr

from pair2scene.model.checkpoint import expected_shapes
from pair2scene.model.config import (
    BOX_DIM,
    CONDITIONED_LOG_SCALE,
    DEPENDENT,
    FLOOR_INDEX,
    LAYER_NORM_EPS,
    MAX_ABS_LOCATION,
    MIN_ANCHOR_HALF_M,
    MIN_TARGET_SIZE,
    N_MEMBERS,
    ROTATION_PAIRS,
    SUPPORT,
    WALL_INDEX,
    InvalidDistribution,
    LayoutConfig,
    LayoutVariant,
    check_draw,
)
from pair2scene.model.pair_prior import CENTRE_DIMS, table_rows


class MixtureArrays(NamedTuple):
    """Parameters of a batch of diagonal logistic mixtures (numpy
    :class:`~pair2scene.model.mixture.MixtureParams`)."""

    logits: np.ndarray
    """(B, K) unnormalised log mixture weights."""
    loc: np.ndarray
    """(B, K, D) locations mu."""
    log_scale: np.ndarray
    """(B, K, D) log scales log s."""


class Window(NamedTuple):
    """An axis-aligned box over some of the mixture's dims: ``low <= x[dims] <= high``
    (numpy :class:`~pair2scene.model.mixture.Window`)."""

    dims: Sequence[int]
    low: np.ndarray
    """(B, len(dims)) lower bounds, one row per mixture."""
    high: np.ndarray
    """(B, len(dims)) upper bounds (>= low)."""


# -- the predictor ---------------------------------------------------------------------


class _Linear(NamedTuple):
    """``x @ w + b`` with ``w`` the torch weight transposed, (in, out), contiguous."""

    w: np.ndarray
    b: np.ndarray


class _Norm(NamedTuple):
    """A layer norm's elementwise affine weight and bias, (D,)."""

    w: np.ndarray
    b: np.ndarray


class _MLP(NamedTuple):
    """Linear -> exact GELU -> Linear."""

    fc: _Linear
    proj: _Linear


class _SelfAttention(NamedTuple):
    """Relational self-attention's projections; ``q`` already carries the
    1 / sqrt(head size) of the scaled dot product."""

    q: _Linear
    kv: _Linear
    proj: _Linear


class _CrossAttention(NamedTuple):
    """Cross-attention's projections, with the key and value projections regrouped per
    head so that they apply to the Q queries and not the G memory tokens
    (:func:`_cross_attend`)."""

    q: _Linear
    """Queries, scaled by 1 / sqrt(head size)."""
    k_heads: np.ndarray
    """(nh, hs, D) each head's rows of the key weight. The key bias is dropped: it adds
    one constant to all of a query's scores, which the softmax removes."""
    v_heads: np.ndarray
    """(nh, D, hs) each head's rows of the value weight, transposed."""
    v_bias: np.ndarray
    """(nh, 1, hs) each head's value bias."""
    proj: _Linear


class _Block(NamedTuple):
    """One LayoutBlock's weights (the cross-attention's None for ``class-only``)."""

    ln_self: _Norm
    self_attn: _SelfAttention
    ln_cross: _Norm | None
    cross_attn: _CrossAttention | None
    ln_mlp: _Norm
    mlp: _MLP


class _Memory(NamedTuple):
    """The present members' projected point tokens, for one layout of the query rows."""

    tokens: np.ndarray
    """(R, G, D) the point tokens of the R query rows that have any."""
    tokens_t: np.ndarray
    """(R, D, G) the same, transposed (contiguous)."""
    rows: np.ndarray | None
    """(R,) their rows among the query rows; None: every row, in order."""


def _linear(x: np.ndarray, layer: _Linear) -> np.ndarray:
    """(..., in) -> (..., out), one matrix product over the flattened leading dims."""
    y = x.reshape(-1, x.shape[-1]) @ layer.w
    y += layer.b
    return y.reshape(*x.shape[:-1], y.shape[-1])


def _gelu(x: np.ndarray) -> np.ndarray:
    """Exact GELU, ``x * Phi(x)`` = ``x / 2 * (1 + erf(x / sqrt 2))`` (torch's default)."""
    t = ndtr(x)
    t *= x
    return t


def _mlp(x: np.ndarray, mlp: _MLP) -> np.ndarray:
    """(..., in) -> (..., out)."""
    return _linear(_gelu(_linear(x, mlp.fc)), mlp.proj)


def _layer_norm(x: np.ndarray, norm: _Norm) -> np.ndarray:
    """Layer norm over the last dim (biased variance, eps :data:`LAYER_NORM_EPS`)."""
    inv_d = np.float32(1.0 / x.shape[-1])
    xc = x - np.add.reduce(x, -1, keepdims=True) * inv_d
    var = np.add.reduce(xc * xc, -1, keepdims=True)
    var *= inv_d
    var += LAYER_NORM_EPS
    xc /= np.sqrt(var, out=var)
    xc *= norm.w
    xc += norm.b
    return xc


def _softmax_(scores: np.ndarray) -> np.ndarray:
    """Softmax over the last dim, in place."""
    scores -= np.maximum.reduce(scores, -1, keepdims=True)
    np.exp(scores, out=scores)
    scores /= np.add.reduce(scores, -1, keepdims=True)
    return scores


def _attend(
    q: np.ndarray, k: np.ndarray, v: np.ndarray, heads: int, bias: np.ndarray | None
) -> np.ndarray:
    """Multi-head attention of already projected (and scaled) queries.

    q : (R, Tq, D); k, v : (R, Tk, D); bias : (R, 1, 1, Tk) added to the scores (-inf
    for masked keys) or None. Returns (R, Tq, D), heads concatenated."""
    r, tq, d = q.shape
    tk, hs = k.shape[1], d // heads
    qh = q.reshape(r, tq, heads, hs).transpose(0, 2, 1, 3)  # (R, nh, Tq, hs)
    kh = k.reshape(r, tk, heads, hs).transpose(0, 2, 3, 1)  # (R, nh, hs, Tk)
    vh = v.reshape(r, tk, heads, hs).transpose(0, 2, 1, 3)  # (R, nh, Tk, hs)
    scores = qh @ kh  # (R, nh, Tq, Tk)
    if bias is not None:
        scores += bias
    return (_softmax_(scores) @ vh).transpose(0, 2, 1, 3).reshape(r, tq, d)


def _cross_attend(h: np.ndarray, memory: _Memory, att: _CrossAttention) -> np.ndarray:
    """Each query row's tokens h (R, Q, D) attend to its memory tokens (R, G, D):
    (R, Q, D) after the output projection.

    The same numbers as projecting the memory to keys and values, regrouped: head n's
    scores are ``q_n (W_k,n m)^T = (q_n W_k,n) m^T`` and its output
    ``p (m W_v,n^T + b_v,n) = (p m) W_v,n^T + b_v,n`` (p's rows sum to 1), so the
    projections act on Q queries per head instead of G memory tokens: a quarter of the
    work at Q = 4, G = 32."""
    r, nq, d = h.shape
    heads, hs = att.k_heads.shape[:2]
    qh = _linear(h, att.q).reshape(r, nq, heads, hs).transpose(0, 2, 1, 3)  # (R, nh, Q, hs)
    scores = (qh @ att.k_heads) @ memory.tokens_t[:, None]  # (R, nh, Q, G)
    context = _softmax_(scores) @ memory.tokens[:, None]  # (R, nh, Q, D)
    y = context @ att.v_heads  # (R, nh, Q, hs)
    y += att.v_bias
    return _linear(y.transpose(0, 2, 1, 3).reshape(r, nq, d), att.proj)


def _softplus(x: np.ndarray) -> np.ndarray:
    """log(1 + e^x), without overflow."""
    return np.logaddexp(0.0, x).astype(x.dtype, copy=False)


def _log_softmax(x: np.ndarray) -> np.ndarray:
    """Log softmax over the last dim."""
    shifted = x - x.max(-1, keepdims=True)
    return shifted - np.log(np.exp(shifted).sum(-1, keepdims=True))


class NumpyPredictor:
    """:class:`~pair2scene.model.layout.LayoutPredictor` in eval mode, in numpy float32.

    config : the predictor's config (any variant; ``full`` / ``no-pretrain`` / ``global``
        take cached point tokens, ``class-only`` none).
    state : the predictor's ``state_dict()`` as numpy arrays (any float dtype; copied to
        float32, weights transposed once here). Entries of the point encoder
        (``point_encoder.*``) are ignored: the encoder's tokens are an input. A missing
        entry, one of the wrong shape, or one the config has no use for raises
        :class:`ValueError` naming it (the shapes:
        :func:`~pair2scene.model.checkpoint.expected_shapes`).
    """

    def __init__(self, config: LayoutConfig, state: Mapping[str, np.ndarray]) -> None:
        self.config = config
        c = config
        self.uses_frames = c.uses_frames
        arrays = {
            name: np.array(value, dtype=np.float32)
            for name, value in state.items()
            if not name.startswith("point_encoder.")
        }
        expected = {
            k: v for k, v in expected_shapes(c, None).items() if not k.startswith("point_encoder.")
        }
        _check_state(arrays, expected)
        hs = c.width // c.heads

        def linear(name: str, scale: float = 1.0) -> _Linear:
            w = np.ascontiguousarray(arrays[f"{name}.weight"].T * np.float32(scale))
            return _Linear(w, arrays[f"{name}.bias"] * np.float32(scale))

        def norm(name: str) -> _Norm:
            return _Norm(arrays[f"{name}.weight"], arrays[f"{name}.bias"])

        def mlp(name: str) -> _MLP:
            return _MLP(linear(f"{name}.fc"), linear(f"{name}.proj"))

        def self_attention(name: str) -> _SelfAttention:
            q = linear(f"{name}.q", 1.0 / math.sqrt(hs))
            return _SelfAttention(q, linear(f"{name}.kv"), linear(f"{name}.proj"))

        def cross_attention(name: str) -> _CrossAttention:
            kv, kv_bias = arrays[f"{name}.kv.weight"], arrays[f"{name}.kv.bias"]
            k_heads = kv[: c.width].reshape(c.heads, hs, c.width)
            v_heads = kv[c.width :].reshape(c.heads, hs, c.width).transpose(0, 2, 1)
            return _CrossAttention(
                linear(f"{name}.q", 1.0 / math.sqrt(hs)),
                np.ascontiguousarray(k_heads),
                np.ascontiguousarray(v_heads),
                kv_bias[c.width :].reshape(c.heads, 1, hs),
                linear(f"{name}.proj"),
            )

        m = c.n_members
        self._member_queries = arrays["member_queries"][:m].copy()  # (M, Q, D)
        self._category = arrays["category.weight"]
        self._size_mlp = mlp("size_mlp")
        self._box_mlp = mlp("box_mlp")
        self._unknown_box = arrays["unknown_box"]
        self._known_size_mlp = mlp("known_size_mlp")
        self._frame = arrays["frame.weight"] if self.uses_frames else None
        self._pair_centre = arrays["pair_centre"] if c.uses_pair_prior else None
        self._pair_turn = arrays["pair_turn"] if c.uses_pair_turns else None
        self._pair_mode = arrays["pair_mode"] if c.uses_pair_modes else None
        if c.uses_points:
            self._point_proj = linear("point_proj")
            self._point_pos = mlp("point_pos")
            self._ln_points = norm("ln_points")
        self._blocks = [
            _Block(
                norm(f"blocks.{i}.ln_self"),
                self_attention(f"blocks.{i}.self_attn"),
                norm(f"blocks.{i}.ln_cross") if c.uses_points else None,
                cross_attention(f"blocks.{i}.cross_attn") if c.uses_points else None,
                norm(f"blocks.{i}.ln_mlp"),
                mlp(f"blocks.{i}.mlp"),
            )
            for i in range(c.depth)
        ]
        self._ln_f = norm("ln_f")
        self._head = mlp("head")
        # The yaw turns of turned_components: exact quarter-turn cosines and sines.
        turns = c.mixture.yaw_modes
        angle = np.arange(turns) * (2 * math.pi / turns)
        self._turn_cos = np.round(np.cos(angle), 12).astype(np.float32)  # (Q,)
        self._turn_sin = np.round(np.sin(angle), 12).astype(np.float32)
        self._turn_swap = (np.arange(turns) * 4 // turns) % 2 == 1  # odd quarter turns

    def forward(
        self,
        categories: np.ndarray,
        scales: np.ndarray,
        anchor_boxes: np.ndarray,
        member_mask: np.ndarray,
        point_tokens: np.ndarray | None = None,
        point_centers: np.ndarray | None = None,
        frames: np.ndarray | None = None,
        frame_sizes: np.ndarray | None = None,
    ) -> MixtureArrays:
        """Mixture parameters per tuple, float32: logits (B, K*Q), loc and log_scale
        (B, K*Q, 12), as ``LayoutPredictor.forward`` (eval, no target) gives them.

        The inputs are :class:`~pair2scene.model.layout.LayoutBatch`'s fields as arrays:
        categories (B, 3) int; scales (B, 3, 3); anchor_boxes (B, 2, 12); member_mask
        (B, 3) bool; point_tokens (B, 3, G, point_dim) and point_centers (B, 3, G, 3),
        read for present members only (NaN placeholders are fine), required unless
        ``class-only``; frames (B,) int, the frame kind each tuple is predicted in, read
        with anchor frames only (None: the support's for every tuple); frame_sizes (B, 3)
        the size of each tuple's frame box (None: the support's).

        After the last block only the dependent's tokens are read, so that block computes
        only those; the result is the same.
        """
        c = self.config
        m, q, d = c.n_members, c.queries, c.width
        categories = np.asarray(categories)
        b = categories.shape[0]
        _check_input("categories", categories, (b, N_MEMBERS))
        scales = np.asarray(scales, dtype=np.float32)
        _check_input("scales", scales, (b, N_MEMBERS, 3))
        anchor_boxes = np.asarray(anchor_boxes, dtype=np.float32)
        _check_input("anchor_boxes", anchor_boxes, (b, N_MEMBERS - 1, BOX_DIM))
        member_mask = np.asarray(member_mask)
        _check_input("member_mask", member_mask, (b, N_MEMBERS))
        mask = member_mask[:, :m].astype(bool)  # (B, M)

        # Member tokens: role queries + category + size; absent members' inputs zeroed
        # (an absent size goes in as 1, whose log is the zero).
        cats = np.where(mask, categories[:, :m], 0)
        if b and not 0 <= cats.min() <= cats.max() < len(self._category):
            raise ValueError(f"categories must be in [0, {len(self._category)}): {categories}")
        sizes = np.where(mask[..., None], scales[:, :m], np.float32(1.0))
        log_size = np.log(np.maximum(sizes, np.float32(MIN_TARGET_SIZE)))  # (B, M, 3)
        ident = self._category[cats] + _mlp(log_size, self._size_mlp)  # (B, M, D)
        x = self._member_queries + ident[:, :, None, :]  # (B, M, Q, D)

        # Spatial embeddings: the dependent's box is the unknown; anchors' boxes via MLP
        # as model targets (log sizes), absent ones all zeros.
        present = mask[:, 1:, None]  # (B, M-1, 1)
        given = anchor_boxes[:, : m - 1]
        boxes = np.where(present, given, np.float32(0.0))  # (B, M-1, 12)
        box_sizes = np.where(present, given[..., 3:6], np.float32(1.0))
        boxes[..., 3:6] = np.log(np.maximum(box_sizes, np.float32(MIN_TARGET_SIZE)))
        if frame_sizes is not None:
            frame_sizes = np.asarray(frame_sizes, dtype=np.float32)
            _check_input("frame_sizes", frame_sizes, (b, 3))
        known = self._known_target(categories, scales, frame_sizes)  # (B, 12)
        dep_spatial = self._unknown_box + _mlp(known[:, 3:6], self._known_size_mlp)  # (B, D)
        if self._frame is not None:
            kinds = np.zeros(b, np.int64) if frames is None else np.asarray(frames)
            _check_input("frames", kinds, (b,))
            if b and not 0 <= kinds.min() <= kinds.max() < len(self._frame):
                raise ValueError(f"frames must be in [0, {len(self._frame)}): {kinds}")
            dep_spatial += self._frame[kinds]
        # the frame kinds the pair tables are keyed by (None: every tuple its support's)
        keyed = np.asarray(frames) if self._frame is not None and frames is not None else None
        if self._pair_centre is not None:  # the centre the pair table gives (x, y)
            known[:, :CENTRE_DIMS] = table_rows(self._pair_centre, categories, keyed)
        spatial = np.concatenate([dep_spatial[:, None], _mlp(boxes, self._box_mlp)], axis=1)
        spatial = spatial[:, :, None, :]  # (B, M, 1, D): one per member, all its tokens
        key_bias = None  # absent members' tokens are no keys
        if not mask.all():
            bias = np.where(mask, np.float32(0.0), np.float32(-np.inf))  # (B, M)
            key_bias = np.repeat(bias, q, axis=1)[:, None, None, :]  # (B, 1, 1, M*Q)

        memory_all, memory_dep = None, None
        if c.uses_points:
            memory_all, memory_dep = self._point_memory(mask, point_tokens, point_centers)
        for i, block in enumerate(self._blocks):
            last = i == len(self._blocks) - 1
            memory = memory_dep if last else memory_all
            x = self._block(block, x, spatial, key_bias, memory, last)

        dependent = _layer_norm(x[:, DEPENDENT], self._ln_f).reshape(b, q * d)  # (B, Q*D)
        raw = _mlp(dependent, self._head)  # (B, K*(1+2*12+Q))
        if self._pair_turn is not None:  # the pair's own split of yaw turns
            k, turns = c.mixture.num_components, c.mixture.yaw_modes
            prior = table_rows(self._pair_turn, categories, keyed)  # (B, Q)
            raw[:, -k * turns :] += np.tile(prior, (1, k))
        params = self._mixture_from_head(raw)
        np.add(params.loc, known[:, None, :], out=params.loc)
        if self._pair_mode is not None:  # the pair's clusters: each component its own
            modes = table_rows(self._pair_mode, categories, keyed)  # (B, K, 3)
            modes = np.repeat(modes, c.mixture.yaw_modes, axis=1)  # (B, K*Q, 3)
            params.loc[..., :CENTRE_DIMS] += modes[..., :CENTRE_DIMS]
            params.logits[...] += modes[..., CENTRE_DIMS]
        return params

    def from_mixture_space(self, y: np.ndarray) -> np.ndarray:
        """Samples of the mixture (..., 12) -> targets: ``y + rotation_offset(y)`` (the
        upright-rotation base, :func:`pair2scene.model.mixture.rotation_offset`) when the
        config models it, else ``y``; as ``LayoutPredictor.from_mixture_space``."""
        if not self.config.mixture.rotation_base:
            return y
        x = np.array(y, copy=True)
        x[..., 9] -= y[..., 7]
        x[..., 10] += y[..., 6]
        return x

    # -- pieces of the forward pass ----------------------------------------------------

    def _known_target(
        self, categories: np.ndarray, scales: np.ndarray, frame_sizes: np.ndarray | None
    ) -> np.ndarray:
        """(B, 12) what the inputs fix of the target (``LayoutPredictor.known_target``):
        the dependent's log size in the model frame and the centre height of an upright
        object resting on its support's top (the floor's or a wall's: its bottom)."""
        dep = np.maximum(scales[:, DEPENDENT], np.float32(MIN_TARGET_SIZE))  # (B, 3)
        known = np.zeros((dep.shape[0], BOX_DIM), np.float32)
        if self.config.variant is LayoutVariant.GLOBAL:
            known[:, 2] = 0.5 * dep[:, 2]
            known[:, 3:6] = np.log(dep)
            return known
        frame = scales[:, SUPPORT] if frame_sizes is None else frame_sizes
        half = np.maximum(0.5 * frame, np.float32(1e-9))  # (B, 3)
        size = dep / np.maximum(half, np.float32(MIN_ANCHOR_HALF_M))  # model-frame size
        top = half[:, 2] / np.maximum(half[:, 2], np.float32(MIN_ANCHOR_HALF_M))
        support = categories[:, SUPPORT]
        on_floor = (support == FLOOR_INDEX) | (support == WALL_INDEX)
        known[:, 2] = np.where(on_floor, -top, top) + 0.5 * size[:, 2]
        known[:, 3:6] = np.log(size)
        return known

    def _point_memory(
        self, mask: np.ndarray, tokens: np.ndarray | None, centers: np.ndarray | None
    ) -> tuple[_Memory, _Memory]:
        """The present members' point tokens projected to the model width, as the memory
        of every member's query rows (B*M) and of the dependents' only (B)."""
        if tokens is None or centers is None:
            raise ValueError(
                f"variant {self.config.variant.value!r} needs point_tokens and point_centers"
            )
        b, m = mask.shape
        tokens, centers = np.asarray(tokens), np.asarray(centers)
        for name, value, width in (
            ("point_tokens", tokens, self.config.point_dim),
            ("point_centers", centers, 3),
        ):
            if value.ndim != 4 or value.shape[:2] != (b, N_MEMBERS) or value.shape[3] != width:
                raise ValueError(f"{name} has shape {value.shape}, expected (B={b}, 3, G, {width})")
        batch_index, member = np.nonzero(mask)  # (P,) row-major: the order of b * M + m
        own_tokens = np.asarray(tokens[batch_index, member], dtype=np.float32)  # (P, G, Denc)
        own_centers = np.asarray(centers[batch_index, member], dtype=np.float32)  # (P, G, 3)
        projected = _linear(own_tokens, self._point_proj)
        projected += _mlp(own_centers, self._point_pos)
        memory = _layer_norm(projected, self._ln_points)  # (P, G, D)
        memory_t = np.ascontiguousarray(memory.transpose(0, 2, 1))  # (P, D, G)
        rows = None if len(member) == b * m else batch_index * m + member
        every = _Memory(memory, memory_t, rows)
        own = member == DEPENDENT
        rows = None if own.sum() == b else batch_index[own]
        return every, _Memory(memory[own], memory_t[own], rows)

    def _block(
        self,
        block: _Block,
        x: np.ndarray,
        spatial: np.ndarray,
        key_bias: np.ndarray | None,
        memory: _Memory | None,
        last: bool,
    ) -> np.ndarray:
        """One LayoutBlock: x (B, M, Q, D) -> (B, M, Q, D), or with ``last`` the
        dependent's tokens only, (B, 1, Q, D); spatial (B, M, 1, D); memory that of the
        output's rows."""
        b, m, q, d = x.shape
        heads = self.config.heads
        # Relational self-attention over all M*Q tokens; spatial joins keys and values.
        h = _layer_norm(x, block.ln_self)
        att = block.self_attn
        kv = _linear(h + spatial, att.kv).reshape(b, m * q, 2 * d)
        if last:
            x, h = x[:, :1], h[:, :1]
        mq = x.shape[1]
        queries = _linear(h, att.q).reshape(b, mq * q, d)
        y = _attend(queries, kv[..., :d], kv[..., d:], heads, key_bias)
        x = x + _linear(y, att.proj).reshape(b, mq, q, d)
        # Each present member's tokens attend to its own point tokens; absent ones get none.
        if memory is not None:
            h = _layer_norm(x, block.ln_cross).reshape(b * mq, q, d)
            flat = x.reshape(b * mq, q, d)  # a view: x is contiguous
            if memory.rows is None:
                flat += _cross_attend(h, memory, block.cross_attn)
            else:
                flat[memory.rows] += _cross_attend(h[memory.rows], memory, block.cross_attn)
        return x + _mlp(_layer_norm(x, block.ln_mlp), block.mlp)

    def _mixture_from_head(self, raw: np.ndarray) -> MixtureArrays:
        """The flat head output -> mixture parameters (``mixture_params_from_head``):
        ``[logits (K) | loc (K*D) | log-scale (K*D) | turn logits (K*Q), Q > 1]``, log
        scales soft-clamped, K components turned into K * Q (``turned_components``)."""
        mix = self.config.mixture
        k, dim, b = mix.num_components, BOX_DIM, raw.shape[0]
        logits = raw[:, :k]
        loc = raw[:, k : k + k * dim].reshape(b, k, dim)
        log_scale = _soft_clamp(
            raw[:, k + k * dim : k + 2 * k * dim].reshape(b, k, dim),
            mix.min_log_scale,
            mix.max_log_scale,
        )
        turns = mix.yaw_modes
        if turns == 1:
            return MixtureArrays(logits.copy(), loc.copy(), log_scale)
        turn_logits = raw[:, k + 2 * k * dim :].reshape(b, k, turns)
        weights = _log_softmax(logits)[..., None] + _log_softmax(turn_logits)  # (B, K, Q)
        turned_loc = np.repeat(loc[:, :, None, :], turns, axis=2)  # (B, K, Q, D)
        turned_scale = np.repeat(log_scale[:, :, None, :], turns, axis=2)
        cos, sin, swap = self._turn_cos, self._turn_sin, self._turn_swap
        for i, j in ROTATION_PAIRS:
            mx, my = loc[..., i, None], loc[..., j, None]  # (B, K, 1)
            turned_loc[..., i] = cos * mx - sin * my
            turned_loc[..., j] = sin * mx + cos * my
            sx, sy = log_scale[..., i, None], log_scale[..., j, None]
            turned_scale[..., i] = np.where(swap, sy, sx)
            turned_scale[..., j] = np.where(swap, sx, sy)
        return MixtureArrays(
            weights.reshape(b, k * turns),
            turned_loc.reshape(b, k * turns, dim),
            turned_scale.reshape(b, k * turns, dim),
        )


def _soft_clamp(x: np.ndarray, low: float, high: float) -> np.ndarray:
    """``high - softplus(high - (low + softplus(x - low)))``
    (:func:`pair2scene.model.mixture.soft_clamp`)."""
    return high - _softplus(high - (low + _softplus(x - low)))


def _check_state(arrays: Mapping[str, np.ndarray], expected: Mapping[str, tuple[int, ...]]) -> None:
    """Raise ValueError naming the first missing, misshapen or unexpected entry."""
    for name, shape in expected.items():
        if name not in arrays:
            raise ValueError(f"the state has no entry {name!r}")
        got = arrays[name].shape
        if len(got) != len(shape) or any(e not in (-1, g) for g, e in zip(got, shape)):
            want = tuple("any" if e == -1 else e for e in shape)
            raise ValueError(f"state entry {name!r} has shape {got}, expected {want}")
        if min(got, default=1) < 1:
            raise ValueError(f"state entry {name!r} is empty: shape {got}")
    for name in arrays:
        if name not in expected:
            raise ValueError(f"state entry {name!r} is not one of this config's parameters")


def _check_input(name: str, value: np.ndarray, shape: tuple[int, ...]) -> None:
    if value.shape != shape:
        raise ValueError(f"{name} has shape {value.shape}, expected {shape}")


# -- the mixture -----------------------------------------------------------------------


def _logsumexp(x: np.ndarray, axis: int = -1) -> np.ndarray:
    """log sum exp over ``axis``, as ``torch.logsumexp``: -inf for all -inf, inf for any
    inf, NaN for NaN."""
    top = x.max(axis, keepdims=True)
    top = np.where(np.isfinite(top), top, 0.0).astype(x.dtype, copy=False)
    with np.errstate(divide="ignore"):
        out = np.log(np.exp(x - top).sum(axis, keepdims=True)) + top
    return out.squeeze(axis)


def _softmax(x: np.ndarray) -> np.ndarray:
    """Softmax over the last dim, as ``torch.softmax`` (NaN where a row has +inf or is
    all -inf)."""
    with np.errstate(invalid="ignore"):
        e = np.exp(x - x.max(-1, keepdims=True))
        return e / e.sum(-1, keepdims=True)


def _logistic_log_pdf(x: np.ndarray, loc: np.ndarray, log_scale: np.ndarray) -> np.ndarray:
    """Elementwise log density of Logistic(loc, exp(log_scale)) at ``x`` (broadcast), at
    -|z| where nothing overflows (:func:`pair2scene.model.mixture.logistic_log_pdf`)."""
    a = np.abs((x - loc) * np.exp(-log_scale))
    return -a - 2.0 * np.log1p(np.exp(-a)) - log_scale


def condition(params: MixtureArrays, dims: Sequence[int], values: np.ndarray) -> MixtureArrays:
    """The mixture conditioned on ``x[dims] = values`` (exact; as
    :func:`pair2scene.model.mixture.condition`): components reweighted by
    ``log p_k(values)``, the given dims' locations set to the values and their log
    scales to -70.

    values : (B, len(dims)) in the target's units (a size goes in as its log).
    """
    dims = list(dims)
    given = np.asarray(values)[..., None, :]  # (B, 1, d)
    log_fit = _logistic_log_pdf(given, params.loc[..., dims], params.log_scale[..., dims])
    logits = params.logits + log_fit.sum(-1)  # (B, K)
    loc, log_scale = params.loc.copy(), params.log_scale.copy()
    loc[..., dims] = given
    log_scale[..., dims] = CONDITIONED_LOG_SCALE
    return MixtureArrays(logits, loc, log_scale)


def check_params(params: MixtureArrays) -> None:
    """Raise :class:`InvalidDistribution` unless every mixture can be drawn from, with
    :func:`pair2scene.model.mixture.check_params`'s messages: locations finite and within
    :data:`MAX_ABS_LOCATION`, log scales finite, weights ``softmax(logits)`` finite."""
    logits, loc, log_scale = params
    weights = _softmax(logits)
    with np.errstate(invalid="ignore"):
        ok = bool((np.abs(loc) <= MAX_ABS_LOCATION).all())  # False for NaN and inf too
    if ok and np.isfinite(log_scale).all() and np.isfinite(weights).all():
        return
    if not np.isfinite(weights).all():
        raise InvalidDistribution("mixture weights are not finite")
    if not np.isfinite(loc).all():
        raise InvalidDistribution("non-finite locations")
    if not ok:
        far = float(np.abs(loc).max())
        raise InvalidDistribution(f"a location of {far:.3g}, beyond {MAX_ABS_LOCATION:g}")
    raise InvalidDistribution("non-finite or zero scales")


def mode(params: MixtureArrays) -> np.ndarray:
    """Location of the heaviest component (the first of equals): (B, D); what
    :func:`sample` returns at temperature 0."""
    k = params.logits.argmax(-1)  # (B,)
    return np.take_along_axis(params.loc, k[..., None, None], axis=-2)[..., 0, :]


def _mirrored(a: np.ndarray, b: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Standardised intervals [a, b] moved off the right tail (where a > 0, to [-b, -a],
    where the sigmoid keeps its digits). Returns (mirrored, lo, hi)."""
    right = a > 0
    return right, np.where(right, -b, a), np.where(right, -a, b)


def _log_interval(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """log(sigmoid(b) - sigmoid(a)) elementwise for a <= b, accurate in both tails."""
    _, lo, hi = _mirrored(a, b)
    log_hi, log_lo = log_expit(hi), log_expit(lo)
    with np.errstate(invalid="ignore", divide="ignore"):
        diff = np.minimum(log_lo - log_hi, 0.0)
        return log_hi + np.log(np.maximum(-np.expm1(diff), 0.0))


def _window_terms(
    params: MixtureArrays, window: Window, temperature: float
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The window in each component's standardised units, a and b (..., K, len(dims)),
    and each component's log mass in it (..., K); float64, the standardising done in
    the parameters' dtype as the torch version does."""
    dims = list(window.dims)
    loc = params.loc[..., dims]
    dtype = loc.dtype
    scale = np.exp(params.log_scale[..., dims]) * temperature
    low = np.asarray(window.low, dtype)
    high = np.maximum(np.asarray(window.high, dtype), low)[..., None, :]
    low = low[..., None, :]
    with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
        a = ((low - loc) / scale).astype(np.float64)
        b = ((high - loc) / scale).astype(np.float64)
    return a, b, _log_interval(a, b).sum(-1)


def window_log_mass(params: MixtureArrays, window: Window, temperature: float = 1.0) -> np.ndarray:
    """Log probability that a draw at ``temperature`` (see :func:`sample`) falls in the
    window: (B,) float64 (-inf where it cannot)."""
    log_mass = _window_terms(params, window, temperature)[2]
    log_w = _log_softmax(params.logits.astype(np.float64) / temperature)
    return _logsumexp(log_w + log_mass, -1)


def sample(
    params: MixtureArrays,
    n: int,
    temperature: float,
    rng: np.random.Generator,
    window: Window | None = None,
) -> np.ndarray:
    """Draw ``n`` candidates from each mixture: -> (B, n, D), in the parameters' dtype.

    The semantics of :func:`pair2scene.model.mixture.sample`: components drawn with
    weights softmax(logits / T), each logistic's scale times T, T = 0 exactly
    :func:`mode`; with a window, each component also weighted by its mass in it and
    each windowed dim drawn from its logistic truncated to the interval (float64), a
    mixture with no mass in its window drawn as if it had none (ignored at T = 0).
    Invalid parameters (:func:`check_params`), weights that overflow at T, and
    non-finite draws raise :class:`InvalidDistribution` with the torch version's
    messages.

    Random numbers, in this order and nothing else from ``rng`` (so the same generator
    state gives the same draws): ``rng.random((M, n))`` float64, one per draw, choosing
    its component by the inverse CDF of the weights (M = the flattened batch), then
    ``rng.random((M, n, D), dtype)`` in the parameters' dtype (float32 or float64),
    floored at the dtype's smallest normal number, for the logistics'
    inverse CDF. The uniforms are drawn in that dtype, not drawn in float64 and cast: a
    cast would round the top 2^-25 of [0, 1) up to 1, an infinite logistic draw.
    """
    check_draw(temperature, n)
    check_params(params)
    logits, loc, log_scale = params
    batch, (k, d) = logits.shape[:-1], loc.shape[-2:]
    dtype = loc.dtype
    if temperature == 0:
        return np.broadcast_to(mode(params)[..., None, :], (*batch, n, d)).copy()

    with np.errstate(over="ignore"):  # overflowing weights are caught below
        tempered = logits.reshape(-1, k) / temperature  # (M, K), in the logits' dtype
    rows = tempered.shape[0]
    if window is not None:
        a, b, log_mass = _window_terms(params, window, temperature)
        m = len(window.dims)
        a, b, log_mass = a.reshape(-1, k, m), b.reshape(-1, k, m), log_mass.reshape(-1, k)
        empty = np.isinf(_logsumexp(tempered.astype(np.float64) + log_mass, -1))  # (M,)
        # A row with no mass in its window is drawn unconfined: its bounds are opened.
        log_mass = np.where(empty[:, None], 0.0, log_mass)
        a = np.where(empty[:, None, None], -np.inf, a)
        b = np.where(empty[:, None, None], np.inf, b)
        tempered = (tempered.astype(np.float64) + log_mass).astype(tempered.dtype)
    probs = _softmax(tempered)  # (M, K)
    if not np.isfinite(probs).all():  # finite logits / T can still overflow
        raise InvalidDistribution(f"mixture weights are not finite at temperature {temperature}")
    cdf = np.cumsum(probs, -1, dtype=np.float64)
    cdf /= cdf[:, -1:]
    # Component j takes u in [cdf[j-1], cdf[j]): zero weights are never drawn.
    comp = (cdf[:, None, :-1] <= rng.random((rows, n))[..., None]).sum(-1)  # (M, n)
    pick = (np.arange(rows)[:, None], comp)
    mu = loc.reshape(-1, k, d)[pick]  # (M, n, D)
    u = np.maximum(rng.random(mu.shape, dtype=dtype), np.finfo(dtype).tiny)
    z = np.log(u) - np.log1p(-u)
    if window is not None:
        dims = list(window.dims)
        z[..., dims] = _truncated_logistic(a[pick], b[pick], u[..., dims].astype(np.float64))
    with np.errstate(over="ignore", invalid="ignore"):  # non-finite draws are caught below
        x = mu + np.exp(log_scale.reshape(-1, k, d)[pick]) * temperature * z
    if not np.isfinite(x).all():
        raise InvalidDistribution(f"non-finite draws at temperature {temperature}")
    return x.reshape(*batch, n, d)


def _truncated_logistic(a: np.ndarray, b: np.ndarray, u: np.ndarray) -> np.ndarray:
    """Standard logistic draws truncated to [a, b] by the inverse CDF at ``u`` in [0, 1)
    (drawn on the :func:`_mirrored` interval and mirrored back); float64."""
    right, lo, hi = _mirrored(a, b)
    p_lo, p_hi = expit(lo), expit(hi)
    p = np.clip(p_lo + u * (p_hi - p_lo), np.finfo(np.float64).tiny, 1.0 - 1e-16)
    z = np.minimum(np.maximum(np.log(p) - np.log1p(-p), lo), hi)
    return np.where(right, -z, z)

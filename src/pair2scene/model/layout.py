"""Layout predictor: the dependent's box given its tuple, as a mixture of logistics.

One relation tuple ``<dependent, support anchor, optional functional anchor>``
goes in; the distribution of the dependent's 12-d box in the support anchor's
canonical frame comes out (:mod:`pair2scene.model.mixture` owns that target
convention). The network, as the method defines it:

- every member of the tuple is Q learned query tokens (paper: Q = 4), plus the
  member's category embedding and an MLP of its log size (clouds are
  normalised, so the size is carried here);
- N blocks (paper: 7, width 512), each
  1. *relational self-attention* over all members' tokens (M*Q tokens, absent
     members masked out as keys). Each anchor's box goes through an MLP into a
     spatial embedding that is added to the keys and values, not the queries:
     a token asks "what" and hears "what, and where". The dependent's box is
     the unknown, so it gets a learned "unknown box" embedding instead;
  2. *geometry-aware cross-attention*: each member's tokens attend to that
     member's own point tokens only (members are folded into the batch: the P
     present members' ``(P, Q, D)`` attend to their ``(P, G, D)``; absent
     members get no update). Within a block, one member's geometry therefore
     reaches another member only through the next block's self-attention;
  3. an MLP; all three pre-norm with residuals;
- a head maps the dependent's Q tokens (flattened) to the K*(1+2*12) raw
  mixture parameters, plus K * 4 turn logits: each component in four quarter turns of
  its yaw (:func:`mixture.turned_components`).

What the inputs already fix is added, not re-learned (:meth:`LayoutPredictor.known_target`):
the dependent's size is an input (its asset is chosen before it is placed), so its
target size in the support's frame is known exactly, and an upright object resting on
its support has its centre at the support's top (the floor: its bottom) plus half its
height. Both are added to every component's locations, and the known size also joins
the dependent's spatial embedding, so the head predicts residuals: a shelf's lower tier,
a lying book. Without this the network has to rediscover a division of two sizes to a
precision of 1e-3 through several MLPs; measured on the full corpus after 4 epochs,
the marginal NLL of the three size dims was still ~ -0.4 nats each.

Loss: mean NLL of the target plus the entropy term of :func:`mixture.loss`.

What the trainer feeds, per variant (``LayoutBatch``; M = 3 members:
0 dependent, 1 support anchor, 2 functional anchor)
--------------------------------------------------------------------------

``full`` (the method) and ``no-pretrain``:
    points         (B, 3, N, 3) each member's cloud in its local frame, normalised by
                   ``pointmae.normalise_points`` (the floor's cloud is the room's, walls
                   included); or, when the encoder is frozen, ``point_tokens`` (B, 3, G,
                   D_enc) / ``point_centers`` (B, 3, G, 3) computed once per distinct
                   cloud by that encoder in eval mode (the ``cpu`` budget assumes this).
    scales         (B, 3, 3) each member's world box size in metres (the floor's: the
                   room's bounds).
    categories     (B, 3) index into :data:`CATEGORY_VOCAB` (the floor is ``floor``);
                   -1 or anything for an absent member.
    anchor_boxes   (B, 2, 12) support and functional anchors' boxes in the support
                   anchor's canonical frame, stored layout (centre, *size*, 6D): row 0
                   is therefore always the unit cube ``(0,0,0, 2,2,2, 1,0,0, 0,1,0)``;
                   row 1 is ``from_vector(func_box).in_frame_of(from_vector(sup_box))``
                   (shards hold world boxes), anything (NaN too) without a functional
                   anchor.
    member_mask    (B, 3) bool, columns 0 and 1 True, column 2: functional anchor present.
    target         (B, 12) the dependent's canonical box as a model target (centre, *log*
                   size, 6D): ``mixture.target_from_box_vector(shard["canonical"])``.
    ``no-pretrain`` differs only in the encoder: built with random weights and trained
    with the predictor (:attr:`LayoutConfig.trains_encoder`); it needs raw points.

``class-only``:
    as ``full`` without ``points`` (pass None): no point encoder, no cross-attention;
    the categories (and sizes) carry each member's identity.

``global`` (no relations: the room alone places the dependent):
    members are the dependent and the room; the functional anchor is ignored.
    points[:, 1]    the room's (the floor's) cloud; scales[:, 1] the room's size;
    categories[:, 1] ``floor``; anchor_boxes[:, 0] the room's bounds in *world*
    coordinates (centre, size, 6D: a floor tuple's ``sup_box`` of the same scene);
    target the dependent's *world* box as a model target
    (``target_from_box_vector(shard["dep_box"])``), for every tuple, whatever its
    support. Columns/rows for the functional anchor are ignored (member_mask[:, 2]
    included). At generation time the samples are world boxes.

Absent members' inputs never reach the output: their category, size and box are
replaced by zeros, their clouds are never encoded (so NaN placeholders are fine),
and their tokens are masked out as keys of the self-attention.

Training notes: when the encoder is frozen (:attr:`LayoutConfig.trains_encoder`
False) its parameters have ``requires_grad`` False; build the optimiser from
``[p for p in model.parameters() if p.requires_grad]``. Dropout, if configured,
draws from torch's global generator.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import NamedTuple

import torch
import torch.nn.functional as F
from torch import Tensor, nn

from pair2scene.curation.frames import (  # noqa: F401  (re-exported)
    FRAME_FUNCTIONAL,
    FRAME_NAMES,
    FRAME_SUPPORT,
    FRAME_WALL,
)
from pair2scene.model import mixture
from pair2scene.model.config import (  # noqa: F401  (re-exported)
    DEPENDENT,
    FLOOR_INDEX,
    FUNCTIONAL,
    HEAD_INIT_STD,
    MIN_ANCHOR_HALF_M,
    N_MEMBERS,
    SUPPORT,
    WALL_INDEX,
    LayoutConfig,
    LayoutVariant,
)
from pair2scene.model.mixture import (
    BOX_DIM,
    MIN_TARGET_SIZE,
    LossParts,
    MixtureParams,
    mixture_params_from_head,
    target_from_box_vector,
)
from pair2scene.model.pair_prior import (
    CENTRE_DIMS,
    mode_table_shape,
    table_shape,
    turn_table_shape,
)


@dataclass
class LayoutBatch:
    """A batch of relation tuples as tensors (see the module docstring per variant).

    Either ``points`` or ``point_tokens`` + ``point_centers`` (cached encoder output)
    feed the geometry; ``class-only`` needs neither.
    """

    categories: Tensor
    """(B, 3) long: category index per member (any value for an absent member)."""
    scales: Tensor
    """(B, 3, 3) float: each member's box size (full extent, metres)."""
    anchor_boxes: Tensor
    """(B, 2, 12) float: support and functional anchors' boxes (centre, size, 6D) in the
    support anchor's canonical frame (``global``: row 0 is the room in world frame)."""
    member_mask: Tensor
    """(B, 3) bool: member present (columns 0, 1 always True)."""
    points: Tensor | None = None
    """(B, 3, N, 3) float: each member's normalised point cloud."""
    point_tokens: Tensor | None = None
    """(B, 3, G, D_enc) float: the encoder's tokens of each member's cloud."""
    point_centers: Tensor | None = None
    """(B, 3, G, 3) float: the encoder's group centres of each member's cloud."""
    target: Tensor | None = None
    """(B, 12) float: the dependent's box as a model target (centre, log size, 6D)."""
    frames: Tensor | None = None
    """(B,) long: the frame each tuple is predicted in (:data:`FRAME_NAMES`); None: the
    support's, for every tuple."""
    frame_sizes: Tensor | None = None
    """(B, 3) float: the size (m) of each tuple's frame box; None: the support's
    (``scales[:, 1]``)."""

    @property
    def batch_size(self) -> int:
        return self.categories.shape[0]

    def to(self, device: torch.device | str) -> LayoutBatch:
        """The batch with every tensor on ``device``."""
        moved = {
            name: (None if value is None else value.to(device))
            for name, value in self.__dict__.items()
        }
        return LayoutBatch(**moved)


class PointMemory(NamedTuple):
    """The point tokens of the present members, the keys and values of the cross-attention."""

    tokens: Tensor
    """(P, G, D) projected point tokens of the P present members."""
    rows: Tensor
    """(P,) long: each one's row in the flattened members ``b * M + m``."""


# -- building blocks -----------------------------------------------------------------


class MLP(nn.Module):
    """Linear -> GELU -> Linear."""

    def __init__(self, d_in: int, d_hidden: int, d_out: int, dropout: float = 0.0) -> None:
        super().__init__()
        self.fc = nn.Linear(d_in, d_hidden)
        self.proj = nn.Linear(d_hidden, d_out)
        self.dropout = nn.Dropout(dropout)

    def forward(self, x: Tensor) -> Tensor:
        return self.dropout(self.proj(F.gelu(self.fc(x))))


class RelationalSelfAttention(nn.Module):
    """Self-attention over all members' tokens; anchors' spatial embeddings join the keys
    and values only."""

    def __init__(self, config: LayoutConfig) -> None:
        super().__init__()
        self.heads = config.heads
        self.dropout = config.dropout
        self.q = nn.Linear(config.width, config.width)
        self.kv = nn.Linear(config.width, 2 * config.width)
        self.proj = nn.Linear(config.width, config.width)
        self.resid_dropout = nn.Dropout(config.dropout)

    def forward(self, x: Tensor, spatial: Tensor, key_mask: Tensor) -> Tensor:
        """x, spatial : (B, T, D); key_mask : (B, T) bool, False for absent members."""
        b, t, d = x.shape
        hs = d // self.heads
        q = self.q(x).view(b, t, self.heads, hs).transpose(1, 2)  # (B, nh, T, hs)
        k, v = self.kv(x + spatial).split(d, dim=-1)
        k = k.view(b, t, self.heads, hs).transpose(1, 2)  # (B, nh, T, hs)
        v = v.view(b, t, self.heads, hs).transpose(1, 2)  # (B, nh, T, hs)
        y = F.scaled_dot_product_attention(
            q,
            k,
            v,
            attn_mask=key_mask[:, None, None, :],  # (B, 1, 1, T)
            dropout_p=self.dropout if self.training else 0.0,
        )
        y = y.transpose(1, 2).reshape(b, t, d)  # (B, T, D)
        return self.resid_dropout(self.proj(y))


class CrossAttention(nn.Module):
    """Each row's query tokens attend to that row's memory tokens."""

    def __init__(self, config: LayoutConfig) -> None:
        super().__init__()
        self.heads = config.heads
        self.dropout = config.dropout
        self.q = nn.Linear(config.width, config.width)
        self.kv = nn.Linear(config.width, 2 * config.width)
        self.proj = nn.Linear(config.width, config.width)
        self.resid_dropout = nn.Dropout(config.dropout)

    def forward(self, x: Tensor, memory: Tensor) -> Tensor:
        """x : (R, Q, D) queries; memory : (R, G, D), row r attends to memory[r] only."""
        r, nq, d = x.shape
        g = memory.shape[1]
        hs = d // self.heads
        q = self.q(x).view(r, nq, self.heads, hs).transpose(1, 2)  # (R, nh, Q, hs)
        k, v = self.kv(memory).split(d, dim=-1)
        k = k.view(r, g, self.heads, hs).transpose(1, 2)  # (R, nh, G, hs)
        v = v.view(r, g, self.heads, hs).transpose(1, 2)  # (R, nh, G, hs)
        y = F.scaled_dot_product_attention(
            q, k, v, dropout_p=self.dropout if self.training else 0.0
        )
        y = y.transpose(1, 2).reshape(r, nq, d)  # (R, Q, D)
        return self.resid_dropout(self.proj(y))


class LayoutBlock(nn.Module):
    """Relational self-attention, then per-member cross-attention to its points, then MLP."""

    def __init__(self, config: LayoutConfig) -> None:
        super().__init__()
        self.queries = config.queries
        self.ln_self = nn.LayerNorm(config.width)
        self.self_attn = RelationalSelfAttention(config)
        self.ln_cross = nn.LayerNorm(config.width) if config.uses_points else None
        self.cross_attn = CrossAttention(config) if config.uses_points else None
        self.ln_mlp = nn.LayerNorm(config.width)
        self.mlp = MLP(config.width, config.mlp_ratio * config.width, config.width, config.dropout)

    def forward(
        self, x: Tensor, spatial: Tensor, key_mask: Tensor, memory: PointMemory | None
    ) -> Tensor:
        """x, spatial : (B, M*Q, D); key_mask : (B, M*Q) bool; memory : the present
        members' point tokens (None without cross-attention)."""
        b, t, d = x.shape
        x = x + self.self_attn(self.ln_self(x), spatial, key_mask)
        if self.cross_attn is not None:
            if memory is None:
                raise ValueError("this block cross-attends to point tokens: memory is None")
            h = self.ln_cross(x).reshape(b * t // self.queries, self.queries, d)  # (B*M, Q, D)
            y = self.cross_attn(h[memory.rows], memory.tokens)  # (P, Q, D)
            # Absent members have nothing to attend to: their rows get no update.
            y = h.new_zeros(h.shape).index_copy(0, memory.rows, y)  # (B*M, Q, D)
            x = x + y.reshape(b, t, d)  # (B, M*Q, D)
        return x + self.mlp(self.ln_mlp(x))


# -- the predictor -------------------------------------------------------------------


class LayoutPredictor(nn.Module):
    """P(dependent's box | tuple) as a mixture of logistics.

    config : the sizes and the variant.
    point_encoder : maps clouds (R, N, 3) to (tokens (R, G, point_dim), centres (R, G, 3))
        (``PointMAEEncoder``); required to feed raw ``points``, unused by ``class-only``
        and when batches carry cached ``point_tokens``. It is taken as built: load
        pretrained weights into it before or after, the predictor never re-initialises
        it. When ``config.trains_encoder`` is False it is frozen and kept in eval mode.
    generator : initialises the predictor's own weights (None: seed 0), so equal
        generators give byte-identical models.
    materialise : False leaves every parameter on the meta device, uninitialised: a
        skeleton that costs no memory whatever the config, for counting parameters and
        reading the expected tensor shapes (:func:`~pair2scene.model.checkpoint.load_checkpoint`
        checks a checkpoint against one, then loads the weights into it with
        ``load_state_dict(..., assign=True)``). Pass an encoder built on the meta device too.
    """

    def __init__(
        self,
        config: LayoutConfig,
        point_encoder: nn.Module | None = None,
        generator: torch.Generator | None = None,
        *,
        materialise: bool = True,
    ) -> None:
        super().__init__()
        self.config = config
        c = config
        # Built on the meta device and initialised from ``generator`` below: the
        # global RNG is neither read nor advanced.
        with torch.device("meta"):
            self.member_queries = nn.Parameter(torch.empty(N_MEMBERS, c.queries, c.width))
            self.category = nn.Embedding(c.n_categories, c.width)
            self.size_mlp = MLP(3, c.width, c.width)
            self.box_mlp = MLP(BOX_DIM, c.width, c.width)
            self.unknown_box = nn.Parameter(torch.empty(c.width))
            self.known_size_mlp = MLP(3, c.width, c.width)
            if c.uses_points:
                self.point_proj = nn.Linear(c.point_dim, c.width)
                self.point_pos = MLP(3, c.width, c.width)
                self.ln_points = nn.LayerNorm(c.width)
            self.blocks = nn.ModuleList(LayoutBlock(c) for _ in range(c.depth))
            self.ln_f = nn.LayerNorm(c.width)
            self.head = MLP(c.queries * c.width, c.width, c.mixture.head_dim)
            if self.uses_frames:
                self.frame = nn.Embedding(len(FRAME_NAMES), c.width)
            if c.uses_pair_prior:  # filled by the trainer, loaded with the weights
                self.register_buffer("pair_centre", torch.empty(table_shape(c.n_categories)))
            if c.uses_pair_modes:  # the same
                shape = mode_table_shape(c.n_categories, c.mixture.num_components)
                self.register_buffer("pair_mode", torch.empty(shape))
            if c.uses_pair_turns:  # the same
                shape = turn_table_shape(c.n_categories, c.mixture.yaw_modes)
                self.register_buffer("pair_turn", torch.empty(shape))
        if materialise:
            self.to_empty(device="cpu")
            seeded = torch.Generator().manual_seed(0) if generator is None else generator
            self._init_weights(seeded)

        self.point_encoder = point_encoder if c.uses_points else None
        if self.point_encoder is not None and not c.trains_encoder:
            self.point_encoder.requires_grad_(False)
            self.point_encoder.eval()

    @property
    def uses_frames(self) -> bool:
        """Whether tuples are predicted in their governing anchor's frame."""
        return self.config.uses_frames

    def _init_weights(self, generator: torch.Generator) -> None:
        """Truncated normal weights with std 1/sqrt(fan_in) (unit gain), residual
        projections further scaled by 1/sqrt(2 * depth) (GPT-2), zero biases, unit layer
        norms; the head's output layer at std 0.02, so training starts from a wide,
        near-uniform mixture centred at 0.

        Not GPT-2's flat 0.02: that suits widths near 768; at width 128 it makes every
        branch ~5x weaker than unit gain, and information that has to cross a value
        and an output projection (an anchor's box reaching the dependent) is then the
        product of several tiny weights: measured on a synthetic copy task, the
        predictor took hundreds of steps to start using the anchor at all."""

        def normal(p: Tensor, s: float) -> None:
            nn.init.trunc_normal_(p, 0.0, s, -2 * s, 2 * s, generator=generator)

        depth_scale = 1.0 / math.sqrt(2 * self.config.depth)
        for name, module in self.named_modules():
            if isinstance(module, nn.LayerNorm):
                nn.init.ones_(module.weight)
                nn.init.zeros_(module.bias)
            elif isinstance(module, nn.Linear):
                s = 1.0 / math.sqrt(module.in_features)
                if name == "head.proj":
                    s = HEAD_INIT_STD
                elif name.startswith("blocks.") and name.endswith("proj"):
                    s *= depth_scale  # one residual projection per sub-layer per block
                normal(module.weight, s)
                nn.init.zeros_(module.bias)
            elif isinstance(module, nn.Embedding):
                normal(module.weight, 1.0)
        normal(self.member_queries, 1.0)
        normal(self.unknown_box, 1.0)  # like the box MLP's output: O(1) per element
        if self.config.uses_pair_prior:
            nn.init.zeros_(self.pair_centre)  # no pair's centre until the trainer fills it
        if self.config.uses_pair_modes:
            nn.init.zeros_(self.pair_mode)
        if self.config.uses_pair_turns:
            nn.init.zeros_(self.pair_turn)

    def train(self, mode: bool = True) -> LayoutPredictor:
        super().train(mode)
        if self.point_encoder is not None and not self.config.trains_encoder:
            self.point_encoder.eval()
        return self

    def num_parameters(self, include_encoder: bool = False) -> int:
        """Parameter count of the predictor (and of the injected encoder if asked)."""
        enc = set() if self.point_encoder is None else set(self.point_encoder.parameters())
        return sum(p.numel() for p in self.parameters() if include_encoder or p not in enc)

    # -- inputs -> tokens ------------------------------------------------------------

    def _point_memory(self, batch: LayoutBatch, mask: Tensor) -> PointMemory:
        """The present members' point tokens, projected to the model width.

        Absent members' clouds (or cached tokens) are never read, so placeholders of any
        value (NaN included) are fine.
        """
        m = mask.shape[1]
        rows = mask.reshape(-1).nonzero().squeeze(1)  # (P,) present rows of B*M
        if batch.point_tokens is not None:
            if self.config.trains_encoder and self.training and torch.is_grad_enabled():
                raise ValueError(
                    "the encoder trains in this configuration: pass raw points, not "
                    "cached point_tokens (cached tokens are for evaluation only)"
                )
            if batch.point_centers is None:
                raise ValueError("point_tokens need point_centers")
            tokens = batch.point_tokens[:, :m].flatten(0, 1)[rows]  # (P, G, Denc)
            centers = batch.point_centers[:, :m].flatten(0, 1)[rows]  # (P, G, 3)
        else:
            if batch.points is None:
                raise ValueError(f"variant {self.config.variant.value!r} needs points")
            if self.point_encoder is None:
                raise ValueError("raw points need a point_encoder (or pass point_tokens)")
            clouds = batch.points[:, :m].flatten(0, 1)[rows]  # (P, N, 3)
            grad = torch.is_grad_enabled() and self.config.trains_encoder
            with torch.set_grad_enabled(grad):
                tokens, centers = self.point_encoder(clouds)  # (P, G, Denc), (P, G, 3)
        if tokens.shape[-1] != self.config.point_dim:
            raise ValueError(
                f"point tokens have width {tokens.shape[-1]}, config.point_dim is "
                f"{self.config.point_dim}"
            )
        tokens = self.ln_points(self.point_proj(tokens) + self.point_pos(centers))  # (P, G, D)
        return PointMemory(tokens, rows)

    def forward(self, batch: LayoutBatch) -> tuple[MixtureParams, Tensor | None]:
        """Mixture parameters per tuple, and the loss when ``batch.target`` is given."""
        c = self.config
        m, q, d = c.n_members, c.queries, c.width
        b = batch.batch_size
        _check_shapes(batch)
        mask = batch.member_mask[:, :m].bool()  # (B, M)

        # Member tokens: role queries + category + size; absent members' inputs zeroed.
        cats = torch.where(mask, batch.categories[:, :m], 0)
        log_size = torch.where(
            mask[..., None], batch.scales[:, :m].clamp_min(MIN_TARGET_SIZE).log(), 0.0
        )
        ident = self.category(cats) + self.size_mlp(log_size)  # (B, M, D)
        x = self.member_queries[:m] + ident[:, :, None, :]  # (B, M, Q, D)
        x = x.reshape(b, m * q, d)  # (B, M*Q, D)

        # Spatial embeddings: the dependent's box is the unknown; anchors' boxes via MLP.
        boxes = target_from_box_vector(
            torch.where(mask[:, 1:, None], batch.anchor_boxes[:, : m - 1], 0.0)
        )  # (B, M-1, 12), log sizes
        boxes = torch.where(mask[:, 1:, None], boxes, 0.0)
        known = self.known_target(batch)  # (B, 12)
        dep_spatial = self.unknown_box + self.known_size_mlp(known[:, 3:6])  # (B, D)
        if self.uses_frames:
            frames = batch.frames if batch.frames is not None else known.new_zeros(b).long()
            dep_spatial = dep_spatial + self.frame(frames)
        spatial = torch.cat([dep_spatial[:, None], self.box_mlp(boxes)], dim=1)  # (B, M, D)
        spatial = spatial[:, :, None, :].expand(b, m, q, d).reshape(b, m * q, d)
        key_mask = mask[:, :, None].expand(b, m, q).reshape(b, m * q)  # (B, M*Q)

        memory = self._point_memory(batch, mask) if c.uses_points else None
        for block in self.blocks:
            x = block(x, spatial, key_mask, memory)

        dependent = self.ln_f(x[:, :q]).reshape(b, q * d)  # (B, Q*D)
        raw = self.head(dependent)  # (B, K*(1+2*12+Q))
        mix = c.mixture
        if c.uses_pair_turns:  # the pair's own split of yaw turns, to every component
            k, turns = mix.num_components, mix.yaw_modes
            prior = self.pair_lookup(self.pair_turn, batch).repeat(1, k)  # (B, K*Q)
            raw = torch.cat([raw[:, : -k * turns], raw[:, -k * turns :] + prior], dim=1)
        params = mixture_params_from_head(
            raw, mix.num_components, BOX_DIM, mix.min_log_scale, mix.max_log_scale, mix.yaw_modes
        )
        params = params._replace(loc=params.loc + known[:, None, :])
        if c.uses_pair_modes:  # the pair's clusters: each component its own centre and share
            modes = self.pair_lookup(self.pair_mode, batch)  # (B, K, 3)
            modes = modes.repeat_interleave(mix.yaw_modes, dim=1)  # (B, K*Q, 3): turns alike
            loc = params.loc.clone()
            loc[..., :CENTRE_DIMS] += modes[..., :CENTRE_DIMS]
            params = params._replace(logits=params.logits + modes[..., CENTRE_DIMS], loc=loc)
        if batch.target is None:
            return params, None
        return params, self.loss(params, batch.target)[0]

    def known_target(self, batch: LayoutBatch) -> Tensor:
        """(B, 12) what the inputs fix of the target: the dependent's log size in the
        model frame and the centre height of an upright object resting on its support's
        top (on the floor: the room's bottom; every frame of a floor object spans the
        room's height, so its bottom is the floor); 0 elsewhere. ``global``: world frame, the
        floor at z = 0."""
        dep = batch.scales[:, DEPENDENT].clamp_min(MIN_TARGET_SIZE)  # (B, 3) metres
        known = dep.new_zeros(dep.shape[0], BOX_DIM)
        if self.config.variant is LayoutVariant.GLOBAL:
            known[:, 2] = 0.5 * dep[:, 2]
            known[:, 3:6] = dep.log()
            return known
        frame = batch.scales[:, SUPPORT] if batch.frame_sizes is None else batch.frame_sizes
        half = (0.5 * frame).clamp_min(1e-9)  # (B, 3)
        size = dep / half.clamp_min(MIN_ANCHOR_HALF_M)  # model-frame size
        top = half[:, 2] / half[:, 2].clamp_min(MIN_ANCHOR_HALF_M)  # the support's top
        # A mounted object's frame (its wall's) spans floor to ceiling like a floor
        # object's: its height is counted from the floor too, the hanging height learned.
        support = batch.categories[:, SUPPORT]
        on_floor = (support == FLOOR_INDEX) | (support == WALL_INDEX)
        known[:, 2] = torch.where(on_floor, -top, top) + 0.5 * size[:, 2]
        known[:, 3:6] = size.log()
        if self.config.uses_pair_prior:
            known[:, :CENTRE_DIMS] = self.pair_centres(batch)
        return known

    def pair_centres(self, batch: LayoutBatch) -> Tensor:
        """(B, 2) the pair table's centre of each tuple (:mod:`pair2scene.model.pair_prior`;
        0 for a pair it lacks)."""
        return self.pair_lookup(self.pair_centre, batch)

    def pair_lookup(self, table: Tensor, batch: LayoutBatch) -> Tensor:
        """(B, ...) ``table``'s row (indexed [frame anchor, dependent, frame]) of each
        tuple."""
        cats = batch.categories
        frames = batch.frames if self.uses_frames else None
        frames = frames if frames is not None else torch.zeros_like(cats[:, 0])
        anchor = torch.where(frames == FRAME_FUNCTIONAL, cats[:, FUNCTIONAL], cats[:, SUPPORT])
        anchor = torch.where(frames == FRAME_WALL, WALL_INDEX, anchor)
        n_anchor, n_dep = table.shape[:2]
        return table[anchor.clamp(0, n_anchor - 1), cats[:, DEPENDENT].clamp(0, n_dep - 1), frames]

    def loss(self, params: MixtureParams, target: Tensor) -> tuple[Tensor, LossParts]:
        """Mean NLL of ``target`` (B, 12) plus the configured entropy term; and its parts."""
        mix = self.config.mixture
        return mixture.loss(
            params,
            self.to_mixture_space(target),
            mix.entropy_weight,
            mix.entropy_regulariser,
            mix.yaw_modes,
        )

    def log_prob(self, params: MixtureParams, target: Tensor) -> Tensor:
        """(B,) log density of ``target`` (B, 12) (model frame, log size)."""
        return mixture.log_prob(params, self.to_mixture_space(target))

    def to_mixture_space(self, target: Tensor) -> Tensor:
        """Targets -> the vector the mixture models (the upright-rotation base removed,
        :func:`mixture.rotation_offset`; unit Jacobian)."""
        if not self.config.mixture.rotation_base:
            return target
        return target - mixture.rotation_offset(target)

    def from_mixture_space(self, y: Tensor) -> Tensor:
        """Inverse of :meth:`to_mixture_space`, for samples of the mixture: (..., 12)."""
        if not self.config.mixture.rotation_base:
            return y
        return y + mixture.rotation_offset(y)


def _check_shapes(batch: LayoutBatch) -> None:
    b = batch.batch_size
    expected = {
        "categories": (b, N_MEMBERS),
        "scales": (b, N_MEMBERS, 3),
        "anchor_boxes": (b, N_MEMBERS - 1, BOX_DIM),
        "member_mask": (b, N_MEMBERS),
    }
    if batch.target is not None:
        expected["target"] = (b, BOX_DIM)
    for name, shape in expected.items():
        got = tuple(getattr(batch, name).shape)
        if got != shape:
            raise ValueError(f"LayoutBatch.{name} has shape {got}, expected {shape}")
    for name in ("points", "point_tokens", "point_centers"):
        value = getattr(batch, name)
        if value is not None and (value.dim() != 4 or tuple(value.shape[:2]) != (b, N_MEMBERS)):
            raise ValueError(
                f"LayoutBatch.{name} has shape {tuple(value.shape)}, expected (B={b}, 3, ., .)"
            )

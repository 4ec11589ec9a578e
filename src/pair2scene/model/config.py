"""The layout model's settings and constants, without torch.

What both the torch modules (:mod:`~pair2scene.model.layout`, :mod:`~pair2scene.model.mixture`,
:mod:`~pair2scene.model.pointmae`, which re-export these names) and their torch-free twins
(:mod:`~pair2scene.model.np_layout`, :mod:`~pair2scene.model.np_pointmae`) need: a
checkpoint's configuration is read, and a scene generated, without importing torch.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, replace
from enum import Enum

from pair2scene.curation.dataset import CATEGORY_VOCAB
from pair2scene.errors import UserError

BOX_DIM = 12
"""Dimension of the box target: centre 3, log size 3, 6D rotation 6."""

MIN_TARGET_SIZE = 1e-6
"""Canonical-frame sizes are clamped to this before the log: a zero extent (a flat
decal stored without thickness) would give -inf. Real thin objects are ~1e-3 of
a room's half-size, far above it."""

GRAM_SCHMIDT_EPS = 1e-9
"""Floor on vector norms in Gram-Schmidt, as in the numpy
:func:`~pair2scene.scene.geometry.sixd_to_matrix`: keeps a degenerate 6D finite."""

MAX_ABS_LOCATION = 1e6
"""Largest component location :func:`sample` accepts, in the target's units (anchor
half-sizes in the model frame; metres for ``global``): a million anchor half-sizes away
is no placement any room holds, only what a broken checkpoint outputs (a trained one
stays within a few dozen)."""


class InvalidDistribution(UserError):
    """Mixture parameters no draw can come from: non-finite or absurd locations,
    non-finite scales, weights that are not a distribution (NaN, or every component at
    zero). What a broken checkpoint (finite but extreme weights) produces; one line, not
    torch's ``invalid multinomial distribution``."""

    def __init__(self, problem: str, source: str | None = None) -> None:
        self.problem, self.source = problem, source
        who = "the model" if source is None else f"{source}: the checkpoint"
        super().__init__(f"{who} produces invalid distributions ({problem})")

    def named(self, source: object) -> InvalidDistribution:
        """The same error naming where the model came from (a checkpoint folder)."""
        return InvalidDistribution(self.problem, str(source))


ROTATION_PAIRS = ((6, 7), (9, 10))
"""Dims of the box target that turn as 2D vectors with the yaw: the rotation's first
column (c0_x, c0_y) and the upright residual of the second (see
:func:`~pair2scene.model.mixture.rotation_offset`)."""
CONDITIONED_LOG_SCALE = -70.0
"""The log scale conditioning gives the dims it fixes (``condition``, torch's and numpy's):
samples reproduce the given values to within ~1e-30."""
LAYER_NORM_EPS = 1e-5
"""``torch.nn.LayerNorm``'s default eps, which every layer norm of the predictor and the
encoder uses."""


def check_draw(temperature: float, n: int) -> None:
    """ValueError unless ``n >= 1`` draws at a finite ``temperature >= 0`` are asked (the
    mixture samplers, torch's and numpy's)."""
    if temperature < 0 or not math.isfinite(temperature):
        raise ValueError(f"temperature must be finite and >= 0, got {temperature}")
    if n < 1:
        raise ValueError(f"n must be >= 1, got {n}")


class EntropyRegulariser(str, Enum):
    """Sign of the entropy term in :func:`loss` (see the module docstring)."""

    BONUS = "bonus"
    """Loss = NLL - lambda * H: keeps the mixture weights spread (no dead components)."""
    PENALTY = "penalty"
    """Loss = NLL + lambda * H: each prediction commits to few components."""


@dataclass(frozen=True)
class MixtureConfig:
    """The mixture head's hyper-parameters; the layout model's config embeds one."""

    num_components: int = 4
    """K, the number of logistic components (the paper uses 4)."""
    dim: int = BOX_DIM
    """D, the dimension of the modelled vector (12 for a box, see the module docstring)."""
    min_log_scale: float = -7.0
    """Lower bound on each logistic's log scale: e^-7 ~ 1e-3 canonical units, i.e. half
    a millimetre on a 1 m desk, finer than any annotation. Without a floor the NLL of
    duplicated training boxes rewards collapsing a component onto them (scale -> 0)."""
    max_log_scale: float = 5.0
    """Upper bound: e^5 ~ 150 anchor half-sizes, wider than any room; it never binds in
    practice and only keeps exp() finite for a diverging head."""
    entropy_weight: float = 0.01
    """lambda, the weight of the mixture-weight entropy term. The 12-d NLL is O(10) nats in size
    per tuple and H <= log 4 ~ 1.4, so 0.01 is a nudge, not a competing objective; a
    starting point to tune on val NLL."""
    entropy_regulariser: EntropyRegulariser = EntropyRegulariser.BONUS
    """Sign of the entropy term: BONUS keeps weights spread, PENALTY sharpens them."""
    rotation_base: bool = True
    """Model the rotation's second column relative to ``e_z x`` the first (see
    :func:`rotation_offset`): exact for every upright object, whatever its yaw."""
    yaw_modes: int = 4
    """Q, the right-angle yaw turns each component comes in (module docstring, "Right-angle
    yaw modes"): 4 = quarter turns, 1 = off (checkpoints written before it load with 1).
    Only for the 12-d box (dim 12); one of 1, 2, 4."""

    def __post_init__(self) -> None:
        if self.yaw_modes not in (1, 2, 4):
            raise ValueError(f"yaw_modes must be 1, 2 or 4, got {self.yaw_modes}")
        if self.yaw_modes > 1 and self.dim != BOX_DIM:
            raise ValueError(f"yaw_modes > 1 needs the {BOX_DIM}-d box, got dim {self.dim}")

    @property
    def head_dim(self) -> int:
        """Width of the flat head output: K * (1 + 2D), plus K * Q turn logits for Q > 1."""
        turns = self.yaw_modes if self.yaw_modes > 1 else 0
        return self.num_components * (1 + 2 * self.dim + turns)


FLOOR_INDEX = CATEGORY_VOCAB.index("floor")
"""Category row of the floor (a support anchor that is the room)."""
WALL_INDEX = CATEGORY_VOCAB.index("wall")
"""Category row of a wall (the support anchor of a mounted object)."""
N_MEMBERS = 3
"""Tuple members, in this order: dependent, support anchor, functional anchor."""
DEPENDENT, SUPPORT, FUNCTIONAL = 0, 1, 2
MIN_ANCHOR_HALF_M = 0.05
"""Floor on the support's half-size per axis in the model frame (metres), see
:mod:`pair2scene.model.features`: canonical heights on 1.7 cm counter tops would reach
the hundreds."""
PAIR_PRIOR_MIN_TUPLES = 5
"""Train tuples a category pair needs (in one frame) for its own median centre in the
pair table (:attr:`LayoutConfig.pair_prior`); fewer: no offset, the network alone."""
HEAD_INIT_STD = 0.02
"""Std of the head's output layer at initialisation: raw outputs start near 0, i.e.
uniform weights, locations near 0 and log scales near 0 (unit-scale logistics)."""


class LayoutVariant(str, Enum):
    """The method and its ablations (see the module docstring for what each is fed)."""

    FULL = "full"
    """The method: pretrained point encoder, relations to both anchors."""
    CLASS_ONLY = "class-only"
    """No geometry: category embeddings (and sizes) instead of point features."""
    NO_PRETRAIN = "no-pretrain"
    """As full, but the point encoder starts from random weights and trains."""
    GLOBAL = "global"
    """No relations: the dependent and the room only, world-frame targets."""


@dataclass(frozen=True)
class LayoutConfig:
    """Hyper-parameters of :class:`LayoutPredictor`."""

    width: int = 512
    """D, the token width (paper: 512)."""
    depth: int = 7
    """Number of blocks (paper: 7)."""
    heads: int = 8
    """Attention heads in both attentions; must divide ``width``."""
    queries: int = 4
    """Q, learned query tokens per member (paper: 4)."""
    mlp_ratio: int = 4
    """Hidden width of each block's MLP, in multiples of ``width``."""
    point_dim: int = 384
    """Width of the point encoder's tokens (``PointMAEEncoder``'s D_enc); they are
    projected to ``width``. Unused by ``class-only``."""
    n_categories: int = len(CATEGORY_VOCAB)
    """Rows of the category embedding: the canonical categories, then ``unknown``."""
    dropout: float = 0.0
    """Dropout on attention weights and residual branches. Draws from torch's global
    generator (nn.Dropout has no other), so keep 0 where runs must be byte-identical."""
    mixture: MixtureConfig = field(default_factory=MixtureConfig)
    """The output distribution: K components (paper: 4) over the 12-d box, the log-scale
    bounds, and lambda / sign of the entropy regulariser."""
    variant: LayoutVariant = LayoutVariant.FULL
    """Which network: the method or one of its ablations."""
    finetune_encoder: bool = False
    """``full`` / ``global``: also train the pretrained encoder (False keeps it frozen,
    in eval mode, and lets the trainer cache its tokens). ``no-pretrain`` always trains
    it."""
    anchor_frames: bool = True
    """Predict each tuple in the frame of the anchor that governs it (a floor object
    against a wall in the wall's frame, one with a functional anchor in that anchor's
    footprint frame; docs/model.md), with a learned embedding of which frame it is.
    False: every tuple in its support's frame (the paper; checkpoints written before
    issue 18). ``global`` ignores it."""
    pair_prior: bool = False
    """Add each (frame anchor, dependent) category pair's median centre across its frame
    (x, y, from the train tuples, pairs with at least :data:`PAIR_PRIOR_MIN_TUPLES`) to
    every component's location, as the known size is added: the network predicts the
    residual, so a rare pair (a pillow on a bed) keeps its own placement where a shared
    network averages it away (docs/model.md). The table is the checkpoint's
    ``pair_centre`` buffer. ``global`` ignores it."""
    pair_turns: bool = False
    """Add each (frame anchor, dependent) pair's log share of each right-angle yaw turn
    (from the train tuples, pairs with at least :data:`PAIR_PRIOR_MIN_TUPLES`) to every
    component's turn logits: the network predicts the residual, so a pair keeps its own
    split of yaws (a pillow on a bed along it, turned end-on only by a fifth) where a
    shared network gives every small object on a bed one split (docs/model.md). The table
    is the checkpoint's ``pair_turn`` buffer. Needs ``mixture.yaw_modes`` > 1; ``global``
    ignores it."""
    pair_modes: bool = False
    """Give each (frame anchor, dependent) pair one centre per mixture component instead
    of its median alone: its train tuples' centres in ``mixture.num_components`` k-means
    clusters, largest first, each added to its component's location (as an offset from
    the median) and its log share to the component's logit. A pair whose tuples lie in
    two places (pillows at a bed's head, a fifth towards its foot) then has a component
    at each, where one median left the network's residuals to reach the second
    (docs/model.md). The table is the checkpoint's ``pair_mode`` buffer. Needs
    ``pair_prior``; ``global`` ignores it."""

    def __post_init__(self) -> None:
        object.__setattr__(self, "variant", LayoutVariant(self.variant))
        if self.width % self.heads:
            raise ValueError(f"heads ({self.heads}) must divide width ({self.width})")
        if min(self.width, self.depth, self.heads, self.queries, self.mlp_ratio) < 1:
            raise ValueError("width, depth, heads, queries and mlp_ratio must be >= 1")
        if self.mixture.dim != BOX_DIM:
            raise ValueError(
                f"the layout head models a {BOX_DIM}-d box, got dim {self.mixture.dim}"
            )

    @property
    def n_members(self) -> int:
        """Members the network sees: 2 for ``global`` (dependent, room), else 3."""
        return 2 if self.variant is LayoutVariant.GLOBAL else N_MEMBERS

    @property
    def uses_frames(self) -> bool:
        """Whether tuples are predicted in their governing anchor's frame (``global``
        predicts in the world's, whatever ``anchor_frames`` says)."""
        return self.anchor_frames and self.variant is not LayoutVariant.GLOBAL

    @property
    def uses_pair_prior(self) -> bool:
        """Whether the network adds the pair table's centres (``global`` never does)."""
        return self.pair_prior and self.variant is not LayoutVariant.GLOBAL

    @property
    def uses_pair_modes(self) -> bool:
        """Whether the network adds the pair table's cluster centres and shares."""
        return self.pair_modes and self.uses_pair_prior

    @property
    def uses_pair_turns(self) -> bool:
        """Whether the network adds the pair table's yaw-turn shares to its turn logits."""
        return (
            self.pair_turns
            and self.mixture.yaw_modes > 1
            and self.variant is not LayoutVariant.GLOBAL
        )

    @property
    def uses_points(self) -> bool:
        """Whether the network has a point encoder and cross-attention."""
        return self.variant is not LayoutVariant.CLASS_ONLY

    @property
    def loads_pretrained_encoder(self) -> bool:
        """Whether the trainer loads pretrained Point-MAE weights into the encoder."""
        return self.variant in (LayoutVariant.FULL, LayoutVariant.GLOBAL)

    @property
    def trains_encoder(self) -> bool:
        """Whether the encoder's weights get gradients (else frozen, eval mode)."""
        if self.variant is LayoutVariant.NO_PRETRAIN:
            return True
        return self.uses_points and self.finetune_encoder

    def with_variant(self, variant: LayoutVariant | str) -> LayoutConfig:
        """The same sizes for another variant."""
        return replace(self, variant=LayoutVariant(variant))


MIN_HALF_DIAGONAL = 1e-6
"""Floor on the normalising half-diagonal (metres): a degenerate zero-size box
would divide by zero; real assets are at least 1 mm along every axis."""


# -- config ----------------------------------------------------------------------------
@dataclass(frozen=True)
class PointMAEConfig:
    """Hyper-parameters of the encoder and its pre-training decoder."""

    n_points: int = 2048
    """Points per cloud (``pair2scene.assets.pointcloud.DEFAULT_POINTS``); the encoder
    accepts any N >= group_size, this is what pre-training samples."""
    n_groups: int = 64
    """G, groups (and tokens) per cloud, centres by farthest point sampling."""
    group_size: int = 32
    """k, points per group (nearest neighbours of the centre); 64 x 32 covers 2048 points."""
    width: int = 256
    """D, the token width of the encoder (and the decoder)."""
    depth: int = 6
    """Transformer blocks of the encoder."""
    heads: int = 4
    """Attention heads; must divide ``width``."""
    mlp_ratio: float = 4.0
    """Hidden width of each block's MLP, as a multiple of ``width``."""
    pointnet_hidden: int = 128
    """h of the mini-PointNet: 3 -> h -> 2h per point, then [point, group max] 4h -> 4h ->
    D; 128 is Point-MAE's (3-128-256, 512-512-D)."""
    pos_hidden: int = 128
    """Hidden width of the positional-embedding MLP of the group centres."""
    mask_ratio: float = 0.6
    """Fraction of groups masked in pre-training (Point-MAE's 0.6)."""
    decoder_depth: int = 2
    """Transformer blocks of the pre-training decoder (Point-MAE uses 4 with depth 12)."""
    decoder_heads: int = 4
    """Attention heads of the decoder; must divide ``width``."""
    dropout: float = 0.0
    """Dropout in attention and MLPs; Point-MAE pre-trains without it."""

    def __post_init__(self) -> None:
        if self.width % self.heads or self.width % self.decoder_heads:
            raise ValueError(f"width {self.width} must be divisible by the head counts")
        if not 0 < self.group_size <= self.n_points or self.n_groups > self.n_points:
            raise ValueError("need group_size <= n_points and n_groups <= n_points")
        if not 0.0 <= self.mask_ratio < 1.0:
            raise ValueError(f"mask_ratio must be in [0, 1), got {self.mask_ratio}")

    @property
    def n_masked(self) -> int:
        """Groups masked per cloud in pre-training: floor(mask_ratio * G), as Point-MAE."""
        return int(self.mask_ratio * self.n_groups)

    @classmethod
    def tiny(cls) -> PointMAEConfig:
        """For tests: 256 points, 16 groups of 16, width 32, depth 2 (seconds on a CPU)."""
        return cls(
            n_points=256, n_groups=16, group_size=16, width=32, depth=2, heads=2,
            pointnet_hidden=16, pos_hidden=16, decoder_depth=1, decoder_heads=2,
        )  # fmt: skip

    @classmethod
    def point_mae(cls) -> PointMAEConfig:
        """The original Point-MAE (ShapeNet) setting: 1024 points, 64 x 32, 384 x 12."""
        return cls(
            n_points=1024, n_groups=64, group_size=32, width=384, depth=12, heads=6,
            pointnet_hidden=128, decoder_depth=4, decoder_heads=6,
        )  # fmt: skip

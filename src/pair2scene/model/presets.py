"""Named model and training presets: ``tiny`` (tests), ``cpu`` (the default), ``paper``.

A preset fixes everything a training run needs besides the data: the layout
predictor's sizes, the point encoder's sizes (and so the points per cloud), and
the optimiser schedule. The variant (full or an ablation) is chosen separately:
``preset.for_variant("class-only")`` keeps the sizes.

How ``cpu`` was sized (2 CPU cores, ~13k training tuples, <= 45 minutes, <= 8 GB)
-----------------------------------------------------------------------------
With the encoder frozen (``full``, ``global``; ``class-only`` has none), the point
tokens of each distinct cloud are computed once and cached, so a step costs the
predictor alone; its bulk is the cross-attention over the present members' point
tokens (~2.1 members x G = 32 tokens per tuple). On the development machine (2 cores,
torch 2.13 CPU) a step of 64 tuples takes ~80 ms and an epoch of the AI2-THOR +
ProcTHOR-1k train split (12,853 tuples, 201 steps, plus the validation NLL) ~18 s, so
the 40 epochs of ``cpu`` take ~12 minutes, plus ~1 minute to build and encode the 4.8k
distinct clouds (``benchmarks/model.py``, docs/benchmarks.md; the validation NLL is
still falling slowly at 40 epochs, docs/model.md). Peak memory of the whole run is
~1 GB.

``no-pretrain`` trains the encoder, so its tokens cannot be cached: every step encodes
the ~134 present clouds of a batch, ~35x the cached step on 2 cores. Within the same
budget that is 2 epochs (:data:`NO_PRETRAIN_EPOCH_DIVISOR`): on CPU the ablation
compares at equal time, not equal epochs; run it on a GPU to compare at equal epochs.
``full`` with ``finetune_encoder`` costs the same.
"""

from __future__ import annotations

from dataclasses import dataclass, replace

from pair2scene.assets.pointcloud import DEFAULT_POINTS, PAPER_POINTS
from pair2scene.model.layout import LayoutConfig, LayoutVariant
from pair2scene.model.mixture import MixtureConfig
from pair2scene.model.pointmae import PointMAEConfig

DEFAULT_PRESET = "cpu"
"""The preset a command uses unless told otherwise."""
NO_PRETRAIN_EPOCH_DIVISOR = 20
"""``no-pretrain`` encodes every cloud at every step (no cached tokens); on CPU that is
~35x the cached step, so :meth:`TrainPreset.for_variant` divides the ``cpu`` preset's
epochs by this much (40 -> 2) to stay within the same 45 minutes."""


@dataclass(frozen=True)
class TrainPreset:
    """Model sizes and optimiser schedule of one named training setup."""

    name: str
    """Key in :data:`PRESETS`."""
    layout: LayoutConfig
    """The layout predictor (its ``point_dim`` equals ``encoder.width``)."""
    encoder: PointMAEConfig
    """The point encoder (and its pre-training); ``encoder.n_points`` points per cloud."""
    batch_size: int
    """Tuples per optimiser step."""
    epochs: int
    """Passes over the training tuples."""
    lr: float
    """Peak AdamW learning rate (after warm-up; cosine decay to ``min_lr_ratio * lr``)."""
    weight_decay: float
    """AdamW decoupled weight decay, on matrices and embeddings only (not biases, norms)."""
    warmup_steps: int
    """Steps of linear learning-rate warm-up from 0."""
    min_lr_ratio: float = 0.1
    """End of the cosine decay, as a fraction of ``lr``."""
    grad_clip: float = 1.0
    """Clip the global gradient norm to this (0: no clipping); guards the NLL's early
    spikes when a logistic's scale collapses onto duplicated boxes."""
    encoder_lr_scale: float = 1.0
    """Learning rate of a trained encoder relative to ``lr`` (``no-pretrain``, or
    ``full`` with ``layout.finetune_encoder``)."""

    def __post_init__(self) -> None:
        if self.layout.uses_points and self.layout.point_dim != self.encoder.width:
            raise ValueError(
                f"preset {self.name!r}: layout.point_dim {self.layout.point_dim} must equal "
                f"encoder.width {self.encoder.width}"
            )
        if min(self.batch_size, self.epochs) < 1 or self.lr <= 0 or self.warmup_steps < 0:
            raise ValueError(f"preset {self.name!r}: bad schedule")

    @property
    def n_points(self) -> int:
        """Points per cloud (the encoder's)."""
        return self.encoder.n_points

    def for_variant(self, variant: LayoutVariant | str) -> TrainPreset:
        """The same preset for another variant; ``no-pretrain`` gets fewer epochs on the
        ``cpu`` preset (see :data:`NO_PRETRAIN_EPOCH_DIVISOR`)."""
        variant = LayoutVariant(variant)
        epochs = self.epochs
        if variant is LayoutVariant.NO_PRETRAIN and self.name == "cpu":
            epochs = max(1, epochs // NO_PRETRAIN_EPOCH_DIVISOR)
        return replace(self, layout=self.layout.with_variant(variant), epochs=epochs)

    def steps_per_epoch(self, n_tuples: int) -> int:
        """Optimiser steps in one pass over ``n_tuples`` (the last batch may be partial)."""
        return -(-n_tuples // self.batch_size)


# fmt: off
PRESETS: dict[str, TrainPreset] = {
    "tiny": TrainPreset(
        name="tiny",
        layout=LayoutConfig(width=32, depth=2, heads=2, queries=2, mlp_ratio=2, point_dim=32),
        encoder=PointMAEConfig.tiny(),
        batch_size=8, epochs=2, lr=1e-3, weight_decay=0.0, warmup_steps=0,
    ),
    "cpu": TrainPreset(
        name="cpu",
        # K = 8 (the paper: 4): measured on the full corpus, 4 diagonal components cannot
        # cover both the position modes and the four axis-aligned yaws of many tuples.
        layout=LayoutConfig(width=128, depth=4, heads=4, queries=4, point_dim=128,
                            mixture=MixtureConfig(num_components=8)),
        # 32 groups of 64 points cover a 2048-point cloud (the cache's default) once:
        # the predictor's cost grows with G, the encoder's only once per cloud.
        encoder=PointMAEConfig(n_points=DEFAULT_POINTS, n_groups=32, group_size=64,
                               width=128, depth=4, heads=4, pointnet_hidden=64,
                               pos_hidden=64, decoder_depth=2, decoder_heads=4),
        batch_size=64, epochs=40, lr=5e-4, weight_decay=0.05, warmup_steps=300,
    ),
    "paper": TrainPreset(
        name="paper",
        # The paper: Q = 4 queries per object, 7 blocks of width 512, K = 4 logistics,
        # 8192 points per cloud. Heads, the encoder's sizes and the schedule are not
        # given by the paper: Point-MAE's own encoder (384 x 12, 6 heads), groups of 32
        # covering 8192 points, and a common transformer schedule.
        layout=LayoutConfig(width=512, depth=7, heads=8, queries=4, point_dim=384,
                            mixture=MixtureConfig(num_components=4)),
        encoder=PointMAEConfig(n_points=PAPER_POINTS, n_groups=256, group_size=32,
                               width=384, depth=12, heads=6, pointnet_hidden=256,
                               decoder_depth=4, decoder_heads=6),
        batch_size=128, epochs=200, lr=1e-4, weight_decay=0.05, warmup_steps=2000,
    ),
}
# fmt: on


def preset(name: str = DEFAULT_PRESET, variant: LayoutVariant | str | None = None) -> TrainPreset:
    """The preset ``name``, for ``variant`` if given. Unknown name: ValueError listing them."""
    try:
        p = PRESETS[name]
    except KeyError:
        raise ValueError(f"unknown preset {name!r}; choose one of {', '.join(PRESETS)}") from None
    return p if variant is None else p.for_variant(variant)

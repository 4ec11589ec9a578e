"""Pre-training the Point-MAE encoder on the procedural asset library.

``pretrain(config, out_dir)`` builds a point-cloud dataset from the procedural
generators (every non-structure category, several sizes, styles and seeds),
trains :class:`~pair2scene.model.pointmae.PointMAE` by masked autoencoding with
AdamW, and writes to ``out_dir``:

- ``encoder.safetensors``: the encoder's weights (the decoder is pre-training only);
- ``pointmae.json``: the encoder config, the input normalisation, the pre-training
  config and its losses. :func:`load_encoder` reads both back.

At every validation step the run's state (weights, AdamW moments, the generator) is saved
as ``pretrain_state.safetensors`` + ``.json``; the same call on the same folder resumes
from it and ends with the same weights as an uninterrupted run.

Every cloud is normalised by its box, as the layout model must do
(:func:`pair2scene.model.pointmae.normalise_points`).
"""

from __future__ import annotations

import dataclasses
import json
import math
import time
from collections.abc import Sequence
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
import torch

from pair2scene.assets.pointcloud import sample_asset
from pair2scene.assets.registry import generate, generators
from pair2scene.categories import CATEGORIES, is_structure
from pair2scene.errors import UserError
from pair2scene.io.atomic import atomic_write_bytes, atomic_write_text
from pair2scene.io.jsondoc import read_json_document
from pair2scene.model.checkpoint import (
    load_training_state,
    read_training_state,
    save_training_state,
)
from pair2scene.model.pointmae import PointMAE, PointMAEConfig, PointMAEEncoder, normalise_points
from pair2scene.progress import track

ENCODER_FILE = "encoder.safetensors"
CONFIG_FILE = "pointmae.json"
FORMAT = "pair2scene.pointmae"
VERSION = 1
NORMALISATION = (
    "points in the object's local frame, minus the box centre, divided by the box "
    "half-diagonal |size|/2 (the box fits the unit sphere); the size is a separate input"
)
"""Written into ``pointmae.json`` so that a consumer can check what the weights expect."""
STATE_STEM = "pretrain_state"
STATE_FORMAT = "pair2scene.pretrain-state"
FINAL_LOSS_STEPS = 50
"""The reported final training loss is the mean over this many last steps (one batch's
loss is noisy: the masks and the assets vary)."""


@dataclass(frozen=True)
class PretrainConfig:
    """What :func:`pretrain` builds and how long it trains."""

    model: PointMAEConfig = field(default_factory=PointMAEConfig)
    """The encoder and decoder; ``model.n_points`` points are sampled per cloud."""
    steps: int = 2000
    """Optimiser steps. About 1 s each on 2 CPU cores at the default model and batch 16."""
    batch_size: int = 32
    """Clouds per step."""
    lr: float = 1e-3
    """Peak AdamW learning rate (Point-MAE's)."""
    weight_decay: float = 0.05
    """AdamW weight decay (Point-MAE's); not applied to biases, norms and the mask token."""
    warmup_steps: int = 100
    """Linear learning-rate warm-up from 0, then a cosine decay to 0 at ``steps``."""
    grad_clip: float = 10.0
    """Gradient-norm clip (Point-MAE's); 0 disables it."""
    categories: tuple[str, ...] | None = None
    """Categories to draw assets of; None: every non-structure category."""
    assets_per_category: int = 12
    """Training assets per category: styles cycle through the generator's variants, each
    with its own size and seed."""
    val_assets_per_category: int = 2
    """Held-out assets per category (later seeds) for the validation loss; 0: none."""
    size_jitter: float = 0.3
    """Each axis of an asset's size is the category's typical size times a log-uniform
    factor in [1/(1+j), 1+j]: varied proportions, still recognisably the category."""
    mirror: bool = True
    """Mirror a training cloud in x with probability 1/2 (left-right mirroring keeps
    +y the front and +z up, so it stays an honest object)."""
    eval_every: int = 250
    """Steps between validation losses (also taken at the first and the last step)."""
    seed: int = 0
    """Seeds the assets, the initial weights, the batches and the masks."""
    device: str = "cpu"
    """Torch device to train on; the data and the random draws stay reproducible."""

    def __post_init__(self) -> None:
        if self.steps < 1 or self.batch_size < 1 or self.assets_per_category < 1:
            raise UserError("pretrain: steps, batch_size and assets_per_category must be >= 1")

    @classmethod
    def tiny(cls) -> PretrainConfig:
        """A seconds-long run for tests: the tiny model on three categories."""
        return cls(
            model=PointMAEConfig.tiny(), steps=20, batch_size=4, warmup_steps=2,
            categories=("chair", "mug", "bed"), assets_per_category=3,
            val_assets_per_category=1, eval_every=10,
        )  # fmt: skip


@dataclass(frozen=True)
class CloudSet:
    """Normalised asset clouds for pre-training."""

    points: np.ndarray
    """(A, N, 3) float32, each normalised by its box (in the unit ball)."""
    categories: tuple[str, ...]
    """(A,) the category of each cloud."""
    half_diagonals: np.ndarray
    """(A,) float32, the box half-diagonal each cloud was divided by (metres)."""


@dataclass(frozen=True)
class PretrainResult:
    """What :func:`pretrain` wrote and measured."""

    encoder_path: Path
    config_path: Path
    train_losses: list[float]
    """Per step, the training Chamfer-L2 of its batch."""
    val_losses: list[tuple[int, float]]
    """(step, mean validation Chamfer-L2) pairs; step 0 is before any update."""
    n_train: int
    n_val: int
    seconds: float


# -- data ------------------------------------------------------------------------------
def pretrain_categories(categories: Sequence[str] | None = None) -> list[str]:
    """``categories`` checked against the generators, or every non-structure category."""
    if categories is None:
        return [c.name for c in CATEGORIES if not is_structure(c.name)]
    gens = generators()
    unknown = [c for c in categories if c not in gens]
    if unknown:
        raise UserError(f"pretrain: no procedural generator for {unknown}")
    return list(categories)


def build_clouds(
    categories: Sequence[str], first: int, count: int, n_points: int, size_jitter: float,
    seed: int,
) -> CloudSet:  # fmt: skip
    """Clouds of assets ``first .. first+count-1`` of each category, normalised.

    Asset j of category c uses style ``j % variants`` and the numpy seed
    ``(seed, index of c, j)``, so a training set (first=0) and a validation set
    (first=count of training) never share an asset, and adding categories leaves
    the others' assets unchanged.
    """
    from pair2scene.assets.typical_sizes import typical_size

    names = [c.name for c in CATEGORIES]
    gens = generators()
    points, cats, halves = [], [], []
    for cat in categories:
        base = np.asarray(typical_size(cat).size, dtype=float)
        for j in range(first, first + count):
            rng = np.random.default_rng([seed, names.index(cat), j])
            factor = np.exp(rng.uniform(-1, 1, 3) * math.log1p(size_jitter))
            asset = generate(cat, base * factor, rng, style=j % gens[cat].variants)
            pts, _ = sample_asset(asset, n_points, rng)
            normed, half = normalise_points(
                torch.from_numpy(pts), torch.from_numpy(np.asarray(asset.size, dtype=float))
            )
            points.append(normed.numpy().astype(np.float32))
            cats.append(cat)
            halves.append(float(half))
    return CloudSet(
        np.stack(points) if points else np.zeros((0, n_points, 3), np.float32),
        tuple(cats),
        np.asarray(halves, dtype=np.float32),
    )


def augment(batch: torch.Tensor, generator: torch.Generator, mirror: bool) -> torch.Tensor:
    """Shuffle each cloud's point order (farthest point sampling starts at point 0, so the
    groups change every time) and, with ``mirror``, flip x of about half the clouds.

    batch : (B, N, 3) -> (B, N, 3).
    """
    b, n, _ = batch.shape
    order = torch.rand(b, n, generator=generator).argsort(dim=1).to(batch.device)  # (B, N)
    out = torch.gather(batch, 1, order.unsqueeze(-1).expand(-1, -1, 3))
    if mirror:
        flip = torch.rand(b, generator=generator) < 0.5
        sign = torch.ones(b, 1, 3)
        sign[flip, 0, 0] = -1.0
        out = out * sign.to(batch.device)
    return out


# -- training --------------------------------------------------------------------------
def learning_rate(step: int, config: PretrainConfig) -> float:
    """Linear warm-up over ``warmup_steps``, then cosine decay to 0 at ``steps``."""
    if step < config.warmup_steps:
        return config.lr * (step + 1) / config.warmup_steps
    span = max(config.steps - config.warmup_steps, 1)
    return config.lr * 0.5 * (1 + math.cos(math.pi * (step - config.warmup_steps) / span))


def _param_groups(model: torch.nn.Module, weight_decay: float) -> list[dict]:
    """Decay matrices only: biases, norm gains and the mask token are not shrunk."""
    decay = [p for p in model.parameters() if p.ndim >= 2]
    rest = [p for p in model.parameters() if p.ndim < 2]
    return [{"params": decay, "weight_decay": weight_decay}, {"params": rest, "weight_decay": 0.0}]


@torch.no_grad()
def evaluate(model: PointMAE, clouds: torch.Tensor, batch_size: int, seed: int) -> float:
    """Mean Chamfer-L2 over ``clouds`` (A, N, 3) with masks drawn from ``seed`` (fixed, so
    the numbers are comparable across steps)."""
    was_training = model.training
    model.eval()
    g = torch.Generator().manual_seed(seed)
    total = 0.0
    for i in range(0, len(clouds), batch_size):
        _, out = model(clouds[i : i + batch_size], g)
        total += float(out.chamfer.sum())
    model.train(was_training)
    return total / max(len(clouds), 1)


def pretrain(config: PretrainConfig, out_dir: str | Path, progress: bool = True) -> PretrainResult:
    """Build the asset clouds, train the masked autoencoder, save the encoder (see the
    module docstring for the files). Same config, same data, masks and initial weights."""
    out_dir = Path(out_dir)
    device = torch.device(config.device)
    start = time.perf_counter()
    cats = pretrain_categories(config.categories)
    n = config.model.n_points
    train = build_clouds(cats, 0, config.assets_per_category, n, config.size_jitter, config.seed)
    val = build_clouds(cats, config.assets_per_category, config.val_assets_per_category, n,
                       config.size_jitter, config.seed)  # fmt: skip
    train_pts = torch.from_numpy(train.points).to(device)
    val_pts = torch.from_numpy(val.points).to(device)

    g = torch.Generator().manual_seed(config.seed)
    model = PointMAE(config.model, g).to(device)
    opt = torch.optim.AdamW(
        _param_groups(model, config.weight_decay), lr=config.lr, betas=(0.9, 0.999)
    )
    train_losses: list[float] = []
    val_losses: list[tuple[int, float]] = []
    val_seed = config.seed + 1
    run = _jsonable(dataclasses.asdict(config))
    first, prior_seconds = 0, 0.0
    state = read_training_state(out_dir, STATE_STEM, STATE_FORMAT)
    if state is not None:
        if state.get("config") != json.loads(json.dumps(run)):
            raise UserError(
                f"{out_dir} holds another pre-training run (different config): choose another "
                "--out or delete it"
            )
        extra = load_training_state(out_dir, STATE_STEM, model, opt)
        g.set_state(extra["generator"])
        first, prior_seconds = int(state["step"]), float(state.get("seconds", 0.0))
        train_losses = [float(v) for v in state["train_losses"]]
        val_losses = [(int(a), float(b)) for a, b in state["val_losses"]]

    def validate(step: int) -> None:
        if len(val_pts):
            val_losses.append((step, evaluate(model, val_pts, config.batch_size, val_seed)))

    def save_state(step: int) -> None:
        doc = {
            "format": STATE_FORMAT, "config": run, "step": step, "train_losses": train_losses,
            "val_losses": [list(v) for v in val_losses],
            "seconds": prior_seconds + time.perf_counter() - start,
        }  # fmt: skip
        save_training_state(out_dir, STATE_STEM, model, opt, doc, {"generator": g.get_state()})

    if first == 0:
        validate(0)
    model.train()
    steps = range(first, config.steps)
    for step in track(steps, "pretrain", enabled=progress, total=len(steps)):
        for group in opt.param_groups:
            group["lr"] = learning_rate(step, config)
        pick = torch.randint(len(train_pts), (config.batch_size,), generator=g)
        batch = augment(train_pts[pick.to(device)], g, config.mirror)
        loss, _ = model(batch, g)
        opt.zero_grad(set_to_none=True)
        loss.backward()
        if config.grad_clip > 0:
            torch.nn.utils.clip_grad_norm_(model.parameters(), config.grad_clip)
        opt.step()
        train_losses.append(loss.item())
        done = step + 1
        if done % config.eval_every == 0 or done == config.steps:
            validate(done)
            if done < config.steps:
                save_state(done)

    seconds = prior_seconds + time.perf_counter() - start
    encoder_path, config_path = save_encoder(
        model.encoder,
        out_dir,
        pretrain={
            "config": _jsonable(
                {k: v for k, v in dataclasses.asdict(config).items() if k != "model"}
            ),
            "categories": cats,
            "n_train": len(train_pts),
            "n_val": len(val_pts),
            "final_train_loss": float(np.mean(train_losses[-FINAL_LOSS_STEPS:])),
            "val_losses": [list(v) for v in val_losses],
            "seconds": round(seconds, 2),
            "torch": torch.__version__,
        },
    )
    for suffix in (".safetensors", ".json"):  # finished: the encoder files are the result
        (out_dir / f"{STATE_STEM}{suffix}").unlink(missing_ok=True)
    return PretrainResult(
        encoder_path, config_path, train_losses, val_losses, len(train_pts), len(val_pts), seconds
    )


# -- files -----------------------------------------------------------------------------
def _safetensors():
    try:
        import safetensors.torch
    except ImportError as exc:  # pragma: no cover - depends on the environment
        raise UserError(
            "saving or loading encoder weights needs safetensors: pip install 'safetensors>=0.4'"
        ) from exc
    return safetensors.torch


def _jsonable(value):
    if isinstance(value, tuple):
        return [_jsonable(v) for v in value]
    if isinstance(value, dict):
        return {k: _jsonable(v) for k, v in value.items()}
    return value


def save_encoder(
    encoder: PointMAEEncoder, out_dir: str | Path, pretrain: dict | None = None
) -> tuple[Path, Path]:
    """Write ``encoder.safetensors`` and ``pointmae.json`` into ``out_dir`` (atomically).

    pretrain : a JSON-able record of how the weights were made (stored as is).
    """
    st = _safetensors()
    out_dir = Path(out_dir)
    state = {k: v.detach().cpu().contiguous() for k, v in encoder.state_dict().items()}
    encoder_path, config_path = out_dir / ENCODER_FILE, out_dir / CONFIG_FILE
    atomic_write_bytes(encoder_path, st.save(state, metadata={"format": FORMAT}))
    doc = {
        "format": FORMAT,
        "version": VERSION,
        "weights": ENCODER_FILE,
        "model": dataclasses.asdict(encoder.config),
        "normalisation": NORMALISATION,
        "pretrain": pretrain,
    }
    atomic_write_text(config_path, json.dumps(doc, indent=1) + "\n")
    return encoder_path, config_path


def load_encoder(folder: str | Path, device: str = "cpu") -> PointMAEEncoder:
    """The encoder saved in ``folder`` by :func:`pretrain` / :func:`save_encoder`, in eval mode."""
    st = _safetensors()
    folder = Path(folder)
    config_path = folder / CONFIG_FILE
    doc = read_json_document(
        config_path, FORMAT, VERSION, "missing (run `pair2scene pretrain --out DIR`)"
    )
    try:
        config = PointMAEConfig(**doc["model"])
    except (TypeError, ValueError, KeyError) as exc:
        raise UserError(f"{config_path}: bad model config ({exc})") from exc
    weights = folder / str(doc.get("weights", ENCODER_FILE))
    try:
        state = st.load_file(str(weights), device=device)
    except FileNotFoundError as exc:
        raise UserError(f"{weights}: missing") from exc
    except Exception as exc:  # safetensors raises its own error types for corrupt files
        raise UserError(f"{weights}: not a readable safetensors file ({exc})") from exc
    encoder = PointMAEEncoder(config)
    try:
        encoder.load_state_dict(state, strict=True)
    except RuntimeError as exc:
        raise UserError(f"{weights}: weights do not fit the config ({exc})") from exc
    return encoder.to(device).eval()


PRESET_SCHEDULES: dict[str, dict] = {
    "tiny": {"steps": 20, "batch_size": 4, "warmup_steps": 2, "assets_per_category": 2,
             "val_assets_per_category": 1, "eval_every": 10},
    "cpu": {"steps": 300, "batch_size": 32, "warmup_steps": 30, "eval_every": 50},
    "paper": {"steps": 2000, "batch_size": 64, "warmup_steps": 100, "eval_every": 250},
}  # fmt: skip
"""Pre-training schedule per preset. ``cpu``: the held-out Chamfer-L2 falls by two
orders of magnitude within the first ~100 steps and flattens by 300 (docs/model.md),
a few minutes on 2 cores."""


def pretrain_config(
    preset_name: str = "cpu",
    steps: int | None = None,
    batch_size: int | None = None,
    seed: int = 0,
) -> PretrainConfig:
    """The pre-training config of a layout preset: its encoder, its schedule."""
    from pair2scene.model.presets import preset

    try:
        encoder = preset(preset_name).encoder
    except ValueError as e:
        raise UserError(str(e)) from None
    schedule = dict(PRESET_SCHEDULES[preset_name])
    if steps is not None:
        schedule["steps"] = steps
    if batch_size is not None:
        schedule["batch_size"] = batch_size
    schedule["warmup_steps"] = min(schedule["warmup_steps"], schedule["steps"] - 1)
    return PretrainConfig(model=encoder, seed=seed, **schedule)

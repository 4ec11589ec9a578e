"""Training the layout predictor on a 3D-Pairs folder: ``pair2scene train``.

``train(TrainConfig(...), data_dir, out_dir)``:

1. loads the tuples and turns them into model inputs (:mod:`pair2scene.model.features`);
2. builds every member's cloud once and, when the encoder is frozen (``full``, ``global``),
   encodes each distinct cloud once (cached in ``out_dir/cache``, reused on resume);
3. trains with AdamW (warm-up, cosine decay, gradient clipping); after every epoch
   measures the validation NLL (the scoring contract: nats per tuple of the stored
   canonical vector), writes the resumable training state and, when the validation NLL
   improved, the checkpoint (``model.safetensors`` + ``config.json``).

An interrupted run continues from its last finished epoch when the same command is run
again; the result is the same as an uninterrupted run (batches and weights are drawn
from per-epoch seeds). Nothing is pickled: the training state is safetensors + JSON too.
"""

from __future__ import annotations

import dataclasses
import hashlib
import json
import math
import resource
import sys
import time
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
import torch

from pair2scene.curation.dataset import PairsDataset, load_pairs
from pair2scene.errors import UserError
from pair2scene.io.atomic import atomic_write_bytes
from pair2scene.model import checkpoint as ckpt
from pair2scene.model.api import CloudInputs, stored_log_prob
from pair2scene.model.features import (
    Features,
    TupleArrays,
    build_clouds,
    dataset_features,
    encode_clouds,
)
from pair2scene.model.layout import LayoutPredictor, LayoutVariant
from pair2scene.model.pair_prior import pair_centre_table, pair_mode_table, pair_turn_table
from pair2scene.model.pointmae import PointMAEEncoder
from pair2scene.model.presets import TrainPreset, preset
from pair2scene.model.pretrain import load_encoder
from pair2scene.progress import track

CACHE_DIR = "cache"


@dataclass(frozen=True)
class TrainConfig:
    """One training run (everything but the data and the output folder)."""

    preset: str = "cpu"
    """Sizes and schedule: ``tiny`` (tests), ``cpu`` (default), ``paper``."""
    variant: str = "full"
    """``full`` (the method), ``class-only``, ``no-pretrain`` or ``global``."""
    encoder: str | None = None
    """Folder of a pre-trained Point-MAE encoder (``pair2scene pretrain``) for ``full`` and
    ``global``; None: the bundled one (``cpu`` preset)."""
    epochs: int | None = None
    """Override the preset's epochs."""
    max_steps: int | None = None
    """Stop after this many optimiser steps in all (the schedule still spans the epochs)."""
    seed: int = 0
    """Seeds the weights and the batch order."""
    device: str = "cpu"
    anchor_frames: bool = True
    """Predict each tuple in its governing anchor's frame (a wall, a functional anchor;
    docs/model.md); False: every tuple in its support's frame, as the paper does."""
    yaw_modes: int = 4
    """Right-angle yaw turns per mixture component (:class:`MixtureConfig.yaw_modes`): 4
    quarter turns, 2 half turns, 1 off (each component one yaw, as the paper)."""
    pair_prior: bool = True
    """Add each category pair's median centre over the train tuples to the network's
    output (:attr:`LayoutConfig.pair_prior`, :mod:`pair2scene.model.pair_prior`); False:
    the network alone places every pair."""
    pair_modes: bool = False
    """Give each category pair one centre per mixture component, its train tuples'
    k-means clusters with their shares (:attr:`LayoutConfig.pair_modes`); False: the
    pair's median alone. Needs ``pair_prior``."""
    pair_turns: bool | None = None
    """Add each category pair's log share of each yaw turn over the train tuples to the
    network's turn logits (:attr:`LayoutConfig.pair_turns`, the bundled model's); False:
    the network alone splits every pair's yaws; None (the default): on wherever there are
    turns to share out (``yaw_modes`` > 1), so ``--yaw-modes 1`` alone trains the paper's
    head. On the bundled data the rooms follow the train tuples' yaws more closely (a pen
    on a dresser), with a lower validation NLL given size (docs/model.md, "The pair
    table's yaw turns")."""

    def resolved_preset(self) -> TrainPreset:
        try:
            p = preset(self.preset, self.variant)
        except ValueError as e:
            raise UserError(str(e)) from None
        if self.epochs is not None:
            if self.epochs < 1:
                raise UserError("--epochs must be >= 1")
            p = dataclasses.replace(p, epochs=self.epochs)
        if p.layout.anchor_frames != self.anchor_frames:
            p = dataclasses.replace(
                p, layout=dataclasses.replace(p.layout, anchor_frames=self.anchor_frames)
            )
        if p.layout.pair_prior != self.pair_prior:
            p = dataclasses.replace(
                p, layout=dataclasses.replace(p.layout, pair_prior=self.pair_prior)
            )
        if p.layout.pair_modes != self.pair_modes:
            p = dataclasses.replace(
                p, layout=dataclasses.replace(p.layout, pair_modes=self.pair_modes)
            )
        if p.layout.mixture.yaw_modes != self.yaw_modes:
            try:
                mix = dataclasses.replace(p.layout.mixture, yaw_modes=self.yaw_modes)
            except ValueError as e:
                raise UserError(f"--yaw-modes: {e}") from None
            p = dataclasses.replace(p, layout=dataclasses.replace(p.layout, mixture=mix))
        turns = self.pair_turns
        if turns is None:
            turns = p.layout.mixture.yaw_modes > 1
        if p.layout.pair_turns != turns:
            p = dataclasses.replace(p, layout=dataclasses.replace(p.layout, pair_turns=turns))
        if self.pair_modes and not self.pair_prior:
            raise UserError("--pair-modes refines the pair table: it needs --pair-prior")
        if self.pair_turns and p.layout.mixture.yaw_modes == 1:
            raise UserError("--pair-turns needs yaw turns to share out: --yaw-modes 2 or 4")
        return p


@dataclass
class TrainResult:
    """What :func:`train` measured."""

    out_dir: Path
    best_epoch: int
    best_val_nll: float
    history: list[dict] = field(default_factory=list)
    """Per epoch: epoch, steps, train_loss, train_nll, val_nll (stored vector), lr, seconds."""
    seconds: float = 0.0
    peak_rss_mb: float = 0.0


def _variant(name: str) -> LayoutVariant:
    try:
        return LayoutVariant(name)
    except ValueError:
        names = ", ".join(v.value for v in LayoutVariant)
        raise UserError(f"unknown variant {name!r}; choose one of {names}") from None


def _digest(*parts: bytes | str) -> str:
    h = hashlib.sha256()
    for p in parts:
        h.update(p.encode() if isinstance(p, str) else p)
        h.update(b"\0")
    return h.hexdigest()[:16]


def data_digest(data: PairsDataset) -> str:
    """A digest of the tuples (their shards' sha256 in manifest order)."""
    return _digest(*(e["sha256"] for e in data.manifest.get("shards", [])))


def peak_rss_mb() -> float:
    """Peak resident memory of this process so far (MB)."""
    rss = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
    return rss / (1024 * 1024) if sys.platform == "darwin" else rss / 1024


def learning_rate(step: int, total: int, p: TrainPreset) -> float:
    """Linear warm-up over ``p.warmup_steps``, cosine decay to ``p.min_lr_ratio * p.lr``."""
    if step < p.warmup_steps:
        return p.lr * (step + 1) / p.warmup_steps
    t = (step - p.warmup_steps) / max(total - p.warmup_steps, 1)
    floor = p.min_lr_ratio * p.lr
    return floor + (p.lr - floor) * 0.5 * (1 + math.cos(math.pi * min(t, 1.0)))


def _param_groups(model: torch.nn.Module, p: TrainPreset) -> list[dict]:
    """Decay matrices and embeddings only; the encoder at ``encoder_lr_scale``."""
    enc = set()
    if model.point_encoder is not None:
        enc = {id(q) for q in model.point_encoder.parameters()}
    groups: dict[tuple[bool, bool], list] = {}
    for q in model.parameters():
        if q.requires_grad:
            groups.setdefault((id(q) in enc, q.ndim >= 2), []).append(q)
    return [
        {
            "params": params,
            "weight_decay": p.weight_decay if decay else 0.0,
            "lr_scale": p.encoder_lr_scale if is_enc else 1.0,
        }
        for (is_enc, decay), params in sorted(groups.items())
    ]


def _split_rows(data: PairsDataset, split: str) -> np.ndarray:
    return np.flatnonzero(data.split == split)


def _subset(arrays: TupleArrays, rows: np.ndarray) -> TupleArrays:
    def take(name: str):
        value = getattr(arrays, name)
        return None if value is None else value[rows]

    return TupleArrays(**{f.name: take(f.name) for f in dataclasses.fields(TupleArrays)})


def _load_frozen_encoder(config: TrainConfig, p: TrainPreset) -> PointMAEEncoder:
    folder = ckpt.DEFAULT_ENCODER_DIR if config.encoder is None else Path(config.encoder)
    if config.encoder is None and not (folder / "pointmae.json").exists():
        raise UserError(
            "no bundled encoder in this installation: pre-train one with "
            "`pair2scene pretrain --out DIR` and pass --encoder DIR"
        )
    encoder = load_encoder(folder)
    if encoder.config != p.encoder:
        raise UserError(
            f"{folder}: the encoder (width {encoder.config.width}, {encoder.config.n_points} "
            f"points) is not the {p.name!r} preset's (width {p.encoder.width}, "
            f"{p.encoder.n_points} points); pre-train one with `pair2scene pretrain "
            f"--preset {p.name} --out DIR` and pass --encoder DIR"
        )
    return encoder


def _cached_tokens(
    cache: Path, key: str, encoder: PointMAEEncoder, clouds: np.ndarray, progress: bool
) -> tuple[torch.Tensor, torch.Tensor]:
    """Encoder output of ``clouds``, read from ``cache`` when an earlier run wrote it."""
    st = ckpt._safetensors()
    path = cache / f"tokens-{key}.safetensors"
    if path.exists():
        try:
            t = st.load_file(str(path))
            if t["tokens"].shape[0] == len(clouds):
                return t["tokens"], t["centers"]
        except Exception:  # a damaged cache file is rebuilt, never trusted
            pass
    tokens, centers = encode_clouds(encoder, clouds, progress=progress)
    atomic_write_bytes(path, st.save({"tokens": tokens.contiguous(), "centers": centers}))
    return tokens, centers


def _cached_clouds(cache: Path, key: str, features: Features, n: int, progress: bool):
    st = ckpt._safetensors()
    path = cache / f"clouds-{key}.safetensors"
    if path.exists():
        try:
            pts = st.load_file(str(path))["points"]
            if pts.shape == (len(features.clouds), n, 3):
                return pts.numpy()
        except Exception:
            pass
    clouds = build_clouds(features.clouds, n, progress=progress)
    atomic_write_bytes(path, st.save({"points": torch.from_numpy(clouds)}))
    return clouds


def train(
    config: TrainConfig, data_dir: str | Path, out_dir: str | Path, progress: bool = True
) -> TrainResult:
    """Train a layout model (see the module docstring); resumes an interrupted run."""
    start = time.perf_counter()
    variant = _variant(config.variant)
    p = config.resolved_preset()
    out = Path(out_dir)
    data = load_pairs(data_dir)
    train_rows, val_rows = _split_rows(data, "train"), _split_rows(data, "val")
    if len(train_rows) == 0:
        raise UserError(f"{data_dir}: no train tuples")
    digest = data_digest(data)

    # -- the state to resume ---------------------------------------------------------
    run_key = {
        "preset": dataclasses.asdict(p) | {"layout": ckpt.layout_config_to_dict(p.layout)},
        "variant": variant.value,
        "seed": config.seed,
        "encoder": config.encoder,
        "data": digest,
    }
    state_doc = _read_state(out)
    if state_doc is not None and state_doc.get("run") != json.loads(json.dumps(run_key)):
        raise UserError(
            f"{out} holds another training run (different data, preset, variant, seed or "
            "encoder): choose another --out or delete it"
        )

    # -- inputs ------------------------------------------------------------------------
    features = dataset_features(data, variant, anchor_frames=p.layout.anchor_frames)
    train_arr, val_arr = _subset(features.arrays, train_rows), _subset(features.arrays, val_rows)
    encoder = None
    inputs = CloudInputs()
    cache = out / CACHE_DIR
    cloud_key = _digest(digest, variant.value, str(p.n_points), "clouds-v1")
    if p.layout.uses_points:
        clouds = _cached_clouds(cache, cloud_key, features, p.n_points, progress)
        if p.layout.trains_encoder:
            g = torch.Generator().manual_seed(config.seed + 1)
            encoder = PointMAEEncoder(p.encoder, g)
            inputs = CloudInputs(points=torch.from_numpy(clouds))
        else:
            encoder = _load_frozen_encoder(config, p)
            enc_digest = _digest(*(v.numpy().tobytes() for v in encoder.state_dict().values()))
            tokens, centers = _cached_tokens(
                cache, _digest(cloud_key, enc_digest), encoder, clouds, progress
            )
            inputs = CloudInputs(tokens=tokens, centers=centers)
            del clouds

    # -- model, optimiser, schedule ------------------------------------------------------
    model = LayoutPredictor(p.layout, encoder, torch.Generator().manual_seed(config.seed))
    if p.layout.uses_pair_prior:  # the train tuples' own centres (resuming reloads it)
        table = pair_centre_table(
            train_arr.categories, train_arr.frames, train_arr.target, p.layout.n_categories
        )
        model.pair_centre.copy_(torch.from_numpy(table))
    if p.layout.uses_pair_modes:  # the train tuples' own clusters (the same)
        modes = pair_mode_table(
            train_arr.categories, train_arr.frames, train_arr.target, p.layout.n_categories,
            p.layout.mixture.num_components,
        )  # fmt: skip
        model.pair_mode.copy_(torch.from_numpy(modes))
    if p.layout.uses_pair_turns:  # the train tuples' own yaw turns (the same)
        turns = pair_turn_table(
            train_arr.categories, train_arr.frames, train_arr.target[:, 6:8],
            p.layout.n_categories, p.layout.mixture.yaw_modes,
        )  # fmt: skip
        model.pair_turn.copy_(torch.from_numpy(turns))
    model = model.to(config.device)
    opt = torch.optim.AdamW(_param_groups(model, p), lr=p.lr, betas=(0.9, 0.95))
    steps_per_epoch = p.steps_per_epoch(len(train_arr))
    total_steps = steps_per_epoch * p.epochs
    if config.max_steps is not None:
        total_steps = min(total_steps, config.max_steps)
    history: list[dict] = []
    first_epoch, step, prior_wall = 0, 0, 0.0
    best = (-1, math.inf)
    if state_doc is not None:
        _load_state(out, model, opt)
        history = state_doc["history"]
        first_epoch, step = state_doc["epoch"] + 1, state_doc["step"]
        prior_wall = float(state_doc.get("wall_seconds", 0.0))
        best_nll = state_doc["best_val_nll"]
        best = (state_doc["best_epoch"], math.inf if best_nll is None else best_nll)

    epochs = range(first_epoch, p.epochs)
    for epoch in epochs:
        if step >= total_steps:
            break
        t0 = time.perf_counter()
        model.train()
        g = torch.Generator().manual_seed(config.seed * 100_003 + epoch)
        order = torch.randperm(len(train_arr), generator=g).numpy()
        losses, nlls = [], []
        batches = range(steps_per_epoch)
        label = f"{variant.value} epoch {epoch + 1}/{p.epochs}"
        for b in track(batches, label, enabled=progress):
            if step >= total_steps:
                break
            rows = order[b * p.batch_size : (b + 1) * p.batch_size]
            lr = learning_rate(step, total_steps, p)
            for group in opt.param_groups:
                group["lr"] = lr * group["lr_scale"]
            batch = inputs.batch(train_arr, rows).to(config.device)
            params, _ = model(batch)
            loss, parts = model.loss(params, batch.target)
            opt.zero_grad(set_to_none=True)
            loss.backward()
            if p.grad_clip > 0:
                torch.nn.utils.clip_grad_norm_(
                    [q for q in model.parameters() if q.requires_grad], p.grad_clip
                )
            opt.step()
            losses.append(loss.item())
            nlls.append(float(parts.nll))
            step += 1
        val_nll = math.nan
        if len(val_arr):
            val_nll = float(-stored_log_prob(model, val_arr, inputs).mean())
        record = {
            "epoch": epoch + 1,
            "steps": step,
            "train_loss": float(np.mean(losses)) if losses else math.nan,
            "train_nll_model_frame": float(np.mean(nlls)) if nlls else math.nan,
            "val_nll": val_nll,
            "lr": learning_rate(max(step - 1, 0), total_steps, p),
            "seconds": round(time.perf_counter() - t0, 2),
        }
        history.append(record)
        improved = not len(val_arr) or (math.isfinite(val_nll) and val_nll < best[1])
        if improved:
            best = (epoch + 1, val_nll)
        seconds = sum(h["seconds"] for h in history)
        meta = {
            "data": {"digest": digest, "train_tuples": len(train_arr), "val_tuples": len(val_arr),
                     "sources": sorted(set(data.source.tolist()))},
            "seed": config.seed,
            "encoder": config.encoder or "bundled",
            "epochs": p.epochs,
            "batch_size": p.batch_size,
            "steps": step,
            "best_epoch": best[0],
            "val_nll": best[1] if math.isfinite(best[1]) else None,
            "history": history,
            "train_seconds": round(seconds, 1),
            "wall_seconds": round(prior_wall + time.perf_counter() - start, 1),
            "peak_rss_mb": round(peak_rss_mb(), 1),
            "parameters": model.num_parameters(),
            "torch": torch.__version__,
        }  # fmt: skip
        if improved:
            ckpt.save_checkpoint(
                out, model, preset=p.name, n_points=p.n_points,
                encoder_config=p.encoder if p.layout.uses_points else None, training=meta,
            )  # fmt: skip
        _save_state(out, model, opt, run_key, epoch, step, history, best, meta["wall_seconds"])
        if progress:
            print(
                f"epoch {epoch + 1}: train loss {record['train_loss']:.3f}, "
                f"val NLL {val_nll:.3f}{' (best)' if improved else ''}",
                file=sys.stderr,
            )
    if not (out / ckpt.CONFIG_FILE).exists():
        raise UserError(f"{out}: no epoch finished with a finite validation NLL")
    return TrainResult(out, best[0], best[1], history, time.perf_counter() - start, peak_rss_mb())


# -- resumable state ---------------------------------------------------------------------

STATE_STEM = "train_state"
STATE_FORMAT = "pair2scene.train-state"


def _read_state(out: Path) -> dict | None:
    return ckpt.read_training_state(out, STATE_STEM, STATE_FORMAT)


def _save_state(out, model, opt, run_key, epoch, step, history, best, wall=0.0) -> None:
    """Weights and AdamW moments as safetensors, the rest as JSON (weights first)."""
    doc = {
        "format": STATE_FORMAT,
        "run": run_key,
        "epoch": epoch,
        "step": step,
        "history": history,
        "best_epoch": best[0],
        "best_val_nll": best[1] if math.isfinite(best[1]) else None,
        "wall_seconds": wall,
    }
    ckpt.save_training_state(out, STATE_STEM, model, opt, doc)


def _load_state(out: Path, model: LayoutPredictor, opt: torch.optim.Optimizer) -> None:
    ckpt.load_training_state(out, STATE_STEM, model, opt)

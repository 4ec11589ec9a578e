"""Layout-model checkpoints on disk: ``model.safetensors`` plus ``config.json``. No pickle.

A checkpoint is a folder::

    config.json          format, version, variant, preset, the layout and encoder
                         configs, the points per cloud, the model frame, how it was trained
    model.safetensors    the predictor's weights, the point encoder's under
                         ``point_encoder.`` (absent for ``class-only``)

Loading never executes anything from the files: JSON is parsed, tensors are read by
safetensors. Every way a checkpoint can be wrong (missing, truncated, another format,
weights that do not fit the config) is a one-line :class:`UserError`.
"""

from __future__ import annotations

import dataclasses
import json
from enum import Enum
from pathlib import Path

import torch

from pair2scene.errors import UserError
from pair2scene.io.atomic import atomic_write_bytes, atomic_write_text
from pair2scene.io.jsondoc import read_json_document
from pair2scene.model.features import MIN_ANCHOR_HALF_M
from pair2scene.model.layout import LayoutConfig, LayoutPredictor, LayoutVariant
from pair2scene.model.mixture import EntropyRegulariser, MixtureConfig
from pair2scene.model.pointmae import PointMAEConfig, PointMAEEncoder

FORMAT = "pair2scene.layout"
VERSION = 1
CONFIG_FILE = "config.json"
WEIGHTS_FILE = "model.safetensors"
DEFAULT_DIR = Path(__file__).parent / "default"
"""The bundled default model (``cpu`` preset, ``full``), shipped inside the package."""
DEFAULT_ENCODER_DIR = DEFAULT_DIR / "encoder"
"""The bundled pre-trained Point-MAE encoder (``cpu`` preset) that ``full`` starts from."""


def _safetensors():
    try:
        import safetensors.torch
    except ImportError as exc:  # pragma: no cover - depends on the environment
        raise UserError("checkpoints need safetensors: pip install 'safetensors>=0.4'") from exc
    return safetensors.torch


def _plain(value):
    """Dataclass / enum trees -> JSON types."""
    if isinstance(value, Enum):
        return value.value
    if isinstance(value, dict):
        return {k: _plain(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [_plain(v) for v in value]
    return value


def layout_config_to_dict(config: LayoutConfig) -> dict:
    return _plain(dataclasses.asdict(config))


def layout_config_from_dict(doc: dict) -> LayoutConfig:
    """Inverse of :func:`layout_config_to_dict`; TypeError/ValueError/KeyError on bad input."""
    doc = dict(doc)
    doc.setdefault("anchor_frames", False)  # written before issue 18: the support's frame
    mix = dict(doc.pop("mixture"))
    mix.setdefault("yaw_modes", 1)  # written before the right-angle yaw modes
    mix["entropy_regulariser"] = EntropyRegulariser(mix["entropy_regulariser"])
    return LayoutConfig(
        **{**doc, "mixture": MixtureConfig(**mix), "variant": LayoutVariant(doc["variant"])}
    )


@dataclasses.dataclass
class Checkpoint:
    """A loaded checkpoint: the predictor (encoder inside) and what config.json says."""

    predictor: LayoutPredictor
    config: LayoutConfig
    encoder_config: PointMAEConfig | None
    n_points: int
    preset: str
    min_anchor_half_m: float
    meta: dict
    """The ``training`` record of config.json (metrics, data, timings), as stored."""
    path: Path | None


def save_checkpoint(
    folder: str | Path,
    predictor: LayoutPredictor,
    *,
    preset: str,
    n_points: int,
    encoder_config: PointMAEConfig | None,
    training: dict | None = None,
) -> Path:
    """Write ``folder/model.safetensors`` and ``folder/config.json`` (each atomically,
    weights first, so a reader never finds a config naming weights that are not there)."""
    st = _safetensors()
    folder = Path(folder)
    state = {k: v.detach().cpu().contiguous() for k, v in predictor.state_dict().items()}
    atomic_write_bytes(folder / WEIGHTS_FILE, st.save(state, metadata={"format": FORMAT}))
    doc = {
        "format": FORMAT,
        "version": VERSION,
        "variant": predictor.config.variant.value,
        "preset": preset,
        "weights": WEIGHTS_FILE,
        "layout": layout_config_to_dict(predictor.config),
        "encoder": None if encoder_config is None else dataclasses.asdict(encoder_config),
        "n_points": n_points,
        "min_anchor_half_m": MIN_ANCHOR_HALF_M,
        "training": training or {},
    }
    atomic_write_text(folder / CONFIG_FILE, json.dumps(doc, indent=1) + "\n")
    return folder


def read_config(folder: str | Path) -> dict:
    """config.json of a checkpoint folder, checked for format and version."""
    if Path(folder).is_file():
        raise UserError(f"{folder}: a checkpoint is a folder holding {CONFIG_FILE}")
    return read_json_document(
        Path(folder) / CONFIG_FILE, FORMAT, VERSION, "missing (not a layout-model checkpoint)"
    )


def load_checkpoint(folder: str | Path | None = None, device: str = "cpu") -> Checkpoint:
    """The checkpoint in ``folder`` (None: the bundled default), in eval mode."""
    st = _safetensors()
    folder = DEFAULT_DIR if folder is None else Path(folder)
    if folder == DEFAULT_DIR and not (folder / CONFIG_FILE).exists():
        raise UserError("no bundled default model in this installation")
    doc = read_config(folder)
    where = folder / CONFIG_FILE
    try:
        config = layout_config_from_dict(doc["layout"])
        enc_doc = doc.get("encoder")
        encoder_config = None if enc_doc is None else PointMAEConfig(**enc_doc)
        n_points = int(doc["n_points"])
        preset = str(doc.get("preset", ""))
        min_half = float(doc.get("min_anchor_half_m", MIN_ANCHOR_HALF_M))
    except (TypeError, ValueError, KeyError) as e:
        raise UserError(f"{where}: bad model config ({type(e).__name__}: {e})") from None
    if config.uses_points and encoder_config is None:
        raise UserError(f"{where}: variant {config.variant.value!r} needs an encoder config")
    if min_half != MIN_ANCHOR_HALF_M:
        raise UserError(
            f"{where}: trained with min_anchor_half_m {min_half}, this version uses "
            f"{MIN_ANCHOR_HALF_M}"
        )
    weights = folder / str(doc.get("weights", WEIGHTS_FILE))
    try:
        state = st.load_file(str(weights), device="cpu")
    except FileNotFoundError:
        raise UserError(f"{weights}: missing") from None
    except Exception as e:  # safetensors raises its own types for truncated/corrupt files
        raise UserError(f"{weights}: not a readable safetensors file ({e})") from None
    encoder = PointMAEEncoder(encoder_config) if config.uses_points else None
    predictor = LayoutPredictor(config, encoder)
    try:
        predictor.load_state_dict(state, strict=True)
    except RuntimeError as e:
        first = str(e).strip().splitlines()[0:2]
        raise UserError(f"{weights}: weights do not fit the config ({' '.join(first)})") from None
    bad = [k for k, v in state.items() if v.is_floating_point() and not torch.isfinite(v).all()]
    if bad:
        raise UserError(f"{weights}: non-finite weights in {bad[0]}")
    predictor = predictor.to(device).eval()
    return Checkpoint(
        predictor=predictor,
        config=config,
        encoder_config=encoder_config,
        n_points=n_points,
        preset=preset,
        min_anchor_half_m=min_half,
        meta=doc.get("training") or {},
        path=folder,
    )


# -- resumable training state --------------------------------------------------------------


def save_training_state(
    folder: Path, stem: str, model: torch.nn.Module, opt: torch.optim.Optimizer, doc: dict,
    extra: dict[str, torch.Tensor] | None = None,
) -> None:  # fmt: skip
    """``folder/<stem>.safetensors`` (weights, AdamW moments, ``extra`` tensors such as a
    generator's state) and ``folder/<stem>.json`` (``doc``), weights first, both atomic."""
    st = _safetensors()
    tensors = {f"model.{k}": v.detach().cpu().contiguous() for k, v in model.state_dict().items()}
    names = {id(q): n for n, q in model.named_parameters()}
    for group in opt.param_groups:
        for q in group["params"]:
            for k in ("exp_avg", "exp_avg_sq", "step"):
                if k in opt.state.get(q, {}):
                    tensors[f"opt.{names[id(q)]}.{k}"] = torch.as_tensor(opt.state[q][k]).cpu()
    for k, v in (extra or {}).items():
        tensors[f"extra.{k}"] = v.detach().cpu().contiguous()
    atomic_write_bytes(folder / f"{stem}.safetensors", st.save(tensors))
    atomic_write_text(folder / f"{stem}.json", json.dumps(doc, indent=1) + "\n")


def read_training_state(folder: Path, stem: str, fmt: str) -> dict | None:
    """The JSON half of a saved state (None when there is none); a damaged one is a
    UserError telling to delete the folder."""
    path = folder / f"{stem}.json"
    if not path.exists():
        return None
    try:
        doc = json.loads(path.read_text(encoding="utf-8"))
        if not isinstance(doc, dict) or doc.get("format") != fmt:
            raise ValueError(f"not a {fmt} file")
    except (OSError, ValueError) as e:
        msg = f"{path}: unreadable training state ({e}); delete {folder} to restart"
        raise UserError(msg) from None
    return doc


def load_training_state(
    folder: Path, stem: str, model: torch.nn.Module, opt: torch.optim.Optimizer
) -> dict[str, torch.Tensor]:
    """Load weights and AdamW moments saved by :func:`save_training_state` into ``model``
    and ``opt``; returns the ``extra`` tensors. Damaged or unfitting: one-line UserError."""
    st = _safetensors()
    path = folder / f"{stem}.safetensors"
    try:
        tensors = st.load_file(str(path))
    except Exception as e:  # safetensors raises its own types for damaged files
        msg = f"{path}: unreadable training state ({e}); delete {folder} to restart"
        raise UserError(msg) from None
    try:
        model.load_state_dict({k[6:]: v for k, v in tensors.items() if k.startswith("model.")})
        by_name = dict(model.named_parameters())
        for key, value in tensors.items():
            if key.startswith("opt."):
                name, what = key[4:].rsplit(".", 1)
                opt.state[by_name[name]][what] = value.float() if what == "step" else value.clone()
    except (RuntimeError, KeyError) as e:
        first = str(e).strip().splitlines()[0]
        msg = f"{path}: the saved state does not fit this model ({first}); delete {folder}"
        raise UserError(msg + " to restart") from None
    return {k[6:]: v for k, v in tensors.items() if k.startswith("extra.")}

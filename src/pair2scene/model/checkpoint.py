"""Layout-model checkpoints on disk: ``model.safetensors`` plus ``config.json``. No pickle.

A checkpoint is a folder::

    config.json          format, version, variant, preset, the layout and encoder
                         configs, the points per cloud, the model frame, how it was trained
    model.safetensors    the predictor's weights, the point encoder's under
                         ``point_encoder.`` (absent for ``class-only``)

Loading never executes anything from the files: JSON is parsed, tensors are read by
safetensors. Every way a checkpoint can be wrong (missing, truncated, another format,
a config out of range, weights that do not fit the config) is a one-line
:class:`UserError` naming the file and, for config.json, the field
(``<folder>/config.json: bad model config: layout.depth: must be at most 64, got 100000
(over the limit)``).

What :func:`load_checkpoint` checks, in this order (nothing is allocated before the
weights are known to fit a model of bounded size)
----------------------------------------------------------------------------------

1. config.json: a regular file of at most 64 MiB, JSON without NaN / Infinity, ``format``
   ``pair2scene.layout``, ``version`` the integer 1 (:func:`read_config`).
2. Every field of the config (:func:`check_model_config`), against the table below:
   integers must be JSON integers (``4.0`` and ``true`` are not), numbers finite, flags
   ``true`` / ``false``, names one of the listed choices. Fields of ``layout``,
   ``layout.mixture`` and ``encoder`` are all required (except the three that older
   checkpoints lack: ``layout.anchor_frames`` and ``layout.pair_prior``, read as false,
   and ``layout.mixture.yaw_modes``, read as 1) and an unknown field there is refused: it
   would change the network this version builds, so the weights would not mean what they
   meant. Unknown top-level keys are ignored (they describe, they do not build);
   ``training`` is free-form but must be an object.
3. The parameter count of the network the config describes, counted from the tensor
   shapes it implies (:func:`expected_shapes`, no memory and no torch): at most
   :data:`MAX_PARAMETERS` (200 M; the ``paper`` preset has ~55 M, ``cpu`` ~2.2 M), else
   refused naming the fields of the largest part.
4. ``weights``: a plain file name inside the folder (no path), a regular file (not a
   pipe or a device), a safetensors header whose tensor names, shapes and floating-point
   dtypes are exactly those (missing, extra or mis-shaped tensors are refused
   before any tensor is read).
5. The tensors: finite, and no weight beyond :data:`MAX_ABS_WEIGHT` (1e4; a trained
   model's are O(1), the bundled one's largest is ~2) in magnitude
   (:func:`read_checkpoint`, numpy). :func:`load_checkpoint` then loads them into a
   skeleton built on torch's meta device (``assign=True``: no initialisation); generation
   uses them without torch (:class:`~pair2scene.model.api.LayoutModel`'s numpy twins).

Sampling a loaded model guards the rest (:func:`pair2scene.model.mixture.check_params`):
weights that pass 5 but still give NaN or absurd distributions are a one-line
:class:`~pair2scene.model.mixture.InvalidDistribution` naming the folder.

Ranges of config.json (every bound inclusive unless written ``<``; presets for scale:
``cpu`` / ``paper``)::

    layout.width, layout.point_dim          1 .. 4096      (128 / 512, 128 / 384)
    layout.depth                            1 .. 64        (4 / 7)
    layout.heads                            1 .. 64, divides width
    layout.queries                          1 .. 64        (4 / 4)
    layout.mlp_ratio                        1 .. 16        (4)
    layout.n_categories                     len(CATEGORY_VOCAB) (123 today) .. 4096
    layout.dropout                          0 .. < 1
    layout.variant                          full | class-only | no-pretrain | global
    layout.finetune_encoder, .anchor_frames, .pair_prior   true | false
    layout.mixture.num_components           1 .. 256       (8 / 4)
    layout.mixture.dim                      12
    layout.mixture.min_log_scale            -20 .. 20, < max_log_scale   (-7)
    layout.mixture.max_log_scale            -20 .. 20      (5)
    layout.mixture.entropy_weight           0 .. 100       (0.01)
    layout.mixture.entropy_regulariser      bonus | penalty
    layout.mixture.rotation_base            true | false
    layout.mixture.yaw_modes                1 | 2 | 4
    encoder.n_points                        1 .. 16384     (2048 / 8192)
    encoder.n_groups                        1 .. 512, <= n_points         (32 / 256)
    encoder.group_size                      1 .. 256, <= n_points         (64 / 32)
    encoder.width, .pointnet_hidden, .pos_hidden   1 .. 4096
    encoder.depth                           1 .. 64        (4 / 12)
    encoder.decoder_depth                   0 .. 64
    encoder.heads, .decoder_heads           1 .. 64, divide width
    encoder.mlp_ratio                       > 0 .. 16, width * mlp_ratio >= 1
    encoder.mask_ratio, .dropout            0 .. < 1
    n_groups * group_size * 4 * pointnet_hidden   <= 2**26 (the mini-PointNet's
                                            activations per cloud; paper: 2**23)
    encoder.width                           = layout.point_dim (variants with points)
    encoder                                 an object; null only for class-only
    n_points                                max(n_groups, group_size) .. 16384
    variant                                 = layout.variant
    preset                                  a string of at most 64 characters
    weights                                 a file name (default model.safetensors)
    min_anchor_half_m                       0.05 (this version's)
    training                                an object (or null)
"""

from __future__ import annotations

import contextlib
import dataclasses
import json
import math
import os
import stat
from collections.abc import Iterator, Mapping
from enum import Enum
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from pair2scene.curation.dataset import CATEGORY_VOCAB
from pair2scene.curation.frames import FRAME_NAMES
from pair2scene.errors import UserError
from pair2scene.io.atomic import atomic_write_bytes, atomic_write_text
from pair2scene.io.jsondoc import read_json_document
from pair2scene.model.config import (
    BOX_DIM,
    MIN_ANCHOR_HALF_M,
    N_MEMBERS,
    EntropyRegulariser,
    LayoutConfig,
    LayoutVariant,
    MixtureConfig,
    PointMAEConfig,
)
from pair2scene.model.pair_prior import mode_table_shape, table_shape, turn_table_shape

if TYPE_CHECKING:  # torch is imported where a network is built, not to read a checkpoint
    import torch

    from pair2scene.model.layout import LayoutPredictor

FORMAT = "pair2scene.layout"
VERSION = 1
CONFIG_FILE = "config.json"
WEIGHTS_FILE = "model.safetensors"
DEFAULT_DIR = Path(__file__).parent / "default"
"""The bundled default model (``cpu`` preset, ``full``), shipped inside the package."""
DEFAULT_ENCODER_DIR = DEFAULT_DIR / "encoder"
"""The bundled pre-trained Point-MAE encoder (``cpu`` preset) that ``full`` starts from."""

# -- limits (the module docstring's table) --------------------------------------------------
MAX_PARAMETERS = 200_000_000
"""Parameters (predictor and encoder) a checkpoint may describe: 200 M, 800 MB of float32,
nearly four times the ``paper`` preset's ~55 M. Counted before anything is allocated."""
MAX_WIDTH = 4096
"""Largest token width or hidden size (``paper``: 512)."""
MAX_DEPTH = 64
"""Most transformer blocks of the predictor or the encoder (``paper``: 7 and 12)."""
MAX_HEADS = 64
"""Most attention heads."""
MAX_QUERIES = 64
"""Most query tokens per member (the paper: 4)."""
MAX_MLP_RATIO = 16
"""Largest hidden width of a block's MLP, in multiples of the width (4 everywhere)."""
MAX_CATEGORIES = 4096
"""Most rows of the category embedding (at least the vocabulary's, 123 today)."""
MAX_COMPONENTS = 256
"""Most mixture components K (``cpu``: 8; the paper: 4)."""
MAX_POINTS = 16384
"""Most points per cloud (the paper: 8192)."""
MAX_GROUPS = 512
"""Most point groups (tokens) per cloud (``paper``: 256)."""
MAX_GROUP_SIZE = 256
"""Most points per group (``cpu``: 64)."""
MAX_GROUP_ACTIVATIONS = 2**26
"""Bound on ``n_groups * group_size * 4 * pointnet_hidden``, the widest activation of the
mini-PointNet per cloud (``paper``: 2**23, 32 MB; at the bound 256 MB per cloud)."""
LOG_SCALE_RANGE = (-20.0, 20.0)
"""Bounds of the mixture's log-scale limits (defaults -7 and 5): exp(-20) ~ 2e-9 and
exp(20) ~ 5e8 anchor half-sizes keep every draw and density finite in float32."""
MAX_ENTROPY_WEIGHT = 100.0
"""Largest weight of the entropy term (a training setting; 0.01 by default)."""
MAX_ABS_WEIGHT = 1e4
"""Largest weight magnitude a checkpoint may hold: a trained model's are O(1) (the
bundled one's largest is ~2); beyond this the forward pass overflows to NaN or gives
distributions nothing can be drawn from."""
MAX_PRESET_CHARS = 64
"""Longest preset name (a label, shown in notes)."""
FLOAT_DTYPES = ("F16", "BF16", "F32", "F64")
"""Tensor dtypes a checkpoint may store (safetensors' names); loaded as float32."""


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
    """Inverse of :func:`layout_config_to_dict`; TypeError/ValueError/KeyError on bad input.
    Checks no ranges: :func:`check_model_config` does, for a config read from a file."""
    doc = dict(doc)
    doc.setdefault("anchor_frames", False)  # written before issue 18: the support's frame
    doc.setdefault("pair_prior", False)  # written before the pair table
    doc.setdefault("pair_turns", False)  # written before the pair table's yaw turns
    doc.setdefault("pair_modes", False)  # written before the pair table's clusters
    mix = dict(doc.pop("mixture"))
    mix.setdefault("yaw_modes", 1)  # written before the right-angle yaw modes
    mix["entropy_regulariser"] = EntropyRegulariser(mix["entropy_regulariser"])
    return LayoutConfig(
        **{**doc, "mixture": MixtureConfig(**mix), "variant": LayoutVariant(doc["variant"])}
    )


# -- checking a config ------------------------------------------------------------------------


@dataclasses.dataclass(frozen=True)
class FieldRange:
    """What one config field may hold."""

    kind: type
    """int, float, bool or str (JSON integer, number, true/false, string)."""
    low: float | None = None
    high: float | None = None
    below_high: bool = False
    """``high`` itself excluded: ``[low, high)``."""
    above_low: bool = False
    """``low`` itself excluded: ``(low, high]``."""
    choices: tuple = ()


def _int(low: int, high: int) -> FieldRange:
    return FieldRange(int, low, high)


_UNIT = FieldRange(float, 0.0, 1.0, below_high=True)
_FLAG = FieldRange(bool)

LAYOUT_FIELDS: dict[str, FieldRange] = {
    "width": _int(1, MAX_WIDTH),
    "depth": _int(1, MAX_DEPTH),
    "heads": _int(1, MAX_HEADS),
    "queries": _int(1, MAX_QUERIES),
    "mlp_ratio": _int(1, MAX_MLP_RATIO),
    "point_dim": _int(1, MAX_WIDTH),
    "n_categories": _int(len(CATEGORY_VOCAB), MAX_CATEGORIES),
    "dropout": _UNIT,
    "variant": FieldRange(str, choices=tuple(v.value for v in LayoutVariant)),
    "finetune_encoder": _FLAG,
    "anchor_frames": _FLAG,
    "pair_prior": _FLAG,
    "pair_turns": _FLAG,
    "pair_modes": _FLAG,
}
"""``layout`` (besides ``mixture``): :class:`~pair2scene.model.layout.LayoutConfig`."""
MIXTURE_FIELDS: dict[str, FieldRange] = {
    "num_components": _int(1, MAX_COMPONENTS),
    "dim": _int(BOX_DIM, BOX_DIM),
    "min_log_scale": FieldRange(float, *LOG_SCALE_RANGE),
    "max_log_scale": FieldRange(float, *LOG_SCALE_RANGE),
    "entropy_weight": FieldRange(float, 0.0, MAX_ENTROPY_WEIGHT),
    "entropy_regulariser": FieldRange(str, choices=tuple(r.value for r in EntropyRegulariser)),
    "rotation_base": _FLAG,
    "yaw_modes": FieldRange(int, choices=(1, 2, 4)),
}
"""``layout.mixture``: :class:`~pair2scene.model.mixture.MixtureConfig`."""
ENCODER_FIELDS: dict[str, FieldRange] = {
    "n_points": _int(1, MAX_POINTS),
    "n_groups": _int(1, MAX_GROUPS),
    "group_size": _int(1, MAX_GROUP_SIZE),
    "width": _int(1, MAX_WIDTH),
    "depth": _int(1, MAX_DEPTH),
    "heads": _int(1, MAX_HEADS),
    "mlp_ratio": FieldRange(float, 0.0, MAX_MLP_RATIO, above_low=True),
    "pointnet_hidden": _int(1, MAX_WIDTH),
    "pos_hidden": _int(1, MAX_WIDTH),
    "mask_ratio": _UNIT,
    "decoder_depth": _int(0, MAX_DEPTH),
    "decoder_heads": _int(1, MAX_HEADS),
    "dropout": _UNIT,
}
"""``encoder``: :class:`~pair2scene.model.pointmae.PointMAEConfig`."""
LEGACY_DEFAULTS: dict[str, Any] = {
    "layout.anchor_frames": False,
    "layout.mixture.yaw_modes": 1,
    "layout.pair_prior": False,
    "layout.pair_turns": False,
    "layout.pair_modes": False,
}
"""Fields older checkpoints lack, and what they mean there."""


def _shown(value: Any) -> str:
    """A value for a one-line message: its JSON-ish repr, at most 40 characters."""
    text = repr(value)
    if type(value) is bool or value is None:
        text = json.dumps(value)
    text = text.replace("\n", " ")
    return text if len(text) <= 40 else text[:37] + "..."


def _key(name: str) -> str:
    """A JSON key for a message: printable, at most 40 characters."""
    text = name if name.isprintable() else repr(name)
    return text if len(text) <= 40 else text[:37] + "..."


def _json_kind(value: Any) -> str:
    names = {dict: "an object", list: "a list", str: "a string", bool: "true/false"}
    if value is None:
        return "null"
    return names.get(type(value), "a number")


def check_field(value: Any, spec: FieldRange, where: str | Path, name: str) -> Any:
    """``value`` if it is what ``spec`` allows (a float field's as a float), else a
    :class:`UserError` ``<where>: <name>: <problem>``."""

    def fail(problem: str) -> UserError:
        return UserError(f"{where}: {name}: {problem}")

    t = type(value)
    if spec.kind is bool and t is not bool:
        raise fail(f"must be true or false, got {_shown(value)}")
    if spec.kind is int and t is not int:
        raise fail(f"must be an integer, got {_shown(value)}")
    if spec.kind is float:
        if t is not int and t is not float:
            raise fail(f"must be a number, got {_shown(value)}")
        if not math.isfinite(value):
            raise fail(f"must be finite, got {_shown(value)}")
        value = float(value)
    if spec.kind is str and t is not str:
        raise fail(f"must be a string, got {_shown(value)}")
    if spec.choices and value not in spec.choices:
        raise fail(f"must be one of {', '.join(map(str, spec.choices))}; got {_shown(value)}")
    if spec.low is not None and (value <= spec.low if spec.above_low else value < spec.low):
        bound = "above" if spec.above_low else "at least"
        raise fail(f"must be {bound} {spec.low:g}, got {_shown(value)}")
    if spec.high is not None and (value >= spec.high if spec.below_high else value > spec.high):
        bound = "below" if spec.below_high else "at most"
        raise fail(f"must be {bound} {spec.high:g}, got {_shown(value)} (over the limit)")
    return value


def check_section(
    doc: Any, fields: dict[str, FieldRange], where: str | Path, prefix: str
) -> dict[str, Any]:
    """The fields of the JSON object ``doc`` (named ``prefix`` in messages), each checked
    by :func:`check_field`; every field required except :data:`LEGACY_DEFAULTS`, unknown
    fields refused."""
    if type(doc) is not dict:
        raise UserError(f"{where}: {prefix}: must be an object, got {_json_kind(doc)}")
    unknown = [k for k in doc if k not in fields]
    if unknown:
        raise UserError(
            f"{where}: {prefix}.{_key(unknown[0])}: unknown field (this "
            "version would build another network than the weights were trained in)"
        )
    out: dict[str, Any] = {}
    for name, spec in fields.items():
        full = f"{prefix}.{name}"
        if name not in doc:
            if full not in LEGACY_DEFAULTS:
                raise UserError(f"{where}: {full}: missing")
            out[name] = LEGACY_DEFAULTS[full]
            continue
        out[name] = check_field(doc[name], spec, where, full)
    return out


def check_encoder_config(doc: Any, where: str | Path, prefix: str = "encoder") -> PointMAEConfig:
    """A Point-MAE config from JSON, every field checked against :data:`ENCODER_FIELDS`
    and the sizes against each other (one-line :class:`UserError` naming ``where`` and
    the field); for any reader of an encoder config (checkpoints, pre-trained encoders)."""
    enc = check_section(doc, ENCODER_FIELDS, where, prefix)

    def fail(field: str, problem: str) -> UserError:
        return UserError(f"{where}: {prefix}.{field}: {problem}")

    for heads in ("heads", "decoder_heads"):
        if enc["width"] % enc[heads]:
            raise fail(heads, f"{enc[heads]} does not divide width {enc['width']}")
    for size in ("n_groups", "group_size"):
        if enc[size] > enc["n_points"]:
            raise fail(size, f"{enc[size]} is more than n_points {enc['n_points']}")
    if int(enc["width"] * enc["mlp_ratio"]) < 1:
        raise fail("mlp_ratio", f"{enc['mlp_ratio']} gives blocks an MLP of no width")
    activations = enc["n_groups"] * enc["group_size"] * 4 * enc["pointnet_hidden"]
    if activations > MAX_GROUP_ACTIVATIONS:
        raise fail(
            "pointnet_hidden",
            f"n_groups x group_size x 4 x pointnet_hidden = {activations:,} activations per "
            f"cloud, over the limit of {MAX_GROUP_ACTIVATIONS:,}",
        )
    try:
        return PointMAEConfig(**enc)
    except (TypeError, ValueError) as e:  # (__post_init__'s checks; covered above)
        raise UserError(f"{where}: {prefix}: {e}") from None


@dataclasses.dataclass(frozen=True)
class ModelConfig:
    """What config.json says, checked (:func:`check_model_config`)."""

    layout: LayoutConfig
    encoder: PointMAEConfig | None
    n_points: int
    preset: str
    min_anchor_half_m: float
    weights: str
    training: dict


def check_model_config(doc: dict, where: str | Path) -> ModelConfig:
    """The checkpoint config ``doc`` (config.json, format and version already checked),
    every field checked against the module docstring's table before anything is built;
    a one-line :class:`UserError` ``<where>: bad model config: <field>: <problem>``
    otherwise."""
    where = f"{where}: bad model config"

    def fail(field: str, problem: str) -> UserError:
        return UserError(f"{where}: {field}: {problem}")

    if type(doc.get("version")) is not int:
        raise fail("version", f"must be the integer {VERSION}, got {_shown(doc.get('version'))}")
    if "layout" not in doc:
        raise fail("layout", "missing")
    layout_doc = doc["layout"]
    layout_fields = {**LAYOUT_FIELDS, "mixture": FieldRange(dict)}  # (checked next)
    layout = check_section(layout_doc, layout_fields, where, "layout")
    mix = check_section(layout_doc.get("mixture"), MIXTURE_FIELDS, where, "layout.mixture")
    if layout["width"] % layout["heads"]:
        raise fail("layout.heads", f"{layout['heads']} does not divide width {layout['width']}")
    if mix["min_log_scale"] >= mix["max_log_scale"]:
        raise fail(
            "layout.mixture.min_log_scale",
            f"{mix['min_log_scale']:g} is not below max_log_scale {mix['max_log_scale']:g}",
        )
    try:
        config = layout_config_from_dict({**layout, "mixture": mix})
    except (TypeError, ValueError, KeyError) as e:  # (__post_init__'s checks; covered above)
        raise UserError(f"{where} ({type(e).__name__}: {e})") from None

    variant = doc.get("variant", config.variant.value)
    if variant != config.variant.value:
        raise fail("variant", f"{_shown(variant)} is not layout.variant {config.variant.value!r}")
    enc_doc = doc.get("encoder")
    encoder = None if enc_doc is None else check_encoder_config(enc_doc, where)
    if config.uses_points:
        if encoder is None:
            raise fail("encoder", f"variant {config.variant.value!r} needs an encoder config")
        if encoder.width != config.point_dim:
            raise fail(
                "layout.point_dim",
                f"{config.point_dim} is not the encoder's width {encoder.width}",
            )
    if "n_points" not in doc:
        raise fail("n_points", "missing")
    n_points = check_field(doc["n_points"], _int(1, MAX_POINTS), where, "n_points")
    if encoder is not None and n_points < max(encoder.n_groups, encoder.group_size):
        raise fail(
            "n_points",
            f"{n_points} points cannot make the encoder's {encoder.n_groups} groups of "
            f"{encoder.group_size}",
        )
    preset = check_field(doc.get("preset", ""), FieldRange(str), where, "preset")
    if len(preset) > MAX_PRESET_CHARS:
        raise fail("preset", f"longer than {MAX_PRESET_CHARS} characters")
    min_half = check_field(
        doc.get("min_anchor_half_m", MIN_ANCHOR_HALF_M), FieldRange(float), where,
        "min_anchor_half_m",
    )  # fmt: skip
    if min_half != MIN_ANCHOR_HALF_M:
        raise fail(
            "min_anchor_half_m",
            f"trained with {min_half}, this version uses {MIN_ANCHOR_HALF_M}",
        )
    weights = check_field(doc.get("weights", WEIGHTS_FILE), FieldRange(str), where, "weights")
    if not weights or weights in (".", "..") or any(c in weights for c in "/\\\x00:"):
        raise fail("weights", f"{_shown(weights)} is not a file name inside the folder")
    training = doc.get("training")
    if training is not None and type(training) is not dict:
        raise fail("training", f"must be an object, got {_json_kind(training)}")
    return ModelConfig(config, encoder, n_points, preset, min_half, weights, training or {})


# -- the network, before its weights ----------------------------------------------------------

PART_FIELDS: dict[str, tuple[str, ...]] = {
    "blocks": ("layout.width", "layout.depth", "layout.mlp_ratio"),
    "head": ("layout.queries", "layout.width", "layout.mixture.num_components"),
    "category": ("layout.n_categories", "layout.width"),
    "point_encoder": ("encoder.width", "encoder.depth", "encoder.mlp_ratio",
                      "encoder.pointnet_hidden"),
}  # fmt: skip
"""Which config fields size each part of the predictor (for the parameter-limit message;
any other part: ``layout.width``)."""


@contextlib.contextmanager
def _no_init() -> Iterator[None]:
    """``torch.nn.init``'s in-place initialisers as no-ops while a skeleton is built: its
    weights are replaced by the checkpoint's, and initialising them anyway (the category
    embedding's ``init.normal_`` alone) costs ~1.1 s of torch's own set-up (issue 22)."""
    import torch

    names = [n for n in vars(torch.nn.init) if n.endswith("_") and not n.startswith("_")]
    saved = {n: getattr(torch.nn.init, n) for n in names}
    for n in names:
        setattr(torch.nn.init, n, lambda tensor, *args, **kwargs: tensor)
    try:
        yield
    finally:
        for n, f in saved.items():
            setattr(torch.nn.init, n, f)


def skeleton(config: LayoutConfig, encoder: PointMAEConfig | None) -> LayoutPredictor:
    """The network ``config`` describes, on torch's meta device: shapes without memory,
    built without initialising what the weights replace (:func:`_no_init`)."""
    import torch

    from pair2scene.model.layout import LayoutPredictor
    from pair2scene.model.pointmae import PointMAEEncoder

    with _no_init():
        with torch.device("meta"):
            point_encoder = PointMAEEncoder(encoder) if config.uses_points else None
        return LayoutPredictor(config, point_encoder, materialise=False)


def _linear(name: str, d_in: int, d_out: int) -> dict[str, tuple[int, ...]]:
    return {f"{name}.weight": (d_out, d_in), f"{name}.bias": (d_out,)}


def _norm(name: str, width: int) -> dict[str, tuple[int, ...]]:
    return {f"{name}.weight": (width,), f"{name}.bias": (width,)}


def _mlp(name: str, d_in: int, d_hidden: int, d_out: int) -> dict[str, tuple[int, ...]]:
    return {**_linear(f"{name}.fc", d_in, d_hidden), **_linear(f"{name}.proj", d_hidden, d_out)}


def _attention(name: str, width: int) -> dict[str, tuple[int, ...]]:
    return {
        **_linear(f"{name}.q", width, width),
        **_linear(f"{name}.kv", width, 2 * width),
        **_linear(f"{name}.proj", width, width),
    }


def encoder_shapes(c: PointMAEConfig, prefix: str = "") -> dict[str, tuple[int, ...]]:
    """The tensors (name -> shape, state-dict order) of a
    :class:`~pair2scene.model.pointmae.PointMAEEncoder` of config ``c``, without torch."""
    h, d = c.pointnet_hidden, c.width
    out = {
        **_linear("embed.first.0", 3, h),
        **_norm("embed.first.1", h),
        **_linear("embed.first.3", h, 2 * h),
        **_linear("embed.second.0", 4 * h, 4 * h),
        **_norm("embed.second.1", 4 * h),
        **_linear("embed.second.3", 4 * h, d),
        **_linear("pos_embed.0", 3, c.pos_hidden),
        **_linear("pos_embed.2", c.pos_hidden, d),
    }
    hidden = int(d * c.mlp_ratio)
    for i in range(c.depth):
        b = f"transformer.blocks.{i}"
        out |= {
            **_norm(f"{b}.ln_1", d),
            **_linear(f"{b}.attn.qkv", d, 3 * d),
            **_linear(f"{b}.attn.proj", d, d),
            **_norm(f"{b}.ln_2", d),
            **_linear(f"{b}.mlp.0", d, hidden),
            **_linear(f"{b}.mlp.2", hidden, d),
        }
    out |= _norm("transformer.ln_f", d)
    return {prefix + k: v for k, v in out.items()}


def expected_shapes(
    config: LayoutConfig, encoder: PointMAEConfig | None
) -> dict[str, tuple[int, ...]]:
    """The tensors (name -> shape, in state-dict order) a checkpoint of ``config`` holds:
    the :class:`~pair2scene.model.layout.LayoutPredictor`'s, its encoder's under
    ``point_encoder.``. Worked out without torch, so that a checkpoint is checked and read
    for generation without importing it (the tests hold it to :func:`skeleton`'s)."""
    c, w = config, config.width
    out: dict[str, tuple[int, ...]] = {
        "member_queries": (N_MEMBERS, c.queries, w),
        "unknown_box": (w,),  # (a module's own parameters come before its children's)
        **({"pair_centre": table_shape(c.n_categories)} if c.uses_pair_prior else {}),
        **(
            {"pair_mode": mode_table_shape(c.n_categories, c.mixture.num_components)}
            if c.uses_pair_modes
            else {}
        ),
        **(
            {"pair_turn": turn_table_shape(c.n_categories, c.mixture.yaw_modes)}
            if c.uses_pair_turns
            else {}
        ),
        "category.weight": (c.n_categories, w),
        **_mlp("size_mlp", 3, w, w),
        **_mlp("box_mlp", BOX_DIM, w, w),
        **_mlp("known_size_mlp", 3, w, w),
    }
    if c.uses_points:
        out |= {
            **_linear("point_proj", c.point_dim, w),
            **_mlp("point_pos", 3, w, w),
            **_norm("ln_points", w),
        }
    for i in range(c.depth):
        b = f"blocks.{i}"
        out |= {**_norm(f"{b}.ln_self", w), **_attention(f"{b}.self_attn", w)}
        if c.uses_points:
            out |= {**_norm(f"{b}.ln_cross", w), **_attention(f"{b}.cross_attn", w)}
        out |= {**_norm(f"{b}.ln_mlp", w), **_mlp(f"{b}.mlp", w, c.mlp_ratio * w, w)}
    out |= {**_norm("ln_f", w), **_mlp("head", c.queries * w, w, c.mixture.head_dim)}
    if c.uses_frames:
        out["frame.weight"] = (len(FRAME_NAMES), w)
    if c.uses_points and encoder is not None:
        out |= encoder_shapes(encoder, "point_encoder.")
    return out


def _field_value(spec: ModelConfig, field: str) -> Any:
    section, _, rest = field.partition(".")
    value: Any = spec.layout if section == "layout" else spec.encoder
    for part in rest.split("."):
        value = getattr(value, part)
    return value


def check_parameter_count(
    shapes: Mapping[str, tuple[int, ...]], spec: ModelConfig, where: str | Path
) -> int:
    """The parameters of a network of tensors ``shapes`` (:func:`expected_shapes`); over
    :data:`MAX_PARAMETERS` a one-line :class:`UserError` naming the fields that size its
    largest part."""
    parts: dict[str, int] = {}
    for name, shape in shapes.items():
        top = name.split(".", 1)[0]
        parts[top] = parts.get(top, 0) + math.prod(shape)
    total = sum(parts.values())
    if total > MAX_PARAMETERS:
        largest = max(parts, key=parts.__getitem__)
        fields = PART_FIELDS.get(largest, ("layout.width",))
        shown = ", ".join(f"{f} {_field_value(spec, f)}" for f in fields)
        raise UserError(
            f"{where}: {shown}: the config describes {total / 1e6:,.0f} M parameters "
            f"({largest}: {parts[largest] / 1e6:,.0f} M), over the limit of "
            f"{MAX_PARAMETERS / 1e6:.0f} M"
        )
    return total


def _one_line(e: BaseException) -> str:
    text = " ".join(str(e).split())
    return text if len(text) <= 200 else text[:197] + "..."


def check_weights_header(path: Path, expected: dict[str, tuple[int, ...]]) -> None:
    """The safetensors file ``path`` holds exactly the tensors ``expected`` (name ->
    shape), in a floating-point dtype; read from its header alone. One-line
    :class:`UserError` otherwise."""
    try:
        info = os.stat(path)
    except FileNotFoundError:
        raise UserError(f"{path}: missing") from None
    except (OSError, ValueError) as e:
        raise UserError(f"{path}: cannot read ({_one_line(e)})") from None
    if not stat.S_ISREG(info.st_mode):
        raise UserError(f"{path}: not a regular file (a safetensors file is expected)")
    from safetensors import safe_open

    found: dict[str, tuple[tuple[int, ...], str]] = {}
    try:
        with safe_open(str(path), framework="numpy") as f:
            for name in f.keys():  # noqa: SIM118  (safe_open is no mapping)
                part = f.get_slice(name)
                found[name] = (tuple(part.get_shape()), part.get_dtype())
    except Exception as e:  # safetensors raises its own types for truncated/corrupt files
        raise UserError(f"{path}: not a readable safetensors file ({_one_line(e)})") from None

    def unfit(problem: str) -> UserError:
        return UserError(f"{path}: weights do not fit the config ({problem})")

    missing = [k for k in expected if k not in found]
    if missing:
        more = f" and {len(missing) - 1} more" if len(missing) > 1 else ""
        raise unfit(f"missing tensor {_shown(missing[0])}{more}")
    extra = [k for k in found if k not in expected]
    if extra:
        more = f" and {len(extra) - 1} more" if len(extra) > 1 else ""
        raise unfit(f"unexpected tensor {_shown(extra[0])}{more}")
    for name, shape in expected.items():
        got, dtype = found[name]
        if got != shape:
            raise unfit(f"{name} has shape {list(got)}, the config gives {list(shape)}")
        if dtype not in FLOAT_DTYPES:
            raise unfit(f"{name} is {dtype}, not a floating-point tensor")


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
    folder = Path(folder)
    if folder.is_file():
        raise UserError(f"{folder}: a checkpoint is a folder holding {CONFIG_FILE}")
    path = folder / CONFIG_FILE
    try:
        mode = os.stat(path).st_mode
    except (OSError, ValueError):
        mode = None  # missing or unreadable: the reader says which
    if mode is not None and not stat.S_ISREG(mode) and not stat.S_ISDIR(mode):
        raise UserError(f"{path}: not a regular file")  # a pipe would block the reader
    return read_json_document(path, FORMAT, VERSION, "missing (not a layout-model checkpoint)")


@dataclasses.dataclass
class CheckpointState:
    """A checkpoint read from its folder, checked, as numpy arrays: what both the torch
    network (:func:`load_checkpoint`) and the torch-free inference
    (:class:`~pair2scene.model.api.LayoutModel`'s numpy twins) are built from."""

    spec: ModelConfig
    state: dict[str, np.ndarray]
    """Every tensor by name, float32, in the header's order."""
    path: Path


def read_checkpoint(folder: str | Path | None = None) -> CheckpointState:
    """The checkpoint in ``folder`` (None: the bundled default) read and checked as the
    module docstring says (steps 1-5), without torch; every problem a one-line
    :class:`UserError`."""
    folder = DEFAULT_DIR if folder is None else Path(folder)
    if folder == DEFAULT_DIR and not (folder / CONFIG_FILE).exists():
        raise UserError("no bundled default model in this installation")
    doc = read_config(folder)
    where = folder / CONFIG_FILE
    spec = check_model_config(doc, where)
    expected = expected_shapes(spec.layout, spec.encoder)
    check_parameter_count(expected, spec, f"{where}: bad model config")
    weights = folder / spec.weights
    check_weights_header(weights, expected)
    state = _read_tensors(weights)
    for name, value in state.items():
        if not np.isfinite(value).all():
            raise UserError(f"{weights}: non-finite weights in {name}")
        if value.size and float(np.abs(value).max()) > MAX_ABS_WEIGHT:
            raise UserError(
                f"{weights}: weights of magnitude {float(np.abs(value).max()):.3g} in {name}, "
                f"beyond {MAX_ABS_WEIGHT:g}: not a trained model"
            )
    return CheckpointState(spec, state, folder)


def _read_tensors(path: Path) -> dict[str, np.ndarray]:
    """The tensors of the safetensors file ``path`` (its header already checked) as
    float32 arrays. numpy has no bfloat16: a BF16 tensor is widened from its bits (the
    upper half of a float32)."""
    from safetensors import safe_open

    out: dict[str, np.ndarray] = {}
    try:
        with safe_open(str(path), framework="numpy") as f:
            for name in f.keys():  # noqa: SIM118  (safe_open is no mapping)
                if f.get_slice(name).get_dtype() == "BF16":
                    out[name] = _bf16_tensor(path, name)
                else:  # (a float64 beyond float32 becomes inf: refused as non-finite)
                    with np.errstate(over="ignore"):
                        out[name] = np.ascontiguousarray(f.get_tensor(name), dtype=np.float32)
    except FileNotFoundError:
        raise UserError(f"{path}: missing") from None
    except UserError:
        raise
    except Exception as e:  # safetensors raises its own types for truncated/corrupt files
        raise UserError(f"{path}: not a readable safetensors file ({_one_line(e)})") from None
    return out


def _bf16_tensor(path: Path, name: str) -> np.ndarray:
    """The BF16 tensor ``name`` of ``path`` as float32, read by its header's offsets
    (safetensors' layout: an 8-byte little-endian header length, the JSON header, the
    data)."""
    with open(path, "rb") as f:
        size = int.from_bytes(f.read(8), "little")
        header = json.loads(f.read(size))
        entry = header[name]
        start, end = entry["data_offsets"]
        f.seek(8 + size + start)
        raw = f.read(end - start)
    shape = tuple(entry["shape"])
    if len(raw) != 2 * math.prod(shape):
        raise UserError(f"{path}: not a readable safetensors file (truncated tensor {name})")
    bits = np.frombuffer(raw, dtype="<u2").astype(np.uint32) << 16
    return bits.view(np.float32).reshape(shape)


def load_checkpoint(folder: str | Path | None = None, device: str = "cpu") -> Checkpoint:
    """The checkpoint in ``folder`` (None: the bundled default) as a torch network in eval
    mode; checked as the module docstring says, every problem a one-line
    :class:`UserError`."""
    return torch_checkpoint(read_checkpoint(folder), device)


def torch_checkpoint(read: CheckpointState, device: str = "cpu") -> Checkpoint:
    """The torch network of a checkpoint :func:`read_checkpoint` read, in eval mode."""
    import torch

    spec, folder = read.spec, read.path
    predictor = skeleton(spec.layout, spec.encoder)
    state = {k: torch.from_numpy(v) for k, v in read.state.items()}
    weights = folder / spec.weights
    try:
        predictor.load_state_dict(state, strict=True, assign=True)
    except RuntimeError as e:  # (the header check makes this unreachable)
        raise UserError(f"{weights}: weights do not fit the config ({_one_line(e)})") from None
    left = [n for n, t in [*predictor.named_parameters(), *predictor.named_buffers()] if t.is_meta]
    if left:
        raise UserError(f"{weights}: weights do not fit the config (no tensor for {left[0]})")
    predictor = predictor.to(device).eval()
    return Checkpoint(
        predictor=predictor,
        config=spec.layout,
        encoder_config=spec.encoder,
        n_points=spec.n_points,
        preset=spec.preset,
        min_anchor_half_m=spec.min_anchor_half_m,
        meta=spec.training,
        path=folder,
    )


# -- resumable training state --------------------------------------------------------------


def save_training_state(
    folder: Path, stem: str, model: torch.nn.Module, opt: torch.optim.Optimizer, doc: dict,
    extra: dict[str, torch.Tensor] | None = None,
) -> None:  # fmt: skip
    """``folder/<stem>.safetensors`` (weights, AdamW moments, ``extra`` tensors such as a
    generator's state) and ``folder/<stem>.json`` (``doc``), weights first, both atomic."""
    import torch

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

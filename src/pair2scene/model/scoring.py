"""Scoring layout models on 3D-Pairs: one number, computed the same way for every model.

The scored quantity (the contract every model meets)
----------------------------------------------------
For each relation tuple, the score is the negative log density, in nats, of the
dependent's 12-d box in the support anchor's canonical frame **exactly as the 3D-Pairs
dataset stores it** (``PairsDataset.canonical``)::

    x = (centre (3), size (3), 6D rotation (6))       no log of the size

and ``nll`` is the mean of ``-log p(x)`` over the tuples of a split. A model scored here
implements :class:`Scorer`: ``log_prob(data) -> (N,)`` gives ``log p(x)`` of every tuple
of ``data``, as a density **of x**, float64 nats.

A model that works in another parametrisation ``y = g(x)`` must return the density of x,
i.e. add the log-Jacobian: ``log p_x(x) = log p_y(g(x)) + log |det dg/dx|``. For the one
in use, log size (:mod:`pair2scene.model.mixture`: ``y = (centre, log size, 6D)``),
``dg/dx`` is diagonal with ``1 / size`` on the three size entries, so

    log p_x = log p_y - sum(log size)        i.e.   nll_x = nll_logsize + sum(log size)

which :func:`log_prob_from_log_size` does. Without it the two numbers differ by the
mean of ``sum(log size)`` over the split (about -4 nats on the full corpora, where most
canonical sizes are well under 1) and do not compare.

Why not a log transform, or fewer numbers: the stored vector is what the dataset holds
and what assembly consumes, so it is the one place where every model can meet. Beware
that it is not a free 12-d vector: the 6D rotation of an upright object has two exact
zeros, a floor object's centre height is exactly ``size_z / 2 - 1``, most yaws are
multiples of 90 degrees. A density on it is finite only because every model floors its
scales (the logistic mixture's ``min_log_scale``, the Gaussian baseline's ``reg``), and
how many nats an exactly predictable number earns is set by that floor. Compare models
whose floors match (:data:`pair2scene.model.baseline.DEFAULT_REG` is matched to the
logistic floor), and read ``median_nll`` beside ``nll``: the mean is the contract, but a
few val boxes that no train box resembles can move it by tens of nats.

Model specs (:func:`load_model`): ``gaussian`` (the baseline, fitted on the train split
of the scored folder), a path to a saved baseline JSON, ``default`` or a checkpoint path
(the learned model: not trained yet; its loader goes in :func:`_load_learned`).
"""

from __future__ import annotations

import dataclasses
import json
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Protocol, runtime_checkable

import numpy as np

from pair2scene.curation.dataset import MemberArrays, PairsDataset, load_pairs
from pair2scene.errors import UserError

if TYPE_CHECKING:
    from pair2scene.model.baseline import GaussianConfig

BOX_DIM = 12
"""The scored vector: canonical centre 3, size 3, 6D rotation 6, as stored."""
SIZE_SLICE = slice(3, 6)
"""Where the three sizes sit in the scored vector."""
SIZE_DIMS = (3, 4, 5)
SIZE_FLOOR = 1e-6
"""Sizes are clamped to this before a log (as pair2scene.model.mixture.MIN_TARGET_SIZE):
a zero extent would give -inf. The smallest canonical size on the corpora is ~2e-3."""
MODEL_SPECS = ("default", "gaussian")
"""Named models :func:`load_model` knows, besides paths."""


# -- the convention, as functions ---------------------------------------------------------


def to_log_size(x: np.ndarray) -> np.ndarray:
    """(N, 12) stored vectors -> (N, 12) with the sizes replaced by their natural log."""
    y = np.array(x, dtype=np.float64)
    y[..., SIZE_SLICE] = np.log(np.maximum(y[..., SIZE_SLICE], SIZE_FLOOR))
    return y


def log_prob_from_log_size(log_prob_y: np.ndarray, size: np.ndarray) -> np.ndarray:
    """Density of the stored vector from a log-size density: (N,), (N, 3) -> (N,) nats.

    ``log p_x = log p_y - sum(log size)`` (the log-Jacobian of ``size -> log size``).
    """
    log_size = np.log(np.maximum(np.asarray(size, dtype=np.float64), SIZE_FLOOR))
    return np.asarray(log_prob_y, dtype=np.float64) - log_size.sum(axis=-1)


# -- the protocol -------------------------------------------------------------------------


@runtime_checkable
class Scorer(Protocol):
    """What :func:`score` needs of a model."""

    def log_prob(self, data: PairsDataset) -> np.ndarray:
        """(N,) float64 log density, in nats, of ``data.canonical`` as stored (see the
        module docstring), one value per tuple of ``data``."""
        ...


@runtime_checkable
class SizeScorer(Scorer, Protocol):
    """A scorer that also gives the marginal density of the stored size (3 dims), so that
    :func:`score` can report the NLL of the placement *given* the size."""

    def log_prob_size(self, data: PairsDataset) -> np.ndarray:
        """(N,) float64 log marginal density of ``data.canonical[:, 3:6]`` as stored."""
        ...


def select_rows(data: PairsDataset, rows: np.ndarray) -> PairsDataset:
    """The tuples ``rows`` ((N,) bool mask or int indices) of ``data``, as a dataset."""

    def take(a: np.ndarray) -> np.ndarray:
        return a[rows]

    def member(m: MemberArrays) -> MemberArrays:
        return MemberArrays(**{f.name: take(getattr(m, f.name)) for f in dataclasses.fields(m)})

    return PairsDataset(
        categories=data.categories,
        kinds=data.kinds,
        kind=take(data.kind),
        dependent=member(data.dependent),
        support=member(data.support),
        functional=member(data.functional),
        canonical=take(data.canonical),
        canonical_functional=take(data.canonical_functional),
        wall_box=take(data.wall_box),
        wall_index=take(data.wall_index),
        canonical_wall=take(data.canonical_wall),
        source=take(data.source),
        scene_id=take(data.scene_id),
        split=take(data.split),
        room_type=take(data.room_type),
        manifest=data.manifest,
    )


# -- scores -------------------------------------------------------------------------------


@dataclass(frozen=True)
class GroupScore:
    """NLL of a group of tuples."""

    nll: float
    """Mean -log p(x) per tuple, nats; inf when some tuple has zero density."""
    n: int


@dataclass(frozen=True)
class ScoreResult:
    """The score of a model on one split."""

    nll: float
    """Mean NLL per tuple (nats) of the stored canonical box: the headline number."""
    n: int
    """Tuples scored."""
    split: str
    median_nll: float
    """Median per-tuple NLL: less swayed by the few boxes unlike anything in train."""
    nonfinite: int
    """Tuples whose log density is not finite (a model bug or a zero density)."""
    per_kind: dict[str, GroupScore] = field(default_factory=dict)
    """By relation kind (floor, support, functional)."""
    nll_given_size: float | None = None
    """Mean -log p(x | size) = -(log p(x) - log p(size)): the placement (centre and
    rotation) given the dependent's size, as generation meets it (the asset, and so its
    size, is chosen first). Fair between a model that takes the dependent's size as an
    input (the learned one) and one that does not (the Gaussian): both are asked the same
    question. None when the model cannot give the size's marginal."""
    per_source: dict[str, GroupScore] = field(default_factory=dict)
    """By source label as the dataset stores it."""
    given_size_per_kind: dict[str, GroupScore] = field(default_factory=dict)
    """:attr:`nll_given_size` by relation kind (floor, support, functional); empty when
    the model cannot give the size's marginal."""

    def to_dict(self) -> dict:
        """Plain JSON types; a non-finite NLL becomes null (JSON has no inf)."""

        def num(v: float) -> float | None:
            return float(v) if np.isfinite(v) else None

        def groups(g: dict[str, GroupScore]) -> dict:
            return {k: {"nll": num(s.nll), "n": s.n} for k, s in g.items()}

        return {
            "nll": num(self.nll),
            "n": self.n,
            "split": self.split,
            "median_nll": num(self.median_nll),
            "nll_given_size": None if self.nll_given_size is None else num(self.nll_given_size),
            "nonfinite": self.nonfinite,
            "per_kind": groups(self.per_kind),
            "per_source": groups(self.per_source),
            "given_size_per_kind": groups(self.given_size_per_kind),
        }


def _mean_nll(nll: np.ndarray) -> float:
    if len(nll) == 0:
        return float("nan")
    if not np.isfinite(nll).all():
        return float("inf")
    return float(nll.mean())


def split_of(data: PairsDataset | str | Path, split: str | None) -> PairsDataset:
    """The tuples of ``split`` (all when None) of a dataset or a 3D-Pairs folder; a
    missing folder or an empty split is a one-line UserError."""
    if not isinstance(data, PairsDataset):
        data = load_pairs(data)
    if split is None:
        return data
    mask = data.split == split
    if not mask.any():
        have = sorted({s or "(none)" for s in data.split.tolist()})
        raise UserError(f"no {split!r} tuples in the dataset (splits present: {', '.join(have)})")
    return select_rows(data, mask)


def score(model: Scorer, data: PairsDataset | str | Path, split: str | None = "val") -> ScoreResult:
    """Mean NLL of ``model`` on the ``split`` tuples of ``data`` (a dataset or a 3D-Pairs
    folder), overall, per relation kind and per source."""
    subset = split_of(data, split)
    lp = np.asarray(model.log_prob(subset), dtype=np.float64)
    if lp.shape != (len(subset),):
        raise ValueError(f"model.log_prob returned shape {lp.shape}, expected ({len(subset)},)")
    nll = -lp
    finite = np.isfinite(nll)

    def by(labels: np.ndarray, values: np.ndarray = nll) -> dict[str, GroupScore]:
        return {
            str(v): GroupScore(_mean_nll(values[labels == v]), int((labels == v).sum()))
            for v in sorted(set(labels.tolist()))
        }

    kinds = np.array([subset.kinds[k] for k in subset.kind.tolist()], dtype=object)
    given_size, given_size_per_kind = None, {}
    if isinstance(model, SizeScorer):
        lps = np.asarray(model.log_prob_size(subset), dtype=np.float64)
        given_size = _mean_nll(-(lp - lps))
        given_size_per_kind = by(kinds, -(lp - lps))
    return ScoreResult(
        nll=_mean_nll(nll),
        n=len(subset),
        split=split if split is not None else "all",
        median_nll=float(np.median(nll)) if len(nll) else float("nan"),
        nonfinite=int((~finite).sum()),
        per_kind=by(kinds),
        per_source=by(subset.source),
        nll_given_size=given_size,
        given_size_per_kind=given_size_per_kind,
    )


# -- models by name -----------------------------------------------------------------------


def load_model(
    spec: str,
    data: PairsDataset | str | Path | None = None,
    baseline_config: GaussianConfig | None = None,
) -> Scorer:
    """A model to score, by spec.

    ``gaussian``: the Gaussian baseline fitted on the train split of ``data`` (required);
    ``default``: the learned model's default checkpoint; a path: a saved baseline JSON
    (:meth:`GaussianBaseline.save`) or a learned-model checkpoint.
    """
    from pair2scene.model.baseline import BASELINE_FORMAT, GaussianBaseline

    if spec == "gaussian":
        if data is None:
            raise ValueError("load_model('gaussian') needs the data to fit on")
        if not isinstance(data, PairsDataset):
            data = load_pairs(data)
        return GaussianBaseline.fit(data, "train", baseline_config)
    if spec == "default":
        return _load_learned(None)
    path = Path(spec)
    if not path.exists():
        raise UserError(
            f"model {spec!r}: no such file or folder (use {' | '.join(MODEL_SPECS)} or a path)"
        )
    if path.is_file() and _json_format(path) == BASELINE_FORMAT:
        return GaussianBaseline.load(path)
    return _load_learned(path)


def _json_format(path: Path) -> str | None:
    """The ``format`` field of a JSON file, None when it is not one."""
    try:
        doc = json.loads(path.read_text(encoding="utf-8"))
    except (OSError, ValueError):
        return None
    return doc.get("format") if isinstance(doc, dict) else None


def _load_learned(path: Path | None) -> Scorer:
    """The learned layout model in checkpoint folder ``path`` (None: the bundled default);
    its ``log_prob`` adds the model frame's and the log size's Jacobians, so it follows
    the contract of this module."""
    from pair2scene.model.api import LayoutModel

    return LayoutModel.from_pretrained(path)

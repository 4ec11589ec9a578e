"""Gaussian-mixture baseline: a density over the canonical box per category key.

For every relation tuple the baseline gives the density of the dependent's 12-d box in
the support anchor's canonical frame, exactly as the 3D-Pairs dataset stores it,

    x = (centre (3), size (3), 6D rotation (6))      (no log of the size),

the quantity :mod:`pair2scene.model.scoring` scores. By default the mixtures live in
(centre, log size, 6D), like the learned model's, and the log-Jacobian is added back.

Anchor frames (issue 18)
------------------------
With :attr:`GaussianConfig.anchor_frames` (the default) every tuple is modelled in the
frame the learned model predicts it in
(:attr:`pair2scene.model.layout.LayoutConfig.anchor_frames`), so that the comparison is
fair: a floor object standing against a wall in that wall's frame, else a floor object
with a functional anchor in the anchor's footprint frame, else its support's frame
(:func:`frame_choice`, the one rule of :mod:`pair2scene.curation.frames`,
kept torch-free here). The frame kind joins the support's key (:func:`frame_key`:
``floor@wall``, ``floor@functional``), so "bed against a wall" and "bed in the room's
frame" get mixtures of their own, and the global key (``(@wall,)``, ``(@functional,)``;
``()`` for the support's frame), so that the last resort of a tuple is a mixture in its
own frame. The dependent's level pools the frames, as it pools the supports. On 3D-Pairs
(issue 18) that is the best of the four ways to key the two coarse levels: one global
mixture over all frames cost the support tuples, whose frame does not change, ~0.9 nats;
frames in the dependent's key too cost the floor and functional tuples ~0.3-0.8 nats
(fewer tuples per key). From the stored support frame to another one is an affine map of
the 12 numbers (centre and size scaled per axis by ``h_support / h_frame``, the rotation
rotated), so the scores stay densities of the stored vector:
``log p_x = log p_frame + 2 (sum log h_support - sum log h_frame)`` (centre and size),
and the size marginal adds the size's half of it.

Mixtures are fitted per category key at four levels, finest first::

    sup_dep_func   (support category, dependent category, functional category | none)
    sup_dep        (support category, dependent category)
    dep            (dependent category)
    global         ()                                   (per frame, see above)

A key gets its own mixture when the training split has at least ``min_count`` tuples
with it (``global`` keys always get one); rarer keys back off to the next level. A
query's density interpolates its fitted levels, finest first:
``(1 - smoothing) p_finest + smoothing p_rest``, recursively down to ``global``
(``smoothing = 0``: hard back-off to the finest fitted key). Each mixture is fitted by a
small seeded EM (k-means++ seeding, Lloyd, then EM) in numpy, with
``min(components, n // min_per_component)`` components.

Why the variance floor matters: the 12 numbers are not free. The 6D rotation of an
upright object has two exact zeros, a floor-standing object's centre height is exactly
``size_z / 2 - 1``, and most yaws are multiples of 90 degrees, so the data lie on a
lower-dimensional set and an unregularised Gaussian collapses (NLL -> -inf). ``reg``
(added to every covariance diagonal) sets how sharp a component may get and so how many
nats an exactly predictable number is worth; its default matches the learned model's
floor (see :data:`DEFAULT_REG`), so that the two are scored on the same footing.

:meth:`GaussianBaseline.sample_arrays` draws from that same interpolated density (one
mixture per key, :meth:`~GaussianBaseline.mixture_for`), conditioned on the dependent's
size as the learned model's samples are (``GaussianPlacement`` in
:mod:`pair2scene.assembly.baselines` places scenes with it).

The model does no file I/O except :meth:`GaussianBaseline.save` / :meth:`load`, a JSON
document (no pickle) whose floats round-trip exactly.
"""

from __future__ import annotations

import json
import math
import zlib
from collections.abc import Collection, Sequence
from dataclasses import asdict, dataclass, field
from pathlib import Path

import numpy as np
from scipy.linalg import solve_triangular
from scipy.special import logsumexp

from pair2scene.curation.dataset import PairsDataset
from pair2scene.curation.frames import (  # noqa: F401  (re-exported for the baseline's users)
    FRAME_FUNCTIONAL,
    FRAME_NAMES,
    FRAME_SUPPORT,
    FRAME_WALL,
    canonical_to_frame,
    footprint_frame,
    frame_choice,
    tuple_frames,
)
from pair2scene.errors import UserError
from pair2scene.io.atomic import atomic_write_text
from pair2scene.model.scoring import (
    BOX_DIM,
    SIZE_DIMS,
    SIZE_FLOOR,
    log_prob_from_log_size,
    to_log_size,
)
from pair2scene.scene.geometry import OrientedBox

BASELINE_FORMAT = "pair2scene.gaussian_baseline"
BASELINE_VERSION = 1
LEVELS: tuple[str, ...] = ("sup_dep_func", "sup_dep", "dep", "global")
"""Back-off levels, finest first (see the module docstring)."""
NONE_KEY = "none"
"""The functional category of a tuple without a functional anchor, in keys."""


DEFAULT_REG = 2.0e-6
"""Variance added to every covariance diagonal. The learned mixture of logistics floors
its log-scale at -7 (pair2scene.model.mixture.MixtureConfig.min_log_scale): a logistic of
scale e^-7 has peak log-density 7 - log 4 = 5.61 nats. A Gaussian of variance v peaks at
-0.5 log(2 pi v); equal peaks give v = exp(-11.23) / (2 pi) ~ 2e-6 (std ~1.4e-3 canonical
units). With this floor an exactly predictable number is worth the same to both models."""


# -- configuration --------------------------------------------------------------------


@dataclass(frozen=True)
class GaussianConfig:
    """Hyper-parameters of :class:`GaussianBaseline`."""

    components: int = 8
    """Maximum mixture components per key. More than the learned model's K = 4, which is
    per tuple: one key pools boxes at up to four right-angle yaws, and a yaw mode only
    earns the floor's nats on the 6D numbers with a component of its own (held-out train
    scenes: 2 -> 4 -> 8 components gave -14 -> -26 -> -29 nats)."""
    min_count: int = 20
    """Training tuples a key needs for its own mixture; rarer keys back off to a coarser
    level. Twenty 12-d points are about the least that pin a few-component mixture down."""
    min_per_component: int = 5
    """A key with n tuples gets at most n // min_per_component components (at least 1):
    a component fitted on a handful of points collapses onto them."""
    covariance: str = "diag"
    """``diag`` (independent dimensions, as the learned logistic mixture) or ``full``
    (also captures linear ties such as centre height = size / 2 - 1 for floor objects;
    on held-out train scenes ~0.5 nats better at K = 8 and ~7x slower to fit)."""
    reg: float = DEFAULT_REG
    """Variance floor added to every covariance diagonal (see :data:`DEFAULT_REG`)."""
    smoothing: float = 0.5
    """Interpolated back-off: each fitted key's density is mixed with its next coarser
    fitted level's, ``(1 - smoothing) p_key + smoothing p_coarser``, down to ``global``.
    Keeps a val box that its key never saw in train (a faucet on a differently sized
    sink) from costing thousands of nats under a sharp Gaussian. 0: hard back-off."""
    log_size: bool = True
    """Fit the mixtures on (centre, log size, 6D), as the learned model does, and add the
    log-Jacobian so that :meth:`GaussianBaseline.log_prob` is still the density of the
    stored vector (pair2scene.model.scoring). Sizes are closer to log-normal: ~0.7 nats
    better on held-out train scenes, and far lighter tails."""
    max_iter: int = 200
    """EM iterations at most."""
    tol: float = 1e-6
    """EM stops when the mean log-likelihood per tuple gains less than this (nats)."""
    kmeans_iter: int = 10
    """Lloyd iterations that seed EM."""
    seed: int = 0
    """Seed of the k-means++ initialisation; each key draws from (seed, crc32(key)), so a
    key's mixture does not depend on which other keys were fitted."""
    anchor_frames: bool = True
    """Model each tuple in the frame of the anchor that governs it, as the learned model
    does by default (a floor object against a wall in the wall's frame, one with a
    functional anchor in that anchor's footprint frame; the module docstring), with the
    frame kind in the keys; scores stay densities of the stored canonical vector. True by
    default so that the learned model is compared with the strongest fair baseline.
    False: every tuple in its support's stored canonical frame (baselines saved before
    issue 18 load with False)."""

    def __post_init__(self) -> None:
        if self.covariance not in ("full", "diag"):
            raise ValueError(f"covariance must be 'full' or 'diag', got {self.covariance!r}")
        if self.components < 1 or self.min_count < 1 or self.min_per_component < 1:
            raise ValueError("components, min_count and min_per_component must be >= 1")
        if not 0.0 <= self.smoothing < 1.0:
            raise ValueError("smoothing must lie in [0, 1)")
        if not self.reg > 0:
            raise ValueError("reg must be > 0 (an unfloored Gaussian collapses, see DEFAULT_REG)")


# -- one mixture ------------------------------------------------------------------------


@dataclass(frozen=True, eq=False)
class GaussianMixture:
    """A Gaussian mixture in D dimensions with K components.

    weights : (K,) summing to 1; means : (K, D); covariances : (K, D, D) when full,
    (K, D) variances when diagonal. Stored values are what is saved; everything derived
    (Cholesky factors) is recomputed from them, so a loaded mixture scores identically.
    """

    weights: np.ndarray
    means: np.ndarray
    covariances: np.ndarray
    count: int = 0
    """Training tuples it was fitted on."""
    _log_w: np.ndarray = field(init=False, repr=False)
    _chol: np.ndarray = field(init=False, repr=False)
    _log_det: np.ndarray = field(init=False, repr=False)

    def __post_init__(self) -> None:
        w = np.asarray(self.weights, dtype=np.float64)
        mu = np.asarray(self.means, dtype=np.float64)
        cov = np.asarray(self.covariances, dtype=np.float64)
        full_shape, diag_shape = (*mu.shape, mu.shape[-1]), mu.shape
        if mu.ndim != 2 or w.shape != mu.shape[:1] or cov.shape not in (full_shape, diag_shape):
            raise ValueError(f"bad mixture shapes: w {w.shape}, mu {mu.shape}, cov {cov.shape}")
        for name, arr in (("weights", w), ("means", mu), ("covariances", cov)):
            arr.setflags(write=False)
            object.__setattr__(self, name, arr)
        with np.errstate(divide="ignore"):
            object.__setattr__(self, "_log_w", np.log(w))
        if self.full:
            chol = np.linalg.cholesky(cov)  # (K, D, D) lower
            log_det = 2.0 * np.log(np.diagonal(chol, axis1=1, axis2=2)).sum(axis=1)
        else:
            chol = np.sqrt(cov)  # (K, D)
            log_det = np.log(cov).sum(axis=1)
        object.__setattr__(self, "_chol", chol)
        object.__setattr__(self, "_log_det", log_det)

    @property
    def full(self) -> bool:
        return self.covariances.ndim == 3

    @property
    def n_components(self) -> int:
        return len(self.weights)

    def component_log_prob(self, x: np.ndarray) -> np.ndarray:
        """x (N, D) -> (N, K): log w_k + log N(x; mu_k, Sigma_k)."""
        x = np.asarray(x, dtype=np.float64)
        n, d = x.shape
        out = np.empty((n, self.n_components))
        for k in range(self.n_components):
            diff = x - self.means[k]  # (N, D)
            if self.full:
                z = solve_triangular(self._chol[k], diff.T, lower=True, check_finite=False)
                maha = np.einsum("dn,dn->n", z, z)
            else:
                maha = ((diff / self._chol[k]) ** 2).sum(axis=1)
            out[:, k] = self._log_w[k] - 0.5 * (d * math.log(2 * math.pi) + self._log_det[k] + maha)
        return out

    def log_prob(self, x: np.ndarray) -> np.ndarray:
        """x (N, D) -> (N,) log density in nats."""
        return logsumexp(self.component_log_prob(x), axis=1)

    def sample(self, n: int, rng: np.random.Generator, temperature: float = 1.0) -> np.ndarray:
        """``n`` draws (n, D). The temperature T acts as in the learned model's sampler
        (:func:`pair2scene.model.mixture.sample`), so the two are compared at the same
        setting: components are drawn with weights proportional to w^(1/T) and every
        covariance is scaled by T^2; T = 0 gives the heaviest component's mean."""
        if not (math.isfinite(temperature) and temperature >= 0):
            raise ValueError(f"temperature must be finite and >= 0, got {temperature}")
        if n < 1:
            raise ValueError(f"n must be >= 1, got {n}")
        if temperature == 0:
            return np.repeat(self.means[int(np.argmax(self.weights))][None], n, axis=0)
        logits = self._log_w / temperature  # w^(1/T), unnormalised
        p = np.exp(logits - logits.max())
        comp = rng.choice(self.n_components, size=n, p=p / p.sum())
        z = rng.standard_normal((n, self.means.shape[1]))
        if self.full:
            noise = np.einsum("nij,nj->ni", self._chol[comp], z)
        else:
            noise = self._chol[comp] * z
        return self.means[comp] + temperature * noise

    def condition(self, dims: Sequence[int], values: np.ndarray) -> GaussianMixture:
        """The mixture over the other dims (in order) given ``x[dims] = values`` (exact).

        Each component is reweighted by how well it explains the values (its marginal
        density there) and replaced by its Gaussian conditional: for a full covariance
        the mean moves by ``S_fg S_gg^-1 (values - mu_g)`` and the covariance becomes the
        Schur complement (never below ``reg``: the floor is independent noise); for a
        diagonal one the other dims are independent of the given ones and keep theirs.
        """
        dims = list(dims)
        free = [d for d in range(self.means.shape[1]) if d not in dims]
        v = np.asarray(values, dtype=np.float64).reshape(len(dims))
        log_fit = self.marginal(dims).component_log_prob(v[None])[0]  # includes log w
        weights = np.exp(log_fit - logsumexp(log_fit))
        if self.full:
            cov = self.covariances
            s_gg = cov[:, dims][:, :, dims]
            s_fg = cov[:, free][:, :, dims]
            gain = np.linalg.solve(s_gg, s_fg.transpose(0, 2, 1)).transpose(0, 2, 1)
            means = self.means[:, free] + np.einsum("kfg,kg->kf", gain, v - self.means[:, dims])
            new_cov = cov[:, free][:, :, free] - gain @ s_fg.transpose(0, 2, 1)
            new_cov = 0.5 * (new_cov + new_cov.transpose(0, 2, 1))
        else:
            means, new_cov = self.means[:, free], self.covariances[:, free]
        return GaussianMixture(weights, means, new_cov, self.count)

    def marginal(self, dims: Sequence[int]) -> GaussianMixture:
        """The mixture's marginal over ``dims`` (same weights, the sub-means and
        sub-covariances)."""
        dims = list(dims)
        cov = self.covariances[:, dims][:, :, dims] if self.full else self.covariances[:, dims]
        return GaussianMixture(self.weights, self.means[:, dims], cov, self.count)

    def to_dict(self) -> dict:
        return {
            "count": self.count,
            "weights": self.weights.tolist(),
            "means": self.means.tolist(),
            "covariances": self.covariances.tolist(),
        }

    @classmethod
    def from_dict(cls, doc: dict) -> GaussianMixture:
        return cls(
            np.array(doc["weights"], dtype=np.float64),
            np.array(doc["means"], dtype=np.float64),
            np.array(doc["covariances"], dtype=np.float64),
            int(doc.get("count", 0)),
        )


def _kmeans_pp(x: np.ndarray, k: int, rng: np.random.Generator) -> np.ndarray:
    """k-means++ seeds: (k,) row indices of x (N, D)."""
    n = len(x)
    idx = [int(rng.integers(n))]
    d2 = ((x - x[idx[0]]) ** 2).sum(axis=1)
    for _ in range(1, k):
        total = d2.sum()
        if total <= 0:  # fewer distinct points than seeds
            break
        i = int(rng.choice(n, p=d2 / total))
        idx.append(i)
        d2 = np.minimum(d2, ((x - x[i]) ** 2).sum(axis=1))
    return np.array(idx)


def _m_step(x: np.ndarray, resp: np.ndarray, full: bool, reg: float) -> GaussianMixture | None:
    """Weights, means and floored covariances from responsibilities resp (N, K); None
    when every component is empty. Empty components (no responsibility) are dropped."""
    nk = resp.sum(axis=0)  # (K,)
    keep = nk > 10 * np.finfo(float).eps * len(x)
    if not keep.any():
        return None
    resp, nk = resp[:, keep], nk[keep]
    means = resp.T @ x / nk[:, None]  # (K, D)
    d = x.shape[1]
    if full:
        cov = np.empty((len(nk), d, d))
        for k in range(len(nk)):
            diff = x - means[k]
            cov[k] = (resp[:, k, None] * diff).T @ diff / nk[k]
            cov[k] = 0.5 * (cov[k] + cov[k].T) + reg * np.eye(d)
    else:
        sq = (x[:, None, :] - means[None]) ** 2  # (N, K, D)
        cov = np.einsum("nk,nkd->kd", resp, sq) / nk[:, None] + reg
    return GaussianMixture(nk / nk.sum(), means, cov, count=len(x))


def fit_mixture(x: np.ndarray, config: GaussianConfig, rng: np.random.Generator) -> GaussianMixture:
    """EM fit of a Gaussian mixture to x (N, D), N >= 1, seeded by ``rng``.

    Components: ``min(config.components, N // config.min_per_component)``, at least 1.
    """
    x = np.asarray(x, dtype=np.float64)
    n = len(x)
    if n == 0:
        raise ValueError("fit_mixture needs at least one point")
    full = config.covariance == "full"
    k = max(1, min(config.components, n // config.min_per_component))
    # Seeding in standardised coordinates: raw canonical heights span hundreds of units
    # on thin supports and would otherwise decide every k-means split alone.
    scale = x.std(axis=0)
    z = (x - x.mean(axis=0)) / np.where(scale > 0, scale, 1.0)
    centres = z[_kmeans_pp(z, k, rng)]
    labels = np.zeros(n, dtype=int)
    for _ in range(config.kmeans_iter):
        d2 = ((z[:, None, :] - centres[None]) ** 2).sum(axis=2)  # (N, K)
        labels = d2.argmin(axis=1)
        centres = np.stack(
            [z[labels == j].mean(axis=0) if (labels == j).any() else centres[j]
             for j in range(len(centres))]
        )  # fmt: skip
    resp = np.zeros((n, len(centres)))
    resp[np.arange(n), labels] = 1.0
    mix = _m_step(x, resp, full, config.reg)
    assert mix is not None
    prev = -np.inf
    for _ in range(config.max_iter):
        comp = mix.component_log_prob(x)  # (N, K)
        ll = logsumexp(comp, axis=1)  # (N,)
        mean_ll = float(ll.mean())
        if mean_ll - prev < config.tol:
            break
        prev = mean_ll
        new = _m_step(x, np.exp(comp - ll[:, None]), full, config.reg)
        if new is None:
            break
        mix = new
    return mix


# -- the baseline -------------------------------------------------------------------------


Key = tuple[str, ...]


def level_keys(
    dependent: Sequence[str], support: Sequence[str], functional: Sequence[str]
) -> dict[str, list[Key]]:
    """Per level, the key of each tuple. Inputs: (N,) category names; an empty
    functional name means no functional anchor. A support name with a frame
    (:func:`frame_key`, ``floor@wall``) gives the tuple that frame's global key
    (``(@wall,)``); the dependent's level pools every frame, as it pools every support."""
    func = [f if f else NONE_KEY for f in functional]
    return {
        "sup_dep_func": [(s, d, f) for s, d, f in zip(support, dependent, func)],
        "sup_dep": [(s, d) for s, d in zip(support, dependent)],
        "dep": [(d,) for d in dependent],
        "global": [(f"@{s.partition('@')[2]}",) if "@" in s else () for s in support],
    }


def _stored(y: np.ndarray, log_size: bool) -> np.ndarray:
    """Draws in the fitted space -> stored vectors (sizes back from their log)."""
    if not log_size:
        return y
    out = np.array(y, dtype=np.float64)
    out[:, list(SIZE_DIMS)] = np.exp(out[:, list(SIZE_DIMS)])
    return out


def _names(categories: Sequence[str], index: np.ndarray) -> list[str]:
    return [categories[i] if i >= 0 else "" for i in index.tolist()]


def dataset_keys(data: PairsDataset) -> tuple[list[str], list[str], list[str]]:
    """(dependent, support, functional) category names of every tuple ("" for none)."""
    return (
        _names(data.categories, data.dependent.category),
        _names(data.categories, data.support.category),
        _names(data.categories, data.functional.category),
    )


def frame_key(support: str, kind: int) -> str:
    """The support's name in the keys of a tuple modelled in frame ``kind``: the category
    itself in its support's frame, ``<support>@wall`` / ``<support>@functional`` in a
    wall's or a functional anchor's frame ("@" is in no category name)."""
    return support if kind == FRAME_SUPPORT else f"{support}@{FRAME_NAMES[kind]}"


@dataclass(frozen=True)
class FramedTuples:
    """What the baseline fits and scores of a dataset: each tuple's box in its frame with
    its keys, and the Jacobians back to the stored canonical vector."""

    x: np.ndarray
    """(N, 12) each dependent's box in its frame (the stored canonical one in the
    support's frame)."""
    dependent: list[str]
    support: list[str]
    """(N,) the support's key name (:func:`frame_key`)."""
    functional: list[str]
    kinds: np.ndarray
    """(N,) frame kind (:data:`FRAME_NAMES`)."""
    log_jacobian: np.ndarray
    """(N,) log p(stored canonical) - log p(x): 2 * the per-part log-Jacobian."""
    size_log_jacobian: np.ndarray
    """(N,) the same for the size marginal: the size's part only."""


def framed_tuples(
    data: PairsDataset, anchor_frames: bool, frames: Collection[int] | None = None
) -> FramedTuples:
    """:class:`FramedTuples` of every tuple of ``data``; without ``anchor_frames`` every
    tuple is in its support's frame (``x`` is ``data.canonical`` and the Jacobians 0).

    frames : the frame kinds that may be used (None: all); a tuple whose frame is not
        among them stays in its support's frame.
    """
    dep, sup, func = dataset_keys(data)
    x = data.canonical.astype(np.float64)
    n = len(data)
    kinds, part_jac = np.full(n, FRAME_SUPPORT, np.int64), np.zeros(n)
    if anchor_frames:
        kinds, frames_box = tuple_frames(data)
        if frames is not None:
            kinds[~np.isin(kinds, list(frames))] = FRAME_SUPPORT
        rows = np.flatnonzero(kinds != FRAME_SUPPORT)
        x[rows], part_jac[rows] = canonical_to_frame(
            x[rows], data.support.box[rows], frames_box[rows]
        )
        sup = [frame_key(s, int(k)) for s, k in zip(sup, kinds.tolist())]
    return FramedTuples(x, dep, sup, func, kinds, 2.0 * part_jac, part_jac)


def _key_seed(seed: int, level: str, key: Key) -> np.random.Generator:
    return np.random.default_rng([seed, zlib.crc32("/".join((level, *key)).encode())])


@dataclass
class GaussianBaseline:
    """Gaussian mixtures over the canonical box per category key, with back-off.

    Implements the scoring protocol (:class:`pair2scene.model.scoring.Scorer`):
    :meth:`log_prob` of a :class:`PairsDataset` -> (N,) nats of ``data.canonical``.
    """

    config: GaussianConfig
    mixtures: dict[str, dict[Key, GaussianMixture]]
    """level -> key -> mixture; ``global`` holds the single key ``()``."""
    _framed: tuple[PairsDataset, FramedTuples] | None = field(
        default=None, init=False, repr=False, compare=False
    )

    @classmethod
    def fit(
        cls,
        data: PairsDataset,
        split: str | None = "train",
        config: GaussianConfig | None = None,
    ) -> GaussianBaseline:
        """Fit on the tuples of ``split`` (all tuples when None), each in its frame
        (:func:`framed_tuples`, with ``config.anchor_frames``)."""
        config = config or GaussianConfig()
        mask = np.ones(len(data), bool) if split is None else data.split == split
        if not mask.any():
            have = sorted(set(data.split.tolist()))
            raise UserError(f"no {split!r} tuples to fit the Gaussian baseline on (splits: {have})")
        framed = framed_tuples(data, config.anchor_frames)
        rows = np.flatnonzero(mask).tolist()
        return cls.fit_arrays(
            framed.x[rows],
            [framed.dependent[i] for i in rows],
            [framed.support[i] for i in rows],
            [framed.functional[i] for i in rows],
            config,
        )

    @classmethod
    def fit_arrays(
        cls,
        x: np.ndarray,
        dependent: Sequence[str],
        support: Sequence[str],
        functional: Sequence[str],
        config: GaussianConfig | None = None,
    ) -> GaussianBaseline:
        """Fit on x (N, 12) with (N,) category names ("" functional: none); x and the
        support names as :func:`framed_tuples` gives them (the arrays are taken as they
        are, whatever ``config.anchor_frames``)."""
        config = config or GaussianConfig()
        x = np.asarray(x, dtype=np.float64)
        if x.ndim != 2 or x.shape[1] != BOX_DIM or len(x) == 0:
            raise ValueError(f"x must be (N>0, {BOX_DIM}), got {x.shape}")
        if config.log_size:
            x = to_log_size(x)
        mixtures: dict[str, dict[Key, GaussianMixture]] = {}
        for level, keys in level_keys(dependent, support, functional).items():
            rows: dict[Key, list[int]] = {}
            for i, key in enumerate(keys):
                rows.setdefault(key, []).append(i)
            if level == "global" and () not in rows:  # every frame falls back on ()
                rows[()] = list(range(len(x)))
            mixtures[level] = {
                key: fit_mixture(x[idx], config, _key_seed(config.seed, level, key))
                for key, idx in sorted(rows.items())
                if len(idx) >= config.min_count or level == "global"
            }
        return cls(config, mixtures)

    def keys(
        self, dependent: Sequence[str], support: Sequence[str], functional: Sequence[str]
    ) -> dict[str, list[Key]]:
        """:func:`level_keys`, a frame's global key that was never fitted (no train tuple
        in that frame) replaced by the global ``()``."""
        keys = level_keys(dependent, support, functional)
        fitted = self.mixtures["global"]
        keys["global"] = [k if k in fitted else () for k in keys["global"]]
        return keys

    # -- queries --------------------------------------------------------------------------

    def resolve(
        self, dependent: Sequence[str], support: Sequence[str], functional: Sequence[str]
    ) -> tuple[np.ndarray, list[Key]]:
        """Which mixture scores each tuple: ((N,) level index into LEVELS, (N,) key)."""
        keys = self.keys(dependent, support, functional)
        n = len(dependent)
        level = np.full(n, len(LEVELS) - 1)
        chosen: list[Key] = [()] * n
        for i in range(n):
            for j, name in enumerate(LEVELS):
                if keys[name][i] in self.mixtures[name]:
                    level[i], chosen[i] = j, keys[name][i]
                    break
        return level, chosen

    def mixture_for(self, dependent: str, support: str, functional: str = "") -> GaussianMixture:
        """One key's density as a single mixture, in the fitted space (log sizes when
        ``config.log_size``): the components of every fitted level of the key, weighted as
        :meth:`log_prob_arrays` interpolates them, so sampling draws from the very density
        that is scored (``functional`` "": no functional anchor)."""
        keys = self.keys([dependent], [support], [functional])
        lam = self.config.smoothing
        parts: list[tuple[float, GaussianMixture]] = []
        for level in reversed(LEVELS):
            mix = self.mixtures[level].get(keys[level][0])
            if mix is None:
                continue
            if level == "global" or lam == 0.0:
                parts = [(1.0, mix)]
            else:
                parts = [(1.0 - lam, mix)] + [(lam * w, m) for w, m in parts]
        if not parts:
            raise ValueError("the baseline has no global mixture")
        return GaussianMixture(
            np.concatenate([w * m.weights for w, m in parts]),
            np.concatenate([m.means for _, m in parts]),
            np.concatenate([m.covariances for _, m in parts]),
            parts[0][1].count,
        )

    def sample_arrays(
        self,
        dependent: str,
        support: str,
        functional: str,
        n: int,
        rng: np.random.Generator,
        size: Sequence[float] | None = None,
        temperature: float = 1.0,
        mixture: GaussianMixture | None = None,
    ) -> np.ndarray:
        """``n`` canonical boxes (n, 12) of one key in the key's frame (the support's
        key names it, :func:`frame_key`), as the dataset stores boxes (centre, size, 6D;
        the 6D part as drawn, not orthonormalised).

        size : (3,) the dependent's canonical size (its size over its frame's half-size,
            the support's without anchor frames): the mixture is conditioned on it
            (:meth:`GaussianMixture.condition`, in log size when ``config.log_size``) and
            every draw has exactly this size, as the learned model's samples do.
        mixture : :meth:`mixture_for` of the key, when the caller keeps it.
        """
        mix = self.mixture_for(dependent, support, functional) if mixture is None else mixture
        if size is None:
            y = mix.sample(n, rng, temperature)
            return _stored(y, self.config.log_size)
        given = np.asarray(size, dtype=np.float64).reshape(3)
        g = np.log(np.maximum(given, SIZE_FLOOR)) if self.config.log_size else given
        free = [d for d in range(BOX_DIM) if d not in SIZE_DIMS]
        out = np.empty((n, BOX_DIM))
        out[:, free] = mix.condition(SIZE_DIMS, g).sample(n, rng, temperature)
        out[:, list(SIZE_DIMS)] = given
        return out

    def level_counts(self, data: PairsDataset) -> dict[str, int]:
        """How many tuples of ``data`` each back-off level scores."""
        f = self.framed(data)
        level, _ = self.resolve(f.dependent, f.support, f.functional)
        return {name: int((level == j).sum()) for j, name in enumerate(LEVELS)}

    def log_prob_arrays(
        self,
        x: np.ndarray,
        dependent: Sequence[str],
        support: Sequence[str],
        functional: Sequence[str],
        dims: Sequence[int] | None = None,
    ) -> np.ndarray:
        """x (N, 12) canonical boxes (centre, size, 6D) with (N,) category names -> (N,)
        log density in nats of x as given (see :mod:`pair2scene.model.scoring`).

        dims : score only the marginal over these dims of x (e.g. the sizes 3, 4, 5).
        """
        x = np.asarray(x, dtype=np.float64).reshape(-1, BOX_DIM)
        y = to_log_size(x) if self.config.log_size else x
        if dims is not None:
            dims = list(dims)
            y = y[:, dims]
        keys = self.keys(dependent, support, functional)
        lam = self.config.smoothing
        # Coarse to fine: acc is the density of the coarser levels, each fitted finer key
        # takes (1 - lam) of the mass and leaves lam to acc.
        acc = np.full(len(y), np.nan)
        for level in reversed(LEVELS):
            groups: dict[Key, list[int]] = {}
            for i, key in enumerate(keys[level]):
                if key in self.mixtures[level]:
                    groups.setdefault(key, []).append(i)
            for key, idx in groups.items():
                mix = self.mixtures[level][key]
                lp = (mix if dims is None else mix.marginal(dims)).log_prob(y[idx])
                if level == "global" or lam == 0.0:
                    acc[idx] = lp
                else:
                    acc[idx] = np.logaddexp(math.log1p(-lam) + lp, math.log(lam) + acc[idx])
        if self.config.log_size:
            sizes = [d - 3 for d in (range(BOX_DIM) if dims is None else dims) if 3 <= d < 6]
            acc = log_prob_from_log_size(acc, x[:, 3:6][:, sizes])
        return acc

    def frame_for(
        self,
        support: OrientedBox,
        on_floor: bool,
        wall: OrientedBox | None,
        functional: OrientedBox | None,
    ) -> tuple[int, OrientedBox]:
        """(frame kind, frame box) a placement query is drawn in: :func:`frame_choice`
        with ``config.anchor_frames`` (a frame no train tuple was in: the support's), else
        always its support's box."""
        if not self.config.anchor_frames:
            return FRAME_SUPPORT, support
        kind, frame = frame_choice(support, on_floor, wall, functional)
        return (kind, frame) if kind in self.frames else (FRAME_SUPPORT, support)

    @property
    def frames(self) -> frozenset[int]:
        """The frame kinds the baseline was fitted in (each has its global mixture): a
        tuple or a query whose frame is not among them (3D-Pairs v1 has no walls) is
        modelled in its support's frame."""
        fitted = self.mixtures["global"]
        return frozenset(
            k for k, name in enumerate(FRAME_NAMES)
            if k == FRAME_SUPPORT or (self.config.anchor_frames and (f"@{name}",) in fitted)
        )  # fmt: skip

    def framed(self, data: PairsDataset) -> FramedTuples:
        """Every tuple of ``data`` as this baseline fits and scores it (kept for the
        last dataset: scoring asks for :meth:`log_prob` and then :meth:`log_prob_size`)."""
        if self._framed is not None and self._framed[0] is data:
            return self._framed[1]
        framed = framed_tuples(data, self.config.anchor_frames, self.frames)
        self._framed = (data, framed)
        return framed

    def _framed_log_prob(self, data: PairsDataset, dims: Sequence[int] | None) -> np.ndarray:
        f = self.framed(data)
        lp = self.log_prob_arrays(f.x, f.dependent, f.support, f.functional, dims=dims)
        return lp + (f.log_jacobian if dims is None else f.size_log_jacobian)

    def log_prob(self, data: PairsDataset) -> np.ndarray:
        """(N,) log density (nats) of each tuple's ``canonical`` box as stored (scored in
        its frame, plus the frame's Jacobian)."""
        return self._framed_log_prob(data, None)

    def log_prob_size(self, data: PairsDataset) -> np.ndarray:
        """(N,) log marginal density (nats) of each tuple's stored canonical size."""
        return self._framed_log_prob(data, SIZE_DIMS)

    # -- persistence ----------------------------------------------------------------------

    def to_dict(self) -> dict:
        return {
            "format": BASELINE_FORMAT,
            "version": BASELINE_VERSION,
            "config": asdict(self.config),
            "levels": {
                level: [{"key": list(key), **m.to_dict()} for key, m in mixes.items()]
                for level, mixes in self.mixtures.items()
            },
        }

    @classmethod
    def from_dict(cls, doc: dict) -> GaussianBaseline:
        if doc.get("format") != BASELINE_FORMAT:
            raise ValueError(f"not a {BASELINE_FORMAT} document")
        if doc.get("version") != BASELINE_VERSION:
            raise ValueError(f"{BASELINE_FORMAT} version {doc.get('version')!r} not supported")
        mixtures = {
            level: {tuple(e["key"]): GaussianMixture.from_dict(e) for e in doc["levels"][level]}
            for level in LEVELS
        }
        # Baselines saved before anchor frames were fitted in the support's frame.
        config = {"anchor_frames": False, **doc["config"]}
        return cls(GaussianConfig(**config), mixtures)

    def save(self, path: str | Path) -> None:
        """Write the baseline as JSON (floats round-trip exactly)."""
        atomic_write_text(Path(path), json.dumps(self.to_dict()) + "\n")

    @classmethod
    def load(cls, path: str | Path) -> GaussianBaseline:
        """Read a baseline written by :meth:`save`; a bad file is a one-line UserError."""
        path = Path(path)
        try:
            doc = json.loads(path.read_text(encoding="utf-8"))
        except FileNotFoundError:
            raise UserError(f"{path}: no such file") from None
        except (OSError, ValueError) as e:
            raise UserError(f"{path}: not a readable baseline JSON ({e})") from None
        try:
            return cls.from_dict(doc)
        except (KeyError, TypeError, ValueError, np.linalg.LinAlgError) as e:
            raise UserError(f"{path}: not a valid {BASELINE_FORMAT} file ({e})") from None

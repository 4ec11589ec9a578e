"""How close a set of generated scenes is to a set of real rooms, object by object.

- :func:`category_kl`: KL(reference || generated) between the category distributions,
  the ATISS definition: each set's distribution is the frequency of every category over
  all objects of all its scenes; categories the generated set never uses get a small
  probability (:data:`KL_EPS`) so that a missing category costs a finite amount.
- :func:`pose_mmd`: for the most frequent (anchor category, dependent category) pairs of
  the reference, the squared maximum mean discrepancy between the dependent's pose
  relative to its anchor in the reference and in the generated scenes. The anchor is the
  object the dependent rests on, or, for floor objects, its functional anchor (a chair's
  desk). The pose is (dx, dy, dz) in metres in the anchor's frame and the cosine and sine
  of the relative yaw; the kernel is a Gaussian RBF whose bandwidth is the median
  distance of the pooled pair (the median heuristic), so that metres and angles both
  count and each pair's value lies in [0, 2].

Structure (walls, floors) and parts of furniture (drawers, shelves) are left out of both:
generated scenes have neither as objects.
"""

from __future__ import annotations

from collections import Counter
from collections.abc import Iterable, Sequence

import numpy as np

from pair2scene.categories import BY_NAME, SuperCategory
from pair2scene.scene.model import FLOOR, Scene, SceneObject

KL_EPS = 1e-6
"""Probability given to a category the generated set lacks (before renormalising)."""
TOP_PAIRS = 10
"""Relation pairs :func:`pose_mmd` compares by default."""
MIN_PAIR_SAMPLES = 3
"""A pair needs this many relative poses in the reference to be compared."""
SKIPPED = (SuperCategory.STRUCTURE, SuperCategory.PART)


def counted(o: SceneObject) -> bool:
    """Whether an object takes part in the distribution metrics."""
    cat = BY_NAME.get(o.category)
    return cat is None or cat.super not in SKIPPED


def category_frequencies(scenes: Iterable[Scene]) -> Counter:
    """category -> number of objects over all ``scenes``."""
    return Counter(o.category for s in scenes for o in s.objects if counted(o))


def category_kl(reference: Sequence[Scene], generated: Sequence[Scene]) -> float:
    """KL(p_reference || p_generated) in nats over the categories of both sets."""
    ref, gen = category_frequencies(reference), category_frequencies(generated)
    if not ref or not gen:
        return float("nan")
    cats = sorted(set(ref) | set(gen))
    p = np.array([ref[c] for c in cats], float)
    q = np.array([gen[c] for c in cats], float)
    p /= p.sum()
    q = q / q.sum() + KL_EPS
    q /= q.sum()
    nz = p > 0
    return float(np.sum(p[nz] * np.log(p[nz] / q[nz])))


def _anchor(o: SceneObject, by_id: dict[str, SceneObject]) -> SceneObject | None:
    support = o.support if o.support is not None else o.source_support
    if support is not None and support != FLOOR and support in by_id:
        return by_id[support]
    if o.functional_anchor is not None and o.functional_anchor in by_id:
        return by_id[o.functional_anchor]
    return None


def relative_poses(scenes: Iterable[Scene]) -> dict[tuple[str, str], np.ndarray]:
    """(anchor category, dependent category) -> (n, 5) poses (dx, dy, dz, cos, sin) of
    the dependent in its anchor's frame, over every anchored object of ``scenes``."""
    out: dict[tuple[str, str], list[np.ndarray]] = {}
    for s in scenes:
        by_id = {o.id: o for o in s.objects if counted(o)}
        for o in by_id.values():
            a = _anchor(o, by_id)
            if a is None:
                continue
            local = a.box.rotation.T @ (o.box.center - a.box.center)
            yaw = o.box.yaw - a.box.yaw
            pose = np.array([*local, np.cos(yaw), np.sin(yaw)])
            out.setdefault((a.category, o.category), []).append(pose)
    return {k: np.stack(v) for k, v in out.items()}


def mmd2(x: np.ndarray, y: np.ndarray, bandwidth: float | None = None) -> float:
    """Squared MMD (the biased V-statistic: exactly 0 for identical sets) between samples
    x (n, d) and y (m, d) with a Gaussian RBF kernel; ``bandwidth`` defaults to the median
    pairwise distance of the pooled samples."""
    z = np.concatenate([x, y])
    d2 = np.sum((z[:, None, :] - z[None, :, :]) ** 2, axis=-1)
    if bandwidth is None:
        off = d2[~np.eye(len(z), dtype=bool)]
        med = float(np.median(np.sqrt(off))) if off.size else 1.0
        bandwidth = med if med > 1e-9 else 1.0
    k = np.exp(-d2 / (2.0 * bandwidth**2))
    n = len(x)
    return float(max(k[:n, :n].mean() + k[n:, n:].mean() - 2.0 * k[:n, n:].mean(), 0.0))


def pose_mmd(
    reference: Sequence[Scene],
    generated: Sequence[Scene],
    top: int = TOP_PAIRS,
    seed: int = 0,
    max_samples: int = 400,
) -> dict:
    """``{"mean", "pairs": [{"pair", "reference", "generated", "mmd2"}], "missing"}``.

    ``mean`` weights each of the ``top`` most frequent reference pairs (with at least
    :data:`MIN_PAIR_SAMPLES` poses) by its reference count; a pair the generated set never
    makes scores the kernel's maximum, 2, and is listed in ``missing``. Sets larger than
    ``max_samples`` are subsampled (seeded) to bound the quadratic cost.
    """
    ref, gen = relative_poses(reference), relative_poses(generated)
    ranked = sorted(
        ((k, v) for k, v in ref.items() if len(v) >= MIN_PAIR_SAMPLES),
        key=lambda kv: (-len(kv[1]), kv[0]),
    )[:top]
    rng = np.random.default_rng(seed)

    def cap(a: np.ndarray) -> np.ndarray:
        if len(a) <= max_samples:
            return a
        return a[np.sort(rng.choice(len(a), max_samples, replace=False))]

    rows, missing, total, weight = [], [], 0.0, 0
    for pair, poses in ranked:
        other = gen.get(pair)
        value = 2.0 if other is None else mmd2(cap(poses), cap(other))
        if other is None:
            missing.append("/".join(pair))
        rows.append({"pair": "/".join(pair), "reference": len(poses),
                     "generated": 0 if other is None else len(other),
                     "mmd2": round(value, 5)})  # fmt: skip
        total += value * len(poses)
        weight += len(poses)
    return {"mean": total / weight if weight else float("nan"), "pairs": rows, "missing": missing}

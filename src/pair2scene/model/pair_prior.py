"""The pair table: each category pair's own median centre, added to the network's output.

A network shared by every tuple learns a frequent pair's placement and averages a rare
one's away: the bundled model, trained without this table, draws a pillow, a book and a
laptop on a bed alike (centre along the bed +0.16 / +0.15 / +0.13 of its half length,
where the 47 training pillows lie at -0.53, at its head), and neither re-weighting the
pairs, fine-tuning on beds, feeding the identity to the head nor feeding this very table
as an input separated them (docs/model.md). With :attr:`LayoutConfig.pair_prior` the
table's centre is added to every component's location, as the known size and resting
height are (``LayoutPredictor.known_target``): the network predicts the residual, and
a rare pair keeps its own centre.

The table is indexed ``[frame anchor, dependent, frame]`` with the category vocabulary
(:data:`~pair2scene.model.features.CATEGORY_VOCAB`): the frame anchor is the member whose
frame the tuple is predicted in (its support; its functional anchor in the functional
frame; the wall category in a wall's frame), so a chair at a desk and a chair at a
dining table have rows of their own. It holds the median (x, y) of the train tuples'
target centres (model frame: half sizes of the frame box) where a pair has at least
:data:`~pair2scene.model.config.PAIR_PRIOR_MIN_TUPLES` of them, and 0 elsewhere. Only
the train split counts, so validation NLL sees no tuple's own position. Numpy only: the
torch model and its numpy twin read the same table from the checkpoint.
"""

from __future__ import annotations

import numpy as np

from pair2scene.curation.frames import FRAME_FUNCTIONAL, FRAME_NAMES, FRAME_WALL
from pair2scene.model.config import (
    DEPENDENT,
    FUNCTIONAL,
    PAIR_PRIOR_MIN_TUPLES,
    SUPPORT,
    WALL_INDEX,
)

CENTRE_DIMS = 2
"""The table's values per pair: the centre's x and y (z is the known resting height)."""


def table_shape(n_categories: int) -> tuple[int, int, int, int]:
    """(anchors, dependents, frames, 2): the ``pair_centre`` buffer's shape."""
    return (n_categories, n_categories, len(FRAME_NAMES), CENTRE_DIMS)


def frame_anchor(categories: np.ndarray, frames: np.ndarray | None) -> np.ndarray:
    """(B,) the category of the member each tuple's frame belongs to.

    categories : (B, 3) member categories (dependent, support, functional anchor);
    frames : (B,) frame kinds (:data:`FRAME_NAMES`), None: every tuple in its support's.
    """
    support = categories[:, SUPPORT]
    if frames is None:
        return support
    out = np.where(frames == FRAME_FUNCTIONAL, categories[:, FUNCTIONAL], support)
    return np.where(frames == FRAME_WALL, WALL_INDEX, out)


def pair_centre_table(
    categories: np.ndarray,
    frames: np.ndarray | None,
    centres: np.ndarray,
    n_categories: int,
    min_tuples: int = PAIR_PRIOR_MIN_TUPLES,
) -> np.ndarray:
    """The table (:func:`table_shape`, float32) from train tuples.

    categories : (N, 3) long; frames : (N,) or None; centres : (N, >= 2) the tuples'
    target centres in their frames (``TupleArrays.target[:, :2]``).
    """
    table = np.zeros(table_shape(n_categories), np.float32)
    groups = _pair_groups(categories, frames, n_categories, min_tuples)
    for (a, d, f), rows in groups:
        table[a, d, f] = np.median(np.asarray(centres, np.float64)[rows, :CENTRE_DIMS], axis=0)
    return table


def _pair_groups(
    categories: np.ndarray, frames: np.ndarray | None, n_categories: int, min_tuples: int
) -> list[tuple[tuple[int, int, int], np.ndarray]]:
    """((frame anchor, dependent, frame), the rows of its tuples) of every key with at
    least ``min_tuples`` tuples."""
    if len(categories) == 0:
        return []
    frame = np.zeros(len(categories), np.int64) if frames is None else np.asarray(frames)
    anchor = frame_anchor(np.asarray(categories), frame)
    dep = np.asarray(categories)[:, DEPENDENT]
    key = np.stack([anchor, dep, frame], axis=1)
    valid = np.flatnonzero((key >= 0).all(axis=1) & (anchor < n_categories) & (dep < n_categories))
    pairs, inverse, counts = np.unique(key[valid], axis=0, return_inverse=True, return_counts=True)
    inverse = inverse.reshape(-1)
    return [
        (tuple(int(v) for v in pairs[i]), valid[inverse == i])
        for i in np.flatnonzero(counts >= min_tuples)
    ]


def turn_table_shape(n_categories: int, turns: int) -> tuple[int, int, int, int]:
    """(anchors, dependents, frames, Q): the ``pair_turn`` buffer's shape."""
    return (n_categories, n_categories, len(FRAME_NAMES), turns)


def pair_turn_table(
    categories: np.ndarray,
    frames: np.ndarray | None,
    rotations: np.ndarray,
    n_categories: int,
    turns: int,
    min_tuples: int = PAIR_PRIOR_MIN_TUPLES,
) -> np.ndarray:
    """The yaw-turn table (:func:`turn_table_shape`, float32) from train tuples: for a pair
    with at least ``min_tuples``, the log share of its tuples whose yaw in the frame is
    nearest to each of the ``turns`` right-angle turns (``q * 360 / turns`` degrees; one
    pseudo-count per turn), minus their mean; 0 elsewhere (the network's split alone).

    rotations : (N, >= 2) the tuples' target rotation's first column, x and y
    (``TupleArrays.target[:, 6:8]``: cos and sin of the yaw).
    """
    table = np.zeros(turn_table_shape(n_categories, turns), np.float32)
    rot = np.asarray(rotations, np.float64)
    yaw = np.arctan2(rot[:, 1], rot[:, 0]) if len(rot) else np.zeros(0)
    turn = np.rint(yaw / (2 * np.pi / turns)).astype(np.int64) % turns
    for (a, d, f), rows in _pair_groups(categories, frames, n_categories, min_tuples):
        share = np.bincount(turn[rows], minlength=turns) + 1.0
        logs = np.log(share / share.sum())
        table[a, d, f] = logs - logs.mean()
    return table


def table_rows(table: np.ndarray, categories: np.ndarray, frames: np.ndarray | None):
    """(B, ...) ``table``'s row for each tuple (0 for a pair it lacks): (B, 2) centres of
    :func:`pair_centre_table`, (B, Q) log shares of :func:`pair_turn_table`."""
    frame = np.zeros(len(categories), np.int64) if frames is None else np.asarray(frames)
    # (np.minimum and np.maximum: np.clip's wrapper costs more than the indexing)
    anchor = np.minimum(np.maximum(frame_anchor(categories, frame), 0), table.shape[0] - 1)
    dep = np.minimum(np.maximum(categories[:, DEPENDENT], 0), table.shape[1] - 1)
    return table[anchor, dep, frame]


MODE_VALUES = 3
"""The mode table's values per pair and component: the cluster centre's x and y, less the
pair's median (its offset from :func:`pair_centre_table`'s centre), and its log share."""
KMEANS_ITERATIONS = 25
SHARE_PSEUDO_COUNT = 0.5
"""Added to each cluster's count before the log share: an empty cluster keeps some weight."""


def mode_table_shape(n_categories: int, modes: int) -> tuple[int, int, int, int, int]:
    """(anchors, dependents, frames, K, 3): the ``pair_mode`` buffer's shape."""
    return (n_categories, n_categories, len(FRAME_NAMES), modes, MODE_VALUES)


def pair_mode_table(
    categories: np.ndarray,
    frames: np.ndarray | None,
    centres: np.ndarray,
    n_categories: int,
    modes: int,
    min_tuples: int = PAIR_PRIOR_MIN_TUPLES,
) -> np.ndarray:
    """The mode table (:func:`mode_table_shape`, float32) from train tuples: for a pair with
    at least ``min_tuples``, its tuples' centres (x, y) split into ``modes`` clusters
    (:func:`kmeans`), largest first, each as its centre's offset from the pair's median
    and its centred log share; 0 elsewhere (the median alone, every component alike).

    A pair whose tuples lie in two places (pillows at a bed's head and, a fifth of them,
    towards its foot) gets a component near each; the network predicts each component's
    residual and reweights them, as it does the median's.
    """
    table = np.zeros(mode_table_shape(n_categories, modes), np.float32)
    xy = np.asarray(centres, np.float64)[:, :CENTRE_DIMS]
    for (a, d, f), rows in _pair_groups(categories, frames, n_categories, min_tuples):
        points = xy[rows]
        centre, counts = kmeans(points, modes, seed=(a, d, f))
        share = np.log(counts + SHARE_PSEUDO_COUNT)
        table[a, d, f, :, :CENTRE_DIMS] = centre - np.median(points, axis=0)
        table[a, d, f, :, CENTRE_DIMS] = share - share.mean()
    return table


def kmeans(points: np.ndarray, k: int, seed=0) -> tuple[np.ndarray, np.ndarray]:
    """(centres (k, 2), counts (k,)) of ``points`` (N, 2) in ``k`` clusters, largest
    first: k-means++ seeding from ``seed``, then Lloyd's iterations. With fewer distinct
    points than ``k``, the spare clusters sit on the largest one's centre with no points."""
    rng = np.random.default_rng(np.asarray(seed, np.int64).reshape(-1) % (2**32))
    pts = np.unique(points, axis=0)
    take = [int(rng.integers(len(pts)))]
    while len(take) < min(k, len(pts)):
        d2 = ((pts[:, None] - pts[take][None]) ** 2).sum(-1).min(1)
        if d2.sum() <= 0:
            break
        take.append(int(rng.choice(len(pts), p=d2 / d2.sum())))
    centres = pts[take].copy()
    for _ in range(KMEANS_ITERATIONS):
        label = ((points[:, None] - centres[None]) ** 2).sum(-1).argmin(1)
        moved = np.array([points[label == j].mean(0) if (label == j).any() else centres[j]
                          for j in range(len(centres))])  # fmt: skip
        if np.array_equal(moved, centres):
            break
        centres = moved
    label = ((points[:, None] - centres[None]) ** 2).sum(-1).argmin(1)
    counts = np.bincount(label, minlength=len(centres)).astype(np.float64)
    order = np.lexsort((centres[:, 1], centres[:, 0], -counts))
    centres, counts = centres[order], counts[order]
    spare = k - len(centres)
    if spare:
        centres = np.concatenate([centres, np.repeat(centres[:1], spare, axis=0)])
        counts = np.concatenate([counts, np.zeros(spare)])
    return centres, counts

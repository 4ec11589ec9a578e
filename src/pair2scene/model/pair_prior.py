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
    if len(categories) == 0:
        return table
    frame = np.zeros(len(categories), np.int64) if frames is None else np.asarray(frames)
    anchor = frame_anchor(np.asarray(categories), frame)
    dep = np.asarray(categories)[:, DEPENDENT]
    key = np.stack([anchor, dep, frame], axis=1)
    valid = (key >= 0).all(axis=1) & (anchor < n_categories) & (dep < n_categories)
    pairs, inverse, counts = np.unique(key[valid], axis=0, return_inverse=True, return_counts=True)
    xy = np.asarray(centres, np.float64)[valid, :CENTRE_DIMS]
    for i in np.flatnonzero(counts >= min_tuples):
        a, d, f = pairs[i]
        table[a, d, f] = np.median(xy[inverse.reshape(-1) == i], axis=0)
    return table


def table_centres(
    table: np.ndarray, categories: np.ndarray, frames: np.ndarray | None
) -> np.ndarray:
    """(B, 2) the table's centre for each tuple (0 for a pair it lacks)."""
    frame = np.zeros(len(categories), np.int64) if frames is None else np.asarray(frames)
    anchor = np.clip(frame_anchor(categories, frame), 0, table.shape[0] - 1)
    dep = np.clip(categories[:, DEPENDENT], 0, table.shape[1] - 1)
    return table[anchor, dep, frame]

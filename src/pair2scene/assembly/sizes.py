"""Object sizes for generation, drawn from the training data's per-category sizes.

The dependent's asset (and so its size) is chosen before it is placed (architecture.md's
open question: draw sizes from the data, not a fixed default). :class:`SizeTable` keeps up
to :data:`KEEP_PER_CATEGORY` observed sizes per category from a 3D-Pairs folder (the
dependents of its train split, rounded to a millimetre); :meth:`SizeTable.draw` picks one
and scales it by a small log-normal jitter, so sizes are real combinations of width,
depth and height (a wide and low sofa, never a wide, deep and tall one). A category the
data never had falls back to the asset library's typical size. Objects hung on a wall are
kept apart (``painting@wall``: a painting on a wall is wide, thin and tall, one lying on a
shelf may be stored any way round; a mounted TV has no foot). The table for the AI2-THOR
+ ProcTHOR-1k train rooms ships with the package (``resources/sizes.json``).
"""

from __future__ import annotations

import json
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from pair2scene.curation.stats import WALL_MARK
from pair2scene.errors import UserError
from pair2scene.io.atomic import atomic_write_text
from pair2scene.resources import load_table, table_path
from pair2scene.scene.model import WALL

SIZES_FORMAT = "pair2scene.sizes"
SIZES_VERSION = 1
KEEP_PER_CATEGORY = 64
"""Observed sizes kept per category (an even subsample of the sorted volumes beyond it)."""
JITTER = 0.05
"""Std of the log-normal factor on each axis of a drawn size: 5 %, below what the eye
notices between two instances and far below the spread between categories."""


LIES_DOWN = frozenset({"baseball_bat"})
"""Categories that rest lying along their longest side, whichever way the data's boxes
stand. The training rooms' bats stand 0.96 m tall on a 9 cm end, leaning on a wall or a
bed in their simulator; ours cannot lean, and stood on end on beds, desks and floors
(in 30 bedrooms 6 of 8 such bats fell, over 10 cm, in ``evaluate``'s simulation)."""


def resting_sizes(category: str, sizes: np.ndarray) -> np.ndarray:
    """Sizes (..., 3) of ``category`` resting on a surface or the floor: of one that
    :data:`LIES_DOWN`, its sides longest first (along x, then y, the shortest up); any
    other's as they are."""
    if category not in LIES_DOWN:
        return sizes
    return -np.sort(-np.asarray(sizes, dtype=float), axis=-1)


def wider_than_deep(sizes: np.ndarray) -> np.ndarray:
    """Sizes (..., 3) of objects hung on a wall, each turned a quarter where it is deeper
    than wide (:meth:`SizeTable.draw`'s ``mounted``)."""
    sizes = np.asarray(sizes)
    return np.where((sizes[..., 1] > sizes[..., 0])[..., None], sizes[..., [1, 0, 2]], sizes)


@dataclass
class SizeTable:
    """Observed sizes per category."""

    sizes: dict[str, np.ndarray] = field(default_factory=dict)
    """category -> (K, 3) float sizes (m)."""

    @classmethod
    def from_pairs(cls, data, split: str | None = "train") -> SizeTable:
        """The dependents' sizes of a :class:`~pair2scene.curation.dataset.PairsDataset`."""
        rows = np.ones(len(data), bool) if split is None else data.split == split
        table: dict[str, list[np.ndarray]] = {}
        wall = data.categories.index(WALL) if WALL in data.categories else -1
        for cat, box, sup in zip(data.dependent.category[rows], data.dependent.box[rows],
                                 data.support.category[rows]):  # fmt: skip
            key = data.categories[cat] + (WALL_MARK if sup == wall else "")
            table.setdefault(key, []).append(np.round(box[3:6], 3))
        out = {}
        for cat, sizes in sorted(table.items()):
            arr = np.unique(np.stack(sizes), axis=0)
            arr = arr[np.argsort(arr.prod(1), kind="stable")]
            if len(arr) > KEEP_PER_CATEGORY:
                arr = arr[np.linspace(0, len(arr) - 1, KEEP_PER_CATEGORY).round().astype(int)]
            out[cat] = arr.astype(float)
        return cls(out)

    def draw(
        self,
        category: str,
        rng: np.random.Generator,
        jitter: float = JITTER,
        fits=None,
        mounted: bool = False,
    ) -> np.ndarray:
        """A size (3,) for ``category``: an observed one, jittered; typical size if unseen.
        ``fits`` ((K, 3) -> (K,) bool) narrows the draw to the sizes it accepts (when none
        does, the smallest footprint is taken). ``mounted``: of one hung on a wall, when
        the data had such, and never deeper than wide: what hangs on a wall spans more
        along it than it stands out from it, and an observed size the other way round is
        a source box read a quarter turn off (1 of the 4 towel rails of the training
        rooms, 0.66 m out from its wall; 1 of 10 wall microwaves; 2 of 22 toilet paper
        holders), so it is turned."""
        observed = self._observed(category, mounted)
        if fits is not None:
            ok = fits(observed)
            observed = observed[ok] if ok.any() else observed[[np.argmin(observed[:, :2].prod(1))]]
        base = observed[int(rng.integers(len(observed)))]
        size = base * np.exp(rng.normal(0.0, jitter, 3))
        return wider_than_deep(size) if mounted else size

    def footprint(self, category: str) -> float:
        """The median floor area (m2, width x depth) of ``category``'s observed sizes
        standing on something (its typical size's if the data has none): what a piece is
        counted on to cover before its size is drawn."""
        observed = self._observed(category)
        return float(np.median(observed[:, 0] * observed[:, 1]))

    def _observed(self, category: str, mounted: bool = False) -> np.ndarray:
        """(K, 3) sizes of ``category`` (hung on a wall: of those, when the data had
        such; else as it rests, :func:`resting_sizes`), or its typical size's (1, 3) when
        the data has none."""
        observed = self.sizes.get(category + WALL_MARK) if mounted else None
        if observed is None:
            observed = self.sizes.get(category)
        if observed is None or len(observed) == 0:
            from pair2scene.assets.typical_sizes import typical_size

            observed = np.asarray(typical_size(category).size, dtype=float)[None]
        return observed if mounted else resting_sizes(category, observed)

    def to_json(self) -> str:
        doc = {
            "format": SIZES_FORMAT,
            "version": SIZES_VERSION,
            "sizes": {c: np.round(s, 3).tolist() for c, s in self.sizes.items()},
        }
        return json.dumps(doc, separators=(",", ":")) + "\n"

    def save(self, path: str | Path) -> None:
        atomic_write_text(Path(path), self.to_json())

    @classmethod
    def load(cls, path: str | Path | None = None) -> SizeTable:
        """A table written by :meth:`save` (None: the bundled one)."""
        return cls(read_size_arrays("sizes", path, "size table"))


def read_size_arrays(table: str, path: str | Path | None, what: str) -> dict[str, np.ndarray]:
    """The ``sizes`` field of bundled table ``table`` (``rooms`` or ``sizes``), or of a
    user's file of that kind at ``path``: name -> (K, 3) finite positive sizes (m)."""
    doc = load_table(table, path)
    path = table_path(table) if path is None else path
    try:
        sizes = {k: np.asarray(v, dtype=float).reshape(-1, 3) for k, v in doc["sizes"].items()}
    except (KeyError, TypeError, ValueError, AttributeError) as e:
        raise UserError(f"{path}: malformed {what} ({e})") from None
    if any((s <= 0).any() or not np.isfinite(s).all() for s in sizes.values()):
        raise UserError(f"{path}: sizes in the {what} must be finite and positive")
    return sizes

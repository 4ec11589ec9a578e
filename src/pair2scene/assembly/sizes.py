"""Object sizes for generation, drawn from the training data's per-category sizes.

The dependent's asset (and so its size) is chosen before it is placed (architecture.md's
open question: draw sizes from the data, not a fixed default). :class:`SizeTable` keeps up
to :data:`KEEP_PER_CATEGORY` observed sizes per category from a 3D-Pairs folder (the
dependents of its train split, rounded to a millimetre) and how many objects had each, in
all rooms and per room type; :meth:`SizeTable.draw` picks one (evenly, or for a counter
as often as the room type's counters had it: :data:`DRAWN_BY_COUNT`) and scales it by a
small log-normal jitter, so sizes are real combinations of width, depth and height (a
wide and low sofa, never a wide, deep and tall one). A category the
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


DRAWN_BY_COUNT = frozenset({"counter_top"})
"""Categories whose sizes are drawn as often as the training rooms had them (by room
type); every other category's observed sizes are drawn evenly. A counter is built to its
room, and one category holds two kinds: a kitchen's runs along its walls cover 2.60 m2
on average, a bathroom's vanities 1.33; drawn evenly over the observed sizes a kitchen's
counters came out 1.86. Other sizes are the asset models a house reused, and the val
houses reused others (TV stands 0.45-0.75 m high in the train living rooms, 0.72-0.75
in the val ones): furniture drawn by count made the rooms less like the val rooms (pose
MMD over 4 x 30 rooms 0.059 / 0.080 -> 0.084 / 0.107 in bedrooms and living rooms;
docs/model.md, "Counters sized by count")."""
MIN_ROOM_OBJECTS = 8
"""Objects of a category a room type's training rooms must have held for its sizes to be
drawn by that room type's counts; fewer, and by every room's (a kitchen's counters are
drawn as the kitchens' 234 were, 2.57 m2 on average, a bathroom's as the bathrooms' 22,
1.33; a bedroom's, of which the training bedrooms had 1, as counters anywhere)."""


@dataclass
class SizeTable:
    """Observed sizes per category, with how often each was seen."""

    sizes: dict[str, np.ndarray] = field(default_factory=dict)
    """category -> (K, 3) float sizes (m)."""
    counts: dict[str, np.ndarray] = field(default_factory=dict)
    """category -> (K,) objects of the training rooms that had each size (a size dropped
    beyond :data:`KEEP_PER_CATEGORY` counted with its neighbour by volume). A category
    without counts (a table written before they were kept) draws its sizes evenly."""
    room_counts: dict[str, dict[str, np.ndarray]] = field(default_factory=dict)
    """room type -> category -> (K,) the same counts over that room type's rooms."""

    @classmethod
    def from_pairs(cls, data, split: str | None = "train") -> SizeTable:
        """The dependents' sizes of a :class:`~pair2scene.curation.dataset.PairsDataset`,
        each object counted once (its floor or support tuple and its functional one are
        one object)."""
        rows = np.ones(len(data), bool) if split is None else data.split == split
        table: dict[str, dict[tuple[str, str], tuple[np.ndarray, str]]] = {}
        wall = data.categories.index(WALL) if WALL in data.categories else -1
        for i in np.flatnonzero(rows):
            cat, sup = data.dependent.category[i], data.support.category[i]
            key = data.categories[cat] + (WALL_MARK if sup == wall else "")
            seen = table.setdefault(key, {})
            obj = (str(data.scene_id[i]), str(data.dependent.id[i]))
            if obj not in seen:
                seen[obj] = (np.round(data.dependent.box[i, 3:6], 3), str(data.room_type[i]))
        out = cls()
        for cat, objects in sorted(table.items()):
            every = np.stack([size for size, _ in objects.values()])
            arr, which = np.unique(every, axis=0, return_inverse=True)
            order = np.argsort(arr.prod(1), kind="stable")
            rank = np.argsort(order)[which.ravel()]  # each object's size, by volume rank
            arr = arr[order]
            kept = np.arange(len(arr))
            if len(arr) > KEEP_PER_CATEGORY:
                kept = np.linspace(0, len(arr) - 1, KEEP_PER_CATEGORY).round().astype(int)
            # each object counts for the kept size nearest its own in volume rank
            slot = np.abs(rank[:, None] - kept[None, :]).argmin(axis=1)
            out.sizes[cat] = arr[kept].astype(float)
            out.counts[cat] = np.bincount(slot, minlength=len(kept)).astype(float)
            rtypes = np.array([rtype for _, rtype in objects.values()])
            for rtype in sorted(set(rtypes)):
                in_type = np.bincount(slot[rtypes == rtype], minlength=len(kept))
                out.room_counts.setdefault(rtype, {})[cat] = in_type.astype(float)
        return out

    def weights(self, category: str, room_type: str | None = None, mounted: bool = False):
        """(K,) how often each of :meth:`observed`'s sizes is drawn, for a category of
        :data:`DRAWN_BY_COUNT`: the room type's counts where its rooms held
        :data:`MIN_ROOM_OBJECTS` of the category, else every room's; None (evenly) for
        any other category, or without counts."""
        if category not in DRAWN_BY_COUNT:
            return None
        key = category + WALL_MARK if mounted and category + WALL_MARK in self.sizes else category
        counts = self.counts.get(key)
        if counts is None or key not in self.sizes:
            return None
        own = self.room_counts.get(room_type or "", {}).get(key)
        return own if own is not None and own.sum() >= MIN_ROOM_OBJECTS else counts

    def draw(
        self,
        category: str,
        rng: np.random.Generator,
        jitter: float = JITTER,
        fits=None,
        mounted: bool = False,
        room_type: str | None = None,
    ) -> np.ndarray:
        """A size (3,) for ``category``: an observed one, jittered; typical size if unseen.
        ``fits`` ((K, 3) -> (K,) bool) narrows the draw to the sizes it accepts (when none
        does, the smallest footprint is taken). ``mounted``: of one hung on a wall, when
        the data had such, and never deeper than wide: what hangs on a wall spans more
        along it than it stands out from it, and an observed size the other way round is
        a source box read a quarter turn off (1 of the 4 towel rails of the training
        rooms, 0.66 m out from its wall; 1 of 10 wall microwaves; 2 of 22 toilet paper
        holders), so it is turned. A category of :data:`DRAWN_BY_COUNT` draws each size
        as often as the objects of ``room_type`` had it (:meth:`weights`; among those
        ``fits`` accepts, by every room's counts when that room type had none of them);
        any other, its observed sizes evenly."""
        observed = self.observed(category, mounted)
        w = self.weights(category, room_type, mounted)
        if fits is not None:
            ok = fits(observed)
            if not ok.any():
                ok = np.arange(len(observed)) == np.argmin(observed[:, :2].prod(1))
            observed = observed[ok]
            if w is not None:
                w = w[ok] if w[ok].sum() > 0 else self.weights(category, None, mounted)[ok]
        if w is None or w.sum() <= 0:
            base = observed[int(rng.integers(len(observed)))]
        else:
            base = observed[int(rng.choice(len(observed), p=w / w.sum()))]
        size = base * np.exp(rng.normal(0.0, jitter, 3))
        return wider_than_deep(size) if mounted else size

    def footprint(self, category: str) -> float:
        """The median floor area (m2, width x depth) of ``category``'s observed sizes
        standing on something, weighted by every room's counts for a category of
        :data:`DRAWN_BY_COUNT` (its typical size's if the data has none): what a piece is
        counted on to cover before its size is drawn."""
        observed = self.observed(category)
        area = observed[:, 0] * observed[:, 1]
        w = self.weights(category)
        if w is None or w.sum() <= 0 or len(w) != len(area):
            return float(np.median(area))
        order = np.argsort(area, kind="stable")
        cumulative = np.cumsum(w[order]) / w.sum()
        return float(area[order][np.searchsorted(cumulative, 0.5)])

    def observed(self, category: str, mounted: bool = False) -> np.ndarray:
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
            "counts": {c: _whole(n) for c, n in self.counts.items()},
            "room_counts": {
                t: {c: _whole(n) for c, n in per.items()}
                for t, per in sorted(self.room_counts.items())
            },
        }
        return json.dumps(doc, separators=(",", ":")) + "\n"

    def save(self, path: str | Path) -> None:
        atomic_write_text(Path(path), self.to_json())

    @classmethod
    def load(cls, path: str | Path | None = None) -> SizeTable:
        """A table written by :meth:`save` (None: the bundled one); counts of a size the
        table has not, negative or not finite are a UserError."""
        doc = load_table("sizes", path)
        where = table_path("sizes") if path is None else path
        sizes = size_arrays(doc, where, "size table")
        out = cls(sizes)
        try:
            out.counts = _counts_of(doc.get("counts", {}), sizes)
            out.room_counts = {str(t): _counts_of(per, sizes)
                               for t, per in doc.get("room_counts", {}).items()}  # fmt: skip
        except (TypeError, ValueError, AttributeError) as e:
            raise UserError(f"{where}: malformed size table counts ({e})") from None
        return out


def _whole(counts: np.ndarray) -> list:
    """Counts for JSON: whole numbers as ints."""
    return [int(v) if float(v).is_integer() else float(v) for v in counts]


def _counts_of(doc: dict, sizes: dict[str, np.ndarray]) -> dict[str, np.ndarray]:
    """category -> (K,) counts of ``doc``, checked against ``sizes``' rows."""
    out = {}
    for cat, values in doc.items():
        counts = np.asarray(values, dtype=float)
        if cat not in sizes or counts.shape != (len(sizes[cat]),):
            raise ValueError(f"{cat}: {counts.size} counts for "
                             f"{len(sizes.get(cat, ()))} sizes")  # fmt: skip
        if not np.isfinite(counts).all() or (counts < 0).any():
            raise ValueError(f"{cat}: counts must be finite and not negative")
        out[cat] = counts
    return out


def read_size_arrays(table: str, path: str | Path | None, what: str) -> dict[str, np.ndarray]:
    """The ``sizes`` field of bundled table ``table`` (``rooms`` or ``sizes``), or of a
    user's file of that kind at ``path``: name -> (K, 3) finite positive sizes (m)."""
    path = table_path(table) if path is None else path
    return size_arrays(load_table(table, path), path, what)


def size_arrays(doc: dict, path: str | Path, what: str) -> dict[str, np.ndarray]:
    """:func:`read_size_arrays` of a document already read from ``path``."""
    try:
        sizes = {k: np.asarray(v, dtype=float).reshape(-1, 3) for k, v in doc["sizes"].items()}
    except (KeyError, TypeError, ValueError, AttributeError) as e:
        raise UserError(f"{path}: malformed {what} ({e})") from None
    if any((s <= 0).any() or not np.isfinite(s).all() for s in sizes.values()):
        raise UserError(f"{path}: sizes in the {what} must be finite and positive")
    return sizes

"""Which floor objects may stand over or under another's footprint.

Mesh collision lets a floor object stand partly under another's overhang, or over a low
one, wherever their parts miss each other: a side table under the edge of a dining
table's top, a lamp's base between an armchair's arm and its back, two oval tables one a
few centimetres above the other. Rooms are not furnished so. In the training rooms
two floor objects' footprints overlap (by more than
:data:`~pair2scene.curation.stats.FLOOR_OVERLAP_SHARE` of the smaller one's) almost only
for a chair tucked under its table or desk, and a plunger or brush by the toilet
(:attr:`~pair2scene.curation.stats.HierarchyStats.floor_overlaps`).

:class:`FloorOverlaps` keeps the category pairs the training rooms show overlapping at
least :data:`MIN_OVERLAPS` times. Placement tests each floor candidate against the placed
floor objects of every other pair (:meth:`FloorCheck.hits`), pushes one that overlaps them
clear of their footprints, as out of a collision, and rejects it when that does not do
(``overlap``)
(:attr:`~pair2scene.assembly.place.AssemblyConfig.separate_footprints`).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from pair2scene.curation.stats import (
    HierarchyStats,
    one_over_other,
    overlap_key,
)
from pair2scene.scene.geometry import OrientedBox
from pair2scene.scene.relations import footprint

MIN_OVERLAPS = 3
"""Overlapping pairs of two floor categories the training rooms must show for placement
to let them overlap: chairs under dining tables (691 pairs) and desks (19), plungers
(7) and brushes (6) by the toilet; the next pairs, twice each, are a toy under a table
or a box under a coffee table."""


@dataclass(frozen=True)
class FloorOverlaps:
    """The pairs of floor categories that may stand one over or under the other."""

    allowed: frozenset[str]
    """:func:`~pair2scene.curation.stats.overlap_key` of each such pair."""

    @classmethod
    def from_stats(
        cls, stats: HierarchyStats, min_overlaps: int = MIN_OVERLAPS
    ) -> FloorOverlaps | None:
        """The pairs ``stats`` counted overlapping at least ``min_overlaps`` times; None
        when the statistics did not count them (then no floor object is kept apart)."""
        if stats.floor_overlaps is None:
            return None
        return cls(frozenset(k for k, n in stats.floor_overlaps.items() if n >= min_overlaps))

    def allows(self, a: str, b: str) -> bool:
        """Whether floor objects of categories ``a`` and ``b`` may overlap."""
        return overlap_key(a, b) in self.allowed

    def check(self, category: str, placed: list[tuple[str, str, OrientedBox]]) -> FloorCheck:
        """The test of one floor object of ``category`` against the ``placed`` floor
        objects ((id, category, box)) it may not overlap."""
        return FloorCheck(
            [(oid, footprint(box)) for oid, cat, box in placed if not self.allows(category, cat)]
        )


class FloorCheck:
    """One floor object's test: the placed floor objects (id, footprint) whose footprint
    it may not overlap by more than
    :data:`~pair2scene.curation.stats.FLOOR_OVERLAP_SHARE` of the smaller one's
    area."""

    def __init__(self, others: list[tuple[str, np.ndarray]]) -> None:
        self.others = others
        # Their bounds, to pass over at once the footprints a candidate's bounds miss
        # (most of a dense room's): :func:`one_over_other` tests the bounds first too.
        corners = [theirs for _, theirs in others]
        self._lo = np.array([c.min(0) for c in corners]).reshape(-1, 2)
        self._hi = np.array([c.max(0) for c in corners]).reshape(-1, 2)

    def hits(self, box: OrientedBox) -> list[str]:
        """The ids of the objects ``box``'s footprint overlaps so."""
        if not self.others:
            return []
        mine = footprint(box)
        near = ~((self._lo > mine.max(0)) | (self._hi < mine.min(0))).any(axis=1)
        return [
            self.others[i][0]
            for i in np.flatnonzero(near)
            if one_over_other(mine, self.others[i][1])
        ]

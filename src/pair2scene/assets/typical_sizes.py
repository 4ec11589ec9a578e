"""The typical size of each asset category: a per-axis median measured on the corpora.

The table is bundled (``resources/typical_sizes.json``, read through
:func:`pair2scene.resources.load_table`); ``python tools/typical_sizes.py`` rewrites it
from the AI2-THOR and ProcTHOR corpora. Assets are previewed at these sizes (the
contact sheet), and object sizes fall back to them for a category no training room had.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import lru_cache

from pair2scene.resources import load_table

__all__ = ["GENERIC_SIZE", "TypicalSize", "asset_categories", "typical_size", "typical_sizes"]

GENERIC_SIZE = (0.3, 0.3, 0.3)
"""Size for a category missing from the table (a category added after the table was
written); the test suite checks that the table covers every category."""


@dataclass(frozen=True)
class TypicalSize:
    size: tuple[float, float, float]
    """Median full extent along local x, y, z (metres)."""
    source: str
    """``ai2thor``, ``procthor``, ``hand`` or ``default`` (not in the table)."""
    count: int
    """Objects the median was taken over (0 for hand sizes)."""


def asset_categories() -> list[str]:
    """Every canonical category that is not a room feature (structure), in table order."""
    from pair2scene.categories import CATEGORIES, is_structure

    return [c.name for c in CATEGORIES if not is_structure(c.name)]


@lru_cache(maxsize=1)
def typical_sizes() -> dict[str, TypicalSize]:
    """The bundled typical-size table, category -> :class:`TypicalSize` (read once)."""
    doc = load_table("typical_sizes")
    return {
        k: TypicalSize(tuple(float(x) for x in v["size"]), v["source"], int(v["count"]))
        for k, v in doc["sizes"].items()
    }


def typical_size(category: str) -> TypicalSize:
    """The typical size of ``category`` (``GENERIC_SIZE`` when the table lacks it)."""
    return typical_sizes().get(category, TypicalSize(GENERIC_SIZE, "default", 0))

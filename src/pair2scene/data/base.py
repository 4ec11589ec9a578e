"""What every source adapter returns: scenes plus a report of what it saw."""

from __future__ import annotations

import hashlib
from collections import Counter
from dataclasses import dataclass, field

from pair2scene.scene.model import Scene

SPLITS = ("train", "val")


@dataclass
class SourceReport:
    """Counts an adapter keeps while reading a source; nothing is dropped silently."""

    unknown_labels: Counter[str] = field(default_factory=Counter)
    """Source labels with no canonical category (objects kept as ``unknown``)."""
    mapped_labels: Counter[str] = field(default_factory=Counter)
    """Source labels that mapped to a canonical category, with their counts."""
    room_features: Counter[str] = field(default_factory=Counter)
    """Structural objects turned into room features (floor, windows, switches...)."""
    warnings: Counter[str] = field(default_factory=Counter)
    """Recoverable problems, e.g. ``no size for asset`` or ``missing model_info entry``."""

    def merge(self, other: SourceReport) -> None:
        self.unknown_labels.update(other.unknown_labels)
        self.mapped_labels.update(other.mapped_labels)
        self.room_features.update(other.room_features)
        self.warnings.update(other.warnings)


@dataclass
class Corpus:
    source: str
    scenes: list[Scene]
    report: SourceReport


def stable_fraction(key: str) -> float:
    """A number in [0, 1) fixed by ``key`` alone (for deterministic splits)."""
    digest = hashlib.sha256(key.encode()).digest()
    return int.from_bytes(digest[:8], "big") / 2**64

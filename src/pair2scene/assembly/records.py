"""What placement records about objects it did not place where the hierarchy said."""

from __future__ import annotations

from dataclasses import dataclass


@dataclass(frozen=True)
class Dropped:
    """An object left out of the scene, and why (``no free surface: dresser_0 is full``,
    ``its support bed_0 was dropped``, rejections by cause, ``physics: ...``)."""

    id: str
    category: str
    reason: str

    def to_dict(self) -> dict:
        return {"id": self.id, "category": self.category, "reason": self.reason}


@dataclass(frozen=True)
class Moved:
    """An object moved off a full support to another one before placement."""

    id: str
    source: str
    """The support the hierarchy gave it."""
    target: str
    """The support it was moved to."""

    def to_dict(self) -> dict:
        return {"id": self.id, "from": self.source, "to": self.target}

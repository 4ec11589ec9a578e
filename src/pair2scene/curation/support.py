"""Heuristic support extraction (being written). Interface fixed here."""

from __future__ import annotations

from dataclasses import dataclass

from pair2scene.scene.model import Scene


@dataclass(frozen=True)
class SupportScores:
    precision: float
    recall: float
    f1: float
    n_true: int
    n_pred: int
    n_correct: int


def extract_support(scene: Scene, library=None) -> Scene:
    """A copy of ``scene`` whose objects' ``support`` is found from geometry alone
    (``source_support`` is left as the source gave it)."""
    raise NotImplementedError("being written")


def support_scores(scenes: list[Scene]) -> SupportScores:
    """Precision/recall/F1 of ``support`` against the sources' own annotation."""
    raise NotImplementedError("being written")

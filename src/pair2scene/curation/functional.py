"""Functional relation distillation (being written). Interface fixed here."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Protocol

from pair2scene.scene.geometry import OrientedBox
from pair2scene.scene.model import Scene, SceneObject


@dataclass(frozen=True)
class Proposal:
    anchor: str
    """Object id of the functional anchor."""
    dependent: str
    k: float
    """Expansion of the anchor's box (metres) for the k-check."""


class Proposer(Protocol):
    def propose(self, scene: Scene, support: str, group: list[SceneObject]) -> list[Proposal]:
        """Proposals among ``group``: the objects resting on the support ``support``."""
        ...


def k_check(anchor: OrientedBox, dependent: OrientedBox, k: float) -> bool:
    """True when the dependent's centroid lies in the anchor's box expanded by k."""
    raise NotImplementedError("being written")


def distill_functional(scene: Scene, proposer: Proposer, use_k_check: bool = True) -> Scene:
    """A copy of ``scene`` with ``functional_anchor`` set from the proposer's pairs."""
    raise NotImplementedError("being written")

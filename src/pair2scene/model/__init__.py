"""The learned layout model: geometry encoder, layout predictor, mixture-of-logistics head.

``from_pretrained()`` loads the bundled default model (or a checkpoint folder); torch is
imported only then.
"""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING

if TYPE_CHECKING:
    from pair2scene.model.api import LayoutModel


def from_pretrained(path: str | Path | None = None, device: str = "cpu") -> LayoutModel:
    """The layout model in checkpoint folder ``path``; None: the bundled default."""
    from pair2scene.model.api import LayoutModel

    return LayoutModel.from_pretrained(path, device)


__all__ = ["from_pretrained"]

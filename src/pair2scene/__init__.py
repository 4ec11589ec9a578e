"""pair2scene: dense, physically plausible 3D indoor scenes from pairwise placement rules.

``Pair2Scene.from_pretrained().generate(room="bedroom", seed=0)`` gives a scene; torch and
the model load only when it is first used.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

__version__ = "0.1.0"

if TYPE_CHECKING:
    from pair2scene.generate import Pair2Scene


def __getattr__(name: str):
    if name == "Pair2Scene":
        from pair2scene.generate import Pair2Scene

        return Pair2Scene
    raise AttributeError(f"module 'pair2scene' has no attribute {name!r}")


__all__ = ["Pair2Scene", "__version__"]

"""Physical validation with MuJoCo (being written). Interface fixed here."""

from __future__ import annotations

from dataclasses import dataclass, field

from pair2scene.scene.model import Scene


@dataclass(frozen=True)
class PhysicsConfig:
    max_translation_m: float = 0.05
    """An object that moves more than this under gravity is dropped."""
    max_rotation_deg: float = 10.0
    """... or turns more than this."""
    settle_seconds: float = 1.0


@dataclass
class PhysicsOutcome:
    scene: Scene
    """The scene without the dropped objects (and their dependents)."""
    dropped: dict[str, str] = field(default_factory=dict)
    """object id -> reason ("moved 0.12 m", "rotated 34 deg", "rests on dropped sofa_0")."""
    motion: dict[str, tuple[float, float]] = field(default_factory=dict)
    """object id -> (translation m, rotation deg) measured in the simulation."""
    seconds: float = 0.0


def validate_physics(scene: Scene, library=None, config: PhysicsConfig = PhysicsConfig()
                     ) -> PhysicsOutcome:
    """Simulate ``scene`` under gravity and drop what does not stay put (with dependents)."""
    raise NotImplementedError("being written")

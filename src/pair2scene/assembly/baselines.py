"""Placement models without the learned network, for baselines: same interface, same path.

Both classes are :class:`~pair2scene.model.api.PlacementModel` s, as the learned model
is: ``draw(query, n, temperature, generator)`` gives (n, 12) world box vectors (centre,
size, 6D) and None (neither confines its draws to ``query.region``), so
:class:`~pair2scene.assembly.place.Placer` runs them through the very rejection sampling
and gravity the learned model gets; only where the candidates come from differs.

* :class:`GaussianPlacement`: the per-pair Gaussian baseline
  (:class:`~pair2scene.model.baseline.GaussianBaseline`) as a sampler: its mixture for the
  query's category key, conditioned on the dependent's size, drawn in the frame the
  learned model would draw in (with the baseline's ``anchor_frames``, the default: the
  wall a floor object is to stand against, else its functional anchor's footprint, else
  its support; :func:`~pair2scene.model.baseline.frame_choice`) and mapped back to the
  world.
* :class:`RandomPlacement`: nothing learned, the null model: anywhere in the room (floor
  objects) or over the support's footprint (supported ones), at any yaw. It goes through
  no anchor frame on purpose (``query.wall`` and ``query.functional`` are ignored): a
  uniform draw in a wall's frame would already know that the object stands at a wall.

Each call seeds a numpy generator with one integer drawn from the placement's
``generator``, so the placer's seed decides every draw (same seed, same scene) and
successive objects of a scene draw different numbers.
"""

from __future__ import annotations

from abc import abstractmethod
from pathlib import Path

import numpy as np

from pair2scene.errors import UserError
from pair2scene.model.api import PlacementModel, PlacementQuery, canonical_to_world
from pair2scene.model.baseline import (
    GaussianBaseline,
    GaussianConfig,
    GaussianMixture,
    frame_key,
)
from pair2scene.scene.geometry import OrientedBox

_EPS = 1e-9
"""The floor :meth:`OrientedBox.in_frame_of` puts under a support's half-size."""


def numpy_rng(generator: np.random.Generator | None) -> np.random.Generator:
    """A generator seeded by one draw from ``generator`` (an unseeded one when None), so
    that the seed of a placement decides the baselines' draws too."""
    seed = int((generator or np.random.default_rng()).integers(0, 2**62))
    return np.random.default_rng(seed)


class _Sampler(PlacementModel):
    """A placement model from a ``sample(query, n, temperature, generator)`` that draws
    over the whole support and knows nothing of ``query.region``."""

    def draw(
        self,
        query: PlacementQuery,
        n: int,
        temperature: float,
        generator: np.random.Generator | None,
    ) -> tuple[np.ndarray, None]:
        """:meth:`sample`'s candidates (of the query's size); None: no region mass."""
        return self.sample(query, n, temperature, generator), None

    @abstractmethod
    def sample(
        self,
        query: PlacementQuery,
        n: int,
        temperature: float,
        generator: np.random.Generator | None,
    ) -> np.ndarray:
        """``n`` candidate world boxes (n, 12) (centre, size, 6D) for one query."""


class GaussianPlacement(_Sampler):
    """The Gaussian baseline as a placement model (see the module docstring).

    The temperature acts as in the learned model's sampler: component weights to the power
    1/T, covariances times T^2 (:meth:`GaussianMixture.sample`).
    """

    honours_temperature = True

    def __init__(self, baseline: GaussianBaseline) -> None:
        self.baseline = baseline
        self.draws_in_frames = baseline.config.anchor_frames
        self._mixtures: dict[tuple[str, str, str], GaussianMixture] = {}

    @classmethod
    def from_spec(cls, path: str | Path, config: GaussianConfig | None = None):
        """A saved baseline JSON (:meth:`GaussianBaseline.save`), or a 3D-Pairs folder to fit
        one on (its train split, with ``config``, default :class:`GaussianConfig`: anchor
        frames on; a few seconds)."""
        from pair2scene.curation.dataset import load_pairs

        path = Path(path)
        if path.is_dir():
            return cls(GaussianBaseline.fit(load_pairs(path), "train", config))
        if not path.exists():
            raise UserError(f"{path}: no such file or folder (a 3D-Pairs folder or a baseline)")
        return cls(GaussianBaseline.load(path))

    def frame(self, query: PlacementQuery) -> tuple[int, OrientedBox]:
        """(frame kind, frame box) ``query`` is drawn in: the learned model's choice
        (:meth:`LayoutModel.frame <pair2scene.model.api.LayoutModel.frame>`) when the
        baseline was fitted with anchor frames, else its support's box."""
        sup = query.support
        func = None if query.functional is None else query.functional.box
        return self.baseline.frame_for(sup.box, sup.is_floor, query.wall, func)

    def sample(
        self,
        query: PlacementQuery,
        n: int = 256,
        temperature: float = 1.0,
        generator: np.random.Generator | None = None,
        keep_size: bool = True,
    ) -> np.ndarray:
        """``n`` candidate world boxes (n, 12) for one query; ``keep_size`` conditions on
        the query's size (every candidate has it), False draws the size too. Drawn in
        :meth:`frame`'s box and mapped back to the world."""
        kind, frame = self.frame(query)
        key = (
            query.category,
            frame_key(query.support.category, kind),
            "" if query.functional is None else query.functional.category,
        )
        mix = self._mixtures.get(key)
        if mix is None:
            mix = self._mixtures[key] = self.baseline.mixture_for(*key)
        size = None
        if keep_size:
            size = np.asarray(query.size, dtype=np.float64) / np.maximum(frame.half_size, _EPS)
        rng = numpy_rng(generator)
        canonical = self.baseline.sample_arrays(*key, n, rng, size, temperature, mixture=mix)
        out = canonical_to_world(canonical, frame)
        if keep_size:  # exactly the asset's size, not half * (size / half)
            out[:, 3:6] = np.asarray(query.size, dtype=np.float64)
        return out


class RandomPlacement(_Sampler):
    """Uniform placement, nothing learned: the null model, the baseline that shows what the
    rules and the rejection sampling alone give. It stays uniform over the room or the
    support whatever anchors the query names (``query.wall`` and ``query.functional`` are
    ignored, unlike the learned model's and the Gaussian's anchor frames): drawing in a
    wall's frame would already put the object at the wall.

    Floor objects: centre uniform over the room's bounds (narrowed by the drawn footprint's
    extent, so candidates are not wasted on walls), standing on the floor. Supported
    objects: centre uniform over the support box's footprint, the bottom at a uniform height
    between the support's bottom and top: the placer drops each onto the surface nearest
    below it, so every tier of a shelf gets objects, a table only its top. Yaw uniform in
    [0, 2 pi) (the placer snaps one near the walls' or the support's axes onto them, as
    it does the learned model's). Uniform draws have no modes to sharpen: the temperature
    changes nothing (``honours_temperature`` is False and generation notes it).
    """

    honours_temperature = False
    draws_in_frames = False

    def sample(
        self,
        query: PlacementQuery,
        n: int = 256,
        temperature: float = 1.0,
        generator: np.random.Generator | None = None,
    ) -> np.ndarray:
        """``n`` candidate world boxes (n, 12) (centre, size, 6D) for one query."""
        del temperature  # nothing to sharpen
        rng = numpy_rng(generator)
        size = np.asarray(query.size, dtype=np.float64)
        sup = query.support.box
        yaw = rng.uniform(0.0, 2 * np.pi, n)
        cos, sin = np.cos(yaw), np.sin(yaw)
        u = rng.uniform(-1.0, 1.0, (n, 2))
        h = rng.uniform(0.0, 1.0, n)
        center = np.empty((n, 3))
        if query.support.is_floor:
            # half extent of each drawn footprint along x and y (the room is axis-aligned)
            ext = 0.5 * np.stack(
                [np.abs(cos) * size[0] + np.abs(sin) * size[1],
                 np.abs(sin) * size[0] + np.abs(cos) * size[1]], axis=1
            )  # fmt: skip
            room_half = sup.half_size[:2]
            span = np.maximum(room_half - ext, 0.0)
            center[:, :2] = sup.center[:2] + u * span
            center[:, 2] = sup.center[2] - sup.half_size[2] + size[2] / 2
            rot_cols = np.stack([cos, sin, np.zeros(n), -sin, cos, np.zeros(n)], axis=1)
        else:
            half = sup.half_size
            local = np.column_stack([u * half[:2], -half[2] + h * 2 * half[2]])
            center = local @ sup.rotation.T + sup.center
            center[:, 2] += size[2] / 2  # ``local`` is where the bottom goes
            # yaw about the support's up axis, in the support's frame
            c0 = np.stack([cos, sin, np.zeros(n)], axis=1) @ sup.rotation.T
            c1 = np.stack([-sin, cos, np.zeros(n)], axis=1) @ sup.rotation.T
            rot_cols = np.concatenate([c0, c1], axis=1)
        return np.concatenate([center, np.broadcast_to(size, (n, 3)), rot_cols], axis=1)

"""Every placement model answers the same call."""

from __future__ import annotations

import numpy as np

from pair2scene.assembly.baselines import RandomPlacement
from pair2scene.model.api import Anchor, LayoutModel, PlacementModel, PlacementQuery
from pair2scene.scene.geometry import OrientedBox


def test_the_models_are_placement_models():
    assert isinstance(RandomPlacement(), PlacementModel)
    assert LayoutModel.honours_temperature and not RandomPlacement.honours_temperature
    assert isinstance(object.__new__(LayoutModel), PlacementModel)  # (no checkpoint needed)


def test_random_draws_have_the_query_size_and_no_region_mass():
    room = OrientedBox.from_yaw([2.0, 2.0, 1.35], [4.0, 4.0, 2.7], 0.0)
    query = PlacementQuery("dresser", [1.0, 0.5, 0.8], Anchor.floor(room))
    boxes, mass = RandomPlacement().draw(query, 16, 1.0, np.random.default_rng(0))
    assert boxes.shape == (16, 12) and mass is None
    assert np.allclose(boxes[:, 3:6], [1.0, 0.5, 0.8])

"""Gravity: resting on the right surface (shelf tiers), rejecting overhangs, the floor."""

from __future__ import annotations

import numpy as np
import pytest

from pair2scene.assembly.rest import dropped, footprint, on_floor, rest_on_surfaces
from pair2scene.assets.registry import generate
from pair2scene.scene.geometry import OrientedBox, rot_x


@pytest.fixture(scope="module")
def bookcase():
    size = (0.9, 0.35, 1.6)
    asset = generate("shelving_unit", size, 0, support_heights=[0.02, 0.42, 0.82, 1.22])
    return asset, OrientedBox.from_yaw([2.0, 1.0, 0.8], size, np.pi / 2)


def book_at(x, y, bottom):
    return OrientedBox.from_yaw([x, y, bottom + 0.12], [0.05, 0.2, 0.24], np.pi / 2)


def test_lands_on_the_predicted_tier(bookcase):
    asset, box = bookcase
    for tier in (0.42, 0.82, 1.22):
        z = rest_on_surfaces(asset, box, book_at(2.0, 1.0, tier + 0.03))
        assert z == pytest.approx(tier, abs=2e-3)
    top = rest_on_surfaces(asset, box, book_at(2.0, 1.0, 1.65))
    assert top == pytest.approx(1.6, abs=2e-3)


def test_overhang_and_off_the_support_are_rejected(bookcase):
    asset, box = bookcase
    assert rest_on_surfaces(asset, box, book_at(2.0, 1.6, 1.65)) is None  # beside it
    assert rest_on_surfaces(asset, box, book_at(2.0, 1.45, 1.65)) is None  # half off the top
    assert rest_on_surfaces(asset, box, book_at(2.0, 1.4, 1.65)) is not None  # near the edge
    tilted = OrientedBox(box.center, box.size, rot_x(0.3))
    assert rest_on_surfaces(asset, tilted, book_at(2.0, 1.0, 1.65)) is None


def test_mug_on_a_table_and_the_floor():
    table = generate("dining_table", [1.2, 0.8, 0.75], 0)
    tbox = OrientedBox.from_yaw([1.0, 1.0, 0.375], [1.2, 0.8, 0.75])
    mug = OrientedBox.from_yaw([1.2, 0.9, 0.9], [0.1, 0.1, 0.1])
    z = rest_on_surfaces(table, tbox, mug)
    assert z == pytest.approx(0.75, abs=2e-3)
    assert dropped(mug, z).bottom == pytest.approx(z)
    square = np.array([[0, 0], [3, 0], [3, 3], [0, 3]], float)
    assert on_floor(OrientedBox.from_yaw([1.5, 1.5, 0.4], [1, 1, 0.8]), square)
    assert not on_floor(OrientedBox.from_yaw([2.8, 1.5, 0.4], [1, 1, 0.8]), square)
    assert footprint(mug).shape == (5, 2)

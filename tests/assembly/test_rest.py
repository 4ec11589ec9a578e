"""Gravity: resting on the right surface (shelf tiers), rejecting overhangs, the floor."""

from __future__ import annotations

import numpy as np
import pytest

from pair2scene.assembly.rest import (
    contact_rectangle,
    dropped,
    footprint,
    into_room,
    on_floor,
    rest_on_surfaces,
)
from pair2scene.assets.registry import generate
from pair2scene.assets.surfaces import surfaces_of
from pair2scene.scene.geometry import OrientedBox, points_in_polygon, rot_x


@pytest.fixture(scope="module")
def bookcase():
    size = (0.9, 0.35, 1.6)
    asset = generate("shelving_unit", size, 0, support_heights=[0.02, 0.42, 0.82, 1.22])
    return asset, OrientedBox.from_yaw([2.0, 1.0, 0.8], size, np.pi / 2)


def rest_z(*args, **kwargs):
    rest = rest_on_surfaces(*args, **kwargs)
    return None if rest is None else rest[0]


def book_at(x, y, bottom):
    return OrientedBox.from_yaw([x, y, bottom + 0.12], [0.05, 0.2, 0.24], np.pi / 2)


def test_lands_on_the_predicted_tier(bookcase):
    asset, box = bookcase
    for tier in (0.42, 0.82, 1.22):
        z = rest_z(asset, box, book_at(2.0, 1.0, tier + 0.03))
        assert z == pytest.approx(tier, abs=2e-3)
    top = rest_z(asset, box, book_at(2.0, 1.0, 1.65))
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
    z = rest_z(table, tbox, mug)
    assert z == pytest.approx(0.75, abs=2e-3)
    assert dropped(mug, z).bottom == pytest.approx(z)
    square = np.array([[0, 0], [3, 0], [3, 3], [0, 3]], float)
    assert on_floor(OrientedBox.from_yaw([1.5, 1.5, 0.4], [1, 1, 0.8]), square)
    assert not on_floor(OrientedBox.from_yaw([2.8, 1.5, 0.4], [1, 1, 0.8]), square)
    assert footprint(mug).shape == (5, 2)


def test_a_screen_wider_than_its_stand_stands_on_its_foot():
    stand = generate("tv_stand", [0.98, 0.45, 0.6], 0)
    sbox = OrientedBox.from_yaw([2.0, 1.0, 0.3], [0.98, 0.45, 0.6])
    tv = generate("television", [1.3, 0.3, 0.8], 0, style=0)  # a screen on a central foot
    contact = contact_rectangle(tv)
    assert (contact.max(0) - contact.min(0))[0] < 0.98  # its foot, not the screen
    screen = OrientedBox.from_yaw([2.0, 1.0, 1.05], tv.size)
    assert rest_on_surfaces(stand, sbox, screen) is None  # judged by its box: hangs off
    z, shift = rest_on_surfaces(stand, sbox, screen, contact=contact)
    assert z == pytest.approx(0.6, abs=2e-3) and not shift.any()


def test_a_small_overhang_is_nudged_back_within_max_shift():
    table = generate("dining_table", [1.2, 0.8, 0.75], 0)
    tbox = OrientedBox.from_yaw([1.0, 1.0, 0.375], [1.2, 0.8, 0.75])
    mug = OrientedBox.from_yaw([1.62, 1.0, 0.8], [0.1, 0.1, 0.1])  # centre off the edge
    assert rest_on_surfaces(table, tbox, mug) is None
    z, shift = rest_on_surfaces(table, tbox, mug, max_shift=0.1)
    assert z == pytest.approx(0.75, abs=2e-3)
    assert -0.1 <= shift[0] <= -0.07 and shift[1] == pytest.approx(0.0)
    moved = OrientedBox.from_yaw([1.62 + shift[0], 1.0 + shift[1], 0.8], [0.1, 0.1, 0.1])
    assert moved.center[0] + 0.05 <= 1.6 + 1e-6  # now on the top
    assert rest_on_surfaces(table, tbox, mug, max_shift=0.03) is None  # too far to nudge


def test_into_room_moves_in_and_against_the_wall():
    square = np.array([[0, 0], [4, 0], [4, 3], [0, 3]], float)
    inside = OrientedBox.from_yaw([2.0, 1.5, 0.4], [1, 1, 0.8])
    assert into_room(inside, square, 0.3, 0.1) is inside  # nothing to do
    through = OrientedBox.from_yaw([3.7, 1.5, 0.4], [1, 1, 0.8])  # 0.2 m through the wall
    fixed = into_room(through, square, 0.3, 0.0)
    assert fixed.center[0] == pytest.approx(3.499) and on_floor(fixed, square)
    assert into_room(through, square, 0.1, 0.0) is None
    near = OrientedBox.from_yaw([0.58, 1.5, 0.4], [1, 1, 0.8])  # 8 cm off the wall
    assert into_room(near, square, 0.0, 0.1).center[0] == pytest.approx(0.5)
    assert into_room(near, square, 0.0, 0.05) is near


def test_a_fridge_holds_its_eggs_on_its_shelves_not_on_its_roof():
    """``top=False`` (a support whose top holds nothing in the data): an egg drawn at the
    fridge's roof height rests on the highest shelf inside instead; a support with no
    surface below its top still carries it on the top."""
    size = (0.8, 0.75, 1.8)
    fridge = generate("fridge", size, rng=0)
    at = OrientedBox.from_yaw([1.0, 2.0, size[2] / 2], size, 0.3)
    egg = OrientedBox.from_yaw([1.0, 2.0, size[2] + 0.05], [0.05, 0.05, 0.07], 0.0)
    z_top, _ = rest_on_surfaces(fridge, at, egg)
    assert z_top == pytest.approx(size[2], abs=1e-3)
    z_in, _ = rest_on_surfaces(fridge, at, egg, top=False)
    inner = sorted(s.z + size[2] / 2 for s in surfaces_of(fridge) if s.z < size[2] / 2 - 0.05)
    assert z_in == pytest.approx(inner[-1], abs=1e-3)  # the nearest shelf below the roof
    block_size = (0.8, 0.6, 0.45)  # a counter block: its top is its only surface
    block = generate("counter_top", block_size, rng=0)
    bb = OrientedBox.from_yaw([0.0, 0.0, 0.225], block_size, 0.0)
    mug = OrientedBox.from_yaw([0.0, 0.0, 0.5], [0.1, 0.08, 0.1], 0.0)
    assert rest_on_surfaces(block, bb, mug, top=False)[0] == pytest.approx(0.45, abs=1e-3)


def test_into_an_l_shaped_room_means_inside_its_floor_not_its_bounds():
    """A box inside the bounds of an L-shaped floor but in its missing corner is not in
    the room (it was let through when no shift was needed)."""
    floor = np.array([[3.3, 0.0], [3.3, 6.6], [0.0, 6.6], [0.0, 3.3], [1.65, 3.3], [1.65, 0.0]])
    corner = OrientedBox.from_yaw([0.8, 1.0, 0.45], [0.8, 0.5, 0.9], 0.0)
    assert not on_floor(corner, floor)
    assert into_room(corner, floor) is None
    assert into_room(corner, floor, max_shift=0.3, snap=0.2) is None
    arm = OrientedBox.from_yaw([2.4, 1.0, 0.45], [0.8, 0.5, 0.9], 0.0)
    assert into_room(arm, floor) is arm
    near = OrientedBox.from_yaw([1.2, 1.0, 0.45], [0.8, 0.5, 0.9], 0.0)  # 0.05 m over
    moved = into_room(near, floor, max_shift=0.1)
    assert moved is None or on_floor(moved, floor)


def test_the_inner_corner_of_an_l_reaching_into_a_turned_box_leaves_it_outside():
    """A chair turned 26 degrees by the inner corner of an L-shaped kitchen (seed 29 of a
    fit kitchen, the first time floor objects stood turned): its four corners stand in
    the room, but the floor's corner (1.67, 3.34) lies inside its footprint, so it reaches
    through the wall (the simulation pushed it 22 cm). Turned square, or moved off the
    corner, it stands in the room."""
    floor = np.array([[0, 0], [3.34, 0], [3.34, 6.69], [1.67, 6.69], [1.67, 3.34], [0, 3.34]])
    chair = OrientedBox.from_yaw([1.587, 3.13, 0.52], [0.451, 0.535, 1.043], np.radians(-63.8))
    assert points_in_polygon(footprint(chair)[1:], floor).all()
    assert not on_floor(chair, floor)
    assert into_room(chair, floor) is None
    square = OrientedBox.from_yaw([1.587, 3.0, 0.52], [0.451, 0.535, 1.043], np.radians(-90))
    away = OrientedBox.from_yaw([2.5, 2.0, 0.52], [0.451, 0.535, 1.043], np.radians(-63.8))
    assert on_floor(square, floor) and on_floor(away, floor)

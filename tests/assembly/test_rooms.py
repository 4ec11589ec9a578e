"""Rooms to generate into: training sizes per type, a door on a wall, file errors."""

from __future__ import annotations

import numpy as np
import pytest

from pair2scene.assembly.rooms import DOOR_WIDTH_M, RoomTable, make_room
from pair2scene.curation.dataset import load_pairs
from pair2scene.errors import UserError
from synthetic_pairs import write_synthetic_pairs


def test_table_from_pairs_and_rooms(tmp_path):
    table = RoomTable.from_pairs(load_pairs(write_synthetic_pairs(tmp_path / "p")))
    assert set(table.sizes) == {"bedroom"} and table.sizes["bedroom"].shape[1] == 3
    table.save(tmp_path / "rooms.json")
    table = RoomTable.load(tmp_path / "rooms.json")
    for seed in range(20):
        room = make_room("bedroom", np.random.default_rng(seed), table)
        w, d = room.floor_polygon.max(0)
        assert (w, d) == pytest.approx((5.0, 4.0))
        (door,) = room.doors
        p0, p1 = np.array(door.p0), np.array(door.p1)
        assert np.linalg.norm(p1 - p0) == pytest.approx(DOOR_WIDTH_M)
        on_wall = [np.isclose(p0[0], 0) and np.isclose(p1[0], 0), np.isclose(p0[1], 0)
                   and np.isclose(p1[1], 0), np.isclose(p0[0], w) and np.isclose(p1[0], w),
                   np.isclose(p0[1], d) and np.isclose(p1[1], d)]  # fmt: skip
        assert any(on_wall)
    kitchen = make_room("kitchen", np.random.default_rng(0), table)  # unseen: any size
    assert kitchen.type == "kitchen" and kitchen.area == pytest.approx(20.0)


def test_bundled_table_and_errors(tmp_path):
    table = RoomTable.load()
    assert {"bedroom", "living_room", "kitchen", "bathroom"} <= set(table.sizes)
    assert 2.0 < table.sizes["bedroom"][:, :2].mean() < 9.0
    bad = tmp_path / "bad.json"
    bad.write_text('{"format": "pair2scene.rooms", "version": 1, "sizes": {"x": [[0, 1, 2]]}}')
    with pytest.raises(UserError, match="finite and positive"):
        RoomTable.load(bad)


def test_rooms_are_drawn_large_enough_for_their_furniture():
    from pair2scene.assembly.rooms import MAX_FLOOR_SHARE

    sizes = np.array([[3.0, 3.0, 2.5], [5.0, 4.0, 2.5], [8.0, 6.0, 2.5]])
    table = RoomTable({"bedroom": sizes})
    free = {make_room("bedroom", np.random.default_rng(s), table).area for s in range(40)}
    assert free == {9.0, 20.0, 48.0}  # no furniture: any training room
    need = 8.0 * MAX_FLOOR_SHARE * 1.5  # more than 40 % of 9 m2, less than of 20 m2
    drawn = {make_room("bedroom", np.random.default_rng(s), table, need).area for s in range(40)}
    assert drawn == {20.0, 48.0}
    huge = make_room("bedroom", np.random.default_rng(0), table, 100.0)
    assert huge.area == pytest.approx(48.0)  # none is large enough: the largest

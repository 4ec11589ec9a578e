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


def test_windows_are_drawn_as_the_statistics_have_them():
    """Counts and shapes from the room type's statistics; each window on a wall, clear of
    the corners, the door and the other windows, under the ceiling."""
    from collections import Counter

    from pair2scene.assembly.rooms import WINDOW_CORNER_GAP_M, WINDOW_GAP_M, draw_windows
    from pair2scene.curation.stats import RoomTypeStats
    from pair2scene.scene.walls import walls_of

    rs = RoomTypeStats()
    rs.window_counts = Counter({0: 1, 1: 2, 2: 1})
    rs.window_shapes = Counter({(1.2, 0.9, 2.1): 1, (2.4, 0.5, 3.5): 1})  # the 2nd too tall
    tall = 0
    counts = []
    for seed in range(200):
        room = make_room("bedroom", np.random.default_rng(seed), stats=rs)
        plain = make_room("bedroom", np.random.default_rng(seed))
        assert np.allclose(room.floor_polygon, plain.floor_polygon)
        assert room.doors == plain.doors and plain.windows == ()  # drawn after the rest
        counts.append(len(room.windows))
        walls = walls_of(room.floor_polygon)
        spans = {}
        for o in (*room.doors, *room.windows):
            on = [w for w in walls if np.abs(w.local(np.array([o.p0, o.p1]))[:, 1]).max() < 1e-6]
            assert len(on) == 1, o
            x = np.sort(on[0].local(np.array([o.p0, o.p1]))[:, 0])
            spans.setdefault(on[0].index, []).append((x, o.kind))
            if o.kind == "window":
                assert abs(x[1]) <= on[0].length / 2 - WINDOW_CORNER_GAP_M + 1e-6
                assert 0.0 <= o.z_min < o.z_max <= room.height - 0.1 + 1e-9
                assert o.width in (pytest.approx(1.2), pytest.approx(2.4))
                if o.width > 2:  # moved down under the ceiling, its sill at most to the floor
                    tall += 1
                    assert o.z_max == pytest.approx(min(3.5, room.height - 0.1))
                    assert o.z_min == pytest.approx(max(0.5 - (3.5 - o.z_max), 0.0))
        for items in spans.values():
            items.sort(key=lambda t: t[0][0])
            for (a, _), (b, _) in zip(items, items[1:]):
                assert b[0] - a[1] >= WINDOW_GAP_M - 1e-6
    assert np.mean(counts) == pytest.approx(1.0, abs=0.15)  # (0 + 2 + 2) / 4
    assert 0.35 < tall / sum(counts) < 0.65
    assert (
        draw_windows(
            np.array([[0, 0], [1, 0], [1, 1], [0, 1]], float),
            2.7,
            (),
            rs.window_counts,
            rs.window_shapes,
            np.random.default_rng(0),
        )
        == ()
    )


def test_a_text_dressing_every_window_gets_exactly_that_many():
    """``min_windows``/``max_windows``: a room for "curtains on the windows" (two) holds
    two windows, whatever count the statistics draw; the shape and door are unchanged."""
    from collections import Counter

    from pair2scene.curation.stats import RoomTypeStats

    rs = RoomTypeStats()
    rs.window_counts = Counter({0: 1, 1: 1, 3: 2})
    rs.window_shapes = Counter({(1.0, 0.9, 2.1): 1})
    drawn = set()
    for seed in range(40):
        free = make_room("living_room", np.random.default_rng(seed), stats=rs)
        exact = make_room("living_room", np.random.default_rng(seed), stats=rs,
                          min_windows=2, max_windows=2)  # fmt: skip
        drawn.add(len(free.windows))
        assert len(exact.windows) == 2 and exact.doors == free.doors
        assert np.allclose(exact.floor_polygon, free.floor_polygon)
    assert drawn == {0, 1, 3}


L_SHAPE = (2.6, 0.0, 0.0, 5.0, 0.0, 5.0, 2.0, 2.0, 2.0, 2.0, 4.0, 0.0, 4.0)
"""(height, x0, y0, ...): an L-shaped room, 5 x 4 m less a 3 x 2 m corner (14 m2)."""


def test_rooms_take_the_training_rooms_shapes():
    """With floor shapes in the statistics, rooms are training rooms' polygons (L-shapes
    too), turned a quarter turn at random, their door on a wall long enough for it."""
    from collections import Counter

    from pair2scene.curation.stats import RoomTypeStats
    from pair2scene.scene.walls import walls_of

    rs = RoomTypeStats()
    rs.floor_shapes = Counter({L_SHAPE: 3, (2.5, 0.0, 0.0, 3.0, 0.0, 3.0, 3.0, 0.0, 3.0): 1})
    shapes, heights, turns = Counter(), set(), set()
    for seed in range(60):
        room = make_room("bedroom", np.random.default_rng(seed), stats=rs)
        again = make_room("bedroom", np.random.default_rng(seed), stats=rs)
        assert np.array_equal(room.floor_polygon, again.floor_polygon)  # same seed, same room
        assert room.floor_polygon.min(0) == pytest.approx((0.0, 0.0))
        shapes[len(room.floor_polygon)] += 1
        heights.add(room.height)
        if len(room.floor_polygon) == 6:
            assert room.area == pytest.approx(14.0)
            assert room.height == 2.6
            # where the missing corner went: one of four quarter turns
            w, d = room.floor_polygon.max(0)
            corners = {(0.0, 0.0), (w, 0.0), (w, d), (0.0, d)}
            (missing,) = corners - {tuple(v) for v in np.round(room.floor_polygon, 9)}
            turns.add(missing)
        (door,) = room.doors
        walls = walls_of(room.floor_polygon)
        on = [w for w in walls if np.abs(w.local(np.array([door.p0, door.p1]))[:, 1]).max() < 1e-6]
        assert len(on) == 1 and on[0].length >= DOOR_WIDTH_M + 0.4 - 1e-9
    assert 30 < shapes[6] < 55 and shapes[4] > 5  # weighted 3 : 1
    assert heights == {2.5, 2.6}
    assert len(turns) == 4
    # large enough for the furniture: only the L (14 m2) holds 5 m2 of it at 40 %
    big = {len(make_room("bedroom", np.random.default_rng(s), stats=rs,
                         furniture_m2=5.0).floor_polygon) for s in range(20)}  # fmt: skip
    assert big == {6}


def test_floor_shapes_round_trip_and_reject_garbage():
    from pair2scene.curation.stats import (
        STATS_FORMAT,
        STATS_VERSION,
        HierarchyStats,
        RoomTypeStats,
        floor_shape,
    )
    from pair2scene.scene.model import Room

    # any start vertex and offset: one key, counter-clockwise from the lower-left corner
    poly = np.array(L_SHAPE[1:]).reshape(-1, 2)
    for k in range(6):
        room = Room("bedroom", np.roll(poly, k, axis=0) + (3.0, -7.0), 2.6)
        assert floor_shape(room) == L_SHAPE
    st = HierarchyStats()
    st.room_types["bedroom"] = RoomTypeStats(rooms=1)
    st.room_types["bedroom"].floor_shapes[L_SHAPE] += 1
    back = HierarchyStats.from_json(st.to_json())
    assert back.room_types["bedroom"].floor_shapes == {L_SHAPE: 1}
    doc = st.to_dict()
    doc["room_types"]["bedroom"]["floor_shapes"] = [[2.6, 0.0, 0.0, 1]]
    assert doc["format"] == STATS_FORMAT and doc["version"] == STATS_VERSION
    with pytest.raises(UserError, match="malformed statistics"):
        HierarchyStats.from_dict(doc)


def _shapes_by_area(areas: list[float]):
    """A Counter of square rooms of ``areas`` (m2), one room each, 2.5 m high."""
    from collections import Counter

    out = Counter()
    for a in areas:
        s = float(np.sqrt(a))
        out[(2.5, 0.0, 0.0, s, 0.0, s, s, 0.0, s)] += 1
    return out


def test_rooms_sized_for_their_furniture_as_the_training_rooms_were():
    """With the training rooms' log furniture share, a room is drawn where its furniture
    covers about the share they had: 3 m2 of furniture at a share of 0.25 gets rooms of
    about 12 m2, 6 m2 rooms of about 24 m2; without it, any room large enough."""
    from pair2scene.assembly.rooms import draw_floor

    shapes = _shapes_by_area([8.0, 12.0, 16.0, 24.0, 32.0, 48.0])
    share = (float(np.log(0.25)), 0.2)

    def areas(furniture, normal):
        out = []
        for seed in range(200):
            poly, _ = draw_floor(shapes, np.random.default_rng(seed), furniture / 0.4,
                                 furniture, normal)  # fmt: skip
            out.append(round(float(np.prod(poly.max(0))), 1))
        return np.array(out)

    small, large = areas(3.0, share), areas(6.0, share)
    assert np.mean(small == 12.0) > 0.6 and np.mean(large == 24.0) > 0.6
    assert set(small) <= {8.0, 12.0, 16.0, 24.0} and set(large) <= {16.0, 24.0, 32.0}
    loose = areas(3.0, None)  # by count alone: each room at least 7.5 m2 equally often
    assert len(set(loose)) == 6 and np.mean(loose == 12.0) < 0.3
    # the same seed draws the same room; no furniture: the share plays no part
    assert np.array_equal(areas(3.0, share), small)
    assert np.array_equal(areas(0.0, share), areas(0.0, None))
    # furniture far beyond every room: the largest, as before
    assert set(areas(100.0, share)) == {48.0}


def test_furniture_share_counted_merged_and_read_back():
    """Curation keeps [rooms, sum, sum of squares] of the log share per room type;
    merging adds them, a composed type weighs its bases, JSON keeps them, and a
    malformed entry is refused."""
    from pair2scene.curation.stats import (
        HierarchyStats,
        RoomTypeStats,
        furniture_share,
    )
    from pair2scene.scene.geometry import OrientedBox
    from pair2scene.scene.model import FLOOR, Room, Scene, SceneObject

    room = Room("bedroom", np.array([[0.0, 0.0], [4.0, 0.0], [4.0, 5.0], [0.0, 5.0]]), 2.6)

    def obj(i, size, support=FLOOR):
        box = OrientedBox(np.array([1.0 + i, 2.0, size[2] / 2]), np.array(size, float))
        return SceneObject(f"o{i}", "bed", box, support=support)

    placed = [obj(0, (2.0, 2.0, 0.5)), obj(1, (1.0, 1.0, 0.5)), obj(2, (1.0, 1.0, 0.1), "o0")]
    assert furniture_share(room, placed) == pytest.approx(5.0 / 20.0)  # the one on the bed not
    assert furniture_share(Room("bedroom", np.zeros((4, 2)), 2.6), placed) == 0.0

    stats = HierarchyStats.fit([Scene("s", room, placed)])
    rs = stats.room_types["bedroom"]
    assert rs.share_sums == pytest.approx([1.0, np.log(0.25), np.log(0.25) ** 2])
    assert rs.share_normal() is None  # one room: no spread
    empty = Scene("e", room, [])  # a room with no floor objects is not counted
    other = HierarchyStats.fit([Scene("t", room, placed[1:]), empty])
    merged = HierarchyStats.merge([stats, other])
    rs = merged.room_types["bedroom"]
    logs = np.log([0.25, 1.0 / 20.0])
    assert rs.share_sums == pytest.approx([2.0, logs.sum(), (logs**2).sum()])
    assert rs.share_normal() == pytest.approx((logs.mean(), logs.std()))
    back = HierarchyStats.from_json(merged.to_json())
    assert back.room_types["bedroom"].share_sums == pytest.approx(rs.share_sums, abs=1e-6)
    assert RoomTypeStats().share_normal() is None  # statistics written before it was kept
    doc = merged.to_dict()
    doc["room_types"]["bedroom"]["share_sums"] = [1.0, "x"]
    with pytest.raises(UserError, match="malformed statistics"):
        HierarchyStats.from_dict(doc)


def test_bundled_statistics_size_rooms_like_the_training_rooms():
    """The bundled statistics keep the furniture share of every trained room type (and
    a composed type gets its bases')."""
    from pair2scene.curation.stats import HierarchyStats
    from pair2scene.resources import load_table

    stats = HierarchyStats.from_dict(load_table("hierarchy_stats"))
    for rtype in ("bedroom", "living_room", "kitchen", "bathroom"):
        rs = stats.room_types[rtype]
        mean, sd = rs.share_normal()
        assert rs.share_sums[0] > 0.8 * rs.rooms and -2.0 < mean < -1.0 and 0.2 < sd < 0.7
    assert stats.room_type("office").share_normal() is not None  # a composed type's bases


def test_a_text_room_is_not_sized_for_the_furniture_it_names():
    """``sized=False`` (a text request) draws among the rooms large enough by count alone,
    as statistics without the share do; sized, the same furniture gets smaller rooms."""
    from pair2scene.curation.stats import RoomTypeStats

    rs = RoomTypeStats()
    rs.floor_shapes = _shapes_by_area([8.0, 12.0, 16.0, 24.0, 32.0, 48.0])
    logs = np.log([0.2, 0.3])
    rs.share_sums = [2.0, float(logs.sum()), float((logs**2).sum())]
    plain = RoomTypeStats(floor_shapes=rs.floor_shapes)

    def areas(stats, sized):
        return [make_room("living_room", np.random.default_rng(s), furniture_m2=2.5,
                          stats=stats, sized=sized).area for s in range(60)]  # fmt: skip

    assert areas(rs, False) == areas(plain, True)
    assert np.median(areas(rs, True)) < np.median(areas(rs, False))

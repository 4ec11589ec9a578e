"""A table with chairs at it is drawn at a size whose edge seats them."""

from __future__ import annotations

import numpy as np

from pair2scene.assembly.place import PERIMETER_PER_SEAT_M, Placer, seats_fit, seats_of
from pair2scene.hierarchy.tree import Hierarchy
from pair2scene.scene.model import FLOOR


def _room(chairs: int, category: str = "dining_table") -> tuple[Hierarchy, str]:
    """A bedroom with a table of ``category`` and ``chairs`` chairs at it, a stool at it, an
    armchair beside it and a chair standing alone."""
    h = Hierarchy("bedroom")
    table = h.add(category, FLOOR)
    for _ in range(chairs):
        h.add("chair", FLOOR, table.id)
    h.add("stool", FLOOR, table.id)
    h.add("armchair", FLOOR, table.id)  # a lounge seat: not drawn up to the table
    h.add("chair", FLOOR)
    h.add("cup", table.id)
    return h, table.id


def test_seats_of_counts_the_chairs_and_stools_at_each_anchor():
    h, table = _room(3)
    assert seats_of(h) == {table: 4}


def test_seats_fit_keeps_the_sizes_whose_perimeter_seats_them():
    sizes = np.array([[0.9, 0.7, 0.75], [1.8, 0.95, 0.75], [1.4, 1.4, 0.75], [2.4, 1.0, 0.75]])
    perimeter = 2 * sizes[:, :2].sum(1)  # 3.2, 5.5, 5.6, 6.8
    assert seats_fit(4)(sizes).tolist() == (perimeter >= 4 * PERIMETER_PER_SEAT_M).tolist()
    assert seats_fit(4)(sizes).tolist() == [True, True, True, True]
    assert seats_fit(6)(sizes).tolist() == [False, True, True, True]
    assert seats_fit(8)(sizes).tolist() == [False, False, False, True]
    # none seats twelve: the longest perimeter, not the smallest footprint
    assert seats_fit(12)(sizes).tolist() == [False, False, False, True]


def _perimeter(placer: Placer, h: Hierarchy, table: str, seed: int) -> float:
    return float(2 * placer.assets_for(h, seed)[table].size[:2].sum())


def test_a_table_for_six_is_drawn_to_seat_six():
    """Over 30 rooms, a dining table with six chairs (and a stool) at it is always at least
    7 x 0.8 m round; without chairs the bundled sizes give smaller ones too (the draw is
    otherwise the same: a table without seats keeps its size)."""
    placer = Placer(None)
    seated, table = _room(6)
    bare, bare_table = _room(0)
    big = [_perimeter(placer, seated, table, s) for s in range(30)]
    free = [_perimeter(placer, bare, bare_table, s) for s in range(30)]
    assert min(big) >= 7 * PERIMETER_PER_SEAT_M
    assert min(free) < 7 * PERIMETER_PER_SEAT_M
    one, one_table = _room(0)
    one.add("chair", FLOOR, one_table)  # one chair and the stool: two seats, any table seats
    assert [_perimeter(placer, one, one_table, s) for s in range(30)] == free


def test_a_desk_with_its_chair_keeps_its_size():
    placer = Placer(None)
    desk, table = _room(0, "desk")
    h = Hierarchy("bedroom")
    alone = h.add("desk", FLOOR)
    h.add("armchair", FLOOR, alone.id)
    h.add("chair", FLOOR)
    h.add("cup", alone.id)
    assert [_perimeter(placer, desk, table, s) for s in range(10)] == [
        _perimeter(placer, h, alone.id, s) for s in range(10)
    ]

"""Spreading objects off full supports, the largest-first order, collision push-out."""

from __future__ import annotations

import numpy as np
import pytest

from pair2scene.assembly.balance import BalanceRules, balance_supports, surface_area
from pair2scene.assembly.collision import MeshWorld, Shape
from pair2scene.assembly.place import placement_order
from pair2scene.assets.mesh import Asset, Part, box
from pair2scene.assets.registry import generate
from pair2scene.hierarchy.tree import Hierarchy
from pair2scene.scene.geometry import yaw_to_matrix
from pair2scene.scene.model import FLOOR

SUP_DEP = {"side_table": {"book": 5, "mug": 3}, "desk": {"book": 2}, "bed": {"pillow": 3}}


def crowded():
    h = Hierarchy("bedroom")
    table = h.add("side_table", FLOOR)
    desk = h.add("desk", FLOOR)
    h.add("bed", FLOOR)
    for _ in range(6):
        h.add("book", table.id)
    h.add("mug", table.id)
    return h.validate(), table.id, desk.id


def assets_of(h: Hierarchy) -> dict:
    sizes = {"side_table": [0.5, 0.4, 0.6], "desk": [1.4, 0.7, 0.75], "bed": [1.6, 2.1, 0.6],
             "book": [0.2, 0.25, 0.04], "mug": [0.1, 0.1, 0.1]}  # fmt: skip
    return {n.id: generate(n.category, sizes[n.category], i) for i, n in enumerate(h.nodes)}


def test_overflow_moves_to_a_support_that_carries_it():
    h, table, desk = crowded()
    assets = assets_of(h)
    cap = 0.3 * surface_area(assets[table])  # 0.06 m^2: one 0.05 m^2 book fits
    balanced, moves, overflow = balance_supports(h, assets, SUP_DEP, BalanceRules(0.3))
    on_table = [o for o, s in balanced.support.items() if s == table]
    load = sum(np.prod(assets[o].size[:2]) for o in on_table)
    assert load <= cap + 1e-9
    assert moves and all(m.source == table and m.target == desk for m in moves)
    # the desk (0.98 m^2 x 0.3) takes books; nothing carries a mug but the side table
    assert {o.category for o in overflow} <= {"book", "mug"}
    assert len(on_table) + len(moves) + len(overflow) == 7
    balanced.validate()  # still a valid hierarchy
    # the bed never takes books: the statistics have no book on a bed
    assert all(m.target != "bed_0" for m in moves)


def test_nothing_moves_under_the_cap():
    h, table, _ = crowded()
    balanced, moves, overflow = balance_supports(h, assets_of(h), SUP_DEP, BalanceRules(10.0))
    assert not moves and not overflow and balanced.support == h.support


def test_a_supports_largest_dependent_stays_whatever_its_footprint():
    """The load bounds clutter: a television whose box covers most of its stand stays on
    it, and what comes after it moves off."""
    h = Hierarchy("living_room")
    stand = h.add("tv_stand", FLOOR)
    tv = h.add("television", stand.id)
    vase = h.add("vase", stand.id)
    table = h.add("side_table", FLOOR)
    sizes = {"tv_stand": [1.2, 0.45, 0.55], "television": [1.2, 0.3, 0.7],
             "vase": [0.15, 0.15, 0.3], "side_table": [0.5, 0.5, 0.6]}  # fmt: skip
    assets = {n.id: generate(n.category, sizes[n.category], i) for i, n in enumerate(h.nodes)}
    sup_dep = {"tv_stand": {"television": 9, "vase": 2}, "side_table": {"vase": 3}}
    assert np.prod(sizes["television"][:2]) > 0.3 * surface_area(assets[stand.id])
    balanced, moves, overflow = balance_supports(h.validate(), assets, sup_dep, BalanceRules(0.3))
    assert balanced.support[tv.id] == stand.id and not overflow
    assert [(m.id, m.target) for m in moves] == [(vase.id, table.id)]


def test_largest_first_keeps_anchors_before_dependents():
    h = Hierarchy("bedroom")
    desk = h.add("desk", FLOOR)
    chair = h.add("chair", FLOOR, desk.id)
    h.add("bed", FLOOR)
    pen = h.add("pen", desk.id)
    laptop = h.add("laptop", desk.id)
    h.add("cell_phone", desk.id, laptop.id)
    h.validate()
    sizes = {"desk": [1.2, 0.6, 0.75], "chair": [0.5, 0.5, 0.9], "bed": [1.6, 2.1, 0.6],
             "pen": [0.14, 0.01, 0.01], "laptop": [0.35, 0.25, 0.02],
             "cell_phone": [0.07, 0.14, 0.01]}  # fmt: skip
    assets = {n.id: generate(n.category, sizes[n.category], 0) for n in h.nodes}
    order = [i.dependent.id for i in placement_order(h, assets)]
    assert sorted(order) == sorted(n.id for n in h.nodes)
    assert order[0] == "bed_0"  # the largest floor object first
    assert order.index(desk.id) < order.index(chair.id)
    assert order.index(laptop.id) < order.index(pen.id)  # larger first on the desk
    assert order.index(laptop.id) < order.index("cell_phone_0")
    assert max(order.index(o) for o in ("bed_0", desk.id, chair.id)) < order.index(pen.id)


def _overlapping_cubes() -> tuple[Asset, MeshWorld, Shape, Shape]:
    """A unit cube placed as "a" at x = 0.9 and a candidate cube 0.1 m into it at x = 0."""
    cube = Asset("x", np.ones(3), (Part("b", box([0, 0, 0], [1, 1, 1])),))
    world = MeshWorld()
    placed = Shape(cube)
    placed.set_pose(np.eye(3), np.array([0.9, 0.0, 0.5]))
    world.add("a", placed)
    cand = Shape(cube)
    cand.set_pose(np.eye(3), np.array([0.0, 0.0, 0.5]))
    return cube, world, placed, cand


def test_push_out_frees_a_shallow_overlap():
    cube, world, _, cand = _overlapping_cubes()
    push = world.push_out(cand, ["a"])
    assert push[0] == pytest.approx(-0.102, abs=1e-6) and abs(push[1]) < 1e-9 and push[2] == 0
    cand.set_pose(np.eye(3), np.array([push[0], 0.0, 0.5]))
    assert not world.colliding(cand, ["a"])
    on_top = Shape(cube)
    on_top.set_pose(np.eye(3), np.array([0.8, 0.0, 1.45]))  # 5 cm into it from above
    push = world.push_out(on_top, ["a"])  # sideways off its footprint: the short way
    assert push[0] == pytest.approx(-0.902, abs=1e-6) and abs(push[1]) < 1e-9
    touching = Shape(cube)
    touching.set_pose(np.eye(3), np.array([0.9, 0.0, 1.5]))  # resting on it
    assert not world.push_out(touching, ["a"]).any()


def test_pairs_kept_for_a_pose_follow_every_move():
    """colliding() then push_out() share the pairs found for the candidate's pose; a new
    pose of the candidate or of a placed object, or a changed world, finds them anew."""
    cube, world, placed, cand = _overlapping_cubes()
    assert world.colliding(cand, ["a"]) == ["a"]
    assert world.push_out(cand, ["a"])[0] == pytest.approx(-0.102, abs=1e-6)
    cand.set_pose(np.eye(3), np.array([-0.2, 0.0, 0.5]))  # the candidate moved clear
    assert world.colliding(cand, ["a"]) == [] and not world.push_out(cand, ["a"]).any()
    placed.set_pose(np.eye(3), np.array([0.7, 0.0, 0.5]))  # the placed object moved in
    assert world.colliding(cand, ["a"]) == ["a"]
    world.remove("a")
    assert world.colliding(cand, ["a"]) == [] and not world.push_out(cand, ["a"]).any()
    other = Shape(cube)
    other.set_pose(np.eye(3), np.array([-1.1, 0.0, 0.5]))
    world.add("a", other)  # the same id, another shape
    assert world.colliding(cand, ["a"]) == ["a"]
    assert world.push_out(cand, ["a"])[0] == pytest.approx(0.102, abs=1e-6)


def test_push_out_clears_every_overlap_at_once():
    """Wedged between two blocks, the candidate moves along the one free direction far
    enough to clear both (each contact's own push would drive it into the other)."""
    cube = Asset("x", np.ones(3), (Part("b", box([0, 0, 0], [1, 1, 1])),))
    world = MeshWorld()
    for name, x in (("left", -0.95), ("right", 0.95)):
        block = Shape(cube)
        block.set_pose(np.eye(3), np.array([x, 0.0, 0.5]))
        world.add(name, block)
    cand = Shape(cube)
    cand.set_pose(yaw_to_matrix(0.3), np.array([0.0, 0.3, 0.5]))
    push = world.push_out(cand, ["left", "right"])
    assert abs(push[0]) < 1e-9 and push[1] > 0 and push[2] == 0
    cand.set_pose(yaw_to_matrix(0.3), np.array([0.0, 0.3, 0.5]) + push)
    assert not world.colliding(cand, ["left", "right"])

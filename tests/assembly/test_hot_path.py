"""The placement hot path (issue 22): its faster forms give what the plain ones gave."""

from __future__ import annotations

import numpy as np
import pytest

from pair2scene.assembly.collision import (
    BoxSet,
    MeshWorld,
    Shape,
    _edge_normals,
    clearing_move,
    obb_overlaps,
)
from pair2scene.assets.registry import generate
from pair2scene.errors import UserError
from pair2scene.scene import geometry
from pair2scene.scene.geometry import points_in_polygon, yaw_to_matrix
from pair2scene.scene.walls import Wall, face_contacts


def _reference_clearing_move(pairs, gap=2e-3):
    """The clearing move as first written: every pair's normals, repeated, one pair at a
    time."""
    directions = np.concatenate([_edge_normals(p) for pair in pairs for p in pair])
    need = np.full(len(directions), -np.inf)
    for mine, theirs in pairs:
        need = np.maximum(need, (theirs @ directions.T).max(0) - (mine @ directions.T).min(0))
    best = int(np.argmin(need))
    return np.array([*(directions[best] * (need[best] + gap)), 0.0])


def _outline(rng, yaw):
    """A convex counter-clockwise rectangle at ``yaw`` (parts of one object share it)."""
    w, d = rng.uniform(0.05, 1.0, 2)
    corners = np.array([[-w, -d], [w, -d], [w, d], [-w, d]]) / 2
    rot = yaw_to_matrix(yaw)[:2, :2]
    return corners @ rot.T + rng.uniform(-0.5, 0.5, 2)


def test_clearing_move_matches_the_pair_by_pair_move():
    """Distinct outlines and distinct directions once each: the same move, tie-breaks
    included (outlines sharing a yaw share their directions)."""
    rng = np.random.default_rng(0)
    for trial in range(300):
        yaws = rng.choice([0.0, 0.3, np.pi / 2], size=2)
        mine = [_outline(rng, yaws[0]) for _ in range(rng.integers(1, 4))]
        theirs = [_outline(rng, yaws[1]) for _ in range(rng.integers(1, 4))]
        pairs = [(m, t) for m in mine for t in theirs if rng.random() < 0.7] or [
            (mine[0], theirs[0])
        ]
        got = clearing_move(pairs)
        want = _reference_clearing_move(pairs)
        np.testing.assert_allclose(got, want, rtol=0, atol=1e-12, err_msg=f"trial {trial}")


def test_clearing_move_of_nothing_is_zero():
    assert not clearing_move([]).any()


def test_edge_normals_are_numpys_to_the_bit():
    """The loop's normals are the array form's (the form they had), bit for bit:
    placement's pushes, and so its scenes, stay the same."""

    def by_arrays(outline):
        edges = np.concatenate((outline[1:], outline[:1])) - outline
        normals = np.stack((edges[:, 1], -edges[:, 0]), axis=1)
        length = np.sqrt(np.add.reduce(normals * normals, axis=1))
        keep = length > 1e-9
        normals = normals[keep] / length[keep, None]
        return np.concatenate([normals, -normals])

    rng = np.random.default_rng(3)
    for _ in range(500):
        outline = _outline(rng, rng.uniform(0, 6.3))
        if rng.random() < 0.3:
            outline = np.insert(outline, 1, outline[0], axis=0)  # a zero-length edge
        assert np.array_equal(_edge_normals(outline), by_arrays(outline))


def test_push_out_is_the_clearing_move_of_the_deep_pairs():
    table = generate("side_table", np.array([0.6, 0.6, 0.6]), 1)
    dresser = generate("dresser", np.array([1.0, 0.5, 0.8]), 2)
    world = MeshWorld()
    placed = Shape(table)
    placed.set_pose(np.eye(3), np.array([0.0, 0.0, 0.3]))
    world.add("t", placed)
    cand = Shape(dresser)
    cand.set_pose(yaw_to_matrix(0.2), np.array([0.5, 0.2, 0.4]))
    deep = world._deep_pairs(cand, "t")
    assert deep
    pairs = [(cand.footprint(i), placed.footprint(j)) for i, j in deep]
    np.testing.assert_allclose(world.push_out(cand, ["t"]), clearing_move(pairs), atol=1e-12)


def test_a_kept_box_set_answers_as_the_plain_test():
    rng = np.random.default_rng(1)
    m = 40
    centers = rng.uniform(-2, 2, (m, 3))
    halves = rng.uniform(0.05, 0.6, (m, 3))
    rots = np.stack([yaw_to_matrix(y) for y in rng.uniform(0, 6.3, m)])
    boxes = BoxSet(centers, halves, rots, 2e-4)
    for _ in range(50):
        c = rng.uniform(-2, 2, (1, 3))
        h = rng.uniform(0.05, 0.6, (1, 3))
        r = yaw_to_matrix(rng.uniform(0, 6.3))[None]
        got = boxes.overlaps(c, h, r)
        assert (got == obb_overlaps(c, h, r, centers, halves, rots, 2e-4)).all()
    assert boxes.overlaps(np.zeros((0, 3)), np.zeros((0, 3)), np.zeros((0, 3, 3))).shape == (0, m)
    assert len(BoxSet(np.zeros((0, 3)), np.zeros((0, 3)), np.zeros((0, 3, 3)))) == 0


def test_few_points_in_a_polygon_by_loop_and_by_numpy_agree():
    """The loop for a footprint against a room and numpy for many points: the same
    answers, on vertices and edges too (rounded coordinates put points on them)."""
    rng = np.random.default_rng(2)
    for _ in range(3000):
        poly = rng.normal(size=(rng.integers(3, 9), 2)).round(int(rng.integers(0, 3)))
        pts = rng.normal(size=(rng.integers(1, 8), 2)).round(int(rng.integers(0, 3)))
        pts[0] = poly[int(rng.integers(len(poly)))]
        loop = points_in_polygon(pts, poly)
        assert len(pts) * len(poly) <= geometry._FEW
        many = points_in_polygon(np.repeat(pts, 20, axis=0), poly)  # numpy's path
        assert (np.repeat(loop, 20) == many).all()


def test_wall_contacts_near_the_angle_limit():
    """Faces skipped by the quick cosine test are exactly those over the angle limit."""
    wall = Wall(0, np.array([0.0, 0.0]), np.array([4.0, 0.0]))
    for degrees in (14.0, 14.999, 15.0, 15.001, 16.0, 44.0):
        yaw = np.radians(degrees)
        box = geometry.OrientedBox.from_yaw([2.0, 0.3, 0.4], [1.0, 0.5, 0.8], yaw)
        contacts = face_contacts(box, [wall], max_gap=0.5, max_angle=15.0)
        assert bool(contacts) == (degrees <= 15.0 + 1e-9), degrees
        wide = face_contacts(box, [wall], max_gap=0.5, max_angle=200.0)
        assert wide  # a limit past 180 degrees skips nothing


def test_dense_give_up_is_checked():
    from pair2scene.assembly.place import AssemblyConfig

    with pytest.raises(UserError, match="dense-give-up"):
        AssemblyConfig(dense_give_up=0)
    assert AssemblyConfig(dense_give_up=None).dense_give_up is None


def test_a_dense_room_gives_up_on_an_object_that_no_longer_fits():
    """In a beyond (dense) scene an object whose candidates keep failing stops early; the
    objects after it are drawn and placed as with the full search."""
    torch = pytest.importorskip("torch")
    from dataclasses import replace

    from pair2scene.assembly.place import AssemblyConfig, Placer
    from pair2scene.assembly.rooms import make_room
    from pair2scene.hierarchy.tree import Hierarchy
    from pair2scene.model import from_pretrained
    from pair2scene.scene.model import FLOOR

    del torch
    model = from_pretrained()
    room = make_room("bedroom", np.random.default_rng(0))
    room = replace(room, floor_polygon=np.array([[0, 0], [2.4, 0], [2.4, 2.8], [0, 2.8]], float))
    h = Hierarchy("bedroom")
    for _ in range(3):
        h.add("bed", FLOOR)
    h.add("garbage_can", FLOOR)
    h.validate()

    def run(give_up):
        cfg = AssemblyConfig(candidates=16, batches=4, dense_give_up=give_up)
        return Placer(model, config=cfg).place(h, room, seed=0, dense=True)

    quick, full = run(50), run(None)
    gave_up = [d for d in quick.stats.dropped if "gave up after 50 for want of room" in d.reason]
    assert gave_up and not any("among 64 candidates" in d.reason for d in gave_up)
    assert {d.id for d in quick.stats.dropped} == {d.id for d in full.stats.dropped}
    boxes = {o.id: o.box.to_vector().tolist() for o in full.scene.objects}
    assert {o.id: o.box.to_vector().tolist() for o in quick.scene.objects} == boxes
    fit = Placer(model, config=AssemblyConfig(candidates=16, batches=4, dense_give_up=5))
    assert not any("gave up" in d.reason for d in fit.place(h, room, seed=0).stats.dropped)


@pytest.mark.slow  # (CI runs the slow tests too: .ci/run; ~30-60 s)
def test_a_crowded_support_gives_up_later_and_names_its_option():
    """Objects on a support have their own limit (dense_give_up_support): on a coffee
    table carrying more bowls than fit, a bowl stops after that many collisions, with the
    option named; what was placed before it is as the full search places it; fit scenes
    still try every candidate."""
    pytest.importorskip("torch")
    from pair2scene.assembly.place import AssemblyConfig, Placer

    with pytest.raises(UserError, match="dense-give-up-support"):
        AssemblyConfig(dense_give_up_support=0)
    model, room, h, table = _bowls_on_a_coffee_table(24)

    def run(give_up, dense=True):
        cfg = AssemblyConfig(candidates=16, batches=4, dense_give_up_support=give_up)
        return Placer(model, config=cfg).place(h, room, seed=0, dense=dense)

    quick, full = run(20), run(None)
    option = "gave up after 20 for want of room (--assembly.dense-give-up-support)"
    gave_up = {d.id for d in quick.stats.dropped if option in d.reason}
    assert gave_up and all("among 64 candidates" in d.reason for d in full.stats.dropped)
    order = [item.dependent.id for item in h.sequence()]
    first = min(order.index(i) for i in gave_up)
    before = set(order[:first])

    def placed(result):
        return {o.id: o.box.to_vector().tolist() for o in result.scene.objects if o.id in before}

    assert table in placed(full) and placed(quick) == placed(full)
    assert not any("gave up" in d.reason for d in run(5, dense=False).stats.dropped)


def test_a_dense_room_takes_its_own_number_of_push_outs(monkeypatch):
    """``dense_push_attempts`` holds in beyond (dense) scenes only: with none allowed, a
    crowded coffee table's bowls are never pushed out of a collision there, while a fit
    scene with the same config pushes them (``push_attempts``)."""
    pytest.importorskip("torch")
    from pair2scene.assembly.place import AssemblyConfig, Placer

    with pytest.raises(UserError, match="dense-push-attempts"):
        AssemblyConfig(dense_push_attempts=-1)
    assert AssemblyConfig(dense_push_attempts=None).dense_push_attempts is None
    pushes = []
    push_out = MeshWorld.push_out
    monkeypatch.setattr(MeshWorld, "push_out", lambda *a: pushes.append(1) or push_out(*a))
    model, room, h, _ = _bowls_on_a_coffee_table(8)
    placer = Placer(model, config=AssemblyConfig(candidates=16, batches=2, dense_push_attempts=0))
    placer.place(h, room, seed=0)
    assert pushes  # fit: push_attempts
    pushes.clear()
    dense = placer.place(h, room, seed=0, dense=True)
    assert not pushes and dense.stats.rejections.get("collision")


def _bowls_on_a_coffee_table(bowls: int):
    """(the bundled layout model, a 3 m square bedroom, a hierarchy of a coffee table
    carrying ``bowls`` bowls, the table's id): a support more crowded the more bowls."""
    from dataclasses import replace

    from pair2scene.assembly.rooms import make_room
    from pair2scene.hierarchy.tree import Hierarchy
    from pair2scene.model import from_pretrained
    from pair2scene.scene.model import FLOOR

    room = make_room("bedroom", np.random.default_rng(0))
    room = replace(room, floor_polygon=np.array([[0, 0], [3.0, 0], [3.0, 3.0], [0, 3.0]], float))
    h = Hierarchy("bedroom")
    table = h.add("coffee_table", FLOOR).id
    for _ in range(bowls):
        h.add("bowl", table)
    h.validate()
    return from_pretrained(), room, h, table

"""Collision: the SAT broad phase against fcl's own box test, and the mesh narrow phase."""

from __future__ import annotations

import numpy as np
import pytest

fcl = pytest.importorskip("fcl")

from pair2scene.assembly.collision import MeshWorld, Shape, obb_overlaps  # noqa: E402
from pair2scene.assets.registry import generate  # noqa: E402
from pair2scene.scene.geometry import rot_x, rot_z  # noqa: E402


def random_rotation(rng: np.random.Generator) -> np.ndarray:
    q, _ = np.linalg.qr(rng.normal(size=(3, 3)))
    return q * np.sign(np.linalg.det(q))


def fcl_boxes_collide(c1, h1, r1, c2, h2, r2) -> bool:
    o1 = fcl.CollisionObject(fcl.Box(*(2 * h1)), fcl.Transform(r1, c1))
    o2 = fcl.CollisionObject(fcl.Box(*(2 * h2)), fcl.Transform(r2, c2))
    return bool(fcl.collide(o1, o2, fcl.CollisionRequest(), fcl.CollisionResult()))


def test_sat_agrees_with_fcl_on_random_boxes():
    rng = np.random.default_rng(0)
    n, m = 60, 40
    ca, cb = rng.uniform(-1, 1, (n, 3)), rng.uniform(-1, 1, (m, 3))
    ha, hb = rng.uniform(0.05, 0.6, (n, 3)), rng.uniform(0.05, 0.6, (m, 3))
    ra = np.stack([random_rotation(rng) for _ in range(n)])
    rb = np.stack([random_rotation(rng) if i % 2 else rot_z(rng.uniform(0, 6)) for i in range(m)])
    got = obb_overlaps(ca, ha, ra, cb, hb, rb)
    want = np.array([[fcl_boxes_collide(ca[i], ha[i], ra[i], cb[j], hb[j], rb[j])
                      for j in range(m)] for i in range(n)])  # fmt: skip
    assert 0.1 < want.mean() < 0.9  # both outcomes are exercised
    assert (got == want).mean() > 0.995  # fcl's GJK has its own tolerance on grazing pairs


def test_sat_touching_boxes_and_margin():
    eye = np.eye(3)[None]
    a = (np.zeros((1, 3)), np.full((1, 3), 0.5), eye)
    touching = (np.array([[1.0, 0, 0]]), np.full((1, 3), 0.5), eye)
    assert obb_overlaps(*a, *touching, margin=1e-3)[0, 0] == False  # noqa: E712
    deep = (np.array([[0.9, 0, 0]]), np.full((1, 3), 0.5), eye)
    assert obb_overlaps(*a, *deep, margin=1e-3)[0, 0]
    # an edge-on rotated box whose corner pokes in: found only through the cross axes
    rotated = (np.array([[1.2, 1.2, 0]]), np.full((1, 3), 0.5), rot_z(np.pi / 4)[None])
    assert not obb_overlaps(*a, *rotated)[0, 0]
    assert obb_overlaps(np.zeros((0, 3)), np.zeros((0, 3)), np.zeros((0, 3, 3)), *a).shape == (0, 1)


def posed(asset, center, rotation=None):
    shape = Shape(asset)
    shape.set_pose(np.eye(3) if rotation is None else rotation, np.asarray(center, float))
    return shape


def test_mesh_world_contact_is_not_collision_but_penetration_is():
    world = MeshWorld()
    table = generate("dining_table", [1.2, 0.8, 0.75], 0)
    world.add("table", posed(table, [0, 0, 0.375]))
    mug = generate("mug", [0.1, 0.1, 0.1], 0)
    assert world.colliding(posed(mug, [0, 0, 0.80]), ["table"]) == []  # resting on the top
    assert world.colliding(posed(mug, [0, 0, 0.76]), ["table"]) == ["table"]  # sunk in
    assert world.colliding(posed(mug, [0.3, 0.2, 0.96]), ["table"]) == []  # above it


def test_concave_furniture_collides_as_its_parts():
    table = generate("dining_table", [1.2, 0.8, 0.75], 0, style=0)
    world = MeshWorld()
    world.add("table", posed(table, [0, 0, 0.375]))
    # a small box under the table top, between the legs: its OBB overlaps the table's box
    box = generate("box", [0.3, 0.3, 0.3], 0)
    under = posed(box, [0, 0, 0.16])
    assert obb_overlaps([[0, 0, 0.16]], [[0.15] * 3], np.eye(3)[None],
                        [[0, 0, 0.375]], [[0.6, 0.4, 0.375]], np.eye(3)[None])[0, 0]  # fmt: skip
    assert world.colliding(under, ["table"]) == []
    world.remove("table")
    assert world.colliding(under, ["table"]) == []


def test_pose_rotation_is_applied():
    bar = generate("box", [1.0, 0.1, 0.1], 0)
    world = MeshWorld()
    world.add("bar", posed(bar, [0, 0, 0.05]))
    crossing = posed(bar, [0, 0, 0.05], rot_z(np.pi / 2))
    assert world.colliding(crossing, ["bar"]) == ["bar"]
    lifted = posed(bar, [0, 0, 0.5], rot_x(0.3))
    assert world.colliding(lifted, ["bar"]) == []


def test_a_shape_moved_after_a_test_is_tested_where_it_now_stands():
    """Each part's fcl object is built at its first narrow-phase test and posed when a
    test asks for it: a shape tested, moved away, moved back and turned is tested where
    it stands each time, as a shape built anew there is."""
    world = MeshWorld()
    table = generate("dining_table", [1.2, 0.8, 0.75], 0)
    world.add("table", posed(table, [0, 0, 0.375]))
    mug = generate("mug", [0.1, 0.1, 0.1], 0)
    moving = posed(mug, [0, 0, 0.76])
    poses = [
        ([0, 0, 0.76], None, ["table"]),  # sunk into the top
        ([3, 0, 0.76], None, []),  # away
        ([0.3, 0.2, 0.76], rot_z(0.7), ["table"]),  # back in, turned
        ([0.3, 0.2, 0.80], rot_z(0.7), []),  # resting on the top
    ]
    for center, rotation, expected in poses:
        moving.set_pose(np.eye(3) if rotation is None else rotation, np.asarray(center, float))
        assert world.colliding(moving, ["table"]) == expected
        assert world.colliding(posed(mug, center, rotation), ["table"]) == expected
        assert world.penetration(moving, world.shapes["table"]) == pytest.approx(
            world.penetration(posed(mug, center, rotation), world.shapes["table"])
        )


def test_a_growing_box_set_holds_the_rows_of_one_made_at_once():
    """Boxes added one at a time (past the first capacity) give the same arrays, bit for
    bit, as the set made of them all at once; a snapshot keeps what it held."""
    from pair2scene.assembly.collision import BoxSet
    from pair2scene.scene.geometry import yaw_to_matrix

    rng = np.random.default_rng(0)
    centers = rng.uniform(-3, 3, (150, 3))
    halves = rng.uniform(0.05, 1.0, (150, 3))
    rots = np.stack([yaw_to_matrix(y) for y in rng.uniform(-np.pi, np.pi, 150)])
    grown = BoxSet.growing(0.002, capacity=4)
    for i in range(100):
        grown.add(centers[i], halves[i], rots[i])
    early = grown.snapshot()
    for i in range(100, 150):
        grown.add(centers[i], halves[i], rots[i])
    whole = BoxSet(centers, halves, rots, 0.002)
    for name in ("centers", "halves", "rots", "extents"):
        assert np.array_equal(getattr(grown, name), getattr(whole, name))
        assert np.array_equal(getattr(early, name), getattr(whole, name)[:100])
    probe = (centers[:20] + 0.1, halves[:20], rots[:20])
    assert np.array_equal(grown.overlaps(*probe), whole.overlaps(*probe))
    assert grown.overlaps(*probe).any() and not grown.overlaps(*probe).all()

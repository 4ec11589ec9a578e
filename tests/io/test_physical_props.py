"""Physical properties shared by the simulator exports (pair2scene.io.physical): exact
mass properties of closed polyhedra, a positive definite inertia for every category's
procedural asset, and the dynamic policy."""

import numpy as np
import pytest

from pair2scene.assets.mesh import Part, box, hull
from pair2scene.assets.registry import generate
from pair2scene.categories import CATEGORIES, SuperCategory
from pair2scene.errors import UserError
from pair2scene.io.physical import (
    CATEGORY_PHYSICS,
    DYNAMIC_CHOICES,
    MATERIAL_FRICTION,
    body_physics,
    convex_mass_properties,
    is_dynamic,
    scene_physics,
)
from pair2scene.scene.geometry import OrientedBox
from pair2scene.scene.model import Room, Scene, SceneObject

SIZES = {
    SuperCategory.LARGE_FURNITURE: (1.0, 0.6, 0.8),
    SuperCategory.FIXTURE: (0.7, 0.5, 0.8),
    SuperCategory.PART: (0.4, 0.35, 0.15),
    SuperCategory.WALL_OBJECT: (0.8, 0.05, 0.6),
    SuperCategory.SMALL_OBJECT: (0.2, 0.15, 0.12),
}
OBJECT_CATEGORIES = [c for c in CATEGORIES if c.super is not SuperCategory.STRUCTURE]


def test_unit_cube():
    mass, com, inertia = convex_mass_properties(box((0.0, 0.0, 0.0), (1.0, 1.0, 1.0)), 1.0)
    assert mass == pytest.approx(1.0)
    assert np.allclose(com, 0.0, atol=1e-12)
    assert np.allclose(inertia, np.eye(3) / 6.0)


def test_box_off_origin_and_rotated():
    a, b, c, rho = 0.4, 1.2, 0.3, 700.0
    angle = 0.7
    rot = np.array(
        [[np.cos(angle), -np.sin(angle), 0], [np.sin(angle), np.cos(angle), 0], [0, 0, 1]]
    )
    mesh = box((1.0, -2.0, 3.0), (a, b, c), rotation=rot)
    mass, com, inertia = convex_mass_properties(mesh, rho)
    m = rho * a * b * c
    assert mass == pytest.approx(m)
    assert np.allclose(com, (1.0, -2.0, 3.0))
    local = m / 12.0 * np.diag([b**2 + c**2, a**2 + c**2, a**2 + b**2])
    assert np.allclose(inertia, rot @ local @ rot.T)


def test_tetrahedron():
    """The corner tetrahedron (0, e1, e2, e3): volume 1/6, centroid 1/4, and about the
    centroid I_xx = 1/80, I_xy = +1/480 (the product of inertia is -1/480)."""
    mesh = hull(np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]], dtype=float))
    mass, com, inertia = convex_mass_properties(mesh, 2.0)
    assert mass == pytest.approx(2.0 / 6.0)
    assert np.allclose(com, 0.25)
    expected = 2.0 * (np.full((3, 3), 1 / 480) + np.eye(3) * (1 / 80 - 1 / 480))
    assert np.allclose(inertia, expected)


def test_flat_part_gets_a_thickness_floor():
    mass, com, inertia = convex_mass_properties(box((0.0, 0.0, 0.5), (0.2, 0.1, 0.0)), 1000.0)
    assert mass > 0 and np.allclose(com, (0.0, 0.0, 0.5))
    assert np.linalg.eigvalsh(inertia).min() > 0


def test_every_object_category_has_a_rule():
    missing = [c.name for c in OBJECT_CATEGORIES if c.name not in CATEGORY_PHYSICS]
    assert not missing
    assert {r.material for r in CATEGORY_PHYSICS.values()} <= set(MATERIAL_FRICTION)


@pytest.mark.parametrize("cat", [c.name for c in OBJECT_CATEGORIES])
def test_inertia_positive_definite_for_every_category(cat):
    sup = next(c.super for c in OBJECT_CATEGORIES if c.name == cat)
    size = np.array(SIZES[sup])
    asset = generate(cat, size, rng=3)
    obj = SceneObject(f"{cat}_0", cat, OrientedBox(np.zeros(3), size), support="floor")
    p = body_physics(obj, asset, "all")
    assert p.mass > 0 and np.isfinite(p.mass)
    assert np.allclose(p.inertia, p.inertia.T)
    moments = np.linalg.eigvalsh(p.inertia)
    assert moments.min() > 0, (cat, moments)
    # the triangle inequality every simulator checks: A + B >= C
    assert moments[0] + moments[1] >= moments[2] * (1 - 1e-9), (cat, moments)
    assert np.all(np.abs(p.com) <= size / 2 + 1e-9)
    assert p.friction == MATERIAL_FRICTION[p.material]
    assert len(p.parts) == len(asset.parts)


def test_mass_follows_the_rule():
    size = np.array([0.22, 0.3, 0.03])  # a book: density rule
    book = body_physics(
        SceneObject("b", "book", OrientedBox(np.zeros(3), size), support="floor"),
        generate("book", size, rng=0),
    )
    volume = sum(p.volume for p in book.parts)
    assert book.mass == pytest.approx(CATEGORY_PHYSICS["book"].density * volume)
    tv = body_physics(  # a television at its typical size: its typical mass
        SceneObject("t", "television", OrientedBox(np.zeros(3), (1.15, 0.32, 0.81))),
        generate("television", (1.15, 0.32, 0.81), rng=0),
    )
    assert tv.mass == pytest.approx(CATEGORY_PHYSICS["television"].typical_mass, rel=0.05)


def _obj(oid, cat, support="floor", bottom=0.0):
    size = np.array([0.3, 0.3, 0.3])
    return SceneObject(oid, cat, OrientedBox(np.array([0, 0, bottom + 0.15]), size), None, support)


def test_dynamic_policy():
    mug_on_table = _obj("mug", "mug", "table", 0.75)
    table = _obj("table", "dining_table")
    sink = _obj("sink", "sink")
    painting = _obj("painting", "painting", "wall:1", 1.5)
    mounted_tv = _obj("tv", "television", "wall:0", 1.2)
    for o, small, everything in [
        (mug_on_table, True, True),
        (table, False, True),
        (sink, False, False),
        (painting, False, False),
        (mounted_tv, False, False),
    ]:
        assert is_dynamic(o, "small") is small, o.id
        assert is_dynamic(o, "all") is everything, o.id
        assert is_dynamic(o, "none") is False
    assert DYNAMIC_CHOICES == ("all", "small", "none")


def test_unknown_dynamic_is_a_user_error():
    scene = Scene("s", Room("bedroom", np.array([[0, 0], [3, 0], [3, 3], [0, 3]])))
    with pytest.raises(UserError, match="dynamic must be one of"):
        scene_physics(scene, {}, dynamic="some")


def test_scene_physics_in_scene_order_and_only_with_assets():
    objs = [_obj("a", "mug"), _obj("b", "dining_table"), _obj("c", "book")]
    scene = Scene("s", Room("bedroom", np.array([[0, 0], [3, 0], [3, 3], [0, 3]])), objs)
    cube = Part("p", box((0, 0, 0), (0.3, 0.3, 0.3)))
    from pair2scene.assets.mesh import Asset

    assets = {o.id: Asset(o.category, o.box.size, (cube,)) for o in objs if o.id != "b"}
    out = scene_physics(scene, assets)
    assert list(out) == ["a", "c"]
    assert out["a"].dynamic and out["a"].object_id == "a" and out["a"].category == "mug"

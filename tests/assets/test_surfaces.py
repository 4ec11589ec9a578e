"""Support surfaces of small assets built from mesh.py primitives."""

from __future__ import annotations

import math

import numpy as np
import pytest

from pair2scene.assets.mesh import Asset, Mesh, Part, box, box_between, cylinder
from pair2scene.assets.surfaces import (
    MIN_CLEARANCE_M,
    SupportSurface,
    clearance_above,
    components,
    convex_part,
    support_surfaces,
    surfaces_of,
)


def test_a_surface_holds_points_inside_its_outline_and_outside_its_holes():
    outline = np.array([[-1, -1], [1, -1], [1, 1], [-1, 1]], float)
    hole = np.array([[-0.2, -0.2], [-0.2, 0.2], [0.2, 0.2], [0.2, -0.2]], float)  # clockwise
    surface = SupportSurface(0.5, outline, 4.0 - 0.16, math.inf, (hole,))
    pts = np.array([[0, 0], [0.5, 0.5], [1.5, 0], [-0.9, 0.9], [0.1, -0.1], [0, 1.01]])
    expected = [False, True, False, True, False, False]
    assert surface.contains(pts).tolist() == expected
    assert surface.contains(pts).tolist() == expected  # (asked again: the same)
    assert surface.contains(pts[1]).tolist() == [True]
    plain = SupportSurface(0.5, outline, 4.0, math.inf)
    assert plain.contains(pts).tolist() == [True, True, False, True, True, False]


def _asset(category: str, parts: list[Part]) -> Asset:
    lo, hi = Mesh.concat([p.mesh for p in parts]).bounds
    return Asset(category, hi - lo, tuple(parts))


def bookcase(w=0.8, d=0.3, h=1.6, t=0.02, tiers=5) -> Asset:
    """Two side panels and a back running full height; tiers overlap the panels by t/2."""
    parts = [
        Part("side_l", box_between((-w / 2, -d / 2, -h / 2), (-w / 2 + t, d / 2, h / 2))),
        Part("side_r", box_between((w / 2 - t, -d / 2, -h / 2), (w / 2, d / 2, h / 2))),
        Part("back", box_between((-w / 2, -d / 2, -h / 2), (w / 2, -d / 2 + t, h / 2))),
    ]
    for i, z in enumerate(np.linspace(-h / 2, h / 2 - t, tiers)):
        parts.append(
            Part(
                f"tier{i}", box_between((-w / 2 + t / 2, -d / 2, z), (w / 2 - t / 2, d / 2, z + t))
            )
        )
    return _asset("shelving_unit", parts)


def test_bookcase_tiers_and_top():
    w, d, h, t = 0.8, 0.3, 1.6, 0.02
    s = support_surfaces(bookcase(w, d, h, t))
    tier_z = np.linspace(-h / 2, h / 2 - t, 5) + t
    assert [x.z for x in s] == pytest.approx(tier_z.tolist())
    pitch = tier_z[1] - tier_z[0]
    # the four inner tiers: between the panels, in front of the back, under the next tier
    for x in s[:4]:
        assert x.clearance == pytest.approx(pitch - t)
        assert x.area == pytest.approx((w - 2 * t) * (d - t))
        assert x.polygon.min(0) == pytest.approx([-w / 2 + t, -d / 2 + t])
        assert x.polygon.max(0) == pytest.approx([w / 2 - t, d / 2])
        assert x.holes == ()
    # the top: the top tier, the panels' and the back's tops are one region, open above
    top = s[-1]
    assert math.isinf(top.clearance)
    assert top.area == pytest.approx(w * d)
    assert len(top.polygon) == 4


def test_polygon_is_counter_clockwise_and_contains():
    s = support_surfaces(bookcase())[0]
    x, y = s.polygon[:, 0], s.polygon[:, 1]
    assert 0.5 * (x @ np.roll(y, -1) - y @ np.roll(x, -1)) > 0
    assert s.contains(np.array([[0.0, 0.0], [0.39, 0.0], [0.0, -0.145]])).tolist() == [
        True,
        False,
        False,
    ]


def test_table_top_one_region_over_legs():
    top = box((0, 0, 0.36), (1.2, 0.8, 0.04))
    legs = [
        box((sx * 0.55, sy * 0.35, -0.02), (0.05, 0.05, 0.72)) for sx in (-1, 1) for sy in (-1, 1)
    ]  # legs run into the top slab
    a = _asset(
        "dining_table", [Part("top", top)] + [Part(f"leg{i}", m) for i, m in enumerate(legs)]
    )
    s = support_surfaces(a)
    assert len(s) == 1
    assert s[0].z == pytest.approx(0.38)
    assert s[0].area == pytest.approx(0.96)
    assert math.isinf(s[0].clearance)


def test_round_table_outline_is_smooth():
    a = _asset(
        "dining_table",
        [
            Part("top", cylinder((0, 0, 0.36), 0.5, 0.04, segments=32)),
            Part("leg", cylinder((0, 0, 0), 0.05, 0.7)),
        ],
    )
    (s,) = support_surfaces(a)
    exact = 0.5 * 32 * 0.25 * math.sin(2 * math.pi / 32)
    assert s.area == pytest.approx(exact, rel=0.01)
    assert len(s.polygon) < 64  # the staircase of cells is simplified


def chair() -> Asset:
    seat = box_between((-0.22, -0.22, -0.02), (0.22, 0.22, 0.03))
    back = box_between((-0.22, -0.22, 0.0), (0.22, -0.18, 0.45))  # stands in the seat's rear
    legs = [
        box_between(
            (sx * 0.2 - 0.02, sy * 0.2 - 0.02, -0.45), (sx * 0.2 + 0.02, sy * 0.2 + 0.02, 0.0)
        )
        for sx in (-1, 1)
        for sy in (-1, 1)
    ]
    return _asset(
        "chair",
        [Part("seat", seat), Part("back", back)] + [Part(f"leg{i}", m) for i, m in enumerate(legs)],
    )


def test_chair_seat_excludes_the_back():
    s = support_surfaces(chair())
    seat = [x for x in s if x.z == pytest.approx(0.03)]
    assert len(seat) == 1
    assert seat[0].area == pytest.approx(0.44 * 0.40)
    assert seat[0].polygon[:, 1].min() == pytest.approx(-0.18)
    assert math.isinf(seat[0].clearance)
    # the back's top (4 cm deep) is a surface too; nothing else (leg tops are covered)
    assert [x.z for x in s] == pytest.approx([0.03, 0.45])


def bowl(radius=0.1, height=0.06, wall=0.006, segments=24) -> Mesh:
    """A disc and a ring of wall slabs standing on it, as one mesh of convex components."""
    disc = cylinder((0, 0, 0.003), radius, 0.006, segments=segments)
    walls = []
    chord = 2 * radius * math.sin(math.pi / segments) + wall  # slabs overlap at the joints
    for k in range(segments):
        a = 2 * math.pi * (k + 0.5) / segments
        rot = np.array([[math.cos(a), -math.sin(a), 0], [math.sin(a), math.cos(a), 0], [0, 0, 1]])
        c = (radius - wall / 2) * np.array([math.cos(a), math.sin(a), 0]) + [0, 0, height / 2]
        walls.append(box(c, (wall, chord, height), rotation=rot))
    return Mesh.concat([disc] + walls)


def test_bowl_floor_found_rim_dropped():
    m = bowl()
    assert len(components(m)) == 25
    s = support_surfaces(m)
    assert len(s) == 1  # the rim is one ring region, but too narrow to hold anything
    floor = s[0]
    assert floor.z == pytest.approx(0.006)
    assert math.isinf(floor.clearance)
    inner = math.pi * (0.1 - 0.006) ** 2
    assert floor.area == pytest.approx(inner, rel=0.05)
    assert floor.contains(np.array([[0.0, 0.0], [0.099, 0.0]])).tolist() == [True, False]


def test_ring_counter_has_a_hole():
    # a counter top around a sink cut-out: four slabs
    parts = [
        box_between((-0.6, -0.3, 0), (0.6, -0.15, 0.04)),
        box_between((-0.6, 0.15, 0), (0.6, 0.3, 0.04)),
        box_between((-0.6, -0.15, 0), (-0.2, 0.15, 0.04)),
        box_between((0.2, -0.15, 0), (0.6, 0.15, 0.04)),
    ]
    (s,) = support_surfaces(Mesh.concat(parts))
    assert s.area == pytest.approx(1.2 * 0.6 - 0.4 * 0.3)
    assert len(s.holes) == 1
    assert s.contains(np.array([[0.0, 0.0], [0.4, 0.0]])).tolist() == [False, True]


def test_min_area_and_clearance_filters():
    base = box_between((-0.5, -0.5, 0), (0.5, 0.5, 0.02))
    small = box_between((0.3, 0.3, 0.02), (0.34, 0.34, 0.2))  # 16 cm^2 top
    m = Mesh.concat([base, small])
    assert [x.z for x in support_surfaces(m)] == pytest.approx([0.02])  # 16 cm^2 < default
    assert [x.z for x in support_surfaces(m, min_area=0.001)] == pytest.approx([0.02, 0.2])
    # a lid 2 cm above the base: the gap is below the clearance minimum
    lid = box_between((-0.5, -0.5, 0.02 + MIN_CLEARANCE_M / 2), (0.5, 0.5, 0.06))
    s = support_surfaces(Mesh.concat([base, lid]))
    assert [x.z for x in s] == pytest.approx([0.06])


def test_clearance_above_inside_and_gap():
    part = convex_part(box_between((0, 0, 1), (1, 1, 2)))
    pts = np.array([[0.5, 0.5, 0.0], [0.5, 0.5, 1.5], [2.0, 0.5, 0.0], [0.5, 0.5, 2.0]])
    c = clearance_above([part], pts)
    assert c.tolist() == [1.0, 0.0, np.inf, np.inf]


def test_surfaces_of_caches_per_asset():
    a = chair()
    first = surfaces_of(a)
    assert surfaces_of(a) is first
    assert all(isinstance(x, SupportSurface) for x in first)

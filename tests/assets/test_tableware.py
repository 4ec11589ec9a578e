"""Tableware, kitchen appliance and food generators (tableware.py, appliances.py, food.py):
contract, determinism and per-family geometry."""

from __future__ import annotations

from functools import cache

import numpy as np
import pytest

from pair2scene.assets.mesh import Asset, Mesh
from pair2scene.assets.registry import generate, generators

TYPICAL = {
    # (x, y, z) metres, near the AI2-THOR medians (utensils: length along y)
    "bowl": (0.2, 0.2, 0.086), "mug": (0.126, 0.091, 0.104), "cup": (0.114, 0.112, 0.147),
    "plate": (0.237, 0.237, 0.023), "pot": (0.3, 0.24, 0.16), "pan": (0.45, 0.28, 0.06),
    "kettle": (0.2, 0.21, 0.19), "bottle": (0.107, 0.107, 0.254),
    "wine_bottle": (0.088, 0.088, 0.326), "spray_bottle": (0.06, 0.112, 0.245),
    "soap_bottle": (0.121, 0.095, 0.238), "salt_shaker": (0.068, 0.068, 0.111),
    "pepper_shaker": (0.067, 0.067, 0.114), "fork": (0.032, 0.229, 0.026),
    "knife": (0.04, 0.333, 0.02), "butter_knife": (0.025, 0.256, 0.012),
    "spoon": (0.041, 0.207, 0.019), "spatula": (0.064, 0.298, 0.017),
    "ladle": (0.08, 0.285, 0.048), "microwave": (0.608, 0.364, 0.353),
    "toaster": (0.219, 0.362, 0.207), "coffee_machine": (0.35, 0.42, 0.44),
    "apple": (0.101, 0.101, 0.122), "bread": (0.158, 0.291, 0.136),
    "potato": (0.077, 0.117, 0.076), "tomato": (0.123, 0.126, 0.102),
    "egg": (0.054, 0.054, 0.079), "lettuce": (0.151, 0.24, 0.153),
    "aluminum_foil": (0.238, 0.065, 0.035), "dish_sponge": (0.074, 0.139, 0.026),
    "soap_bar": (0.055, 0.091, 0.025), "scrub_brush": (0.132, 0.134, 0.476),
    "plunger": (0.148, 0.148, 0.539), "candle": (0.051, 0.051, 0.168),
    "vase": (0.175, 0.175, 0.208),
}  # fmt: skip
CATEGORIES = sorted(TYPICAL)
SCALES = ((1.0, 1.0, 1.0), (0.5, 0.5, 0.5), (1.7, 1.3, 1.5))
"""Typical size, half of it, and a bigger, stretched one (proportions must adapt)."""
HOLLOW = {"bowl": 0.6, "cup": 0.5, "mug": 0.7, "pot": 0.75, "pan": 0.5, "vase": 0.7}
"""Hollow vessels and the least free depth above the cavity floor, as a fraction of height."""
UTENSIL_ENDS = {
    "fork": ("tine_", "handle"), "knife": ("blade", "handle"),
    "butter_knife": ("blade", "handle"), "spoon": ("bowl", "handle"),
    "spatula": ("blade", "handle"), "ladle": ("bowl_", "handle"),
}  # fmt: skip
"""Part-name prefixes of a utensil's working end (at +y) and its handle (at -y)."""
SEED = 7
FAMILY_MODULES = {f"pair2scene.assets.generators.{m}" for m in ("tableware", "appliances", "food")}
"""The modules whose categories this file covers."""


@cache
def _asset(category: str, style: int, scale: int = 0, seed: int = SEED) -> Asset:
    size = np.asarray(TYPICAL[category]) * SCALES[scale]
    return generate(category, size, seed, style=style)


def _inside(asset: Asset, points: np.ndarray, names: str = "") -> np.ndarray:
    """(N,) bool: each point (N, 3) lies inside some part (whose name starts with names)."""
    pts = np.atleast_2d(np.asarray(points, dtype=float))
    hit = np.zeros(len(pts), dtype=bool)
    for part in asset.parts:
        if not part.name.startswith(names):
            continue
        m = part.mesh
        d = np.einsum("ij,ij->i", m.face_normals, m.triangles[:, 0])
        hit |= np.all(pts @ m.face_normals.T - d <= 1e-9, axis=1)
    return hit


def _parts(asset: Asset, prefix: str) -> Mesh:
    meshes = [p.mesh for p in asset.parts if p.name.startswith(prefix)]
    assert meshes, f"{asset.category}: no part named {prefix}*"
    return Mesh.concat(meshes)


def _variants(category: str) -> int:
    return generators()[category].variants


def test_registers_exactly_the_family():
    mine = {c for c, g in generators().items() if g.fn.__module__ in FAMILY_MODULES}
    assert mine == set(CATEGORIES)
    assert all(_variants(c) >= 2 for c in CATEGORIES)


@pytest.mark.parametrize("category", CATEGORIES)
def test_contract(category):
    for style in range(_variants(category)):
        for scale in range(len(SCALES)):
            asset = _asset(category, style, scale)
            size = np.asarray(TYPICAL[category]) * SCALES[scale]
            np.testing.assert_allclose(asset.mesh.bounds, [-size / 2, size / 2], atol=1e-6)
            assert 0 < len(asset.parts) < 60
            for part in asset.parts:
                assert part.name, category
                assert part.mesh.is_watertight(), (category, style, scale, part.name)
                assert part.mesh.is_convex(), (category, style, scale, part.name)
                assert part.mesh.volume > 0, (category, style, scale, part.name)


@pytest.mark.parametrize("category", CATEGORIES)
def test_deterministic_and_styles_differ(category):
    a = _asset(category, 0)
    b = generate(category, TYPICAL[category], SEED, style=0)
    assert all(np.array_equal(p.mesh.vertices, q.mesh.vertices) for p, q in zip(a.parts, b.parts))
    meshes = [_asset(category, s).mesh for s in range(_variants(category))]
    for i in range(len(meshes)):
        for j in range(i + 1, len(meshes)):
            same = meshes[i].vertices.shape == meshes[j].vertices.shape and np.allclose(
                meshes[i].vertices, meshes[j].vertices
            )
            assert not same, (category, i, j)


@pytest.mark.parametrize("category", sorted(HOLLOW))
def test_vessels_are_hollow(category):
    for style in range(_variants(category)):
        for scale in range(len(SCALES)):
            asset = _asset(category, style, scale)
            h = asset.size[2]
            walls = _parts(asset, "wall").bounds
            cx, cy = walls.mean(0)[:2]
            zs = np.linspace(h / 2 - 1e-4, -h / 2 + 1e-4, 400)
            column = _inside(asset, np.c_[np.full_like(zs, cx), np.full_like(zs, cy), zs])
            assert column.any(), (category, style, scale, "no floor under the cavity")
            depth = (h / 2 - zs[np.argmax(column)]) / h
            assert depth >= HOLLOW[category], (category, style, scale, depth)
            # walls all around: every horizontal ray from the cavity centre hits a wall
            z = 0.5 * (walls[0, 2] + walls[1, 2])
            r = np.linspace(0.0, max(asset.size[:2]), 200)
            for a in np.linspace(0, 2 * np.pi, 8, endpoint=False):
                ray = np.c_[cx + r * np.cos(a), cy + r * np.sin(a), np.full_like(r, z)]
                assert _inside(asset, ray, "wall").any(), (category, style, scale, a)


def test_plate_is_shallow_with_a_rim():
    for style in range(_variants("plate")):
        for scale in range(len(SCALES)):
            asset = _asset("plate", style, scale)
            sx, _, h = asset.size
            assert h < 0.2 * sx
            # the centre is a recessed floor; the rim reaches the top at the edge
            assert not _inside(asset, [0, 0, h / 2 - 0.25 * h]).any()
            assert _inside(asset, [0, 0, -h / 2 + 0.3 * h]).any()
            assert _inside(asset, [0.93 * sx / 2, 0, h / 2 - 0.1 * h]).any()


def test_handles_sit_where_they_should():
    for style in range(2):
        for scale in range(len(SCALES)):
            mug = _asset("mug", style, scale)
            handle = _parts(mug, "handle").bounds
            assert handle[1, 0] == pytest.approx(mug.size[0] / 2)
            assert handle[0, 0] > 0.0
            pot = _asset("pot", style, scale)
            assert _parts(pot, "handle_right").bounds[1, 0] == pytest.approx(pot.size[0] / 2)
            assert _parts(pot, "handle_left").bounds[0, 0] == pytest.approx(-pot.size[0] / 2)
            pan = _asset("pan", style, scale)
            assert _parts(pan, "handle").bounds[1, 0] == pytest.approx(pan.size[0] / 2)
            assert _parts(pan, "wall").bounds.mean(0)[0] < 0.0
            kettle = _asset("kettle", style, scale)
            assert _parts(kettle, "spout").bounds[1, 1] == pytest.approx(kettle.size[1] / 2)
            assert (
                _parts(kettle, "handle").bounds.mean(0)[1]
                < _parts(kettle, "spout").bounds.mean(0)[1]
            )


@pytest.mark.parametrize("category", sorted(UTENSIL_ENDS))
def test_utensils_lie_along_y(category):
    head, handle = UTENSIL_ENDS[category]
    for style in range(_variants(category)):
        for scale in range(len(SCALES)):
            asset = _asset(category, style, scale)
            assert _parts(asset, head).bounds.mean(0)[1] > 0.1 * asset.size[1]
            assert _parts(asset, handle).bounds.mean(0)[1] < 0.0
            assert _parts(asset, head).bounds[1, 1] == pytest.approx(asset.size[1] / 2)


def test_pan_handle_follows_the_long_side():
    # AI2-THOR pans are deeper than wide: the handle then points to +y
    for style in range(2):
        asset = generate("pan", (0.279, 0.43, 0.049), 0, style=style)
        assert _parts(asset, "handle").bounds[1, 1] == pytest.approx(0.43 / 2)
        walls = _parts(asset, "wall").bounds
        assert walls.mean(0)[1] < 0.0
        assert np.ptp(walls[:, 0]) == pytest.approx(0.279)


def test_knife_on_its_edge_when_the_box_is_tall():
    # AI2-THOR stores knives 1.4 cm wide and 4.7 cm high: the blade must stand up
    asset = generate("knife", (0.014, 0.333, 0.047), 0, style=0)
    ext = np.ptp(_parts(asset, "blade").bounds, axis=0)
    assert ext[2] > 2 * ext[0]
    flat = _asset("knife", 0)
    ext = np.ptp(_parts(flat, "blade").bounds, axis=0)
    assert ext[0] > 2 * ext[2]


def test_front_details_face_plus_y():
    for style in range(2):
        mw = _asset("microwave", style)
        body = _parts(mw, "body").bounds
        assert body[1, 1] < mw.size[1] / 2
        for name in ("window", "door_", "panel"):
            assert _parts(mw, name).bounds[0, 1] >= body[1, 1] - 1e-9
        assert _parts(mw, "panel").bounds.mean(0)[0] < 0.0  # the viewer's right
        assert _parts(mw, "door_").bounds.mean(0)[0] > 0.0
        for bottle in ("spray_bottle", "soap_bottle"):
            a = _asset(bottle, style)
            assert _parts(a, "nozzle").bounds[1, 1] == pytest.approx(a.size[1] / 2)
        cm = _asset("coffee_machine", style)
        front = _parts(cm, "carafe" if style == 0 else "portafilter_handle").bounds
        assert front.mean(0)[1] > 0.0


def _top_area(asset: Asset, z: float, tol: float = 1e-6) -> float:
    """Area of upward faces at height z (horizontal resting surfaces)."""
    m = asset.mesh
    up = (m.face_normals[:, 2] > 1 - 1e-6) & (np.abs(m.triangles[:, :, 2] - z).max(1) < tol)
    return float(m.face_areas[up].sum())


@pytest.mark.parametrize(
    "category", ["microwave", "coffee_machine", "dish_sponge", "aluminum_foil", "soap_bar"]
)
def test_flat_tops_hold_things(category):
    for style in range(_variants(category)):
        asset = _asset(category, style)
        sx, sy, h = asset.size
        if category == "aluminum_foil" and style == 0:
            continue  # an open carton: its top is the lid edge
        if category == "soap_bar" and style == 1:
            continue  # an oval pebble: its flat top is small
        area = _top_area(asset, h / 2)
        assert area > (0.3 if category == "soap_bar" else 0.4) * sx * sy, (category, style, area)


@pytest.mark.parametrize("sizes", [(0.219, 0.362, 0.207), (0.36, 0.22, 0.2)])
def test_toaster_slots_are_open_and_lever_faces_front(sizes):
    for style in range(2):
        asset = generate("toaster", sizes, 0, style=style)
        sx, sy, h = asset.size
        gx, gy = np.meshgrid(np.linspace(-0.3, 0.3, 25) * sx, np.linspace(-0.3, 0.3, 25) * sy)
        top = np.c_[gx.ravel(), gy.ravel(), np.full(gx.size, h / 2 - 0.03 * h)]
        free = ~_inside(asset, top)
        assert 0.1 < free.mean() < 0.7, (style, free.mean())
        # under the slots the body is solid (bread rests on it)
        assert _inside(asset, top[free] - (0, 0, 0.4 * h)).all()
        assert _parts(asset, "lever").bounds[1, 1] == pytest.approx(sy / 2)


@pytest.mark.parametrize(
    "category", ["apple", "tomato", "potato", "egg", "lettuce", "bread", "soap_bar"]
)
def test_food_is_solid_and_fills_its_box(category):
    for style in range(_variants(category)):
        asset = _asset(category, style)
        g = (
            np.stack(np.meshgrid(*[np.linspace(-0.45, 0.45, 12)] * 3), -1).reshape(-1, 3)
            * asset.size
        )
        fill = _inside(asset, g).mean()
        assert _inside(asset, [0.0, 0.0, 0.0]).all()
        assert fill > 0.4, (category, style, fill)


def test_bottles_have_a_narrow_neck():
    for category in ("bottle", "wine_bottle", "soap_bottle"):
        for style in range(2):
            asset = _asset(category, style)
            sx, _, h = asset.size
            y = _parts(asset, "body").bounds.mean(0)[1]
            xs = np.linspace(-sx / 2, sx / 2, 101)

            def width(z, asset=asset, y=y, xs=xs):
                return _inside(asset, np.c_[xs, np.full_like(xs, y), np.full_like(xs, z)]).mean()

            assert width(-0.2 * h) > 0.9
            assert width(0.38 * h) < 0.5, (category, style)


def test_salt_and_pepper_differ():
    for style in range(2):
        salt, pepper = _asset("salt_shaker", style), _asset("pepper_shaker", style)
        assert len(salt.parts) != len(pepper.parts) or not np.allclose(
            salt.mesh.vertices, pepper.mesh.vertices
        )


def test_tall_and_flat_things():
    for style in range(2):
        candle = _asset("candle", style)
        assert _parts(candle, "wick").bounds[1, 2] > 0.3 * candle.size[2]
        plunger = _asset("plunger", style)
        assert _parts(plunger, "cup").bounds[0, 2] < -0.4 * plunger.size[2]
        assert _parts(plunger, "handle").bounds[1, 2] == pytest.approx(plunger.size[2] / 2)
        brush = _asset("scrub_brush", style)  # a tall box: a standing brush
        assert _parts(brush, "handle").bounds[1, 2] > 0.3 * brush.size[2]
        hand = generate("scrub_brush", (0.07, 0.15, 0.06), 0, style=style)
        assert _parts(hand, "bristles").bounds[0, 2] == pytest.approx(-0.03)
        foil = _asset("aluminum_foil", style)
        if style == 0:
            assert np.ptp(_parts(foil, "roll").bounds[:, 0]) > 0.8 * foil.size[0]


@pytest.mark.parametrize("style", [0, 1])
def test_a_fork_rests_on_its_tines_and_the_end_of_its_handle(style):
    """Its handle arches over the table and comes down at its end: the fork touches the
    bottom of its box at both ends, so it rests where it is put (with the handle's end
    raised to the box top it tipped over its head in the simulation)."""
    for seed in range(4):
        fork = generate("fork", [0.03, 0.21, 0.031], seed, style=style)
        bottom = fork.mesh.vertices[:, 2].min()
        ends = {}
        for part in fork.parts:
            v = part.mesh.vertices
            if part.name.startswith("tine_") or part.name == "handle":
                assert v[:, 2].min() == pytest.approx(bottom, abs=1e-6), part.name
                ends[part.name[:4]] = v[:, 1]
        assert ends["tine"].min() > 0.05 and ends["hand"].min() < -0.1  # the two ends
        top = fork.mesh.vertices[:, 2].max()
        arch = [p for p in fork.parts if p.name == "handle_arch"][0].mesh.vertices
        assert arch[:, 2].max() == pytest.approx(top, abs=1e-6)  # highest in between


def test_a_romaine_lettuce_lies_on_a_flat_underside():
    """Lying on its side, a romaine head's outer leaves are pressed flat underneath: its
    lowest vertices span a patch, not the points of round leaves it rolled on."""
    for seed in range(4):
        head = generate("lettuce", [0.13, 0.243, 0.13], seed, style=1)
        v = head.mesh.vertices
        bottom = v[v[:, 2] < v[:, 2].min() + 1e-6]
        assert len(bottom) >= 6
        assert np.ptp(bottom[:, 0]) > 0.02 and np.ptp(bottom[:, 1]) > 0.02

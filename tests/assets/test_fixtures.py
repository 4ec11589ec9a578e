"""Fixture, lamp, wall-object and plant generators: contract and shape checks."""

from __future__ import annotations

import numpy as np
import pytest

from pair2scene.assets.mesh import Asset, Mesh, Part
from pair2scene.assets.registry import generate, generators

ATOL = 1e-6
MODULES = {f"pair2scene.assets.generators.{m}" for m in ("fixtures", "lighting")}
"""The modules whose categories this file covers (the ceiling, floor and wall lamps are in
lighting.py)."""

# three sizes per category: a typical one and two awkward ones (AI2-THOR's 5th/95th
# percentiles where the data has the category)
SIZES: dict[str, list[tuple[float, float, float]]] = {
    "sink": [(0.66, 0.51, 0.15), (0.6, 0.5, 0.95), (1.2, 0.55, 0.85)],
    "sink_basin": [(0.53, 0.35, 0.13), (0.23, 0.2, 0.08), (0.8, 0.5, 0.18)],
    "toilet": [(0.53, 0.97, 1.04), (0.4, 0.65, 0.75), (0.45, 0.55, 0.8)],
    "bathtub": [(1.7, 0.75, 0.6), (1.35, 1.78, 0.6), (0.9, 0.8, 0.45)],
    "bathtub_basin": [(1.2, 0.91, 0.42), (0.49, 0.44, 0.31), (2.1, 1.9, 0.5)],
    "shower": [(0.9, 0.9, 2.0), (0.9, 0.06, 1.9), (0.2, 1.2, 1.9)],
    "towel_holder": [(0.17, 0.05, 0.21), (0.66, 0.11, 0.21), (0.6, 0.1, 0.04)],
    "toilet_paper_hanger": [(0.23, 0.1, 0.08), (0.19, 0.06, 0.04), (0.29, 0.13, 0.18)],
    "faucet": [(0.27, 0.24, 0.21), (0.06, 0.17, 0.11), (0.58, 0.37, 0.43)],
    "stove": [(0.76, 0.65, 0.92), (0.6, 0.52, 0.06), (0.22, 0.22, 0.03)],
    "stove_knob": [(0.07, 0.07, 0.03), (0.075, 0.082, 0.082), (0.05, 0.03, 0.05)],
    "ceiling_lamp": [(0.45, 0.45, 0.7), (0.6, 0.6, 0.15), (1.2, 0.9, 1.0)],
    "floor_lamp": [(0.52, 0.51, 1.89), (0.4, 0.4, 1.2), (0.66, 0.61, 2.08)],
    "wall_lamp": [(0.18, 0.22, 0.3), (0.4, 0.15, 0.2), (0.12, 0.3, 0.5)],
    "painting": [(0.82, 0.03, 0.6), (0.46, 0.02, 0.09), (1.18, 0.08, 0.9)],
    "mirror": [(0.54, 0.07, 0.85), (1.68, 0.04, 1.19), (0.3, 0.03, 0.48)],
    "curtains": [(0.96, 0.21, 2.17), (3.27, 0.3, 2.49), (0.5, 0.07, 0.87)],
    "blinds": [(1.1, 0.03, 0.2), (1.1, 0.05, 1.4), (2.4, 0.08, 2.2)],
    "house_plant": [(0.37, 0.38, 0.65), (0.22, 0.25, 0.47), (0.6, 0.56, 1.07)],
    "vacuum_cleaner": [(0.36, 0.31, 1.01), (0.4, 0.3, 0.3), (0.3, 0.45, 0.7)],
}
CATEGORIES = sorted(SIZES)
CASES = [
    (cat, size, style)
    for cat in CATEGORIES
    for size in SIZES[cat]
    for style in range(generators()[cat].variants)
]


def make(cat: str, size, style: int, seed: int = 7) -> Asset:
    return generate(cat, size, rng=seed, style=style)


def named(asset: Asset, prefix: str) -> list[Part]:
    """Parts whose name starts with ``prefix``."""
    return [p for p in asset.parts if p.name.startswith(prefix)]


def part(asset: Asset, name: str) -> Part:
    (p,) = [p for p in asset.parts if p.name == name]
    return p


def bounds(parts: list[Part]) -> np.ndarray:
    """(2, 3) joint bounds of parts."""
    return Mesh.concat([p.mesh for p in parts]).bounds


def occupied(asset: Asset, point) -> bool:
    """Whether ``point`` (3,) lies inside any (convex) part."""
    p = np.asarray(point, dtype=float)
    for q in asset.parts:
        m = q.mesh
        d = np.einsum("ij,ij->i", m.face_normals, m.triangles[:, 0])
        if np.all(m.face_normals @ p - d <= 1e-9):
            return True
    return False


def up_area_at(parts: list[Part], z: float, tol: float = 1e-6) -> float:
    """Area of upward-facing faces at height z."""
    total = 0.0
    for p in parts:
        m = p.mesh
        at = (m.face_normals[:, 2] > 0.999) & (np.abs(m.triangles[:, :, 2].mean(1) - z) < tol)
        total += float(m.face_areas[at].sum())
    return total


# -- contract ----------------------------------------------------------------------------
def test_registers_exactly_these_categories():
    mine = {c for c, g in generators().items() if g.fn.__module__ in MODULES}
    mine.discard("table_lamp")  # in lighting.py too, but tested with the household objects
    assert mine == set(CATEGORIES)
    for cat in CATEGORIES:
        assert generators()[cat].variants >= 2


@pytest.mark.parametrize("cat,size,style", CASES)
def test_fills_box_with_closed_convex_parts(cat, size, style):
    asset = make(cat, size, style)
    half = np.asarray(size) / 2
    np.testing.assert_allclose(asset.mesh.bounds, [-half, half], atol=ATOL)
    assert 0 < len(asset.parts) < 60
    names = [p.name for p in asset.parts]
    assert len(set(names)) == len(names), "part names are unique"
    for p in asset.parts:
        assert p.mesh.is_watertight(), p.name
        assert p.mesh.is_convex(), p.name
        assert p.mesh.volume > 0, p.name


@pytest.mark.parametrize("cat", CATEGORIES)
def test_survives_odd_sizes(cat):
    """Boxes from 2 cm to 3 m along any axis still give closed convex parts that fill them."""
    rng = np.random.default_rng(11)
    for k in range(8):
        size = np.exp(rng.uniform(np.log(0.02), np.log(3.0), 3))
        a = generate(cat, size, rng=k, style=k % generators()[cat].variants)
        np.testing.assert_allclose(a.mesh.bounds, [-size / 2, size / 2], atol=ATOL)
        for p in a.parts:
            assert p.mesh.is_watertight() and p.mesh.is_convex() and p.mesh.volume > 0, p.name


@pytest.mark.parametrize("cat", CATEGORIES)
def test_deterministic_and_styles_differ(cat):
    size = SIZES[cat][0]
    n = generators()[cat].variants
    meshes = []
    for style in range(n):
        a, b = make(cat, size, style, seed=3), make(cat, size, style, seed=3)
        assert [p.name for p in a.parts] == [p.name for p in b.parts]
        np.testing.assert_array_equal(a.mesh.vertices, b.mesh.vertices)
        meshes.append(a.mesh)
    for i in range(n):
        for j in range(i + 1, n):
            same = meshes[i].vertices.shape == meshes[j].vertices.shape and np.allclose(
                meshes[i].vertices, meshes[j].vertices
            )
            assert not same, f"{cat}: styles {i} and {j} build the same mesh"


# -- sinks, toilets, tubs, showers ---------------------------------------------------------
def _cavity_is_open(asset: Asset, prefix: str) -> None:
    """The hollow above the floor of ``prefix`` is free and bounded by taller walls."""
    floor = bounds(named(asset, f"{prefix}_floor"))
    walls = bounds(named(asset, f"{prefix}_wall"))
    rim, floor_top = walls[1, 2], floor[1, 2]
    assert rim > floor_top
    centre = (floor[0] + floor[1]) / 2
    for f in (0.2, 0.5, 0.9):
        assert not occupied(asset, (centre[0], centre[1], floor_top + f * (rim - floor_top)))
    assert occupied(asset, (centre[0], centre[1], floor_top - 1e-4))


@pytest.mark.parametrize("size", SIZES["sink"])
@pytest.mark.parametrize("style", [0, 1])
def test_sink_basin_faucet_and_support(size, style):
    a = make("sink", size, style)
    sx, sy, sz = size
    _cavity_is_open(a, "basin")
    faucet = bounds(named(a, "faucet"))
    basin = bounds(named(a, "basin"))
    assert faucet[1, 2] == pytest.approx(sz / 2, abs=ATOL), "the faucet is the top"
    assert faucet[0, 1] < basin[0, 1], "the faucet stands behind the basin (-y)"
    spout = bounds(named(a, "faucet_spout"))
    assert spout[1, 1] > basin[0, 1], "the spout reaches over the basin"
    # an upward deck or counter around the basin rim carries the faucet
    rim = basin[1, 2]
    deck = named(a, "deck") + named(a, "counter")
    assert up_area_at(deck, rim) > 0.02 * sx * sy
    if sz > 0.45:
        stand = named(a, "pedestal") if style == 0 else named(a, "cabinet") + named(a, "plinth")
        assert bounds(stand)[0, 2] == pytest.approx(-sz / 2, abs=ATOL)
        assert bounds(stand)[1, 2] <= basin[0, 2] + 1e-6
    if style == 1 and sz > 0.45:
        doors = named(a, "door")
        assert doors and bounds(doors)[1, 1] > 0.4 * sy


@pytest.mark.parametrize("size", SIZES["sink_basin"])
@pytest.mark.parametrize("style", [0, 1])
def test_sink_basin_is_hollow(size, style):
    _cavity_is_open(make("sink_basin", size, style), "basin")


@pytest.mark.parametrize("size", SIZES["toilet"])
@pytest.mark.parametrize("style", [0, 1])
def test_toilet_bowl_front_tank_back(size, style):
    a = make("toilet", size, style)
    sx, sy, sz = size
    seat = bounds([part(a, "seat")])
    assert 0.3 * sz < seat[1, 2] + sz / 2 < 0.55 * sz, "seat at sitting height"
    assert (seat[0, 1] + seat[1, 1]) / 2 > 0, "bowl toward +y"
    assert seat[1, 1] == pytest.approx(sy / 2, abs=ATOL)
    assert up_area_at([part(a, "seat")], seat[1, 2]) > 0.3 * (seat[1, 0] - seat[0, 0]) * (
        seat[1, 1] - seat[0, 1]
    )
    tank = bounds(named(a, "tank") if style == 0 else named(a, "cistern"))
    assert tank[0, 1] == pytest.approx(-sy / 2, abs=ATOL)
    assert tank[1, 1] < 0 and tank[1, 2] > 0.95 * sz / 2 - 0.02


@pytest.mark.parametrize("cat", ["bathtub", "bathtub_basin"])
@pytest.mark.parametrize("style", [0, 1])
def test_tubs_are_hollow(cat, style):
    prefix = "tub" if cat == "bathtub" else "basin"
    for size in SIZES[cat]:
        a = make(cat, size, style)
        _cavity_is_open(a, prefix)
        if cat == "bathtub" and style == 1:
            feet = named(a, "foot")
            assert len(feet) == 4
            assert bounds(feet)[0, 2] == pytest.approx(-size[2] / 2, abs=ATOL)
            assert bounds(named(a, "tub_floor"))[0, 2] > -size[2] / 2 + 0.02


@pytest.mark.parametrize("style", [0, 1])
def test_shower_cubicle(style):
    sx, sy, sz = SIZES["shower"][0]
    a = make("shower", (sx, sy, sz), style)
    tray = bounds([part(a, "tray")])
    np.testing.assert_allclose(tray[:, :2], [[-sx / 2, -sy / 2], [sx / 2, sy / 2]], atol=ATOL)
    assert tray[0, 2] == pytest.approx(-sz / 2, abs=ATOL)
    assert not occupied(a, (0.0, 0.0, 0.0)), "room to stand inside"
    head = bounds([part(a, "head")])
    assert head[0, 2] > 0.3 * sz and head[0, 1] < 0, "head high up, off the -y wall"
    front = named(a, "glass_front") if style == 0 else named(a, "curtain")
    assert bounds(front)[1, 1] > 0.4 * sy


@pytest.mark.parametrize("style", [0, 1])
def test_shower_panel_follows_the_thin_axis(style):
    for size in SIZES["shower"][1:]:
        a = make("shower", size, style)
        sheet = named(a, "glass") if style == 0 else named(a, "curtain")
        b = bounds(sheet)
        long_axis = 0 if size[0] > size[1] else 1
        assert b[1, long_axis] - b[0, long_axis] > 0.8 * size[long_axis]
        assert b[1, 2] - b[0, 2] > 0.8 * size[2]
        assert b[1, 1 - long_axis] - b[0, 1 - long_axis] <= size[1 - long_axis] + ATOL


# -- small fixtures ------------------------------------------------------------------------
@pytest.mark.parametrize("style", [0, 1])
def test_towel_holder_hangs_on_the_wall(style):
    for size in SIZES["towel_holder"]:
        a = make("towel_holder", size, style)
        on_wall = [p for p in a.parts if p.mesh.bounds[0, 1] < -size[1] / 2 + 1e-6]
        assert on_wall and all(p.name.startswith(("plate", "rosette")) for p in on_wall)
        held = named(a, "rail") + named(a, "ring")
        assert bounds(held)[1, 1] == pytest.approx(size[1] / 2, abs=ATOL)


@pytest.mark.parametrize("style", [0, 1])
def test_toilet_paper_hanger_on_the_wall(style):
    for size in SIZES["toilet_paper_hanger"]:
        a = make("toilet_paper_hanger", size, style)
        plate = bounds(named(a, "back_plate") + named(a, "wall_plate"))
        assert plate[0, 1] == pytest.approx(-size[1] / 2, abs=ATOL)
        spindle = bounds([part(a, "spindle")])
        assert spindle[0, 1] > plate[1, 1] - 1e-9
        assert spindle[1, 0] - spindle[0, 0] > 0.5 * size[0]


@pytest.mark.parametrize("style", [0, 1])
def test_faucet_spout_points_forward(style):
    for size in SIZES["faucet"]:
        a = make("faucet", size, style)
        spout = bounds(named(a, "spout"))
        assert spout[1, 1] == pytest.approx(size[1] / 2, abs=ATOL)
        plate = bounds([part(a, "plate")])
        assert plate[0, 2] == pytest.approx(-size[2] / 2, abs=ATOL)
        assert (plate[0, 1] + plate[1, 1]) / 2 < 0, "mounted at the back"


@pytest.mark.parametrize("style", [0, 1])
def test_stove_burners_on_top(style):
    big, flat, single = SIZES["stove"]
    for size in (big, flat):
        a = make("stove", size, style)
        burners = [p for p in a.parts if p.name[:-1] == "burner_"]
        assert len(burners) == 4
        top = bounds([part(a, "cooktop")])[1, 2]
        assert top > size[2] / 2 - 0.04
        assert up_area_at([part(a, "cooktop")], top) > 0.5 * size[0] * size[1]
        for b in burners:
            lo, hi = b.mesh.bounds
            assert lo[2] >= top - 1e-9 and hi[2] <= size[2] / 2 + 1e-9
        xs = sorted(float(b.mesh.vertices[:, 0].mean()) for b in burners)
        assert xs[1] < 0 < xs[2], "two burners each side"
    tall = make("stove", big, style)
    body = named(tall, "oven_door") if style == 0 else named(tall, "door")
    assert body and bounds(body)[0, 2] < 0 and bounds(body)[1, 1] > 0.4 * big[1]
    # a footprint the size of one burner is a single burner, centred, on top
    one = make("stove", single, style)
    assert not [p for p in one.parts if p.name[:-1] == "burner_"]
    burner = bounds([part(one, "burner")])
    np.testing.assert_allclose((burner[0, :2] + burner[1, :2]) / 2, 0.0, atol=1e-9)
    assert burner[1, 2] > 0


def test_stove_knob_axis():
    top = make("stove_knob", (0.07, 0.07, 0.03), 0)
    assert bounds([part(top, "base")])[0, 2] == pytest.approx(-0.015, abs=ATOL)
    front = make("stove_knob", (0.075, 0.082, 0.082), 1)
    skirt = bounds([part(front, "skirt")])
    assert skirt[0, 1] == pytest.approx(-0.041, abs=ATOL), "mounted on a panel at -y"
    assert skirt[1, 1] < 0.0
    pointer = bounds([part(front, "pointer")])
    assert pointer[0, 2] > -1e-9, "the pointer marks the top"


# -- lamps ---------------------------------------------------------------------------------
@pytest.mark.parametrize("style", [0, 1, 2])
def test_ceiling_lamp_hangs_from_canopy(style):
    for size in SIZES["ceiling_lamp"]:
        a = make("ceiling_lamp", size, style)
        canopy = bounds([part(a, "canopy")])
        assert canopy[1, 2] == pytest.approx(size[2] / 2, abs=ATOL)
        np.testing.assert_allclose((canopy[0, :2] + canopy[1, :2]) / 2, 0.0, atol=1e-6)
        assert canopy[1, 0] - canopy[0, 0] < 0.5 * size[0]
        rest = [p for p in a.parts if p.name not in ("canopy", "rod")]
        assert bounds(rest)[1, 2] < canopy[0, 2] + 1e-9, "everything hangs below the canopy"


@pytest.mark.parametrize("style", [0, 1, 2])
def test_floor_lamp_base_pole_shade(style):
    for size in SIZES["floor_lamp"]:
        a = make("floor_lamp", size, style)
        shade = bounds([part(a, "shade")])
        assert shade[1, 2] == pytest.approx(size[2] / 2, abs=0.01 * size[2])
        assert shade[1, 0] - shade[0, 0] == pytest.approx(size[0], abs=ATOL)
        feet = named(a, "base") + named(a, "leg")
        assert bounds(feet)[0, 2] == pytest.approx(-size[2] / 2, abs=ATOL)
        # halfway up only the slim pole passes
        mid = [p for p in a.parts if p.mesh.bounds[0, 2] < 0 < p.mesh.bounds[1, 2]]
        assert [p.name for p in mid] == ["pole"]
        assert np.ptp(part(a, "pole").mesh.vertices[:, 0]) < 0.15 * size[0]


@pytest.mark.parametrize("style", [0, 1, 2])
def test_wall_lamp_bracket_at_back(style):
    for size in SIZES["wall_lamp"]:
        a = make("wall_lamp", size, style)
        plate = bounds([part(a, "back_plate")])
        assert plate[0, 1] == pytest.approx(-size[1] / 2, abs=ATOL)
        assert plate[1, 1] < 0
        shade = bounds([part(a, "shade")])
        assert shade[1, 1] == pytest.approx(size[1] / 2, abs=ATOL)


# -- wall objects --------------------------------------------------------------------------
@pytest.mark.parametrize("cat,face", [("painting", "canvas"), ("mirror", "glass")])
@pytest.mark.parametrize("style", [0, 1, 2])
def test_picture_faces_the_room(cat, face, style):
    for size in SIZES[cat]:
        sx, sy, sz = size
        a = make(cat, size, style)
        assert min(p.mesh.bounds[0, 1] for p in a.parts) == pytest.approx(-sy / 2, abs=ATOL)
        sheet = bounds([part(a, face)])
        assert sheet[1, 0] - sheet[0, 0] > 0.7 * sx and sheet[1, 2] - sheet[0, 2] > 0.7 * sz
        frame = named(a, "frame")
        if frame:
            assert sheet[1, 1] < bounds(frame)[1, 1], "recessed behind its frame"
        # a ray from the room toward the wall through the centre hits the picture first
        y_hit = max(
            p.mesh.bounds[1, 1]
            for p in a.parts
            if occupied(Asset(cat, a.size, (p,)), (0.0, p.mesh.bounds[1, 1] - 1e-6, 0.0))
        )
        assert y_hit == pytest.approx(sheet[1, 1])


@pytest.mark.parametrize("style", [0, 1])
def test_curtains_rod_and_panels(style):
    for size in SIZES["curtains"]:
        sx, sy, sz = size
        a = make("curtains", size, style)
        rod = bounds([part(a, "rod")])
        assert rod[1, 2] > sz / 2 - 0.05
        panels = named(a, "panel")
        assert bounds(panels)[0, 2] == pytest.approx(-sz / 2, abs=ATOL)
        left, right = bounds(named(a, "panel_left")), bounds(named(a, "panel_right"))
        gap = right[0, 0] - left[1, 0]
        if style == 0:
            assert gap > 0.3 * sx, "drawn open"
        else:
            assert abs(gap) < 0.02 * sx, "drawn closed"
        brackets = bounds(named(a, "bracket"))
        assert brackets[0, 1] == pytest.approx(-sy / 2, abs=ATOL)


@pytest.mark.parametrize("style", [0, 1, 2])
def test_blinds_under_a_head_rail(style):
    for size in SIZES["blinds"]:
        sx, sy, sz = size
        a = make("blinds", size, style)
        rail = bounds([part(a, "head_rail")])
        np.testing.assert_allclose(rail[1], np.asarray(size) / 2, atol=ATOL)
        assert rail[1, 0] - rail[0, 0] == pytest.approx(sx, abs=ATOL)
        covering = {0: "slat", 1: "vane", 2: "fabric"}[style]
        cover = named(a, covering)
        assert bounds(cover)[1, 2] <= rail[0, 2] + 1e-9
        if style == 0:
            assert len(cover) >= 2
            z = sorted(float(p.mesh.vertices[:, 2].mean()) for p in cover)
            assert np.allclose(np.diff(z), z[1] - z[0]), "evenly spaced slats"
        if style == 1:
            assert len(cover) == max(2, round(sx / 0.09))


# -- floor objects -------------------------------------------------------------------------
@pytest.mark.parametrize("style", [0, 1, 2])
def test_house_plant_pot_and_foliage(style):
    for size in SIZES["house_plant"]:
        sx, sy, sz = size
        a = make("house_plant", size, style)
        pot = bounds(named(a, "pot"))
        assert pot[0, 2] == pytest.approx(-sz / 2, abs=ATOL)
        np.testing.assert_allclose((pot[0, :2] + pot[1, :2]) / 2, 0.0, atol=0.01 * sx)
        assert pot[1, 0] - pot[0, 0] < 0.8 * sx
        foliage = [p for p in a.parts if p.name.startswith(("leaves", "leaf", "crown"))]
        assert len(foliage) >= 4
        assert bounds(foliage)[1, 2] == pytest.approx(sz / 2, abs=ATOL)
        assert all(float(p.mesh.vertices[:, 2].mean()) > pot[1, 2] for p in foliage)


@pytest.mark.parametrize("style", [0, 1])
def test_vacuum_cleaner_front_is_the_floor_nozzle(style):
    for size in SIZES["vacuum_cleaner"]:
        sx, sy, sz = size
        a = make("vacuum_cleaner", size, style)
        head = bounds(named(a, "floor_head") + named(a, "nozzle"))
        assert head[0, 2] == pytest.approx(-sz / 2, abs=ATOL)
        assert head[1, 1] == pytest.approx(sy / 2, abs=ATOL)
        wheels = bounds(named(a, "wheel"))
        assert wheels[0, 2] == pytest.approx(-sz / 2, abs=ATOL) and wheels[1, 1] < 0.1 * sy
        grip = bounds(named(a, "grip") + named(a, "wand") + named(a, "hose"))
        assert grip[1, 2] > 0.4 * sz

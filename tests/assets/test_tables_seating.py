"""Generators of tables, beds and seating: box fit, convex parts, determinism, and the
geometry placement relies on (tops, knee space, seats, backs, arms, mattresses)."""

from __future__ import annotations

import re

import numpy as np
import pytest

from pair2scene.assets.mesh import Asset, Mesh, Part
from pair2scene.assets.registry import generate, generators

# three sizes per category: small, typical, large (metres: x width, y depth, z height)
SIZES: dict[str, list[tuple[float, float, float]]] = {
    "dining_table": [(0.7, 0.7, 0.72), (1.6, 0.9, 0.76), (3.0, 1.1, 0.8)],
    "coffee_table": [(0.6, 0.6, 0.35), (1.1, 0.6, 0.45), (1.6, 0.9, 0.3)],
    "side_table": [(0.35, 0.3, 0.5), (0.5, 0.45, 0.6), (0.7, 0.6, 0.75)],
    "desk": [(0.8, 0.5, 0.74), (1.4, 0.7, 0.76), (1.6, 0.7, 1.6)],
    "dressing_table": [(0.7, 0.4, 0.75), (1.0, 0.45, 1.4), (1.4, 0.55, 1.8)],
    "bed": [(0.9, 1.9, 0.8), (1.6, 2.1, 1.1), (2.0, 2.2, 1.4)],
    "dog_bed": [(0.45, 0.35, 0.12), (0.8, 0.6, 0.22), (1.2, 0.9, 0.3)],
    "chair": [(0.4, 0.4, 0.75), (0.48, 0.52, 0.9), (0.65, 0.7, 1.2)],
    "stool": [(0.3, 0.3, 0.45), (0.4, 0.4, 0.7), (0.5, 0.5, 0.8)],
    "ottoman": [(0.4, 0.4, 0.35), (0.6, 0.6, 0.45), (1.2, 0.5, 0.45)],
    "armchair": [(0.6, 0.65, 0.7), (0.85, 0.85, 0.9), (1.1, 1.0, 1.1)],
    "sofa": [(1.3, 0.8, 0.8), (2.1, 0.9, 0.85), (3.0, 1.0, 0.9)],
}
FURNITURE_MIN_STYLES = 2
MAX_PARTS = 60
UP = 0.99
"""cos of the largest tilt of a face still counted as an upward surface."""
SEAT_CUSHION = re.compile(r"seat(_\d+)?$")


def _cases(categories=SIZES):
    gens = generators()
    return [
        (c, style, i)
        for c in categories
        for style in range(gens[c].variants)
        for i in range(len(SIZES[c]))
    ]


@pytest.fixture(scope="module")
def assets() -> dict[tuple[str, int, int], Asset]:
    """Every category x style x size, built once (seeded by the case)."""
    return {(c, s, i): generate(c, SIZES[c][i], rng=100 * s + i, style=s) for c, s, i in _cases()}


# -- geometry helpers -----------------------------------------------------------------
def _part(asset: Asset, name: str) -> Part:
    found = [p for p in asset.parts if p.name == name]
    assert len(found) == 1, f"{asset.category} style {asset.style}: no single part {name!r}"
    return found[0]


def _parts(asset: Asset, pattern: str) -> list[Part]:
    rx = re.compile(pattern)
    return [p for p in asset.parts if rx.match(p.name)]


def _inside(mesh: Mesh, point: np.ndarray, eps: float = 1e-9) -> bool:
    """Whether ``point`` (3,) lies strictly inside the closed convex ``mesh``."""
    n = mesh.face_normals
    d = np.einsum("ij,ij->i", n, mesh.triangles[:, 0])
    keep = np.linalg.norm(n, axis=1) > 0
    return bool(np.all(n[keep] @ point - d[keep] < -eps))


def _free(asset: Asset, point) -> bool:
    p = np.asarray(point, dtype=float)
    return not any(_inside(part.mesh, p) for part in asset.parts)


def _upward_area(mesh: Mesh, z_min: float) -> float:
    """Area of faces facing up (normal z > UP) whose centre lies at or above z_min."""
    up = (mesh.face_normals[:, 2] > UP) & (mesh.triangles[:, :, 2].mean(1) >= z_min - 1e-9)
    return float(mesh.face_areas[up].sum())


def _top_z(part: Part) -> float:
    return float(part.mesh.bounds[1, 2])


def _centre(part: Part) -> np.ndarray:
    return part.mesh.bounds.mean(0)


# -- contract -------------------------------------------------------------------------
def test_all_categories_registered_with_styles():
    gens = generators()
    for c in SIZES:
        assert c in gens, c
        assert gens[c].variants >= FURNITURE_MIN_STYLES, c


@pytest.mark.parametrize("case", _cases(), ids=lambda c: f"{c[0]}-s{c[1]}-{c[2]}")
def test_fits_box_with_closed_convex_parts(assets, case):
    cat, _, i = case
    asset = assets[case]
    size = np.asarray(SIZES[cat][i])
    np.testing.assert_allclose(asset.mesh.bounds, np.stack([-size / 2, size / 2]), atol=1e-6)
    assert 0 < len(asset.parts) < MAX_PARTS
    names = [p.name for p in asset.parts]
    assert len(set(names)) == len(names), "part names must be unique"
    for p in asset.parts:
        assert p.mesh.is_watertight(), p.name
        assert p.mesh.is_convex(), p.name
        assert p.mesh.volume > 0, p.name


@pytest.mark.parametrize("cat", list(SIZES))
def test_deterministic_and_seed_dependent(cat):
    size = SIZES[cat][1]
    for style in range(generators()[cat].variants):
        a = generate(cat, size, rng=7, style=style)
        b = generate(cat, size, rng=7, style=style)
        c = generate(cat, size, rng=8, style=style)
        assert [p.name for p in a.parts] == [p.name for p in b.parts]
        np.testing.assert_array_equal(a.mesh.vertices, b.mesh.vertices)
        same = a.mesh.vertices.shape == c.mesh.vertices.shape and np.allclose(
            a.mesh.vertices, c.mesh.vertices
        )
        assert not same, f"{cat} style {style} ignores its rng"


@pytest.mark.parametrize("cat", list(SIZES))
def test_styles_differ(cat, assets):
    n = generators()[cat].variants
    meshes = [assets[(cat, s, 1)].mesh for s in range(n)]
    for s in range(n):
        for t in range(s + 1, n):
            a, b = meshes[s], meshes[t]
            same = a.vertices.shape == b.vertices.shape and np.allclose(a.vertices, b.vertices)
            assert not same, f"{cat}: styles {s} and {t} build the same mesh"


# -- tables ---------------------------------------------------------------------------
TABLES = ["dining_table", "coffee_table", "side_table", "desk", "dressing_table"]


@pytest.mark.parametrize("case", _cases(TABLES), ids=lambda c: f"{c[0]}-s{c[1]}-{c[2]}")
def test_table_top_is_an_upward_surface(assets, case):
    cat, style, i = case
    asset = assets[case]
    sx, sy, sz = SIZES[cat][i]
    top = _part(asset, "top")
    z_top = _top_z(top)
    # the top is the whole upper face (a round top covers pi/4 of its box)
    assert _upward_area(top.mesh, z_top) > 0.7 * sx * sy
    raised = cat in ("desk", "dressing_table") and sz >= 1.05
    if raised:
        # a hutch or mirror stands on the back of the top; the work top is at desk height
        assert 0.3 * sz <= z_top + sz / 2 <= 0.7 * sz
        above = [p for p in asset.parts if p.mesh.bounds[0, 2] >= z_top - 1e-9]
        assert above and all(_centre(p)[1] < 0 for p in above)
    else:
        assert z_top == pytest.approx(sz / 2, abs=1e-6)
    under = float(top.mesh.bounds[0, 2])
    assert not _free(asset, (0.0, 0.0, (under + z_top) / 2)), "the probe misses the top"
    z_mid = (-sz / 2 + under) / 2
    if cat == "side_table" and style == 1:
        # small cabinet: a drawer at the front over an open niche
        assert _part(asset, "drawer").mesh.bounds[1, 1] > 0.4 * sy
        z_niche = (_top_z(_part(asset, "bottom")) + _part(asset, "shelf").mesh.bounds[0, 2]) / 2
        assert _free(asset, (0.0, 0.3 * sy, z_niche))
        return
    assert _free(asset, (0.0, 0.3 * sy, z_mid))
    pedestal = (cat == "dining_table" and style == 1) or (cat == "side_table" and style == 2)
    if not pedestal:
        assert _free(asset, (0.0, 0.0, z_mid)), "space under the top's centre is blocked"


@pytest.mark.parametrize("case", _cases(["desk", "dressing_table"]), ids=lambda c: f"{c}")
def test_knee_space_open_to_front(assets, case):
    cat, _, i = case
    asset = assets[case]
    sx, sy, sz = SIZES[cat][i]
    under = float(_part(asset, "top").mesh.bounds[0, 2])
    x = -0.15 * sx if cat == "desk" else 0.0
    for frac_z in (0.25, 0.5):
        z = -sz / 2 + frac_z * (under + sz / 2)
        for y in (0.0, 0.25 * sy, 0.49 * sy):
            assert _free(asset, (x, y, z)), f"knee space blocked at y={y:.2f} z={z:.2f}"


def test_coffee_table_shelves_are_below_the_top(assets):
    for style in (0, 2):
        asset = assets[("coffee_table", style, 1)]
        shelf, top = _part(asset, "shelf"), _part(asset, "top")
        assert _top_z(shelf) < top.mesh.bounds[0, 2] - 0.1
        assert _upward_area(shelf.mesh, _top_z(shelf)) > 0.3 * 1.1 * 0.6


# -- beds -----------------------------------------------------------------------------
@pytest.mark.parametrize("case", _cases(["bed"]), ids=lambda c: f"{c}")
def test_bed_mattress_and_headboard(assets, case):
    from pair2scene.assets.generators.beds import MATTRESS_TOP

    _, style, i = case
    asset = assets[case]
    sx, sy, sz = SIZES["bed"][i]
    mattress = _part(asset, "mattress")
    lo, hi = mattress.mesh.bounds
    # where the training rooms' beds carry things: 0.45 m + 0.2 x the height, 5 % either way
    a, b, cap = MATTRESS_TOP
    assert hi[2] + sz / 2 == pytest.approx(min(a + b * sz, cap * sz), rel=0.051)
    assert hi[0] - lo[0] > 0.8 * sx and hi[1] - lo[1] > 0.75 * sy
    assert _upward_area(mattress.mesh, hi[2]) > 0.6 * sx * sy
    head = _parts(asset, "headboard")
    assert head
    assert max(_top_z(p) for p in head) == pytest.approx(sz / 2, abs=1e-6)
    for p in head:
        assert _centre(p)[1] < -0.4 * sy
        assert p.mesh.bounds[1, 1] <= lo[1] + 0.15 * sy
    assert _free(asset, (0.0, 0.0, hi[2] + 0.05 * sz)), "something lies on the mattress"
    if style == 1:
        foot = _part(asset, "footboard")
        assert _centre(foot)[1] > 0.4 * sy
        assert hi[2] < _top_z(foot) < sz / 2 - 0.1 * sz


@pytest.mark.parametrize("style", range(3))
def test_bed_mattress_fits_the_source_heights(style):
    """Curation builds a source's bed with its mattress top where the source's objects
    rest (the lowest of them: a pillow spawned higher falls onto it), held inside the box."""
    from pair2scene.assets.generators.beds import FITTED_MATTRESS

    size = (1.6, 2.1, 0.91)
    for heights, want in (([0.57, 0.9], 0.57), ([0.62], 0.62), ([0.01], FITTED_MATTRESS[0] * 0.91),
                          ([0.91], FITTED_MATTRESS[1] * 0.91)):  # fmt: skip
        asset = generate("bed", size, rng=style, style=style, support_heights=heights)
        lo, hi = _part(asset, "mattress").mesh.bounds
        assert hi[2] + size[2] / 2 == pytest.approx(want, abs=1e-6), heights
        head = max(_top_z(p) for p in _parts(asset, "headboard"))
        assert head == pytest.approx(size[2] / 2, abs=1e-6)


BUNK_SIZES = [(1.15, 1.86, 1.58), (1.16, 2.43, 1.96), (1.15, 2.52, 2.32)]
"""The bunk and loft bed boxes of the training rooms' size table."""


@pytest.mark.parametrize("style", range(3))
@pytest.mark.parametrize("size", BUNK_SIZES, ids=lambda s: f"h{s[2]}")
def test_tall_beds_are_bunk_beds(size, style):
    from pair2scene.assets import surfaces_of
    from pair2scene.assets.generators.beds import BUNK_HEADROOM_M, BUNK_MIN_HEIGHT_M

    assert size[2] >= BUNK_MIN_HEIGHT_M > max(s[2] for s in SIZES["bed"])
    asset = generate("bed", size, rng=style, style=style)
    sx, sy, sz = size
    half = np.array(size) / 2
    np.testing.assert_allclose(asset.mesh.bounds, [-half, half], atol=1e-6)
    assert len({p.name for p in asset.parts}) == len(asset.parts) < MAX_PARTS
    for part in asset.parts:
        assert part.mesh.is_convex() and part.mesh.is_watertight(), part.name
    upper, lower = _part(asset, "mattress"), _part(asset, "mattress_lower")
    # two decks: the lower near the floor, the upper high, headroom between them
    assert _top_z(lower) + sz / 2 < 0.6
    assert _top_z(upper) > _top_z(lower) + BUNK_HEADROOM_M
    # the places things rest: the two mattresses, and nothing but post tops besides
    big = sorted((s for s in surfaces_of(asset) if s.area > 0.01), key=lambda s: s.z)
    assert [s.z for s in big] == pytest.approx([_top_z(lower), _top_z(upper)], abs=1e-3)
    assert big[0].area > 0.7 * sx * sy and big[1].area > 0.7 * sx * sy
    assert big[0].clearance >= BUNK_HEADROOM_M and np.isinf(big[1].clearance)
    # a rail guards the upper deck on both long sides; the ladder stands at the foot,
    # on the half the style gives it
    rails = _parts(asset, r"rail_(left|right)_\d")
    assert {round(float(np.sign(_centre(p)[0]))) for p in rails} == {-1, 1}
    assert all(_top_z(p) > _top_z(upper) for p in rails)
    stiles = _parts(asset, r"ladder_stile_\d")
    assert len(stiles) == 2 and all(_centre(p)[1] > 0.45 * sy for p in stiles)
    side = np.sign(np.mean([_centre(p)[0] for p in stiles]))
    assert side == (-1 if style == 1 else 1)
    assert _parts(asset, r"ladder_rung_\d")
    # its head at -y, as every bed's
    assert all(_centre(p)[1] < -0.45 * sy for p in _parts(asset, "headboard"))


@pytest.mark.parametrize("case", _cases(["dog_bed"]), ids=lambda c: f"{c}")
def test_dog_bed_cushion_in_rim(assets, case):
    _, _, i = case
    asset = assets[case]
    sx, sy, sz = SIZES["dog_bed"][i]
    cushion = _part(asset, "cushion")
    c_top = _top_z(cushion)
    assert c_top < 0.0, "the cushion lies low inside the rim"
    assert _upward_area(cushion.mesh, c_top) > 0.2 * sx * sy
    assert _free(asset, (0.0, 0.0, c_top + 0.2 * (sz / 2 - c_top)))
    rim = [p for p in asset.parts if p.name != "cushion"]
    back = max(_top_z(p) for p in rim if _centre(p)[1] < -0.3 * sy)
    front = max(_top_z(p) for p in rim if _centre(p)[1] > 0.3 * sy)
    assert back == pytest.approx(sz / 2, abs=1e-6) and front < back - 0.1 * sz


# -- seating --------------------------------------------------------------------------
def _seats(asset: Asset) -> list[Part]:
    seats = [p for p in asset.parts if SEAT_CUSHION.match(p.name)]
    assert seats, f"{asset.category} style {asset.style} has no seat"
    return seats


@pytest.mark.parametrize(
    "case", _cases(["chair", "armchair", "sofa"]), ids=lambda c: f"{c[0]}-s{c[1]}-{c[2]}"
)
def test_seat_with_back_at_minus_y(assets, case):
    cat, _, i = case
    asset = assets[case]
    sx, sy, sz = SIZES[cat][i]
    seats = _seats(asset)
    seat_top = max(_top_z(p) for p in seats)
    assert 0.35 * sz <= seat_top + sz / 2 <= 0.65 * sz, "seat far from mid-height"
    assert sum(_upward_area(p.mesh, _top_z(p)) for p in seats) > 0.35 * sx * sy
    seat_y = np.mean([_centre(p)[1] for p in seats])
    back = _parts(asset, "back")
    assert max(_top_z(p) for p in back) == pytest.approx(sz / 2, abs=1e-6)
    for p in back:
        assert _centre(p)[1] < seat_y - 0.15 * sy, f"{p.name} is not behind the seat"
        assert p.mesh.bounds[0, 2] < seat_top + 0.4 * (sz / 2 - seat_top)
    for p in seats:  # room to sit: nothing just above a seat's centre
        c = _centre(p)
        assert _free(asset, (c[0], c[1] + 0.1 * sy, _top_z(p) + 0.1 * sz))


@pytest.mark.parametrize(
    "case", _cases(["armchair", "sofa"]), ids=lambda c: f"{c[0]}-s{c[1]}-{c[2]}"
)
def test_arms_at_both_sides(assets, case):
    cat, style, i = case
    asset = assets[case]
    sx, sy, sz = SIZES[cat][i]
    seat_top = max(_top_z(p) for p in _seats(asset))
    if cat == "sofa" and style == 2:
        assert not _parts(asset, "arm_"), "the armless sofa has arms"
        return
    left, right = _parts(asset, "arm_left"), _parts(asset, "arm_right")
    assert left and right
    assert max(_centre(p)[0] for p in left) < -0.3 * sx
    assert min(_centre(p)[0] for p in right) > 0.3 * sx
    for arm in (left, right):
        assert seat_top + 0.05 * sz < max(_top_z(p) for p in arm) < sz / 2 - 0.05 * sz
        assert max(p.mesh.bounds[1, 1] for p in arm) > 0.4 * sy, "arms reach the front"


def test_sofa_cushion_split():
    for size, split in (((1.3, 0.8, 0.8), 2), ((2.2, 0.9, 0.85), 3)):
        for style in (0, 2, 3):
            n = len(_seats(generate("sofa", size, rng=0, style=style)))
            assert n in (2, 3) and (n == split or style == 2), (size, style, n)
        assert len(_seats(generate("sofa", size, rng=0, style=1))) == 1


@pytest.mark.parametrize(
    "case", _cases(["stool", "ottoman"]), ids=lambda c: f"{c[0]}-s{c[1]}-{c[2]}"
)
def test_stool_and_ottoman_tops_are_seats(assets, case):
    cat, _, i = case
    asset = assets[case]
    sx, sy, sz = SIZES[cat][i]
    area = sum(_upward_area(p.mesh, sz / 2 - 0.05 * sz) for p in asset.parts)
    assert area > 0.5 * sx * sy
    assert _free(asset, (0.0, 0.0, sz / 2 + 1e-3))
    if cat == "stool":
        assert _top_z(_part(asset, "seat")) == pytest.approx(sz / 2, abs=1e-6)


def test_chair_styles_stand_on_the_floor(assets):
    for style in range(generators()["chair"].variants):
        asset = assets[("chair", style, 1)]
        sz = SIZES["chair"][1][2]
        feet = [p for p in asset.parts if p.mesh.bounds[0, 2] <= -sz / 2 + 1e-6]
        xs = np.concatenate([p.mesh.vertices[:, :2] for p in feet])
        # the floor contact spans the seat: the chair cannot tip forward or back
        assert np.ptp(xs[:, 1]) > 0.5 * SIZES["chair"][1][1]
        assert np.ptp(xs[:, 0]) > 0.5 * SIZES["chair"][1][0]

"""Storage furniture generators: validity, determinism, styles, instance fitting, shape facts."""

from __future__ import annotations

import numpy as np
import pytest

from pair2scene.assets.mesh import Asset, Part
from pair2scene.assets.registry import generate, generators

SIZES: dict[str, list[tuple[float, float, float]]] = {
    "shelving_unit": [(0.9, 0.35, 1.6), (0.4, 0.3, 0.8), (2.0, 0.45, 2.2)],
    "tv_stand": [(1.5, 0.4, 0.5), (0.8, 0.35, 0.4), (2.2, 0.5, 0.7)],
    "dresser": [(1.2, 0.5, 0.8), (0.5, 0.4, 1.2), (1.8, 0.55, 0.9)],
    "wardrobe": [(1.0, 0.6, 2.0), (0.5, 0.5, 1.7), (2.4, 0.65, 2.3)],
    "cabinet": [(1.6, 0.45, 0.8), (0.5, 0.4, 0.6), (1.0, 0.45, 1.9)],
    "counter_top": [(2.0, 0.62, 0.9), (0.6, 0.6, 0.9), (3.6, 0.65, 0.92)],
    "fridge": [(0.7, 0.7, 1.8), (0.55, 0.6, 0.85), (0.9, 0.75, 1.8)],
    "laundry_hamper": [(0.45, 0.35, 0.6), (0.3, 0.3, 0.4), (0.6, 0.4, 0.7)],
    "safe": [(0.4, 0.4, 0.5), (0.3, 0.3, 0.25), (0.6, 0.55, 1.2)],
    "cart": [(0.6, 0.4, 0.85), (0.4, 0.3, 0.6), (1.0, 0.5, 1.0)],
    "garbage_can": [(0.3, 0.3, 0.4), (0.2, 0.2, 0.25), (0.45, 0.35, 0.75)],
    "drawer": [(0.5, 0.45, 0.15), (0.3, 0.35, 0.1), (0.9, 0.55, 0.25)],
    "cabinet_door": [(0.45, 0.04, 0.7), (0.3, 0.03, 0.35), (0.6, 0.05, 2.0)],
    "shelf": [(0.8, 0.25, 0.03), (0.6, 0.3, 0.2), (1.2, 0.35, 0.06)],
}
FITTING = {"shelving_unit", "tv_stand", "cabinet", "cart", "dresser", "counter_top", "fridge"}
PARTS = {"drawer", "cabinet_door", "shelf"}
HEIGHT_ATOL = 1e-9
"""Fitted heights are exact: the generators span the box, so ``generate``'s fit is the identity."""

CASES = [
    (cat, i, style)
    for cat, sizes in SIZES.items()
    for i in range(len(sizes))
    for style in range(generators()[cat].variants)
]


# -- helpers ---------------------------------------------------------------------------
PROBES = np.array(
    [[1, 1, 1], [4, 1, 1], [1, 4, 1], [1, 1, 4], [2, 2, 1], [1, 2, 2], [2, 1, 2]], dtype=float
)
PROBES /= PROBES.sum(1, keepdims=True)
"""Barycentric sample points per triangle for the free-space probe."""


def bottom_z(asset: Asset) -> float:
    return -asset.size[2] / 2


def parts_named(asset: Asset, *keys: str) -> list[Part]:
    return [p for p in asset.parts if any(k in p.name for k in keys)]


def inside_any(asset: Asset, point, eps: float = 1e-6) -> bool:
    """Whether ``point`` (3,) lies strictly inside any (convex) part."""
    p = np.asarray(point, dtype=float)
    for part in asset.parts:
        m = part.mesh
        d = np.einsum("ij,ij->i", m.face_normals, p - m.triangles[:, 0])
        if np.all(d < -eps):
            return True
    return False


def upward_faces(asset: Asset, height: float) -> tuple[float, float]:
    """(area of upward faces at ``height`` above the box bottom, the part of that area with
    free space 1 cm above it), both as fractions of the box footprint."""
    z = bottom_z(asset) + height
    total = free = 0.0
    for part in asset.parts:
        m = part.mesh
        up = (m.face_normals[:, 2] > 0.99) & np.all(np.abs(m.triangles[:, :, 2] - z) < 1e-9, 1)
        for tri, area in zip(m.triangles[up], m.face_areas[up]):
            total += area
            for b in PROBES:
                if not inside_any(asset, b @ tri + (0.0, 0.0, 0.01)):
                    free += area / len(PROBES)
    footprint = asset.size[0] * asset.size[1]
    return total / footprint, free / footprint


def board_heights(asset: Asset, min_fraction: float = 0.3) -> list[float]:
    """Heights above the bottom of the uncovered upward faces spanning at least
    ``min_fraction`` of the footprint (tiers and tops; not knobs, lips, or a plinth's top
    hidden under the bottom board)."""
    zs = set()
    for part in asset.parts:
        m = part.mesh
        up = m.face_normals[:, 2] > 0.99
        zs |= {round(float(z), 9) for z in m.triangles[up][:, 0, 2]}
    out = [z - bottom_z(asset) for z in sorted(zs)]
    return [h for h in out if upward_faces(asset, h)[1] >= min_fraction]


def span(part: Part, axis: int) -> tuple[float, float]:
    lo, hi = part.mesh.bounds
    return float(lo[axis]), float(hi[axis])


# -- registry --------------------------------------------------------------------------
def test_registered_with_styles_and_fitting():
    gens = generators()
    for cat in SIZES:
        g = gens[cat]
        assert g.variants >= 2, cat
        assert g.fits_support_heights == (cat in FITTING), cat


# -- every category, size and style ----------------------------------------------------
@pytest.mark.parametrize("cat,size_index,style", CASES)
def test_valid_asset(cat, size_index, style):
    size = np.array(SIZES[cat][size_index])
    asset = generate(cat, size, rng=7, style=style)
    assert asset.source == "procedural"
    np.testing.assert_allclose(asset.mesh.bounds, [-size / 2, size / 2], atol=1e-6)
    assert 1 <= len(asset.parts) < 60
    names = [p.name for p in asset.parts]
    assert len(set(names)) == len(names), "part names are unique"
    for part in asset.parts:
        assert part.mesh.is_watertight(), (part.name, "watertight")
        assert part.mesh.is_convex(), (part.name, "convex")
        assert part.mesh.volume > 0, part.name


@pytest.mark.parametrize("cat", list(SIZES))
def test_deterministic_and_styles_differ(cat):
    size = SIZES[cat][0]
    variants = generators()[cat].variants
    meshes = []
    for style in range(variants):
        a = generate(cat, size, rng=3, style=style).mesh
        b = generate(cat, size, rng=3, style=style).mesh
        np.testing.assert_array_equal(a.vertices, b.vertices)
        np.testing.assert_array_equal(a.faces, b.faces)
        meshes.append(a)
    for i in range(variants):
        for j in range(i + 1, variants):
            same = meshes[i].vertices.shape == meshes[j].vertices.shape and np.allclose(
                meshes[i].vertices, meshes[j].vertices
            )
            assert not same, f"{cat}: styles {i} and {j} are the same mesh"


# -- instance fitting ------------------------------------------------------------------
def test_bookcase_fits_four_tiers_exactly():
    size = (0.9, 0.35, 1.6)
    heights = [0.02, 0.42, 0.82, 1.22]
    for style in range(generators()["shelving_unit"].variants):
        asset = generate("shelving_unit", size, rng=0, style=style, support_heights=heights)
        found = board_heights(asset)
        np.testing.assert_allclose(found, heights + [1.6], atol=HEIGHT_ATOL)
        tiers = sorted(parts_named(asset, "tier_"), key=lambda p: span(p, 2)[1])
        assert len(tiers) == 4
        for tier, h in zip(tiers, heights):
            assert span(tier, 2)[1] - bottom_z(asset) == pytest.approx(h, abs=HEIGHT_ATOL)
        for h in heights:
            area, free = upward_faces(asset, h)
            assert free > 0.5 * area > 0.2, (style, h)  # a real board with room above it


def test_bookcase_default_tiers_spread_over_height():
    size = (0.9, 0.35, 1.6)
    for seed in range(4):
        for style in range(generators()["shelving_unit"].variants):
            asset = generate("shelving_unit", size, rng=seed, style=style)
            hs = board_heights(asset)
            assert hs[-1] == pytest.approx(1.6)
            assert hs[0] < 0.2
            gaps = np.diff(hs)
            assert len(hs) >= 5, hs  # 4+ gaps over 1.6 m
            assert gaps.max() < 0.45 and gaps.min() > 0.25, hs
            # open front: across every bay at mid height, near the front, it is mostly empty
            # (cubby dividers take a few samples)
            for lo, hi in zip(hs[:-1], hs[1:]):
                z = bottom_z(asset) + (lo + hi) / 2
                free = [not inside_any(asset, (x, 0.15, z)) for x in np.linspace(-0.4, 0.4, 17)]
                assert np.mean(free) > 0.7, (seed, style, lo)


def test_support_heights_cleaned():
    """Near-duplicates collapse into the lower one; heights near the top are the top."""
    size = (0.9, 0.35, 1.6)
    asset = generate(
        "shelving_unit", size, rng=0, style=0, support_heights=[0.42, 0.43, 0.82, 1.57]
    )
    hs = board_heights(asset)
    assert any(abs(h - 0.42) < HEIGHT_ATOL for h in hs)
    assert not any(abs(h - 0.43) < 1e-3 for h in hs)
    assert not any(abs(h - 1.57) < 1e-3 for h in hs)
    assert hs[-1] == pytest.approx(1.6)
    # a bay left taller than 0.6 m by the data still gets shelves
    assert max(np.diff(hs)) < 0.6


FIT_CASES = {
    "shelving_unit": ((0.9, 0.35, 1.6), [0.3, 0.9]),
    "tv_stand": ((1.5, 0.4, 0.5), [0.05, 0.25]),
    "cabinet": ((1.6, 0.45, 0.8), [0.35]),
    "cart": ((0.6, 0.4, 0.85), [0.15, 0.5]),
    "dresser": ((1.2, 0.5, 0.8), [0.4]),
    "counter_top": ((2.0, 0.62, 0.9), [0.35]),
    "fridge": ((0.8, 0.75, 1.8), [0.5, 0.95]),
}


@pytest.mark.parametrize("cat", sorted(FITTING))
def test_fitting_categories_land_on_support_heights(cat):
    size, heights = FIT_CASES[cat]
    for style in range(generators()[cat].variants):
        asset = generate(cat, size, rng=1, style=style, support_heights=heights + [size[2]])
        for h in heights:
            area, free = upward_faces(asset, h)
            assert area > 0.3 and free > 0.3, (cat, style, h, area, free)
        top_area, _ = upward_faces(asset, size[2])
        assert top_area > 0.7, (cat, style)
        for p in parts_named(asset, "tier_"):
            assert span(p, 2)[0] >= bottom_z(asset) - 1e-12


def test_fitted_dresser_keeps_drawers_below_open_shelf():
    asset = generate("dresser", (1.2, 0.5, 0.8), rng=2, style=0, support_heights=[0.4, 0.8])
    fronts = parts_named(asset, "_front")
    assert fronts
    assert max(span(p, 2)[1] for p in fronts) - bottom_z(asset) < 0.4
    # no fitted height: the whole front is drawers
    full = generate("dresser", (1.2, 0.5, 0.8), rng=2, style=0)
    top_front = max(span(p, 2)[1] for p in parts_named(full, "_front")) - bottom_z(full)
    assert top_front > 0.7


def test_fitted_cart_tiers_stay_above_wheels():
    asset = generate("cart", (0.6, 0.4, 0.85), rng=0, style=0, support_heights=[0.06, 0.5])
    assert upward_faces(asset, 0.06)[0] > 0.5
    for w in parts_named(asset, "wheel_"):
        assert span(w, 2)[0] == pytest.approx(bottom_z(asset))


# -- family shape facts ----------------------------------------------------------------
FRONTED = ["dresser", "cabinet", "wardrobe", "counter_top", "fridge"]


@pytest.mark.parametrize("cat", FRONTED)
def test_fronts_visible_at_plus_y(cat):
    for i, size in enumerate(SIZES[cat]):
        for style in range(generators()[cat].variants):
            asset = generate(cat, size, rng=i, style=style)
            fronts = [
                p for p in asset.parts if p.name.startswith("door") or p.name.endswith("_front")
            ]
            handles = parts_named(asset, "handle", "knob")
            assert fronts and handles, (cat, style)
            carcass = parts_named(asset, "body", "side_", "tier_", "back")
            y_carcass = max(span(p, 1)[1] for p in carcass)
            for f in fronts:
                assert span(f, 1)[0] >= y_carcass - 1e-9, f.name
            y_face = min(span(f, 1)[1] for f in fronts)
            for hd in handles:
                assert span(hd, 1)[0] >= y_face - 0.04 - 1e-9
                assert span(hd, 1)[1] > y_face
            assert max(span(hd, 1)[1] for hd in handles) >= size[1] / 2 - 0.01
            # the fronts cover most of the front face
            front_area = sum(
                (span(f, 0)[1] - span(f, 0)[0]) * (span(f, 2)[1] - span(f, 2)[0]) for f in fronts
            )
            assert front_area > 0.45 * size[0] * size[2], (cat, style, front_area)


def test_counter_top_slab_overhangs_body_and_plinth_recessed():
    for style in range(3):
        asset = generate("counter_top", (2.0, 0.62, 0.9), rng=0, style=style)
        (top,) = parts_named(asset, "top")
        assert span(top, 2)[1] == pytest.approx(0.45)
        assert span(top, 1) == pytest.approx((-0.31, 0.31))
        others = [p for p in asset.parts if p.name != "top"]
        assert max(span(p, 1)[1] for p in others) < 0.31
        (plinth,) = parts_named(asset, "plinth")
        doors = parts_named(asset, "door_", "_front")
        assert span(plinth, 1)[1] < min(span(d, 1)[0] for d in doors) - 0.02
        assert span(plinth, 2)[0] == pytest.approx(-0.45)


def test_wardrobe_tall_doors_on_plinth():
    for style in range(3):
        asset = generate("wardrobe", (1.0, 0.6, 2.0), rng=0, style=style)
        (plinth,) = parts_named(asset, "plinth")
        assert span(plinth, 2)[0] == pytest.approx(-1.0)
        doors = [
            p
            for p in asset.parts
            if p.name.startswith("door") and "handle" not in p.name and "knob" not in p.name
        ]
        assert len(doors) >= 2
        assert max(span(d, 2)[1] - span(d, 2)[0] for d in doors) > 1.2


def test_fridge_door_split_with_handles():
    for style in range(3):
        asset = generate("fridge", (0.7, 0.7, 1.8), rng=0, style=style)
        doors = parts_named(asset, "door_")
        handles = parts_named(asset, "handle")
        assert len(doors) == 2 and len(handles) == 2
        assert max(span(h, 1)[1] for h in handles) == pytest.approx(0.35)
        (roof,) = parts_named(asset, "roof")
        assert all(span(d, 1)[0] >= span(roof, 1)[1] - 1e-9 for d in doors)


@pytest.mark.parametrize("style", range(3))
def test_fridge_is_hollow_with_shelves_behind_closed_doors(style):
    """Things are kept inside a fridge: shelves under a roof, the doors closing the front."""
    from pair2scene.assets.surfaces import support_surfaces

    size = (0.8, 0.75, 1.8)
    asset = generate("fridge", size, rng=3, style=style)
    inner = [s for s in support_surfaces(asset) if s.z < size[2] / 2 - 0.01]
    levels = sorted({round(s.z + size[2] / 2, 3) for s in inner})
    assert len(levels) >= 4, levels  # the floor and a shelf every 0.3-0.4 m
    assert all(np.isfinite(s.clearance) and s.clearance > 0.08 for s in inner)
    for s in inner:  # a point 5 cm above each shelf's centre is inside no part
        c = np.r_[s.polygon.mean(axis=0), s.z + 0.05]
        assert not inside_any(asset, c), (style, s.z)
    (roof,) = parts_named(asset, "roof")
    y_in = span(roof, 1)[1]  # the cabinet's front: the doors cover it all
    doors = parts_named(asset, "door_")
    assert sum((span(d, 0)[1] - span(d, 0)[0]) * (span(d, 2)[1] - span(d, 2)[0]) for d in doors) > (
        0.8 * size[0] * size[2]
    )
    assert all(span(d, 1)[0] >= y_in - 1e-9 for d in doors)


def test_tv_stand_low_with_top():
    for style in range(3):
        asset = generate("tv_stand", (1.5, 0.4, 0.5), rng=0, style=style)
        hs = board_heights(asset)
        assert hs[-1] == pytest.approx(0.5)
        assert 2 <= len(hs) <= 3, hs
        assert upward_faces(asset, hs[0])[1] > 0.3  # an open lower tier


def test_cart_tiers_and_wheels():
    for style in range(2):
        for seed in range(3):
            asset = generate("cart", (0.6, 0.4, 0.85), rng=seed, style=style)
            wheels = parts_named(asset, "wheel_")
            assert len(wheels) == 4
            assert all(span(w, 2)[0] == pytest.approx(-0.425) for w in wheels)
            hs = board_heights(asset)
            assert 2 <= len(hs) <= 3 and hs[-1] == pytest.approx(0.85)
            assert hs[0] > max(span(w, 2)[1] for w in wheels) - bottom_z(asset)


def test_open_and_lidded_containers():
    open_bin = generate("garbage_can", (0.3, 0.3, 0.4), rng=0, style=0)
    assert not inside_any(open_bin, (0.0, 0.0, 0.1))
    for style in (1, 2):
        lidded = generate("garbage_can", (0.3, 0.3, 0.4), rng=0, style=style)
        assert parts_named(lidded, "lid")
        assert inside_any(lidded, (0.0, 0.0, 0.0))
        # tapered: narrower at the floor than at the top
        (body,) = parts_named(lidded, "body")
        v = body.mesh.vertices
        low, high = v[v[:, 2] < v[:, 2].min() + 1e-9], v[v[:, 2] > v[:, 2].max() - 1e-9]
        assert np.ptp(low[:, 0]) < np.ptp(high[:, 0])
    hamper = generate("laundry_hamper", (0.45, 0.35, 0.6), rng=0, style=0)
    assert parts_named(hamper, "lid")
    basket = generate("laundry_hamper", (0.45, 0.35, 0.6), rng=0, style=1)
    assert not inside_any(basket, (0.0, 0.0, 0.1))


def test_safe_door_and_hardware_at_front():
    for style in range(2):
        asset = generate("safe", (0.4, 0.4, 0.5), rng=0, style=style)
        (door,) = parts_named(asset, "door")
        (body,) = parts_named(asset, "body")
        assert span(door, 1)[0] == pytest.approx(span(body, 1)[1])
        hardware = parts_named(asset, "dial", "keypad", "handle")
        assert hardware and all(span(p, 1)[0] >= span(door, 1)[1] - 0.03 for p in hardware)


def test_drawer_part_is_open_box_with_front():
    for style in range(2):
        asset = generate("drawer", (0.5, 0.45, 0.15), rng=0, style=style)
        (front,) = parts_named(asset, "front")
        assert span(front, 0) == pytest.approx((-0.25, 0.25))
        assert span(front, 2) == pytest.approx((-0.075, 0.075))
        assert span(front, 1)[1] > 0.15
        hardware = parts_named(asset, "handle", "knob")
        assert hardware and max(span(p, 1)[1] for p in hardware) == pytest.approx(0.225)
        assert not inside_any(asset, (0.0, 0.0, 0.03))  # open-topped box


def test_cabinet_door_handle_on_front_face():
    for style in range(2):
        asset = generate("cabinet_door", (0.45, 0.04, 0.7), rng=0, style=style)
        hardware = parts_named(asset, "handle", "knob")
        body = [p for p in asset.parts if p not in hardware]
        assert len(hardware) == 1
        y_face = max(span(p, 1)[1] for p in body)
        assert span(hardware[0], 1) == pytest.approx((y_face, 0.02))
        assert min(span(p, 1)[0] for p in body) == pytest.approx(-0.02)


def test_shelf_board_and_lip():
    plain = generate("shelf", (0.8, 0.25, 0.2), rng=0, style=0)
    assert board_heights(plain, 0.9) == [pytest.approx(0.2)]
    assert parts_named(plain, "bracket")
    lipped = generate("shelf", (0.8, 0.25, 0.06), rng=0, style=1)
    (lip,) = parts_named(lipped, "lip_front")
    (board,) = parts_named(lipped, "board")
    assert span(lip, 1)[1] == pytest.approx(0.125)
    assert span(lip, 2)[1] > span(board, 2)[1] + 0.01
    assert upward_faces(lipped, span(board, 2)[1] + 0.03)[1] > 0.5


def test_counter_run_reaches_counter_height_with_its_top_a_support_surface():
    from pair2scene.assets.surfaces import surfaces_of

    size = np.array([1.6, 0.6, 0.9])
    for style in range(3):
        asset = generate("counter_top", size, rng=0, style=style)
        assert asset.size[2] >= 0.5
        assert asset.size[2] == pytest.approx(0.9, abs=0.01)
        tops = [s.z + asset.size[2] / 2 for s in surfaces_of(asset)]
        assert max(tops) == pytest.approx(0.9, abs=0.02)


@pytest.mark.parametrize("size", [(2.44, 1.83, 0.9), (3.05, 2.44, 0.92), (1.22, 1.22, 0.9)])
def test_a_deep_counter_is_an_l_or_a_c_of_runs_with_open_floor_inside(size):
    from pair2scene.assets.generators.storage import RUN_DEPTH_M
    from pair2scene.assets.surfaces import surfaces_of

    w, d, h = size
    shapes = []
    for seed in range(12):
        asset = generate("counter_top", size, rng=seed, style=seed % 3)
        np.testing.assert_allclose(asset.mesh.bounds, [-np.divide(size, 2), np.divide(size, 2)],
                                   atol=1e-6)  # fmt: skip
        assert 1 <= len(asset.parts) < 60
        names = [p.name for p in asset.parts]
        assert len(set(names)) == len(names), "part names are unique"
        assert all(p.mesh.is_convex() and p.mesh.is_watertight() for p in asset.parts)
        (top,) = [s for s in surfaces_of(asset) if s.z > h / 2 - 0.01]  # the counter top
        run = RUN_DEPTH_M[0] * 0.9

        def inside(x: float, y: float, top=top) -> bool:
            return bool(top.contains(np.array([[x, y]]))[0])

        assert inside(0.0, -d / 2 + run / 2), "a run along the back"
        assert inside(w / 2 - run / 2, d / 2 - 0.05), "a run down the right side"
        assert not inside(0.0, d / 2 - 0.05), "open in the middle of the front"
        right = [p for p in asset.parts if p.name.startswith("right_")]
        assert right and all(p.name.startswith(("back_", "right_", "left_")) for p in asset.parts)
        # the side run's doors and drawers face the inside (-x), away from the wall at +x
        fronts = [p for p in right if "door" in p.name or "drawer" in p.name]
        assert max(p.mesh.bounds[1][0] for p in fronts) < w / 2 - 0.3
        shapes.append("C" if inside(-w / 2 + run / 2, d / 2 - 0.05) else "L")
        assert top.area < 0.75 * w * d
    assert set(shapes) == {"L", "C"} or size == (1.22, 1.22, 0.9)  # too narrow for a C


def test_a_straight_counter_or_an_island_stays_one_block():
    from pair2scene.assets.surfaces import surfaces_of

    for size in [(2.44, 0.61, 0.9), (1.83, 0.92, 0.9)]:
        asset = generate("counter_top", size, rng=3, style=1)
        assert not any(p.name.startswith(("back_", "right_")) for p in asset.parts)
        (top,) = [s for s in surfaces_of(asset) if s.z > size[2] / 2 - 0.01]
        assert top.area == pytest.approx(size[0] * size[1], rel=0.02)


def test_a_counter_asked_solid_is_one_block_whatever_its_size():
    """Curation's physics check stands a source's objects on a counter whose shape the
    box does not tell (``generate(..., solid=True)``): its top is whole, where the same
    seed builds an L or a C; a straight counter is the same asset either way."""
    from pair2scene.assets.surfaces import surfaces_of

    size = (2.44, 1.83, 0.9)
    for seed in range(4):
        shaped = generate("counter_top", size, rng=seed)
        solid = generate("counter_top", size, rng=seed, solid=True)
        assert any(p.name.startswith("right_") for p in shaped.parts)
        assert not any(p.name.startswith(("back_", "right_", "left_")) for p in solid.parts)
        (top,) = [s for s in surfaces_of(solid) if s.z > size[2] / 2 - 0.01]
        assert top.area == pytest.approx(size[0] * size[1], rel=0.02)
    straight = (2.44, 0.61, 0.9)
    a, b = generate("counter_top", straight, rng=5), generate("counter_top", straight, rng=5,
                                                                solid=True)  # fmt: skip
    assert [p.name for p in a.parts] == [p.name for p in b.parts]
    for p, q in zip(a.parts, b.parts):
        np.testing.assert_array_equal(p.mesh.vertices, q.mesh.vertices)
    # a category with no solid form is built as usual
    chair = generate("chair", (0.5, 0.5, 0.9), rng=1)
    assert chair is not generate("chair", (0.5, 0.5, 0.9), rng=1, solid=True)  # (own key)
    assert [p.name for p in chair.parts] == [
        p.name for p in generate("chair", (0.5, 0.5, 0.9), rng=1, solid=True).parts
    ]

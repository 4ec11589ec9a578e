"""Household generators: electronics, books, bedding and the other small objects.

Every category is built at three sizes in every style and checked against the generator
contract (bounds, convex watertight parts, determinism, distinct styles); then each family
gets checks of the geometry placement relies on (screens facing +y, tops at the top, holes
left open, the box deciding whether a thing lies or stands).
"""

from __future__ import annotations

import numpy as np
import pytest

from pair2scene.assets.mesh import Asset, Mesh
from pair2scene.assets.registry import generate, generators

TYPICAL_SIZES: dict[str, tuple[float, float, float]] = {
    # (x, y, z) metres, near the AI2-THOR medians of each category
    "television": (1.14, 0.31, 0.8),
    "laptop": (0.4, 0.3, 0.29),
    "desktop_computer": (0.88, 0.3, 0.57),
    "monitor": (0.55, 0.2, 0.45),
    "keyboard": (0.45, 0.15, 0.03),
    "table_lamp": (0.3, 0.3, 0.5),
    "book": (0.22, 0.27, 0.03),
    "pillow": (0.45, 0.35, 0.14),
    "box": (0.4, 0.4, 0.28),
    "statue": (0.19, 0.15, 0.35),
    "remote_control": (0.06, 0.21, 0.02),
    "alarm_clock": (0.19, 0.09, 0.18),
    "cell_phone": (0.076, 0.15, 0.01),
    "tissue_box": (0.2, 0.1, 0.15),
    "teddy_bear": (0.45, 0.33, 0.47),
    "watch": (0.045, 0.24, 0.012),
    "key_chain": (0.13, 0.07, 0.009),
    "credit_card": (0.086, 0.054, 0.002),
    "pen": (0.011, 0.2, 0.011),
    "pencil": (0.009, 0.18, 0.009),
    "cd": (0.12, 0.12, 0.004),
    "newspaper": (0.33, 0.13, 0.03),
    "cloth": (0.21, 0.18, 0.023),
    "towel": (0.35, 0.3, 0.15),
    "hand_towel": (0.13, 0.04, 0.4),
    "toilet_paper": (0.11, 0.11, 0.1),
    "paper_towel_roll": (0.15, 0.15, 0.33),
    "watering_can": (0.15, 0.27, 0.2),
    "baseball_bat": (0.07, 0.07, 0.86),
    "basketball": (0.24, 0.24, 0.24),
    "tennis_racket": (0.26, 0.68, 0.03),
    "dumbbell": (0.13, 0.33, 0.13),
    "boots": (0.28, 0.3, 0.45),
    "garbage_bag": (0.5, 0.5, 0.56),
    "decor": (0.4, 0.31, 0.14),
}
SIZE_FACTORS = ((1.0, 1.0, 1.0), (0.6, 0.7, 0.5), (1.7, 1.4, 1.9))
"""Per-axis factors on the typical size: typical, small and squat, large and tall."""
MAX_PARTS = 60
ATOL = 1e-6


def _sizes(category: str) -> list[np.ndarray]:
    return [np.array(TYPICAL_SIZES[category]) * f for f in SIZE_FACTORS]


def _styles(category: str) -> range:
    return range(generators()[category].variants)


def _part(asset: Asset, name: str) -> Mesh:
    matches = [p.mesh for p in asset.parts if p.name == name]
    assert matches, f"{asset.category}: no part {name!r} in {[p.name for p in asset.parts]}"
    return matches[0]


def _parts(asset: Asset, prefix: str) -> list[Mesh]:
    found = [p.mesh for p in asset.parts if p.name.startswith(prefix)]
    assert found, f"{asset.category}: no part starting {prefix!r}"
    return found


def _center(mesh: Mesh) -> np.ndarray:
    return mesh.bounds.mean(0)


def _inside(mesh: Mesh, point) -> bool:
    """Is ``point`` (3,) inside the convex ``mesh``?"""
    n = mesh.face_normals
    d = np.einsum("ij,ij->i", n, mesh.triangles[:, 0])
    return bool(np.all(n @ np.asarray(point, dtype=float) - d <= 1e-9))


def _free(asset: Asset, point) -> bool:
    return not any(_inside(p.mesh, point) for p in asset.parts)


# -- the contract, for every category ----------------------------------------------------
def test_registers_exactly_the_household_categories():
    mine = {
        c
        for c, g in generators().items()
        if g.fn.__module__.endswith(".household") or c == "table_lamp"  # lighting.py
    }
    assert mine == set(TYPICAL_SIZES)
    assert all(generators()[c].variants >= 2 for c in mine)


@pytest.mark.parametrize("category", sorted(TYPICAL_SIZES))
def test_contract_bounds_parts_and_determinism(category):
    for size in _sizes(category):
        for style in _styles(category):
            asset = generate(category, size, rng=7, style=style)
            assert asset.style == style and asset.source == "procedural"
            np.testing.assert_allclose(asset.mesh.bounds, [-size / 2, size / 2], atol=ATOL)
            assert 0 < len(asset.parts) < MAX_PARTS
            for p in asset.parts:
                assert p.name, category
                assert p.mesh.is_watertight(), (category, style, p.name)
                assert p.mesh.is_convex(), (category, style, p.name)
            again = generate(category, size, rng=7, style=style)
            np.testing.assert_array_equal(asset.mesh.vertices, again.mesh.vertices)


@pytest.mark.parametrize("category", sorted(TYPICAL_SIZES))
def test_styles_differ(category):
    size = np.array(TYPICAL_SIZES[category])
    meshes = [generate(category, size, rng=3, style=s).mesh for s in _styles(category)]
    for i in range(len(meshes)):
        for j in range(i + 1, len(meshes)):
            a, b = meshes[i].vertices, meshes[j].vertices
            assert a.shape != b.shape or not np.allclose(a, b), (category, i, j)


# -- screens ---------------------------------------------------------------------------------
@pytest.mark.parametrize("category", ["television", "monitor", "desktop_computer"])
def test_screens_face_front(category):
    for size in _sizes(category):
        for style in _styles(category):
            a = generate(category, size, rng=1, style=style)
            screen, panel = _part(a, "screen"), _part(a, "panel")
            assert screen.bounds[1, 1] >= panel.bounds[1, 1] - 1e-9  # proud of the housing
            assert _center(screen)[1] > _center(panel)[1]
            assert _center(screen)[2] >= -1e-9  # held up, not lying at the bottom
            width = screen.bounds[1, 0] - screen.bounds[0, 0]
            assert width > 0.5 * (panel.bounds[1, 0] - panel.bounds[0, 0])


def test_wall_tv_is_flat_against_the_back_and_stands_on_feet_otherwise():
    size = np.array([1.2, 0.08, 0.7])
    wall = generate("television", size, rng=0, style=2)
    assert _part(wall, "screen").bounds[1, 1] == pytest.approx(size[1] / 2)
    assert _part(wall, "wall_bracket").bounds[0, 1] == pytest.approx(-size[1] / 2)
    stand = generate("television", TYPICAL_SIZES["television"], rng=0, style=0)
    assert _part(stand, "foot").bounds[0, 2] == pytest.approx(-0.4)


def test_laptop_base_below_screen_leaning_back():
    for size in _sizes("laptop"):
        for style in _styles("laptop"):
            a = generate("laptop", size, rng=2, style=style)
            base, lid, screen = _part(a, "base"), _part(a, "lid"), _part(a, "screen")
            assert base.bounds[0, 2] == pytest.approx(-size[2] / 2)
            assert lid.bounds[1, 2] > 0.4 * size[2]
            assert _center(lid)[1] < _center(base)[1]  # the lid rises at -y
            assert lid.bounds[0, 1] < base.bounds[0, 1]  # and leans back past the hinge
            assert _center(screen)[1] > _center(lid)[1]  # the screen faces the user (+y)
            keys = [p for p in a.parts if p.name.startswith("key")]
            assert len(keys) >= 5
            deck = base.bounds[1, 2]
            for k in keys:
                assert k.mesh.bounds[1, 2] > deck  # keys stand on the deck
                assert _center(k.mesh)[1] > base.bounds[0, 1]
            assert _center(_part(a, "touchpad"))[1] > max(_center(k.mesh)[1] for k in keys)


def test_keyboard_keys_on_a_slab():
    for size in _sizes("keyboard"):
        for style in _styles("keyboard"):
            a = generate("keyboard", size, rng=4, style=style)
            base = _part(a, "base")
            assert base.bounds[0, 2] == pytest.approx(-size[2] / 2)
            keys = _parts(a, "key")
            assert len(keys) >= 10
            assert max(k.bounds[1, 2] for k in keys) == pytest.approx(size[2] / 2)
            if style == 0:  # flat deck: every key stands above it
                assert all(k.bounds[1, 2] > base.bounds[1, 2] for k in keys)
    compact = generate("keyboard", TYPICAL_SIZES["keyboard"], rng=4, style=0)
    assert _center(_part(compact, "space_bar"))[1] > 0.0  # the space bar is nearest the typist


# -- lamp, book, pillow, box, statue ---------------------------------------------------------
def test_table_lamp_base_stem_shade():
    for size in _sizes("table_lamp"):
        for style in (0, 1):
            a = generate("table_lamp", size, rng=5, style=style)
            base, stem, shade = _part(a, "base"), _part(a, "stem"), _part(a, "shade")
            assert base.bounds[0, 2] == pytest.approx(-size[2] / 2)
            assert shade.bounds[1, 2] == pytest.approx(size[2] / 2)
            shade_w = shade.bounds[1, 0] - shade.bounds[0, 0]
            assert shade_w > 4 * (stem.bounds[1, 0] - stem.bounds[0, 0])
            assert shade_w == pytest.approx(size[0])
        desk = generate("table_lamp", size, rng=5, style=2)
        assert _center(_part(desk, "head"))[1] > _center(_part(desk, "base"))[1]
        assert _center(_part(desk, "head"))[2] > 0.0


def test_book_lies_or_stands_as_the_box_says():
    flat = np.array([0.22, 0.27, 0.03])
    standing = np.array([0.03, 0.2, 0.25])
    for style in _styles("book"):
        a = generate("book", flat, rng=0, style=style)
        spine, pages = _part(a, "spine"), _part(a, "pages")
        front, back = _part(a, "front_cover"), _part(a, "back_cover")
        assert spine.bounds[0, 0] == pytest.approx(-flat[0] / 2)  # spine along -x
        assert front.bounds[1, 2] == pytest.approx(flat[2] / 2)
        assert back.bounds[0, 2] == pytest.approx(-flat[2] / 2)
        assert back.bounds[1, 2] <= pages.bounds[0, 2] + 1e-3 <= front.bounds[0, 2] + 1e-3
        b = generate("book", standing, rng=0, style=style)
        spine, front = _part(b, "spine"), _part(b, "front_cover")
        assert spine.bounds[1, 1] == pytest.approx(standing[1] / 2)  # spine faces +y
        assert spine.bounds[0, 2] == pytest.approx(-standing[2] / 2)  # stands on its edge
        assert front.bounds[1, 0] - front.bounds[0, 0] < 0.2 * standing[0] + 1e-3


def test_pillow_flat_and_standing():
    for style in _styles("pillow"):
        size = np.array(TYPICAL_SIZES["pillow"])
        body = _part(generate("pillow", size, rng=0, style=style), "body")
        ext = body.bounds[1] - body.bounds[0]
        assert np.all(ext[:2] > 0.8 * size[:2]) and ext[2] > 0.8 * size[2]
        upright = np.array([0.45, 0.15, 0.4])
        a = generate("pillow", upright, rng=0, style=style)
        ext = _part(a, "body").bounds[1] - _part(a, "body").bounds[0]
        assert ext[2] > 0.8 * upright[2] and ext[1] <= upright[1] + 1e-9
    piped = generate("pillow", TYPICAL_SIZES["pillow"], rng=0, style=0)
    assert len(_parts(piped, "piping")) >= 8


@pytest.mark.parametrize("style", [0, 1, 2])
def test_a_lying_pillow_rests_on_a_flat_underside(style):
    """Its lowest faces make one flat patch across much of its footprint (a domed or round
    underside rocked on a mattress in the stability simulation); still in its box, and
    every part convex."""
    size = np.array([0.6, 0.4, 0.16])
    asset = generate("pillow", size, rng=style, style=style)
    np.testing.assert_allclose(asset.mesh.bounds, [-size / 2, size / 2], atol=1e-9)
    assert all(p.mesh.is_convex() for p in asset.parts)
    tris = asset.mesh.triangles
    flat = np.all(np.abs(tris[:, :, 2] + size[2] / 2) < 1e-9, axis=1)
    base = tris[flat].reshape(-1, 3)[:, :2]
    extent = base.max(0) - base.min(0)
    assert np.all(extent > 0.4 * size[:2]), extent


def test_box_open_has_room_inside_closed_has_flat_top():
    for size in _sizes("box"):
        open_box = generate("box", size, rng=1, style=0)
        assert _free(open_box, (0.0, 0.0, 0.0))
        assert len(_parts(open_box, "flap")) == 4
        for flap in _parts(open_box, "flap"):  # flaps stand up above the walls
            assert flap.bounds[1, 2] > _part(open_box, "wall_front").bounds[1, 2]
        closed = generate("box", size, rng=1, style=1)
        assert _inside(_part(closed, "body"), (0.0, 0.1 * size[1], size[2] / 2 - 0.01 * size[2]))


def test_statue_on_a_plinth():
    for size in _sizes("statue"):
        for style in _styles("statue"):
            a = generate("statue", size, rng=6, style=style)
            assert _part(a, "plinth").bounds[0, 2] == pytest.approx(-size[2] / 2)
        bust = generate("statue", size, rng=6, style=1)
        head, torso = _part(bust, "head"), _part(bust, "torso")
        assert _center(head)[2] > torso.bounds[1, 2]
        assert _center(_part(bust, "nose"))[1] > _center(head)[1]  # the face looks at +y


# -- clock, tissues, teddy -------------------------------------------------------------------
def test_alarm_clock_faces_front():
    for size in _sizes("alarm_clock"):
        round_clock = generate("alarm_clock", size, rng=2, style=0)
        face, body = _part(round_clock, "face"), _part(round_clock, "body")
        assert _center(face)[1] > _center(body)[1]
        assert max(
            p.mesh.bounds[1, 1] for p in round_clock.parts if "hand" in p.name
        ) == pytest.approx(size[1] / 2)
        digital = generate("alarm_clock", size, rng=2, style=1)
        assert _center(_part(digital, "display"))[1] > 0.0


def test_tissue_tuft_rises_from_the_box():
    for size in _sizes("tissue_box"):
        for style in _styles("tissue_box"):
            a = generate("tissue_box", size, rng=3, style=style)
            top = _part(a, "body").bounds[1, 2]
            tissues = _parts(a, "tissue")
            assert max(t.bounds[1, 2] for t in tissues) == pytest.approx(size[2] / 2)
            assert all(_center(t)[2] > top for t in tissues)


def test_teddy_bear_head_on_top_snout_forward():
    for size in _sizes("teddy_bear"):
        for style in _styles("teddy_bear"):
            a = generate("teddy_bear", size, rng=8, style=style)
            head, body = _part(a, "head"), _part(a, "body")
            assert _center(head)[2] > _center(body)[2]
            assert _center(_part(a, "snout"))[1] > _center(head)[1]
            assert len(_parts(a, "ear")) == 2 and len(_parts(a, "leg")) == 2


# -- flat hand-held things -------------------------------------------------------------------
@pytest.mark.parametrize(
    "category,marker",
    [
        ("remote_control", "power_button"),
        ("cell_phone", "screen"),
        ("credit_card", "chip"),
        ("credit_card", "hologram"),
        ("key_chain", "ring"),
    ],
)
def test_flat_things_follow_the_long_side(category, marker):
    size = np.array(TYPICAL_SIZES[category])
    for swapped in (size, size[[1, 0, 2]]):
        long_axis = int(np.argmax(swapped[:2]))
        for style in _styles(category):
            a = generate(category, swapped, rng=0, style=style)
            found = [p.mesh for p in a.parts if p.name.startswith(marker)]
            if not found:  # the marker belongs to the other style
                continue
            if marker == "screen":  # the screen is up and runs along the phone
                m = found[0]
                assert m.bounds[1, 2] > _part(a, "body").bounds[1, 2]
                ext = m.bounds[1] - m.bounds[0]
                assert ext[long_axis] > ext[1 - long_axis]
            else:  # the marker sits toward one end of the long side
                centre = np.mean([_center(m) for m in found], axis=0)
                assert abs(centre[long_axis]) > 0.2 * swapped[long_axis]


def test_cd_has_a_hole_and_card_print_is_on_top():
    for size in _sizes("cd"):
        disc = generate("cd", size, rng=0, style=0)
        assert _free(disc, (0.0, 0.0, 0.0))
    card = generate("credit_card", TYPICAL_SIZES["credit_card"], rng=0, style=0)
    assert _part(card, "chip").bounds[1, 2] == pytest.approx(0.001)


def test_watch_lies_open_or_stands_on_its_band():
    for style in _styles("watch"):
        flat = generate("watch", TYPICAL_SIZES["watch"], rng=0, style=style)
        case = _part(flat, "case")
        assert abs(_center(case)[1]) < 0.1 * TYPICAL_SIZES["watch"][1]
        loop_size = np.array([0.05, 0.07, 0.07])
        loop = generate("watch", loop_size, rng=0, style=style)
        assert _center(_part(loop, "case"))[2] > 0.3 * loop_size[2]
        assert _free(loop, (0.0, 0.0, -0.1 * loop_size[2]))  # the wrist goes there


# -- long things -----------------------------------------------------------------------------
@pytest.mark.parametrize(
    "category,tip", [("pen", "tip"), ("pencil", "lead"), ("baseball_bat", "barrel")]
)
def test_long_things_lie_along_the_long_side_or_stand(category, tip):
    lying = np.array(TYPICAL_SIZES[category])
    lying = (
        np.array([lying[1], lying[0], lying[2]])
        if category != "baseball_bat"
        else np.array([0.86, 0.07, 0.07])
    )
    upright = np.array([lying[1], lying[2], lying[0]])
    for style in _styles(category):
        a = generate(category, lying, rng=0, style=style)
        assert abs(_center(_part(a, tip))[0]) > 0.2 * lying[0]
        b = generate(category, upright, rng=0, style=style)
        assert _center(_part(b, tip))[2] < -0.2 * upright[2]  # tip / barrel down


def test_racket_head_away_from_handle_and_dumbbell_heads_at_the_ends():
    size = np.array(TYPICAL_SIZES["tennis_racket"])
    for style in _styles("tennis_racket"):
        a = generate("tennis_racket", size, rng=0, style=style)
        head = [p.mesh for p in a.parts if p.name.startswith(("frame", "head"))]
        assert min(_center(m)[1] for m in head) > _center(_part(a, "handle"))[1]
    strung = generate("tennis_racket", size, rng=0, style=0)
    assert len(_parts(strung, "string")) >= 8
    size = np.array(TYPICAL_SIZES["dumbbell"])
    for style, prefix in ((0, "head"), (1, "plate")):
        a = generate("dumbbell", size, rng=0, style=style)
        ys = [_center(m)[1] for m in _parts(a, prefix)]
        assert min(ys) < -0.3 * size[1] and max(ys) > 0.3 * size[1]
        assert _free(a, (0.0, 0.0, 0.4 * size[2]))  # room for the hand around the grip


def test_basketball_is_round():
    """Round above its middle; below it pressed a little flat where it rests (its lower
    half stretched by at most 6 % to keep the box)."""
    size = np.array(TYPICAL_SIZES["basketball"])
    for style in _styles("basketball"):
        a = generate("basketball", size, rng=0, style=style)
        v = _part(a, "ball").vertices
        r = np.linalg.norm(v, axis=1)
        upper = v[:, 2] >= 0.0
        assert r[upper].min() > 0.45 * size[0] and r[upper].max() < 0.5 * size[0] + 1e-9
        assert r.min() > 0.45 * size[0] and r.max() < 0.53 * size[0]
        assert len(_parts(a, "seam")) >= 2


# -- textiles and rolls ----------------------------------------------------------------------
@pytest.mark.parametrize("category", ["towel", "hand_towel"])
def test_towels_hang_in_thin_upright_boxes_and_lie_folded_otherwise(category):
    hanging, folded = np.array([0.4, 0.05, 0.6]), np.array([0.35, 0.3, 0.12])
    for style in _styles(category):
        a = generate(category, hanging, rng=0, style=style)
        fold = _part(a, "fold")
        assert fold.bounds[1, 2] == pytest.approx(hanging[2] / 2)
        assert _part(a, "front_layer").bounds[0, 2] == pytest.approx(-hanging[2] / 2)
        assert _free(a, (0.0, 0.0, -0.2 * hanging[2]))  # the gap between the layers
        b = generate(category, folded, rng=0, style=style)
        assert "fold" not in [p.name for p in b.parts]


def test_stacked_towels_are_layers():
    a = generate("towel", (0.35, 0.3, 0.3), rng=1, style=0)
    towels = sorted(_parts(a, "towel"), key=lambda m: _center(m)[2])
    assert len(towels) >= 2
    for lower, upper in zip(towels[:-1], towels[1:]):
        assert upper.bounds[0, 2] == pytest.approx(lower.bounds[1, 2], abs=1e-6)


@pytest.mark.parametrize(
    "category,style", [("toilet_paper", 0), ("toilet_paper", 1), ("paper_towel_roll", 1)]
)
def test_rolls_have_an_open_core(category, style):
    for size in _sizes(category):
        a = generate(category, size, rng=0, style=style)
        rolls = _parts(a, "roll")
        assert len(rolls) >= 8
        lo = np.min([m.bounds[0] for m in rolls], axis=0)
        hi = np.max([m.bounds[1] for m in rolls], axis=0)
        assert _free(a, (lo + hi) / 2)


def test_paper_towel_holder_rod_through_the_roll():
    for size in _sizes("paper_towel_roll"):
        a = generate("paper_towel_roll", size, rng=0, style=0)
        rod, roll = _part(a, "rod"), _part(a, "roll")
        assert rod.bounds[1, 2] > roll.bounds[1, 2]
        assert _part(a, "base").bounds[0, 2] == pytest.approx(-size[2] / 2)


# -- the rest ----------------------------------------------------------------------------------
def test_boots_are_a_pair_with_toes_forward():
    for size in _sizes("boots"):
        for style in _styles("boots"):
            a = generate("boots", size, rng=0, style=style)
            for side, sign in (("left", -1), ("right", 1)):
                shaft, vamp = _part(a, f"{side}_shaft"), _part(a, f"{side}_vamp")
                assert np.sign(_center(shaft)[0]) == sign
                assert _center(shaft)[1] < _center(vamp)[1]
                assert shaft.bounds[1, 2] > 0.3 * size[2]


def test_watering_can_spout_forward_and_bag_tied_on_top():
    for size in _sizes("watering_can"):
        for style in _styles("watering_can"):
            a = generate("watering_can", size, rng=0, style=style)
            assert _center(_part(a, "rose"))[1] > _center(_part(a, "body"))[1]
    for size in _sizes("garbage_bag"):
        for style in _styles("garbage_bag"):
            a = generate("garbage_bag", size, rng=0, style=style)
            assert _center(_part(a, "knot"))[2] > _part(a, "sack").bounds[1, 2] - 0.2 * size[2]


def test_decor_adapts_to_tall_boxes():
    tall = np.array([0.3, 0.37, 1.34])
    bowl = generate("decor", tall, rng=0, style=0)
    assert _part(bowl, "pedestal").bounds[1, 2] > 0.0
    branches = generate("decor", tall, rng=0, style=2)
    assert len(_parts(branches, "branch")) >= 3
    low = generate("decor", TYPICAL_SIZES["decor"], rng=0, style=2)
    assert len(_parts(low, "pillar")) == 3


@pytest.mark.parametrize("category", ["baseball_bat", "pen"])
@pytest.mark.parametrize("style", [0, 1])
def test_a_lying_round_object_rests_on_faces_and_a_standing_one_is_unturned(category, style):
    """Lying, a bat's or a pen's round parts have a face down (their lowest vertices
    span some width across the axis), not the edge they rolled off in the simulation;
    standing on end (a tall box) they are built as before, unturned about their axis."""
    for seed in range(3):
        lying = generate(category, [0.15, 0.012, 0.011], seed, style=style)
        low = lying.mesh.vertices[:, 2].min()
        for part in lying.parts:
            v = part.mesh.vertices  # lengthwise along x
            if part.name in ("barrel", "cap", "end_cap") and v[:, 2].min() < low + 1e-4:
                bottom = v[v[:, 2] < v[:, 2].min() + 1e-7]
                assert np.ptp(bottom[:, 1]) > 1e-4, part.name  # a face across, not an edge
        standing = generate(category, [0.012, 0.011, 0.15], seed, style=style)
        xy = standing.mesh.vertices[:, :2]
        assert np.isclose(np.abs(xy[:, 0]).max(), 0.006)  # a vertex on the box face


@pytest.mark.parametrize("style", [0, 1])
def test_a_basketball_rests_on_a_flat_patch(style):
    """A ball's bottom is pressed a little flat (its lowest vertices span a patch about a
    third of its radius across), so it does not roll off a bed on the edge of a seam
    through its pole; it still fills its box."""
    for seed in range(3):
        ball = generate("basketball", [0.24, 0.24, 0.24], seed, style=style)
        v = ball.mesh.vertices
        bottom = v[v[:, 2] < v[:, 2].min() + 1e-6]
        assert np.ptp(bottom[:, 0]) > 0.02 and np.ptp(bottom[:, 1]) > 0.02
        np.testing.assert_allclose(np.ptp(v, axis=0), [0.24, 0.24, 0.24], atol=1e-6)

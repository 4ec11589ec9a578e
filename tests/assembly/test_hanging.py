"""Towels hung on their holder by rule: the bars a holder offers, the size a towel takes
to hang there, the pose it hangs at, and placement hanging one where it used to drop it."""

from __future__ import annotations

import numpy as np
import pytest

from pair2scene.assembly.collision import MeshWorld, Shape, Tolerances
from pair2scene.assembly.hanging import (
    FOLD,
    LAYER_GAP_SHARE,
    SPAN_SHARE,
    bars,
    draped,
    hang,
    hangs_on,
    hung_size,
)
from pair2scene.assets.mesh import Asset
from pair2scene.assets.registry import generate
from pair2scene.scene.geometry import OrientedBox

AT = OrientedBox.from_yaw([1.0, 2.0, 1.2], [0.5, 0.1, 0.1], 0.7)
"""Where a holder hangs, turned about z."""


def _holder(seed: int, style: int | None = None) -> Asset:
    rng = np.random.default_rng(seed)
    size = [rng.uniform(0.15, 0.8), rng.uniform(0.05, 0.15), rng.uniform(0.03, 0.7)]
    return generate("towel_holder", np.array(size), rng=seed, style=style)


def test_a_rail_is_hung_on_between_its_arms_and_a_double_rail_over_both():
    single = generate("towel_holder", np.array([0.6, 0.1, 0.05]), rng=1, style=0)
    (bar,) = bars(single)
    arms = [p for p in single.parts if p.name.startswith("arm")]
    assert bar.span[0] >= max(p.mesh.bounds[1][0] for p in arms if p.name.startswith("arm_left"))
    assert bar.span[1] <= min(p.mesh.bounds[0][0] for p in arms if p.name.startswith("arm_right"))
    assert bar.top == pytest.approx(single.parts[0].mesh.bounds[1][2], abs=0.02)
    double = generate("towel_holder", np.array([0.6, 0.1, 0.05]), rng=1, style=1)
    first, front, back = bars(double)
    assert {p.name for p in first.parts} == {"rail_0", "rail_back_0"}
    assert back.y < first.y < front.y and first.radius > front.radius


def test_a_ring_is_hung_on_its_lower_half_narrower_than_its_inside():
    ring = generate("towel_holder", np.array([0.2, 0.08, 0.3]), rng=2, style=1)
    (bar,) = bars(ring)
    parts = [p for p in ring.parts if p.name.startswith("ring")]
    lo = np.min([p.mesh.bounds[0] for p in parts], axis=0)
    hi = np.max([p.mesh.bounds[1] for p in parts], axis=0)
    assert all(p.mesh.vertices[:, 2].mean() < (lo[2] + hi[2]) / 2 for p in bar.parts)
    assert bar.width < hi[0] - lo[0] - 4 * bar.radius
    assert bars(generate("counter_top", np.array([1.0, 0.6, 0.9]), rng=0)) == []


def test_a_towel_takes_a_draped_size_its_bar_fits_between_the_layers_of():
    holder = generate("towel_holder", np.array([0.3, 0.1, 0.05]), rng=4, style=0)
    bar = bars(holder)[0]
    flat = hung_size(np.array([0.5, 0.3, 0.06]), holder)  # drawn folded on a shelf
    assert flat[0] <= SPAN_SHARE * bar.width + 1e-9
    assert flat[1] >= (bar.radius + 0.001) / LAYER_GAP_SHARE
    assert draped(flat[None])[0] and flat[2] == pytest.approx(0.3)  # its depth hangs down
    upright = hung_size(np.array([0.13, 0.04, 0.4]), holder)  # as AI2-THOR's hang
    assert upright[2] == pytest.approx(0.4)
    assert not draped(np.array([[0.5, 0.3, 0.06]]))[0]
    assert hung_size(np.array([0.5, 0.3, 0.06]), generate("chair", np.ones(3), 0)) is None


@pytest.mark.parametrize("category", ["hand_towel", "towel"])
def test_a_towel_hangs_with_its_fold_on_the_bar_and_nothing_else_touching(category):
    world = MeshWorld(Tolerances())
    for seed in range(40):
        holder = _holder(seed)
        size = hung_size(np.array([0.4, 0.2, 0.05]), holder)
        towel = generate(category, size, rng=seed)
        box = hang(towel, holder, AT)
        assert box is not None, seed
        np.testing.assert_allclose(box.rotation, AT.rotation)
        local = AT.to_local(box.center[None])[0]
        bar = next(b for b in bars(holder) if b.width >= size[0])
        assert local[0] == pytest.approx(sum(bar.span) / 2, abs=1e-9)
        assert local[1] == pytest.approx(bar.y, abs=1e-9)
        posed = {}
        for name, asset, where in (("towel", towel, box), ("holder", holder, AT)):
            posed[name] = Shape(asset)
            posed[name].set_pose(where.rotation, where.center)
        assert world.penetration(posed["towel"], posed["holder"]) <= world.touch_between(
            posed["towel"], posed["holder"]
        ), seed
        posed["towel"].set_pose(box.rotation, box.center - [0, 0, 0.002])
        assert world.penetration(posed["towel"], posed["holder"]) > 0.0, "it rests on the bar"


def test_what_cannot_hang_does_not():
    holder = generate("towel_holder", np.array([0.2, 0.08, 0.3]), rng=2, style=1)  # a ring
    wide = generate("hand_towel", np.array([0.5, 0.05, 0.4]), rng=0)
    assert hang(wide, holder, AT) is None
    folded = generate("hand_towel", np.array([0.1, 0.2, 0.05]), rng=0)
    assert not any(p.name == FOLD for p in folded.parts) and hang(folded, holder, AT) is None
    assert hangs_on("hand_towel", holder) and not hangs_on("soap_bar", holder)
    assert not hangs_on("hand_towel", generate("counter_top", np.array([1.0, 0.6, 0.9]), 0))


class _NoDraws:
    """A stand-in model that must not be asked: the towel hangs by rule."""

    honours_temperature = False
    draws_in_frames = True

    def draw(self, query, n, temperature, generator):
        raise AssertionError(f"drew for {query.category}")


def test_placement_hangs_a_towel_on_its_holder_touching_it_and_nothing_else():
    from pair2scene.assembly.place import Placer
    from pair2scene.hierarchy.tree import Hierarchy
    from pair2scene.metrics.physical import floating, intersecting
    from pair2scene.scene.model import AssetRef, Room, SceneObject, wall_support

    room = Room("bathroom", np.array([[0.0, 0.0], [3.0, 0.0], [3.0, 3.0], [0.0, 3.0]]), 2.6)
    h = Hierarchy("bathroom")
    rail = h.add("towel_holder", "wall")
    towel = h.add("hand_towel", rail.id)
    holder = generate("towel_holder", np.array([0.5, 0.1, 0.05]), 3, style=0)
    kept = SceneObject(rail.id, "towel_holder",
                       OrientedBox.from_yaw([1.5, 0.05 + 1e-3, 1.1], holder.size, 0.0),
                       AssetRef("procedural", None, 0, 3), wall_support(0))  # fmt: skip
    result = Placer(_NoDraws()).place(h.validate(), room, seed=0, keep=[kept],
                                      keep_assets={rail.id: holder})  # fmt: skip
    assert result.stats.dropped == []
    by = {o.id: o for o in result.scene.objects}
    assert by[towel.id].support == rail.id
    assets = {rail.id: holder, towel.id: result.assets[towel.id]}
    assert floating(result.scene, assets) == {}
    assert intersecting(result.scene, assets) == {}
    assert by[towel.id].box.bottom > 0.3


def _placed_styles(hierarchy, library: bool, rebuilt: str, support: str) -> dict[str, set]:
    """The styles the placer builds each object of ``hierarchy`` in over 16 scene seeds;
    checks that the seed scene.json keeps rebuilds object ``rebuilt`` (on ``support``)
    exactly, as ``keep_assets`` reads a scene back."""
    from pair2scene.assembly.keep import keep_assets
    from pair2scene.assembly.place import AssemblyConfig, Placer
    from pair2scene.scene.model import AssetRef, Room, Scene, SceneObject

    placer = Placer(_NoDraws(), config=AssemblyConfig(asset_library=library))
    room = Room(
        hierarchy.room_type, np.array([[0.0, 0.0], [4.0, 0.0], [4.0, 4.0], [0.0, 4.0]]), 2.6
    )
    styles: dict[str, set] = {}
    for seed in range(16):
        assets = placer.assets_for(hierarchy.validate(), seed)
        for oid, asset in assets.items():
            styles.setdefault(oid, set()).add(asset.style)
        kept = assets[rebuilt]
        ref = AssetRef("procedural", None, kept.style, kept.extra["seed"])
        obj = SceneObject(rebuilt, kept.category,
                          OrientedBox.from_yaw([1, 1, 1], kept.size), ref, support)  # fmt: skip
        back = keep_assets(Scene("s", room, [obj]))[rebuilt]
        assert back.style == kept.style
        np.testing.assert_array_equal(back.mesh.vertices, kept.mesh.vertices)
    return styles


def test_a_toilet_roll_resting_on_a_surface_stands_on_its_end_and_reads_back_so():
    """On a cistern or a counter a roll is built standing (style 0: lying, as on a
    spindle, it rolled off in the simulation); on its holder either style. Its seed alone
    rebuilds it (scene.json keeps the seed, read back by ``keep_assets``)."""
    from pair2scene.hierarchy.tree import Hierarchy

    h = Hierarchy("bathroom")
    counter = h.add("counter_top", "floor")
    spindle = h.add("toilet_paper_hanger", "wall")
    on_counter = h.add("toilet_paper", counter.id)
    on_spindle = h.add("toilet_paper", spindle.id)
    styles = _placed_styles(h, False, on_counter.id, counter.id)  # (a mesh a roll)
    assert styles[on_counter.id] == {0}
    assert styles[on_spindle.id] == {0, 1}


@pytest.mark.parametrize("library", [False, True])
def test_a_television_stands_on_its_feet_on_furniture_and_hangs_on_its_bracket(library):
    """On a stand a television is built on its pedestal or two feet (the wall-mounted
    style, a panel with nothing under it, toppled off its stand in the simulation); on
    a wall on its bracket (not a pedestal hanging on the wall). The library's assets
    (:func:`library_assets`) hold both, and its seed alone rebuilds each."""
    from pair2scene.assembly.place import library_assets
    from pair2scene.assembly.sizes import SizeTable
    from pair2scene.hierarchy.tree import Hierarchy

    h = Hierarchy("living_room")
    stand = h.add("tv_stand", "floor")
    on_stand = h.add("television", stand.id)
    on_wall = h.add("television", "wall")
    styles = _placed_styles(h, library, on_wall.id, "wall:0")
    assert styles[on_stand.id] <= {0, 1} and styles[on_wall.id] == {2}
    if not library:
        assert styles[on_stand.id] == {0, 1}
    built = [a.style for a in library_assets(SizeTable.load()) if a.category == "television"]
    assert {0, 1} & set(built) and 2 in built


def test_a_towel_over_a_vanity_is_shortened_to_hang_clear_of_it():
    """A rail 0.25 m above a counter: a 0.6 m towel would reach into it; it hangs
    shortened to end a little above the counter's top, touching nothing but its rail."""
    from pair2scene.assembly.hanging import CLEAR_BELOW_M, clear_length
    from pair2scene.assembly.place import Placer
    from pair2scene.hierarchy.tree import Hierarchy
    from pair2scene.metrics.physical import floating, intersecting
    from pair2scene.scene.model import AssetRef, Room, SceneObject, wall_support

    room = Room("bathroom", np.array([[0.0, 0.0], [3.0, 0.0], [3.0, 3.0], [0.0, 3.0]]), 2.6)
    h = Hierarchy("bathroom")
    counter = h.add("counter_top", "floor")
    rail = h.add("towel_holder", "wall")
    towel = h.add("towel", rail.id)
    holder = generate("towel_holder", np.array([0.5, 0.1, 0.05]), 3, style=0)
    vanity = generate("counter_top", np.array([1.2, 0.55, 0.85]), 2)
    kept = [
        SceneObject(counter.id, "counter_top", OrientedBox.from_yaw([1.5, 0.28, 0.425],
                    vanity.size), AssetRef("procedural", None, 0, 2), "floor"),
        SceneObject(rail.id, "towel_holder", OrientedBox.from_yaw([1.5, 0.051, 1.1],
                    holder.size), AssetRef("procedural", None, 0, 3), wall_support(0)),
    ]  # fmt: skip
    given = {counter.id: vanity, rail.id: holder}
    result = Placer(_NoDraws()).place(h.validate(), room, seed=0, keep=kept, keep_assets=given)
    assert result.stats.dropped == []
    hung = next(o for o in result.scene.objects if o.id == towel.id)
    assert hung.box.bottom == pytest.approx(0.85 + CLEAR_BELOW_M, abs=0.005)
    assets = {counter.id: vanity, rail.id: holder, towel.id: result.assets[towel.id]}
    assert floating(result.scene, assets) == {} and intersecting(result.scene, assets) == {}
    assert clear_length(hung.box, [kept[0].box]) is None  # clear now


def test_physics_fixes_a_towel_on_its_holder_as_it_fixes_the_holder():
    """Curation's check, evaluate's stability and the exports keep a hung towel still
    (a rigid towel on a round bar slides off); ``dynamic="all"`` frees it as it frees
    every object; a soap bar on the same holder is not hung and stays free."""
    from pair2scene.curation.physics import Role, plan_bodies
    from pair2scene.io.physical import scene_physics
    from pair2scene.scene.model import Room, Scene, SceneObject, wall_support

    room = Room("bathroom", np.array([[0.0, 0.0], [3.0, 0.0], [3.0, 3.0], [0.0, 3.0]]), 2.6)
    holder = generate("towel_holder", np.array([0.5, 0.1, 0.05]), 3, style=0)
    at = OrientedBox.from_yaw([1.5, 0.051, 1.1], holder.size)
    towel = generate("towel", hung_size(np.array([0.4, 0.2, 0.05]), holder), 1)
    soap = generate("soap_bar", np.array([0.08, 0.05, 0.03]), 1)
    objects = [
        SceneObject("towel_holder_0", "towel_holder", at, None, wall_support(0)),
        SceneObject("towel_0", "towel", hang(towel, holder, at), None, "towel_holder_0"),
        SceneObject("soap_bar_0", "soap_bar", OrientedBox.from_yaw([2, 1, 0.015], soap.size),
                    None, "towel_holder_0"),
    ]  # fmt: skip
    scene = Scene("s", room, objects)
    plans = plan_bodies(scene)
    assert plans["towel_0"].role is Role.STATIC and plans["towel_0"].why == "hangs on a holder"
    assert plans["soap_bar_0"].role is Role.FREE
    assets = {"towel_holder_0": holder, "towel_0": towel, "soap_bar_0": soap}
    small = scene_physics(scene, assets)
    assert not small["towel_0"].dynamic and small["soap_bar_0"].dynamic
    assert scene_physics(scene, assets, "all")["towel_0"].dynamic

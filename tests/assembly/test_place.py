"""Placement with the bundled model: collision-free, resting, bounded, seeded."""

from __future__ import annotations

import itertools

import numpy as np
import pytest

torch = pytest.importorskip("torch")

from pair2scene.assembly.collision import MeshWorld, Shape  # noqa: E402
from pair2scene.assembly.place import (  # noqa: E402
    AssemblyConfig,
    Placer,
    door_boxes,
    floor_region,
    upright_yaw,
)
from pair2scene.assembly.rest import contact_rectangle, into_room, rest_on_surfaces  # noqa: E402
from pair2scene.assembly.rooms import make_room  # noqa: E402
from pair2scene.errors import UserError  # noqa: E402
from pair2scene.hierarchy.tree import Hierarchy  # noqa: E402
from pair2scene.model import from_pretrained  # noqa: E402
from pair2scene.scene.geometry import OrientedBox, rot_x  # noqa: E402
from pair2scene.scene.model import FLOOR  # noqa: E402


@pytest.fixture(scope="module")
def placer():
    return Placer(from_pretrained())


def office() -> Hierarchy:
    h = Hierarchy("bedroom")
    bed = h.add("bed", FLOOR)
    desk = h.add("desk", FLOOR)
    h.add("chair", FLOOR, desk.id)
    h.add("side_table", FLOOR, bed.id)
    h.add("laptop", desk.id)
    h.add("mug", desk.id)
    h.add("book", desk.id)
    h.add("pillow", bed.id)
    return h.validate()


def test_places_everything_without_collisions_and_at_rest(placer):
    room = make_room("bedroom", np.random.default_rng(0))
    result = placer.place(office(), room, seed=0)
    scene, stats = result.scene, result.stats
    assert stats.requested == 8
    assert stats.placed + len(stats.dropped) == 8 and stats.placed >= 6
    by_id = {o.id: o for o in scene.objects}
    world = MeshWorld()
    assets = {}
    for o in scene.objects:
        asset = result.assets[o.id]
        np.testing.assert_allclose(asset.size, o.box.size)
        shape = Shape(asset)
        shape.set_pose(o.box.rotation, o.box.center)
        world.add(o.id, shape)
        assets[o.id] = asset
    for a, b in itertools.combinations(by_id, 2):
        assert world.penetration(world.shapes[a], world.shapes[b]) <= 0.01, (a, b)
    for o in scene.objects:
        assert abs(o.box.rotation[2, 2] - 1) < 1e-9  # upright
        if o.support == FLOOR:
            assert o.box.bottom == pytest.approx(0.0, abs=1e-9)
            assert room.contains_xy(o.box.corners()[:, :2]).all()
        else:
            sup = by_id[o.support]
            rest = rest_on_surfaces(
                assets[sup.id], sup.box, o.box, contact=contact_rectangle(assets[o.id])
            )
            assert rest is not None and o.box.bottom == pytest.approx(rest[0], abs=1e-6)
            assert not rest[1].any()  # already where the nudge put it
    assert 0 < stats.acceptance_rate <= 1 and stats.resamples_per_object >= 0
    assert set(stats.to_dict()["seconds"]) == {"model", "assets", "collision", "total"}


def test_same_seed_same_scene(placer):
    room = make_room("bedroom", np.random.default_rng(1))
    a = placer.place(office(), room, seed=5).scene
    b = placer.place(office(), room, seed=5).scene
    assert [(o.id, o.box.to_vector().tolist()) for o in a.objects] == [
        (o.id, o.box.to_vector().tolist()) for o in b.objects
    ]


def test_impossible_objects_are_dropped_with_their_dependents(placer):
    tiny = make_room("bedroom", np.random.default_rng(0))
    h = Hierarchy("bedroom")
    for _ in range(3):
        bed = h.add("bed", FLOOR)
        h.add("pillow", bed.id)
    h.validate()
    from dataclasses import replace

    cramped = replace(tiny, floor_polygon=np.array([[0, 0], [2.2, 0], [2.2, 2.6], [0, 2.6]], float))
    fast = Placer(placer.model, config=AssemblyConfig(candidates=8, batches=2))
    stats = fast.place(h, cramped, seed=0).stats
    assert stats.placed < 6 and len(stats.dropped) == 6 - stats.placed
    reasons = {d.reason for d in stats.dropped}
    assert any("no valid placement" in r for r in reasons)
    assert any("was dropped" in r for r in reasons)


def test_upright_and_door_boxes():
    tilted = OrientedBox([0, 0, 1], [1, 1, 1], rot_x(0.4))
    assert upright_yaw(tilted.rotation[:, 0]) == 0.0
    assert upright_yaw(np.array([0.0, 0.0, 1.0])) == 0.0  # x straight up: no heading
    room = make_room("bedroom", np.random.default_rng(0))
    (box,) = door_boxes(room, 0.8, room.height)
    assert box.size[1] == pytest.approx(2 * max(0.8, room.doors[0].width))
    (deep,) = door_boxes(room, 1.5, room.height)
    assert deep.size[1] == pytest.approx(3.0)


def test_yaw_snaps_to_the_support_axes_only_when_close():
    from pair2scene.scene.geometry import yaw_to_matrix

    def x_axis(deg: float) -> np.ndarray:
        return yaw_to_matrix(np.radians(deg))[:, 0]

    assert upright_yaw(x_axis(97), 0.0, 10.0) == pytest.approx(np.pi / 2)
    assert upright_yaw(x_axis(120), 0.0, 10.0) == pytest.approx(np.radians(120))
    assert upright_yaw(x_axis(33), np.radians(30), 10.0) == pytest.approx(np.radians(30))
    assert upright_yaw(x_axis(97)) == pytest.approx(np.radians(97))  # (no snap asked)


def test_an_object_whose_base_fits_no_surface_is_dropped_without_drawing(placer):
    from pair2scene.assembly.place import no_room_on
    from pair2scene.assets.registry import generate

    dresser = generate("dresser", np.array([0.65, 0.74, 1.03]), 1)
    wide_tv = generate("television", np.array([1.18, 0.07, 0.8]), 2)
    small_tv = generate("television", np.array([0.5, 0.07, 0.35]), 2)
    reason = no_room_on(wide_tv, dresser)
    assert reason is not None and reason.startswith("too large: its base is 1.18")
    assert no_room_on(small_tv, dresser) is None

    class Given(Placer):  # the assets above, whatever the size table would draw
        def assets_for(self, hierarchy, seed, given=None):
            return {"dresser_0": dresser, "television_0": wide_tv}

    h = Hierarchy("bedroom")
    d = h.add("dresser", FLOOR)
    h.add("television", d.id)
    stats = Given(placer.model).place(h.validate(), make_room("bedroom", np.random.default_rng(0)))
    stats = stats.stats
    assert [x.id for x in stats.dropped] == ["television_0"]
    assert stats.dropped[0].reason.endswith("of dresser_0")
    assert "unsupported" not in stats.rejections  # no candidate was drawn for it


class _Fixed:
    """A stand-in model whose every candidate is one given box (the query's size; the
    centre may depend on it)."""

    def __init__(self, center, yaw=0.0):
        self.center, self.yaw = center, yaw

    honours_temperature = False

    def draw(self, query, n, temperature, generator):
        center = self.center(query.size) if callable(self.center) else self.center
        box = OrientedBox.from_yaw(center, query.size, self.yaw)
        return np.repeat(box.to_vector()[None], n, axis=0), None


def _door_room():
    from pair2scene.scene.model import Opening, Room

    polygon = np.array([[0, 0], [4, 0], [4, 4], [0, 4]], float)
    return Room("bedroom", polygon, 2.6, (Opening("door", (1.5, 0.0), (2.4, 0.0), 0.0, 2.1),))


def test_a_candidate_in_a_doors_swing_is_moved_out_of_it():
    """A dresser drawn 0.35 m from the door's wall (its swing is as deep as the 0.9 m door
    is wide) moves the shortest way out of the swing, into the room, instead of being
    rejected."""
    h = Hierarchy("bedroom")
    h.add("dresser", FLOOR)
    room = _door_room()
    placer = Placer(_Fixed(lambda size: [1.95, 0.35 + size[1] / 2, size[2] / 2]))
    result = placer.place(h.validate(), room, seed=0)
    assert result.stats.placed == 1 and result.stats.resamples == [0]
    assert result.stats.repaired == 1
    (obj,) = result.scene.objects
    (zone,) = door_boxes(room, placer.config.door_clearance_m, room.height)
    half = obj.box.size[1] / 2
    assert obj.box.center[1] - half == pytest.approx(0.9 + 2e-3, abs=1e-6)  # just clear
    assert zone.size[1] == pytest.approx(2 * 0.9)
    assert obj.box.center[0] == pytest.approx(1.95)
    far = Placer(placer.model, config=AssemblyConfig(floor_repair_m=0.5))
    stats = far.place(h, room, seed=0).stats  # 0.55 m out of the swing: too far
    assert stats.placed == 0 and stats.rejections == {"door": 256}


def test_a_floor_object_pushed_flush_against_a_wall_stays():
    """Moved into the room and flush against the wall, a footprint's corners lie on the
    wall, where the even-odd polygon test answers either way: still in the room."""
    h = Hierarchy("bedroom")
    h.add("dresser", FLOOR)
    for x in (3.7, 3.95, 4.1):  # near the wall at x = 4, through it, half out
        result = Placer(_Fixed([x, 2.0, 0.5], yaw=np.pi / 2)).place(
            h.validate(), _door_room(), seed=0
        )
        assert result.stats.placed == 1 and result.stats.resamples == [0], x
        (obj,) = result.scene.objects
        assert obj.box.corners()[:, 0].max() == pytest.approx(4.0, abs=2e-3)


@pytest.mark.parametrize("shape", ["rectangle", "L"])
def test_no_candidate_drawn_outside_the_floor_region_could_stay(shape):
    """The floor region is where the model's draws are confined: it must hold every
    centre the room test could accept. Centres drawn just outside it (any yaw, any size,
    rectangular and L-shaped rooms) are all refused by into_room with the placer's reach;
    a little inside it (it allows for the wall snap, which only narrow rooms use) some
    are taken: it is not needlessly wide either."""
    from pair2scene.scene.model import Room

    cfg = AssemblyConfig()
    polygon = {"rectangle": [[0, 0], [4.2, 0], [4.2, 3.1], [0, 3.1]],
               "L": [[0, 0], [5, 0], [5, 2], [2.5, 2], [2.5, 4], [0, 4]]}[shape]  # fmt: skip
    room = Room("bedroom", np.array(polygon, float), 2.6)
    rng = np.random.default_rng(7)
    taken_inside = 0
    for _ in range(400):
        size = rng.uniform([0.2, 0.2, 0.3], [2.2, 2.4, 1.5])
        region = floor_region(room, size, cfg.floor_repair_m + cfg.wall_snap_m)
        yaw = rng.choice([0.0, np.pi / 2, rng.uniform(0, 2 * np.pi)])
        side = rng.integers(4)
        axis, sign = side % 2, 1 if side < 2 else -1
        for offset, outside in ((0.005, True), (-cfg.wall_snap_m - 0.02, False)):
            centre = region.center.copy()
            centre[1 - axis] += rng.uniform(-1, 1) * region.half_size[1 - axis]
            centre[axis] += sign * (region.half_size[axis] + offset)
            box = OrientedBox.from_yaw([*centre[:2], size[2] / 2], size, yaw)
            kept = into_room(box, room.floor_polygon, cfg.floor_repair_m, cfg.wall_snap_m)
            if outside:
                assert kept is None, (size, yaw, centre)
            else:
                taken_inside += kept is not None
    assert taken_inside > 20


def test_floor_draws_are_confined_to_the_room_and_the_rest_reported(placer):
    """With the bundled model every floor candidate's centre lies in its floor region,
    and the scene's statistics give the mass the model put beyond it (0 < m < 1)."""
    h = office()
    room = make_room("bedroom", np.random.default_rng(0))
    seen = []
    model = placer.model

    class Spy:
        def draw(self, query, *args):
            boxes, mass = model.draw(query, *args)
            seen.append((query, boxes, mass))
            return boxes, mass

    result = Placer(Spy(), config=placer.config).place(h, room, seed=1)
    floor = [(q, b, m) for q, b, m in seen if q.support.is_floor]
    assert len(floor) == 4 and all(q.region is not None for q, _, _ in floor)
    for q, boxes, mass in floor:
        assert (np.abs(boxes[:, :2] - q.region.center[:2]) <= q.region.half_size[:2] + 1e-9).all()
        assert 0 < mass <= 1
    outside = result.scene.stats["model_mass_outside_room"]
    assert outside == pytest.approx(np.mean([1 - m for _, _, m in floor]), abs=1e-4)
    assert all(q.region is None for q, _, _ in seen if not q.support.is_floor)


class _AgainstTheWall:
    """A dresser flush against the wall y = 4, and on it a candidate whose base rests
    on the top's back edge while its leaves (its box) reach through the wall."""

    honours_temperature = False

    def __init__(self):
        self.drawn = {}

    def draw(self, query, n, temperature, generator):
        from pair2scene.assets.surfaces import surfaces_of

        size = np.asarray(query.size, float)
        if query.support.is_floor:
            box = OrientedBox.from_yaw([2.0, 4.0 - size[1] / 2, size[2] / 2], size, 0.0)
        else:
            sup = query.support
            top = max(surfaces_of(sup.asset), key=lambda s: s.polygon[:, 1].max())
            base = contact_rectangle(query.asset)[:, 1].max()
            y = sup.box.center[1] + top.polygon[:, 1].max() - base - 0.005
            box = OrientedBox.from_yaw([2.0, y, sup.box.top + size[2] / 2], size, 0.0)
        self.drawn[query.category] = box
        return np.repeat(box.to_vector()[None], n, axis=0), None


def test_an_object_on_a_support_does_not_reach_through_a_wall():
    """Objects on a support were tested against the walls only through their support:
    a plant whose pot stood at the back edge of a dresser flush against the wall had its
    leaves through the wall (and a book overhanging that edge fell in simulation). It is
    moved into the room like a floor object (within the support's nudge)."""
    h = Hierarchy("bedroom")
    dresser = h.add("dresser", FLOOR)
    h.add("house_plant", dresser.id)
    model = _AgainstTheWall()
    # (the dresser is drawn facing the wall: the navigation guard, which would refuse
    # it for its front out of reach, is not what this test is about)
    config = AssemblyConfig(navigable=False)
    result = Placer(model, config=config).place(h.validate(), _door_room(), seed=0)
    assert result.stats.placed == 2, result.stats.dropped
    plant = next(o for o in result.scene.objects if o.category == "house_plant")
    assert model.drawn["house_plant"].corners()[:, 1].max() > 4.05  # drawn through it
    assert plant.box.corners()[:, 1].max() <= 4.0 + 2e-3
    assert result.stats.repaired >= 1


class _PerCategory(_Fixed):
    """A stand-in model drawing one given box per category (the centre may depend on the
    query's size)."""

    def draw(self, query, n, temperature, generator):
        center = self.center[query.category](query.size)
        box = OrientedBox.from_yaw(center, query.size, self.yaw)
        return np.repeat(box.to_vector()[None], n, axis=0), None


def test_what_rests_on_a_table_by_the_door_does_not_overhang_into_its_swing():
    """A dining table stands just clear of the door's zone (0.9 m deep: the door's width);
    a house plant drawn on its near edge, its foliage over the zone, is moved back onto
    the table out of the zone, as a floor object would be."""
    h = Hierarchy("living_room")
    table = h.add("dining_table", FLOOR)
    h.add("house_plant", table.id)
    room = _door_room()
    edge = 0.9 + 0.01  # the table's near edge, just clear of the zone
    tops = {}

    def table_at(size):
        tops["z"] = float(size[2])
        return [1.95, edge + size[1] / 2, size[2] / 2]

    def plant_at(size):  # its box's near half over the zone, its pot on the table
        return [1.95, edge + 0.6 * size[1] / 2, tops["z"] + size[2] / 2]

    placer = Placer(_PerCategory({"dining_table": table_at, "house_plant": plant_at}))
    result = placer.place(h.validate(), room, seed=0)
    assert result.stats.placed == 2, result.stats.dropped
    plant = next(o for o in result.scene.objects if o.category == "house_plant")
    (zone,) = door_boxes(room, placer.config.door_clearance_m, room.height)
    assert plant.box.corners()[:, 1].min() >= zone.corners()[:, 1].max() - 1e-6
    assert plant.support == table.id and result.stats.repaired == 1


class _Recording:
    """The bundled model, noting the temperature each query is drawn at."""

    def __init__(self, inner):
        self.inner, self.seen = inner, []

    def __getattr__(self, name):
        return getattr(self.inner, name)

    def draw(self, query, n, temperature, generator, *args, **kwargs):
        self.seen.append((query.category, temperature))
        return self.inner.draw(query, n, temperature, generator, *args, **kwargs)


def test_objects_on_a_support_are_drawn_at_the_support_temperature():
    model = _Recording(from_pretrained())
    config = AssemblyConfig(temperature=0.7, support_temperature=0.9)
    h = Hierarchy("bedroom")
    dresser = h.add("dresser", FLOOR)
    h.add("book", dresser.id)
    result = Placer(model, config=config).place(
        h.validate(), make_room("bedroom", np.random.default_rng(0)), seed=0
    )
    assert result.stats.placed == 2
    assert {c: t for c, t in model.seen} == {"dresser": 0.7, "book": 0.9}
    with pytest.raises(UserError, match="support-temperature must be > 0"):
        AssemblyConfig(support_temperature=0.0)

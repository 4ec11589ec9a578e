"""Physical validation: corrupted scenes lose exactly what is wrong, clean ones nothing."""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest

from pair2scene.assets.identity import asset_seed
from pair2scene.curation.physics import (
    PhysicsConfig,
    Role,
    dependents_closure,
    plan_bodies,
    rotation_shift,
    validate_physics,
)
from pair2scene.scene.geometry import OrientedBox
from pair2scene.scene.model import FLOOR, Room, Scene, SceneObject

TABLE_SIZE = (1.0, 0.8, 0.75)
MUG_SIZE = (0.1, 0.08, 0.1)
CHAIR_SIZE = (0.45, 0.5, 0.9)


def _obj(oid, category, center, size, support=FLOOR, yaw=0.0, **kw) -> SceneObject:
    return SceneObject(
        oid, category, OrientedBox.from_yaw(center, size, yaw), support=support, **kw
    )


def _room() -> Room:
    return Room("dining_room", np.array([[-3.0, -3.0], [3.0, -3.0], [3.0, 3.0], [-3.0, 3.0]]))


def _clean_objects() -> list[SceneObject]:
    top = TABLE_SIZE[2]
    return [
        _obj("table_0", "dining_table", (0.0, 0.0, top / 2), TABLE_SIZE),
        _obj("mug_0", "mug", (0.2, 0.1, top + MUG_SIZE[2] / 2), MUG_SIZE, support="table_0"),
        _obj("chair_0", "chair", (1.5, 0.0, CHAIR_SIZE[2] / 2), CHAIR_SIZE, yaw=np.pi / 2),
    ]


def _scene(objects) -> Scene:
    return Scene("test/room", _room(), list(objects), source="test")


def _moved(o: SceneObject, dz=0.0, dx=0.0) -> SceneObject:
    return o.with_box(OrientedBox(o.box.center + [dx, 0.0, dz], o.box.size, o.box.rotation))


def test_clean_scene_loses_nothing():
    out = validate_physics(_scene(_clean_objects()))
    assert out.dropped == {}, out.dropped
    assert [o.id for o in out.scene.objects] == ["table_0", "mug_0", "chair_0"]
    assert set(out.motion) == {"table_0", "mug_0", "chair_0"}
    assert all(t < 0.01 and r < 2.0 for t, r in out.motion.values()), out.motion
    assert out.notes == []


def test_floating_mug_is_dropped():
    objs = _clean_objects()
    objs[1] = _moved(objs[1], dz=0.3)
    out = validate_physics(_scene(objs), config=PhysicsConfig(max_fall_m=0.0))
    assert set(out.dropped) == {"mug_0"}
    assert out.dropped["mug_0"].startswith("moved")
    assert out.motion["mug_0"][0] > 0.25


@pytest.mark.parametrize("dz", [0.3, 0.9])
def test_mug_held_above_its_table_falls_onto_it_and_stays(dz):
    """A spawn pose (ProcTHOR's pillows over a bed): it lands on the top, and is kept."""
    objs = _clean_objects()
    objs[1] = _moved(objs[1], dz=dz)
    out = validate_physics(_scene(objs))
    assert out.dropped == {}
    assert out.fitted["mug_0"] == pytest.approx(-dz, abs=0.02)
    assert out.motion["mug_0"][0] < 0.05


def test_mug_far_above_its_table_or_beside_it_is_still_dropped():
    objs = _clean_objects()
    high = _moved(objs[1], dz=1.3)  # further than max_fall_m
    beside = _moved(objs[1], dz=0.3, dx=0.45)  # its centre is past the table's edge
    for mug in (high, beside):
        out = validate_physics(_scene([objs[0], mug, objs[2]]))
        assert set(out.dropped) == {"mug_0"}, out.dropped
        assert "mug_0" not in out.fitted


def test_book_half_off_the_edge_tips_and_is_dropped():
    top = TABLE_SIZE[2]
    edge = TABLE_SIZE[0] / 2
    book = _obj("book_0", "book", (edge + 0.08, 0.0, top + 0.02), (0.24, 0.17, 0.04), "table_0")
    out = validate_physics(_scene([*_clean_objects(), book]))
    assert set(out.dropped) == {"book_0"}


def test_interpenetrating_chairs_lose_at_least_one():
    objs = _clean_objects()
    chair = objs[2]
    # the second chair's box overlaps the first's by 10 cm along x
    second = _moved(replace(chair, id="chair_1"), dx=CHAIR_SIZE[1] - 0.10)
    out = validate_physics(_scene([*objs, second]))
    assert {"chair_0", "chair_1"} & set(out.dropped)
    assert set(out.dropped) <= {"chair_0", "chair_1"}
    assert any(r.startswith("overlapped") for r in out.dropped.values())


def test_dropped_table_takes_its_mug():
    objs = _clean_objects()
    objs[0] = _moved(objs[0], dz=0.3)  # the table floats...
    objs[1] = _moved(objs[1], dz=0.3)  # ...with its mug on it
    out = validate_physics(_scene(objs))
    assert set(out.dropped) == {"table_0", "mug_0"}
    assert [o.id for o in out.scene.objects] == ["chair_0"]


def test_dependents_closure_follows_support_chains_and_owned_parts():
    objs = [
        *_clean_objects(),
        _obj("book_0", "book", (0.0, 0.0, 0.8), (0.2, 0.15, 0.03), support="table_0"),
        _obj("pen_0", "pen", (0.0, 0.0, 0.82), (0.01, 0.14, 0.01), support="book_0"),
        _obj("drawer_0", "drawer", (0.0, 0.3, 0.6), (0.4, 0.2, 0.1), part_of="table_0"),
        _obj("drawer_1", "drawer", (0.0, 0.3, 0.6), (0.4, 0.2, 0.1), part_of="mug_0"),
    ]
    scene = _scene(objs)
    out = dependents_closure(scene, {"table_0": "moved 0.30 m"}, plan_bodies(scene))
    assert out["mug_0"] == "rests on dropped table_0"
    assert out["pen_0"] == "rests on dropped book_0"
    assert out["drawer_0"] == "part of dropped table_0"
    # a part "of" a small object is the adapter's host guess: it does not follow it
    assert "drawer_1" not in out
    assert "chair_0" not in out


def test_plan_bodies_roles():
    objs = [
        *_clean_objects(),
        _obj("painting_0", "painting", (0.0, 2.99, 1.5), (0.8, 0.02, 0.6), support=None),
        _obj("counter_top_0", "counter_top", (-2.0, 0.0, 0.45), (0.6, 2.0, 0.9)),
        _obj("tv_0", "television", (2.9, 0.0, 1.5), (1.0, 0.06, 0.6), support=None),
        _obj("remote_0", "remote_control", (0.0, 0.0, 0.02), (0.05, 0.15, 0.02), support=None),
        _obj("shelf_0", "shelf", (0.0, 0.0, 0.2), (0.9, 0.7, 0.02), part_of="table_0"),
        _obj("cabinet_door_0", "cabinet_door", (-2.0, 0.3, 0.4), (0.5, 0.02, 0.7)),
    ]
    plans = plan_bodies(_scene(objs))
    roles = {k: p.role for k, p in plans.items()}
    assert roles["table_0"] is Role.FREE and roles["mug_0"] is Role.FREE
    assert roles["painting_0"] is Role.STATIC  # wall object
    assert roles["counter_top_0"] is Role.STATIC  # fixture
    assert roles["tv_0"] is Role.STATIC  # no support known, high above the floor
    assert roles["remote_0"] is Role.FREE  # no support known, but on the floor
    assert roles["shelf_0"] is Role.OWNED and plans["shelf_0"].owner == "table_0"
    assert roles["cabinet_door_0"] is Role.STATIC  # a part with no furniture owner


def test_static_objects_are_never_dropped():
    painting = _obj("painting_0", "painting", (0.0, 2.99, 1.5), (0.8, 0.02, 0.6), support=None)
    out = validate_physics(_scene([*_clean_objects(), painting]))
    assert out.roles["painting_0"] is Role.STATIC
    assert "painting_0" not in out.dropped and "painting_0" not in out.motion


def test_same_input_same_output():
    objs = _clean_objects()
    objs[1] = _moved(objs[1], dz=0.3)
    a = validate_physics(_scene(objs))
    b = validate_physics(_scene(objs))
    assert a.dropped == b.dropped and a.motion == b.motion and a.fitted == b.fitted


def test_asset_seed_is_stable():
    assert asset_seed("chair_0") == asset_seed("chair_0")
    assert asset_seed("chair_0") != asset_seed("chair_1")
    assert asset_seed("chair_0", seed=1) != asset_seed("chair_0")


def test_rotation_shift():
    q0 = np.array([[1.0, 0.0, 0.0, 0.0]])
    a = np.radians(90)
    qz = np.array([[np.cos(a / 2), 0.0, 0.0, np.sin(a / 2)]])
    half = np.array([[1.0, 1.0, 1.0]])
    # a quarter turn about z moves a corner (1, 1, z) by |(-1, 1) - (1, 1)| = 2
    assert rotation_shift(q0, qz, half)[0] == pytest.approx(2.0)
    assert rotation_shift(q0, q0, half)[0] == pytest.approx(0.0)


def test_empty_and_static_only_scenes():
    out = validate_physics(_scene([]))
    assert out.dropped == {} and out.scene.objects == []
    painting = _obj("painting_0", "painting", (0.0, 2.99, 1.5), (0.8, 0.02, 0.6), support=None)
    out = validate_physics(_scene([painting]))
    assert out.dropped == {} and len(out.scene.objects) == 1


def test_ai2thor_fixture_room_keeps_most_objects(fixtures):
    from pair2scene.data.ai2thor import load_ai2thor

    corpus = load_ai2thor(fixtures / "ai2thor")
    config = PhysicsConfig()
    kept = total = 0
    for scene in corpus.scenes:
        out = validate_physics(scene, config=config)
        assert out.notes == [], out.notes
        assert {o.id for o in out.scene.objects} | set(out.dropped) == {o.id for o in scene.objects}
        kept += len(out.scene.objects)
        total += len(scene.objects)
    # Measured: 115 of 164 kept (70%). The losses are mostly where the procedural
    # stand-ins differ from the AI2-THOR assets: the bedroom desk's pedestal sits where
    # the source's chair is tucked in, and the desk takes its 15 parts and 7 objects.
    assert kept / total >= 0.65, (kept, total)


def test_food_stands_in_a_fridge_and_on_a_table():
    """An egg on its broad end on a fridge shelf and a potato lying on a table stay put
    (a round-bottomed egg toppled and a round potato rolled, and curation dropped them)."""
    fridge = (0.8, 0.75, 1.8)
    egg, potato = (0.055, 0.055, 0.078), (0.081, 0.123, 0.081)
    top = TABLE_SIZE[2]
    objs = [
        _obj("fridge_0", "fridge", (-2.0, 0.0, fridge[2] / 2), fridge),
        _obj("egg_0", "egg", (-2.1, -0.05, 0.95 + egg[2] / 2), egg, support="fridge_0"),
        _obj("egg_1", "egg", (-1.9, 0.05, 0.5 + egg[2] / 2), egg, support="fridge_0"),
        *_clean_objects(),
        _obj("potato_0", "potato", (-0.2, 0.0, top + potato[2] / 2), potato, support="table_0"),
    ]
    for seed in range(3):
        out = validate_physics(_scene(objs), config=PhysicsConfig(seed=seed))
        assert out.dropped == {}, (seed, out.dropped)


def test_objects_on_a_deep_counter_stand_wherever_its_top_was():
    """A 2.44 x 1.83 m counter is built as an L or a C of runs for generation, open in
    the front middle; the source's counter may be an island or a C of another hand, so
    the check stands its objects on the counter's solid form and keeps a mug there."""
    size = (2.44, 1.83, 0.9)
    counter = _obj("counter_0", "counter_top", (0.0, 0.0, size[2] / 2), size)
    mugs = [
        _obj(f"mug_{k}", "mug", (x, y, size[2] + MUG_SIZE[2] / 2), MUG_SIZE, support="counter_0")
        for k, (x, y) in enumerate([(0.0, 0.7), (0.0, -0.6)])  # the front middle, the back
    ]
    out = validate_physics(_scene([counter, *mugs]))
    assert out.dropped == {}, out.dropped
    assert {"mug_0", "mug_1"} <= {o.id for o in out.scene.objects}

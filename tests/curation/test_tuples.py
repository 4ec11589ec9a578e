"""Relation tuples of a hand-made scene: canonical frames, kinds, skips, floor-only exclusion."""

from __future__ import annotations

from collections import Counter

import numpy as np
import pytest

from pair2scene.curation.tuples import PairTuple, RelationKind, scene_tuples
from pair2scene.scene.geometry import OrientedBox
from pair2scene.scene.model import FLOOR, AssetRef, Room, Scene, SceneObject

YAW = np.radians(30.0)
TABLE = OrientedBox.from_yaw([2.0, 1.5, 0.375], [1.2, 0.8, 0.75], YAW)


def obj(oid, cat, center, size, yaw=0.0, support=FLOOR, functional=None, **kw):
    box = OrientedBox.from_yaw(center, size, yaw)
    asset = AssetRef("ai2thor", f"{cat}_asset", None)
    return SceneObject(oid, cat, box, asset, support=support, functional_anchor=functional, **kw)


def dining_scene() -> Scene:
    """A 4 x 3 m room, 2.5 m high: a rotated table with a mug at the centre of its top,
    a chair at the table, a sofa, a painting on the wall and a drawer of the table."""
    room = Room("dining_room", np.array([[0, 0], [4, 0], [4, 3], [0, 3]], float), 2.5)
    objects = [
        SceneObject("table_0", "dining_table", TABLE, AssetRef("ai2thor", "T1", 2), support=FLOOR),
        obj("mug_0", "mug", [2.0, 1.5, 0.8], [0.1, 0.1, 0.1], yaw=YAW, support="table_0"),
        obj("chair_0", "chair", [2.0, 0.8, 0.45], [0.5, 0.5, 0.9], functional="table_0"),
        obj("sofa_0", "sofa", [1.0, 2.5, 0.4], [2.0, 0.9, 0.8]),
        obj("painting_0", "painting", [0.02, 1.5, 1.6], [0.05, 0.8, 0.6], support=None),
        obj("drawer_0", "drawer", [2.0, 1.5, 0.6], [0.4, 0.4, 0.1], support="table_0",
            part_of="table_0"),
    ]  # fmt: skip
    return Scene("test/dining", room, objects, source="handmade", split="train")


def by_dep(tuples: list[PairTuple]) -> dict[str, PairTuple]:
    return {t.dependent.id: t for t in tuples}


def test_mug_at_the_centre_of_a_table_top():
    t = by_dep(scene_tuples(dining_scene()))["mug_0"]
    assert t.kind is RelationKind.SUPPORT
    assert (t.support.id, t.support.category) == ("table_0", "dining_table")
    assert t.support.asset == AssetRef("ai2thor", "T1", 2)
    assert t.support.box is TABLE
    # centred over the table, just above its top (z = +1 in the canonical frame)
    np.testing.assert_allclose(t.canonical.center, [0.0, 0.0, (0.8 - 0.375) / 0.375], atol=1e-9)
    np.testing.assert_allclose(t.canonical.size, [0.1 / 0.6, 0.1 / 0.4, 0.1 / 0.375])
    np.testing.assert_allclose(t.canonical.rotation, np.eye(3), atol=1e-9)  # table's turn removed
    assert t.canonical.from_frame_of(TABLE).allclose(t.dependent.box)
    assert t.functional is None and t.canonical_functional is None


def test_floor_tuple_uses_the_room_bounds():
    t = by_dep(scene_tuples(dining_scene()))["sofa_0"]
    assert t.kind is RelationKind.FLOOR
    assert (t.support.id, t.support.category, t.support.asset) == (FLOOR, "floor", None)
    np.testing.assert_allclose(t.support.box.center, [2.0, 1.5, 1.25])
    np.testing.assert_allclose(t.support.box.size, [4.0, 3.0, 2.5])
    # x: (1 - 2) / 2, y: (2.5 - 1.5) / 1.5, z: (0.4 - 1.25) / 1.25
    np.testing.assert_allclose(t.canonical.center, [-0.5, 1 / 1.5, -0.68])
    np.testing.assert_allclose(t.canonical.size, [1.0, 0.6, 0.64])


def test_functional_tuple_keeps_both_frames():
    t = by_dep(scene_tuples(dining_scene()))["chair_0"]
    assert t.kind is RelationKind.FUNCTIONAL
    assert t.support.id == FLOOR and t.functional.id == "table_0"
    assert t.functional.box is TABLE
    chair = t.dependent.box
    assert t.canonical.allclose(chair.in_frame_of(t.support.box))
    assert t.canonical_functional.allclose(chair.in_frame_of(TABLE))
    # in the table's frame the chair is beside it, on the table's local -y side
    assert t.canonical_functional.center[1] < -1.0


def test_scene_order_skips_and_metadata():
    skipped: Counter[str] = Counter()
    tuples = scene_tuples(dining_scene(), skipped=skipped)
    assert [t.dependent.id for t in tuples] == ["table_0", "mug_0", "chair_0", "sofa_0"]
    assert skipped == {"no support": 1, "part": 1}
    t = tuples[0]
    assert (t.source, t.scene_id, t.split, t.room_type) == (
        "handmade", "test/dining", "train", "dining_room"
    )  # fmt: skip
    assert scene_tuples(dining_scene(), source="other")[0].source == "other"


def test_exclude_floor_only_keeps_functional_tuples_on_the_floor():
    skipped: Counter[str] = Counter()
    tuples = scene_tuples(dining_scene(), exclude_floor_only=True, skipped=skipped)
    assert [t.dependent.id for t in tuples] == ["mug_0", "chair_0"]
    assert skipped["floor-only excluded"] == 2


def test_dangling_references():
    scene = dining_scene()
    objects = [o for o in scene.objects if o.id != "table_0"]
    skipped: Counter[str] = Counter()
    tuples = scene_tuples(Scene(scene.id, scene.room, objects, "handmade"), skipped=skipped)
    # the mug's support is gone: no tuple; the chair loses its functional anchor only
    assert [t.dependent.id for t in tuples] == ["chair_0", "sofa_0"]
    assert tuples[0].kind is RelationKind.FLOOR and tuples[0].functional is None
    assert skipped["support not in scene"] == 1


@pytest.mark.parametrize("kind", list(RelationKind))
def test_relation_kinds_are_strings(kind):
    assert RelationKind(kind.value) is kind

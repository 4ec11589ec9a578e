"""Scene model: rooms, openings, objects, scenes and their relation tuples."""

from __future__ import annotations

import numpy as np
import pytest

from pair2scene.categories import SuperCategory
from pair2scene.scene.geometry import OrientedBox, polygon_area
from pair2scene.scene.model import (
    FLOOR,
    AssetRef,
    Opening,
    RelationTuple,
    Room,
    Scene,
    SceneObject,
)

CCW = [[0.0, 0.0], [4.0, 0.0], [4.0, 3.0], [0.0, 3.0]]
L_SHAPE = [[0, 0], [2, 0], [2, 1], [1, 1], [1, 2], [0, 2]]


def obj(oid: str, category: str = "unknown", support=None, functional=None) -> SceneObject:
    box = OrientedBox([0.0, 0.0, 0.5], [1.0, 1.0, 1.0])
    return SceneObject(oid, category, box, support=support, functional_anchor=functional)


def room() -> Room:
    return Room("bedroom", np.array(CCW))


# -- Room ------------------------------------------------------------------------------
def test_room_keeps_counter_clockwise_polygon():
    r = Room("bedroom", CCW)
    np.testing.assert_array_equal(r.floor_polygon, CCW)
    assert r.area == pytest.approx(12.0)
    assert r.height == 2.7


def test_room_normalises_clockwise_polygon():
    cw = CCW[::-1]
    assert polygon_area(cw) < 0
    r = Room("bedroom", cw)
    assert polygon_area(r.floor_polygon) == pytest.approx(12.0)
    assert r.area == pytest.approx(12.0)
    np.testing.assert_array_equal(r.floor_polygon, CCW)  # reversed back
    assert {tuple(p) for p in r.floor_polygon} == {tuple(p) for p in CCW}


def test_room_normalises_clockwise_l_shape():
    r = Room("kitchen", L_SHAPE[::-1])
    assert r.area == pytest.approx(3.0)
    assert r.floor_polygon.dtype == float


def test_room_polygon_is_a_read_only_copy():
    src = np.array(CCW)
    r = Room("bedroom", src)
    src[0, 0] = 99.0
    assert r.floor_polygon[0, 0] == 0.0
    with pytest.raises(ValueError):
        r.floor_polygon[0, 0] = 1.0


@pytest.mark.parametrize(
    "polygon",
    [[[0, 0], [1, 0]], [], [[0, 0, 0], [1, 0, 0], [1, 1, 0]], [0, 1, 2, 3]],
    ids=["two-points", "empty", "3d-points", "flat"],
)
def test_room_rejects_bad_polygons(polygon):
    with pytest.raises(ValueError, match="floor_polygon"):
        Room("bedroom", polygon)


def test_room_bounds():
    r = Room("living_room", np.array(L_SHAPE) * 2.0 + [1.0, -1.0], height=2.5)
    b = r.bounds
    np.testing.assert_allclose(b.center, [3.0, 1.0, 1.25])
    np.testing.assert_allclose(b.size, [4.0, 4.0, 2.5])
    np.testing.assert_array_equal(b.rotation, np.eye(3))
    assert b.bottom == pytest.approx(0.0)
    assert b.top == pytest.approx(2.5)


def test_room_contains_xy():
    r = Room("bedroom", L_SHAPE)
    np.testing.assert_array_equal(
        r.contains_xy(np.array([[0.5, 0.5], [1.5, 1.5], [0.5, 1.5], [3.0, 0.5]])),
        [True, False, True, False],
    )


def test_opening_width_and_defaults():
    door = Opening("door", (1.0, 0.0), (1.6, 0.8))
    assert door.width == pytest.approx(1.0)
    assert (door.z_min, door.z_max, door.id) == (0.0, 2.1, None)


# -- SceneObject -----------------------------------------------------------------------
def test_scene_object_with_box_and_super_category():
    o = SceneObject("bed_0", "bed", OrientedBox([0, 0, 0.3], [2, 1.6, 0.6]), AssetRef("user"))
    moved = o.with_box(OrientedBox([1, 0, 0.3], [2, 1.6, 0.6]))
    assert moved.box.center[0] == 1.0 and o.box.center[0] == 0.0
    assert moved.id == o.id and moved.asset == o.asset
    assert o.super == SuperCategory.LARGE_FURNITURE
    assert obj("x", "unknown").super == SuperCategory.UNKNOWN


def test_asset_ref_to_dict():
    assert AssetRef("procedural", style=2).to_dict() == {
        "source": "procedural",
        "id": None,
        "style": 2,
    }


# -- Scene -----------------------------------------------------------------------------
def test_scene_rejects_duplicate_ids():
    with pytest.raises(ValueError, match="duplicate object ids.*'a'"):
        Scene("s", room(), [obj("a"), obj("b"), obj("a")])


def test_scene_accepts_empty_and_unique():
    assert Scene("s", room()).objects == []
    s = Scene("s", room(), [obj("a"), obj("b")])
    assert [o.id for o in s.objects] == ["a", "b"]


def make_scene() -> Scene:
    return Scene(
        "s",
        room(),
        [
            obj("desk", "desk", support=FLOOR),
            obj("laptop", "laptop", support="desk"),
            obj("chair", "chair", support=FLOOR, functional="desk"),
            obj("mug", "mug", support="desk", functional="laptop"),
            obj("loose", "book", support=None),
        ],
    )


def test_support_edges_skip_floor_and_unknown():
    assert make_scene().support_edges() == [("laptop", "desk"), ("mug", "desk")]


def test_tuples_in_file_order():
    assert make_scene().tuples() == [
        RelationTuple("desk", FLOOR, None),
        RelationTuple("laptop", "desk", None),
        RelationTuple("chair", FLOOR, "desk"),
        RelationTuple("mug", "desk", "laptop"),
    ]


def test_lookup_helpers():
    s = make_scene()
    assert s.get("mug").category == "mug"
    assert set(s.by_id()) == {"desk", "laptop", "chair", "mug", "loose"}
    assert [o.id for o in s.children(FLOOR)] == ["desk", "chair"]
    assert [o.id for o in s.children("desk")] == ["laptop", "mug"]
    assert s.children("mug") == []
    with pytest.raises(KeyError):
        s.get("nope")

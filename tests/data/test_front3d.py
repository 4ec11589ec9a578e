"""3D-FRONT adapter: frame conversion, floor outlines, openings, labels, splits, errors.

The fixture under tests/fixtures/3dfront is hand-written in the 3D-FRONT format
(see its README); the expected numbers below are read off that fixture.
"""

from __future__ import annotations

import json
import shutil
from collections import Counter
from pathlib import Path

import numpy as np
import pytest

from pair2scene.categories import UNKNOWN
from pair2scene.data import front3d
from pair2scene.data.base import stable_fraction
from pair2scene.data.front3d import (
    floor_outline,
    future_box,
    load_front3d,
    quaternion_to_matrix,
    rect_polygon_distance,
)
from pair2scene.errors import UserError
from pair2scene.io.scene_json import scene_from_dict, scene_to_dict
from pair2scene.scene.geometry import corner_distance, is_rotation, polygon_area

FIXTURE = Path(__file__).resolve().parents[1] / "fixtures" / "3dfront"
HOUSE_FILES = ("fx-house-a.json", "fx-house-b.json")
S45 = float(np.sqrt(0.5))
IDENTITY = (0.0, 0.0, 0.0, 1.0)
YAW_90 = (0.0, S45, 0.0, S45)
"""+90 degrees about the source's up axis (+y)."""


def y_quat(degrees: float) -> tuple[float, float, float, float]:
    half = np.radians(degrees) / 2
    return (0.0, float(np.sin(half)), 0.0, float(np.cos(half)))


@pytest.fixture(scope="module")
def corpus():
    return load_front3d(FIXTURE)


@pytest.fixture(scope="module")
def scenes(corpus):
    return {s.id: s for s in corpus.scenes}


# -- frame conversion ----------------------------------------------------------------
def test_identity_chair_faces_world_minus_y():
    box = future_box((0.5, 0.9, 0.6), pos=(0, 0, 0), rot=IDENTITY)
    r = box.rotation
    assert is_rotation(r) and np.linalg.det(r) == pytest.approx(1.0)
    # model front +z -> world (x, -z, y) = -Y; model up +y -> world +Z; model +x is the
    # chair's left, so its right is world -X.
    np.testing.assert_allclose(r[:, 1], [0, -1, 0], atol=1e-12)
    np.testing.assert_allclose(r[:, 2], [0, 0, 1], atol=1e-12)
    np.testing.assert_allclose(r[:, 0], [-1, 0, 0], atol=1e-12)
    np.testing.assert_allclose(np.cross(r[:, 0], r[:, 1]), r[:, 2], atol=1e-12)


def test_yaw_about_source_up_is_yaw_about_world_up():
    box = future_box((0.5, 0.9, 0.6), pos=(0, 0, 0), rot=YAW_90)
    # R_y(+90) turns the model's +z (front) to source +x, which is world +X.
    np.testing.assert_allclose(box.rotation[:, 1], [1, 0, 0], atol=1e-12)
    np.testing.assert_allclose(box.rotation[:, 2], [0, 0, 1], atol=1e-12)
    assert np.linalg.det(box.rotation) == pytest.approx(1.0)
    for deg in (0, 30, 90, 180, -120):
        yawed = future_box((1, 1, 1), (0, 0, 0), y_quat(deg))
        # identity faces -Y (heading -90 deg); a source yaw adds counter-clockwise.
        front = yawed.rotation[:, 1]
        heading = np.degrees(np.arctan2(front[1], front[0]))
        assert (heading - (deg - 90) + 180) % 360 - 180 == pytest.approx(0, abs=1e-9)


def test_size_permutation_and_scale():
    box = future_box((2.0, 1.0, 3.0), pos=(0, 0, 0), rot=y_quat(37), scale=(1.5, 0.5, 2.0))
    # ours (right, front, up) = model (x, z, y), each scaled along its own model axis.
    np.testing.assert_allclose(box.size, [3.0, 6.0, 0.5])


def test_bottom_origin_puts_bed_on_floor():
    box = future_box((1.8, 1.1, 2.1), pos=(1.0, 0.0, -2.0), rot=y_quat(180), scale=(1, 1.2, 1))
    assert box.bottom == pytest.approx(0.0, abs=1e-12)
    assert box.top == pytest.approx(1.32)
    np.testing.assert_allclose(box.center, [1.0, 2.0, 0.66], atol=1e-12)


def test_quaternion_matrix_is_rotation_and_normalises():
    rng = np.random.default_rng(0)
    for q in rng.normal(size=(20, 4)):
        assert is_rotation(quaternion_to_matrix(3.0 * q))
    np.testing.assert_allclose(quaternion_to_matrix(YAW_90) @ [0, 0, 1], [1, 0, 0], atol=1e-12)
    with pytest.raises(ValueError):
        quaternion_to_matrix((0, 0, 0, 0))


def _source_corners(size, pos, rot, scale) -> np.ndarray:
    """(8, 3) world corners of a placed model, computed in 3D-FRONT's own frame."""
    sx, sy, sz = size
    local = np.array(
        [[x, y, z] for x in (-sx / 2, sx / 2) for y in (0, sy) for z in (-sz / 2, sz / 2)]
    )
    src = (local * scale) @ quaternion_to_matrix(rot).T + pos  # (8, 3), y up
    return front3d.front_points_to_world(src)


@pytest.mark.parametrize("seed", range(5))
def test_box_matches_source_corners_for_any_pose(seed):
    rng = np.random.default_rng(seed)
    for _ in range(20):
        size = rng.uniform(0.1, 2.0, 3)
        pos = rng.uniform(-5, 5, 3)
        rot = rng.normal(size=4)
        scale = rng.uniform(0.5, 1.5, 3) * rng.choice([-1.0, 1.0], 3)  # mirrors included
        box = future_box(size, pos, rot, scale)
        assert is_rotation(box.rotation)
        assert corner_distance(box.corners(), _source_corners(size, pos, rot, scale)) < 1e-9


# -- floor outlines ------------------------------------------------------------------
def _quad(x0, y0, x1, y1, flip=False):
    """Two triangles (2, 3, 2) covering an axis-aligned rectangle."""
    a, b, c, d = (x0, y0), (x1, y0), (x1, y1), (x0, y1)
    tris = [[a, b, c], [a, c, d]]
    return np.array([t[::-1] for t in tris] if flip else tris, dtype=float)


def test_outline_of_l_shape_with_t_junction():
    # The upper arm's bottom edge meets the lower block's top edge in a T-junction at (2, 2).
    tris = np.concatenate([_quad(0, 0, 4, 2), _quad(0, 2, 2, 4, flip=True)])
    poly = floor_outline(tris)
    expected = [[0, 0], [4, 0], [4, 2], [2, 2], [2, 4], [0, 4]]
    np.testing.assert_allclose(poly, expected)
    assert polygon_area(poly) == pytest.approx(12.0)


def test_outline_keeps_outer_loop_and_merges_near_vertices():
    ring = [_quad(0, 0, 5, 1), _quad(0, 4, 5, 5), _quad(0, 1, 1, 4), _quad(4, 1, 5, 4)]
    tris = np.concatenate(ring) + np.random.default_rng(1).uniform(-1e-4, 1e-4, (8, 3, 2))
    poly = floor_outline(tris)
    assert len(poly) == 4  # the hole's loop loses, collinear vertices go
    assert polygon_area(poly) == pytest.approx(25.0, abs=1e-2)


def test_outline_of_nothing_is_none():
    assert floor_outline(np.zeros((0, 3, 2))) is None
    assert floor_outline(np.array([[[0, 0], [1, 1], [2, 2]]], dtype=float)) is None


def test_rect_polygon_distance():
    square = np.array([[0, 0], [4, 0], [4, 4], [0, 4]], dtype=float)
    assert rect_polygon_distance(np.array([3.9, 1]), np.array([4.1, 2]), square) == 0
    assert rect_polygon_distance(np.array([4.2, 1]), np.array([4.3, 2]), square) == (
        pytest.approx(0.2)
    )
    assert rect_polygon_distance(np.array([-1, -1]), np.array([5, 5]), square) == 0


# -- the fixture ---------------------------------------------------------------------
def test_fixture_rooms_objects_categories(corpus, scenes):
    assert corpus.source == "3dfront"
    assert sorted(scenes) == [
        "fx-house-a/LivingDiningRoom-205",
        "fx-house-a/MasterBedroom-101",
        "fx-house-b/Library-7",
        "fx-house-b/StorageRoom-9",
    ]
    assert {s.id: s.room.type for s in corpus.scenes} == {
        "fx-house-a/MasterBedroom-101": "bedroom",
        "fx-house-a/LivingDiningRoom-205": "apartment",
        "fx-house-b/Library-7": "office",
        "fx-house-b/StorageRoom-9": "other",
    }
    assert sum(len(s.objects) for s in corpus.scenes) == 22
    cats = Counter(o.category for s in corpus.scenes for o in s.objects)
    assert cats == Counter(
        {"chair": 6, "side_table": 2, UNKNOWN: 2, "bed": 1, "wardrobe": 1, "ceiling_lamp": 1,
         "sofa": 1, "coffee_table": 1, "tv_stand": 1, "dining_table": 1, "desk": 1,
         "shelving_unit": 1, "floor_lamp": 1, "cabinet": 1, "armchair": 1}
    )  # fmt: skip
    for s in corpus.scenes:
        assert s.source == "3dfront"
        assert len({o.id for o in s.objects}) == len(s.objects)
        for o in s.objects:
            # no support annotation in 3D-FRONT: floor by height, else unknown
            assert o.source_support is None
            assert o.support == ("floor" if o.box.bottom < 0.05 else None)
            assert o.asset.source == "3dfuture" and o.asset.id.startswith("fx-")
            assert is_rotation(o.box.rotation)
    living = scenes["fx-house-a/LivingDiningRoom-205"]
    assert [o.id for o in living.objects if o.category == "chair"] == [
        "chair_0", "chair_1", "chair_2", "chair_3"
    ]  # fmt: skip


def test_fixture_boxes(scenes):
    bedroom = scenes["fx-house-a/MasterBedroom-101"].by_id()
    bed = bedroom["bed_0"].box
    assert bed.bottom == pytest.approx(0.0)
    np.testing.assert_allclose(bed.center, [1.0, 1.1, 0.55], atol=1e-9)
    np.testing.assert_allclose(bed.size, [2.0, 2.2, 1.1], atol=1e-9)
    np.testing.assert_allclose(bed.rotation[:, 1], [0, 1, 0], atol=1e-9)  # foot end to +Y
    wardrobe = bedroom["wardrobe_0"].box  # against the x = 0 wall, opening to +X
    np.testing.assert_allclose(wardrobe.rotation[:, 1], [1, 0, 0], atol=1e-6)
    np.testing.assert_allclose(wardrobe.aabb()[0], [0.0, 2.2, 0.0], atol=1e-6)
    scaled = bedroom["side_table_1"].box
    np.testing.assert_allclose(scaled.size, [0.6, 0.54, 0.66], atol=1e-9)
    lamp = bedroom["ceiling_lamp_0"].box  # hangs: bottom at 2.5, top at the 2.9 m ceiling
    assert (lamp.bottom, lamp.top) == (pytest.approx(2.5), pytest.approx(2.9))
    sofa = scenes["fx-house-a/LivingDiningRoom-205"].by_id()["sofa_0"].box
    np.testing.assert_allclose(sofa.rotation[:, 1], [0, -1, 0], atol=1e-9)  # faces the TV


def test_fixture_floor_height_and_openings(scenes):
    bedroom = scenes["fx-house-a/MasterBedroom-101"].room
    np.testing.assert_allclose(
        bedroom.floor_polygon, [[0, 0], [4, 0], [4, 2], [2, 2], [2, 4], [0, 4]], atol=1e-9
    )
    assert bedroom.area == pytest.approx(12.0)
    assert bedroom.height == pytest.approx(2.9)
    (door,) = bedroom.doors
    assert (door.id, door.p0, door.p1) == ("ma-door-1", (4.0, 0.8), (4.0, 1.7))
    assert (door.z_min, door.z_max) == (pytest.approx(0.0), pytest.approx(2.1))
    # ma-window-2 is referenced by the bedroom too but lies on the living room's far wall.
    assert [w.id for w in bedroom.windows] == ["ma-window-1"]
    assert bedroom.windows[0].width == pytest.approx(1.3)

    living = scenes["fx-house-a/LivingDiningRoom-205"].room
    assert living.height == pytest.approx(front3d.DEFAULT_ROOM_HEIGHT)  # no WallInner mesh
    assert [d.id for d in living.doors] == ["ma-door-1"]
    assert [w.id for w in living.windows] == ["ma-window-2"]

    storage = scenes["fx-house-b/StorageRoom-9"].room
    assert storage.height == pytest.approx(2.6)
    assert [d.id for d in storage.doors] == ["mb-door-1"]  # referenced by no room

    library = scenes["fx-house-b/Library-7"].room  # no floor mesh: furniture bounds + 0.5 m
    np.testing.assert_allclose(
        library.floor_polygon, [[-0.5, -0.5], [3.8, -0.5], [3.8, 2.5], [-0.5, 2.5]], atol=1e-9
    )


def test_unknown_and_missing_labels_are_counted_not_dropped(corpus, scenes):
    bedroom = scenes["fx-house-a/MasterBedroom-101"].by_id()
    assert bedroom["unknown_0"].source_label == "Decorative Ladder"
    assert bedroom["unknown_1"].source_label is None  # no label anywhere
    assert bedroom["unknown_1"].asset.id == "fx-9999"
    assert corpus.report.unknown_labels == Counter({"Decorative Ladder": 1, "<missing>": 1})
    assert corpus.report.mapped_labels["dining chair"] == 4
    assert sum(corpus.report.mapped_labels.values()) == 20
    # Fallbacks: the furniture's own category, its title, model_info's super-category.
    library = scenes["fx-house-b/Library-7"].by_id()
    assert library["floor_lamp_0"].source_label == "Floor Lamp"
    storage = scenes["fx-house-b/StorageRoom-9"].by_id()
    assert storage["armchair_0"].source_label == "Armchair"
    assert storage["cabinet_0"].source_label == "Cabinet/Shelf/Desk"


def test_warnings(corpus):
    assert corpus.report.warnings == Counter(
        {
            front3d.W_MISSING_INFO: 3,  # fx-9999, fx-0023, fx-0025
            front3d.W_NO_SIZE: 1,
            front3d.W_NO_FURNITURE: 1,  # the hallway
            front3d.W_NO_FLOOR: 1,  # the library
            front3d.W_UNKNOWN_REF: 1,
            "no support annotation: on the floor by height": 21,
            "unmapped room type: StorageRoom": 1,
        }
    )
    bedroom = next(s for s in corpus.scenes if s.id.endswith("MasterBedroom-101"))
    assert bedroom.stats["objects_skipped"] == 1


def test_mirrored_object_warns_and_keeps_a_proper_box(tmp_path):
    house = json.loads((FIXTURE / "fx-house-b.json").read_text())
    house["scene"]["room"][0]["children"][0]["scale"] = [-1, 1, 1]
    (tmp_path / "house.json").write_text(json.dumps(house))
    shutil.copy(FIXTURE / "model_info.json", tmp_path)
    corpus = load_front3d(tmp_path / "house.json")
    assert corpus.report.warnings[front3d.W_MIRRORED] == 1
    desk = corpus.scenes[0].by_id()["desk_0"].box
    assert is_rotation(desk.rotation)
    np.testing.assert_allclose(desk.rotation[:, 1], [0, 1, 0], atol=1e-9)


# -- locating model_info.json ----------------------------------------------------------
def test_missing_model_info_keeps_every_object(tmp_path):
    for name in HOUSE_FILES:
        shutil.copy(FIXTURE / name, tmp_path)
    corpus = load_front3d(tmp_path)
    assert corpus.report.warnings[front3d.W_NO_MODEL_INFO] == 1
    assert front3d.W_MISSING_INFO not in corpus.report.warnings
    objects = [o for s in corpus.scenes for o in s.objects]
    assert len(objects) == 22
    # Only the house files' own labels are left: titles and one furniture category.
    cats = Counter(o.category for o in objects)
    assert cats == Counter(
        {UNKNOWN: 17, "side_table": 2, "wardrobe": 1, "floor_lamp": 1, "armchair": 1}
    )
    assert sum(corpus.report.unknown_labels.values()) == 17
    assert corpus.report.unknown_labels["table/desk"] == 1  # the title, kept as source label


def test_model_info_beside_in_3d_future_folder(tmp_path, corpus):
    front, future = tmp_path / "3D-FRONT", tmp_path / "3D-FUTURE-model"
    front.mkdir()
    future.mkdir()
    for name in HOUSE_FILES:
        shutil.copy(FIXTURE / name, front)
    shutil.copy(FIXTURE / "model_info.json", future)
    moved = load_front3d(front)
    assert [o.category for s in moved.scenes for o in s.objects] == [
        o.category for s in corpus.scenes for o in s.objects
    ]


def test_single_house_file(scenes):
    corpus = load_front3d(FIXTURE / "fx-house-b.json", progress=True)
    assert [s.id for s in corpus.scenes] == ["fx-house-b/Library-7", "fx-house-b/StorageRoom-9"]
    assert corpus.scenes[0].by_id()["desk_0"].category == "desk"


# -- splits, round trip, errors ------------------------------------------------------
def test_split_is_deterministic_and_partitions(corpus):
    for s in corpus.scenes:
        assert s.split == ("val" if stable_fraction(s.id) < 0.2 else "train")
    train = load_front3d(FIXTURE, split="train")
    val = load_front3d(FIXTURE, split="val")
    assert {s.split for s in train.scenes} <= {"train"}
    assert {s.split for s in val.scenes} <= {"val"}
    assert sorted(s.id for s in train.scenes + val.scenes) == sorted(s.id for s in corpus.scenes)
    again = load_front3d(FIXTURE)
    assert [(s.id, s.split) for s in again.scenes] == [(s.id, s.split) for s in corpus.scenes]


def test_scenes_round_trip_through_scene_json(corpus):
    for scene in corpus.scenes:
        back = scene_from_dict(json.loads(json.dumps(scene_to_dict(scene))))
        assert [o.id for o in back.objects] == [o.id for o in scene.objects]
        assert all(a.box.allclose(b.box) for a, b in zip(back.objects, scene.objects, strict=True))


@pytest.mark.parametrize(
    "text",
    ["{not json", "[1, 2, 3]", '{"uid": "x", "furniture": []}', '{"scene": {"room": {}}}'],
)
def test_malformed_file_is_a_one_line_user_error(tmp_path, text):
    bad = tmp_path / "bad.json"
    bad.write_text(text)
    with pytest.raises(UserError) as err:
        load_front3d(bad)
    message = str(err.value)
    assert message.startswith(f"{bad}: not valid 3D-FRONT JSON: ")
    assert "\n" not in message


def test_bad_paths_and_splits_are_user_errors(tmp_path):
    with pytest.raises(UserError, match="no such file"):
        load_front3d(tmp_path / "missing")
    with pytest.raises(UserError, match="no 3D-FRONT house JSON"):
        load_front3d(tmp_path)
    with pytest.raises(UserError, match="unknown split"):
        load_front3d(FIXTURE, split="test")
    (tmp_path / "model_info.json").write_text("{")
    shutil.copy(FIXTURE / "fx-house-a.json", tmp_path)
    with pytest.raises(UserError, match="model_info.json: not valid"):
        load_front3d(tmp_path)


def _mutations(node, path=()):
    """Every (path, container) leaf-or-branch position of a JSON tree."""
    if isinstance(node, dict):
        for k, v in node.items():
            yield (*path, k)
            yield from _mutations(v, (*path, k))
    elif isinstance(node, list):
        for i, v in enumerate(node):
            yield (*path, i)
            yield from _mutations(v, (*path, i))


@pytest.mark.parametrize("seed", range(3))
def test_corrupted_houses_load_or_raise_user_error(tmp_path, seed):
    """Wrong types or missing keys anywhere: a corpus or a UserError, never a traceback."""
    rng = np.random.default_rng(seed)
    shutil.copy(FIXTURE / "model_info.json", tmp_path)
    original = json.loads((FIXTURE / "fx-house-a.json").read_text())
    paths = list(_mutations(original))
    for trial in range(40):
        house = json.loads(json.dumps(original))
        for _ in range(3):
            *parent_path, key = paths[rng.integers(len(paths))]
            parent = house
            try:
                for k in parent_path:
                    parent = parent[k]
                junk = [None, "x", -1, 0, [], {}, [1, 2], {"a": 1}, 1e309][rng.integers(9)]
                if isinstance(parent, dict) and rng.random() < 0.3:
                    parent.pop(key, None)
                else:
                    parent[key] = junk
            except (KeyError, IndexError, TypeError):
                continue
        file = tmp_path / f"house-{trial}.json"
        file.write_text(json.dumps(house))
        try:
            corpus = load_front3d(file)
        except UserError as err:
            assert str(err).startswith(f"{file}: ") and "\n" not in str(err)
        else:
            for scene in corpus.scenes:
                assert all(is_rotation(o.box.rotation) for o in scene.objects)
                assert np.all(np.isfinite(scene.room.floor_polygon))


def test_the_toolbox_model_info_mapping_reads_as_3d_futures_list(tmp_path, corpus):
    """The 3D-FRONT toolbox's model_info (model id -> category name) gives the same
    categories as 3D-FUTURE's list of entries; a mapping to anything else is one line."""
    entries = json.loads((FIXTURE / "model_info.json").read_text())
    mapping = {e["model_id"]: e["category"] for e in entries}
    for name in HOUSE_FILES:
        shutil.copy(FIXTURE / name, tmp_path)
    (tmp_path / "model_info.json").write_text(json.dumps(mapping))
    toolbox = load_front3d(tmp_path)
    assert front3d.W_NO_MODEL_INFO not in toolbox.report.warnings

    def categories(c):
        return [o.category for s in sorted(c.scenes, key=lambda s: s.id) for o in s.objects]

    # the same objects, named alike where the mapping names their model (a null category
    # falls back to 3D-FUTURE's super-category, which the mapping does not carry)
    pairs = list(zip(categories(toolbox), categories(corpus), strict=True))
    differ = [(a, b) for a, b in pairs if a != b]
    nulls = sum(e["category"] is None for e in entries)
    assert len(differ) <= nulls and all(a == "unknown" for a, _ in differ)
    assert len(pairs) - len(differ) > 20
    (tmp_path / "model_info.json").write_text(json.dumps({"fx-0001": 3}))
    with pytest.raises(UserError, match="'fx-0001' maps to int"):
        load_front3d(tmp_path)


@pytest.mark.parametrize("which", ["floor", "pendant"])
def test_a_lamp_known_only_as_lighting_is_named_by_where_it_is(tmp_path, which):
    """3D-FUTURE's super-category "Lighting" says only "a lamp": on the floor it is a floor
    lamp, hanging a ceiling lamp (it had been a ceiling lamp wherever it stood)."""
    house = json.loads((FIXTURE / "fx-house-b.json").read_text())
    info = json.loads((FIXTURE / "model_info.json").read_text())
    if which == "floor":  # the library's floor lamp, its own label gone
        entry = next(f for f in house["furniture"] if f.get("category") == "Floor Lamp")
        entry["category"] = "Lighting"
    (tmp_path / "fx-house-b.json").write_text(json.dumps(house))
    shutil.copy(FIXTURE / "fx-house-a.json", tmp_path)
    for e in info:
        if e["category"] == "Pendant Lamp":
            e["category"] = None  # the bedroom's pendant: only its super-category left
    (tmp_path / "model_info.json").write_text(json.dumps(info))
    scenes = {s.id: s.by_id() for s in load_front3d(tmp_path).scenes}
    assert scenes["fx-house-a/MasterBedroom-101"]["ceiling_lamp_0"].source_label == "Lighting"
    library = scenes["fx-house-b/Library-7"] if which == "floor" else None
    if library is not None:
        assert library["floor_lamp_0"].source_label == "Lighting"
        assert "ceiling_lamp_0" not in library
    assert front3d.lamp_by_height(0.0) == "floor_lamp"
    assert front3d.lamp_by_height(0.8) == "table_lamp"
    assert front3d.lamp_by_height(2.2) == "ceiling_lamp"


def test_a_room_whose_objects_stand_outside_its_floor_is_warned_of(tmp_path, corpus):
    assert front3d.W_OUTSIDE_FLOOR not in corpus.report.warnings
    house = json.loads((FIXTURE / "fx-house-a.json").read_text())
    room = house["scene"]["room"][0]
    for child in room["children"]:  # 40 m east of the room, floor left where it was
        if isinstance(child.get("pos"), list):
            child["pos"][0] += 40.0
    (tmp_path / "fx-house-a.json").write_text(json.dumps(house))
    shutil.copy(FIXTURE / "model_info.json", tmp_path)
    moved = load_front3d(tmp_path)
    assert moved.report.warnings[front3d.W_OUTSIDE_FLOOR] == 1
    assert len(moved.scenes) == len([s for s in corpus.scenes if s.id.startswith("fx-house-a")])

"""AI2-THOR adapter: the fixture rooms, and the full corpus fetched from PyPI."""

import json
from collections import Counter

import numpy as np
import pytest

from pair2scene.categories import BY_NAME
from pair2scene.data.ai2thor import GROUPS, OBB_AGREEMENT_M, convert_box, load_ai2thor
from pair2scene.data.unity import AssetDatabase
from pair2scene.scene.geometry import corner_distance, is_rotation
from pair2scene.scene.model import FLOOR


@pytest.fixture(scope="module")
def small(fixtures):
    return load_ai2thor(fixtures / "ai2thor")


def test_fixture_rooms_are_named_and_typed(small):
    assert [s.id for s in small.scenes] == [
        "ai2thor/FloorPlan1",
        "ai2thor/FloorPlan301",
        "ai2thor/FloorPlan_Train1_1",
    ]
    assert [s.room.type for s in small.scenes] == ["kitchen", "bedroom", "apartment"]
    assert all(s.split == "train" for s in small.scenes)


def test_floor_is_at_zero_and_objects_stand_on_it(small):
    for scene in small.scenes:
        on_floor = [o for o in scene.objects if o.support == FLOOR]
        assert on_floor, scene.id
        bottoms = np.array([o.box.bottom for o in on_floor])
        assert np.median(np.abs(bottoms)) < 0.01, scene.id


def test_structure_becomes_room_features(small):
    cats = {o.category for s in small.scenes for o in s.objects}
    assert not cats & {"floor", "window", "light_switch", "wall"}
    bedroom = small.scenes[1]
    assert len(bedroom.room.windows) == 1
    w = bedroom.room.windows[0]
    assert w.width > 0.5 and 0 < w.z_min < w.z_max <= bedroom.room.height
    assert small.report.room_features["LightSwitch"] == 2  # RoboTHOR lists none


def test_source_support_picks_the_nearest_receptacle_below(small):
    bedroom = small.scenes[1]
    objs = bedroom.by_id()
    # FloorPlan301: the book and the laptop lie on the bed, the lamp on the dresser.
    assert objs["book_0"].source_support == "bed_0"
    assert objs["laptop_0"].source_support == "bed_0"
    assert objs["table_lamp_0"].source_support == "dresser_0"
    for o in bedroom.objects:
        if o.source_support not in (None, FLOOR):
            sup = objs[o.source_support]
            assert sup.box.top - 0.05 <= o.box.bottom + 1e-9 or sup.box.contains(o.box.center)[0]


def test_parts_belong_to_their_furniture(small):
    bedroom = small.scenes[1]
    drawers = [o for o in bedroom.objects if o.category == "drawer"]
    assert drawers and all(d.part_of in ("dresser_0", "desk_0") for d in drawers)
    # a tissue box on a shelf of the desk's hutch rests, for us, on the desk
    tissue = bedroom.get("tissue_box_0")
    assert tissue.source_support.startswith("shelf_") and tissue.support == "desk_0"


def test_bed_box_matches_the_source(small):
    bed = small.scenes[1].get("bed_0")
    assert np.allclose(bed.box.size, [1.467, 2.075, 0.910], atol=2e-3)
    assert bed.box.bottom == pytest.approx(0.0, abs=0.01)
    assert is_rotation(bed.box.rotation)


# -- the full corpus (downloaded once from PyPI into the cache) ---------------------------
def test_full_corpus_counts(ai2thor_corpus):
    c = ai2thor_corpus
    assert len(c.scenes) == 195
    assert Counter(s.split for s in c.scenes) == {"train": 160, "val": 35}
    assert Counter(s.room.type for s in c.scenes) == {
        "kitchen": 30,
        "living_room": 30,
        "bedroom": 30,
        "bathroom": 30,
        "apartment": 75,
    }
    assert not c.report.unknown_labels
    assert len(c.report.mapped_labels) == 118
    assert all(o.category in BY_NAME for s in c.scenes for o in s.objects)


def test_val_split_holds_out_part_of_every_group(ai2thor_corpus):
    val = Counter(s.room.type for s in ai2thor_corpus.scenes if s.split == "val")
    assert val == {"kitchen": 5, "living_room": 5, "bedroom": 5, "bathroom": 5, "apartment": 15}
    again = load_ai2thor(split="val")
    assert [s.id for s in again.scenes] == [s.id for s in ai2thor_corpus.scenes if s.split == "val"]


def test_room_names_match_the_asset_database(ai2thor_databases):
    """Rooms are named by their position in the file; every named room must use
    only assets the asset database lists for that scene name."""
    meta = json.loads((ai2thor_databases / "ai2thor-object-metadata.json").read_text())
    raw = json.loads((ai2thor_databases / "asset-database.json").read_text())
    scenes_of = {a["assetId"]: set(a.get("scenes") or ()) for group in raw.values() for a in group}
    checked = 0
    for group in GROUPS:
        for name, records in zip(group.names, meta[group.key]):
            used = [scenes_of[r["assetId"]] for r in records if scenes_of.get(r.get("assetId"))]
            assert used, name
            votes = Counter(s for sc in used for s in sc)
            assert votes.most_common(1)[0][0] == name
            checked += 1
    assert checked == 195


def test_converted_boxes_reproduce_the_source_obb(ai2thor_databases):
    """Euler angles (Unity, zxy), AABB centre and asset size alone, before any
    refit, must reproduce AI2-THOR's own OBB corners within 2 cm for >= 95%."""
    meta = json.loads((ai2thor_databases / "ai2thor-object-metadata.json").read_text())
    assets = AssetDatabase.load(ai2thor_databases / "asset-database.json")
    errors = []
    for rooms in meta.values():
        for records in rooms:
            for rec in records:
                if rec.get("objectOrientedBoundingBox"):
                    cb = convert_box(rec, assets)
                    errors.append(corner_distance(cb.converted.corners(), cb.obb))
    errors = np.array(errors)
    assert len(errors) == 4717
    agreement = float(np.mean(errors <= OBB_AGREEMENT_M))
    print(f"OBB agreement within 2 cm: {agreement:.4f} of {len(errors)}")
    assert agreement >= 0.95

"""The front survey (tools/front_survey.py): cue functions on hand-made scenes, the
fitting rules, and every checkable (source, category, cue) of both corpora."""

import sys
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest

from pair2scene.data.ai2thor import load_ai2thor
from pair2scene.data.procthor import load_procthor
from pair2scene.scene.geometry import OrientedBox, yaw_to_matrix
from pair2scene.scene.model import FLOOR, AssetRef, Opening, Room, Scene, SceneObject

# the survey is an offline tool, not part of the package: import it from tools/
sys.path.insert(0, str(Path(__file__).resolve().parents[2] / "tools"))
from front_survey import (  # noqa: E402
    AGREEMENT_BAR,
    BELOW_BAR,
    MIN_SAMPLES,
    Cue,
    Observation,
    _Evidence,
    asset_offset_index,
    build_report,
    category_offset_index,
    front_quadrant,
    held_out_agreement,
    observe,
    room_walls,
    suggest_offsets,
    tables_match,
    write_doc,
)

ROOM = np.array([[0.0, 0.0], [4.0, 0.0], [4.0, 4.0], [0.0, 4.0]])


def thing(oid, category, center, size, yaw_deg=0.0, support=FLOOR, asset=None):
    box = OrientedBox.from_yaw(center, size, np.radians(yaw_deg))
    ref = AssetRef("ai2thor", asset or f"{category}_asset")
    return SceneObject(oid, category, box, ref, support=support)


def room(objects, source="procthor", scene_id="procthor/test/0/room|1", polygon=ROOM, **kw):
    return Scene(scene_id, Room("bedroom", polygon, **kw), list(objects), source=source)


def cues_of(scene, object_id):
    """{cue: offset in degrees} of one object's observations."""
    return {ob.cue: 90 * ob.quadrant for ob in observe(scene) if ob.object_id == object_id}


# -- the correction itself --------------------------------------------------------------------
@pytest.mark.parametrize(
    "yaw, direction, offset",
    [
        (0, [0, 1], 0),
        (0, [-1, 0], 90),
        (0, [0, -1], 180),
        (0, [1, 0], 270),
        (90, [0, 1], 270),  # +y points to world -x; world +y is the old +x
        (0, [0.6, 0.8], 0),  # within 45 degrees
    ],
)
def test_front_quadrant(yaw, direction, offset):
    direction = np.array(direction, float) / np.linalg.norm(direction)
    assert 90 * front_quadrant(yaw_to_matrix(np.radians(yaw)), direction) == offset


# -- cues on tiny hand-made scenes --------------------------------------------------------------
def test_a_chair_facing_its_table():
    table = thing("table", "dining_table", [2, 2, 0.4], [1.2, 0.8, 0.8])
    facing = thing("chair_a", "chair", [2, 1.2, 0.45], [0.45, 0.5, 0.9])  # south, +y north
    away = thing("chair_b", "chair", [2, 2.8, 0.45], [0.45, 0.5, 0.9])  # north, +y north
    side = thing("chair_c", "chair", [3.0, 2.0, 0.45], [0.45, 0.5, 0.9], yaw_deg=90)
    s = room([table, facing, away, side])
    assert cues_of(s, "chair_a")[Cue.PARTNER] == 0
    assert cues_of(s, "chair_b")[Cue.PARTNER] == 180
    # east of the table, +y turned to world -x: facing it
    assert cues_of(s, "chair_c")[Cue.PARTNER] == 0


def test_a_chair_tucked_under_its_table_still_faces_it():
    table = thing("table", "dining_table", [2, 2, 0.4], [1.2, 0.8, 0.8])
    chair = thing("chair", "chair", [2, 1.7, 0.45], [0.45, 0.5, 0.9])  # centre under the table
    assert cues_of(room([table, chair]), "chair")[Cue.PARTNER] == 0


def test_a_chair_far_from_any_table_has_no_partner():
    table = thing("table", "dining_table", [1, 1, 0.4], [1.2, 0.8, 0.8])
    chair = thing("chair", "chair", [3, 3.5, 0.45], [0.45, 0.5, 0.9])
    assert Cue.PARTNER not in cues_of(room([table, chair]), "chair")


def test_a_desk_faces_its_chair_even_off_centre():
    desk = thing("desk", "desk", [2, 0.4, 0.38], [1.6, 0.7, 0.75])
    chair = thing("chair", "chair", [2.55, 1.05, 0.45], [0.5, 0.5, 0.9], yaw_deg=180)
    s = room([desk, chair])
    assert cues_of(s, "desk")[Cue.PARTNER] == 0
    assert cues_of(s, "chair")[Cue.PARTNER] == 0


def test_a_bed_against_a_wall():
    # headboard (-y) 2 cm from the wall y = 0: the front is +y
    bed = thing("bed", "bed", [2, 1.02, 0.3], [1.6, 2.0, 0.6])
    assert cues_of(room([bed]), "bed")[Cue.WALL] == 0
    reversed_bed = thing("bed", "bed", [2, 1.02, 0.3], [1.6, 2.0, 0.6], yaw_deg=180)
    assert cues_of(room([reversed_bed]), "bed")[Cue.WALL] == 180
    # along the wall x = 4, front to world -x
    side = thing("bed", "bed", [2.98, 2, 0.3], [1.6, 2.0, 0.6], yaw_deg=90)
    assert cues_of(room([side]), "bed")[Cue.WALL] == 0


def test_no_wall_cue_in_a_corner_at_an_angle_or_away_from_walls():
    corner = thing("bed", "bed", [0.82, 1.02, 0.3], [1.6, 2.0, 0.6])
    angled = thing("bed", "bed", [2, 1.4, 0.3], [1.6, 2.0, 0.6], yaw_deg=30)
    middle = thing("bed", "bed", [2, 2, 0.3], [1.6, 2.0, 0.6])
    for bed in (corner, angled, middle):
        assert Cue.WALL not in cues_of(room([bed]), "bed")


def test_the_wall_cue_follows_an_l_shaped_room():
    ell = np.array([[0, 0], [4, 0], [4, 2], [2, 2], [2, 4], [0, 4]], float)
    # against the inner wall y = 2 that only runs from x = 2 to 4
    dresser = thing("dresser", "dresser", [3, 1.72, 0.4], [0.6, 0.5, 0.8], yaw_deg=180)
    assert cues_of(room([dresser], polygon=ell), "dresser")[Cue.WALL] == 0


def test_pillows_mark_the_head_of_a_bed():
    bed = thing("bed", "bed", [2, 2, 0.3], [1.6, 2.0, 0.6])
    pillow = thing("pillow", "pillow", [2, 1.2, 0.7], [0.5, 0.3, 0.15], support="bed")
    assert cues_of(room([bed, pillow]), "bed")[Cue.PILLOWS] == 0
    flipped = thing("pillow", "pillow", [2, 2.8, 0.7], [0.5, 0.3, 0.15], support="bed")
    assert cues_of(room([bed, flipped]), "bed")[Cue.PILLOWS] == 180


def test_a_tv_and_its_stand_face_the_same_way():
    stand = thing("stand", "tv_stand", [2, 2, 0.25], [1.4, 0.45, 0.5])
    tv = thing("tv", "television", [2, 2, 0.8], [1.2, 0.1, 0.6], yaw_deg=180, support="stand")
    s = room([stand, tv])
    assert cues_of(s, "tv")[Cue.SUPPORT] == 180
    assert cues_of(s, "stand")[Cue.CARRIES] == 180


def test_the_support_cue_reads_a_raw_support_through_the_tables():
    # iTHOR's TV_Stand_201_1 faces Unity -z: a TV facing +y on it faces its true front
    stand = thing("stand", "tv_stand", [2, 2, 0.25], [1.4, 0.45, 0.5], asset="TV_Stand_201_1")
    tv = thing("tv", "television", [2, 2, 0.8], [1.2, 0.1, 0.6], support="stand")
    s = room([stand, tv], source="ai2thor", scene_id="ai2thor/FloorPlan_Train1_1")
    raw = {ob.cue: ob.quadrant for ob in observe(s, raw=True) if ob.object_id == "tv"}
    assert 90 * raw[Cue.SUPPORT] == 180
    assert cues_of(s, "tv")[Cue.SUPPORT] == 0


def test_drawers_sit_at_the_front():
    dresser = thing("dresser", "dresser", [2, 2, 0.4], [1.2, 0.5, 0.8], yaw_deg=90)
    # +y of the dresser points to world -x: its drawers sit on that side
    drawers = [
        thing(f"drawer_{i}", "drawer", [1.9, 1.7 + 0.3 * i, 0.4], [0.28, 0.4, 0.2], 90, "dresser")
        for i in range(3)
    ]
    drawers = [replace(d, part_of="dresser") for d in drawers]
    assert cues_of(room([dresser, *drawers]), "dresser")[Cue.DRAWERS] == 0


def test_ithor_walls_are_pulled_in_to_the_objects():
    floor = np.array([[-0.3, -0.3], [4.3, -0.3], [4.3, 5.5], [-0.3, 5.5]])
    dresser = thing("dresser", "dresser", [2, 0.25, 0.4], [1.2, 0.5, 0.8])
    bed = thing("bed", "bed", [3.2, 3.0, 0.3], [1.6, 2.0, 0.6])
    lamp = thing("lamp", "floor_lamp", [0.1, 4.0, 0.8], [0.2, 0.2, 1.6])
    window = Opening("window", (4.0, 1.0), (4.0, 2.0), 1.0, 2.0)
    s = room([dresser, bed, lamp], "ai2thor", "ai2thor/FloorPlan301", floor, windows=(window,))
    walls = room_walls(s)
    normals = sorted(tuple(np.round(w.normal, 6)) for w in walls)
    # the top side (extent y = 4.0, floor y = 5.5) lies 1.5 m in: no wall there
    assert normals == sorted([(0.0, 1.0), (-1.0, 0.0), (1.0, 0.0)])
    assert cues_of(s, "dresser")[Cue.WALL] == 0
    robothor = room([dresser, bed], "ai2thor", "ai2thor/FloorPlan_Train1_1", floor)
    assert room_walls(robothor) == []


# -- fitting the tables -----------------------------------------------------------------------
def _ob(asset, quadrant, category="bed", cue=Cue.WALL, source="test"):
    d = np.array([0.0, 1.0])
    return Observation(source, "s", asset, category, asset, cue, d, quadrant)


def test_an_asset_needs_two_readings_to_leave_a_split_category():
    counts = np.array([9, 0, 11, 0])
    assert asset_offset_index(counts, [(0, 0.95)], k_cat=2) == 2
    assert asset_offset_index(counts, [(0, 0.95), (0, 0.95)], k_cat=2) == 0
    # a category 98% at 0 outweighs two readings of a cue that errs often
    assert asset_offset_index(np.array([196, 2, 0, 2]), [(1, 0.6), (1, 0.6)], k_cat=0) == 0


def test_the_category_follows_the_assets_too_rarely_seen_to_override():
    ev = _Evidence(np.array([3, 0, 10, 0]), {f"a{i}": [(2, 0.9), (2, 0.9)] for i in range(5)})
    ev.assets.update({"b0": [(0, 0.9)], "b1": [(0, 0.9)], "b2": [(0, 0.9)]})
    assert category_offset_index(ev) == 0  # the five two-reading assets override anyway
    assert category_offset_index(_Evidence(np.array([3, 0, 5, 0]), {})) == 0  # too few


def test_suggest_offsets_and_held_out():
    obs = [_ob(f"bed_{i}", 2) for i in range(12)]  # twelve assets, one reading each, at 180
    obs += [_ob("odd", 0), _ob("odd", 0), _ob("odd", 0)]  # one asset modelled the Unity way
    obs += [_ob("lonely", 0)]  # one reading against the category: not enough
    cat, asset = suggest_offsets(obs)
    assert cat == {"test": {"bed": 180}}
    assert asset == {"test": {"odd": 0}}
    held = held_out_agreement(obs)[("test", "bed", Cue.WALL)]
    assert held == pytest.approx(15 / 16)  # only the lonely reading misses
    # a cue that does not speak for the category does not vote
    assert suggest_offsets([_ob(f"x{i}", 2, category="bowl") for i in range(20)]) == ({}, {})


# -- the corpora ------------------------------------------------------------------------------
@pytest.fixture(scope="module")
def ai2thor_raw(ai2thor_databases):
    return load_ai2thor(ai2thor_databases, correct_front=False)


@pytest.fixture(scope="module")
def report(ai2thor_raw, ai2thor_corpus, procthor_1k):
    raw = ai2thor_raw.scenes + load_procthor(procthor_1k, correct_front=False).scenes
    fixed = ai2thor_corpus.scenes + load_procthor(procthor_1k).scenes
    return build_report(raw, fixed)


# Every (source, category, cue) the data can check: a declared cue, at least
# MIN_SAMPLES readings on objects with an asset id, not unreliable. Listed here
# so that a row that stops being checkable shows up (test below).
CHECKED = [
    ("ai2thor", "armchair", Cue.WALL),
    ("ai2thor", "bed", Cue.WALL),
    ("ai2thor", "chair", Cue.PARTNER),
    ("ai2thor", "coffee_machine", Cue.WALL),
    ("ai2thor", "desk", Cue.PARTNER),
    ("ai2thor", "dresser", Cue.DRAWERS),
    ("ai2thor", "dresser", Cue.WALL),
    ("ai2thor", "fridge", Cue.WALL),
    ("ai2thor", "microwave", Cue.WALL),
    ("ai2thor", "side_table", Cue.DRAWERS),
    ("ai2thor", "sink", Cue.WALL),
    ("ai2thor", "sofa", Cue.WALL),
    ("ai2thor", "television", Cue.SUPPORT),
    ("ai2thor", "television", Cue.WALL),
    ("ai2thor", "toaster", Cue.WALL),
    ("ai2thor", "toilet", Cue.WALL),
    ("ai2thor", "tv_stand", Cue.CARRIES),
    ("ai2thor", "tv_stand", Cue.WALL),
    ("procthor", "armchair", Cue.WALL),
    ("procthor", "bed", Cue.WALL),
    ("procthor", "chair", Cue.PARTNER),
    ("procthor", "counter_top", Cue.WALL),
    ("procthor", "desk", Cue.WALL),
    ("procthor", "dresser", Cue.WALL),
    ("procthor", "fridge", Cue.WALL),
    ("procthor", "painting", Cue.WALL),
    ("procthor", "shelving_unit", Cue.WALL),
    ("procthor", "side_table", Cue.WALL),
    ("procthor", "television", Cue.SUPPORT),
    ("procthor", "television", Cue.WALL),
    ("procthor", "tv_stand", Cue.CARRIES),
    ("procthor", "tv_stand", Cue.WALL),
]
ROWS = [pytest.param(*key, id="-".join([key[0], key[1], key[2].value])) for key in CHECKED]
# Cues that speak for the category but stay under the bar: reported, each with
# its reason (front_survey.BELOW_BAR); strict, so a fix shows up.
ROWS += [
    pytest.param(*key, id="-".join([key[0], key[1], key[2].value]), marks=pytest.mark.xfail(
        reason=reason, strict=True
    ))
    for key, reason in BELOW_BAR.items()
]  # fmt: skip


@pytest.mark.shared_data
@pytest.mark.parametrize("source, category, cue", ROWS)
def test_corrected_fronts_agree_with_the_cue(report, source, category, cue):
    row = report.row(source, category, cue)
    assert row is not None and row.before.n >= MIN_SAMPLES
    share = row.after.fraction(0)
    print(f"{source} {category} {cue.value}: n={row.before.n} before "
          f"{row.before.fraction(0):.0%} after {share:.0%}")  # fmt: skip
    assert share >= AGREEMENT_BAR


@pytest.mark.shared_data
def test_every_checkable_row_is_listed(report):
    checkable = {
        r.before.key for r in report.rows if r.before.keyed and r.status in ("checked", "FAILS")
    }
    assert checkable == set(CHECKED)
    below = {r.before.key for r in report.rows if r.before.keyed and r.status == "below bar"}
    assert below == set(BELOW_BAR)


@pytest.mark.shared_data
def test_tables_match_the_measurements(report):
    assert tables_match(report) == []


@pytest.mark.shared_data
def test_the_doc_is_written(report, tmp_path):
    text = write_doc(report, tmp_path / "front.md").read_text()
    assert "| ai2thor | category `bed` | 180 |" in text
    assert "| procthor | chair | partner | 767 |" in text
    assert "below bar" in text and "unreliable" in text


def test_the_survey_runs_on_the_fixtures(fixtures, tmp_path):
    # the whole survey on the committed rooms: too few readings to check any row,
    # but every stage (observe, fit, report, doc) runs on real houses anywhere
    dbs, houses = fixtures / "ai2thor", fixtures / "procthor"
    raw = load_ai2thor(dbs, correct_front=False).scenes
    raw += load_procthor(houses, databases=dbs, correct_front=False).scenes
    fixed = load_ai2thor(dbs).scenes + load_procthor(houses, databases=dbs).scenes
    report = build_report(raw, fixed)
    assert report.rows and all(r.before.n > 0 for r in report.rows)
    assert {r.before.source for r in report.rows} == {"ai2thor", "procthor"}
    text = write_doc(report, tmp_path / "front.md").read_text()
    for heading in ("## Method", "## The corrections", "## Categories with a front, per cue"):
        assert heading in text
    assert "| ai2thor | category `bed` | 180 |" in text  # the tables are documented

"""The 3D-FRONT adapter on the pitfalls of real house files, with answers known by
construction (tests/fixtures/3dfront-pitfalls/make.py writes the fixture):

- ``size`` is [width, depth, height] (z up) and a ``bbox`` beside it repeats it, but a
  ``bbox`` on its own is the model's y-up extent; a 3D-FUTURE mesh, when at hand, wins;
- floors of overlapping, repeated and tiled pieces with zero-area slivers;
- doors and windows of several meshes (frame, leaf, threshold, sill; a bay window of
  five), a door listed under one of its two rooms only, a lone flat sill;
- "Lighting" lamps on the floor and under the ceiling; a room whose furniture stands
  outside its floor; the toolbox's model_info shape (model id -> category).
"""

from __future__ import annotations

import importlib.util
import json
from pathlib import Path

import numpy as np
import pytest
from tests.clitools import run_cli

from pair2scene.data import front3d
from pair2scene.data.front3d import floor_outline, load_front3d
from pair2scene.io.scene_json import dumps_scene, scene_from_dict
from pair2scene.scene.geometry import polygon_area
from pair2scene.scene.walls import walls_of

ROOT = Path(__file__).resolve().parents[1] / "fixtures" / "3dfront-pitfalls"
HOUSES = ROOT / "3D-FRONT"


@pytest.fixture(scope="module")
def corpus():
    return load_front3d(HOUSES)


@pytest.fixture(scope="module")
def rooms(corpus):
    return {s.id.split("/")[1]: s for s in corpus.scenes}


def test_the_fixture_is_what_its_script_writes():
    spec = importlib.util.spec_from_file_location("make_pitfalls", ROOT / "make.py")
    make = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(make)
    assert (HOUSES / "pitfall-house.json").read_text() == json.dumps(make.house, indent=1) + "\n"
    info = json.loads((ROOT / "3D-FUTURE-model" / "model_info.json").read_text())
    assert info == make.model_info and isinstance(info, dict)  # the toolbox's shape


def test_sizes_read_in_the_right_axes(rooms):
    bedroom = rooms["MasterBedroom-1"].by_id()
    bed = bedroom["bed_0"].box.size  # size [1.95, 2.33, 1.21]: width, depth, height
    assert bed[2] < 1.4 and bed[1] > bed[0]
    np.testing.assert_allclose(bed, [1.95, 2.33, 1.21])
    np.testing.assert_allclose(bedroom["wardrobe_0"].box.size, [1.6, 0.62, 2.43])
    # size and bbox both [0.8, 0.35, 2.0]: z up, as the size says
    np.testing.assert_allclose(bedroom["shelving_unit_0"].box.size, [0.8, 0.35, 2.0])
    np.testing.assert_allclose(bedroom["desk_0"].box.size, [1.4, 0.7, 0.76])  # bbox: y-up
    for o in bedroom.values():  # every one stands on the floor or hangs under the ceiling
        assert o.box.bottom == pytest.approx(0.0) or o.category == "ceiling_lamp"
    living = rooms["LivingRoom-2"].by_id()
    # the sofa's size [2.1, 0.9, 2.5] is wrong; its raw_model.obj is 2.2 x 0.85 (up) x 0.95
    np.testing.assert_allclose(living["sofa_0"].box.size, [2.2, 0.95, 0.85], atol=1e-4)
    # the coffee table's model_info entry gives its bounding box: 110 x 55 x 42 cm
    np.testing.assert_allclose(living["coffee_table_0"].box.size, [1.1, 0.55, 0.42])


def test_lamps_by_where_they_are(rooms):
    bedroom = rooms["MasterBedroom-1"].by_id()
    assert bedroom["floor_lamp_0"].source_label == "Lighting"
    assert bedroom["floor_lamp_0"].box.bottom == pytest.approx(0.0)
    assert bedroom["ceiling_lamp_0"].box.top == pytest.approx(2.75)


def test_floor_outlines_of_tiled_and_sliver_floors(rooms):
    bedroom = rooms["MasterBedroom-1"].room
    expected = np.array([[0, 0], [5, 0], [5, 2.5], [3, 2.5], [3, 4], [0, 4]], float)
    np.testing.assert_allclose(bedroom.floor_polygon, expected, atol=1e-6)
    assert polygon_area(bedroom.floor_polygon) == pytest.approx(17.0)
    living = rooms["LivingRoom-2"].room
    assert polygon_area(living.floor_polygon) == pytest.approx(16.0)


def test_floor_outline_units():
    square = [[[0, 0], [2, 0], [2, 2]], [[0, 0], [2, 2], [0, 2]]]
    sliver = [[[0, 0.5], [0, 1.0], [0, 1.5]]]  # three points on the left edge
    tile = [[[1, 0], [2, 0], [2, 1]], [[1, 0], [2, 1], [1, 1]]]  # overlaps the square
    crack = [[[2.0005, 0], [3, 0], [3, 2]], [[2.0005, 0], [3, 2], [2.0005, 2]]]  # 0.5 mm gap
    tris = np.array(square * 4 + sliver + tile * 3 + crack, float)
    poly = floor_outline(tris)
    np.testing.assert_allclose(poly, [[0, 0], [3, 0], [3, 2], [0, 2]], atol=1e-6)
    apart = np.array(square + [[[5, 0], [5.5, 0], [5.5, 0.5]]], float)  # a detached scrap
    np.testing.assert_allclose(floor_outline(apart), [[0, 0], [2, 0], [2, 2], [0, 2]])
    assert floor_outline(np.array(sliver, float)) is None


def test_one_opening_per_door_and_window_with_its_height(rooms):
    bedroom, living = rooms["MasterBedroom-1"].room, rooms["LivingRoom-2"].room
    # the door is listed under the living room only: it opens into both
    (door,) = bedroom.doors
    (door2,) = living.doors
    assert door.id == door2.id == "door-frame"
    assert (door.z_min, door.z_max) == (pytest.approx(0.0), pytest.approx(2.1))
    assert door.width == pytest.approx(0.9)
    (window,) = bedroom.windows  # frame and sill; the lone sill is no window
    assert (window.z_min, window.z_max) == (pytest.approx(0.9), pytest.approx(2.3))
    (bay,) = living.windows  # five pieces
    assert bay.width == pytest.approx(2.6) and bay.z_max - bay.z_min == pytest.approx(1.8)
    for room in (bedroom, living):
        walls = walls_of(room.floor_polygon)
        for o in (*room.doors, *room.windows):
            assert o.z_max > o.z_min
            assert any(w.span(o.p0, o.p1, tol=1e-6) is not None for w in walls), o


def test_the_report_counts_each_pitfall(corpus):
    w = corpus.report.warnings
    assert w[front3d.W_SIZE_MESH] == 1  # the sofa
    assert w[front3d.W_FLAT_OPENING] == 1  # the lone sill
    assert w[front3d.W_OUTSIDE_FLOOR] == 1  # SecondBedroom-3
    assert w[front3d.W_BAD_FLOOR] == 0 and w[front3d.W_NO_FLOOR] == 0


def test_every_room_written_as_scene_json_passes_validate(corpus, tmp_path):
    files = []
    for scene in corpus.scenes:
        text = dumps_scene(scene)
        scene_from_dict(json.loads(text))
        files.append(tmp_path / f"{scene.id.replace('/', '_')}.json")
        files[-1].write_text(text)
    proc = run_cli("validate", *map(str, files))
    assert proc.returncode == 0, proc.stderr
    assert proc.stdout.count(": ok") == len(corpus.scenes) == 3

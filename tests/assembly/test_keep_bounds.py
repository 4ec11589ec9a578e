"""scene.json's physical limits (validate and --keep alike) and --keep's semantics: a
user's kept layout is theirs (overlaps, objects outside, floating or under the floor are
notes), an ``other`` room is filled by the closest trained type (issue 21)."""

from __future__ import annotations

import copy
import json
import math
import time
from pathlib import Path

import pytest

from clitools import run_cli
from pair2scene.assembly.collision import MeshWorld, Shape
from pair2scene.assembly.keep import MAX_KEPT_OBJECTS, keep_assets, load_keep, read_keep
from pair2scene.cli import main
from pair2scene.errors import SceneFileError, UserError
from pair2scene.hierarchy.synthesis import load_stats
from pair2scene.io.scene_json import (
    MAX_COORD_M,
    MAX_FLOOR_VERTICES,
    MAX_OBJECTS,
    MAX_TEXT,
    read_scene,
)

FIXTURE = Path(__file__).resolve().parents[1] / "fixtures" / "scenes" / "valid_bedroom.json"
BASE = json.loads(FIXTURE.read_text(encoding="utf-8"))
IDENTITY = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]]


def scene(**room) -> dict:
    d = copy.deepcopy(BASE)
    d["room"].update(room)
    return d


def box(oid: str, category: str, center, size, support="floor") -> dict:
    return {"id": oid, "category": category, "center": list(center), "size": list(size),
            "rotation": IDENTITY, "support": support}  # fmt: skip


def write(tmp_path: Path, doc: dict, name: str = "scene.json") -> Path:
    path = tmp_path / name
    path.write_text(json.dumps(doc), encoding="utf-8")
    return path


def one_line(err: str) -> str:
    lines = err.splitlines()
    assert len(lines) == 1 and lines[0].startswith("error: "), err
    assert "Traceback" not in err
    return lines[0].removeprefix("error: ")


# -- case 2: physical limits of scene.json ----------------------------------------------
def huge_size(d):
    d["objects"][0]["size"][0] = 1e308


def huge_center(d):
    d["objects"][0]["center"] = [1e308, 1.0, 0.375]


def far_polygon(d):
    d["room"]["floor_polygon"] = [[0, 0], [150, 0], [150, 3], [0, 3]]


def long_id(d):
    d["objects"][1]["id"] = "x" * (MAX_TEXT + 1)


def many_objects(d):
    d["objects"] = [d["objects"][0]] * (MAX_OBJECTS + 1)


def tall_room(d):
    d["room"]["height"] = 101


def far_door(d):
    d["room"]["doors"][0]["z_max"] = 1e300


LIMITS = [
    (huge_size, "objects[0].size[0]", "must be <= 100 m"),
    (huge_center, "objects[0].center[0]", "must be within +-100 m"),
    (far_polygon, "room.floor_polygon[1][0]", "must be within +-100 m"),
    (long_id, "objects[1].id", f"more than {MAX_TEXT}"),
    (many_objects, "objects", f"more than {MAX_OBJECTS:,}"),
    (tall_room, "room.height", "must be <= 100 m"),
    (far_door, "room.doors[0].z_max", "must be within +-100 m"),
]


@pytest.mark.parametrize("edit, field, problem", LIMITS, ids=[e.__name__ for e, *_ in LIMITS])
def test_values_beyond_the_limits_are_refused(tmp_path, capsys, edit, field, problem):
    d = scene()
    edit(d)
    path = write(tmp_path, d)
    with pytest.raises(SceneFileError) as e:
        read_scene(path)
    assert e.value.field == field and problem in e.value.problem, str(e.value)
    assert main(["validate", str(path)]) == 2
    assert one_line(capsys.readouterr().err).startswith(f"{path}: {field}: ")


def test_polygon_extent_is_limited(tmp_path):
    d = scene(floor_polygon=[[-60, 0], [60, 0], [60, 3], [-60, 3]])
    with pytest.raises(SceneFileError, match="spans 120 m along x, more than 100"):
        read_scene(write(tmp_path, d))
    d = scene(floor_polygon=[[-MAX_COORD_M / 2, 0], [MAX_COORD_M / 2, 0], [0, 3]])
    read_scene(write(tmp_path, d))  # 100 m is allowed


def test_a_100000_vertex_floor_is_refused_fast(tmp_path, capsys):
    n = 100_000
    poly = [[2 + 2 * math.cos(2 * math.pi * i / n), 2 + 2 * math.sin(2 * math.pi * i / n)]
            for i in range(n)]  # fmt: skip
    path = write(tmp_path, scene(floor_polygon=poly))
    start = time.perf_counter()
    with pytest.raises(SceneFileError, match=f"has {n} vertices, more than 1,000"):
        read_scene(path)
    assert time.perf_counter() - start < 10.0  # bounded work (seconds on a slow, busy CI)
    ok = scene(floor_polygon=poly[:: n // MAX_FLOOR_VERTICES][:MAX_FLOOR_VERTICES])
    assert len(read_scene(write(tmp_path, ok, "ok.json")).room.floor_polygon) == 1000


def test_keep_refuses_what_validate_refuses(tmp_path):
    d = scene()
    huge_size(d)
    path = write(tmp_path, d)
    start = time.perf_counter()
    proc = run_cli("generate", "--keep", str(path), "--out", str(tmp_path / "o"), "--num", "1",
                   "--model", "random", cwd=tmp_path, timeout=120)  # fmt: skip
    assert proc.returncode == 2, proc.stderr
    assert "objects[0].size[0]: must be <= 100 m" in one_line(proc.stderr)
    assert "RuntimeWarning" not in proc.stderr and time.perf_counter() - start < 60
    assert not (tmp_path / "o").exists() or not any((tmp_path / "o").iterdir())


def test_too_many_objects_to_keep(tmp_path):
    d = scene()
    d["objects"] = [box(f"chair_{i}", "chair", (1, 1, 0.45), (0.5, 0.5, 0.9))
                    for i in range(MAX_KEPT_OBJECTS + 1)]  # fmt: skip
    with pytest.raises(UserError, match=f"more than the {MAX_KEPT_OBJECTS}"):
        read_keep(write(tmp_path, d))


# -- case 3: --keep semantics ----------------------------------------------------------
def odd_layout() -> dict:
    """The fixture with a second desk 30 cm into the first, a bed floating 2 m up, a bed
    outside the room and a side table sunk 15 cm into the floor."""
    d = scene()
    d["objects"] += [
        box("desk_1", "desk", (1.3, 1.0, 0.375), (1.2, 0.6, 0.75)),
        box("bed_0", "bed", (2.8, 1.7, 2.2), (1.4, 1.6, 0.4), support=None),
        box("bed_1", "bed", (7.0, 1.5, 0.25), (1.6, 2.0, 0.5)),
        box("side_table_0", "side_table", (3.5, 0.4, 0.1), (0.5, 0.4, 0.5)),
    ]
    return d


def test_odd_kept_layouts_are_notes(tmp_path):
    kept = load_keep(write(tmp_path, odd_layout()))
    notes = "\n".join(kept.notes)
    assert len(kept.scene.objects) == 7  # everything kept, as given
    assert "kept objects desk_0 and desk_1 intersect (90.0 cm deep)" in notes
    assert "bed_0 (bed) floats 2.00 m above the floor with nothing under it" in notes
    assert "bed_1 (bed) stands outside the room (3.80 m beyond its floor)" in notes
    assert "side_table_0 (side_table) reaches 15 cm under the floor" in notes
    for oid in ("desk_0", "laptop_0", "chair_0"):  # the fixture's own objects are fine
        assert f" {oid} (" not in notes
    assert all(n.endswith("kept as given") for n in kept.notes)


def test_objects_on_others_inside_or_hung_do_not_float(tmp_path):
    d = scene()
    d["objects"] += [
        box("shelving_unit_0", "shelving_unit", (3.5, 2.5, 0.9), (0.8, 0.4, 1.8)),
        box("book_0", "book", (3.5, 2.5, 1.0), (0.2, 0.15, 0.03), support=None),
        box("painting_0", "painting", (2.0, 2.98, 1.6), (0.8, 0.04, 0.6), support="wall:2"),
        box("ceiling_lamp_0", "ceiling_lamp", (2.0, 1.5, 2.5), (0.4, 0.4, 0.4), support=None),
        box("cabinet_0", "cabinet", (0.2, 2.0, 1.8), (0.4, 0.8, 0.7), support=None),
    ]
    _, notes = read_keep(write(tmp_path, d))
    assert notes == []


def test_other_room_is_filled_by_the_closest_trained_type(tmp_path):
    d = scene(type="other")
    d["objects"] = [
        box("bed_0", "bed", (2, 1.5, 0.25), (1.6, 2.0, 0.5)),
        box("side_table_0", "side_table", (3.5, 0.4, 0.25), (0.5, 0.4, 0.5)),
    ]
    stats = load_stats()
    room_types = sorted(stats.room_types)
    kept = load_keep(write(tmp_path, d))
    assert kept.scene.room.type in room_types and kept.scene.room.type != "other"
    assert f"the room is filled as room type {kept.scene.room.type!r}" in kept.notes[0]
    assert ", ".join(room_types) in kept.notes[0]
    # statistics that have 'other' rooms fill it with them
    own = copy.copy(stats)
    own.room_types = {**stats.room_types, "other": stats.room_types["bedroom"]}
    scene_, notes = read_keep(write(tmp_path, d), own)
    assert scene_.room.type == "other" and notes == []


def test_generate_keeps_an_odd_other_room_with_notes(tmp_path):
    d = odd_layout()
    d["room"]["type"] = "other"
    path = write(tmp_path, d, "partial.json")
    out = tmp_path / "out"
    args = ["--num", "1", "--model", "random", "--max-objects", "6"]
    proc = run_cli("generate", "--keep", str(path), "--out", str(out), *args, cwd=tmp_path)
    assert proc.returncode == 0, proc.stderr
    summary = json.loads((out / "summary.json").read_text(encoding="utf-8"))
    (entry,) = summary["scenes"]
    notes = "\n".join(entry["hierarchy_notes"])
    for words in ("no 'other' rooms", "desk_0 and desk_1 intersect", "bed_0 (bed) floats",
                  "bed_1 (bed) stands outside", "side_table_0 (side_table) reaches"):  # fmt: skip
        assert words in notes, notes
    written = read_scene(out / entry["id"] / "scene.json")
    given = {o["id"]: o for o in d["objects"]}
    assert set(given) <= {o.id for o in written.objects}
    for o in written.objects:
        if o.id in given:  # kept exactly where they were
            assert o.box.center.tolist() == pytest.approx(given[o.id]["center"])
    added = [o for o in written.objects if o.id not in given]
    assert added and entry["objects_placed"] == len(added)
    # only what was added must be collision-free (the kept desks stay intersecting)
    assets = keep_assets(written)  # (the exact assets: added objects carry their seeds)
    world = MeshWorld()
    for o in written.objects:
        shape = Shape(assets[o.id])
        shape.set_pose(o.box.rotation, o.box.center)
        world.add(o.id, shape)
    for a in added:
        for b in written.objects:
            if b.id != a.id:
                depth = world.penetration(world.shapes[a.id], world.shapes[b.id])
                assert depth <= 0.01, (a.id, b.id, depth)

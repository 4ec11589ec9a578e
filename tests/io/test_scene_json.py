"""scene.json: round trip, deterministic output, atomic writes, and malformed files.

Every malformed file must end in one SceneFileError naming the file and the field,
and ``pair2scene validate`` must turn it into one ``error:`` line and exit code 2.
"""

from __future__ import annotations

import codecs
import copy
import json
import re
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import pytest

from clitools import run_cli
from pair2scene.cli import main
from pair2scene.errors import SceneFileError, UserError
from pair2scene.io import atomic, scene_json
from pair2scene.io.atomic import atomic_open, atomic_write_bytes
from pair2scene.io.scene_json import (
    dumps_scene,
    read_scene,
    scene_from_dict,
    scene_to_dict,
    write_scene,
)
from pair2scene.scene.geometry import OrientedBox, euler_to_matrix, yaw_to_matrix
from pair2scene.scene.model import FLOOR, AssetRef, Opening, Room, Scene, SceneObject

FIXTURES = Path(__file__).resolve().parents[1] / "fixtures" / "scenes"
EYE = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]]

BASE: dict = {
    "format": "pair2scene.scene",
    "version": 1,
    "id": "s0",
    "source": "generated",
    "split": None,
    "room": {
        "type": "bedroom",
        "floor_polygon": [[0.0, 0.0], [4.0, 0.0], [4.0, 3.0], [0.0, 3.0]],
        "height": 2.7,
        "doors": [{"id": "d0", "p0": [1.0, 0.0], "p1": [2.0, 0.0], "z_min": 0.0, "z_max": 2.1}],
        "windows": [{"id": "w0", "p0": [4.0, 1.0], "p1": [4.0, 2.0], "z_min": 0.9, "z_max": 2.0}],
    },
    "objects": [
        {
            "id": "desk_0",
            "category": "desk",
            "center": [1.0, 1.0, 0.375],
            "size": [1.2, 0.6, 0.75],
            "rotation": EYE,
            "support": "floor",
            "functional_anchor": None,
            "asset": {"source": "procedural", "id": None, "style": 0},
        },
        {
            "id": "laptop_0",
            "category": "laptop",
            "center": [1.0, 1.0, 0.76],
            "size": [0.3, 0.2, 0.02],
            "rotation": EYE,
            "support": "desk_0",
            "functional_anchor": None,
            "asset": None,
        },
        {
            "id": "chair_0",
            "category": "chair",
            "center": [1.0, 0.3, 0.45],
            "size": [0.5, 0.5, 0.9],
            "rotation": EYE,
            "support": "floor",
            "functional_anchor": "desk_0",
            "asset": None,
        },
    ],
    "stats": {"n_objects": 3},
}


# -- round trip ------------------------------------------------------------------------
def make_scene() -> Scene:
    """A scene that uses every field of the contract."""
    room = Room(
        "living_room",
        np.array([[0.0, 0.0], [5.0, 0.0], [5.0, 2.0], [2.5, 2.0], [2.5, 4.0], [0.0, 4.0]]),
        height=2.65,
        doors=(Opening("door", (1.0, 0.0), (1.9, 0.0), 0.0, 2.05, "door|1"),),
        windows=(
            Opening("window", (5.0, 0.5), (5.0, 1.5), 0.8, 2.2, "window|1"),
            Opening("window", (0.0, 1.0), (0.0, 3.0), 1.0, 2.0, None),
        ),
    )
    tilt = euler_to_matrix([0.1, -0.2, 0.3], "zxy")
    objects = [
        SceneObject(
            "sofa_0",
            "sofa",
            OrientedBox([1.25, 3.3, 0.425], [2.1, 0.9, 0.85], yaw_to_matrix(-np.pi / 2)),
            asset=AssetRef("ai2thor", "Sofa_1", None),
            support=FLOOR,
            source_label="Sofa",
            source_support="Floor",
        ),
        SceneObject(
            "table_0",
            "coffee_table",
            OrientedBox([1.25, 2.0, 0.2], [1.0 / 3.0, 0.6, 0.4], yaw_to_matrix(0.123456789)),
            asset=AssetRef("procedural", None, 3),
            support=FLOOR,
            functional_anchor="sofa_0",
        ),
        SceneObject(
            "book_0",
            "book",
            OrientedBox([1.2, 2.1, 0.42], [0.15, 0.22, 0.04], tilt),
            asset=AssetRef("user"),
            support="table_0",
            functional_anchor=None,
            source_label="Book",
            source_support="CoffeeTable|2",
        ),
        SceneObject(
            "drawer_0",
            "drawer",
            OrientedBox([1.25, 2.0, 0.1], [0.3, 0.5, 0.1]),
            support="table_0",
            part_of="table_0",
        ),
        SceneObject(
            "mystery_0",
            "unknown",
            OrientedBox([4.0, -1e-9, 1e-3], [1e-3, 2e-6, 7.0], yaw_to_matrix(np.pi)),
        ),
    ]
    stats = {
        "n_objects": 5,
        "seconds": 0.125,
        "warnings": ["book_0 tilted", "sizes [1,  2]"],
        "nested": {"a": [1, 2, 3], "b": None, "ok": True},
    }
    return Scene("scene_7", room, objects, source="generated", split="val", stats=stats)


def test_round_trip_all_fields(tmp_path):
    scene = make_scene()
    path = write_scene(scene, tmp_path / "scene.json")
    assert path == tmp_path / "scene.json"
    back = read_scene(path)

    assert (back.id, back.source, back.split) == ("scene_7", "generated", "val")
    assert back.stats == scene.stats
    assert back.room.type == scene.room.type
    assert back.room.height == pytest.approx(scene.room.height)
    np.testing.assert_allclose(back.room.floor_polygon, scene.room.floor_polygon, atol=1e-6)
    assert back.room.doors == scene.room.doors
    assert back.room.windows == scene.room.windows
    assert [o.id for o in back.objects] == [o.id for o in scene.objects]
    for a, b in zip(scene.objects, back.objects, strict=True):
        assert b.box.allclose(a.box, atol=1e-6), a.id
        for key in (
            "category",
            "asset",
            "support",
            "functional_anchor",
            "source_label",
            "source_support",
            "part_of",
        ):
            assert getattr(b, key) == getattr(a, key), (a.id, key)
    assert back.tuples() == scene.tuples()
    assert back.support_edges() == [("book_0", "table_0"), ("drawer_0", "table_0")]


def test_optional_fields_absent_when_none():
    d = scene_to_dict(make_scene())
    mystery = d["objects"][4]
    assert mystery["support"] is None and mystery["asset"] is None
    for key in ("source_label", "source_support", "part_of"):
        assert key not in mystery
    assert d["objects"][3]["part_of"] == "table_0"


def test_output_is_deterministic(tmp_path):
    a = write_scene(make_scene(), tmp_path / "a.json").read_bytes()
    b = write_scene(make_scene(), tmp_path / "b.json").read_bytes()
    assert a == b
    assert dumps_scene(make_scene()) == a.decode("utf-8")
    # Reading and writing again is a fixed point.
    c = write_scene(read_scene(tmp_path / "a.json"), tmp_path / "c.json").read_bytes()
    assert c == a
    assert a.startswith(b'{\n "format": "pair2scene.scene",\n "version": 1,\n')
    assert a.endswith(b"}\n")
    # No "-0.0": yaw pi has -sin(pi) = -1.2e-16 in its matrix, the centre y is -1e-9.
    assert scene_to_dict(make_scene())["objects"][4]["center"] == [4.0, 0.0, 0.001]
    assert not re.search(rb"-0\.0[,\]]", a)
    assert b"\r" not in a


def test_floats_are_rounded_to_6_decimals():
    d = scene_to_dict(make_scene())
    assert d["objects"][1]["size"][0] == 0.333333
    assert d["objects"][4]["size"][1] == 2e-06


def test_number_lists_on_one_line():
    text = dumps_scene(make_scene())
    lines = text.splitlines()
    number = r"-?\d[\d.eE+-]*"
    # No number ever stands on its own line; every vector is "[a, b, c]" on its line.
    assert not [ln for ln in lines if re.fullmatch(rf"\s*{number},?", ln)]
    vec3 = rf"\[{number}, {number}, {number}\]"
    assert len([ln for ln in lines if re.fullmatch(rf'\s*"center": {vec3},', ln)]) == 5
    assert len([ln for ln in lines if re.fullmatch(rf'\s*"size": {vec3},', ln)]) == 5
    rows = [ln for ln in lines if re.fullmatch(rf"\s*{vec3},?", ln)]
    assert len(rows) == 5 * 3
    assert re.search(rf'"p0": \[{number}, {number}\]', text)
    assert '"a": [1, 2, 3]' in text
    # Strings that look like number lists are left exactly as they are.
    assert '"sizes [1,  2]"' in text


def test_fixture_is_canonical():
    """The checked-in fixture reads, and writing it back gives the same bytes."""
    path = FIXTURES / "valid_bedroom.json"
    scene = read_scene(path)
    assert [o.id for o in scene.objects] == ["desk_0", "laptop_0", "chair_0"]
    assert dumps_scene(scene) == path.read_text(encoding="utf-8"), (
        "scene.json output changed; if deliberate, regenerate tests/fixtures/scenes/"
    )
    assert scene_to_dict(scene) == json.loads(path.read_text(encoding="utf-8"))


def test_base_dict_is_valid():
    scene = scene_from_dict(copy.deepcopy(BASE), "mem")
    assert scene.id == "s0"
    assert [t.support for t in scene.tuples()] == ["floor", "desk_0", "floor"]


# -- atomic writes ---------------------------------------------------------------------
def _listing(folder: Path) -> list[str]:
    return sorted(p.name for p in folder.iterdir())


def test_atomic_write_leaves_no_temp_file(tmp_path):
    target = tmp_path / "out" / "scene.json"  # parent created on demand
    write_scene(make_scene(), target)
    write_scene(make_scene(), target)  # overwrite
    assert _listing(target.parent) == ["scene.json"]
    atomic_write_bytes(tmp_path / "blob.bin", b"\x00\x01")
    assert (tmp_path / "blob.bin").read_bytes() == b"\x00\x01"
    assert _listing(tmp_path) == ["blob.bin", "out"]


def test_failed_serialisation_leaves_target_untouched(tmp_path, monkeypatch):
    target = tmp_path / "scene.json"
    target.write_text("OLD", encoding="utf-8")

    def boom(scene):
        raise RuntimeError("serialisation failed")

    monkeypatch.setattr(scene_json, "dumps_scene", boom)
    with pytest.raises(RuntimeError, match="serialisation failed"):
        write_scene(make_scene(), target)
    assert target.read_text(encoding="utf-8") == "OLD"
    assert _listing(tmp_path) == ["scene.json"]


def test_unserialisable_stats_leave_target_untouched(tmp_path):
    target = tmp_path / "scene.json"
    target.write_text("OLD", encoding="utf-8")
    scene = make_scene()
    scene.stats = {"bad": float("nan")}
    with pytest.raises(ValueError):
        write_scene(scene, target)
    assert target.read_text(encoding="utf-8") == "OLD"
    assert _listing(tmp_path) == ["scene.json"]


def test_failure_midway_through_the_write_leaves_target_untouched(tmp_path, monkeypatch):
    target = tmp_path / "scene.json"
    target.write_text("OLD", encoding="utf-8")

    def broken_fsync(fd):
        raise OSError(28, "No space left on device")

    monkeypatch.setattr(atomic.os, "fsync", broken_fsync)
    with pytest.raises(OSError, match="No space"):
        write_scene(make_scene(), target)
    assert target.read_text(encoding="utf-8") == "OLD"
    assert _listing(tmp_path) == ["scene.json"]


def test_atomic_open_exception_inside_block(tmp_path):
    target = tmp_path / "x.txt"
    with pytest.raises(KeyError):
        with atomic_open(target) as fh:
            fh.write("partial")
            assert _listing(tmp_path) != []  # the temporary file exists meanwhile
            raise KeyError("stop")
    assert not target.exists()
    assert _listing(tmp_path) == []


@pytest.mark.parametrize("call", ["mkdir", "open"])
def test_an_interrupt_right_after_the_temporary_is_made_leaves_nothing(tmp_path, monkeypatch, call):
    """A SIGTERM that generation turns into SystemExit can land between the moment a
    temporary folder (file) is made and the next line of the writer; the writer must still
    remove it (a scene folder written under load was once left behind so)."""
    real = getattr(atomic.os, call)

    def made_then_stopped(path, *args, **kwargs):
        out = real(path, *args, **kwargs)
        if Path(path).name.startswith("."):
            if call == "open":
                atomic.os.close(out)
            raise SystemExit(143)
        return out

    monkeypatch.setattr(atomic.os, call, made_then_stopped)
    (tmp_path / "scene").mkdir()
    (tmp_path / "scene" / "scene.json").write_text("OLD", encoding="utf-8")
    with pytest.raises(SystemExit):
        if call == "mkdir":
            atomic.replace_folder(tmp_path / "scene", lambda tmp: None)
        else:
            atomic_write_bytes(tmp_path / "scene" / "scene.json", b"NEW")
    assert _listing(tmp_path) == ["scene"]
    assert _listing(tmp_path / "scene") == ["scene.json"]
    assert (tmp_path / "scene" / "scene.json").read_text(encoding="utf-8") == "OLD"


# -- malformed files -------------------------------------------------------------------
@dataclass(frozen=True)
class Case:
    id: str
    field: str
    mutate: Callable[[dict], object] | None = None
    """Edits a deep copy of BASE in place, or returns a replacement document."""
    raw: bytes | None = None
    """Exact file content, instead of a mutated BASE."""
    special: str | None = None
    """'directory' or 'missing'."""

    def write(self, folder: Path) -> Path:
        path = folder / f"{self.id}.json"
        if self.special == "directory":
            path.mkdir()
        elif self.special == "missing":
            pass
        elif self.raw is not None:
            path.write_bytes(self.raw)
        else:
            d = copy.deepcopy(BASE)
            out = self.mutate(d)
            path.write_text(json.dumps(d if out is None else out), encoding="utf-8")
        return path


def _obj(i: int, **changes) -> Callable[[dict], None]:
    return lambda d: d["objects"][i].update(changes)


def _del(*keys: str | int) -> Callable[[dict], None]:
    def f(d):
        for k in keys[:-1]:
            d = d[k]
        del d[keys[-1]]

    return f


def _set(*keys: str | int, value) -> Callable[[dict], None]:
    def f(d):
        for k in keys[:-1]:
            d = d[k]
        d[keys[-1]] = value

    return f


VALID_TEXT = json.dumps(BASE)

CASES = [
    Case("invalid-json", "(json)", raw=b'{"format": "pair2scene.scene", "version": 1,'),
    Case("trailing-comma", "(json)", raw=VALID_TEXT[:-1].encode() + b",}"),
    Case("empty-file", "(file)", raw=b""),
    Case("whitespace-only", "(file)", raw=b" \n\t\n"),
    Case("not-utf8", "(file)", raw=b'{"format": "pair2scene.scene\xff\xfe"}'),
    Case("utf8-bom", "(json)", raw=codecs.BOM_UTF8 + VALID_TEXT.encode()),
    Case("huge-int-literal", "(json)", raw=b"[" + b"7" * 5000 + b"]"),
    Case("deep-nesting", "(json)", raw=b"[" * 100_000 + b"]" * 100_000),
    Case("directory", "(file)", special="directory"),
    Case("missing-file", "(file)", special="missing"),
    Case("top-level-list", "(top level)", mutate=lambda d: [d]),
    Case("top-level-string", "(top level)", mutate=lambda d: "scene"),
    Case("wrong-format", "format", _set("format", value="pair2scene.layout")),
    Case("missing-format", "format", _del("format")),
    Case("missing-version", "version", _del("version")),
    Case("version-2", "version", _set("version", value=2)),
    Case("version-string", "version", _set("version", value="1")),
    Case("version-bool", "version", _set("version", value=True)),
    Case("missing-room", "room", _del("room")),
    Case("room-not-object", "room", _set("room", value=[1, 2])),
    Case("room-missing-type", "room.type", _del("room", "type")),
    Case(
        "polygon-2-points",
        "room.floor_polygon",
        _set("room", "floor_polygon", value=[[0, 0], [1, 0]]),
    ),
    Case(
        "polygon-collinear",
        "room.floor_polygon",
        _set("room", "floor_polygon", value=[[0, 0], [1, 1], [2, 2]]),
    ),
    Case(
        "polygon-non-numeric",
        "room.floor_polygon[1][1]",
        _set("room", "floor_polygon", 1, 1, value="0"),
    ),
    Case(
        "polygon-point-3d",
        "room.floor_polygon[2]",
        _set("room", "floor_polygon", 2, value=[4, 3, 0]),
    ),
    Case("height-negative", "room.height", _set("room", "height", value=-2.7)),
    Case("height-zero", "room.height", _set("room", "height", value=0)),
    Case("height-infinity", "room.height", _set("room", "height", value=float("inf"))),
    Case("doors-not-list", "room.doors", _set("room", "doors", value={"p0": [0, 0]})),
    Case(
        "door-z-max-below-z-min",
        "room.doors[0].z_max",
        _set("room", "doors", 0, "z_max", value=-1.0),
    ),
    Case("window-missing-p1", "room.windows[0].p1", _del("room", "windows", 0, "p1")),
    Case("missing-objects", "objects", _del("objects")),
    Case("objects-not-list", "objects", _set("objects", value={"desk_0": {}})),
    Case("object-not-object", "objects[1]", _set("objects", 1, value="laptop_0")),
    Case("object-missing-id", "objects[1].id", _del("objects", 1, "id")),
    Case("object-id-number", "objects[1].id", _obj(1, id=7)),
    Case("object-id-empty", "objects[1].id", _obj(1, id="")),
    Case("duplicate-id", "objects[2].id", _obj(2, id="desk_0")),
    Case("id-floor", "objects[2].id", _obj(2, id="floor")),
    Case("unknown-category", "objects[1].category", _obj(1, category="hoverboard")),
    Case("center-nan", "objects[0].center[0]", _set("objects", 0, "center", 0, value=float("nan"))),
    Case("center-huge-int", "objects[0].center[2]", _set("objects", 0, "center", 2, value=10**400)),
    Case("center-2d", "objects[0].center", _obj(0, center=[1.0, 1.0])),
    Case("center-bool", "objects[0].center[1]", _set("objects", 0, "center", 1, value=True)),
    Case("size-zero", "objects[0].size[1]", _set("objects", 0, "size", 1, value=0)),
    Case("size-negative", "objects[2].size[2]", _set("objects", 2, "size", 2, value=-0.9)),
    Case(
        "rotation-scaled",
        "objects[1].rotation",
        _obj(1, rotation=[[2, 0, 0], [0, 2, 0], [0, 0, 2]]),
    ),
    Case(
        "rotation-sheared",
        "objects[1].rotation",
        _obj(1, rotation=[[1, 0.01, 0], [0, 1, 0], [0, 0, 1]]),
    ),
    Case(
        "rotation-reflection",
        "objects[1].rotation",
        _obj(1, rotation=[[1, 0, 0], [0, 1, 0], [0, 0, -1]]),
    ),
    Case("rotation-2-rows", "objects[1].rotation", _obj(1, rotation=[[1, 0, 0], [0, 1, 0]])),
    Case(
        "rotation-short-row",
        "objects[1].rotation[2]",
        _obj(1, rotation=[[1, 0, 0], [0, 1, 0], [0, 1]]),
    ),
    Case("support-missing-object", "objects[1].support", _obj(1, support="table_9")),
    Case("support-self", "objects[1].support", _obj(1, support="laptop_0")),
    Case("support-cycle", "objects[0].support", _obj(0, support="laptop_0")),
    Case("support-not-string", "objects[0].support", _obj(0, support=3)),
    Case(
        "functional-anchor-missing",
        "objects[2].functional_anchor",
        _obj(2, functional_anchor="bed_0"),
    ),
    Case("part-of-missing", "objects[1].part_of", _obj(1, part_of="cabinet_0")),
    Case("asset-without-source", "objects[0].asset.source", _del("objects", 0, "asset", "source")),
    Case("asset-not-object", "objects[0].asset", _obj(0, asset="procedural")),
    Case(
        "asset-style-string",
        "objects[0].asset.style",
        _set("objects", 0, "asset", "style", value="2"),
    ),
    Case("stats-not-object", "stats", _set("stats", value=[1, 2])),
    Case("scene-id-number", "id", _set("id", value=5)),
]

# Cases also run through a real `python -m pair2scene validate` process.
SUBPROCESS_CASES = {
    "invalid-json",
    "not-utf8",
    "directory",
    "missing-file",
    "huge-int-literal",
    "deep-nesting",
    "center-huge-int",
    "rotation-reflection",
    "support-cycle",
}


def test_cases_are_distinct():
    ids = [c.id for c in CASES]
    assert len(ids) == len(set(ids)) >= 24
    assert SUBPROCESS_CASES <= set(ids)


def check_message(msg: str, path: Path, field: str) -> None:
    assert "\n" not in msg and "\r" not in msg, msg
    assert str(path) in msg, msg
    assert field in msg, msg
    assert msg.startswith(f"{path}: {field}: "), msg


@pytest.mark.parametrize("case", CASES, ids=[c.id for c in CASES])
def test_read_scene_rejects(case, tmp_path):
    path = case.write(tmp_path)
    with pytest.raises(SceneFileError) as info:
        read_scene(path)
    err = info.value
    assert isinstance(err, UserError) and err.exit_code == 2
    assert err.field == case.field
    assert err.path == str(path)
    check_message(str(err), path, case.field)


@pytest.mark.parametrize("case", CASES, ids=[c.id for c in CASES])
def test_cli_validate_rejects_in_process(case, tmp_path, capsys):
    path = case.write(tmp_path)
    assert main(["validate", str(path)]) == 2
    out, err = capsys.readouterr()
    assert out == ""
    lines = err.splitlines()
    assert len(lines) == 1, err
    assert lines[0].startswith("error: ")
    check_message(lines[0].removeprefix("error: "), path, case.field)


@pytest.mark.slow  # (CI runs the slow tests too: .ci/run)
def test_cli_validate_rejects_in_subprocess(tmp_path):
    cases = [c for c in CASES if c.id in SUBPROCESS_CASES]
    assert len(cases) >= 5
    for case in cases:
        path = case.write(tmp_path)
        proc = run_cli("validate", str(path), cwd=tmp_path)
        assert proc.returncode == 2, (case.id, proc.stderr)
        assert "Traceback" not in proc.stderr, (case.id, proc.stderr)
        lines = proc.stderr.splitlines()
        assert len(lines) == 1, (case.id, proc.stderr)
        assert lines[0].startswith("error:"), (case.id, proc.stderr)
        check_message(lines[0].removeprefix("error: "), path, case.field)
        assert proc.stdout == "", case.id


def test_cli_validate_accepts_valid_file(tmp_path, capsys):
    path = tmp_path / "scene.json"
    path.write_text(json.dumps(BASE), encoding="utf-8")
    assert main(["validate", str(path)]) == 0
    out, err = capsys.readouterr()
    assert err == ""
    assert out == f"{path}: ok (3 objects, room bedroom)\n"

    proc = run_cli("validate", str(path), str(FIXTURES / "valid_bedroom.json"), cwd=tmp_path)
    assert proc.returncode == 0, proc.stderr
    assert proc.stderr == ""
    assert proc.stdout.count(": ok (3 objects, room bedroom)") == 2


def test_cli_validate_stops_at_first_bad_file(tmp_path, capsys):
    good = tmp_path / "good.json"
    good.write_text(json.dumps(BASE), encoding="utf-8")
    bad = Case("version-2", "version", _set("version", value=2)).write(tmp_path)
    assert main(["validate", str(good), str(bad), str(good)]) == 2
    out, err = capsys.readouterr()
    assert out == f"{good}: ok (3 objects, room bedroom)\n"
    assert err.startswith(f"error: {bad}: version: ") and err.count("\n") == 1

"""scene.json: the versioned file contract of architecture.md, with validation.

Reading never raises anything but :class:`SceneFileError` for a bad file; its
message is one line naming the file and the field (``objects[3].rotation``).

An object's ``support`` is ``floor``, ``wall:<i>`` (hung on wall i: the edge from
``floor_polygon[i]`` to ``floor_polygon[i + 1]``, 0 <= i < the number of vertices) or
another object's id. ``wall`` alone (a hierarchy's "wall not chosen yet") and any other
``wall:...`` are errors. The room keeps its polygon counter-clockwise: a clockwise
``floor_polygon`` is reversed on reading and every ``wall:<i>`` is renumbered to name the
same edge, so a file written back names its walls in the counter-clockwise order.

Physical limits (README, "scene.json"), the same for ``validate``, ``--keep`` and every
reader of scene folders, so that no value a reader accepts can overflow, stall or warn
further on:

- every coordinate (object centres, floor polygon vertices, door and window end points,
  their ``z_min`` / ``z_max``) is a finite number with ``|value| <=`` :data:`MAX_COORD_M`
  (100 m);
- every size (object ``size``, room ``height``) is finite, > 0 and ``<=``
  :data:`MAX_SIZE_M` (100 m); the floor polygon spans at most :data:`MAX_SIZE_M` along x
  and along y;
- the floor polygon has at most :data:`MAX_FLOOR_VERTICES` (1,000) vertices, the room at
  most :data:`MAX_OPENINGS` (1,000) doors and as many windows, the scene at most
  :data:`MAX_OBJECTS` (10,000) objects;
- ids, categories, supports, labels, the room type and every other string field have at
  most :data:`MAX_TEXT` (200) characters;
- the file has at most :data:`MAX_SCENE_BYTES` (64 MiB), nests at most 64 levels (the
  free-form ``stats`` included) and is UTF-8 (:func:`pair2scene.io.jsondoc.read_json_file`).

Counts are checked before their items, so an oversized file is refused at once.
"""

from __future__ import annotations

import json
import math
import os
import re
from dataclasses import replace
from pathlib import Path
from typing import Any

import numpy as np

from pair2scene.categories import BY_NAME, UNKNOWN
from pair2scene.errors import SceneFileError
from pair2scene.io.atomic import atomic_write_text
from pair2scene.io.jsondoc import MAX_JSON_BYTES, JsonFileError, read_json_file
from pair2scene.scene.geometry import OrientedBox, is_rotation, polygon_area
from pair2scene.scene.model import (
    FLOOR,
    WALL,
    AssetRef,
    Opening,
    Room,
    Scene,
    SceneObject,
    is_root,
    wall_support,
)

FORMAT = "pair2scene.scene"
VERSION = 1
DECIMALS = 6
"""Floats are written with 6 decimals: micrometres, and stable across platforms."""
MIN_OPENING_WIDTH = 1e-3
"""m; a door or window narrower than this is a data error."""
MIN_FLOOR_AREA = 1e-4
"""m^2; below this a floor polygon is degenerate (collinear or repeated points)."""
MIN_WALL_LENGTH = 1e-3
"""m; an edge of the floor polygon shorter than this (a repeated vertex) is no wall an
object can hang on (:func:`pair2scene.scene.walls.walls_of` leaves it out too)."""
MAX_COORD_M = 100.0
"""m; the largest |coordinate| a scene.json may hold (centres, vertices, openings)."""
MAX_SIZE_M = 100.0
"""m; the largest object size, room height and floor polygon extent."""
MAX_FLOOR_VERTICES = 1000
"""Vertices a floor polygon may have (real rooms have 4 to a few dozen)."""
MAX_OPENINGS = 1000
"""Doors a room may have, and windows."""
MAX_OBJECTS = 10_000
"""Objects a scene may have (generated rooms have up to a few hundred)."""
MAX_TEXT = 200
"""Characters an id, a category, a support, a label or any other string field may have."""
MAX_SCENE_BYTES = MAX_JSON_BYTES
"""Bytes a scene.json may have (64 MiB)."""
_WALL_SUPPORT = re.compile(r"wall:(0|[1-9][0-9]*)", re.ASCII)
"""The one spelling of a wall support: ``wall:<i>``, i a decimal without leading zeros."""


# -- writing -------------------------------------------------------------------------
def _r(x: Any) -> Any:
    """JSON-ready copy: numpy arrays and scalars to Python, floats rounded."""
    if isinstance(x, np.ndarray):
        x = x.tolist()
    if isinstance(x, dict):
        return {str(k): _r(v) for k, v in x.items()}
    if isinstance(x, (list, tuple)):
        return [_r(v) for v in x]
    if isinstance(x, (bool, np.bool_)):
        return bool(x)
    if isinstance(x, np.integer):
        return int(x)
    if isinstance(x, (float, np.floating)):
        v = round(float(x), DECIMALS)
        return 0.0 if v == 0 else v  # no "-0.0" in files
    return x


def _opening_to_dict(o: Opening) -> dict:
    return {"id": o.id, "p0": _r(o.p0), "p1": _r(o.p1), "z_min": _r(o.z_min), "z_max": _r(o.z_max)}


def scene_to_dict(scene: Scene) -> dict:
    """The JSON-ready dict of ``scene`` (architecture.md's scene.json)."""
    objects = []
    for o in scene.objects:
        d = {
            "id": o.id,
            "category": o.category,
            "center": _r(o.box.center),
            "size": _r(o.box.size),
            "rotation": _r(o.box.rotation),
            "support": o.support,
            "functional_anchor": o.functional_anchor,
            "asset": o.asset.to_dict() if o.asset else None,
        }
        for key in ("source_label", "source_support", "part_of"):
            if getattr(o, key) is not None:
                d[key] = getattr(o, key)
        objects.append(d)
    room = scene.room
    return {
        "format": FORMAT,
        "version": VERSION,
        "id": scene.id,
        "source": scene.source,
        "split": scene.split,
        "room": {
            "type": room.type,
            "floor_polygon": _r(room.floor_polygon),
            "height": _r(room.height),
            "doors": [_opening_to_dict(d) for d in room.doors],
            "windows": [_opening_to_dict(w) for w in room.windows],
        },
        "objects": objects,
        "stats": _r(scene.stats),
    }


# A JSON string (left as it is: its text may look like a number list) or a number list.
_NUMBER_LIST = re.compile(r'"(?:[^"\\]|\\.)*"|\[\s*(-?[\d.eE+-]+(?:,\s*-?[\d.eE+-]+)*)\s*\]')


def _one_line(m: re.Match) -> str:
    if m.group(1) is None:
        return m.group(0)
    return "[" + re.sub(r"\s+", " ", m.group(1)) + "]"


def dumps_json(data: Any) -> str:
    """Indented JSON with every list of numbers kept on one line (readable diffs)."""
    text = json.dumps(data, indent=1, allow_nan=False)
    return _NUMBER_LIST.sub(_one_line, text) + "\n"


def dumps_scene(scene: Scene) -> str:
    return dumps_json(scene_to_dict(scene))


def write_scene(scene: Scene, path: str | os.PathLike) -> Path:
    """Write ``scene`` to ``path`` atomically (temporary file, then rename)."""
    atomic_write_text(path, dumps_scene(scene))
    return Path(path)


# -- reading and validation ----------------------------------------------------------
class _Check:
    """Field-by-field validation that stops at the first problem, naming the field."""

    def __init__(self, origin: str) -> None:
        self.origin = origin

    def fail(self, field: str, problem: str) -> SceneFileError:
        return SceneFileError(self.origin, field, problem)

    def obj(self, d: Any, field: str) -> dict:
        if not isinstance(d, dict):
            raise self.fail(field, f"must be an object, got {_kind(d)}")
        return d

    def req(self, d: dict, key: str, field: str) -> Any:
        if key not in d:
            raise self.fail(f"{field}.{key}" if field else key, "is missing")
        return d[key]

    def string(self, v: Any, field: str, nullable: bool = False) -> str | None:
        if v is None and nullable:
            return None
        if not isinstance(v, str) or not v:
            raise self.fail(field, f"must be a non-empty string, got {_kind(v)}")
        if len(v) > MAX_TEXT:
            raise self.fail(field, f"has {len(v)} characters, more than {MAX_TEXT}")
        return v

    def number(self, v: Any, field: str, positive: bool = False) -> float:
        """A finite number: a size (``positive``: > 0 and <= MAX_SIZE_M m) or a coordinate
        (|v| <= MAX_COORD_M m)."""
        if isinstance(v, bool) or not isinstance(v, (int, float)) or not _finite(v):
            raise self.fail(field, f"must be a finite number, got {_kind(v)}")
        if positive and v <= 0:
            raise self.fail(field, f"must be > 0, got {v}")
        if positive and v > MAX_SIZE_M:
            raise self.fail(field, f"must be <= {MAX_SIZE_M:g} m, got {v:g}")
        if abs(v) > MAX_COORD_M:
            raise self.fail(field, f"must be within +-{MAX_COORD_M:g} m, got {v:g}")
        return float(v)

    def vector(self, v: Any, n: int, field: str, positive: bool = False) -> np.ndarray:
        if not isinstance(v, list) or len(v) != n:
            raise self.fail(field, f"must be a list of {n} numbers, got {_kind(v)}")
        return np.array([self.number(x, f"{field}[{i}]", positive) for i, x in enumerate(v)])

    def count(self, v: list, most: int, field: str, what: str) -> None:
        if len(v) > most:
            raise self.fail(field, f"has {len(v)} {what}, more than {most:,}")

    def matrix(self, v: Any, field: str) -> np.ndarray:
        if not isinstance(v, list) or len(v) != 3:
            raise self.fail(field, f"must be a 3x3 list of rows, got {_kind(v)}")
        m = np.stack([self.vector(row, 3, f"{field}[{i}]") for i, row in enumerate(v)])
        if not is_rotation(m):
            raise self.fail(field, "is not a rotation (orthonormal, determinant +1)")
        return m


def _finite(v: int | float) -> bool:
    """math.isfinite that also takes ints too large for a float (JSON allows them)."""
    try:
        return math.isfinite(v)
    except OverflowError:
        return False


def _kind(v: Any) -> str:
    if v is None:
        return "null"
    if isinstance(v, bool):
        return "a boolean"
    if isinstance(v, int) and not _finite(v):
        return "an integer too large for a float"
    if isinstance(v, (int, float)):
        return repr(v) if not math.isfinite(v) else "a number"
    if isinstance(v, str):
        return "a string" if v else "an empty string"
    if isinstance(v, list):
        return f"a list of {len(v)}"
    if isinstance(v, dict):
        return "an object"
    return type(v).__name__


def _opening(c: _Check, d: Any, kind: str, field: str) -> Opening:
    c.obj(d, field)
    p0 = c.vector(c.req(d, "p0", field), 2, f"{field}.p0")
    p1 = c.vector(c.req(d, "p1", field), 2, f"{field}.p1")
    z_min = c.number(d.get("z_min", 0.0), f"{field}.z_min")
    z_max = c.number(d.get("z_max", 2.1), f"{field}.z_max")
    if np.hypot(*(p1 - p0)) < MIN_OPENING_WIDTH:
        raise c.fail(f"{field}.p1", "must differ from p0 (an opening needs a width)")
    if z_max <= z_min:
        raise c.fail(f"{field}.z_max", f"must be above z_min ({z_min}), got {z_max}")
    oid = c.string(d.get("id"), f"{field}.id", nullable=True)
    return Opening(kind, tuple(p0), tuple(p1), z_min, z_max, oid)  # type: ignore[arg-type]


def _room(c: _Check, d: Any) -> Room:
    c.obj(d, "room")
    rtype = c.string(c.req(d, "type", "room"), "room.type")
    poly_raw = c.req(d, "floor_polygon", "room")
    if not isinstance(poly_raw, list) or len(poly_raw) < 3:
        raise c.fail(
            "room.floor_polygon", f"must list at least 3 [x, y] points, got {_kind(poly_raw)}"
        )
    c.count(poly_raw, MAX_FLOOR_VERTICES, "room.floor_polygon", "vertices")
    poly = np.stack([c.vector(p, 2, f"room.floor_polygon[{i}]") for i, p in enumerate(poly_raw)])
    extent = poly.max(axis=0) - poly.min(axis=0)
    if extent.max() > MAX_SIZE_M:
        axis = "xy"[int(np.argmax(extent))]
        raise c.fail(
            "room.floor_polygon", f"spans {extent.max():g} m along {axis}, more than {MAX_SIZE_M:g}"
        )
    if abs(polygon_area(poly)) < MIN_FLOOR_AREA:
        raise c.fail("room.floor_polygon", "has no area (collinear or repeated points)")
    height = c.number(c.req(d, "height", "room"), "room.height", positive=True)
    openings = {}
    for key, kind in (("doors", "door"), ("windows", "window")):
        raw = d.get(key, [])
        if not isinstance(raw, list):
            raise c.fail(f"room.{key}", f"must be a list, got {_kind(raw)}")
        c.count(raw, MAX_OPENINGS, f"room.{key}", key)
        openings[key] = tuple(_opening(c, o, kind, f"room.{key}[{i}]") for i, o in enumerate(raw))
    return Room(rtype, poly, height, openings["doors"], openings["windows"])


def _asset(c: _Check, d: Any, field: str) -> AssetRef | None:
    if d is None:
        return None
    c.obj(d, field)
    source = c.string(c.req(d, "source", field), f"{field}.source")
    aid = d.get("id")
    if aid is not None and not isinstance(aid, str):
        raise c.fail(f"{field}.id", f"must be a string or null, got {_kind(aid)}")
    if aid is not None and len(aid) > MAX_TEXT:
        raise c.fail(f"{field}.id", f"has {len(aid)} characters, more than {MAX_TEXT}")
    style = d.get("style")
    if style is not None and (isinstance(style, bool) or not isinstance(style, int)):
        raise c.fail(f"{field}.style", f"must be an integer or null, got {_kind(style)}")
    seed = d.get("seed")
    if seed is not None and (isinstance(seed, bool) or not isinstance(seed, int) or seed < 0):
        raise c.fail(f"{field}.seed", f"must be a non-negative integer or null, got {seed!r}")
    return AssetRef(source, aid, style, seed)


def _object(c: _Check, d: Any, field: str) -> SceneObject:
    c.obj(d, field)
    oid = c.string(c.req(d, "id", field), f"{field}.id")
    cat = c.string(c.req(d, "category", field), f"{field}.category")
    if cat not in BY_NAME and cat != UNKNOWN:
        raise c.fail(f"{field}.category", f"unknown category {cat!r}")
    center = c.vector(c.req(d, "center", field), 3, f"{field}.center")
    size = c.vector(c.req(d, "size", field), 3, f"{field}.size", positive=True)
    rotation = c.matrix(c.req(d, "rotation", field), f"{field}.rotation")
    opt = {}
    for key in ("support", "functional_anchor", "source_label", "source_support", "part_of"):
        opt[key] = c.string(d.get(key), f"{field}.{key}", nullable=True)
    return SceneObject(
        id=oid,  # type: ignore[arg-type]
        category=cat,  # type: ignore[arg-type]
        box=OrientedBox(center, size, rotation),
        asset=_asset(c, d.get("asset"), f"{field}.asset"),
        **opt,
    )


def _wall_support(c: _Check, ref: str, polygon: np.ndarray, field: str) -> None:
    """Check a support id that names a wall (``wall`` or ``wall:...``) against the floor
    polygon (N, 2) as the file lists it."""
    n = len(polygon)
    valid = f"'wall:<i>' with 0 <= i < {n} (the floor polygon's {n} edges)"
    if ref == WALL:
        raise c.fail(field, f"'wall' (no wall chosen) is only valid in hierarchies: use {valid}")
    m = _WALL_SUPPORT.fullmatch(ref)
    if m is None:
        raise c.fail(field, f"malformed wall support {ref!r}: must be {valid}")
    i = int(m.group(1))
    if i >= n:
        raise c.fail(field, f"wall index {i} out of range: must be {valid}")
    a, b = polygon[i], polygon[(i + 1) % n]
    if np.hypot(*(b - a)) < MIN_WALL_LENGTH:
        j = (i + 1) % n
        raise c.fail(field, f"wall {i} has no length (floor_polygon[{j}] repeats [{i}])")


def _names_wall(ref: str | None) -> bool:
    """Whether a support id is meant as a wall: ``wall`` or ``wall:...`` (object ids such
    as ``wall_shelf_0`` are not)."""
    return isinstance(ref, str) and (ref == WALL or ref.startswith(WALL + ":"))


def _links(c: _Check, objects: list[SceneObject], polygon: np.ndarray) -> None:
    ids = {o.id: i for i, o in enumerate(objects)}
    for i, o in enumerate(objects):
        for key in ("support", "functional_anchor", "part_of"):
            ref = getattr(o, key)
            if ref is None or (key == "support" and ref == FLOOR):
                continue
            if key == "support" and _names_wall(ref):
                _wall_support(c, ref, polygon, f"objects[{i}].support")
                continue
            if ref == o.id:
                raise c.fail(f"objects[{i}].{key}", f"object {o.id!r} refers to itself")
            if ref not in ids:
                raise c.fail(f"objects[{i}].{key}", f"refers to unknown object {ref!r}")
    parent = {o.id: o.support for o in objects}
    grounded: set[str] = set()  # ids whose chain of supports ends at the floor or a wall
    for i, o in enumerate(objects):
        chain: dict[str, None] = {}
        cur: str | None = o.id
        while cur is not None and not is_root(cur) and cur not in grounded:
            if cur in chain:
                raise c.fail(f"objects[{i}].support", f"support cycle through {o.id!r}")
            chain[cur] = None
            cur = parent[cur]
        grounded.update(chain)


def _renumber_walls(objects: list[SceneObject], n: int) -> list[SceneObject]:
    """``objects`` with every ``wall:<j>`` support, an edge of a clockwise polygon of ``n``
    vertices as the file lists it, renamed after the same edge of the reversed
    (counter-clockwise) polygon the room keeps: file edge j (vertex j to j + 1) is the
    reversed polygon's edge n - 2 - j (mod n)."""
    out = []
    for o in objects:
        m = _WALL_SUPPORT.fullmatch(o.support) if isinstance(o.support, str) else None
        if m is not None:
            o = replace(o, support=wall_support((n - 2 - int(m.group(1))) % n))
        out.append(o)
    return out


def scene_from_dict(d: Any, origin: str = "<scene>") -> Scene:
    """Validate and convert a parsed scene.json; raises SceneFileError naming the field."""
    c = _Check(origin)
    c.obj(d, "(top level)")
    fmt = c.req(d, "format", "")
    if fmt != FORMAT:
        raise c.fail("format", f"must be {FORMAT!r}, got {fmt!r}")
    version = c.req(d, "version", "")
    if isinstance(version, bool) or not isinstance(version, int):
        raise c.fail("version", f"must be an integer, got {_kind(version)}")
    if version != VERSION:
        raise c.fail("version", f"unsupported version {version} (this release reads {VERSION})")
    room = _room(c, c.req(d, "room", ""))
    raw = c.req(d, "objects", "")
    if not isinstance(raw, list):
        raise c.fail("objects", f"must be a list, got {_kind(raw)}")
    c.count(raw, MAX_OBJECTS, "objects", "objects")
    objects, seen = [], set()
    for i, od in enumerate(raw):
        o = _object(c, od, f"objects[{i}]")
        if o.id in seen:
            raise c.fail(f"objects[{i}].id", f"duplicate id {o.id!r}")
        if o.id == FLOOR:
            raise c.fail(f"objects[{i}].id", f"{FLOOR!r} is reserved for the floor")
        if _names_wall(o.id):
            raise c.fail(f"objects[{i}].id", f"{o.id!r} is reserved for walls")
        seen.add(o.id)
        objects.append(o)
    listed = np.asarray(d["room"]["floor_polygon"], dtype=float)  # (validated by _room)
    _links(c, objects, listed)
    if polygon_area(listed) < 0:  # the room reversed it: rename the walls after it
        objects = _renumber_walls(objects, len(listed))
    stats = d.get("stats", {})
    if stats is None:
        stats = {}
    c.obj(stats, "stats")
    sid = c.string(d.get("id"), "id", nullable=True)
    src = c.string(d.get("source"), "source", nullable=True)
    split = c.string(d.get("split"), "split", nullable=True)
    return Scene(
        id=sid or Path(origin).parent.name or "scene",
        room=room,
        objects=objects,
        source=src,
        split=split,
        stats=stats,
    )


def read_scene(path: str | os.PathLike) -> Scene:
    """Read and validate a scene.json; any problem raises one SceneFileError."""
    origin = str(path)
    try:
        data = read_json_file(path, "scene.json", MAX_SCENE_BYTES, finite=False)
    except JsonFileError as e:  # numbers are checked field by field, naming the field
        raise SceneFileError(origin, e.field, e.problem) from None
    return scene_from_dict(data, origin)

"""3D-FRONT source adapter: house JSON files plus 3D-FUTURE's ``model_info.json`` -> Corpus.

3D-FRONT cannot be shipped; users bring it. A house file holds ``furniture``
(3D-FUTURE model references with their extent), ``mesh`` (architecture: floors,
walls, doors, windows, as flat vertex and face lists) and ``scene.room``, whose
``children`` place furniture and meshes by ``ref`` with a position, a quaternion
and a scale. Every room with furniture becomes one :class:`Scene`.

Frames. 3D-FRONT and 3D-FUTURE are y-up and right-handed; a 3D-FUTURE model
faces its local +z and has its origin at the bottom centre. The conversion to
architecture.md's frames is done here, once:

- world: ``(x, y, z) -> (x, -z, y)`` (:data:`WORLD_FROM_FRONT`, +90 deg about x);
- object: ``(right, front, up) = (-x_m, +z_m, +y_m)`` (:data:`OURS_FROM_MODEL`;
  with up +y and front +z, the model's +x is its *left*);
- rotation ``R = WORLD_FROM_FRONT @ R_src @ OURS_FROM_MODEL.T``.

Both mappings are proper rotations, so a box keeps determinant +1. The world is
shifted so that the room's floor mesh lies at z = 0.

What real house files hold, and how it is read:

- Extents. A furniture entry's ``size`` is [width, depth, height] (z up), and a
  ``bbox`` beside it repeats it; an entry with only a ``bbox`` has it in the model's own
  y-up axes (checked on 14 public house files against 3D-FUTURE's meshes: every ``size``
  z-up, every lone ``bbox`` y-up). When 3D-FUTURE's model folder is at hand, the
  model's own mesh extent wins (:func:`read_obj_extent`) and a file extent that
  disagrees is counted; a model_info ``boundingBox`` (the toolbox's, in cm) comes next.
- Floors. A room's floor comes in pieces that overlap, repeat and meet in T-junctions,
  with zero-area slivers among them: the outline is their union's outer ring
  (:func:`floor_outline`).
- Doors and windows. Each is several meshes (frame, leaf, threshold, sill; a bay
  window two dozen), and a door between two rooms is listed under one of them: the
  pieces of one opening are joined, laid on the wall they run along, and kept with
  their full height; a flat piece on its own (a sill) is no opening (:func:`openings_of`).
- Lamps. 3D-FUTURE's "Lighting" says only "a lamp": which one follows from its height
  (:func:`lamp_by_height`).
"""

from __future__ import annotations

import math
from collections import Counter
from collections.abc import Iterable, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Literal

import numpy as np

from pair2scene.categories import (
    FRONT3D_ROOM_TYPES,
    FUTURE3D_LABELS,
    UNKNOWN,
    LabelMapper,
    RoomType,
)
from pair2scene.data.base import SPLITS, Corpus, SourceReport, stable_fraction
from pair2scene.data.support import floor_by_height
from pair2scene.errors import UserError
from pair2scene.io.jsondoc import MAX_STATS_BYTES, JsonFileError, read_json_file
from pair2scene.progress import track
from pair2scene.scene.geometry import OrientedBox, points_in_polygon, polygon_area
from pair2scene.scene.model import AssetRef, Opening, Room, Scene, SceneObject

SOURCE = "3dfront"
ASSET_SOURCE = "3dfuture"
MODEL_INFO = "model_info.json"
FUTURE_FOLDER = "3D-FUTURE-model"
"""3D-FUTURE's own folder name; ``model_info.json`` often sits in it, beside 3D-FRONT."""

WORLD_FROM_FRONT = np.array([[1.0, 0.0, 0.0], [0.0, 0.0, -1.0], [0.0, 1.0, 0.0]])
"""(3, 3) 3D-FRONT world (y up) -> our world (z up): ``(x, y, z) -> (x, -z, y)``."""

OURS_FROM_MODEL = np.array([[-1.0, 0.0, 0.0], [0.0, 0.0, 1.0], [0.0, 1.0, 0.0]])
"""(3, 3) 3D-FUTURE model axes -> our object axes: right = -x_m, front = +z_m, up = +y_m."""

DEFAULT_ROOM_HEIGHT = 2.8
"""m; 3D-FRONT ceilings are mostly 2.6-3.0 m. Used when a room has no WallInner mesh."""
VAL_FRACTION = 0.2
"""Share of rooms in the ``val`` split, decided by a hash of the scene id."""


@dataclass(frozen=True)
class Front3DTolerances:
    """Distances used to read 3D-FRONT geometry, each with its reason."""

    vertex_merge: float = 1e-3
    """m; vertices of one floor closer than 1 mm are one vertex (meshes are stored as
    float32 and split into pieces that share their borders to ~1e-6 m)."""
    opening_touch: float = 0.3
    """m; a door or window mesh sits inside a wall (0.1-0.25 m thick), so its bounding
    box lies within this distance of the floor outline of each room it opens into."""
    fallback_margin: float = 0.5
    """m; a room without a floor mesh gets its furniture's xy bounds grown by this much
    (furniture stands against walls, plus the space to reach it)."""
    min_opening_width: float = 0.01
    """m; a door or window narrower than this is a broken mesh, not an opening."""
    opening_join: float = 0.05
    """m; a door or window is several meshes (frame, leaf, threshold, sill; up to two
    dozen for a bay window): pieces of one kind whose boxes come this close are one
    opening."""
    min_opening_height: float = 0.3
    """m; an opening lower than this is a threshold or sill piece on its own (flat, often
    of zero height), not a door or window."""
    opening_angle_deg: float = 20.0
    """deg; an opening is laid on the floor outline's edge it runs along, within this
    angle."""
    max_coordinate: float = 1e4
    """m; houses span tens of metres, so a coordinate, size or scale beyond 10 km is
    corrupt data (and would overflow squared distances)."""


TOL = Front3DTolerances()

# Warning keys counted in ``SourceReport.warnings`` (generic, so counts stay readable).
W_NO_MODEL_INFO = "model_info.json not found (categories from house files only)"
W_MISSING_INFO = "missing model_info entry"
W_NO_SIZE = "no size (object skipped)"
W_SIZE_MESH = "size field disagrees with its 3D-FUTURE mesh (mesh extent used)"
W_BAD_TRANSFORM = "bad pos/rot/scale (object skipped)"
W_MIRRORED = "mirrored object (negative scale)"
W_UNKNOWN_REF = "child refers to no furniture or mesh"
W_BAD_MESH = "malformed mesh (ignored)"
W_NO_FURNITURE = "room without furniture (skipped)"
W_NO_FLOOR = "no floor mesh (floor from furniture bounds)"
W_BAD_FLOOR = "floor mesh without an outline (floor from furniture bounds)"
W_OUTSIDE_FLOOR = "room whose objects stand mostly outside its floor (kept as read)"
MIN_INSIDE_SHARE = 0.5
"""A room with fewer of its objects' centres on its floor outline than this share is
warned of (:data:`W_OUTSIDE_FLOOR`): its furniture and floor do not belong together."""
W_BAD_OPENING = "degenerate door/window mesh (ignored)"
W_FLAT_OPENING = "door/window piece without height on its own, a threshold or sill (ignored)"
W_OFF_WALL_OPENING = "door/window along no wall of its room (kept where its mesh is)"
W_DUPLICATE_ROOM = "duplicate room instanceid (renamed)"
W_NO_ROOM_ID = "room without instanceid (named by index)"


def _unmapped_room(label: str) -> str:
    return f"unmapped room type: {label}"


# -- frame conversion ---------------------------------------------------------------
def quaternion_to_matrix(quat: Sequence[float]) -> np.ndarray:
    """Rotation matrix of a quaternion in 3D-FRONT's ``[qx, qy, qz, qw]`` order.

    quat : (4,) float, any non-zero length (normalised here)  ->  (3, 3) float.
    Raises ValueError for a zero or non-finite quaternion.
    """
    q = np.asarray(quat, dtype=float)
    norm = float(np.linalg.norm(q)) if q.shape == (4,) else 0.0
    if not math.isfinite(norm) or norm < 1e-9:
        raise ValueError(f"not a rotation quaternion: {list(np.ravel(q))}")
    x, y, z, w = q / norm
    return np.array(
        [
            [1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
            [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
            [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)],
        ]
    )


def front_points_to_world(xyz: np.ndarray) -> np.ndarray:
    """3D-FRONT (y-up) points -> our world (z-up): (N, 3) -> (N, 3)."""
    return np.asarray(xyz, dtype=float).reshape(-1, 3) @ WORLD_FROM_FRONT.T


def future_box(
    size: Sequence[float],
    pos: Sequence[float],
    rot: Sequence[float],
    scale: Sequence[float] = (1.0, 1.0, 1.0),
) -> OrientedBox:
    """The world box (z-up) of a placed 3D-FUTURE model.

    size : (3,) the model's extent along its own x, y (up), z (front), unscaled;
    pos : (3,) the model origin (its bottom centre) in 3D-FRONT coordinates;
    rot : (4,) quaternion ``[qx, qy, qz, qw]``; scale : (3,) per model axis.

    A negative scale mirrors the model. A box cannot show a mirror, so its axes
    follow the mirrored model and, when that flips handedness, the right axis is
    reversed (left and right of a box are the same faces).
    """
    size = np.abs(np.asarray(size, dtype=float))
    pos = np.asarray(pos, dtype=float)
    scale = np.asarray(scale, dtype=float)
    r_src = quaternion_to_matrix(rot)
    signs = np.where(scale < 0, -1.0, 1.0)
    r_model = r_src @ np.diag(signs)  # (3, 3) columns: the placed model's axes, y-up
    if np.linalg.det(r_model) < 0:
        r_model = r_model @ np.diag([-1.0, 1.0, 1.0])
    rotation = WORLD_FROM_FRONT @ r_model @ OURS_FROM_MODEL.T
    extent = size * np.abs(scale)  # (3,) along model x, y, z
    # The origin is the bottom centre: the centre is half the scaled height up the
    # model's (possibly mirrored) up axis.
    center_src = pos + r_src @ np.array([0.0, size[1] * scale[1] / 2, 0.0])
    return OrientedBox(WORLD_FROM_FRONT @ center_src, np.abs(OURS_FROM_MODEL) @ extent, rotation)


# -- floor outline -------------------------------------------------------------------
def floor_outline(triangles: np.ndarray, tol: float = TOL.vertex_merge) -> np.ndarray | None:
    """The outer boundary of a union of triangles, as a counter-clockwise polygon.

    triangles : (T, 3, 2) world xy  ->  (N, 2) float, or None when no closed outline.

    Real floors come in pieces: tiles that overlap or repeat (a border piece stored 3-8
    times), pieces meeting in T-junctions, zero-area sliver triangles. Slivers (thinner
    than ``tol``) are dropped; the rest are united on a ``tol`` grid and cracks narrower
    than ``tol`` between pieces closed; the largest part's outer ring wins (holes and
    detached scraps lose). Collinear vertices are dropped and the polygon starts at its
    lowest-x, then lowest-y vertex.
    """
    import shapely

    tri = np.asarray(triangles, dtype=float).reshape(-1, 3, 2)
    if len(tri) == 0:
        return None
    e = np.roll(tri, -1, axis=1) - tri  # (T, 3, 2) edges
    area2 = np.abs(e[:, 0, 0] * e[:, 1, 1] - e[:, 0, 1] * e[:, 1, 0])  # twice the area
    longest = np.linalg.norm(e, axis=2).max(axis=1)
    tri = tri[area2 > tol * np.maximum(longest, tol)]  # height over the longest side > tol
    if len(tri) == 0:
        return None
    rings = np.concatenate([tri, tri[:, :1]], axis=1)  # (T, 4, 2) closed
    union = shapely.union_all(shapely.polygons(rings), grid_size=tol)
    union = union.buffer(tol, join_style="mitre").buffer(-tol, join_style="mitre")
    parts = [g for g in getattr(union, "geoms", [union]) if g.geom_type == "Polygon"]
    parts = [g for g in parts if not g.is_empty]
    if not parts:
        return None
    best = max(parts, key=lambda g: g.area).exterior.simplify(tol)
    poly = np.asarray(best.coords, dtype=float)[:-1]
    poly = _drop_collinear(poly, tol)
    if len(poly) < 3 or abs(polygon_area(poly)) < tol:
        return None
    if polygon_area(poly) < 0:
        poly = poly[::-1]
    start = int(np.lexsort((poly[:, 1], poly[:, 0]))[0])
    return np.roll(poly, -start, axis=0)


def _drop_collinear(poly: np.ndarray, tol: float) -> np.ndarray:
    """Remove vertices that lie on the line through their neighbours: (N, 2) -> (M, 2)."""
    pts = list(poly)
    changed = True
    while changed and len(pts) > 3:
        changed = False
        for i in range(len(pts)):
            prev, cur, nxt = pts[i - 1], pts[i], pts[(i + 1) % len(pts)]
            base = nxt - prev
            length = float(np.hypot(*base))
            rel = cur - prev
            dist = abs(rel[0] * base[1] - rel[1] * base[0]) / length if length > tol else 0.0
            if dist < tol:
                del pts[i]
                changed = True
                break
    return np.array(pts)


# -- doors and windows ---------------------------------------------------------------
OpeningKind = Literal["door", "window"]


def _point_segment_distance(p: np.ndarray, a: np.ndarray, b: np.ndarray) -> float:
    d = b - a
    denom = float(d @ d)
    t = 0.0 if denom == 0 else float(np.clip((p - a) @ d / denom, 0.0, 1.0))
    return float(np.hypot(*(p - (a + t * d))))


def _segments_cross(a: np.ndarray, b: np.ndarray, c: np.ndarray, d: np.ndarray) -> bool:
    def side(p: np.ndarray, q: np.ndarray, r: np.ndarray) -> float:
        return float((q[0] - p[0]) * (r[1] - p[1]) - (q[1] - p[1]) * (r[0] - p[0]))

    return side(a, b, c) * side(a, b, d) < 0 and side(c, d, a) * side(c, d, b) < 0


def rect_polygon_distance(lo: np.ndarray, hi: np.ndarray, polygon: np.ndarray) -> float:
    """Distance between an axis-aligned rectangle and a polygon; 0 when they overlap.

    lo, hi : (2,) rectangle corners (may be degenerate); polygon : (N, 2).
    """
    rect = np.array([[lo[0], lo[1]], [hi[0], lo[1]], [hi[0], hi[1]], [lo[0], hi[1]]])
    if points_in_polygon(rect, polygon).any():
        return 0.0
    if np.all((polygon >= lo) & (polygon <= hi), axis=1).any():
        return 0.0
    best = math.inf
    for i in range(4):
        a, b = rect[i], rect[(i + 1) % 4]
        for j in range(len(polygon)):
            c, d = polygon[j], polygon[(j + 1) % len(polygon)]
            if _segments_cross(a, b, c, d):
                return 0.0
            best = min(
                best,
                _point_segment_distance(a, c, d),
                _point_segment_distance(b, c, d),
                _point_segment_distance(c, a, b),
                _point_segment_distance(d, a, b),
            )
    return best


def opening_from_points(kind: OpeningKind, points: np.ndarray, opening_id: str | None) -> Opening:
    """A door or window from its mesh vertices in our world: points (N, 3).

    The segment runs along the longer side of the xy bounding box, through its middle.
    """
    lo, hi = points[:, :2].min(0), points[:, :2].max(0)
    mid = (lo + hi) / 2
    if hi[0] - lo[0] >= hi[1] - lo[1]:
        p0, p1 = (lo[0], mid[1]), (hi[0], mid[1])
    else:
        p0, p1 = (mid[0], lo[1]), (mid[0], hi[1])
    return Opening(
        kind=kind,
        p0=(float(p0[0]), float(p0[1])),
        p1=(float(p1[0]), float(p1[1])),
        z_min=float(points[:, 2].min()),
        z_max=float(points[:, 2].max()),
        id=opening_id,
    )


def on_outline(opening: Opening, points: np.ndarray, polygon: np.ndarray) -> Opening | None:
    """``opening`` laid on the edge of the floor ``polygon`` that its mesh ``points``
    (N, 3) run along: the edge within :attr:`~Front3DTolerances.opening_angle_deg` of the
    opening's direction, overlapping it, whose line its nearest point lies closest to (a
    door stands in the wall, its inner face on the floor's edge; a bay window bulges out
    from it); its ends the points' extent along that edge. None when it runs along no edge within
    :attr:`~Front3DTolerances.opening_touch`."""
    d = np.subtract(opening.p1, opening.p0)
    d = d / max(float(np.hypot(*d)), 1e-12)
    cos_max = math.cos(math.radians(TOL.opening_angle_deg))
    best, best_off = None, TOL.opening_touch
    for a, b in zip(polygon, np.roll(polygon, -1, axis=0), strict=True):
        u = b - a
        length = float(np.hypot(*u))
        if length < TOL.min_opening_width or abs(float(u @ d)) / length < cos_max:
            continue
        u = u / length
        rel = points[:, :2] - a
        along = rel @ u
        off = float(np.abs(rel[:, 0] * u[1] - rel[:, 1] * u[0]).min())  # its inner face
        lo, hi = max(float(along.min()), 0.0), min(float(along.max()), length)
        if hi - lo < TOL.min_opening_width or off >= best_off:
            continue
        best, best_off = (a + u * lo, a + u * hi), off
    if best is None:
        return None
    p0, p1 = best
    return Opening(opening.kind, (float(p0[0]), float(p0[1])), (float(p1[0]), float(p1[1])),
                   opening.z_min, opening.z_max, opening.id)  # fmt: skip


def _box_gap(lo_a: np.ndarray, hi_a: np.ndarray, lo_b: np.ndarray, hi_b: np.ndarray) -> float:
    """Largest per-axis gap between two axis-aligned boxes (0 or less: they touch)."""
    return float(np.max(np.maximum(lo_a - hi_b, lo_b - hi_a)))


def openings_of(
    pieces: list[tuple[OpeningKind, str, np.ndarray]],
    polygon: np.ndarray,
    warnings: Counter[str],
) -> tuple[list[Opening], list[Opening]]:
    """(doors, windows) of a room from its door and window mesh ``pieces`` (kind, uid,
    points (N, 3) above the room's floor): the pieces that touch the floor ``polygon``
    (:attr:`~Front3DTolerances.opening_touch`), grouped into one opening per physical
    door or window (:attr:`~Front3DTolerances.opening_join`), each laid on its wall
    (:func:`on_outline`) with the height of all its pieces. A group lower than
    :attr:`~Front3DTolerances.min_opening_height` or narrower than
    :attr:`~Front3DTolerances.min_opening_width` is counted in ``warnings`` and left out."""
    near = [(kind, uid, points, points.min(0), points.max(0)) for kind, uid, points in pieces]
    parent = list(range(len(near)))

    def root(i: int) -> int:
        while parent[i] != i:
            parent[i] = parent[parent[i]]
            i = parent[i]
        return i

    for i, (kind_i, _, _, lo_i, hi_i) in enumerate(near):
        for j in range(i):
            kind_j, _, _, lo_j, hi_j = near[j]
            if kind_i == kind_j and _box_gap(lo_i, hi_i, lo_j, hi_j) <= TOL.opening_join:
                parent[root(i)] = root(j)
    groups: dict[int, list[int]] = {}
    for i in range(len(near)):
        groups.setdefault(root(i), []).append(i)
    doors, windows = [], []
    for members in groups.values():
        kind = near[members[0]][0]
        points = np.concatenate([near[i][2] for i in members])
        uid = min(near[i][1] for i in members)
        lo, hi = points[:, :2].min(0), points[:, :2].max(0)
        if rect_polygon_distance(lo, hi, polygon) > TOL.opening_touch:
            continue  # another room's (a bay window's far panes count with the rest)
        if float(np.ptp(points[:, 2])) < TOL.min_opening_height:
            warnings[W_FLAT_OPENING] += 1
            continue
        opening = opening_from_points(kind, points, uid)
        laid = on_outline(opening, points, polygon)
        if laid is None:
            warnings[W_OFF_WALL_OPENING] += 1
        else:
            opening = laid
        if opening.width < TOL.min_opening_width:
            warnings[W_BAD_OPENING] += 1
            continue
        (doors if kind == "door" else windows).append(opening)
    doors.sort(key=lambda o: o.id or "")
    windows.sort(key=lambda o: o.id or "")
    return doors, windows


def _opening_kind(mesh_type: str) -> OpeningKind | None:
    t = mesh_type.lower()
    if "door" in t:
        return "door"
    if "window" in t:
        return "window"
    return None


# -- reading files -------------------------------------------------------------------
@dataclass(frozen=True)
class _Mesh:
    uid: str
    type: str
    points: np.ndarray
    """(N, 3) vertices in our world frame (z up), not yet shifted to the floor."""
    faces: np.ndarray
    """(F, 3) int vertex indices."""


def _one_line(exc: BaseException) -> str:
    return " ".join(str(exc).split())


def _read_json(file: Path, what: str) -> Any:
    """A house file or model_info.json, read within :func:`read_json_file`'s bounds (a
    3D-FRONT house runs to tens of MB: the statistics' size limit); values are checked
    field by field later, so non-finite numbers are not refused here."""
    try:
        return read_json_file(file, what, MAX_STATS_BYTES, finite=False)
    except JsonFileError as e:
        if e.missing:
            raise UserError(f"{file}: cannot read: {e.problem}") from None
        raise UserError(f"{file}: not valid {what}: {e.problem}") from None


def find_model_info(path: Path) -> Path | None:
    """``model_info.json`` for a house file or folder: in the folder (or the file's
    folder), else in ``3D-FUTURE-model/`` beside that folder; None when absent."""
    base = path if path.is_dir() else path.parent
    for candidate in (base / MODEL_INFO, base.parent / FUTURE_FOLDER / MODEL_INFO):
        if candidate.is_file():
            return candidate
    return None


def future_models(path: Path, info_file: Path | None) -> Path | None:
    """3D-FUTURE's model folder (one ``<jid>/`` folder per model) for a house file or
    folder: the folder of ``model_info.json``, else ``3D-FUTURE-model/`` beside the
    houses' folder; None when neither exists."""
    base = path if path.is_dir() else path.parent
    for folder in (None if info_file is None else info_file.parent, base.parent / FUTURE_FOLDER):
        if folder is not None and folder.is_dir():
            return folder
    return None


def load_model_info(file: Path) -> dict[str, dict]:
    """``model_info.json`` -> {model_id: entry}: 3D-FUTURE's list of entries (each with
    its ``model_id``), or the 3D-FRONT toolbox's mapping of model ids to a category name
    (or to an entry)."""
    data = _read_json(file, "3D-FUTURE model_info.json")
    if isinstance(data, dict):
        out: dict[str, dict] = {}
        for model_id, value in data.items():
            if value is None or isinstance(value, str):  # (null: no category known)
                value = {"category": value}
            if not isinstance(value, dict):
                raise UserError(
                    f"{file}: not valid model_info.json: model {model_id!r} maps to "
                    f"{type(value).__name__}, expected a category name or an object"
                )
            out[str(model_id)] = {**value, "model_id": str(model_id)}
        return out
    if not isinstance(data, list) or not all(isinstance(e, dict) for e in data):
        raise UserError(
            f"{file}: not valid 3D-FUTURE model_info.json: expected a list of objects "
            "(3D-FUTURE) or an object of model id -> category (3D-FRONT toolbox)"
        )
    return {str(e["model_id"]): e for e in data if e.get("model_id") is not None}


def _house_files(path: Path) -> list[Path]:
    if path.is_file():
        return [path]
    if path.is_dir():
        files = sorted(p for p in path.glob("*.json") if p.name != MODEL_INFO and p.is_file())
        if not files:
            raise UserError(f"{path}: no 3D-FRONT house JSON files in this folder")
        return files
    raise UserError(f"{path}: no such file or folder")


def _vector(value: Any, n: int, default: Sequence[float] | None) -> np.ndarray | None:
    """A finite float vector of length n, the default when absent, None when malformed."""
    if value is None:
        return None if default is None else np.asarray(default, dtype=float)
    try:
        v = np.asarray(value, dtype=float).reshape(-1)
    except (TypeError, ValueError):
        return None
    return v if v.shape == (n,) and _sane(v) else None


def _sane(values: np.ndarray) -> bool:
    """Finite and within :attr:`Front3DTolerances.max_coordinate`."""
    return bool(np.all(np.isfinite(values)) and np.all(np.abs(values) <= TOL.max_coordinate))


def _field_extent(entry: dict) -> tuple[np.ndarray, str] | None:
    """A furniture entry's extent as its file gives it, and the field: ``size`` (3
    floats: width, depth, height), else ``bbox`` (3 floats, maybe nested, or min and max
    corners)."""
    for key in ("size", "bbox"):
        value = entry.get(key)
        if value is None:
            continue
        try:
            v = np.asarray(value, dtype=float).reshape(-1)
        except (TypeError, ValueError):
            continue
        if v.shape == (6,):
            v = v[3:] - v[:3]
        if v.shape == (3,) and _sane(v) and np.all(np.abs(v) > 0):
            return np.abs(v), key
    return None


def read_obj_extent(file: Path) -> np.ndarray | None:
    """(3,) extent of the vertices (``v`` lines) of an OBJ file; None when it has none or
    cannot be read."""
    try:
        with file.open(encoding="utf-8", errors="replace") as f:
            rows = [line.split()[1:4] for line in f if line.startswith("v ")]
        v = np.asarray(rows, dtype=float)
    except (OSError, ValueError):
        return None
    if v.ndim != 2 or v.shape[1] != 3 or not len(v) or not _sane(v):
        return None
    return v.max(0) - v.min(0)


MESH_FILE = "raw_model.obj"
"""A 3D-FUTURE model's mesh, in its own y-up axes and metres: ``<jid>/raw_model.obj``."""
MESH_AGREE = 0.1
"""Relative difference per axis within which a file's extent agrees with its mesh's."""


def _parse_mesh(entry: dict) -> _Mesh | None:
    """A mesh entry in our world frame, or None when its arrays are malformed."""
    try:
        xyz = np.asarray(entry.get("xyz", []), dtype=float)
        idx = np.asarray(entry.get("faces", []), dtype=float)
    except (TypeError, ValueError):
        return None
    if xyz.ndim != 1 or xyz.size == 0 or xyz.size % 3 or not _sane(xyz):
        return None
    if idx.ndim != 1 or idx.size % 3 or not np.all(np.isfinite(idx)):
        return None
    points = front_points_to_world(xyz.reshape(-1, 3))
    if np.any(idx != np.round(idx)) or (idx.size and (idx.min() < 0 or idx.max() >= len(points))):
        return None
    faces = idx.astype(np.int64).reshape(-1, 3)
    return _Mesh(str(entry.get("uid")), str(entry.get("type", "")), points, faces)


GENERIC_LAMPS = ("lighting",)
"""Labels that say only "a lamp" (3D-FUTURE's super-category): which lamp it is follows
from where it is (:func:`lamp_by_height`)."""
FLOOR_LAMP_MAX_M = 0.15
"""A lamp whose bottom is this close to the floor stands on it: a floor lamp..."""
CEILING_LAMP_MIN_M = 1.6
"""... one whose bottom is this high hangs from the ceiling; between, it stands on
furniture: a table lamp."""


def lamp_by_height(bottom: float) -> str:
    """The lamp category of a generic lamp whose box bottom is at ``bottom`` (m above the
    floor)."""
    if bottom < FLOOR_LAMP_MAX_M:
        return "floor_lamp"
    return "ceiling_lamp" if bottom >= CEILING_LAMP_MIN_M else "table_lamp"


def _choose_label(candidates: Iterable[Any], probe: LabelMapper) -> str | None:
    """The first candidate the 3D-FUTURE table maps, else the first non-empty one."""
    present = [c.strip() for c in candidates if isinstance(c, str) and c.strip()]
    for label in present:
        if probe(label) != UNKNOWN:
            return label
    return present[0] if present else None


# -- houses -> scenes ----------------------------------------------------------------
@dataclass
class _Context:
    """Everything one load shares across houses (mutable counters live here)."""

    model_info: dict[str, dict] | None
    mapper: LabelMapper
    probe: LabelMapper
    """Same table, counters ignored: trying fallback labels must not count them."""
    report: SourceReport
    models: Path | None = None
    """3D-FUTURE's model folder (``<jid>/raw_model.obj``), when found."""
    mesh_extents: dict[str, np.ndarray | None] = field(default_factory=dict)


def _require(cond: bool, file: Path, problem: str) -> None:
    if not cond:
        raise UserError(f"{file}: not valid 3D-FRONT JSON: {problem}")


def _house_scenes(data: Any, file: Path, ctx: _Context) -> list[Scene]:
    _require(isinstance(data, dict), file, "expected an object at the top level")
    scene_data = data.get("scene")
    _require(isinstance(scene_data, dict), file, "missing 'scene' object")
    rooms = scene_data.get("room")
    _require(isinstance(rooms, list), file, "missing 'scene.room' list")
    furniture_list = data.get("furniture", [])
    mesh_list = data.get("mesh", [])
    _require(isinstance(furniture_list, list), file, "'furniture' is not a list")
    _require(isinstance(mesh_list, list), file, "'mesh' is not a list")
    _require(all(isinstance(r, dict) for r in rooms), file, "a 'scene.room' entry is not an object")
    _require(
        all(
            isinstance(r.get("children") or [], list)
            and all(isinstance(c, dict) for c in r.get("children") or [])
            for r in rooms
        ),
        file,
        "a room's 'children' is not a list of objects",
    )
    _require(
        all(isinstance(e, dict) for e in furniture_list + mesh_list),
        file,
        "a 'furniture' or 'mesh' entry is not an object",
    )

    house = str(data.get("uid") or file.stem)
    furniture = {str(e.get("uid")): e for e in furniture_list}
    meshes: dict[str, _Mesh] = {}
    for entry in mesh_list:
        mesh = _parse_mesh(entry)
        if mesh is None:
            ctx.report.warnings[W_BAD_MESH] += 1
        else:
            meshes[mesh.uid] = mesh

    # Door/window meshes no room references still open into the rooms they touch.
    referenced = {str(c.get("ref")) for r in rooms for c in r.get("children") or []}
    orphan_openings = [
        m for uid, m in meshes.items() if uid not in referenced and _opening_kind(m.type)
    ]
    house_doors = [m for m in meshes.values() if _opening_kind(m.type) == "door"]

    scenes, seen_ids = [], Counter()
    for index, room in enumerate(rooms):
        instance = room.get("instanceid")
        if not instance:
            ctx.report.warnings[W_NO_ROOM_ID] += 1
            instance = f"room-{index}"
        instance = str(instance)
        seen_ids[instance] += 1
        if seen_ids[instance] > 1:
            ctx.report.warnings[W_DUPLICATE_ROOM] += 1
            instance = f"{instance}#{seen_ids[instance] - 1}"
        scene = _room_scene(room, f"{house}/{instance}", furniture, meshes, orphan_openings,
                            house_doors, ctx)  # fmt: skip
        if scene is not None:
            scene.stats.update({"house": house, "room_instance": instance})
            scenes.append(scene)
    return scenes


def _room_scene(
    room: dict,
    scene_id: str,
    furniture: dict[str, dict],
    meshes: dict[str, _Mesh],
    orphan_openings: list[_Mesh],
    house_doors: list[_Mesh],
    ctx: _Context,
) -> Scene | None:
    warnings = ctx.report.warnings
    children = room.get("children") or []
    placed: list[tuple[dict, dict]] = []  # (child, furniture entry)
    room_meshes: list[_Mesh] = []
    for child in children:
        ref = str(child.get("ref"))
        if ref in furniture:
            placed.append((child, furniture[ref]))
        elif ref in meshes:
            room_meshes.append(meshes[ref])
        else:
            warnings[W_UNKNOWN_REF] += 1
    if not placed:
        warnings[W_NO_FURNITURE] += 1
        return None

    floors = [m for m in room_meshes if m.type.lower() == "floor"]
    floor_z = min(float(m.points[:, 2].min()) for m in floors) if floors else 0.0
    shift = np.array([0.0, 0.0, floor_z])

    objects, skipped = _room_objects(placed, shift, ctx)
    if not objects:
        warnings[W_NO_FURNITURE] += 1
        return None

    polygon = None
    if floors:
        tris = np.concatenate([m.points[m.faces][:, :, :2] for m in floors])  # (T, 3, 2)
        polygon = floor_outline(tris)
        if polygon is None:
            warnings[W_BAD_FLOOR] += 1
    else:
        warnings[W_NO_FLOOR] += 1
    if polygon is None:
        polygon = _furniture_bounds(objects)
    else:
        centers = np.array([o.box.center[:2] for o in objects])
        if points_in_polygon(centers, polygon).mean() < MIN_INSIDE_SHARE:
            warnings[W_OUTSIDE_FLOOR] += 1

    walls = [m for m in room_meshes if m.type.lower() == "wallinner"]
    height = max((float(m.points[:, 2].max()) - floor_z for m in walls), default=0.0)
    if height <= 0:
        height = DEFAULT_ROOM_HEIGHT

    # A door joins two rooms but is listed under one: every door of the house that
    # touches this room opens into it. Windows: this room's and those no room lists.
    candidates = {m.uid: m for m in room_meshes + orphan_openings if _opening_kind(m.type)}
    candidates.update({m.uid: m for m in house_doors})
    pieces = [
        (_opening_kind(m.type), uid, m.points - shift) for uid, m in sorted(candidates.items())
    ]
    doors, windows = openings_of(pieces, polygon, warnings)  # type: ignore[arg-type]

    source_type = str(room.get("type") or "")
    room_type = FRONT3D_ROOM_TYPES.get(source_type.lower())
    if room_type is None:
        warnings[_unmapped_room(source_type or "<missing>")] += 1
        room_type = RoomType.OTHER

    split = "val" if stable_fraction(scene_id) < VAL_FRACTION else "train"
    return Scene(
        id=scene_id,
        room=Room(room_type.value, polygon, height, tuple(doors), tuple(windows)),
        objects=objects,
        source=SOURCE,
        split=split,
        stats={"source_room_type": source_type, "objects_skipped": skipped},
    )


def _room_objects(
    placed: list[tuple[dict, dict]], shift: np.ndarray, ctx: _Context
) -> tuple[list[SceneObject], int]:
    """Scene objects of a room's furniture children, and how many were skipped."""
    warnings = ctx.report.warnings
    objects: list[SceneObject] = []
    per_category: Counter[str] = Counter()
    skipped = 0
    for child, entry in placed:
        jid = entry.get("jid")
        info: dict = {}
        if ctx.model_info is not None:
            found = ctx.model_info.get(str(jid))
            if found is None:
                warnings[W_MISSING_INFO] += 1
            else:
                info = found
        label = _choose_label(
            (
                info.get("category"),
                entry.get("category"),
                entry.get("title"),
                info.get("super-category"),
            ),
            ctx.probe,
        )
        size = _model_extent(entry, info, None if jid is None else str(jid), ctx)
        if size is None:
            warnings[W_NO_SIZE] += 1
            skipped += 1
            continue
        pos = _vector(child.get("pos"), 3, (0.0, 0.0, 0.0))
        rot = _vector(child.get("rot"), 4, (0.0, 0.0, 0.0, 1.0))
        scale = _vector(child.get("scale"), 3, (1.0, 1.0, 1.0))
        try:
            if pos is None or rot is None or scale is None or not np.all(scale != 0):
                raise ValueError("malformed transform")
            box = future_box(size, pos, rot, scale)
        except ValueError:
            warnings[W_BAD_TRANSFORM] += 1
            skipped += 1
            continue
        if np.any(scale < 0):
            warnings[W_MIRRORED] += 1
        category = ctx.mapper(label)
        if label is not None and label.lower() in GENERIC_LAMPS:
            category = lamp_by_height(box.bottom - float(shift[2]))  # above the floor
        objects.append(
            SceneObject(
                id=f"{category}_{per_category[category]}",
                category=category,
                box=OrientedBox(box.center - shift, box.size, box.rotation),
                asset=AssetRef(ASSET_SOURCE, None if jid is None else str(jid)),
                support=None,
                source_label=label,
                source_support=None,
            )
        )
        per_category[category] += 1
    return objects, skipped


def info_extent(info: dict) -> np.ndarray | None:
    """(3,) a model's extent along its own x, y (up), z (front) from a model_info entry's
    ``boundingBox`` (the 3D-FRONT toolbox's: ``xLen``, ``yLen``, ``zLen`` in cm, width,
    depth, height); None without a sane one."""
    box = info.get("boundingBox")
    if not isinstance(box, dict):
        return None
    try:
        v = np.array([float(box[k]) for k in ("xLen", "zLen", "yLen")]) / 100.0
    except (KeyError, TypeError, ValueError):
        return None
    return v if _sane(v) and np.all(v > 0) else None


def _model_extent(entry: dict, info: dict, jid: str | None, ctx: _Context) -> np.ndarray | None:
    """(3,) a furniture model's extent along its own x, y (up), z (front): its 3D-FUTURE
    mesh's when the model folder has it (:data:`MESH_FILE`), else its model_info
    bounding box (:func:`info_extent`), else the file's: ``size`` is [width, depth,
    height] (z up; a ``bbox`` beside it repeats it), a ``bbox`` on its own is in the
    model's y-up axes. A file extent that disagrees with the mesh is counted."""
    field = _field_extent(entry)
    extent = info_extent(info)
    if extent is None and field is not None:
        value, key = field
        extent = value[[0, 2, 1]] if key == "size" else value
    mesh = _mesh_extent(jid, ctx)
    if mesh is None:
        return extent
    if extent is not None and np.any(np.abs(extent - mesh) > MESH_AGREE * mesh + 1e-3):
        ctx.report.warnings[W_SIZE_MESH] += 1
    return mesh


def _mesh_extent(jid: str | None, ctx: _Context) -> np.ndarray | None:
    if jid is None or ctx.models is None:
        return None
    if jid not in ctx.mesh_extents:
        file = ctx.models / jid / MESH_FILE
        ctx.mesh_extents[jid] = read_obj_extent(file) if file.is_file() else None
    return ctx.mesh_extents[jid]


def _furniture_bounds(objects: list[SceneObject]) -> np.ndarray:
    """(4, 2) counter-clockwise rectangle: the objects' xy bounds grown by the margin."""
    lows, highs = zip(*(o.box.aabb() for o in objects), strict=True)
    lo = np.min(lows, axis=0)[:2] - TOL.fallback_margin
    hi = np.max(highs, axis=0)[:2] + TOL.fallback_margin
    return np.array([[lo[0], lo[1]], [hi[0], lo[1]], [hi[0], hi[1]], [lo[0], hi[1]]])


# -- public entry point --------------------------------------------------------------
def load_front3d(path: str | Path, split: str | None = None, progress: bool = False) -> Corpus:
    """Read 3D-FRONT houses into a corpus: one scene per room with furniture.

    ``path`` is a house JSON file or a folder of them. ``model_info.json`` is looked
    up in the folder (or the file's folder), then in ``../3D-FUTURE-model/``;
    without it, categories come from the house files' own labels (usually none, so
    ``unknown``) and a warning is counted. ``split`` keeps only ``train`` or ``val``
    rooms (fixed by a hash of the scene id). Nothing is dropped silently: skipped
    rooms and objects, unmapped labels and room types are counted in the report.

    Raises UserError for a missing path or a malformed JSON file (one line).
    """
    if split is not None and split not in SPLITS:
        raise UserError(f"unknown split {split!r}: expected one of {', '.join(SPLITS)}")
    root = Path(path)
    files = _house_files(root)
    report = SourceReport()
    info_file = find_model_info(root)
    model_info = None
    if info_file is None:
        report.warnings[W_NO_MODEL_INFO] += 1
    else:
        model_info = load_model_info(info_file)
    mapper = LabelMapper(FUTURE3D_LABELS, case_insensitive=True)
    probe = LabelMapper(FUTURE3D_LABELS, case_insensitive=True)
    ctx = _Context(model_info, mapper, probe, report, future_models(root, info_file))

    scenes: list[Scene] = []
    for file in track(files, "3D-FRONT houses", enabled=progress):
        data = _read_json(file, "3D-FRONT JSON")
        try:
            house_scenes = _house_scenes(data, file, ctx)
        except (TypeError, ValueError, AttributeError) as exc:
            # Values of the wrong type deep inside an entry (a dict where a number goes).
            raise UserError(f"{file}: not valid 3D-FRONT JSON: {_one_line(exc)}") from None
        scenes.extend(s for s in house_scenes if split is None or s.split == split)
    # 3D-FRONT annotates no support: objects standing on the floor get it by height.
    for scene in scenes:
        scene.objects = floor_by_height(scene.objects, report)
    report.unknown_labels.update(mapper.unknown)
    report.mapped_labels.update(mapper.mapped)
    return Corpus(SOURCE, scenes, report)

"""The asset library: one place to ask for "a chair of this size".

Three sources, asked in this order:

- **user meshes**: a folder with an ``assets.json`` mapping, e.g.
  ``[{"file": "chair_a.obj", "category": "chair", "up": "+y", "front": "+z",
  "scale": 0.01}]`` (a list, or ``{"assets": [...]}``). ``file`` is relative to the
  folder (OBJ, GLB/glTF, PLY, STL or OFF); ``category`` a canonical category;
  ``up`` and ``front`` the model's up and front axes ("+x", "-x", "+y", "-y", "+z",
  "-z"; defaults "+z" and "+y"); ``scale`` metres per model unit (default 1).
  glTF files are y-up by specification: give them ``"up": "+y"``.
- **3D-FUTURE**: ``<root>/model_info.json`` and ``<root>/<model_id>/raw_model.obj``
  (or ``normalized_model.obj``); categories mapped with
  :data:`pair2scene.categories.FUTURE3D_LABELS`; models are y-up, front +z, metres.
- **procedural generators** (default :func:`pair2scene.assets.registry.generate`): for
  every category without a mesh candidate.

User and 3D-FUTURE candidates of a category compete on fit: the one whose extent is
closest to the requested size (least ``sum |log(size_i / extent_i)|``) wins, near ties
broken by the rng for variety; it is then scaled per axis to fill the requested box.

A mesh asset's ``parts`` are the convex hulls of the mesh's connected components
(approximate; ``asset.extra["parts"]`` says so), which physics and support surfaces
use; ``asset.extra["render_mesh"]`` is the original mesh (a :class:`Mesh`) in the same
local frame, for rendering, export and point clouds; ``asset.extra["file"]`` is the
source file.

Nothing is read until first needed. Loaded meshes are kept in a small LRU; each model's
raw bounds (needed to rank candidates) are also kept in a JSON file under the cache
folder, so a large 3D-FUTURE folder is scanned once.
"""

from __future__ import annotations

import contextlib
import json
import math
from collections import OrderedDict
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from pair2scene.assets.mesh import Asset, Mesh, Part
from pair2scene.assets.registry import MIN_SIZE_M, fallback_box, generate
from pair2scene.categories import BY_NAME, FUTURE3D_LABELS, UNKNOWN, LabelMapper
from pair2scene.errors import UserError
from pair2scene.io.atomic import atomic_write_text
from pair2scene.paths import cache_dir

MAPPING_FILE = "assets.json"
FUTURE_INFO_FILE = "model_info.json"
FUTURE_MODEL_FILES = ("raw_model.obj", "normalized_model.obj")
"""Per 3D-FUTURE model, in order of preference: raw models keep their real size."""
MESH_SUFFIXES = (".obj", ".glb", ".gltf", ".ply", ".stl", ".off")
PARTS_NOTE = "convex hulls of components"
FIT_TIE = 0.1
"""Candidates within this of the best fit cost (about 3% per axis) are equally good; the
rng picks among them."""
MAX_PARTS = 64
"""Convex parts per mesh asset: enough for furniture, few enough for fast physics."""
KEEP_PARTS = 48
"""Beyond MAX_PARTS, the KEEP_PARTS largest components keep their own hull; the rest
share one hull per cell of a coarse grid over the asset (GROUP_GRID cells)."""
GROUP_GRID = (2, 2, 4)
"""x, y, z cells of that grid: at most 16 grouped hulls, split most along the height."""
MIN_PART_THICKNESS_M = 0.001
"""A flat component (a table top modelled as one quad) is given this thickness."""
WELD_REL = 1e-6
"""Vertices closer than this fraction of the bounding-box diagonal are one vertex."""
MESH_CACHE_ENTRIES = 32
"""Loaded meshes kept in memory."""

_AXES = {
    "+x": (1, 0, 0),
    "-x": (-1, 0, 0),
    "+y": (0, 1, 0),
    "-y": (0, -1, 0),
    "+z": (0, 0, 1),
    "-z": (0, 0, -1),
}
_ENTRY_KEYS = {"file", "category", "up", "front", "scale"}


def axis_rotation(up: str = "+z", front: str = "+y") -> np.ndarray:
    """(3, 3) rotation taking a model whose up and front are the given axes to the local
    frame (+z up, +y front): ``local = R @ model``."""
    u, f = np.array(_AXES[up], dtype=float), np.array(_AXES[front], dtype=float)
    if abs(u @ f) > 0:
        raise ValueError(f"up {up} and front {front} must be perpendicular")
    return np.stack([np.cross(f, u), f, u])  # rows: the model's right, front and up


@dataclass(frozen=True, eq=False)
class MeshEntry:
    """One mesh the library can serve."""

    source: str
    """``user`` or ``3dfuture``."""
    asset_id: str
    """The file name relative to the user folder, or the 3D-FUTURE model id."""
    category: str
    path: Path
    rotation: np.ndarray
    """(3, 3) model frame -> local frame."""
    scale: float
    """Metres per model unit."""


@dataclass(frozen=True, eq=False)
class LoadedMesh:
    """A mesh in the local frame, centred on its parts' bounds, in metres."""

    parts: tuple[Mesh, ...]
    """Convex hulls of the components."""
    render: Mesh
    """The whole original mesh."""
    extent: np.ndarray
    """(3,) size of the parts' bounds."""


class AssetLibrary:
    """Assets by category and size from user meshes, 3D-FUTURE and the generators.

    procedural : serve categories without a mesh candidate from ``generator``; if False
        they get a labelled box. user_dir : a folder with an ``assets.json`` (see the
        module docstring). future_dir : a 3D-FUTURE model folder. generator : the
        procedural generator, ``fn(category, size, rng) -> Asset``. bounds_cache : the
        JSON file keeping model bounds (default ``cache_dir()/asset_library/bounds.json``).
    """

    def __init__(
        self,
        procedural: bool = True,
        user_dir: Path | str | None = None,
        future_dir: Path | str | None = None,
        generator: Callable[..., Asset] = generate,
        bounds_cache: Path | str | None = None,
    ) -> None:
        self.procedural = procedural
        self.user_dir = Path(user_dir) if user_dir is not None else None
        self.future_dir = Path(future_dir) if future_dir is not None else None
        self.generator = generator
        self.bounds_cache = (
            Path(bounds_cache)
            if bounds_cache is not None
            else cache_dir() / "asset_library" / "bounds.json"
        )
        self.future_labels = LabelMapper(dict(FUTURE3D_LABELS), case_insensitive=True)
        """Counts the 3D-FUTURE labels mapped and those left unknown (skipped)."""
        self._entries: dict[str, list[MeshEntry]] | None = None
        self._bounds: dict[str, list] | None = None
        self._bounds_dirty = False
        self._meshes: OrderedDict[int, LoadedMesh] = OrderedDict()

    # -- catalogue --------------------------------------------------------------------
    def entries(self, category: str | None = None) -> list[MeshEntry]:
        """The mesh candidates of ``category`` (all of them if None)."""
        if self._entries is None:
            found: list[MeshEntry] = []
            if self.user_dir is not None:
                found += _read_user_mapping(self.user_dir)
            if self.future_dir is not None:
                found += _read_future_info(self.future_dir, self.future_labels)
            self._entries = {}
            for e in found:
                self._entries.setdefault(e.category, []).append(e)
        if category is None:
            return [e for es in self._entries.values() for e in es]
        return list(self._entries.get(category, []))

    def mesh_categories(self) -> set[str]:
        """Categories with at least one mesh candidate."""
        self.entries()
        return set(self._entries or {})

    # -- retrieval --------------------------------------------------------------------
    def retrieve(
        self, category: str, size: Sequence[float], rng: np.random.Generator | int | None = None
    ) -> Asset:
        """An asset of ``category`` filling a box of ``size`` (3,) metres.

        rng : a Generator or a seed (None: seed 0); breaks near ties between mesh
        candidates, and drives the procedural generator.
        """
        size = np.asarray(size, dtype=float).reshape(-1)
        if size.shape != (3,) or not np.all(np.isfinite(size)) or np.any(size <= 0):
            raise UserError(f"asset size must be three positive numbers, got {size.tolist()}")
        size = np.maximum(size, MIN_SIZE_M)
        if category != UNKNOWN and category not in BY_NAME:
            raise UserError(f"unknown category {category!r}")
        rng = (
            rng
            if isinstance(rng, np.random.Generator)
            else np.random.default_rng(0 if rng is None else rng)
        )
        candidates = self.entries(category)
        if not candidates:
            if self.procedural:
                return self.generator(category, size, rng)
            return fallback_box(category, size)
        entry = self.closest(candidates, size, rng)
        return self._fit(entry, size)

    def closest(
        self, candidates: Sequence[MeshEntry], size: np.ndarray, rng: np.random.Generator
    ) -> MeshEntry:
        """The candidate whose extent fits ``size`` (3,) best; near ties drawn by ``rng``."""
        extents = np.array([self.extent(e) for e in candidates])  # (C, 3)
        self.save_bounds()
        cost = np.abs(np.log(size / extents)).sum(1)
        ties = np.flatnonzero(cost <= cost.min() + FIT_TIE)
        ties = sorted(ties, key=lambda i: (cost[i], candidates[i].asset_id))
        return candidates[ties[int(rng.integers(len(ties)))] if len(ties) > 1 else ties[0]]

    def extent(self, entry: MeshEntry) -> np.ndarray:
        """(3,) the entry's size in metres in the local frame (from its raw bounds)."""
        lo, hi = self._raw_bounds(entry)
        ext = np.abs(entry.rotation @ (hi - lo)) * entry.scale
        return np.maximum(ext, MIN_SIZE_M)

    def load(self, entry: MeshEntry) -> LoadedMesh:
        """The entry's mesh in the local frame with its convex parts (cached)."""
        key = id(entry)
        found = self._meshes.get(key)
        if found is not None:
            self._meshes.move_to_end(key)
            return found
        v, f = _read_mesh(entry.path)
        v = v @ entry.rotation.T * entry.scale
        parts = _convex_parts(Mesh(v, f))
        if not parts:
            raise UserError(f"{entry.path}: the mesh has no solid component")
        lo, hi = Mesh.concat(list(parts)).bounds
        centre = (lo + hi) / 2
        loaded = LoadedMesh(
            tuple(p.transformed(translation=-centre) for p in parts),
            Mesh(v - centre, f),
            np.maximum(hi - lo, MIN_SIZE_M),
        )
        self._meshes[key] = loaded
        while len(self._meshes) > MESH_CACHE_ENTRIES:
            self._meshes.popitem(last=False)
        return loaded

    def _fit(self, entry: MeshEntry, size: np.ndarray) -> Asset:
        loaded = self.load(entry)
        s = size / loaded.extent
        parts = tuple(Part(f"component_{i:02d}", m.scaled(s)) for i, m in enumerate(loaded.parts))
        extra = {
            "parts": PARTS_NOTE,
            "render_mesh": loaded.render.scaled(s),
            "file": str(entry.path),
        }
        return Asset(
            entry.category,
            size.copy(),
            parts,
            style=0,
            source=entry.source,
            asset_id=entry.asset_id,
            extra=extra,
        )

    # -- the bounds cache ---------------------------------------------------------------
    def _raw_bounds(self, entry: MeshEntry) -> tuple[np.ndarray, np.ndarray]:
        """(3,) min and (3,) max of the entry's vertices in model units."""
        if self._bounds is None:
            self._bounds = _read_bounds_cache(self.bounds_cache)
        path = str(entry.path.resolve())
        try:
            st = entry.path.stat()
        except OSError as exc:
            raise UserError(f"{entry.path}: cannot read: {exc.strerror}") from None
        stamp = [st.st_mtime_ns, st.st_size]
        rec = self._bounds.get(path)
        if rec is not None and rec[:2] == stamp:
            b = np.asarray(rec[2:], dtype=float).reshape(2, 3)
            return b[0], b[1]
        v, _ = _read_mesh(entry.path)
        lo, hi = v.min(0), v.max(0)
        self._bounds[path] = stamp + lo.tolist() + hi.tolist()
        self._bounds_dirty = True
        return lo, hi

    def save_bounds(self) -> None:
        """Write newly read model bounds to ``bounds_cache`` (once per batch, not per model;
        a read-only cache only costs speed)."""
        if self._bounds_dirty and self._bounds is not None:
            with contextlib.suppress(OSError):
                atomic_write_text(self.bounds_cache, json.dumps(self._bounds))
            self._bounds_dirty = False


# -- reading the sources ---------------------------------------------------------------
def _read_json(path: Path, what: str):
    if not path.is_file():
        raise UserError(f"{path}: missing ({what})")
    try:
        return json.loads(path.read_text(encoding="utf-8"))
    except json.JSONDecodeError as exc:
        raise UserError(f"{path}: not valid JSON: line {exc.lineno}: {exc.msg}") from None
    except (OSError, UnicodeDecodeError) as exc:
        raise UserError(f"{path}: cannot read: {exc}") from None


def _read_user_mapping(folder: Path) -> list[MeshEntry]:
    """The entries of a user folder's ``assets.json``; UserError naming the problem."""
    if not folder.is_dir():
        raise UserError(f"{folder}: not a folder (user assets)")
    mapping = folder / MAPPING_FILE
    data = _read_json(mapping, f"a user asset folder needs a {MAPPING_FILE} mapping")
    if isinstance(data, dict) and set(data) == {"assets"}:
        data = data["assets"]
    if not isinstance(data, list):
        raise UserError(f'{mapping}: expected a list of entries or {{"assets": [...]}}')
    out = []
    for i, item in enumerate(data):
        where = f"{mapping}: entry {i}"
        if not isinstance(item, dict):
            raise UserError(f"{where}: expected an object, got {type(item).__name__}")
        extra = sorted(set(item) - _ENTRY_KEYS)
        if extra:
            raise UserError(
                f"{where}: unknown key(s) {', '.join(extra)} "
                f"(allowed: {', '.join(sorted(_ENTRY_KEYS))})"
            )
        file = item.get("file")
        if not isinstance(file, str) or not file:
            raise UserError(f"{where}: 'file' must be a file name")
        where = f"{mapping}: entry {i} ({file})"
        path = folder / file
        if not path.is_file():
            raise UserError(f"{where}: no such file {path}")
        if path.suffix.lower() not in MESH_SUFFIXES:
            raise UserError(
                f"{where}: unsupported mesh format {path.suffix!r} (use {', '.join(MESH_SUFFIXES)})"
            )
        cat = item.get("category")
        if not isinstance(cat, str) or cat not in BY_NAME:
            raise UserError(
                f"{where}: unknown category {cat!r} (a canonical category name, "
                "e.g. 'chair'; see 'pair2scene assets list')"
            )
        up, front = item.get("up", "+z"), item.get("front", "+y")
        for key, val in (("up", up), ("front", front)):
            if val not in _AXES:
                raise UserError(f"{where}: '{key}' must be one of {', '.join(_AXES)}, got {val!r}")
        if _AXES[up] == _AXES[front] or np.dot(_AXES[up], _AXES[front]) != 0:
            raise UserError(f"{where}: 'up' {up} and 'front' {front} must be perpendicular")
        scale = item.get("scale", 1.0)
        if (
            isinstance(scale, bool)
            or not isinstance(scale, (int, float))
            or not math.isfinite(scale)
            or scale <= 0
        ):
            raise UserError(
                f"{where}: 'scale' must be a positive number (metres per unit), got {scale!r}"
            )
        out.append(MeshEntry("user", file, cat, path, axis_rotation(up, front), float(scale)))
    return out


def _read_future_info(root: Path, labels: LabelMapper) -> list[MeshEntry]:
    """The 3D-FUTURE models whose label maps to a category and whose file is present."""
    if not root.is_dir():
        raise UserError(f"{root}: not a folder (3D-FUTURE models)")
    info_path = root / FUTURE_INFO_FILE
    info = _read_json(info_path, "a 3D-FUTURE folder has a model_info.json")
    if not isinstance(info, list):
        raise UserError(f"{info_path}: expected a list of models")
    rotation = axis_rotation("+y", "+z")
    out = []
    for i, item in enumerate(info):
        if not isinstance(item, dict) or not isinstance(item.get("model_id"), str):
            raise UserError(f"{info_path}: entry {i}: expected an object with a 'model_id'")
        label = item.get("category") or item.get("super-category")
        cat = labels(label)
        if cat == UNKNOWN:
            continue
        jid = item["model_id"]
        path = next(
            (root / jid / n for n in FUTURE_MODEL_FILES if (root / jid / n).is_file()), None
        )
        if path is not None:
            out.append(MeshEntry("3dfuture", jid, cat, path, rotation, 1.0))
    return out


def _read_bounds_cache(path: Path) -> dict[str, list]:
    """The saved model bounds; an unreadable file is simply ignored (rebuilt)."""
    try:
        data = json.loads(path.read_text(encoding="utf-8"))
    except (OSError, ValueError):
        return {}
    if not isinstance(data, dict):
        return {}
    return {k: v for k, v in data.items() if isinstance(v, list) and len(v) == 8}


def _read_mesh(path: Path) -> tuple[np.ndarray, np.ndarray]:
    """Vertices (V, 3) and faces (F, 3) of a mesh file (a scene is flattened into one)."""
    import trimesh

    try:
        tm = trimesh.load(path, force="mesh", process=False)
    except Exception as exc:  # trimesh raises many kinds on bad files
        raise UserError(f"{path}: cannot read mesh: {str(exc).splitlines()[0]}") from None
    v = np.asarray(getattr(tm, "vertices", np.zeros((0, 3))), dtype=float).reshape(-1, 3)
    f = np.asarray(getattr(tm, "faces", np.zeros((0, 3))), dtype=np.int64).reshape(-1, 3)
    if len(f) == 0 or not np.all(np.isfinite(v)):
        raise UserError(f"{path}: no triangles (or non-finite vertices) in the mesh")
    return v, f


# -- convex parts ----------------------------------------------------------------------
def _weld(mesh: Mesh) -> Mesh:
    """Merge coincident vertices (files split them along UV and normal seams)."""
    diag = float(np.linalg.norm(np.ptp(mesh.vertices, axis=0)))
    q = np.round(mesh.vertices / max(diag * WELD_REL, 1e-12)).astype(np.int64)
    _, first, inverse = np.unique(q, axis=0, return_index=True, return_inverse=True)
    return Mesh(mesh.vertices[first], inverse.reshape(-1)[mesh.faces])


def _component_vertices(mesh: Mesh) -> list[np.ndarray]:
    """Vertices (k, 3) of each connected component of ``mesh``, after welding.

    Faces connect through manifold edges (shared by exactly two faces): two separate
    boxes that merely touch along an edge or at a corner stay two components.
    """
    from scipy.sparse import coo_matrix
    from scipy.sparse.csgraph import connected_components

    w = _weld(mesh)
    f = w.faces
    nf = len(f)
    edges = np.sort(np.concatenate([f[:, [0, 1]], f[:, [1, 2]], f[:, [2, 0]]]), axis=1)
    face_of = np.tile(np.arange(nf), 3)
    _, inv, counts = np.unique(edges, axis=0, return_inverse=True, return_counts=True)
    inv = inv.reshape(-1)
    order = np.argsort(inv, kind="stable")
    pos = np.flatnonzero(counts[inv[order]] == 2)  # consecutive pairs: one edge's two faces
    a, b = face_of[order[pos[0::2]]], face_of[order[pos[1::2]]]
    graph = coo_matrix((np.ones(len(a)), (a, b)), shape=(nf, nf))
    _, label = connected_components(graph, directed=False)
    return [w.vertices[np.unique(f[label == k])] for k in np.unique(label)]


def _hull(points: np.ndarray) -> Mesh | None:
    """Convex hull of points (N, 3), thickened to MIN_PART_THICKNESS_M where flat."""
    from scipy.spatial import QhullError

    from pair2scene.assets.mesh import hull

    pts = np.unique(points, axis=0)
    if len(pts) < 1:
        return None
    centre = pts.mean(0)
    _, _, vt = np.linalg.svd(pts - centre, full_matrices=True)
    spread = np.ptp((pts - centre) @ vt.T, axis=0)  # (3,) extent along principal axes
    for k in np.flatnonzero(spread < MIN_PART_THICKNESS_M):
        off = vt[k] * MIN_PART_THICKNESS_M / 2
        pts = np.concatenate([pts + off, pts - off])
    try:
        return hull(pts)
    except (QhullError, ValueError):
        return None


def _convex_parts(mesh: Mesh) -> list[Mesh]:
    """Convex hulls of the components of ``mesh``, at most MAX_PARTS of them."""
    comps = _component_vertices(mesh)
    hulls = [(h, c) for c in comps if (h := _hull(c)) is not None]
    if not hulls:
        return []
    if len(hulls) <= MAX_PARTS:
        return [h for h, _ in hulls]
    hulls.sort(key=lambda hc: -hc[0].area)
    kept = [h for h, _ in hulls[:KEEP_PARTS]]
    lo, hi = mesh.bounds
    grid = np.array(GROUP_GRID)
    groups: dict[tuple[int, ...], list[np.ndarray]] = {}
    for h, _ in hulls[KEEP_PARTS:]:
        c = h.bounds.mean(0)
        cell = np.clip(((c - lo) / np.maximum(hi - lo, 1e-12) * grid).astype(int), 0, grid - 1)
        groups.setdefault(tuple(cell.tolist()), []).append(h.vertices)
    for key in sorted(groups):
        h = _hull(np.concatenate(groups[key]))
        if h is not None:
            kept.append(h)
    return kept

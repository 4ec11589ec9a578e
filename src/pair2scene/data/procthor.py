"""ProcTHOR houses (the ProcTHOR-10K house JSON format), one house per line, gzipped.

Each room of a house becomes one scene. Object positions are box centres
(Unity, y-up, left-handed), rotations Euler angles, sizes come from the asset
database of the AI2-THOR wheel. Objects resting on furniture are nested as
``children`` of it: that nesting is the source's support annotation. Frames
follow the front convention measured in ``pair2scene.data.orientation``.
"""

from __future__ import annotations

import gzip
import json
from collections import Counter
from collections.abc import Iterator
from dataclasses import replace
from pathlib import Path

import numpy as np

from pair2scene.categories import (
    AI2THOR_LABELS,
    PROCTHOR_ROOM_TYPES,
    LabelMapper,
    RoomType,
    SuperCategory,
    is_structure,
    super_category,
)
from pair2scene.data import unity
from pair2scene.data.base import SPLITS, Corpus, SourceReport, stable_fraction
from pair2scene.data.fixtures import build_kitchens_and_bathrooms
from pair2scene.data.orientation import front_offset_deg, turn_front
from pair2scene.data.support import ON_FLOOR_M
from pair2scene.errors import UserError
from pair2scene.scene.geometry import OrientedBox, points_in_polygon
from pair2scene.scene.model import FLOOR, AssetRef, Opening, Room, Scene, SceneObject

VAL_FRACTION = 0.2
"""Files not named train/val are split by a hash of the scene id."""
DEFAULT_HEIGHT_M = 2.7


def _read_lines(path: Path) -> Iterator[tuple[int, dict]]:
    opener = gzip.open if path.suffix == ".gz" else open
    try:
        with opener(path, "rt", encoding="utf-8") as fh:
            for i, line in enumerate(fh):
                if not line.strip():
                    continue
                try:
                    house = json.loads(line)
                except json.JSONDecodeError as e:
                    raise UserError(f"{path}: line {i + 1}: not valid JSON ({e.msg})") from None
                if not isinstance(house, dict):
                    raise UserError(f"{path}: line {i + 1}: a house must be a JSON object")
                yield i, house
    except FileNotFoundError:
        raise UserError(f"{path}: no such file") from None
    except (OSError, EOFError, UnicodeDecodeError) as e:
        raise UserError(f"{path}: not a readable (gzipped) JSON-lines file ({e})") from None


def _wall_segment(wall_id: str) -> tuple[np.ndarray, np.ndarray] | None:
    """World xy endpoints from a ProcTHOR wall id ``wall|room|x0|z0|x1|z1``."""
    parts = wall_id.split("|")
    try:
        x0, z0, x1, z1 = (float(v) for v in parts[-4:])
    except ValueError:
        return None
    # unity (x, z) -> world (x, y)
    return np.array([x0, z0]), np.array([x1, z1])


def _opening(rec: dict, kind: str) -> Opening | None:
    seg = _wall_segment(str(rec.get("wall0", "")))
    hole = rec.get("holePolygon") or []
    if seg is None or len(hole) < 2:
        return None
    a, b = seg
    length = float(np.linalg.norm(b - a))
    if length <= 0:
        return None
    d = (b - a) / length
    t0, t1 = sorted(float(np.clip(h["x"], 0.0, length)) for h in hole[:2])
    z0, z1 = sorted(float(h["y"]) for h in hole[:2])
    return Opening(kind, tuple(a + d * t0), tuple(a + d * t1), z0, z1, rec.get("id"))


def _flatten(objs: list, parent: str | None) -> Iterator[tuple[dict, str | None]]:
    for o in objs or []:
        yield o, parent
        yield from _flatten(o.get("children") or [], o.get("id"))


def convert_house(
    house: dict,
    house_id: str,
    split: str,
    assets: unity.AssetDatabase,
    mapper: LabelMapper,
    report: SourceReport,
    correct_front: bool = True,
) -> list[Scene]:
    """One ProcTHOR house -> one Scene per room.

    correct_front : turn each box's frame so that +y is the object's front
    (pair2scene.data.orientation); off only to measure the raw conversion.
    """
    rooms = house.get("rooms") or []
    polys = []
    for r in rooms:
        poly = np.array([[p["x"], p["z"]] for p in r["floorPolygon"]], dtype=float)
        polys.append(poly)
    heights: dict[str, float] = {}
    for w in house.get("walls") or []:
        top = max((p["y"] for p in w.get("polygon", [])), default=0.0)
        rid = w.get("roomId")
        heights[rid] = max(heights.get(rid, 0.0), float(top))
    records = list(_flatten(house.get("objects") or [], None))
    centers = np.array([[o["position"]["x"], o["position"]["z"]] for o, _ in records]).reshape(
        -1, 2
    )
    owner = np.full(len(records), -1)
    for k, poly in enumerate(polys):
        inside = points_in_polygon(centers, poly) if len(records) else np.zeros(0, bool)
        owner[(owner < 0) & inside] = k
    if len(polys) == 1:
        owner[owner < 0] = 0
    n_lost = int(np.count_nonzero(owner < 0))
    if n_lost:
        report.warnings["object outside every room (skipped)"] += n_lost
    scenes = []
    for k, r in enumerate(rooms):
        rid = r.get("id", f"room{k}")
        rtype = PROCTHOR_ROOM_TYPES.get(r.get("roomType"), RoomType.OTHER)
        if rtype is RoomType.OTHER:
            report.warnings[f"room type {r.get('roomType')!r} mapped to other"] += 1
        doors = tuple(
            o
            for o in (
                _opening(d, "door")
                for d in house.get("doors") or []
                if rid in (d.get("room0"), d.get("room1"))
            )
            if o
        )
        windows = tuple(
            o
            for o in (
                _opening(w, "window")
                for w in house.get("windows") or []
                if rid in (w.get("room0"), w.get("room1"))
            )
            if o
        )
        room = Room(rtype.value, polys[k], heights.get(rid) or DEFAULT_HEIGHT_M, doors, windows)
        objects: list[SceneObject] = []
        ids: dict[str, str] = {}
        counts: Counter[str] = Counter()
        for i in np.flatnonzero(owner == k):
            rec, parent = records[int(i)]
            info = assets.get(rec.get("assetId"))
            label = info.object_type if info else None
            cat = mapper(label)
            if is_structure(cat):
                report.room_features[label or "?"] += 1
                continue
            if info is None:
                report.warnings["asset not in the asset database (skipped)"] += 1
                continue
            box = OrientedBox(
                unity.vec(rec["position"]), info.size, unity.rotation(rec["rotation"])
            )
            if correct_front:
                box = turn_front(box, front_offset_deg("procthor", cat, rec.get("assetId")))
            oid = f"{cat}_{counts[cat]}"
            counts[cat] += 1
            ids[rec.get("id")] = oid
            # Nesting is the source's support annotation. Top-level objects low enough
            # stand on the floor; higher ones hang on a wall and get none.
            if parent is not None:
                support = parent  # resolved to our id below
            elif box.bottom < ON_FLOOR_M and super_category(cat) is not SuperCategory.WALL_OBJECT:
                support = FLOOR
            else:
                support = None
            objects.append(
                SceneObject(
                    oid,
                    cat,
                    box,
                    AssetRef("ai2thor", rec.get("assetId")),
                    source_label=label,
                    source_support=support,
                )
            )
        resolved = []
        for o in objects:
            sup = o.source_support
            if sup not in (None, FLOOR):
                sup = ids.get(sup)
                if sup is None:
                    report.warnings["support parent skipped or in another room"] += 1
            resolved.append(replace(o, source_support=sup, support=sup))
        resolved = build_kitchens_and_bathrooms(resolved, polys[k].mean(0), report)
        scenes.append(Scene(f"{house_id}/{rid}", room, resolved, source="procthor", split=split))
    return scenes


def load_procthor(
    path: str | Path,
    split: str | None = None,
    progress: bool = False,
    databases: str | Path | None = None,
    correct_front: bool = True,
) -> Corpus:
    """Scenes of a ProcTHOR ``.jsonl.gz`` (or ``.jsonl``) file, or of every such file
    in a folder. A file named ``train``/``val`` gives its split; others are split
    by a hash of the scene id. correct_front : apply the measured front
    corrections (see convert_house)."""
    from pair2scene.data.fetch import databases_dir
    from pair2scene.progress import track

    path = Path(path)
    if path.is_dir():
        files = sorted(p for p in path.iterdir() if p.name.endswith((".jsonl", ".jsonl.gz")))
        if not files:
            raise UserError(f"{path}: no .jsonl or .jsonl.gz files")
    elif path.exists():
        files = [path]
    else:
        raise UserError(f"{path}: no such file or folder")
    root = Path(databases) if databases is not None else databases_dir()
    assets = unity.AssetDatabase.load(root / "asset-database.json")
    mapper = LabelMapper(AI2THOR_LABELS)
    report = SourceReport()
    scenes: list[Scene] = []
    for f in files:
        stem = f.name.split(".")[0]
        lines = list(_read_lines(f))
        for i, house in track(lines, f"ProcTHOR {f.name}", enabled=progress):
            house_id = f"procthor/{stem}/{i}"
            if stem in SPLITS:
                house_split = stem
            else:
                house_split = "val" if stable_fraction(house_id) < VAL_FRACTION else "train"
            if split is not None and split != house_split:
                continue
            try:
                scenes.extend(
                    convert_house(
                        house, house_id, house_split, assets, mapper, report, correct_front
                    )
                )
            except (KeyError, TypeError, ValueError, AttributeError) as e:
                raise UserError(
                    f"{f}: line {i + 1}: malformed house ({type(e).__name__}: {e})"
                ) from None
    report.unknown_labels.update(mapper.unknown)
    report.mapped_labels.update(mapper.mapped)
    return Corpus("procthor", scenes, report)

"""AI2-THOR designed rooms: 120 iTHOR rooms and 75 RoboTHOR apartments.

Source: ``procthor/databases/ai2thor-object-metadata.json`` of the PyPI wheel
``procthor==0.0.1.dev2`` (Apache-2.0), per room a list of object metadata as
AI2-THOR reports it, plus ``asset-database.json`` for unrotated sizes.

Boxes: rotation from the object's Euler angles, centre from its world AABB,
size from the asset database (parts such as drawers have none: their size is
unmixed from the AABB). Where AI2-THOR also gives oriented-box corner points
and they disagree with that box (an asset whose bounding box is rotated inside
its prefab, an open laptop), the box is refit to the corners, keeping the
object's rotation, and the refit is counted in the report. Then the frame is
turned so that +y is the object's front where the asset is modelled facing
another way (``pair2scene.data.orientation``, measured from these rooms).
"""

from __future__ import annotations

import json
from collections import Counter
from dataclasses import dataclass, replace
from pathlib import Path

import numpy as np

from pair2scene.categories import AI2THOR_LABELS, LabelMapper, RoomType, is_structure
from pair2scene.data import unity
from pair2scene.data.base import Corpus, SourceReport
from pair2scene.data.fixtures import build_kitchens_and_bathrooms
from pair2scene.data.orientation import front_offset_deg, turn_front
from pair2scene.data.support import (
    floor_by_height,
    resolve_part_hosts,
    support_from_receptacles,
)
from pair2scene.errors import UserError
from pair2scene.scene.geometry import OrientedBox, corner_distance
from pair2scene.scene.model import FLOOR, AssetRef, Opening, Room, Scene, SceneObject

METADATA_FILE = "ai2thor-object-metadata.json"
ASSET_DB_FILE = "asset-database.json"

OBB_AGREEMENT_M = 0.02
"""A converted box agrees with the source's OBB when every corner is within 2 cm."""
DEFAULT_HEIGHT_M = 2.5
"""AI2-THOR's metadata has no ceiling; iTHOR rooms are at least this high."""
CEILING_CLEARANCE_M = 0.1
EXTENT_FLOOR_MARGIN_M = 0.02
FLOOR_CLIP_REPORT_M = 0.3
"""Clipping the Floor box by more than this is counted in the report."""
"""Rooms without a Floor object: the floor is the objects' extent grown by this."""
FLOOR_STANDING_TYPES = frozenset(
    {
        "Bed",
        "Sofa",
        "ArmChair",
        "Chair",
        "DiningTable",
        "CoffeeTable",
        "SideTable",
        "Desk",
        "Dresser",
        "TVStand",
        "ShelvingUnit",
        "CounterTop",
        "Fridge",
        "Toilet",
        "GarbageCan",
    }
)
"""Types that stand on the floor in every AI2-THOR room (to find its level)."""
"""Room height is the highest object top plus this, when above the default."""


@dataclass(frozen=True)
class RoomGroup:
    key: str
    """Key in the metadata file."""
    room_type: RoomType
    names: tuple[str, ...]
    """AI2-THOR scene names, in file order."""
    val: frozenset[str]


def _ithor(key: str, rtype: RoomType, base: int) -> RoomGroup:
    names = tuple(f"FloorPlan{base + i}" for i in range(1, 31))
    # AI2-THOR's own split of every iTHOR type: 1-20 train, 21-25 val, 26-30 test.
    # We have train/val only: its val rooms are our val, its test rooms join train.
    return RoomGroup(key, rtype, names, frozenset(names[20:25]))


_ROBOTHOR_TRAIN = tuple(f"FloorPlan_Train{a}_{b}" for a in range(1, 13) for b in range(1, 6))
_ROBOTHOR_VAL = tuple(f"FloorPlan_Val{a}_{b}" for a in range(1, 4) for b in range(1, 6))

GROUPS: tuple[RoomGroup, ...] = (
    _ithor("kitchens", RoomType.KITCHEN, 0),
    _ithor("living_rooms", RoomType.LIVING_ROOM, 200),
    _ithor("bedrooms", RoomType.BEDROOM, 300),
    _ithor("bathrooms", RoomType.BATHROOM, 400),
    # RoboTHOR's own split: 60 train apartments, 15 val.
    RoomGroup(
        "robothor", RoomType.APARTMENT, _ROBOTHOR_TRAIN + _ROBOTHOR_VAL, frozenset(_ROBOTHOR_VAL)
    ),
)


@dataclass(frozen=True)
class ConvertedBox:
    box: OrientedBox
    """The box the adapter uses."""
    converted: OrientedBox
    """The box from Euler angles, AABB centre and asset size alone (before any refit)."""
    obb: np.ndarray | None
    """(8, 3) the source's own OBB corners in world coordinates, if it has them."""


def convert_box(obj: dict, assets: unity.AssetDatabase) -> ConvertedBox:
    """The oriented box of one AI2-THOR object record."""
    rot = unity.rotation(obj["rotation"])
    aabb = obj["axisAlignedBoundingBox"]
    center = unity.vec(aabb["center"])
    info = assets.get(obj.get("assetId"))
    obb_raw = obj.get("objectOrientedBoundingBox")
    obb = unity.points(obb_raw["cornerPoints"]) if obb_raw else None
    if info is not None:
        size = info.size
    elif obb is not None:
        size = unity.fit_box_to_corners(obb, rot).size
    else:
        size = unity.size_from_aabb(np.abs(unity.vec(aabb["size"])), rot)
    converted = OrientedBox(center, np.maximum(size, unity.MIN_SIZE), rot)
    box = converted
    if obb is not None and corner_distance(converted.corners(), obb) > OBB_AGREEMENT_M:
        box = unity.fit_box_to_corners(obb, rot)
    return ConvertedBox(box, converted, obb)


def _rectangle(corners: list, margin: float = 0.0) -> np.ndarray:
    """(4, 2) counter-clockwise xy bounds of Unity points, grown by ``margin``."""
    pts = unity.points(corners)
    lo, hi = pts.min(0)[:2] - margin, pts.max(0)[:2] + margin
    return np.array([[lo[0], lo[1]], [hi[0], lo[1]], [hi[0], hi[1]], [lo[0], hi[1]]])


def _window(obj: dict, idx: int) -> Opening:
    """A window's opening: its long horizontal side of the AABB, at its height range."""
    c = unity.vec(obj["axisAlignedBoundingBox"]["center"])
    s = np.abs(unity.vec(obj["axisAlignedBoundingBox"]["size"]))
    axis = 0 if s[0] >= s[1] else 1
    p0, p1 = c[:2].copy(), c[:2].copy()
    p0[axis] -= s[axis] / 2
    p1[axis] += s[axis] / 2
    return Opening(
        "window",
        tuple(p0),
        tuple(p1),
        float(c[2] - s[2] / 2),
        float(c[2] + s[2] / 2),
        f"window_{idx}",
    )


def floor_level(records: list[dict]) -> float:
    """Unity height of the floor surface: the Floor object's top, or for rooms
    without one the median bottom of their floor-standing furniture."""
    for r in records:
        if r.get("objectType") == "Floor":
            return max(c[1] for c in r["axisAlignedBoundingBox"]["cornerPoints"])
    bottoms = [
        min(c[1] for c in r["axisAlignedBoundingBox"]["cornerPoints"])
        for r in records
        if r.get("objectType") in FLOOR_STANDING_TYPES
    ]
    return float(np.median(bottoms)) if bottoms else 0.0


def convert_room(
    records: list[dict],
    scene_id: str,
    room_type: RoomType,
    split: str,
    assets: unity.AssetDatabase,
    mapper: LabelMapper,
    report: SourceReport,
    correct_front: bool = True,
) -> Scene:
    """One AI2-THOR room (its list of object records) -> Scene, floor moved to z = 0.

    correct_front : turn each box's frame so that +y is the object's front
    (pair2scene.data.orientation); off only to measure the raw conversion.
    """
    # Walls are lined with windows, paintings, switches and furniture: the extent of
    # everything but the floor approximates the walls. iTHOR's Floor object can run
    # metres past them (FloorPlan212), so the floor is its box clipped to that extent.
    others = [
        c
        for r in records
        if r.get("objectType") != "Floor"
        for c in r["axisAlignedBoundingBox"]["cornerPoints"]
    ]
    extent = _rectangle(others, margin=EXTENT_FLOOR_MARGIN_M) if others else None
    floors = [r for r in records if r.get("objectType") == "Floor"]
    if floors:
        polygon = _rectangle(floors[0]["axisAlignedBoundingBox"]["cornerPoints"])
        if extent is not None:
            clipped = np.clip(polygon, extent.min(0), extent.max(0))
            if np.abs(clipped - polygon).max() > FLOOR_CLIP_REPORT_M:
                report.warnings["Floor object runs past the walls: clipped to the objects"] += 1
            polygon = clipped
    elif extent is not None:
        report.warnings["no Floor object: floor from the extent of all objects"] += 1
        polygon = extent
    else:
        raise UserError(f"{scene_id}: room has neither a Floor nor any object")
    lift = np.array([0.0, 0.0, floor_level(records)])
    windows: list[Opening] = []
    objects: list[SceneObject] = []
    source_ids: dict[str, str] = {}
    receptacles: dict[str, list[str]] = {}
    counts: Counter[str] = Counter()
    top = 0.0
    for rec in records:
        otype = rec.get("objectType")
        cat = mapper(otype)
        if cat == "floor":
            source_ids[rec["objectId"]] = FLOOR
            report.room_features[otype] += 1
            continue
        cb = convert_box(rec, assets)
        box = OrientedBox(cb.box.center - lift, cb.box.size, cb.box.rotation)
        asset_id = rec.get("assetId") or None
        if correct_front:
            box = turn_front(box, front_offset_deg("ai2thor", cat, asset_id))
        top = max(top, box.top)
        if cat == "window":
            w = _window(rec, len(windows))
            windows.append(replace(w, z_min=w.z_min - lift[2], z_max=w.z_max - lift[2]))
        if is_structure(cat):
            report.room_features[otype] += 1
            continue
        if cb.box is not cb.converted:
            report.warnings["box refit to the source OBB"] += 1
        oid = f"{cat}_{counts[cat]}"
        counts[cat] += 1
        source_ids[rec["objectId"]] = oid
        receptacles[oid] = list(rec.get("parentReceptacles") or [])
        asset = AssetRef("ai2thor", asset_id)
        objects.append(SceneObject(oid, cat, box, asset, source_label=otype))
    objects = support_from_receptacles(objects, receptacles, source_ids, report)
    objects = resolve_part_hosts(objects)
    objects = floor_by_height(objects, report)
    objects = build_kitchens_and_bathrooms(objects, polygon.mean(0), report)
    height = max(DEFAULT_HEIGHT_M, round(top + CEILING_CLEARANCE_M, 2))
    room = Room(room_type.value, polygon, height, (), tuple(windows))
    return Scene(scene_id, room, objects, source="ai2thor", split=split)


def load_ai2thor(
    databases: str | Path | None = None,
    split: str | None = None,
    progress: bool = False,
    correct_front: bool = True,
) -> Corpus:
    """All 195 AI2-THOR rooms (or one split) as scenes.

    databases : folder holding ``ai2thor-object-metadata.json`` and
    ``asset-database.json``; default: the cache, fetched on first use.
    correct_front : apply the measured front corrections (see convert_room).
    """
    from pair2scene.data.fetch import databases_dir

    root = Path(databases) if databases is not None else databases_dir()
    meta_path = root / METADATA_FILE
    try:
        metadata = json.loads(meta_path.read_text(encoding="utf-8"))
    except FileNotFoundError:
        raise UserError(
            f"{meta_path}: no such file (run 'pair2scene data fetch ai2thor')"
        ) from None
    except (OSError, ValueError) as e:
        raise UserError(f"{meta_path}: not readable AI2-THOR metadata ({e})") from None
    assets = unity.AssetDatabase.load(root / ASSET_DB_FILE)
    mapper = LabelMapper(AI2THOR_LABELS)
    report = SourceReport()
    jobs = []
    for group in GROUPS:
        rooms = metadata.get(group.key)
        if not isinstance(rooms, list):
            raise UserError(f"{meta_path}: missing room list {group.key!r}")
        if len(rooms) != len(group.names):
            report.warnings[f"{group.key}: {len(rooms)} rooms, expected {len(group.names)}"] += 1
        for i, records in enumerate(rooms):
            name = group.names[i] if i < len(group.names) else f"{group.key}_{i}"
            room_split = "val" if name in group.val else "train"
            if split is None or split == room_split:
                jobs.append((records, f"ai2thor/{name}", group.room_type, room_split))
    scenes = []
    from pair2scene.progress import track

    for records, sid, rtype, room_split in track(jobs, "AI2-THOR rooms", enabled=progress):
        try:
            scenes.append(
                convert_room(records, sid, rtype, room_split, assets, mapper, report, correct_front)
            )
        except (KeyError, TypeError, ValueError) as e:
            raise UserError(f"{meta_path}: {sid}: malformed object record ({e})") from None
    report.unknown_labels.update(mapper.unknown)
    report.mapped_labels.update(mapper.mapped)
    return Corpus("ai2thor", scenes, report)

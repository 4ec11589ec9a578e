"""Support annotations taken from the sources themselves (ground truth for curation).

AI2-THOR lists, per object, the receptacles it rests in or on
(``parentReceptacles``), often several (a book on a shelf *of* a shelving unit
standing on the floor). We keep the one whose top is nearest below the object.
Parts (drawers, shelves, cabinet doors) are not furniture: each is attached to
the object that contains it (``part_of``), and anything resting on a part is
supported, in pair2scene's sense, by the part's owner.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import replace

import numpy as np

from pair2scene.categories import SuperCategory
from pair2scene.data.base import SourceReport
from pair2scene.scene.geometry import OrientedBox
from pair2scene.scene.model import FLOOR, SceneObject

RESTING_TOLERANCE_M = 0.05
"""A receptacle counts as "below" when its top is at most this far above the
object's bottom: source meshes interpenetrate by a few centimetres."""
PART_HOST_MARGIN_M = 0.03
"""A part belongs to an object whose box, grown by this, contains the part's centre."""


def pick_receptacle(
    box: OrientedBox, candidates: Sequence[tuple[str, OrientedBox | None]]
) -> str | None:
    """Of (id, box) candidates (box None for the floor), the receptacle ``box`` rests on.

    In order: the object receptacle whose top is nearest below ``box``'s bottom (a
    book on a shelf, not the unit around the shelf); else the smallest one whose box
    holds ``box``'s bottom centre (a pillow on a sofa's seat, below the backrest top;
    an egg in a fridge); else the floor, if listed; else the nearest top.
    """
    if not candidates:
        return None
    objects = [(cid, b) for cid, b in candidates if b is not None]
    bottom = box.bottom
    if objects:
        gaps = np.array([bottom - b.top for _, b in objects])
        below = np.flatnonzero(gaps >= -RESTING_TOLERANCE_M)
        if below.size:
            return objects[int(below[np.argmin(gaps[below])])][0]
        foot = np.array([box.center[0], box.center[1], bottom + RESTING_TOLERANCE_M / 5])
        holding = [(float(np.prod(b.size)), cid) for cid, b in objects if b.contains(foot)[0]]
        if holding:
            return min(holding)[1]
    if any(b is None for _, b in candidates):
        return FLOOR
    tops = np.array([b.top for _, b in objects])
    return objects[int(np.argmin(np.abs(bottom - tops)))][0]


def support_from_receptacles(
    objects: list[SceneObject],
    receptacles: dict[str, list[str]],
    source_ids: dict[str, str],
    report: SourceReport,
) -> list[SceneObject]:
    """Set ``source_support`` from each object's receptacle list.

    receptacles : object id -> the source's receptacle ids;
    source_ids : source id -> object id (or ``floor``).
    """
    boxes = {o.id: o.box for o in objects}
    out = []
    for o in objects:
        cands: list[tuple[str, OrientedBox | None]] = []
        for rid in receptacles.get(o.id, []):
            mapped = source_ids.get(rid)
            if mapped is None:
                report.warnings["receptacle not in the room (ignored)"] += 1
            elif mapped == FLOOR:
                cands.append((FLOOR, None))
            elif mapped != o.id and mapped in boxes:
                cands.append((mapped, boxes[mapped]))
        out.append(replace(o, source_support=pick_receptacle(o.box, cands)))
    return out


def resolve_part_hosts(objects: list[SceneObject]) -> list[SceneObject]:
    """Attach parts to their owner and set each object's ``support``.

    The owner of a part is the smallest furniture or fixture whose box (grown by
    PART_HOST_MARGIN_M) contains the part's centre. ``support`` is the source
    support with parts replaced by their owner; a part rests on its owner.
    """
    # Owners are furniture and fixtures: a vase standing in a shelf's box is no owner.
    hosts = [
        o for o in objects if o.super in (SuperCategory.LARGE_FURNITURE, SuperCategory.FIXTURE)
    ]
    volumes = np.array([np.prod(h.box.size) for h in hosts])
    order = np.argsort(volumes, kind="stable")
    part_of: dict[str, str | None] = {}
    for o in objects:
        if o.super is not SuperCategory.PART:
            continue
        part_of[o.id] = None
        for k in order:
            host = hosts[int(k)]
            if host.box.contains(o.box.center, margin=PART_HOST_MARGIN_M)[0]:
                part_of[o.id] = host.id
                break

    def owner(ref: str | None) -> str | None:
        if ref in part_of:
            return part_of[ref] or ref
        return ref

    out = []
    for o in objects:
        if o.id in part_of:
            host = part_of[o.id]
            out.append(replace(o, part_of=host, support=host or owner(o.source_support)))
        else:
            sup = owner(o.source_support)
            out.append(replace(o, support=None if sup == o.id else sup))
    return out


ON_FLOOR_M = 0.05
"""An object with no support annotation whose bottom is within this of the floor
stands on it."""


def floor_by_height(objects: list[SceneObject], report: SourceReport) -> list[SceneObject]:
    """Give ``support = floor`` to unannotated objects standing on the floor.

    Many AI2-THOR objects (all RoboTHOR furniture) list no receptacle. This sets
    ``support`` only; ``source_support`` stays what the source said (None).
    """
    out = []
    for o in objects:
        if (
            o.support is None
            and o.box.bottom < ON_FLOOR_M
            and o.super not in (SuperCategory.PART, SuperCategory.WALL_OBJECT)
        ):
            report.warnings["no support annotation: on the floor by height"] += 1
            o = replace(o, support=FLOOR)
        out.append(o)
    return out

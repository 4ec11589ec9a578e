"""How one object stands relative to another, seen from above: the gap between their
footprints and whether the first one's front points at the second.

These are the functional relations of a room that people read at a glance (a chair pulled
up to its table, facing it; a sofa facing the TV), measured the same way wherever they
are used: the hierarchy statistics learn how often real dependents face their functional
anchor and how far they stand from it (:mod:`pair2scene.curation.stats`), placement keeps
generated ones to that (:mod:`pair2scene.assembly.place`), and the layout measures score
rooms with them (:mod:`pair2scene.metrics.layout`).

Footprints are convex polygons, counter-clockwise (:func:`footprint`: a box's outline
seen from above).
"""

from __future__ import annotations

import numpy as np

from pair2scene.scene.geometry import OrientedBox, following
from pair2scene.scene.navigation import footprint_polygon as footprint

FACING_MAX_DEG = 45.0
"""An object faces a target when its +y is within this many degrees of the direction to
the target: half of a right angle, so a chair set square to the table's side or end
passes and one turned sideways (90 degrees) or away does not."""

ALONE_M = 0.5
"""A floor object stands alone in the room when its footprint is further than this from
every wall and from every other floor object's footprint: in the training rooms no bed,
dresser, table, side table or house plant does, a basketball or a dog bed often does
(:func:`stands_alone`)."""

__all__ = [
    "ALONE_M", "FACING_MAX_DEG", "facing_angle", "faces", "footprint", "footprint_gap",
    "nearest_point", "angle_to_footprint", "stands_alone", "wall_gap", "alone_in_room",
]  # fmt: skip


def _closest_on_segments(point: np.ndarray, a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """(M, 2) closest point to ``point`` (2,) on each segment a[i] -> b[i]."""
    d = b - a
    t = np.einsum("ij,ij->i", point - a, d) / np.maximum(np.einsum("ij,ij->i", d, d), 1e-18)
    return a + np.clip(t, 0.0, 1.0)[:, None] * d


def _inside_convex(point: np.ndarray, poly: np.ndarray) -> bool:
    """Whether ``point`` lies in the counter-clockwise convex polygon ``poly``."""
    e = following(poly) - poly
    r = point - poly
    return bool(np.all(e[:, 0] * r[:, 1] - e[:, 1] * r[:, 0] >= -1e-12))


def nearest_point(point: np.ndarray, poly: np.ndarray) -> np.ndarray:
    """The point of the convex polygon ``poly`` (inside included) nearest to ``point``."""
    point = np.asarray(point, float)
    if _inside_convex(point, poly):
        return point
    near = _closest_on_segments(point, poly, following(poly))
    return near[np.argmin(np.linalg.norm(near - point, axis=1))]


def footprint_gap(a: np.ndarray, b: np.ndarray) -> float:
    """Distance between two convex polygons (counter-clockwise, (N, 2)); 0 when they
    overlap."""
    for p, q in ((a, b), (b, a)):  # separating axis: the edge normals of both
        e = following(p) - p
        n = np.stack([e[:, 1], -e[:, 0]], axis=1)
        if np.any((q @ n.T).min(axis=0) > np.einsum("ij,ij->i", p, n) + 1e-12):
            break
    else:
        return 0.0
    return _vertex_gap(a, b)  # apart: the closest pair has a vertex of one of them


def _vertex_gap(a: np.ndarray, b: np.ndarray) -> float:
    """Least distance from a vertex of either closed outline to an edge of the other."""
    best = np.inf
    for p, q in ((a, b), (b, a)):
        q1 = following(q)
        for v in p:
            near = _closest_on_segments(v, q, q1)
            best = min(best, float(np.linalg.norm(near - v, axis=1).min()))
    return best


def wall_gap(poly: np.ndarray, floor_polygon: np.ndarray) -> float:
    """Distance from the convex polygon ``poly`` (a footprint) to the outline of the room
    ``floor_polygon`` (its walls, L-shaped rooms included); 0 where they touch or cross."""
    return _vertex_gap(poly, floor_polygon)


def stands_alone(
    poly: np.ndarray, floor_polygon: np.ndarray, others: list[np.ndarray], gap: float = ALONE_M
) -> bool:
    """Whether the footprint ``poly`` is further than ``gap`` from every wall of the room
    ``floor_polygon`` and from every footprint of ``others`` (the other floor objects)."""
    if wall_gap(poly, floor_polygon) <= gap:
        return False
    lo, hi = poly.min(axis=0) - gap, poly.max(axis=0) + gap
    for q in others:  # (a bounding-box test first: most are far)
        if np.all(q.max(axis=0) >= lo) and np.all(q.min(axis=0) <= hi):
            if footprint_gap(poly, q) <= gap:
                return False
    return True


def alone_in_room(prints: list[np.ndarray], floor_polygon: np.ndarray) -> list[bool]:
    """For each of a room's floor footprints, whether it stands alone among the others
    (:func:`stands_alone`)."""
    return [
        stands_alone(p, floor_polygon, prints[:i] + prints[i + 1 :]) for i, p in enumerate(prints)
    ]


def facing_angle(box: OrientedBox, target_xy: np.ndarray) -> float:
    """Degrees between ``box``'s front (+y, seen from above) and the direction from its
    centre to ``target_xy``; 0 when the target is at the centre itself."""
    front = box.rotation[:2, 1]
    to = np.asarray(target_xy, float) - box.center[:2]
    nf, nt = float(np.linalg.norm(front)), float(np.linalg.norm(to))
    if nt < 1e-9:
        return 0.0
    if nf < 1e-9:  # lying on its back: no front seen from above
        return 180.0
    cos = float(front @ to) / (nf * nt)
    return float(np.degrees(np.arccos(np.clip(cos, -1.0, 1.0))))


def angle_to_footprint(box: OrientedBox, target: np.ndarray) -> float:
    """:func:`facing_angle` of ``box`` towards the nearest point of the footprint
    ``target`` (a chair at a table's long side looks square at that side, not at the
    table's centre); towards the footprint's centroid when ``box``'s centre lies over it
    (a chair pushed far under its table)."""
    point = nearest_point(box.center[:2], target)
    if np.linalg.norm(point - box.center[:2]) < 1e-9:
        point = target.mean(axis=0)
    return facing_angle(box, point)


def faces(box: OrientedBox, anchor: OrientedBox) -> bool:
    """Whether ``box``'s front points at ``anchor``'s footprint
    (:func:`angle_to_footprint` below :data:`FACING_MAX_DEG`)."""
    return angle_to_footprint(box, footprint(anchor)) < FACING_MAX_DEG


def by_back_half(box: OrientedBox, anchor: OrientedBox) -> bool:
    """Whether ``box``'s centre lies behind ``anchor``'s middle, in ``anchor``'s frame
    (towards its back, -y): a nightstand by the head of its bed."""
    return bool(anchor.to_local(box.center[None])[0, 1] < 0.0)

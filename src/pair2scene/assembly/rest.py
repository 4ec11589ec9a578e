"""Gravity for placement: where a candidate comes to rest on its support.

A candidate box from the layout model is dropped along -z onto the support surface
beneath it: among the support asset's upward surfaces (:func:`surfaces_of`, exact for
procedural assets: table tops, shelf tiers, seats) those under the candidate's contact
footprint, with room for its height, the one nearest the predicted bottom wins (so a book
predicted on a bookcase's second tier lands on the second tier, not the top).

The footprint that must be carried is the object's *contact* footprint: the rectangle of
its mesh's lowest vertices (a television's foot, a lamp's base, a chair's four legs), with
its centre; a wide screen may overhang a narrow stand as long as its foot stands on it.

A candidate slightly off its surface, or slightly through a wall, is moved onto / into it
when that takes at most ``max_shift`` (a local refinement, like the drop itself: the
model's draw is kept, nudged by centimetres); one that needs more is rejected.
"""

from __future__ import annotations

import weakref
from dataclasses import dataclass

import numpy as np

from pair2scene.assets.mesh import Asset
from pair2scene.assets.surfaces import surfaces_of
from pair2scene.curation.stats import ON_TOP_M
from pair2scene.scene.geometry import OrientedBox, points_in_polygon


@dataclass(frozen=True)
class RestRules:
    """When a footprint counts as carried (with the reason for each)."""

    min_corner_fraction: float = 0.75
    """Contact-footprint corners that must be over the surface, besides the centre: 3 of
    4, so an object may overhang a little (a laptop's edge past a desk) but not hang off."""
    top_band_m: float = ON_TOP_M
    """A surface this close to its support's top is the top (the statistics' band,
    :data:`~pair2scene.curation.stats.ON_TOP_M`)."""
    max_drop_m: float = 0.5
    """A surface this far below the predicted bottom is not where the model meant the
    object to go (a shelf's bottom tier when it predicted the top): it is taken only when
    no surface lies nearer (the model may mean a drawer, which the assets keep shut: the
    object then rests on the top, as if dropped from above)."""
    max_rise_m: float = 0.25
    """Nor, in the same way, is one this far above it (into the next tier up)."""
    upright_tol: float = 1e-3
    """The support must be upright (its z axis within this of world z) for its surfaces
    to be horizontal; a tilted support carries nothing."""
    contact_band_m: float = 0.01
    """Vertices within this of the asset's bottom are its contact with the surface."""


RULES = RestRules()
_INSET = 1e-3
_CONTACTS: weakref.WeakKeyDictionary = weakref.WeakKeyDictionary()


def _rectangle(lo: np.ndarray, hi: np.ndarray) -> np.ndarray:
    """(4, 2) counter-clockwise corners of the rectangle [lo, hi]."""
    (x0, y0), (x1, y1) = lo, hi
    return np.array([[x0, y0], [x1, y0], [x1, y1], [x0, y1]])


def contact_rectangle(asset: Asset, band: float = RULES.contact_band_m) -> np.ndarray:
    """(4, 2) local xy corners of the rectangle around the asset's lowest vertices."""
    cached = _CONTACTS.get(asset)
    if cached is None:
        v = asset.mesh.vertices
        low = v[v[:, 2] <= v[:, 2].min() + band, :2]
        cached = _rectangle(low.min(0), low.max(0))
        _CONTACTS[asset] = cached
    return cached


def footprint(box: OrientedBox, contact: np.ndarray | None = None) -> np.ndarray:
    """(5, 2) world xy of the box's centre and the four corners of its bottom face (or of
    ``contact``, a (4, 2) rectangle in the box's local xy)."""
    if contact is None:
        h = box.half_size
        contact = _rectangle(-h[:2], h[:2])
    out = np.empty((5, 2))
    out[0] = box.center[:2]
    np.add(box.center[:2], contact @ box.rotation[:2, :2].T, out=out[1:])
    return out


def _carried(surface, local: np.ndarray, rules: RestRules) -> bool:
    inside = surface.contains(local)
    return bool(inside[0] and inside[1:].mean() >= rules.min_corner_fraction)


def _shift_into(points: np.ndarray, lo: np.ndarray, hi: np.ndarray) -> np.ndarray | None:
    """The smallest xy shift that brings ``points`` (N, 2) inside the rectangle [lo, hi],
    or None when they are wider than it."""
    lo, hi = lo + _INSET, hi - _INSET  # land inside, not on the edge
    pmin, pmax = points.min(0), points.max(0)
    if ((pmax - pmin) > (hi - lo) + 1e-9).any():
        return None
    return np.maximum(lo - pmin, 0.0) - np.maximum(pmax - hi, 0.0)


def rest_on_surfaces(
    support: Asset,
    support_box: OrientedBox,
    box: OrientedBox,
    rules: RestRules = RULES,
    contact: np.ndarray | None = None,
    max_shift: float = 0.0,
    top: bool = True,
) -> tuple[float, np.ndarray] | None:
    """Where ``box`` comes to rest on ``support`` (posed at ``support_box``): the world z of
    the surface and the world xy shift (zero unless it had to be moved on, at most
    ``max_shift``), or None when no surface carries it. ``top=False``: not on a surface
    at the support's top (within ``rules.top_band_m``) when it has others (a fridge's
    shelves, not its roof)."""
    if abs(support_box.rotation[2, 2] - 1.0) > rules.upright_tol:
        return None
    points = np.column_stack([footprint(box, contact), np.zeros(5)])
    local = support_box.to_local(points)[:, :2]
    height = box.top - box.bottom
    best, best_key = None, (True, np.inf, np.inf)
    surfaces = surfaces_of(support)
    if not top:
        below = [s for s in surfaces if s.z < support_box.size[2] / 2 - rules.top_band_m]
        surfaces = below or surfaces
    for surface in surfaces:
        z = float(support_box.center[2] + surface.z)
        gap = z - box.bottom
        if surface.clearance < height:
            continue
        far = gap < -rules.max_drop_m or gap > rules.max_rise_m
        shift = np.zeros(2)
        if not _carried(surface, local, rules):
            if max_shift <= 0:
                continue
            moved = _shift_into(local[1:], surface.polygon.min(0), surface.polygon.max(0))
            if moved is None or np.linalg.norm(moved) > max_shift:
                continue
            if not _carried(surface, local + moved, rules):
                continue
            shift = moved
        key = (far, float(np.linalg.norm(shift)), abs(gap))
        if best is None or key < best_key:
            best, best_key = (z, support_box.rotation[:2, :2] @ shift), key
    return best


def on_floor(box: OrientedBox, floor_polygon: np.ndarray, tol: float = 1e-3) -> bool:
    """Whether the whole footprint of ``box`` lies inside the room's floor polygon: its
    corners inside, and no corner of the floor inside it (the inner corner of an L-shaped
    room reaches into a box turned across it whose corners all stand in the room). A corner
    within ``tol`` of a wall counts as inside (a box moved flush against a wall has its
    corners on the boundary, where the even-odd test answers either way)."""
    h = np.maximum(box.half_size[:2] - tol, 0.0)
    if not points_in_polygon(footprint(box, _rectangle(-h, h)), floor_polygon).all():
        return False
    poly = np.asarray(floor_polygon, float)
    local = (poly - box.center[:2]) @ box.rotation[:2, :2]  # the floor's corners in its frame
    return not bool((np.abs(local) < h).all(axis=1).any())


def into_room(
    box: OrientedBox, floor_polygon: np.ndarray, max_shift: float = 0.0, snap: float = 0.0
) -> OrientedBox | None:
    """``box`` moved (at most ``max_shift``) so that its footprint is inside the floor
    polygon, then pushed flush against a wall it stands within ``snap`` of (furniture
    stands against walls, not a hand's width off them); None when it cannot be."""
    poly = np.asarray(floor_polygon, float)
    lo, hi = poly.min(0), poly.max(0)
    corners = footprint(box)[1:]
    shift = np.zeros(2)
    inside = on_floor(box, poly)
    if not inside:
        moved = _shift_into(corners, lo, hi)
        if moved is None or np.linalg.norm(moved) > max_shift:
            return None
        shift = moved
    if snap > 0:
        c = corners + shift
        for axis in range(2):
            near_lo, near_hi = c[:, axis].min() - lo[axis], hi[axis] - c[:, axis].max()
            if 0 < near_lo <= snap and near_lo <= near_hi:
                shift[axis] -= near_lo
            elif 0 < near_hi <= snap:
                shift[axis] += near_hi
    if not shift.any():  # (inside the bounds is not inside an L-shaped floor)
        return box if inside else None
    center = box.center.copy()
    center[:2] += shift
    moved_box = OrientedBox(center, box.size, box.rotation)
    return moved_box if on_floor(moved_box, poly) else None


def dropped(box: OrientedBox, z: float) -> OrientedBox:
    """``box`` moved along z so that its bottom is at ``z``."""
    center = box.center.copy()
    center[2] += z - box.bottom
    return OrientedBox(center, box.size, box.rotation)

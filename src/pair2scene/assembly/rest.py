"""Gravity for placement: where a candidate comes to rest on its support.

A candidate box from the layout model is dropped along -z onto the support surface
beneath it: among the support asset's upward surfaces (:func:`surfaces_of`, exact for
procedural assets: table tops, shelf tiers, seats) those under the candidate's footprint,
with room for its height, the one nearest the predicted bottom wins (so a book predicted
on a bookcase's second tier lands on the second tier, not the top). A candidate whose
footprint is not carried by any surface is rejected: it would hang off an edge or fall.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from pair2scene.assets.mesh import Asset
from pair2scene.assets.surfaces import surfaces_of
from pair2scene.scene.geometry import OrientedBox, points_in_polygon


@dataclass(frozen=True)
class RestRules:
    """When a footprint counts as carried (with the reason for each)."""

    min_corner_fraction: float = 0.75
    """Footprint corners that must be over the surface, besides the centre: 3 of 4, so an
    object may overhang a little (a laptop's edge past a desk) but not hang off."""
    max_drop_m: float = 0.5
    """A surface this far below the predicted bottom is not where the model meant the
    object to go (a shelf's bottom tier when it predicted the top)."""
    max_rise_m: float = 0.25
    """Nor is one this far above it (into the next tier up)."""
    upright_tol: float = 1e-3
    """The support must be upright (its z axis within this of world z) for its surfaces
    to be horizontal; a tilted support carries nothing."""


RULES = RestRules()


def footprint(box: OrientedBox) -> np.ndarray:
    """(5, 2) world xy of the box's bottom face: its centre and four corners."""
    corners = box.corners()
    bottom = corners[np.argsort(corners[:, 2])[:4]]
    return np.vstack([box.center[None, :2], bottom[:, :2]])


def rest_on_surfaces(
    support: Asset, support_box: OrientedBox, box: OrientedBox, rules: RestRules = RULES
) -> float | None:
    """World z of the surface of ``support`` (posed at ``support_box``) on which ``box``
    comes to rest, or None when none carries it."""
    if abs(support_box.rotation[2, 2] - 1.0) > rules.upright_tol:
        return None
    local = support_box.to_local(np.column_stack([footprint(box), np.zeros(5)]))[:, :2]
    height = box.top - box.bottom
    best, best_gap = None, np.inf
    for surface in surfaces_of(support):
        z = float(support_box.center[2] + surface.z)
        gap = z - box.bottom
        if gap < -rules.max_drop_m or gap > rules.max_rise_m or surface.clearance < height:
            continue
        inside = surface.contains(local)
        if not inside[0] or inside[1:].mean() < rules.min_corner_fraction:
            continue
        if abs(gap) < best_gap:
            best, best_gap = z, abs(gap)
    return best


def on_floor(box: OrientedBox, floor_polygon: np.ndarray) -> bool:
    """Whether the whole footprint of ``box`` lies inside the room's floor polygon."""
    return bool(points_in_polygon(footprint(box), floor_polygon).all())


def dropped(box: OrientedBox, z: float) -> OrientedBox:
    """``box`` moved along z so that its bottom is at ``z``."""
    center = box.center.copy()
    center[2] += z - box.bottom
    return OrientedBox(center, box.size, box.rotation)

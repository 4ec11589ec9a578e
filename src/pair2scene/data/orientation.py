"""Which way each AI2-THOR / ProcTHOR category faces: the yaw fix the adapters apply.

pair2scene's convention: an object's local +y is its front (the side it faces).
The Unity adapters map Unity's local forward (+z) to our +y, which is right for
most AI2-THOR assets but not all. The tables below turn the rest, per source and
category (:data:`FRONT_YAW_OFFSET_DEG`) or per asset where an asset is modelled
unlike its category (:data:`FRONT_YAW_OFFSET_BY_ASSET_DEG`); the adapters apply
them once, through :func:`turn_front`.

The tables are measured, not guessed: ``python tools/front_survey.py`` surveys
both corpora with cues that need no knowledge of the asset (walls behind
furniture, chairs at tables, drawers at the front...), checks the tables against
the data and writes ``docs/front_convention.md``.
"""

from __future__ import annotations

import numpy as np

from pair2scene.scene.geometry import OrientedBox, yaw_to_matrix

OFFSETS_DEG: tuple[int, ...] = (0, 90, 180, 270)
"""Yaw offsets about local z, counter-clockwise seen from above: the corrected
front is the old +y (0), -x (90), -y (180) or +x (270)."""

# -- the correction ---------------------------------------------------------------------------

# Derived from, and checked against, the measurements of tools/front_survey.py (see
# docs/front_convention.md and tests/data/test_front_survey.py). Categories not listed
# keep the adapter's Unity-forward front (offset 0).
FRONT_YAW_OFFSET_DEG: dict[str, dict[str, int]] = {
    # iTHOR's bed prefabs (Bed_1 ... Bed_30) have their headboard at Unity +z;
    # ProcTHOR's copies of the same assets have it at -z like the rest.
    "ai2thor": {"bed": 180},
    "procthor": {},
}
"""source -> category -> yaw offset in degrees (one of :data:`OFFSETS_DEG`)."""

FRONT_YAW_OFFSET_BY_ASSET_DEG: dict[str, dict[str, int]] = {
    "ai2thor": {
        # RoboTHOR's own beds follow Unity +z, unlike iTHOR's
        "RoboTHOR_bed_grankulla": 0,
        "RoboTHOR_bed_hemnes": 0,
        "RoboTHOR_bed_kritter": 0,
        "RoboTHOR_hemnes_day_bed": 0,
        # five of iTHOR's nine TV stands face Unity -z (wall and TV agree on each)
        "TV_Stand_201_1": 180,
        "TV_Stand_202_1": 180,
        "TV_Stand_211_1": 180,
        "TV_Stand_222_1": 180,
        "TV_Stand_223_1": 180,
    },
    "procthor": {},
}
"""source -> asset id -> yaw offset in degrees, overriding the asset's category."""


def front_offset_deg(source: str, category: str, asset_id: str | None = None) -> int:
    """The yaw offset (degrees) that turns an object's adapter frame to face its front."""
    by_asset = FRONT_YAW_OFFSET_BY_ASSET_DEG.get(source, {})
    if asset_id is not None and asset_id in by_asset:
        return by_asset[asset_id]
    return FRONT_YAW_OFFSET_DEG.get(source, {}).get(category, 0)


def turn_front(box: OrientedBox, offset_deg: int) -> OrientedBox:
    """The same box with its local frame turned by ``offset_deg`` about local z.

    Rotation R' = R @ Rz(offset); for 90 and 270 degrees the local x and y
    extents swap, so the box occupies exactly the same space (same corner set).
    """
    if offset_deg not in OFFSETS_DEG:
        raise ValueError(f"front offset must be one of {OFFSETS_DEG}, got {offset_deg}")
    if offset_deg == 0:
        return box
    size = box.size if offset_deg == 180 else box.size[[1, 0, 2]]
    return OrientedBox(box.center, size, box.rotation @ yaw_to_matrix(np.radians(offset_deg)))

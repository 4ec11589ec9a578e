"""Asset identity: which stand-in asset an object gets.

Every stage that builds an object's asset (the curation's physics check and support
extraction, the layout model's point clouds, scene assembly) seeds the generator with
:func:`asset_seed` of the object's id, so they all see the same mesh.
"""

from __future__ import annotations

import zlib

__all__ = ["asset_seed", "library_seed"]


def asset_seed(object_id: str, seed: int = 0) -> int:
    """A stable seed for an object's asset: the same object gets the same asset in every
    run and every stage (crc32 of the id, not Python's salted ``hash``), unsigned 32-bit;
    ``seed`` varies it (a run seed mixed in by golden-ratio multiplication)."""
    return (zlib.crc32(object_id.encode("utf-8")) ^ (seed * 0x9E3779B1)) & 0xFFFFFFFF


def library_seed(category: str, size, variant: int = 0) -> int:
    """The mesh seed of the asset library's ``category`` at ``size`` (3,) metres: one mesh
    per observed size (``variant`` > 0: the next one, where a first does not do, as a
    style a resting object must have), the same in every scene and process (crc32 of the
    category, the size to 0.1 mm and the variant), 31-bit."""
    mm = [round(float(v) * 1e4) for v in size]
    return zlib.crc32(f"{category}|{mm[0]}|{mm[1]}|{mm[2]}|{int(variant)}".encode()) & 0x7FFFFFFF

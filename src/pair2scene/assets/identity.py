"""Asset identity: which stand-in asset an object gets.

Every stage that builds an object's asset (the curation's physics check and support
extraction, the layout model's point clouds, scene assembly) seeds the generator with
:func:`asset_seed` of the object's id, so they all see the same mesh.
"""

from __future__ import annotations

import zlib

__all__ = ["asset_seed"]


def asset_seed(object_id: str, seed: int = 0) -> int:
    """A stable seed for an object's asset: the same object gets the same asset in every
    run and every stage (crc32 of the id, not Python's salted ``hash``), unsigned 32-bit;
    ``seed`` varies it (a run seed mixed in by golden-ratio multiplication)."""
    return (zlib.crc32(object_id.encode("utf-8")) ^ (seed * 0x9E3779B1)) & 0xFFFFFFFF

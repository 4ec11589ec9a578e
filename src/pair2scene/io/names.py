"""Scene ids as file and folder names.

Source scene ids name where a scene came from (``procthor/val/3/room|2``,
``3dfront/<uuid>/MasterBedroom-2``): a ``/`` in one would make nested folders, ``|`` or
``:`` are not portable, ``..`` would climb out of the output folder. :func:`safe_name`
maps an id to one path component; ids that are already safe are kept as they are, so
generated scenes keep their names (``bedroom_0003``).
"""

from __future__ import annotations

import hashlib
import re
from pathlib import Path

SAFE = re.compile(r"[A-Za-z0-9][A-Za-z0-9._-]*")
"""What a name may be as it is: portable file-name characters, not starting with a dot
(hidden files, ``.`` and ``..``) or a dash (read as an option)."""
MAX_NAME = 120
"""Longest name kept as it is (file systems allow 255 bytes; room for suffixes)."""
DIGEST_CHARS = 8
"""Hex digits of the id's digest appended to a changed name, so that two ids that map to
the same characters (``a/b`` and ``a_b``) stay two names."""


def safe_name(scene_id: str) -> str:
    """One portable path component for ``scene_id``: the id itself when it is one
    (:data:`SAFE`, at most :data:`MAX_NAME` characters), else its runs of other characters
    replaced by ``_``, cut to length, and a short digest of the id appended."""
    if SAFE.fullmatch(scene_id) and len(scene_id) <= MAX_NAME:
        return scene_id
    digest = hashlib.sha256(scene_id.encode("utf-8", "surrogatepass")).hexdigest()
    stem = re.sub(r"[^A-Za-z0-9._-]+", "_", scene_id).strip("._-")[:MAX_NAME]
    return f"{stem}-{digest[:DIGEST_CHARS]}" if stem else f"scene-{digest[:DIGEST_CHARS]}"


def scene_folder(out: str | Path, scene_id: str) -> Path:
    """The folder of scene ``scene_id`` under ``out``: ``out/<safe_name(scene_id)>``."""
    return Path(out) / safe_name(scene_id)

"""The tables bundled with the package, in this folder, and the one way to read them.

=====================  =====================  ===============================================
name                   file                   what
=====================  =====================  ===============================================
``hierarchy_stats``    stats.json             support / functional dependency statistics of
                                              the curated train rooms (hierarchy synthesis)
``typical_sizes``      typical_sizes.json     per-category median asset size (m)
``rooms``              rooms.json             training room bounds per room type
``sizes``              sizes.json             observed object sizes per category
``functional_pairs``   functional_pairs.json  commonsense functional pairs (curation)
``room_types``         room_types.json        recipes of room types the training data lacks
                                              (office, study, ...; hierarchy.room_types)
=====================  =====================  ===============================================

:func:`load_table` reads one of them (or a user's file of the same kind, by path) and
checks its ``format`` and ``version`` fields; the functional-pair table is a plain JSON
list a user edits by hand, so it carries neither.
"""

from __future__ import annotations

import json
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from pair2scene.errors import UserError

__all__ = ["TABLES", "Table", "load_table", "table_path"]


@dataclass(frozen=True)
class Table:
    """One bundled table: its file in this folder and the header its documents carry."""

    file: str
    format: str | None
    """The document's ``format`` field; None for a headerless table."""
    version: int | None
    """The supported ``version`` field; None for a headerless table."""


TABLES: dict[str, Table] = {
    "hierarchy_stats": Table("stats.json", "pair2scene.hierarchy_stats", 1),
    "typical_sizes": Table("typical_sizes.json", "pair2scene.typical_sizes", 1),
    "rooms": Table("rooms.json", "pair2scene.rooms", 1),
    "sizes": Table("sizes.json", "pair2scene.sizes", 1),
    "functional_pairs": Table("functional_pairs.json", None, None),
    "room_types": Table("room_types.json", "pair2scene.room_types", 1),
}


def _table(name: str) -> Table:
    try:
        return TABLES[name]
    except KeyError:
        raise ValueError(f"no bundled table {name!r}; known: {', '.join(TABLES)}") from None


def table_path(name: str) -> Path:
    """The bundled file of table ``name`` (a key of :data:`TABLES`)."""
    return Path(__file__).with_name(_table(name).file)


def load_table(name: str, path: str | Path | None = None) -> Any:
    """The JSON document of table ``name``: the bundled file, or ``path`` (a user's file
    of the same kind). A dict for a table with a header, whose ``format`` and ``version``
    are checked; the functional-pair table is a list.

    Every problem (unreadable, not JSON, wrong format or version) is a one-line
    :class:`~pair2scene.errors.UserError` naming the file.
    """
    table = _table(name)
    path = table_path(name) if path is None else Path(path)
    try:
        text = path.read_text(encoding="utf-8")
    except OSError as e:
        raise UserError(f"{path}: cannot read ({e.strerror})") from None
    try:
        doc = json.loads(text)
    except json.JSONDecodeError as e:
        raise UserError(f"{path}: not valid JSON ({e.msg}, line {e.lineno})") from None
    if table.format is None:
        return doc
    if not isinstance(doc, dict) or doc.get("format") != table.format:
        raise UserError(f"{path}: format is not {table.format!r}")
    if doc.get("version") != table.version:
        version = doc.get("version")
        raise UserError(f"{path}: version {version!r} not supported (expected {table.version})")
    return doc

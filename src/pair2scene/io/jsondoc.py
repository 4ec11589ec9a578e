"""Reading the package's own JSON documents: a ``format`` and a ``version`` field, checked."""

from __future__ import annotations

import json
from pathlib import Path

from pair2scene.errors import UserError


def read_json_document(path: str | Path, fmt: str, version: int, missing: str = "missing") -> dict:
    """The JSON object in ``path`` whose ``format`` is ``fmt`` and ``version`` is ``version``.

    Every problem is a one-line :class:`UserError` naming the file: ``missing`` is what is
    said when it does not exist (e.g. a hint at the command that writes it).
    """
    path = Path(path)
    try:
        doc = json.loads(path.read_text(encoding="utf-8"))
    except FileNotFoundError:
        raise UserError(f"{path}: {missing}") from None
    except (OSError, ValueError) as e:
        raise UserError(f"{path}: not readable JSON ({e})") from None
    if not isinstance(doc, dict) or doc.get("format") != fmt:
        raise UserError(f"{path}: format is not {fmt!r}")
    if doc.get("version") != version:
        raise UserError(f"{path}: version {doc.get('version')!r} not supported ({version})")
    return doc

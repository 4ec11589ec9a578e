"""Reading JSON a user gives: bounded, every problem one line naming the file.

:func:`read_json_file` is the one reader of user-supplied JSON (scene.json files,
hierarchy files, ``--stats`` files, the package's own documents). It refuses, with one
:class:`JsonFileError` (a :class:`~pair2scene.errors.UserError`):

- a missing file, a folder, an unreadable file;
- a file over ``max_bytes`` (:data:`MAX_JSON_BYTES`, 64 MiB, unless the caller says
  otherwise; statistics files may have :data:`MAX_STATS_BYTES`, 256 MiB), checked before
  it is read and while reading (a device or a pipe is read at most that far);
- bytes that are not UTF-8, an empty file, text that is not JSON (an integer literal of
  more than Python's 4300 digits included);
- nesting deeper than ``max_depth`` (:data:`MAX_JSON_DEPTH`, 64 levels: ``[[1]]`` is 2).
  Python's parser recurses and gives up near 1000 levels; that is caught, and what it
  parses is then walked without recursion, so any file is refused in time linear in its
  size;
- with ``finite=True`` (the default), ``NaN``, ``Infinity`` and number literals too large
  for a float (``1e999``): a number must be finite. Readers that name the field
  themselves (scene.json) pass ``finite=False`` and check every number.
"""

from __future__ import annotations

import json
import math
import os
import stat
from pathlib import Path
from typing import Any

from pair2scene.errors import UserError

MAX_JSON_BYTES = 64 * 2**20
"""Bytes a JSON file may have unless its reader says otherwise (64 MiB: a scene.json of the
largest scene the contract allows, 10,000 objects, is about 10 MB)."""
MAX_STATS_BYTES = 256 * 2**20
"""Bytes a statistics file (``--stats``) may have: 256 MiB (the bundled one has 0.5 MB)."""
MAX_JSON_DEPTH = 64
"""Levels of nesting a JSON file may have (the package's own files have at most 6)."""


class JsonFileError(UserError):
    """A JSON file that cannot be read: one line, ``<path>: <problem>``.

    ``field`` is ``(file)`` for a problem with the file (missing, a folder, too large, not
    UTF-8, empty) and ``(json)`` for one with its text (not JSON, too deep, not finite);
    ``missing`` tells a file that does not exist."""

    def __init__(self, path: str, field: str, problem: str, missing: bool = False) -> None:
        self.path, self.field, self.problem, self.missing = path, field, problem, missing
        super().__init__(f"{path}: {problem}")


def _mb(n: int) -> str:
    return f"{n / 2**20:.0f} MiB" if n >= 2**20 else f"{n} bytes"


def read_json_text(path: str | Path, what: str, max_bytes: int = MAX_JSON_BYTES) -> str:
    """The UTF-8 text of ``path``, at most ``max_bytes`` bytes; ``what`` names the kind of
    file in messages (``statistics``, ``hierarchy``)."""
    where = str(path)

    def fail(problem: str, missing: bool = False) -> JsonFileError:
        return JsonFileError(where, "(file)", problem, missing)

    try:
        with open(path, "rb") as fh:
            info = os.fstat(fh.fileno())
            if stat.S_ISDIR(info.st_mode):
                raise fail(f"is a directory, not a {what} file")
            if stat.S_ISREG(info.st_mode) and info.st_size > max_bytes:
                raise fail(
                    f"is {_mb(info.st_size)}, over the {_mb(max_bytes)} a {what} file may have"
                )
            data = fh.read(max_bytes + 1)
    except FileNotFoundError:
        raise fail("no such file", missing=True) from None
    except IsADirectoryError:
        raise fail(f"is a directory, not a {what} file") from None
    except OSError as e:
        raise fail(f"cannot read ({e.strerror or e})") from None
    if len(data) > max_bytes:
        raise fail(f"is over the {_mb(max_bytes)} a {what} file may have")
    try:
        text = data.decode("utf-8")
    except UnicodeDecodeError as e:
        raise fail(f"not UTF-8 text (byte {e.start}): not a {what} file") from None
    if not text.strip():
        raise fail("is empty")
    return text


def parse_json(text: str, where: str, max_depth: int = MAX_JSON_DEPTH, finite: bool = True) -> Any:
    """``text`` parsed, nested at most ``max_depth`` levels, its numbers finite when
    ``finite``; a :class:`JsonFileError` naming ``where`` otherwise."""

    def fail(problem: str) -> JsonFileError:
        return JsonFileError(where, "(json)", problem)

    deep = f"nested deeper than {max_depth} levels"
    try:
        doc = json.loads(text)
    except json.JSONDecodeError as e:
        raise fail(f"not valid JSON ({e.msg} at line {e.lineno} column {e.colno})") from None
    except RecursionError:
        raise fail(deep) from None
    except ValueError as e:  # an integer literal over Python's 4300-digit limit
        raise fail(f"not valid JSON ({str(e).splitlines()[0]})") from None
    at = check_tree(doc, max_depth, finite)
    if at is not None:
        depth, field = at
        if depth > max_depth:
            raise fail(deep)
        raise fail(f"{field} is not a finite number (JSON numbers must be finite)")
    return doc


def check_tree(doc: Any, max_depth: int, finite: bool) -> tuple[int, str] | None:
    """The first place (its depth and path) where ``doc`` nests deeper than ``max_depth``
    or (``finite``) holds a NaN or an infinity; None when there is none. Iterative: one
    pass over the values, no recursion."""
    top = type(doc)
    if top is float and finite and not math.isfinite(doc):
        return 0, "(top level)"
    if top is not dict and top is not list:
        return None
    stack: list[tuple[Any, int, tuple | None, Any]] = [(doc, 1, None, None)]
    while stack:
        entry = stack.pop()
        value, depth = entry[0], entry[1]
        if depth > max_depth:
            return depth, _path(entry)
        items = value.items() if type(value) is dict else enumerate(value)
        for key, v in items:
            t = type(v)
            if t is dict or t is list:
                stack.append((v, depth + 1, entry, key))
            elif t is float and finite and not math.isfinite(v):
                return depth, _path((v, depth + 1, entry, key))
    return None


def _path(entry: tuple) -> str:
    """``a.b[2]`` of a stack entry (value, depth, parent entry, key)."""
    keys = []
    while entry is not None and entry[2] is not None:
        keys.append(entry[3])
        entry = entry[2]
    out = ""
    for k in reversed(keys):
        if isinstance(k, int):
            out += f"[{k}]"
        elif k.isidentifier():
            out += f".{k}" if out else k
        else:
            out += f"[{k!r}]"
    if len(out) > 120:  # (a message stays short)
        out = out[:117] + "..."
    return out or "(top level)"


def read_json_file(
    path: str | Path,
    what: str,
    max_bytes: int = MAX_JSON_BYTES,
    max_depth: int = MAX_JSON_DEPTH,
    finite: bool = True,
) -> Any:
    """The JSON value in ``path``, read within the bounds of the module docstring; any
    problem is one :class:`JsonFileError` naming the file. ``what`` names the kind of file
    in messages (``statistics``, ``hierarchy``, ``scene.json``)."""
    text = read_json_text(path, what, max_bytes)
    return parse_json(text, str(path), max_depth, finite)


def read_json_document(
    path: str | Path,
    fmt: str,
    version: int,
    missing: str = "missing",
    max_bytes: int = MAX_JSON_BYTES,
    finite: bool = False,
) -> dict:
    """The JSON object in ``path`` whose ``format`` is ``fmt`` and ``version`` is ``version``,
    read by :func:`read_json_file` (``finite``: refuse NaN and infinities; off by default,
    as the package's own documents, summaries and checkpoints, may hold them).

    Every problem is a one-line :class:`UserError` naming the file: ``missing`` is what is
    said when it does not exist (e.g. a hint at the command that writes it).
    """
    path = Path(path)
    try:
        doc = read_json_file(path, fmt, max_bytes, finite=finite)
    except JsonFileError as e:
        if e.missing:
            raise UserError(f"{path}: {missing}") from None
        raise UserError(f"{path}: not readable JSON ({e.problem})") from None
    if not isinstance(doc, dict) or doc.get("format") != fmt:
        raise UserError(f"{path}: format is not {fmt!r}")
    if doc.get("version") != version:
        shown = repr(doc.get("version"))
        shown = shown if len(shown) <= 40 else shown[:37] + "..."
        raise UserError(f"{path}: version {shown} not supported ({version})")
    return doc

"""Where the package keeps downloaded and derived data."""

from __future__ import annotations

import os
from collections.abc import Callable
from pathlib import Path
from typing import Protocol, TypeVar

CACHE_ENV = "PAIR2SCENE_CACHE"


class _Rooted(Protocol):
    root: Path


T = TypeVar("T", bound=_Rooted)
_PROCESS_WIDE: dict[str, _Rooted] = {}


def cache_dir() -> Path:
    """``$PAIR2SCENE_CACHE``, default ``~/.cache/pair2scene`` (not created here)."""
    env = os.environ.get(CACHE_ENV)
    return Path(env).expanduser() if env else Path.home() / ".cache" / "pair2scene"


def process_wide(folder: str, make: Callable[[Path], T]) -> T:
    """The process's one ``make(cache_dir() / folder)`` (a store with a ``root``), made
    again when :func:`cache_dir` has moved since (another ``$PAIR2SCENE_CACHE``)."""
    root = cache_dir() / folder
    found = _PROCESS_WIDE.get(folder)
    if found is None or found.root != root:
        found = _PROCESS_WIDE[folder] = make(root)
    return found  # type: ignore[return-value]

"""Where the package keeps downloaded and derived data."""

from __future__ import annotations

import os
from pathlib import Path

CACHE_ENV = "PAIR2SCENE_CACHE"


def cache_dir() -> Path:
    """``$PAIR2SCENE_CACHE``, default ``~/.cache/pair2scene`` (not created here)."""
    env = os.environ.get(CACHE_ENV)
    return Path(env).expanduser() if env else Path.home() / ".cache" / "pair2scene"

"""Writing a placed scene: one exporter per file, one table from file name to exporter,
and the scene folder that holds them.

Each exporter is a plain ``export(scene, assets) -> bytes`` over the shared scene
description (:mod:`pair2scene.io.scene_meshes`); formats never use each other's
internals. :func:`write_scene_folder` writes everything into a temporary folder beside
the target and renames it into place, so an interrupted run never leaves a half-written
scene folder.

The temporary folders are hidden: ``.<id>.<random>`` (the new files) and
``.<id>.old.<random>`` (a folder being replaced, as ``x`` inside). Every reader of an
output folder skips names starting with ``.``, and a write that was killed (SIGKILL, a
power cut: nothing runs to remove its folder) leaves one that
:func:`remove_stale_scene_folders` removes, on the next run's start
(:func:`pair2scene.generate.generate_scenes`). It removes a folder only when both its name
has that pattern and it holds nothing but what :func:`write_scene_folder` writes.
"""

from __future__ import annotations

import contextlib
import os
import re
import shutil
import stat
import tempfile
from collections.abc import Callable
from pathlib import Path

from pair2scene.assets.mesh import Asset
from pair2scene.io.atomic import atomic_write_bytes, current_umask, is_temporary
from pair2scene.io.bev import bev_png
from pair2scene.io.glb import glb_bytes
from pair2scene.io.scene_json import dumps_scene
from pair2scene.scene.model import Scene

Exporter = Callable[[Scene, "dict[str, Asset]"], bytes]

SCENE_FILES: dict[str, Exporter] = {
    "scene.json": lambda scene, assets: dumps_scene(scene).encode("utf-8"),
    "scene.glb": glb_bytes,
    "bev.png": bev_png,
}
"""File name in a scene folder -> its exporter."""


OLD_HOLDER = "old."
"""The part of a temporary folder's name that marks a replaced scene folder's holder."""
_TEMP_FOLDER = re.compile(r"\.[A-Za-z0-9][A-Za-z0-9._-]*\.(old\.)?[a-z0-9_]+")
"""A name :func:`write_scene_folder` gives its temporary folders (``.<id>.<random>``,
``.<id>.old.<random>``; ``<id>`` is a :func:`pair2scene.io.names.safe_name`)."""


def write_scene_folder(folder: str | Path, scene: Scene, assets: dict[str, Asset]) -> Path:
    """Write every file of :data:`SCENE_FILES` into ``folder`` atomically (all appear
    together, or the folder is left as it was). The folder gets the mode a plain mkdir
    gives (``0o777`` less the umask), its files what a plain open gives."""
    folder = Path(folder)
    folder.parent.mkdir(parents=True, exist_ok=True)
    tmp = Path(tempfile.mkdtemp(dir=folder.parent, prefix=f".{folder.name}."))
    old: Path | None = None
    try:
        for name, export in SCENE_FILES.items():
            atomic_write_bytes(tmp / name, export(scene, assets))
        os.chmod(tmp, 0o777 & ~current_umask())  # mkdtemp makes 0700
        if folder.exists():
            old = Path(tempfile.mkdtemp(dir=folder.parent, prefix=f".{folder.name}.{OLD_HOLDER}"))
            folder.rename(old / "x")
        tmp.rename(folder)
    except BaseException:
        if old is not None and not folder.exists():  # interrupted between the renames
            with contextlib.suppress(OSError):
                (old / "x").rename(folder)  # the previous folder goes back
        shutil.rmtree(tmp, ignore_errors=True)
        if old is not None:
            shutil.rmtree(old, ignore_errors=True)
        raise
    if old is not None:
        shutil.rmtree(old, ignore_errors=True)
    return folder


def _written_here(folder: str, depth: int = 0) -> bool:
    """Whether ``folder`` holds nothing but what :func:`write_scene_folder` writes: the
    :data:`SCENE_FILES`, their temporary files and (a holder) one replaced scene folder
    ``x``. At most a handful of entries are looked at."""
    allowed = len(SCENE_FILES) * 2 + 1
    try:
        with os.scandir(folder) as it:
            for n, entry in enumerate(it):
                if n >= allowed:
                    return False
                kind = entry.stat(follow_symlinks=False).st_mode
                if stat.S_ISDIR(kind):
                    if depth or entry.name != "x" or not _written_here(entry.path, 1):
                        return False
                elif not stat.S_ISREG(kind) or not (
                    entry.name in SCENE_FILES
                    or any(is_temporary(entry.name, f) for f in SCENE_FILES)
                ):
                    return False
    except OSError:
        return False
    return True


def stale_scene_folders(out: str | Path) -> list[Path]:
    """The temporary folders in ``out`` that interrupted :func:`write_scene_folder` calls
    left: hidden folders (not links) named ``.<id>.<random>`` or ``.<id>.old.<random>``
    that hold only scene files. Anything else, hidden or not, is never listed."""
    found = []
    try:
        entries = sorted(os.scandir(out), key=lambda e: e.name)
    except OSError:
        return found
    for entry in entries:
        if not _TEMP_FOLDER.fullmatch(entry.name):
            continue
        with contextlib.suppress(OSError):
            if entry.is_dir(follow_symlinks=False) and _written_here(entry.path):
                found.append(Path(entry.path))
    return found


def remove_stale_scene_folders(out: str | Path) -> list[str]:
    """Remove :func:`stale_scene_folders` of ``out``; returns their names. Call it only
    while no other process writes scene folders into ``out``."""
    removed = []
    for path in stale_scene_folders(out):
        shutil.rmtree(path, ignore_errors=True)
        if not path.exists():
            removed.append(path.name)
    return removed

"""Writing a placed scene: one exporter per file, one table from file name to exporter,
and the scene folder that holds them.

Each exporter is a plain ``export(scene, assets) -> bytes`` over the shared scene
description (:mod:`pair2scene.io.scene_meshes`); formats never use each other's
internals. :func:`write_scene_folder` writes everything into a temporary folder beside
the target and renames it into place, so an interrupted run never leaves a half-written
scene folder.
"""

from __future__ import annotations

import shutil
import tempfile
from collections.abc import Callable
from pathlib import Path

from pair2scene.assets.mesh import Asset
from pair2scene.io.atomic import atomic_write_bytes
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


def write_scene_folder(folder: str | Path, scene: Scene, assets: dict[str, Asset]) -> Path:
    """Write every file of :data:`SCENE_FILES` into ``folder`` atomically (all appear
    together, or the folder is left as it was)."""
    folder = Path(folder)
    folder.parent.mkdir(parents=True, exist_ok=True)
    tmp = Path(tempfile.mkdtemp(dir=folder.parent, prefix=f".{folder.name}."))
    try:
        for name, export in SCENE_FILES.items():
            atomic_write_bytes(tmp / name, export(scene, assets))
        if folder.exists():
            old = Path(tempfile.mkdtemp(dir=folder.parent, prefix=f".{folder.name}.old."))
            folder.rename(old / "x")
            tmp.rename(folder)
            shutil.rmtree(old, ignore_errors=True)
        else:
            tmp.rename(folder)
    except BaseException:
        shutil.rmtree(tmp, ignore_errors=True)
        raise
    return folder

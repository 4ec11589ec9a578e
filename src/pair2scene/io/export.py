"""Writing a placed scene: one exporter per file, one table from file name to exporter,
and the scene folder that holds them.

Each exporter writes from a :class:`SceneSources`: the scene, its assets and the shared
scene description (:mod:`pair2scene.io.scene_meshes`) worked out once for all of them
(the GLB too, which the viewer page embeds); formats never use each other's internals.
:func:`write_scene_folder` writes everything into a temporary folder beside the target
and renames it into place, so an interrupted run never leaves a half-written scene folder.

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
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from functools import cached_property
from pathlib import Path
from typing import TYPE_CHECKING

from pair2scene.assets.mesh import Asset
from pair2scene.errors import UserError
from pair2scene.io.atomic import atomic_write_bytes, is_temporary, replace_folder
from pair2scene.io.scene_json import dumps_scene
from pair2scene.scene.model import Scene

if TYPE_CHECKING:
    from PIL import Image as PILImage

    from pair2scene.io.scene_meshes import SceneMeshes

DEFAULT_FORMATS = ("json", "glb", "png", "html")
"""What a scene folder holds unless asked otherwise (:attr:`ExportConfig.formats`)."""


@dataclass(frozen=True)
class ExportConfig:
    """What a scene folder holds (``--formats``) and how simulator exports treat bodies
    (``--dynamic``)."""

    formats: str = ",".join(DEFAULT_FORMATS)
    """Comma-separated formats written into each scene folder: json (scene.json, always),
    glb (scene.glb, the room in glTF's y-up frame), png (bev.png, the top view), html
    (scene.html, a self-contained viewer page), mjcf (mjcf/scene.xml and its meshes, for
    MuJoCo, Genesis, robosuite), usd (scene.usdc with UsdPhysics, for Isaac Sim; needs
    ``pair2scene[usd]``), urdf (urdf/: one URDF per object, scene.urdf and
    scene_urdf.json, for PyBullet, SAPIEN, ManiSkill)."""
    dynamic: str = "small"
    """Which objects are free bodies in mjcf, usd and urdf: small (small objects; large
    furniture, fixtures and wall objects fixed), all (everything but fixtures and wall
    objects) or none (everything fixed)."""

    def format_list(self) -> tuple[str, ...]:
        """The formats, checked and in :data:`FORMATS` order (json always among them); an
        unknown one is a one-line :class:`~pair2scene.errors.UserError`."""
        from pair2scene.io.physical import DYNAMIC_CHOICES

        names = {f.strip() for f in self.formats.split(",") if f.strip()}
        bad = sorted(names - set(FORMATS))
        if bad:
            raise UserError(
                f"--formats: unknown {', '.join(bad)} (choose from {', '.join(FORMATS)})"
            )
        if self.dynamic not in DYNAMIC_CHOICES:
            raise UserError(f"--dynamic must be one of {', '.join(DYNAMIC_CHOICES)}")
        if "usd" in names:
            try:
                import pxr  # noqa: F401
            except ImportError:
                raise UserError(
                    "--formats usd needs usd-core: pip install 'pair2scene[usd]'"
                ) from None
        return tuple(f for f in FORMATS if f in names or f == "json")


class SceneSources:
    """What a scene folder's formats are written from: the scene, its assets, which
    bodies the simulator formats leave free, and what several formats draw on (the
    scene's meshes: the GLB and the top view; the GLB: scene.glb and the viewer page),
    each worked out once, when a format first asks."""

    def __init__(self, scene: Scene, assets: dict[str, Asset], dynamic: str = "small") -> None:
        self.scene, self.assets, self.dynamic = scene, assets, dynamic
        self._top_view: Callable[[], PILImage.Image] | None = None

    @cached_property
    def meshes(self) -> SceneMeshes:
        from pair2scene.io.scene_meshes import SceneMeshes

        return SceneMeshes.of(self.scene, self.assets)

    def start_top_view(self) -> None:
        """Start drawing the top view: the renderer draws in its own threads while the
        other formats are written (:meth:`top_view` waits for it)."""
        from pair2scene.io.bev import start_bev

        if self._top_view is None:
            self._top_view = start_bev(self.scene, self.assets, meshes=self.meshes)

    def top_view(self) -> bytes:
        """bev.png's bytes."""
        from pair2scene.io.bev import png_bytes

        self.start_top_view()
        assert self._top_view is not None
        return png_bytes(self._top_view())

    @cached_property
    def glb(self) -> bytes:
        from pair2scene.io.glb import glb_bytes  # (writers load when used: the CLI starts fast)

        return glb_bytes(self.scene, self.assets, self.meshes)


@dataclass(frozen=True)
class Format:
    """One format of a scene folder: the file or folder it makes and how."""

    entry: str
    """Its name in the scene folder."""
    write: Callable[[Path, SceneSources], object]
    """write(path of the entry, what it is written from)."""
    folder: bool = False
    """The entry is a folder (its writer makes it whole, or not at all)."""


def _bytes_format(entry: str, export: Callable[[SceneSources], bytes]) -> Format:
    return Format(entry, lambda path, src: atomic_write_bytes(path, export(src)))


def _html(path: Path, src: SceneSources) -> None:
    from pair2scene.io.viewer import scene_html

    page = scene_html(src.scene, src.assets, back_link=f"../{INDEX_HTML}", glb=src.glb)
    atomic_write_bytes(path, page)


def _mjcf(path: Path, src: SceneSources) -> None:
    from pair2scene.io.mjcf import write_mjcf

    write_mjcf(src.scene, src.assets, path, src.dynamic)


def _usd(path: Path, src: SceneSources) -> None:
    from pair2scene.io.usd import write_usd

    write_usd(src.scene, src.assets, path, src.dynamic)


def _urdf(path: Path, src: SceneSources) -> None:
    from pair2scene.io.urdf import write_urdf

    write_urdf(src.scene, src.assets, path, src.dynamic)


FORMATS: dict[str, Format] = {
    "json": _bytes_format("scene.json", lambda src: dumps_scene(src.scene).encode("utf-8")),
    "glb": _bytes_format("scene.glb", lambda src: src.glb),
    "png": _bytes_format("bev.png", lambda src: src.top_view()),
    "html": Format("scene.html", _html),
    "mjcf": Format("mjcf", _mjcf, folder=True),
    "usd": Format("scene.usdc", _usd),
    "urdf": Format("urdf", _urdf, folder=True),
}
"""Format name -> what it writes into a scene folder (:class:`ExportConfig` says which)."""
INDEX_HTML = "index.html"
"""The gallery of an output folder (:func:`pair2scene.io.viewer.write_index`), which each
scene.html links back to."""
SCENE_ENTRIES = frozenset(f.entry for f in FORMATS.values())
"""Every name a scene folder may hold."""
FOLDER_ENTRIES = frozenset(f.entry for f in FORMATS.values() if f.folder)
_TEMP_ENTRY = re.compile(
    r"\.(" + "|".join(re.escape(e) for e in sorted(SCENE_ENTRIES)) + r")\.(old\.)?[a-z0-9_]+"
)
"""A temporary folder a format's writer makes beside its entry while writing."""


_TEMP_FOLDER = re.compile(r"\.[A-Za-z0-9][A-Za-z0-9._-]*\.(old\.)?[a-z0-9_]+")
"""A name :func:`write_scene_folder` gives its temporary folders (``.<id>.<random>``,
``.<id>.old.<random>``; ``<id>`` is a :func:`pair2scene.io.names.safe_name`)."""


def write_scene_folder(
    folder: str | Path,
    scene: Scene,
    assets: dict[str, Asset],
    formats: Sequence[str] = DEFAULT_FORMATS,
    dynamic: str = "small",
) -> Path:
    """Write the ``formats`` (names of :data:`FORMATS`; scene.json always) into ``folder``
    atomically (all appear together, or the folder is left as it was). The folder gets the
    mode a plain mkdir gives (``0o777`` less the umask), its files what a plain open
    gives. ``dynamic``: the free bodies of the simulator formats."""

    src = SceneSources(scene, assets, dynamic)

    def fill(tmp: Path) -> None:
        names = list(dict.fromkeys(["json", *formats]))
        if "png" in names:  # drawn while the others are written; written last
            src.start_top_view()
            names.append(names.pop(names.index("png")))
        for name in names:
            form = FORMATS[name]
            form.write(tmp / form.entry, src)

    return replace_folder(folder, fill)


def _written_here(folder: str, depth: int = 0) -> bool:
    """Whether ``folder`` holds nothing but what :func:`write_scene_folder` writes: the
    :data:`FORMATS`' entries, their writers' temporary files and folders and (a holder)
    one replaced scene folder ``x``. At most a handful of entries are looked at; the
    simulator formats' folders are not looked into."""
    allowed = len(SCENE_ENTRIES) * 2 + 1
    try:
        with os.scandir(folder) as it:
            for n, entry in enumerate(it):
                if n >= allowed:
                    return False
                kind = entry.stat(follow_symlinks=False).st_mode
                if stat.S_ISDIR(kind):
                    if entry.name == "x" and not depth:
                        if not _written_here(entry.path, 1):
                            return False
                    elif not (entry.name in FOLDER_ENTRIES or _TEMP_ENTRY.fullmatch(entry.name)):
                        return False
                elif not stat.S_ISREG(kind) or not (
                    entry.name in SCENE_ENTRIES
                    or any(is_temporary(entry.name, f) for f in SCENE_ENTRIES)
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


def export_scene(
    source: str | Path,
    formats: Sequence[str],
    dynamic: str = "small",
    out: str | Path | None = None,
) -> Path:
    """Add ``formats`` to a scene written earlier: ``source`` is a scene folder (its
    scene.json) or a scene.json file; the files go beside it (or into ``out``). The assets
    are rebuilt from scene.json (exactly the generated ones: scene.json records each
    object's generator seed). Each entry is written atomically; scene.json itself is left
    as it is. Returns the folder written to."""
    from pair2scene.assembly.keep import keep_assets
    from pair2scene.io.scene_json import read_scene

    source = Path(source)
    path = source / FORMATS["json"].entry if source.is_dir() else source
    if not path.is_file():
        raise UserError(f"{source}: no scene.json there")
    scene = read_scene(path)
    folder = Path(out) if out is not None else path.parent
    folder.mkdir(parents=True, exist_ok=True)
    src = SceneSources(scene, keep_assets(scene), dynamic)
    for name in formats:
        if name == "json" and out is None:
            continue  # it is the source
        form = FORMATS[name]
        form.write(folder / form.entry, src)
    return folder

"""Source specs on the command line (``ai2thor``, ``procthor:PATH``, ``3dfront:PATH``,
``scenes:DIR``)."""

from __future__ import annotations

from pair2scene.data.base import SPLITS, Corpus
from pair2scene.errors import UserError

SOURCE_FORMS = "ai2thor, procthor:PATH, 3dfront:PATH or scenes:DIR (a folder of scene.json files)"
SOURCE_KINDS = ("ai2thor", "procthor", "3dfront", "scenes")
"""What a source spec may start with (before its ``:``)."""


def source_kind(spec: str) -> str:
    """The kind of a source spec (``procthor:PATH`` -> ``procthor``), lower case; an
    unknown one is returned as it is."""
    return spec.partition(":")[0].strip().lower()


def load_source(spec: str, split: str | None = None, progress: bool = False) -> Corpus:
    """Load every scene of a source spec, or of one split of it."""
    if split is not None and split not in SPLITS:
        raise UserError(f"unknown split {split!r}: use {' or '.join(SPLITS)}")
    kind, path = source_kind(spec), spec.partition(":")[2]
    if kind == "ai2thor" and not path:
        from pair2scene.data.ai2thor import load_ai2thor

        return load_ai2thor(split=split, progress=progress)
    if kind in ("procthor", "3dfront", "scenes") and not path:
        raise UserError(f"source {kind!r} needs a path: {kind}:PATH")
    if kind == "procthor":
        from pair2scene.data.procthor import load_procthor

        return load_procthor(path, split=split, progress=progress)
    if kind == "3dfront":
        from pair2scene.data.front3d import load_front3d

        return load_front3d(path, split=split, progress=progress)
    if kind == "scenes":
        from pair2scene.data.scene_folder import load_scene_dir

        return load_scene_dir(path, split=split, progress=progress)
    raise UserError(f"unknown source {spec!r}: use {SOURCE_FORMS}")

"""A folder of scene.json files, the project's own format, as a source: ``scenes:DIR``.

Your own rooms, written by any tool in the scene.json contract (README, "scene.json") or
by ``pair2scene generate``, go through ``curate`` and ``data stats`` like the bundled
sources. The files are read as :func:`pair2scene.evaluate.scene_files` finds them
(``DIR/<id>/scene.json`` or ``DIR/*.json``; hidden names, such as the temporary folder a
killed ``generate`` left, are skipped); a file that breaks the contract stops the read
with its one line. A scene keeps the split its file gives (``"split": "train"`` or
``"val"``); one without is split by a hash of its id, :data:`VAL_FRACTION` to val, as the
ProcTHOR adapter splits houses.
"""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path

from pair2scene.data.base import SPLITS, Corpus, SourceReport, stable_fraction
from pair2scene.errors import UserError

VAL_FRACTION = 0.2
"""Share of the scenes without a split of their own that go to val."""


def load_scene_dir(path: str | Path, split: str | None = None, progress: bool = False) -> Corpus:
    """Every scene of the folder ``path`` (only those of ``split`` when given)."""
    from pair2scene.categories import BY_NAME
    from pair2scene.evaluate import scene_files
    from pair2scene.io.scene_json import read_scene
    from pair2scene.progress import track

    report = SourceReport()
    scenes = []
    seen: dict[str, Path] = {}
    files = scene_files(path)
    for f in track(files, f"scenes {Path(path).name}", progress, total=len(files)):
        scene = read_scene(f)
        if scene.id in seen:
            raise UserError(f"{f}: scene id {scene.id!r} is also {seen[scene.id]}'s")
        seen[scene.id] = f
        own = scene.split if scene.split in SPLITS else None
        if own is None:
            own = "val" if stable_fraction(scene.id) < VAL_FRACTION else "train"
        if split is not None and own != split:
            continue
        for o in scene.objects:
            counts = report.mapped_labels if o.category in BY_NAME else report.unknown_labels
            counts[o.category] += 1
        scenes.append(replace(scene, split=own))
    return Corpus(f"scenes:{path}", scenes, report)

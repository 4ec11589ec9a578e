"""``summary.json``: what ``pair2scene generate`` wrote into an output folder, per scene,
and the request that made it (a rerun of the same request resumes; another is refused).

A summary is checked as it is read (:func:`read_summary`): a file in another shape (a
field of the wrong type, a scene record without the figures the totals are computed from)
stops a resume and an evaluation with one line naming the file and the field, and the
hint to delete it or choose another output folder. It is never silently replaced: the
scenes it records would be lost from the totals.
"""

from __future__ import annotations

import json
import math
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from pair2scene.errors import UserError
from pair2scene.io.atomic import atomic_write_text
from pair2scene.io.jsondoc import read_json_document

SUMMARY_FORMAT = "pair2scene.summary"
SUMMARY_VERSION = 1
SUMMARY_FILE = "summary.json"


@dataclass
class Summary:
    """An output folder's summary: the request, one record per scene written (sorted by
    id; each :meth:`pair2scene.generate.SceneStats.to_dict` with its ``id``) and, once a
    run ends, the totals."""

    request: dict
    scenes: dict[str, dict] = field(default_factory=dict)
    """scene id -> its record."""
    totals: dict | None = None
    """Means over the scenes (:meth:`compute_totals`); None while a run is under way."""
    kept: int = 0
    """Scenes of this run's request an earlier run had already written, kept as they were
    (not in summary.json: a property of the run, not of the folder)."""

    def to_dict(self) -> dict:
        out = {"format": SUMMARY_FORMAT, "version": SUMMARY_VERSION, "request": self.request,
               "scenes": [self.scenes[k] for k in sorted(self.scenes)]}  # fmt: skip
        if self.totals is not None:
            out["totals"] = self.totals
        return out

    def add(self, record: dict) -> None:
        self.scenes[record["id"]] = record

    def compute_totals(self) -> dict:
        """Scenes, objects per scene, acceptance, resamples per object, seconds per scene
        (means over the scenes; {} without any)."""
        scenes = list(self.scenes.values())
        if not scenes:
            return {}

        def mean(key: str) -> float:
            return round(float(np.mean([s[key] for s in scenes])), 4)

        return {
            "scenes": len(scenes),
            "objects_per_scene": mean("objects_placed"),
            "acceptance_rate": mean("acceptance_rate"),
            "resamples_per_object": mean("resamples_per_object"),
            "seconds_per_scene": round(
                float(np.mean([s["seconds"]["total"] for s in scenes])), 4
            ),  # fmt: skip
        }

    def write(self, out: str | Path) -> None:
        """``out/summary.json``, atomically."""
        atomic_write_text(Path(out) / SUMMARY_FILE, json.dumps(self.to_dict(), indent=1) + "\n")


RECORD_NUMBERS = ("objects_placed", "acceptance_rate", "resamples_per_object")
"""The figures every scene record has (numbers), besides ``id`` and ``seconds.total``:
what the totals and an evaluation's process figures are computed from."""
_HINT = "not a summary pair2scene generate wrote: delete it, or choose another --out"


def _number(value: object) -> bool:
    return isinstance(value, int | float) and not isinstance(value, bool) and math.isfinite(value)


def _check_record(path: Path, i: int, record: object) -> None:
    """One line naming the file and the field when scene record ``i`` is not one
    :meth:`Summary.add` was given."""
    where = f"{path}: scenes[{i}]"
    if not isinstance(record, dict):
        raise UserError(f"{where}: must be an object ({_HINT})")
    if not isinstance(record.get("id"), str) or not record["id"]:
        raise UserError(f"{where}.id: must be a scene id ({_HINT})")
    for key in RECORD_NUMBERS:
        if not _number(record.get(key)):
            raise UserError(f"{where}.{key}: must be a number ({_HINT})")
    seconds = record.get("seconds")
    if not isinstance(seconds, dict) or not _number(seconds.get("total")):
        raise UserError(f"{where}.seconds.total: must be a number ({_HINT})")


def read_summary(folder: str | Path) -> Summary | None:
    """``folder/summary.json``, checked, or None when there is none; one-line errors for a
    file in another shape (naming the file and the field)."""
    path = Path(folder) / SUMMARY_FILE
    if not path.is_file():
        return None
    doc = read_json_document(path, SUMMARY_FORMAT, SUMMARY_VERSION)
    request, scenes = doc.get("request"), doc.get("scenes")
    if not isinstance(request, dict):
        raise UserError(f"{path}: request: must be an object ({_HINT})")
    if not isinstance(scenes, list):
        raise UserError(f"{path}: scenes: must be a list of records with an id ({_HINT})")
    for i, record in enumerate(scenes):
        _check_record(path, i, record)
    totals = doc.get("totals")
    if totals is not None and not isinstance(totals, dict):
        raise UserError(f"{path}: totals: must be an object ({_HINT})")
    return Summary(request, {s["id"]: s for s in scenes}, totals)


def resume_summary(out: str | Path, request: dict) -> Summary:
    """The summary to continue in ``out``: its own when it holds the same request, a new
    one when there is none; another request's folder is refused."""
    summary = read_summary(out)
    if summary is None:
        return Summary(request)
    if summary.request != request:
        raise UserError(f"{out} holds scenes of another request; choose another --out")
    summary.totals = None
    return summary

"""The main job: hierarchy -> placement -> scene folders. ``pair2scene generate`` calls it.

>>> from pair2scene import Pair2Scene
>>> p2s = Pair2Scene.from_pretrained()            # bundled model, statistics, sizes, rooms
>>> result = p2s.generate(room="bedroom", seed=0)
>>> result.scene.objects[0].box                    # the placed scene (pair2scene.scene)

:func:`generate_scenes` writes ``OUT/<scene_id>/{scene.json, scene.glb, bev.png}`` per
scene and ``OUT/summary.json`` with every scene's statistics; run again with the same
arguments it skips the scenes already written (resume), and gives the same files.
"""

from __future__ import annotations

import json
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from pair2scene.assembly.place import AssemblyConfig, Placer
from pair2scene.assembly.rooms import RoomTable, make_room
from pair2scene.assembly.sizes import SizeTable
from pair2scene.errors import UserError
from pair2scene.hierarchy.build import build_hierarchy, room_key
from pair2scene.hierarchy.synthesis import load_stats
from pair2scene.hierarchy.tree import Hierarchy
from pair2scene.io.atomic import atomic_write_text
from pair2scene.io.jsondoc import read_json_document
from pair2scene.scene.model import Scene

SUMMARY_FORMAT = "pair2scene.summary"
SUMMARY_VERSION = 1


@dataclass
class Generated:
    """One generated scene and what made it."""

    scene: Scene
    hierarchy: Hierarchy
    assets: dict
    """object id -> asset (what scene.glb shows and physics would simulate)."""
    stats: dict = field(default_factory=dict)


class Pair2Scene:
    """The generator: a layout model, hierarchy statistics, size and room tables."""

    def __init__(self, model, stats=None, sizes=None, rooms=None, config=None) -> None:
        self.model = model
        self.stats = load_stats() if stats is None else stats
        self.rooms = RoomTable.load() if rooms is None else rooms
        self.placer = Placer(model, SizeTable.load() if sizes is None else sizes, config,
                             sup_dep=self.stats.sup_dep)  # fmt: skip

    @classmethod
    def from_pretrained(
        cls, model: str | Path | None = None, config: AssemblyConfig | None = None
    ) -> Pair2Scene:
        """The bundled model (or a checkpoint folder) with the bundled tables."""
        from pair2scene.model import from_pretrained

        spec = None if model in (None, "default") else model
        return cls(from_pretrained(spec), config=config)

    def generate(
        self,
        room: str | None = None,
        text: str | None = None,
        seed: int = 0,
        mode: str = "fit",
        max_objects: int | None = None,
        llm: str = "auto",
        scene_id: str | None = None,
    ) -> Generated:
        """One scene for a room type or a description; same arguments, same scene."""
        hierarchy = build_hierarchy(
            None if room is None else room_key(room), text, mode, max_objects, seed,
            self.stats, llm,
        )  # fmt: skip
        room_obj = make_room(hierarchy.room_type, np.random.default_rng([seed, 1]), self.rooms)
        sid = scene_id or f"{hierarchy.room_type}_{seed:04d}"
        placement = self.placer.place(hierarchy, room_obj, seed=seed, scene_id=sid)
        stats = placement.stats.to_dict()
        stats["hierarchy_notes"] = list(hierarchy.notes)
        stats["mode"] = mode
        stats["seed"] = seed
        # Timings vary from run to run: summary.json has them, scene.json must not, so that
        # the same seed gives a byte-identical scene.json.
        placement.scene.stats = {k: v for k, v in stats.items() if k != "seconds"}
        return Generated(placement.scene, hierarchy, placement.assets, stats)


def generate_scenes(
    out: str | Path,
    room: str | None = None,
    text: str | None = None,
    num: int = 1,
    seed: int = 0,
    mode: str = "fit",
    max_objects: int | None = None,
    model: str = "default",
    llm: str = "auto",
    progress: bool = True,
) -> dict:
    """``num`` scenes (seeds ``seed`` .. ``seed + num - 1``) into ``out``; returns the
    summary (also written as ``out/summary.json``). Scenes already in ``out`` from an
    earlier run of the same request are kept, not regenerated."""
    from pair2scene.assembly.export import write_scene_folder
    from pair2scene.progress import track

    if (room is None) == (text is None):
        raise UserError("give exactly one of --room or --text")
    if num < 1:
        raise UserError("--num must be >= 1")
    out = Path(out)
    if out.exists() and not out.is_dir():
        raise UserError(f"{out}: exists and is not a folder")
    request = {"room": room, "text": text, "mode": mode, "max_objects": max_objects,
               "model": str(model), "llm": llm}  # fmt: skip
    summary = _read_summary(out, request)
    p2s = Pair2Scene.from_pretrained(model)
    # A bad room type or text fails here, in one line, before any progress is shown.
    build_hierarchy(None if room is None else room_key(room), text, mode, max_objects, seed,
                    p2s.stats, llm)  # fmt: skip
    done = {s["id"]: s for s in summary["scenes"]}
    for i in track(range(num), "generating", enabled=progress):
        s = seed + i
        prefix = room_key(room) if room is not None else "text"
        sid = f"{prefix}_{s:04d}"
        if sid in done and (out / sid / "scene.json").is_file():
            continue
        result = p2s.generate(room, text, s, mode, max_objects, llm, scene_id=sid)
        write_scene_folder(out / sid, result.scene, result.assets)
        done[sid] = {"id": sid, **result.stats}
        summary["scenes"] = [done[k] for k in sorted(done)]
        _write_summary(out, summary)
    summary["scenes"] = [done[k] for k in sorted(done)]
    summary["totals"] = _totals(summary["scenes"])
    _write_summary(out, summary)
    return summary


def _read_summary(out: Path, request: dict) -> dict:
    path = out / "summary.json"
    if not path.exists():
        return {"format": SUMMARY_FORMAT, "version": SUMMARY_VERSION, "request": request,
                "scenes": []}  # fmt: skip
    doc = read_json_document(path, SUMMARY_FORMAT, SUMMARY_VERSION)
    if doc.get("request") != request:
        raise UserError(f"{out} holds scenes of another request; choose another --out")
    return doc


def _write_summary(out: Path, summary: dict) -> None:
    atomic_write_text(out / "summary.json", json.dumps(summary, indent=1) + "\n")


def _totals(scenes: list[dict]) -> dict:
    if not scenes:
        return {}

    def mean(key: str) -> float:
        return round(float(np.mean([s[key] for s in scenes])), 4)

    return {
        "scenes": len(scenes),
        "objects_per_scene": mean("objects_placed"),
        "acceptance_rate": mean("acceptance_rate"),
        "resamples_per_object": mean("resamples_per_object"),
        "seconds_per_scene": round(float(np.mean([s["seconds"]["total"] for s in scenes])), 4),
    }

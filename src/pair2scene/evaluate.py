"""The evaluation harness: a folder of generated scenes against a set of real rooms.

``pair2scene evaluate --scenes DIR --reference ai2thor:val --out report.json`` calls
:func:`evaluate`. DIR is what ``pair2scene generate`` wrote (``DIR/<id>/scene.json`` and
``DIR/summary.json``), or any folder of scene.json files (other tools' scenes: the
process figures are then missing). The report has, at the top level:

- physical (:mod:`pair2scene.metrics.physical`, mesh level, each scene's own assets
  rebuilt exactly from scene.json): ``collision_rate`` and ``floating_rate`` (share of
  all objects), ``stability`` (share of the simulated objects that move < 2 cm in 2 s);
- process (from summary.json): ``acceptance_rate``, ``resamples_per_object``,
  ``objects_per_scene``, ``seconds_per_scene``;
- distribution (:mod:`pair2scene.metrics.distribution`): ``category_kl``,
  ``pose_mmd``;
- images (:mod:`pair2scene.metrics.topview`, :mod:`~pair2scene.metrics.fid`,
  :mod:`~pair2scene.metrics.sca`): ``fid``, ``kid`` (x 1e-3) and ``sca`` on 256 x 256
  top views rendered identically for both sets.

Beside these, one section per entry of :data:`SECTIONS`, each a table of measures that
real rooms get too, side by side: ``layout`` (:mod:`pair2scene.metrics.layout`: furniture
against walls, chairs facing their table, sofas facing the TV, nightstands at the bed's
head), ``navigation`` (:mod:`pair2scene.scene.navigation`: reachable floor, fronts and
doors) and ``walls`` (:mod:`pair2scene.metrics.wall_objects`: wall objects and windows
per room, each wall category's share), as ``{measure: {"generated": stat, "reference":
stat}}`` with ``stat`` = ``{"rate", "count": [numerator, denominator], "rooms"}`` (rooms
it was measurable in). Each row also says whether the two differ by more than sampling
noise (:mod:`pair2scene.metrics.significance`): ``p_value`` of a two-sided exact test
(``test``: ``fisher`` for shares, ``poisson`` for counts per room) and, for shares, 95 %
Wilson intervals ``generated_ci`` and ``reference_ci``.

The reference is filtered to the room types of the generated scenes. Per-scene physics
is cached beside the report (``<out>.cache.json``, keyed by each scene.json's digest),
so an interrupted evaluation resumes where it stopped.
"""

from __future__ import annotations

import hashlib
import json
import time
from collections import Counter
from collections.abc import Callable, Sequence
from pathlib import Path

import numpy as np

from pair2scene.errors import UserError
from pair2scene.io.atomic import atomic_write_text
from pair2scene.metrics.significance import add_tests
from pair2scene.scene.model import Scene

REPORT_FORMAT = "pair2scene.evaluation"
REPORT_VERSION = 1
CACHE_FORMAT = "pair2scene.evaluation_cache.2"  # bumped when a metric changes
SPLITS = ("train", "val")
SMALL_SET = 20
"""Fewer scenes than this in a set: the image metrics come with a note."""
MIN_SCA_IMAGES = 10
"""Fewer scenes than this in either set: no SCA (5-fold cross-validation needs a few
images per fold and class)."""
REFERENCE_FORMS = "ai2thor[:val], procthor:PATH[:val], 3dfront:PATH[:val] or a scene folder"


# -- inputs ----------------------------------------------------------------------------
def scene_files(folder: str | Path) -> list[Path]:
    """Every scene.json under ``folder`` (``folder/<id>/scene.json``, deeper folders of
    older writers whose ids held a ``/``, or ``folder/*.json``), sorted. Hidden folders
    (an interrupted write's temporary ``.<id>.*``) are not scenes."""
    folder = Path(folder)
    if not folder.is_dir():
        raise UserError(f"{folder}: no such folder")

    def visible(p: Path) -> bool:
        return not any(part.startswith(".") for part in p.relative_to(folder).parts)

    files = sorted(p for p in folder.rglob("scene.json") if visible(p) and p.is_file())
    if not files:
        files = sorted(p for p in folder.glob("*.json") if p.name != "summary.json"
                       and visible(p))  # fmt: skip
    if not files:
        raise UserError(f"{folder}: no scene.json files (expected {folder}/<id>/scene.json)")
    return files


def load_scene_folder(folder: str | Path) -> list[Scene]:
    """The scenes of a folder (:func:`scene_files`); a bad file stops with its one line."""
    from pair2scene.io.scene_json import read_scene

    return [read_scene(p) for p in scene_files(folder)]


def read_summary(folder: str | Path) -> dict | None:
    """``folder/summary.json`` as pair2scene generate wrote it, or None when absent."""
    from pair2scene.io.summary import read_summary as read

    summary = read(folder)
    return None if summary is None else summary.to_dict()


def parse_reference(spec: str) -> tuple[str, str | None]:
    """``ai2thor:val`` -> ("ai2thor", "val"); ``procthor:PATH:val`` -> ("procthor:PATH",
    "val"); a spec without a split suffix -> (spec, None) (every room)."""
    head, _, tail = spec.rpartition(":")
    if head and tail in SPLITS:
        return head, tail
    return spec, None


def load_reference(
    specs: Sequence[str], room_types: Sequence[str] | None = None, progress: bool = False
) -> list[Scene]:
    """The real rooms of every spec (a source with an optional split, or a folder of
    scene.json files), only those of ``room_types`` when given."""
    from pair2scene.data.sources import SOURCE_KINDS, load_source, source_kind

    if not specs:
        raise UserError(f"give at least one --reference ({REFERENCE_FORMS})")
    scenes: list[Scene] = []
    for spec in specs:
        if Path(spec).is_dir():
            scenes += load_scene_folder(spec)
            continue
        source, split = parse_reference(spec)
        kind = source_kind(source)
        if kind not in SOURCE_KINDS or (kind == "ai2thor" and ":" in source):
            raise UserError(f"--reference {spec}: unknown source; use {REFERENCE_FORMS}")
        try:
            scenes += load_source(source, split=split, progress=progress).scenes
        except UserError as e:  # the form was right: what was wrong is in the message
            raise UserError(f"--reference {spec}: {e}") from None
    if room_types is not None:
        wanted = set(room_types)
        scenes = [s for s in scenes if s.room.type in wanted]
        if not scenes:
            raise UserError(
                f"the reference has no {' or '.join(sorted(wanted))} rooms; "
                f"give a reference with that room type"
            )
    return scenes


# -- per-scene physics, cached ---------------------------------------------------------
def _digest(path: Path) -> str:
    return hashlib.sha256(path.read_bytes()).hexdigest()[:16]


def _read_cache(path: Path) -> dict:
    try:
        doc = json.loads(path.read_text(encoding="utf-8"))
    except (OSError, ValueError):
        return {}
    return doc.get("scenes", {}) if doc.get("format") == CACHE_FORMAT else {}


def physical_per_scene(
    files: Sequence[Path], cache: Path | None, simulate: bool = True, progress: bool = True
) -> dict[str, dict]:
    """scene file -> its :func:`~pair2scene.metrics.physical.physical_report` (without
    the per-object lists' bulk), computed once per scene.json content."""
    from pair2scene.assembly.keep import keep_assets
    from pair2scene.io.scene_json import read_scene
    from pair2scene.metrics.physical import physical_report
    from pair2scene.progress import track

    done = _read_cache(cache) if cache is not None else {}
    out: dict[str, dict] = {}
    for path in track(files, "physics", enabled=progress):
        key = f"{path.parent.name}/{path.name}:{_digest(path)}:{int(simulate)}"
        if key not in done:
            scene = read_scene(path)
            t0 = time.perf_counter()
            report = physical_report(scene, keep_assets(scene), simulate=simulate)
            report["seconds"] = round(time.perf_counter() - t0, 3)
            done[key] = report
            if cache is not None:
                atomic_write_text(cache, json.dumps({"format": CACHE_FORMAT, "scenes": done}))
        out[str(path)] = done[key]
    return out


def _pooled(reports: Sequence[dict]) -> dict:
    objects = sum(r["objects"] for r in reports)
    inter = sum(len(r["intersecting"]) for r in reports)
    flo = sum(len(r["floating"]) for r in reports)
    out = {
        "collision_rate": inter / objects if objects else 0.0,
        "floating_rate": flo / objects if objects else 0.0,
        "stability": None,
    }
    sim = [r for r in reports if r.get("stability") is not None]
    if sim:
        simulated = sum(r["simulated"] for r in sim)
        moved = sum(len(r["unstable"]) for r in sim)
        out["stability"] = 1.0 - moved / simulated if simulated else 1.0
        out["stability_failed_scenes"] = len(reports) - len(sim)
    return out


# -- the harness -----------------------------------------------------------------------
def _process(summary: dict | None, scenes: Sequence[Scene]) -> dict:
    out = {
        "acceptance_rate": None,
        "resamples_per_object": None,
        "objects_per_scene": float(np.mean([len(s.objects) for s in scenes])),
        "seconds_per_scene": None,
    }
    if summary is None:
        return out
    rows = summary.get("scenes", [])
    ids = {s.id for s in scenes}
    rows = [r for r in rows if r.get("id") in ids] or rows
    if rows:
        out["acceptance_rate"] = float(np.mean([r["acceptance_rate"] for r in rows]))
        out["resamples_per_object"] = float(np.mean([r["resamples_per_object"] for r in rows]))
        out["seconds_per_scene"] = float(np.mean([r["seconds"]["total"] for r in rows]))
    return out


def _counted_only(scene: Scene) -> Scene:
    """The scene without structure and furniture parts (drawers, shelves as objects):
    generated scenes have neither, and a drawer's box drawn over its dresser is an artefact
    of how the source annotates, not a difference in layout."""
    from dataclasses import replace

    from pair2scene.metrics.distribution import counted

    return replace(scene, objects=[o for o in scene.objects if counted(o)])


def image_metrics(
    reference: Sequence[Scene],
    generated: Sequence[Scene],
    seed: int = 0,
    threads: int | None = None,
    sca_repeats: int | None = None,
) -> dict:
    """FID, KID (x 1e-3) and SCA of the two sets' top views; ``threads``: torch threads
    for the networks (default: torch's); ``sca_repeats``: repeats of SCA's k-fold
    cross-validation (default :data:`~pair2scene.metrics.sca.REPEATS`)."""
    from pair2scene.metrics.fid import InceptionFeatures, fid, kid
    from pair2scene.metrics.sca import REPEATS, sca
    from pair2scene.metrics.topview import topview_batch

    real = topview_batch([_counted_only(s) for s in reference])
    fake = topview_batch([_counted_only(s) for s in generated])
    net = InceptionFeatures(threads=threads)
    fr, fg = net.features(real), net.features(fake)
    kid_mean, kid_std = kid(fr, fg, seed=seed)
    if min(len(real), len(fake)) >= MIN_SCA_IMAGES:
        result = sca(real, fake, seed=seed, threads=threads or 1,
                     repeats=REPEATS if sca_repeats is None else sca_repeats)  # fmt: skip
    else:
        result = {"accuracy": None, "note": f"SCA needs {MIN_SCA_IMAGES} scenes in each set"}
    return {
        "fid": fid(fr, fg),
        "kid": kid_mean * 1e3,
        "kid_std": kid_std * 1e3,
        "sca": result["accuracy"],
        "sca_detail": result,
    }


def _layout(reference: Sequence[Scene], generated: Sequence[Scene]) -> dict:
    from pair2scene.metrics.layout import layout_section

    return layout_section(reference, generated)


def _navigation(reference: Sequence[Scene], generated: Sequence[Scene]) -> dict:
    """Navigability (:mod:`pair2scene.scene.navigation`, agent radius 0.2 m): the mean
    reachable share of the free floor, rooms reaching 0.97 of it, floor objects whose front
    is reachable, doors whose swing is clear; and the pooled details of both sides."""
    from pair2scene.scene.navigation import navigation_report

    sides = {"generated": navigation_report(generated), "reference": navigation_report(reference)}

    def stat(pooled: dict, rate: str, n: str | None, d: str) -> dict:
        rooms = pooled.get("rooms", 0)
        value = pooled.get(rate) if rooms else None
        total = pooled.get(d, 0) or 0
        count = None
        if n is not None and value is not None:
            count = [round(value * total) if n == "share" else total - pooled[n], total]
        return {"rate": value, "count": count, "rooms": rooms}

    rows = {
        "reachable_free_floor": ("mean_reachable_fraction", None, "rooms"),
        "rooms_reachable_0.97": ("share_rooms_reachable", "share", "rooms"),
        "objects_reachable": ("share_objects_reachable", "unreachable_objects", "floor_objects"),
        "doors_clear": ("share_doors_clear", "share", "rooms_with_doors"),
    }
    out: dict = {
        name: {side: stat(sides[side]["all"], *spec) for side in ("generated", "reference")}
        for name, spec in rows.items()
    }
    out["pooled"] = {f"{side} rooms": pooled for side, pooled in sides.items()}  # not a row
    return out


def _walls(reference: Sequence[Scene], generated: Sequence[Scene]) -> dict:
    from pair2scene.metrics.wall_objects import wall_section

    return wall_section(reference, generated)


Section = Callable[[Sequence[Scene], Sequence[Scene]], dict]
SECTIONS: dict[str, Section] = {
    "layout": _layout,
    "navigation": _navigation,
    "walls": _walls,
}
"""The report's sections of side-by-side measures: name -> function(reference, generated)
giving ``{measure: {"generated": stat, "reference": stat}}`` (other entries are details
the CLI does not print); each becomes ``report[name]`` and a table of the CLI."""
PER_ROOM = frozenset({"wall_objects_per_room", "windows_per_room"})
"""Rows of :data:`SECTIONS` that count things per room (k in n rooms), not shares of
things (k of n): tested as Poisson rates, not by Fisher's test."""


def evaluate(
    scenes: str | Path,
    references: Sequence[str],
    out: str | Path | None = None,
    physics: bool = True,
    simulate: bool = True,
    images: bool = True,
    seed: int = 0,
    progress: bool = True,
    threads: int | None = None,
    sca_repeats: int | None = None,
) -> dict:
    """Every metric of a folder of generated scenes against the reference rooms of the
    same types; written to ``out`` (JSON, atomically) when given. ``sca_repeats``:
    repeats of SCA's cross-validation (:func:`~pair2scene.metrics.sca.sca`)."""
    from pair2scene.io.scene_json import read_scene
    from pair2scene.metrics.distribution import category_kl, pose_mmd

    t0 = time.perf_counter()
    files = scene_files(scenes)
    generated = [read_scene(p) for p in files]
    types = sorted({s.room.type for s in generated})
    reference = load_reference(references, types, progress=progress)
    summary = read_summary(scenes)
    report: dict = {"format": REPORT_FORMAT, "version": REPORT_VERSION}
    report["scenes"] = str(scenes)
    report["reference"] = list(references)
    report["room_types"] = dict(Counter(s.room.type for s in generated))
    report["n_generated"] = len(generated)
    report["n_reference"] = len(reference)
    if summary is not None:
        report["request"] = summary.get("request")

    physical: dict = {"collision_rate": None, "floating_rate": None, "stability": None}
    per_scene = {}
    if physics:
        cache = None if out is None else Path(f"{out}.cache.json")
        per_scene = physical_per_scene(files, cache, simulate=simulate, progress=progress)
        physical = _pooled(list(per_scene.values()))
    report.update(physical)
    report.update(_process(summary, generated))
    report["category_kl"] = category_kl(reference, generated)
    poses = pose_mmd(reference, generated, seed=seed)
    report["pose_mmd"] = poses["mean"]
    for name, section in SECTIONS.items():
        report[name] = add_tests(section(reference, generated), PER_ROOM)
    if images:
        from contextlib import nullcontext

        from rich.console import Console

        what = f"FID, KID and SCA on {len(reference)} + {len(generated)} top views"
        with Console(stderr=True).status(what) if progress else nullcontext():
            img = image_metrics(reference, generated, seed=seed, threads=threads,
                                sca_repeats=sca_repeats)  # fmt: skip
        report.update({k: v for k, v in img.items() if k != "sca_detail"})
        report["details_sca"] = img["sca_detail"]
    else:
        report.update(fid=None, kid=None, sca=None)
    report["details"] = {
        "pose_pairs": poses["pairs"],
        "pose_missing": poses["missing"],
        "per_scene": {
            Path(k).parent.name: {
                key: r[key]
                for key in (
                    "objects",
                    "collision_rate",
                    "floating_rate",
                    "stability",
                    "intersecting",
                    "floating",
                    "unstable",
                )
                if key in r
            }  # fmt: skip
            for k, r in per_scene.items()
        },
    }
    notes = []
    if len(reference) < SMALL_SET or len(generated) < SMALL_SET:
        notes.append(
            f"{len(generated)} generated and {len(reference)} reference scenes: FID, KID and "
            f"SCA are noisy below {SMALL_SET} each (add references, e.g. procthor:PATH:val, "
            "or generate more)"
        )
    if report.get("sca") is None and images:
        notes.append(img["sca_detail"].get("note", "no SCA"))
    report["notes"] = notes
    report["seconds"] = round(time.perf_counter() - t0, 2)
    report = _finite(report)
    if out is not None:
        out = Path(out)
        out.parent.mkdir(parents=True, exist_ok=True)
        atomic_write_text(out, json.dumps(report, indent=1) + "\n")
    return report


def _finite(x):
    """NaN / inf -> None, so the report is strict JSON."""
    if isinstance(x, dict):
        return {k: _finite(v) for k, v in x.items()}
    if isinstance(x, list):
        return [_finite(v) for v in x]
    if isinstance(x, float) and not np.isfinite(x):
        return None
    if isinstance(x, np.floating | np.integer):
        return _finite(x.item())
    return x


HEADLINE = (
    "collision_rate", "floating_rate", "stability", "acceptance_rate", "resamples_per_object",
    "objects_per_scene", "seconds_per_scene", "category_kl", "pose_mmd", "sca", "fid", "kid",
)  # fmt: skip
"""The report's top-level figures, in the order the CLI prints them."""


def section_rows(section: dict) -> list[tuple[str, dict, dict]]:
    """(measure, generated stat, reference stat) for every row of a report section (see
    :data:`SECTIONS`), in its order; entries that are not rows are left out."""
    return [
        (name, row["generated"], row["reference"])
        for name, row in section.items()
        if isinstance(row, dict) and {"generated", "reference"} <= row.keys()
    ]

"""The main job: hierarchy -> placement -> scene folders. ``pair2scene generate`` calls it.

>>> from pair2scene import Pair2Scene
>>> p2s = Pair2Scene.from_pretrained()            # bundled model, statistics, sizes, rooms
>>> result = p2s.generate(room="bedroom", seed=0)
>>> result.scene.objects[0].box                    # the placed scene (pair2scene.scene)

:func:`generate_scenes` writes ``OUT/<scene_id>/{scene.json, scene.glb, bev.png}`` per
scene and ``OUT/summary.json`` with every scene's statistics; run again with the same
arguments it skips the scenes already written (resume), and gives the same files.

No debris: a scene folder and summary.json appear whole or not at all (written beside,
then renamed). What a killed run's write left (hidden ``.<id>.<random>`` folders,
``.summary.json.<random>.tmp`` files) is removed when the next run into that folder
starts, and readers skip hidden names meanwhile. One run at a time writes into a folder
(a second one is refused in one line). A SIGTERM unwinds like Ctrl-C (the scene being
written is dropped, exit 143).
"""

from __future__ import annotations

import contextlib
import os
import sys
import time
from collections.abc import Iterator, Sequence
from dataclasses import dataclass, fields, is_dataclass, replace
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from pair2scene.assembly.anchors import AnchorRules, SpotRules
from pair2scene.assembly.keep import Kept, load_keep, merge_keep
from pair2scene.assembly.mounting import MountHeights
from pair2scene.assembly.overlaps import FloorOverlaps
from pair2scene.assembly.place import AssemblyConfig, AssemblyStats, Placer
from pair2scene.assembly.records import Dropped
from pair2scene.assembly.rooms import RoomTable, make_room
from pair2scene.assembly.sizes import SizeTable
from pair2scene.assembly.walls import WallRules
from pair2scene.categories import WINDOW_DRESSINGS
from pair2scene.errors import UserError
from pair2scene.hierarchy.build import build_hierarchy, room_key
from pair2scene.hierarchy.synthesis import MAX_OBJECTS_LIMIT, HierarchyConfig, load_stats
from pair2scene.hierarchy.tree import Hierarchy
from pair2scene.io.atomic import folder_lock
from pair2scene.io.export import ExportConfig
from pair2scene.io.summary import Summary, resume_summary
from pair2scene.scene.model import FLOOR, Scene, on_wall

if TYPE_CHECKING:  # (the model imports torch: only when a model is loaded)
    from pair2scene.assets.mesh import Asset
    from pair2scene.curation.stats import HierarchyStats
    from pair2scene.model.api import PlacementModel

PLACEMENT_MODELS = "default, random, gaussian:PAIRS_DIR, gaussian:FILE.json or a checkpoint folder"
"""What ``--model`` takes (:func:`load_placement_model`)."""
ABLATIONS = {"no-rejection": "reject", "no-gravity": "gravity", "no-confine": "confine"}
"""``--ablation`` name -> the :class:`AssemblyConfig` flag it turns off."""


@dataclass(frozen=True)
class GenerateConfig:
    """Every setting of generation, one default each: how a hierarchy is drawn and how it
    is placed. ``pair2scene generate`` has an option per field (``--hierarchy.k``,
    ``--assembly.temperature``, ``--assembly.tolerances.touch``...), its docstring as help.
    """

    hierarchy: HierarchyConfig = HierarchyConfig()
    """How the support and functional trees are drawn from the statistics."""
    assembly: AssemblyConfig = AssemblyConfig()
    """How the hierarchy is placed: candidates, temperature, repairs, loads, ablations."""


@dataclass(frozen=True)
class SettleReport:
    """What the closing MuJoCo settle of a scene did (:func:`settle_scene`)."""

    dropped: list[Dropped]
    """Per object that fell or slid, and its dependents."""
    seconds: float
    max_motion_m: float
    """Largest motion of a kept object while settling."""
    mean_motion_m: float
    notes: list[str]


@dataclass(frozen=True)
class SceneStats:
    """What generating one scene took; :meth:`to_dict` is its record in summary.json (and,
    without ``seconds``, scene.json's ``stats``)."""

    assembly: AssemblyStats
    """The placement's figures (before any settle)."""
    mode: str
    seed: int
    hierarchy_notes: list[str]
    """The hierarchy's notes (a template cut, a count not reached) and a kept file's."""
    kept: int | None = None
    """Objects kept from a partial scene (``--keep``); None without one."""
    settle: SettleReport | None = None
    """The closing settle (``--settle``); None without one."""

    @property
    def dropped(self) -> list[Dropped]:
        """Per object not in the scene: why (placement's, then the settle's)."""
        return self.assembly.dropped + (self.settle.dropped if self.settle else [])

    @property
    def objects_placed(self) -> int:
        return self.assembly.placed - (len(self.settle.dropped) if self.settle else 0)

    @property
    def acceptance_rate(self) -> float:
        if self.settle is None:
            return self.assembly.acceptance_rate
        return self.objects_placed / max(self.assembly.requested, 1)

    def to_dict(self, timings: bool = True) -> dict:
        """The JSON record (keys in summary.json's order); ``timings`` False leaves out the
        ``seconds`` that vary from run to run (scene.json must be byte-identical for a
        seed)."""
        out = self.assembly.to_dict()
        if self.kept is not None:
            out["kept"] = self.kept
        if self.settle is not None:
            out["dropped"] = [d.to_dict() for d in self.dropped]
            out["objects_placed"] = self.objects_placed
            out["acceptance_rate"] = round(self.acceptance_rate, 4)
            out["seconds"]["physics"] = self.settle.seconds
            out["seconds"]["total"] = round(out["seconds"]["total"] + self.settle.seconds, 4)
            out["settle"] = {"max_motion_m": self.settle.max_motion_m,
                             "mean_motion_m": self.settle.mean_motion_m,
                             "notes": list(self.settle.notes)}  # fmt: skip
        out["hierarchy_notes"] = list(self.hierarchy_notes)
        out["mode"] = self.mode
        out["seed"] = self.seed
        if not timings:
            del out["seconds"]
        return out


@dataclass(frozen=True)
class Generated:
    """One generated scene and what made it."""

    scene: Scene
    hierarchy: Hierarchy
    assets: dict[str, Asset]
    """object id -> asset (what scene.glb shows and physics would simulate)."""
    stats: SceneStats


class Pair2Scene:
    """The generator: a placement model, hierarchy statistics, size and room tables, and
    the settings (:class:`GenerateConfig`)."""

    def __init__(
        self,
        model: PlacementModel,
        stats: HierarchyStats | None = None,
        sizes: SizeTable | None = None,
        rooms: RoomTable | None = None,
        config: GenerateConfig | None = None,
    ) -> None:
        self.model = model
        self.config = config or GenerateConfig()
        for name in ("temperature", "support_temperature"):
            if not model.honours_temperature and getattr(self.config.assembly, name) != getattr(
                AssemblyConfig, name
            ):
                flag = name.replace("_", "-")
                raise UserError(
                    f"{type(model).__name__} draws uniformly: a sampling temperature changes "
                    f"nothing for it (leave --assembly.{flag} at its default)"
                )
        self.stats = load_stats() if stats is None else stats
        self.rooms = RoomTable.load() if rooms is None else rooms
        self.placer = Placer(model, SizeTable.load() if sizes is None else sizes,
                             self.config.assembly, sup_dep=self.stats.sup_dep,
                             walls=WallRules.from_stats(self.stats),
                             anchors=AnchorRules.from_stats(self.stats),
                             spots=SpotRules.from_stats(self.stats),
                             same_model=self.stats.same_model_shares(),
                             askew=self.stats.askew_shares(),
                             isolated=self.stats.isolated_shares(),
                             heights=MountHeights.from_stats(self.stats),
                             overlaps=FloorOverlaps.from_stats(self.stats),
                             top_free=self.stats.top_kept_free(
                                 max_share=self.config.assembly.top_free_share))  # fmt: skip

    @classmethod
    def from_pretrained(
        cls,
        model: str | Path | None = None,
        config: GenerateConfig | None = None,
        stats: str | Path | None = None,
    ) -> Pair2Scene:
        """A placement model by spec (:func:`load_placement_model`: the bundled one, a
        checkpoint folder, or a baseline) with the bundled tables, or with the tables of
        your own curation (``stats``: its ``stats.json``, :func:`own_tables`)."""
        if stats is None:
            return cls(load_placement_model(model), config=config)
        hierarchy, sizes, rooms = own_tables(stats)
        return cls(load_placement_model(model), hierarchy, sizes, rooms, config)

    def generate(
        self,
        room: str | None = None,
        text: str | None = None,
        seed: int = 0,
        mode: str = "fit",
        max_objects: int | None = None,
        llm: str = "auto",
        scene_id: str | None = None,
        keep: str | Path | Kept | None = None,
        settle: bool = False,
    ) -> Generated:
        """One scene for a room type or a description; same arguments, same scene.

        keep : a partial scene.json (or one :func:`load_keep` read) whose room and objects
            are kept as they are, the rest
            filled in around and on them (its room type is used when neither ``room`` nor
            ``text`` is given).
        settle : end with a short MuJoCo simulation of the whole scene
            (:func:`settle_scene`): objects take their resting poses, and any that falls
            or slides is dropped with the reason.
        """
        if keep is not None and not isinstance(keep, Kept):
            keep = load_keep(keep, self.stats)
        partial, keep_notes = (None, []) if keep is None else (keep.scene, keep.notes)
        if partial is not None and len(partial.objects) > MAX_OBJECTS_LIMIT:
            raise UserError(
                f"the partial scene to keep has {len(partial.objects)} objects; a scene may "
                f"have at most {MAX_OBJECTS_LIMIT} (MAX_OBJECTS_LIMIT)"
            )
        if room is None and text is None:
            if partial is None:
                raise UserError("give a room type, a description or a partial scene to keep")
            room = partial.room.type
        hierarchy = build_hierarchy(
            None if room is None else room_key(room), text, mode, max_objects, seed,
            self.stats, llm, self.config.hierarchy,
        )  # fmt: skip
        kept_assets: dict = {}
        assets = None
        if partial is None:
            # The room is drawn after the furniture, large enough to hold it.
            assets = self.placer.assets_for(hierarchy, seed)
            furniture = sum(float(np.prod(assets[n.id].size[:2])) for n in hierarchy.nodes
                            if hierarchy.support[n.id] == FLOOR)  # fmt: skip
            dressings = sum(1 for n in hierarchy.nodes if n.category in WINDOW_DRESSINGS
                            and on_wall(hierarchy.support[n.id]))  # fmt: skip
            room_obj = make_room(hierarchy.room_type, np.random.default_rng([seed, 1]),
                                 self.rooms, furniture,
                                 self.stats.room_type(hierarchy.room_type), dressings,
                                 dressings if text is not None and dressings else None,
                                 sized=text is None)  # fmt: skip
        else:
            room_obj = partial.room
            kept_assets = keep.assets
            hierarchy, _ = merge_keep(hierarchy, partial.objects)
        sid = scene_id or f"{hierarchy.room_type}_{seed:04d}"
        placement = self.placer.place(
            hierarchy, room_obj, seed=seed, scene_id=sid,
            keep=None if partial is None else partial.objects, keep_assets=kept_assets,
            dense=mode == "beyond", assets=assets,
        )  # fmt: skip
        report = None
        if settle:
            placement.scene, report = settle_scene(
                placement.scene, placement.assets, frozenset(o.id for o in partial.objects)
                if partial is not None else frozenset(),
            )  # fmt: skip
        stats = SceneStats(
            placement.stats, mode, seed, list(hierarchy.notes) + keep_notes,
            kept=None if partial is None else len(partial.objects), settle=report,
        )  # fmt: skip
        # Timings vary from run to run: summary.json has them, scene.json must not, so that
        # the same seed gives a byte-identical scene.json.
        placement.scene.stats = stats.to_dict(timings=False)
        return Generated(placement.scene, hierarchy, placement.assets, stats)


def load_placement_model(spec: str | Path | None = None) -> PlacementModel:
    """The placement model a ``--model`` spec names; all run through the same placement.

    ``default`` / None: the bundled layout model; ``random``: uniform placement
    (:class:`~pair2scene.assembly.baselines.RandomPlacement`); ``gaussian:PAIRS_DIR``: the
    Gaussian baseline (:class:`~pair2scene.assembly.baselines.GaussianPlacement`) fitted
    on that 3D-Pairs folder's train split (a few seconds), or ``gaussian:FILE.json`` a
    saved one; otherwise the path of a checkpoint folder (names are looked at first:
    ``./random`` is a folder).
    """
    from pair2scene.model import from_pretrained

    text = "default" if spec is None else str(spec)
    if text == "default":
        return from_pretrained(None)
    # (the baselines load SciPy's linear algebra: only when asked for)
    from pair2scene.assembly.baselines import GaussianPlacement, RandomPlacement

    if text == "random":
        return RandomPlacement()
    if text == "gaussian" or text.startswith("gaussian:"):
        source = text.partition(":")[2]
        if not source:
            raise UserError(
                "--model gaussian needs its data: gaussian:PAIRS_DIR (a 3D-Pairs folder to fit "
                "on) or gaussian:FILE.json (a saved baseline)"
            )
        return GaussianPlacement.from_spec(source)
    if not Path(text).exists():
        raise UserError(f"--model {text!r}: no such model (use {PLACEMENT_MODELS})")
    return from_pretrained(Path(text))


def ablation_names(ablation: str | Sequence[str] | None) -> list[str]:
    """The ablations asked for, checked, sorted and without repeats."""
    names = [ablation] if isinstance(ablation, str) else list(ablation or [])
    for name in names:
        if name not in ABLATIONS:
            raise UserError(f"--ablation {name!r}: unknown (use {' or '.join(ABLATIONS)})")
    return sorted(set(names))


def ablation_config(
    ablation: str | Sequence[str] | None, config: GenerateConfig | None = None
) -> GenerateConfig:
    """``config`` (default: :class:`GenerateConfig`) with the ablations' placement steps
    switched off (``no-rejection``: ``assembly.reject=False``; ``no-gravity``:
    ``assembly.gravity=False``; ``no-confine``: ``assembly.confine=False``)."""
    config = config or GenerateConfig()
    flags = {ABLATIONS[name]: False for name in ablation_names(ablation)}
    return replace(config, assembly=replace(config.assembly, **flags))


def config_changes(config: GenerateConfig, base: GenerateConfig | None = None) -> dict[str, object]:
    """The settings of ``config`` that differ from ``base`` (the defaults), by dotted path
    (``{"assembly.max_load": 0.5}``): what summary.json records of them, so a resumed run
    is the same request."""

    def leaves(obj, prefix: str) -> dict[str, object]:
        out: dict[str, object] = {}
        for f in fields(obj):
            value = getattr(obj, f.name)
            if is_dataclass(value):
                out.update(leaves(value, f"{prefix}{f.name}."))
            else:
                out[f"{prefix}{f.name}"] = value
        return out

    default = leaves(base or GenerateConfig(), "")
    return {k: v for k, v in leaves(config, "").items() if v != default[k]}


_USER_LP_THREADS = "LP_NUM_THREADS" in os.environ
"""Whether the environment set llvmpipe's thread count itself (then :func:`set_threads`
leaves it)."""


def set_threads(threads: int | None = None) -> None:
    """The process's CPU threads: ``threads``, or one, for numpy's BLAS (every BLAS
    library loaded, numpy's and scipy's: threadpoolctl) and torch's, when torch is loaded.

    Generation itself needs no torch, and the layout model's forward passes always run
    numpy's BLAS on one thread (:func:`pair2scene.model.api.one_blas_thread`), so that a
    scene's bytes do not depend on the thread count or the machine's cores: they are a
    handful of small matrices, where a second thread gains nothing on an idle machine and
    costs a lot on a busy one. The rest of a scene's products (asset meshes, point clouds,
    collision) are as small; left at a BLAS's default of one thread a core, each library's
    worker threads spin between them, and two generating processes on two cores made 1.68x
    the scenes of one instead of 1.89x (run in turn; docs/benchmarks.md). Parallelism comes from
    processes: run several generate jobs side by side.

    The top view's software GL (Mesa's llvmpipe) is held to the same count
    (``LP_NUM_THREADS``, unless the environment set it before pair2scene was imported):
    it starts a rasterising thread a core otherwise. It reads the setting when the first
    GL context is made, so a later call does not change it."""
    if threads is not None and threads < 1:
        raise UserError("--threads must be at least 1")
    if not _USER_LP_THREADS:
        os.environ["LP_NUM_THREADS"] = str(threads or 1)
    from threadpoolctl import ThreadpoolController

    ThreadpoolController().limit(limits=threads or 1, user_api="blas")
    torch = sys.modules.get("torch")
    if torch is not None:
        torch.set_num_threads(threads or 1)


def settle_scene(
    scene: Scene, assets: dict[str, Asset], fixed: frozenset[str] = frozenset()
) -> tuple[Scene, SettleReport]:
    """A short MuJoCo settle of the whole scene (pair2scene.curation.physics: contacts
    push shallow overlaps apart, then 1 s under gravity): every free object takes its
    resting pose; one that moves more than 5 cm or tips over is dropped with its
    dependents. ``fixed`` objects (kept by the user) are never dropped and keep their
    pose. Returns the settled scene and what the settle did."""
    from pair2scene.curation.physics import PhysicsConfig, validate_physics

    outcome = validate_physics(scene, config=PhysicsConfig(fit_heights=False), assets=assets)
    dropped = {k: v for k, v in outcome.dropped.items() if k not in fixed}
    by_id = scene.by_id()
    objects = []
    for o in scene.objects:
        if o.id in dropped:
            continue
        settled = outcome.settled.get(o.id)
        if settled is not None and o.id not in fixed:
            o = o.with_box(settled)
        if o.functional_anchor in dropped:
            o = replace(o, functional_anchor=None)
        objects.append(o)
    motion = [m for oid, (m, _) in outcome.motion.items() if oid not in dropped]
    report = SettleReport(
        dropped=[Dropped(k, by_id[k].category, f"physics: {v}") for k, v in dropped.items()],
        seconds=round(outcome.seconds, 4),
        max_motion_m=round(float(max(motion, default=0.0)), 4),
        mean_motion_m=round(float(np.mean(motion)) if motion else 0.0, 4),
        notes=list(outcome.notes),
    )
    return replace(scene, objects=objects), report


def own_tables(stats: str | Path) -> tuple[HierarchyStats, SizeTable | None, RoomTable | None]:
    """The hierarchy statistics of ``stats`` (a ``stats.json`` that ``pair2scene curate
    --out DIR`` wrote), with the object sizes and room sizes of its curation when the
    3D-Pairs folder is beside it (``DIR/manifest.json``; else None: the bundled ones), so
    that rooms hold your data's categories at your data's sizes."""
    from pair2scene.curation.dataset import load_pairs

    path = Path(stats)
    if path.is_dir():
        path = path / "stats.json"
    if not path.is_file():
        raise UserError(f"--stats {stats}: no such file (give the stats.json of a curation)")
    hierarchy = load_stats(path)
    if not (path.parent / "manifest.json").is_file():
        return hierarchy, None, None
    data = load_pairs(path.parent)
    return hierarchy, SizeTable.from_pairs(data, split=None), RoomTable.from_pairs(data, None)


SUMMARY_WRITE_SHARE = 0.05
"""summary.json is rewritten after a scene unless that would spend more than about this
share of the run's time on it (it grows with the scenes: rewritten after every one of
100,000 it would make a run quadratic). A scene it does not list yet is generated again
on a resume (the same seed gives the same files)."""


@contextlib.contextmanager
def _terminate_unwinds() -> Iterator[None]:
    """While writing, SIGTERM raises SystemExit(143) (as Ctrl-C raises KeyboardInterrupt)
    so that the scene being written is removed on the way out; only in the main thread and
    when SIGTERM has its default handler (a caller's own handler is left alone)."""
    import signal
    import threading

    if threading.current_thread() is not threading.main_thread() or (
        signal.getsignal(signal.SIGTERM) is not signal.SIG_DFL
    ):
        yield
        return

    def stop(signum, frame) -> None:
        raise SystemExit(128 + signum)

    signal.signal(signal.SIGTERM, stop)
    try:
        yield
    finally:
        signal.signal(signal.SIGTERM, signal.SIG_DFL)


def clean_output_folder(out: str | Path) -> list[str]:
    """Remove what killed writes left in ``out`` (the temporary scene folders of
    :func:`~pair2scene.io.export.remove_stale_scene_folders`, summary.json's temporary
    files); returns their names. Only while no other run writes there."""
    from pair2scene.io.atomic import remove_stale_temporaries
    from pair2scene.io.export import remove_stale_scene_folders
    from pair2scene.io.summary import SUMMARY_FILE

    return remove_stale_scene_folders(out) + remove_stale_temporaries(out, SUMMARY_FILE)


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
    keep: str | Path | None = None,
    settle: bool = False,
    ablation: str | Sequence[str] | None = None,
    config: GenerateConfig | None = None,
    stats: str | Path | None = None,
    export: ExportConfig | None = None,
) -> Summary:
    """``num`` scenes (seeds ``seed`` .. ``seed + num - 1``) into ``out``, each in
    ``out/<id>/``; returns the summary (also written as ``out/summary.json``). Scenes
    already in ``out`` from an earlier run of the same request are kept, not regenerated.

    config : the settings (:class:`GenerateConfig`; its defaults when None); those that
        differ from the defaults are part of the request in summary.json.

    model : a spec of :func:`load_placement_model` (``default``, ``random``,
        ``gaussian:PAIRS_DIR``, ``gaussian:FILE.json``, a checkpoint folder).
    ablation : any of ``no-rejection``, ``no-gravity``, ``no-confine`` (:func:`ablation_config`).
    stats : the ``stats.json`` of your own curation (:func:`own_tables`); None: the bundled
        statistics and tables.
    export : what each scene folder holds (:class:`~pair2scene.io.export.ExportConfig`:
        scene.json, scene.glb, bev.png and scene.html by default; MuJoCo, USD, URDF on
        request); with scene.html, ``out/index.html`` is a gallery of every scene.

    Bad input is a one-line UserError before anything is written (``out`` is created only
    then); an output folder that cannot be written is one too. A killed run's leftovers
    are removed first (:func:`clean_output_folder`); a second run into the same ``out`` at
    the same time is refused.
    """
    from pair2scene.io.export import write_scene_folder
    from pair2scene.io.names import scene_folder
    from pair2scene.io.viewer import write_index
    from pair2scene.progress import track

    if room is not None and text is not None:
        raise UserError("give one of --room or --text, not both")
    if room is None and text is None and keep is None:
        raise UserError("give --room, --text or --keep")
    if num < 1:
        raise UserError("--num must be >= 1")
    ablations = ablation_names(ablation)
    export = export or ExportConfig()
    formats = export.format_list()
    out = Path(out)
    if out.exists() and not out.is_dir():
        raise UserError(f"{out}: exists and is not a folder")
    request = {"room": room, "text": text, "mode": mode, "max_objects": max_objects,
               "model": str(model), "llm": llm}  # fmt: skip
    if keep is not None or settle:  # (earlier summaries have neither key)
        request.update(keep=None if keep is None else str(keep), settle=settle)
    if ablations:  # (likewise)
        request["ablation"] = ablations
    if stats is not None:  # (likewise)
        request["stats"] = str(stats)
    config = ablation_config(ablations, config)
    settings = config_changes(config, ablation_config(ablations))
    if settings:  # (likewise; the ablations' flags are in "ablation")
        request["settings"] = settings
    summary = resume_summary(out, request)
    p2s = Pair2Scene.from_pretrained(model, config, stats)
    # A bad room type, text or partial scene fails here, in one line, before any progress.
    kept = None if keep is None else load_keep(keep, p2s.stats)
    if kept is not None and room is None and text is None:
        room = kept.scene.room.type
    build_hierarchy(None if room is None else room_key(room), text, mode, max_objects, seed,
                    p2s.stats, llm, config.hierarchy)  # fmt: skip
    try:
        out.mkdir(parents=True, exist_ok=True)
    except OSError as e:
        raise UserError(f"{out}: cannot create the folder ({e.strerror or e})") from None
    busy = (
        "another pair2scene generate is writing there; wait for it to end, or choose another --out"
    )
    with folder_lock(out, busy), _terminate_unwinds():
        clean_output_folder(out)
        summary = resume_summary(out, request)  # (again: what an earlier run added since)
        write_seconds, since = 0.0, time.monotonic()
        for i in track(range(num), "generating", enabled=progress):
            s = seed + i
            prefix = room_key(room) if room is not None else "text"
            sid = f"{prefix}_{s:04d}"
            if sid in summary.scenes and (scene_folder(out, sid) / "scene.json").is_file():
                summary.kept += 1
                continue
            result = p2s.generate(room, text, s, mode, max_objects, llm, scene_id=sid,
                                  keep=kept, settle=settle)  # fmt: skip
            _writing(out, write_scene_folder, scene_folder(out, sid), result.scene,
                     result.assets, formats, export.dynamic)  # fmt: skip
            summary.add({"id": sid, **result.stats.to_dict()})
            if write_seconds <= SUMMARY_WRITE_SHARE * (time.monotonic() - since):
                start = time.monotonic()
                _writing(out, summary.write, out)
                write_seconds, since = time.monotonic() - start, time.monotonic()
        summary.totals = summary.compute_totals()
        _writing(out, summary.write, out)
        if "html" in formats:
            _writing(out, write_index, out)
    return summary


def _writing(out: Path, write, *args) -> None:
    """``write(*args)``; a file system error (a full disk, no permission) is one line."""
    try:
        write(*args)
    except OSError as e:
        where = e.filename or out
        raise UserError(f"{where}: cannot write ({e.strerror or e})") from None

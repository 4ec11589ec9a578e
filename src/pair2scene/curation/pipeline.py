"""Curation: source scenes -> 3D-Pairs (relation tuples on disk), statistics and a report.

Per scene: support from geometry (:func:`~pair2scene.curation.support.extract_support`),
physics (:func:`~pair2scene.curation.physics.validate_physics`, optional), functional
anchors (:func:`~pair2scene.curation.functional.distill_functional`), then relation
tuples (:mod:`pair2scene.curation.tuples`). Support is scored against the source's own
annotation on the scenes *before* physics drops anything, so the figure measures the
extraction alone.

Scenes are processed in deterministic chunks (``chunk_scenes`` consecutive scenes of a
source); each chunk becomes one shard of the dataset, written atomically together with
the chunk's counts and statistics (:class:`~pair2scene.curation.dataset.PairsWriter`).
A rerun of the same command skips every chunk whose shard is on disk and intact, so an
interrupted run resumes where it stopped; a chunk whose scenes or settings changed gets
a new key and is redone.

Output folder::

    manifest.json, shards/   the 3D-Pairs dataset (pair2scene.curation.dataset)
    stats.json               HierarchyStats of the curated train scenes
    report.json              counts, drop rates, support precision/recall/F1, timings

report.json (format ``pair2scene.curation_report``, version 1)::

    config            the run's settings
    sources           per source label (``ai2thor``, ``procthor``, ...; the full spec
                      when two sources share a kind): spec, rooms, objects, dropped,
                      drop_rate (objects dropped by physics / objects), drop_reasons,
                      tuples (per kind and total), objects_without_tuple (why),
                      support_eval, functional, chunks, chunks_reused, seconds, loader
    skipped_sources   [{spec, reason}] for sources that could not be read
    counts            sources, curated, skipped, rooms, objects, dropped, drop_rate,
                      tuples, per_kind
    support_eval      {label: {precision, recall, f1, n_true, n_pred, n_correct, scenes,
                      errors_by_category}} for every source with a support annotation
                      (AI2-THOR, ProcTHOR; not 3D-FRONT): report["support_eval"]["ai2thor"]["f1"]
    functional        mode, proposals, passed_k_check, kept, llm (client and proposer
                      statistics when the LLM proposer ran, else null)
    timings           total_s, and per source load_s, wall_s and the summed stage times
    resume            chunks, reused, computed
    outputs           file names of the dataset manifest, stats and report
"""

from __future__ import annotations

import dataclasses
import functools
import hashlib
import json
import multiprocessing as mp
import os
import time
from collections import Counter
from collections.abc import Callable, Iterator, Sequence
from concurrent.futures import ProcessPoolExecutor
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from pair2scene.curation.dataset import MANIFEST, PairsWriter
from pair2scene.curation.stats import HierarchyStats
from pair2scene.curation.tuples import RELATION_KINDS, PairTuple, scene_tuples
from pair2scene.errors import UserError
from pair2scene.io.atomic import atomic_write_text
from pair2scene.scene.model import Scene

REPORT_FORMAT = "pair2scene.curation_report"
REPORT_VERSION = 1
REPORT_FILE = "report.json"
STATS_FILE = "stats.json"
PIPELINE_VERSION = 1
"""Part of every chunk key, with the code's digest (:func:`code_fingerprint`)."""
FUNCTIONAL_MODES = ("offline", "llm")
LLM_BASE_URL_ENV = "PAIR2SCENE_LLM_BASE_URL"
LLM_ENV = (LLM_BASE_URL_ENV, "OPENAI_BASE_URL", "PAIR2SCENE_LLM_MODEL")
"""What selects the LLM (part of the chunk key in llm mode; pair2scene.llm reads them)."""
CHUNK_SCENES = 64
"""Scenes per chunk (and so per shard): ~1,500-3,000 tuples; an interruption loses at most
one chunk's work (well under a minute with physics)."""


# -- configuration ------------------------------------------------------------------------


@dataclass(frozen=True)
class CurateConfig:
    """Settings of one curation run."""

    sources: tuple[str, ...]
    """Source specs: ``ai2thor``, ``procthor:PATH``, ``3dfront:PATH``."""
    out: Path
    """Output folder (created; an earlier run's output there is resumed)."""
    functional: str = "offline"
    """Functional proposer: ``offline`` (category-pair table) or ``llm`` (needs
    PAIR2SCENE_LLM_BASE_URL)."""
    physics: bool = True
    """Run the MuJoCo check and drop what does not stay put."""
    exclude_floor_only: frozenset[str] = frozenset()
    """Sources (label, kind or spec) whose ``floor`` tuples are left out (noisy layouts)."""
    seed: int = 0
    """Seed of the procedural assets the physics check builds."""
    chunk_scenes: int = CHUNK_SCENES
    """Scenes per chunk and shard."""
    workers: int | None = None
    """Processes for the per-scene stages; None: min(2, CPUs). 1 runs in this process.
    The LLM proposer always runs in this process (one client, one cache, one ledger)."""
    fresh: bool = False
    """Ignore an earlier run's shards in ``out`` and redo everything."""
    use_k_check: bool = True
    """Keep only functional proposals whose dependent lies within k of the anchor."""
    stats_splits: tuple[str, ...] = ("train",)
    """Splits whose scenes the hierarchy statistics are fitted on (val stays unseen)."""

    def __post_init__(self) -> None:
        object.__setattr__(self, "sources", tuple(self.sources))
        object.__setattr__(self, "out", Path(self.out))
        object.__setattr__(self, "exclude_floor_only", frozenset(self.exclude_floor_only))
        object.__setattr__(self, "stats_splits", tuple(self.stats_splits))


# -- the stages, as parts -----------------------------------------------------------------


def _make_proposer(mode: str):
    from pair2scene.curation import functional

    make = getattr(functional, "make_proposer", None)
    if make is not None:
        return make(mode)
    if mode == "offline":
        return functional.OfflineProposer()
    from pair2scene.llm import LLMClient, LLMConfig

    config = LLMConfig.from_env()
    if config is None:
        raise UserError(f"--functional llm needs an endpoint: set {LLM_BASE_URL_ENV}")
    return functional.LLMProposer(LLMClient(config))


def _extract_support(scene: Scene) -> Scene:
    from pair2scene.curation import support

    return support.extract_support(scene)


def _validate_physics(scene: Scene, seed: int):
    from pair2scene.curation import physics

    fields = {f.name for f in dataclasses.fields(physics.PhysicsConfig)}
    config = physics.PhysicsConfig(**({"seed": seed} if "seed" in fields else {}))
    return physics.validate_physics(scene, None, config)


def _distill_functional(scene: Scene, proposer, use_k_check: bool) -> Scene:
    from pair2scene.curation import functional
    from pair2scene.curation.wall_objects import wall_anchors

    # Objects on a wall take the floor object they hang over (or face) as their anchor.
    return wall_anchors(functional.distill_functional(scene, proposer, use_k_check=use_k_check))


def _support_scores(scenes: list[Scene]):
    from pair2scene.curation import support

    return support.support_scores(scenes)


@dataclass(frozen=True)
class Stages:
    """The per-scene stages the pipeline composes (module-level functions, so that worker
    processes receive them by name). Tests pass small fakes."""

    extract_support: Callable[[Scene], Scene] = _extract_support
    validate_physics: Callable[[Scene, int], Any] = _validate_physics
    """(scene, seed) -> PhysicsOutcome (``scene``, ``dropped``)."""
    distill_functional: Callable[[Scene, Any, bool], Scene] = _distill_functional
    """(scene, proposer, use_k_check) -> scene with ``functional_anchor`` set."""
    support_scores: Callable[[list[Scene]], Any] = _support_scores
    """scenes -> SupportScores (``n_true``, ``n_pred``, ``n_correct``, micro-averaged)."""
    make_proposer: Callable[[str], Any] = _make_proposer
    """functional mode -> Proposer."""


# -- per scene ----------------------------------------------------------------------------


@dataclass
class SceneResult:
    """What the stages did to one scene."""

    scene: Scene
    """Curated: support, physics drops, functional anchors."""
    objects: int
    dropped: dict[str, str]
    support_counts: tuple[int, int, int] | None
    """(n_true, n_pred, n_correct) against the source's annotation; None without one."""
    support_errors: dict[str, int]
    proposals: int
    passed_k_check: int | None
    seconds: dict[str, float]


class _CountingProposer:
    """Passes proposals through, counting them."""

    def __init__(self, inner) -> None:
        self.inner = inner
        self.count = 0

    def propose(self, scene, support, group):
        out = self.inner.propose(scene, support, group)
        self.count += len(out)
        return out


def has_support_truth(scene: Scene) -> bool:
    """True when the source annotated some support in ``scene`` (3D-FRONT does not)."""
    return any(o.source_support is not None for o in scene.objects)


@dataclass
class _Context:
    stages: Stages
    proposer: Any
    physics: bool
    seed: int
    use_k_check: bool


_WORKER: _Context | None = None


def _init_worker(stages: Stages, mode: str, physics: bool, seed: int, use_k_check: bool) -> None:
    global _WORKER
    _WORKER = _Context(stages, stages.make_proposer(mode), physics, seed, use_k_check)


def _worker_process(scene: Scene) -> SceneResult:
    assert _WORKER is not None
    return process_scene(scene, _WORKER)


def process_scene(scene: Scene, ctx: _Context) -> SceneResult:
    """Run the stages on one scene."""
    seconds = {}
    t = time.perf_counter()
    supported = ctx.stages.extract_support(scene)
    seconds["support_s"] = time.perf_counter() - t
    counts, errors = None, {}
    if has_support_truth(scene):
        scores = ctx.stages.support_scores([supported])
        counts = (int(scores.n_true), int(scores.n_pred), int(scores.n_correct))
        by_cat = getattr(scores, "errors_by_category", None)
        errors = dict(by_cat()) if callable(by_cat) else {}
    dropped: dict[str, str] = {}
    curated = supported
    t = time.perf_counter()
    if ctx.physics:
        outcome = ctx.stages.validate_physics(supported, ctx.seed)
        curated, dropped = outcome.scene, dict(outcome.dropped)
    seconds["physics_s"] = time.perf_counter() - t
    t = time.perf_counter()
    counting = _CountingProposer(ctx.proposer)
    curated = ctx.stages.distill_functional(curated, counting, ctx.use_k_check)
    seconds["functional_s"] = time.perf_counter() - t
    figures = curated.stats.get("functional") if isinstance(curated.stats, dict) else None
    passed = figures.get("passed_k_check") if isinstance(figures, dict) else None
    return SceneResult(
        scene=curated,
        objects=len(scene.objects),
        dropped=dropped,
        support_counts=counts,
        support_errors=errors,
        proposals=counting.count,
        passed_k_check=None if passed is None else int(passed),
        seconds=seconds,
    )


class _Runner:
    """Maps scenes through the stages in order, in this process or in a process pool."""

    def __init__(self, config: CurateConfig, stages: Stages, workers: int) -> None:
        self.config, self.stages, self.workers = config, stages, workers
        self._pool: ProcessPoolExecutor | None = None
        self._local: _Context | None = None

    def map(self, scenes: Sequence[Scene]) -> Iterator[SceneResult]:
        cfg = self.config
        if not scenes:
            return iter(())
        if self.workers <= 1 or len(scenes) < 2:
            if self._local is None:
                proposer = self.stages.make_proposer(cfg.functional)
                self._local = _Context(
                    self.stages, proposer, cfg.physics, cfg.seed, cfg.use_k_check
                )
            return (process_scene(s, self._local) for s in scenes)
        if self._pool is None:
            # spawn, not fork: MuJoCo/GL state and the progress bar's thread stay out of
            # the workers.
            self._pool = ProcessPoolExecutor(
                max_workers=self.workers,
                mp_context=mp.get_context("spawn"),
                initializer=_init_worker,
                initargs=(self.stages, cfg.functional, cfg.physics, cfg.seed, cfg.use_k_check),
            )
        return self._pool.map(_worker_process, scenes, chunksize=1)

    @property
    def proposer(self):
        return None if self._local is None else self._local.proposer

    def close(self) -> None:
        if self._pool is not None:
            self._pool.shutdown(wait=True, cancel_futures=True)
            self._pool = None


# -- chunks -------------------------------------------------------------------------------


def scene_fingerprint(scene: Scene) -> bytes:
    """A digest of everything of ``scene`` the stages read."""
    h = hashlib.sha256()
    room = scene.room
    h.update(json.dumps([scene.id, scene.split, scene.source, room.type, room.height]).encode())
    h.update(room.floor_polygon.astype("<f8").tobytes())
    for o in scene.objects:
        asset = None if o.asset is None else o.asset.to_dict()
        meta = [
            o.id,
            o.category,
            asset,
            o.support,
            o.source_support,
            o.part_of,
            o.functional_anchor,
        ]
        h.update(json.dumps(meta).encode())
        h.update(o.box.to_vector().astype("<f8").tobytes())
    return h.digest()


@functools.lru_cache(maxsize=1)
def code_fingerprint() -> str:
    """A digest of the package's code and data tables: a run after any change to them
    redoes every chunk instead of mixing shards of two versions of the stages."""
    root = Path(__file__).resolve().parents[1]
    h = hashlib.sha256()
    for path in sorted(p for p in root.rglob("*") if p.suffix in (".py", ".json")):
        h.update(path.relative_to(root).as_posix().encode() + b"\0")
        h.update(path.read_bytes())
    return h.hexdigest()


def chunk_key(scenes: Sequence[Scene], settings: dict) -> str:
    """The shard key of a chunk: its scenes and every setting that changes its output."""
    h = hashlib.sha256(json.dumps(settings, sort_keys=True).encode())
    for s in scenes:
        h.update(scene_fingerprint(s))
    return h.hexdigest()[:32]


def _source_labels(specs: Sequence[str]) -> list[str]:
    kinds = [s.partition(":")[0].strip().lower() for s in specs]
    counts = Counter(kinds)
    return [k if counts[k] == 1 else s for k, s in zip(kinds, specs)]


def _chunk_meta(label: str, results: list[SceneResult], stats_splits: Sequence[str]) -> dict:
    """What the report and statistics need of a chunk, kept in the manifest so that a
    resumed run does not redo it. No timings: equal input gives an equal manifest."""
    dropped_reasons: Counter[str] = Counter()
    for r in results:
        dropped_reasons.update(reason.split(" ", 1)[0].rstrip(":") for reason in r.dropped.values())
    scored = [r for r in results if r.support_counts is not None]
    errors: Counter[str] = Counter()
    for r in scored:
        errors.update(r.support_errors)
    passed = [r.passed_k_check for r in results]
    stats = HierarchyStats.fit(
        r.scene for r in results if (r.scene.split or "train") in stats_splits
    )
    return {
        "source": label,
        "rooms": len(results),
        "objects": sum(r.objects for r in results),
        "dropped": sum(len(r.dropped) for r in results),
        "drop_reasons": dict(sorted(dropped_reasons.items())),
        "support": {
            "scenes": len(scored),
            "n_true": sum(r.support_counts[0] for r in scored),
            "n_pred": sum(r.support_counts[1] for r in scored),
            "n_correct": sum(r.support_counts[2] for r in scored),
            "errors_by_category": dict(sorted(errors.items())),
        },
        "functional": {
            "proposals": sum(r.proposals for r in results),
            "passed_k_check": None if None in passed else sum(passed),
            "kept": sum(o.functional_anchor is not None for r in results for o in r.scene.objects),
        },
        "stats": stats.to_dict(),
    }


# -- the report ---------------------------------------------------------------------------


@dataclass
class SupportEval:
    """Support extraction against the source's annotation (micro-averaged over edges)."""

    precision: float
    recall: float
    f1: float
    n_true: int
    n_pred: int
    n_correct: int
    scenes: int
    errors_by_category: dict[str, int] = field(default_factory=dict)

    @classmethod
    def from_counts(
        cls, n_true: int, n_pred: int, n_correct: int, scenes: int, errors: dict[str, int]
    ) -> SupportEval:
        p = n_correct / n_pred if n_pred else 0.0
        r = n_correct / n_true if n_true else 0.0
        f1 = 2 * p * r / (p + r) if p + r else 0.0
        return cls(p, r, f1, n_true, n_pred, n_correct, scenes, errors)


@dataclass
class SourceSummary:
    label: str
    spec: str
    rooms: int = 0
    objects: int = 0
    dropped: int = 0
    drop_reasons: dict[str, int] = field(default_factory=dict)
    tuples: dict[str, int] = field(default_factory=dict)
    """Per relation kind, plus ``total``."""
    objects_without_tuple: dict[str, int] = field(default_factory=dict)
    support_eval: SupportEval | None = None
    proposals: int = 0
    passed_k_check: int | None = None
    kept: int = 0
    chunks: int = 0
    chunks_reused: int = 0
    seconds: dict[str, float] = field(default_factory=dict)
    loader: dict[str, Any] = field(default_factory=dict)

    @property
    def drop_rate(self) -> float:
        return self.dropped / self.objects if self.objects else 0.0

    def to_dict(self) -> dict:
        return {
            "spec": self.spec,
            "rooms": self.rooms,
            "objects": self.objects,
            "dropped": self.dropped,
            "drop_rate": round(self.drop_rate, 6),
            "drop_reasons": self.drop_reasons,
            "tuples": self.tuples,
            "objects_without_tuple": self.objects_without_tuple,
            "support_eval": None
            if self.support_eval is None
            else dataclasses.asdict(self.support_eval),
            "functional": {
                "proposals": self.proposals,
                "passed_k_check": self.passed_k_check,
                "kept": self.kept,
            },
            "chunks": self.chunks,
            "chunks_reused": self.chunks_reused,
            "seconds": {k: round(v, 3) for k, v in self.seconds.items()},
            "loader": self.loader,
        }


@dataclass
class SkippedSource:
    spec: str
    reason: str


@dataclass
class CurateReport:
    """The outcome of :func:`curate` (also written to ``out/report.json``)."""

    config: CurateConfig
    sources: list[SourceSummary]
    skipped: list[SkippedSource]
    tuples: int
    seconds: float
    llm: dict | None = None
    stats: HierarchyStats | None = field(default=None, repr=False)

    def source(self, label: str) -> SourceSummary:
        for s in self.sources:
            if s.label == label:
                return s
        raise KeyError(label)

    def to_dict(self) -> dict:
        cfg = self.config
        per_kind = Counter()
        for s in self.sources:
            per_kind.update({k: v for k, v in s.tuples.items() if k != "total"})
        objects = sum(s.objects for s in self.sources)
        dropped = sum(s.dropped for s in self.sources)
        passed = [s.passed_k_check for s in self.sources]
        return {
            "format": REPORT_FORMAT,
            "version": REPORT_VERSION,
            "config": {
                "sources": list(cfg.sources),
                "out": str(cfg.out),
                "functional": cfg.functional,
                "physics": cfg.physics,
                "exclude_floor_only": sorted(cfg.exclude_floor_only),
                "seed": cfg.seed,
                "chunk_scenes": cfg.chunk_scenes,
                "use_k_check": cfg.use_k_check,
                "stats_splits": list(cfg.stats_splits),
            },
            "sources": {s.label: s.to_dict() for s in self.sources},
            "skipped_sources": [dataclasses.asdict(s) for s in self.skipped],
            "counts": {
                "sources": len(cfg.sources),
                "curated": len(self.sources),
                "skipped": len(self.skipped),
                "rooms": sum(s.rooms for s in self.sources),
                "objects": objects,
                "dropped": dropped,
                "drop_rate": round(dropped / objects, 6) if objects else 0.0,
                "tuples": self.tuples,
                "per_kind": {k: per_kind.get(k, 0) for k in RELATION_KINDS},
            },
            "support_eval": {
                s.label: dataclasses.asdict(s.support_eval) for s in self.sources if s.support_eval
            },
            "functional": {
                "mode": cfg.functional,
                "proposals": sum(s.proposals for s in self.sources),
                "passed_k_check": None if None in passed else sum(passed),
                "kept": sum(s.kept for s in self.sources),
                "llm": self.llm,
            },
            "timings": {
                "total_s": round(self.seconds, 3),
                "per_source": {
                    s.label: {k: round(v, 3) for k, v in s.seconds.items()} for s in self.sources
                },
            },
            "resume": {
                "chunks": sum(s.chunks for s in self.sources),
                "reused": sum(s.chunks_reused for s in self.sources),
                "computed": sum(s.chunks - s.chunks_reused for s in self.sources),
            },
            "outputs": {"manifest": MANIFEST, "stats": STATS_FILE, "report": REPORT_FILE},
        }


# -- the pipeline -------------------------------------------------------------------------


def _check_config(config: CurateConfig, labels: list[str]) -> None:
    if not config.sources:
        raise UserError("no source: give at least one --source")
    dup = sorted({s for s in config.sources if config.sources.count(s) > 1})
    if dup:
        raise UserError(f"source given twice: {dup[0]}")
    if config.functional not in FUNCTIONAL_MODES:
        raise UserError(
            f"unknown functional mode {config.functional!r}: use {' or '.join(FUNCTIONAL_MODES)}"
        )
    if config.chunk_scenes < 1:
        raise UserError("chunk size must be at least 1 scene")
    names = set(labels) | set(config.sources)
    names |= {s.partition(":")[0].strip().lower() for s in config.sources}
    for name in sorted(config.exclude_floor_only):
        if name not in names:
            raise UserError(f"--exclude-floor-only {name}: not one of the sources given")
    if config.functional == "llm" and not (
        os.environ.get(LLM_BASE_URL_ENV, "").strip()
        or os.environ.get("OPENAI_BASE_URL", "").strip()
    ):
        raise UserError(f"--functional llm needs an LLM endpoint: set {LLM_BASE_URL_ENV}")


def _excluded(config: CurateConfig, spec: str, label: str) -> bool:
    kind = spec.partition(":")[0].strip().lower()
    return bool({spec, label, kind} & config.exclude_floor_only)


def _llm_stats(proposer) -> dict | None:
    if proposer is None:
        return None
    out = {}
    for name, owner in (("proposer", proposer), ("client", getattr(proposer, "client", None))):
        stats = getattr(owner, "stats", None)
        if stats is None:
            continue
        if dataclasses.is_dataclass(stats):
            stats = dataclasses.asdict(stats)
        out[name] = json.loads(json.dumps(stats, default=str))
    return out or None


def curate(
    config: CurateConfig, progress: bool = True, stages: Stages | None = None
) -> CurateReport:
    """Curate every source of ``config`` into ``config.out`` and return the report.

    A source that cannot be read (a UserError from its adapter: a malformed or missing
    file) is recorded in the report as skipped and the others go on; when none can be
    read this raises UserError (and leaves an earlier dataset in ``out`` as it was).
    """
    from pair2scene.data.sources import load_source
    from pair2scene.progress import track

    t_start = time.perf_counter()
    stages = stages or Stages()
    labels = _source_labels(config.sources)
    _check_config(config, labels)
    out = config.out
    if out.exists() and not out.is_dir():
        raise UserError(f"{out}: exists and is not a folder")
    writer = PairsWriter(out, fresh=config.fresh)
    llm = config.functional == "llm"
    workers = 1 if llm else (config.workers or min(2, os.cpu_count() or 1))
    runner = _Runner(config, stages, workers)
    summaries: list[SourceSummary] = []
    skipped: list[SkippedSource] = []
    plan: list[str] = []
    chunk_stats: list[HierarchyStats] = []
    try:
        for spec, label in zip(config.sources, labels):
            t0 = time.perf_counter()
            try:
                corpus = load_source(spec, progress=progress)
            except UserError as e:
                skipped.append(SkippedSource(spec, str(e)))
                continue
            summary = SourceSummary(label, spec)
            summary.seconds["load_s"] = time.perf_counter() - t0
            summary.loader = {
                "warnings": dict(sorted(corpus.report.warnings.items())),
                "unknown_labels": sum(corpus.report.unknown_labels.values()),
            }
            exclude = _excluded(config, spec, label)
            settings = {
                "pipeline": PIPELINE_VERSION,
                "code": code_fingerprint(),
                "source": label,
                "physics": config.physics,
                "seed": config.seed,
                "functional": config.functional,
                "llm": [os.environ.get(v) for v in LLM_ENV] if llm else None,
                "use_k_check": config.use_k_check,
                "exclude_floor_only": exclude,
                "stats_splits": list(config.stats_splits),
            }
            scenes = corpus.scenes
            chunks = [
                scenes[i : i + config.chunk_scenes]
                for i in range(0, len(scenes), config.chunk_scenes)
            ]
            keys = [chunk_key(c, settings) for c in chunks]
            todo = [(k, c) for k, c in zip(keys, chunks) if writer.finished(k) is None]
            summary.chunks, summary.chunks_reused = len(chunks), len(chunks) - len(todo)
            t1 = time.perf_counter()
            pending = [s for _, c in todo for s in c]
            results = iter(
                track(runner.map(pending), f"curating {label}", progress, total=len(pending))
            )
            stage_s: Counter[str] = Counter()
            for key, chunk in todo:
                done = [next(results) for _ in chunk]
                tuples: list[PairTuple] = []
                why: Counter[str] = Counter()
                for r in done:
                    tuples.extend(scene_tuples(r.scene, exclude, label, why))
                    stage_s.update(r.seconds)
                meta = _chunk_meta(label, done, config.stats_splits)
                meta["objects_without_tuple"] = dict(sorted(why.items()))
                writer.write(key, tuples, meta)
            for _ in results:  # exhausted: closes the progress bar
                pass
            summary.seconds["wall_s"] = time.perf_counter() - t1
            summary.seconds.update(stage_s)
            _summarise(summary, [writer.entries[k] for k in keys])
            chunk_stats.extend(
                HierarchyStats.from_dict(writer.entries[k]["meta"]["stats"]) for k in keys
            )
            plan.extend(keys)
            summaries.append(summary)
    finally:
        runner.close()
    if not summaries:
        reasons = "; ".join(s.reason for s in skipped)
        raise UserError(f"no source could be read: {reasons}")
    manifest = writer.finalize(plan)
    stats = HierarchyStats.merge(chunk_stats)
    atomic_write_text(out / STATS_FILE, stats.to_json())
    report = CurateReport(
        config=config,
        sources=summaries,
        skipped=skipped,
        tuples=manifest["count"],
        seconds=time.perf_counter() - t_start,
        llm=_llm_stats(runner.proposer) if llm else None,
        stats=stats,
    )
    atomic_write_text(out / REPORT_FILE, json.dumps(report.to_dict(), indent=1) + "\n")
    return report


def _summarise(summary: SourceSummary, entries: list[dict]) -> None:
    """Fill ``summary``'s counts from its chunks' manifest entries."""
    kinds: Counter[str] = Counter()
    reasons: Counter[str] = Counter()
    without: Counter[str] = Counter()
    errors: Counter[str] = Counter()
    sup = Counter()
    passed: list[int | None] = []
    for e in entries:
        meta = e["meta"]
        summary.rooms += meta["rooms"]
        summary.objects += meta["objects"]
        summary.dropped += meta["dropped"]
        reasons.update(meta["drop_reasons"])
        without.update(meta["objects_without_tuple"])
        kinds.update(e["counts"]["per_kind"])
        s = meta["support"]
        sup.update({k: s[k] for k in ("scenes", "n_true", "n_pred", "n_correct")})
        errors.update(s["errors_by_category"])
        f = meta["functional"]
        summary.proposals += f["proposals"]
        summary.kept += f["kept"]
        passed.append(f["passed_k_check"])
    summary.passed_k_check = None if None in passed else sum(passed)
    summary.drop_reasons = dict(sorted(reasons.items()))
    summary.objects_without_tuple = dict(sorted(without.items()))
    summary.tuples = {k: kinds.get(k, 0) for k in RELATION_KINDS}
    summary.tuples["total"] = sum(kinds.values())
    if sup["scenes"]:
        top = dict(sorted(errors.items(), key=lambda kv: (-kv[1], kv[0])))
        summary.support_eval = SupportEval.from_counts(
            sup["n_true"], sup["n_pred"], sup["n_correct"], sup["scenes"], top
        )

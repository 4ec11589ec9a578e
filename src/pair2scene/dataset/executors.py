"""Running the plan: which shards still need making, who makes them, and the progress.

``local``: ``--jobs`` worker processes (the ``spawn`` context: no forked torch state),
each loading the model once in its initializer with one torch thread; a task is a shard;
workers report each scene through a queue, for one progress bar over all of them. A
worker that dies (killed, out of memory) breaks the pool: the pool is started again and
the shards not yet whole are made again, up to :data:`WORKER_RESTARTS` times. With
``--jobs 1`` the shards are made in this process.

``ray``: ``--jobs`` Ray actors, each loading the model once; a task is a shard; the
actors report each scene through a Ray queue (an actor of no CPU); a task that raises is
submitted again, up to :data:`SHARD_ATTEMPTS` times, and a task whose actor was killed
(the actor is restarted, up to :data:`ACTOR_RESTARTS` times) as long as actors may
restart, so a lost worker costs only its shard. The actors write
into ``OUT`` themselves: on a cluster, ``OUT`` must be on a file system every node sees.

Every shard is written whole or not at all (:func:`pair2scene.dataset.shards.make_shard`)
and the scenes are the same bytes whichever worker makes them.
"""

from __future__ import annotations

import pickle
import queue as queue_module
import re
import time
from collections import Counter
from dataclasses import dataclass, field
from pathlib import Path

from pair2scene.dataset.plan import DatasetConfig, PlannedScene, plan_shards, slice_shards
from pair2scene.dataset.shards import (
    dataset_lock,
    make_shard,
    open_dataset,
    shard_problem,
    write_index,
)
from pair2scene.errors import UserError

EXECUTORS = ("local", "ray")
"""The ``--executor`` choices."""
SHARD_ATTEMPTS = 3
"""Ray: how many times a shard that raises is tried before the run fails (a shard whose
actor was lost is tried again as long as actors may restart)."""
ACTOR_RESTARTS = 4
"""Ray: how many times a killed actor is restarted."""
WORKER_RESTARTS = 4
"""Local: how many times the worker pool is started again after a worker died."""
POLL_SECONDS = 0.2
"""How often the progress loop looks at the workers' reports."""
_DETAIL = re.compile(r" \([^()]*\)$")
"""A drop reason's closing tally of rejected candidates, ``(collision 11, outside 2)``."""
_MEASURE = re.compile(r"\d+\.\d+")
"""A measure in a drop reason (``its base is 1.14 x 0.03 m``), summed as ``#``."""
RAY_HINT = "--executor ray needs Ray: pip install 'pair2scene[ray]' (or pip install 'ray>=2.9')"
"""The one line shown when Ray is not importable."""


@dataclass
class RunSummary:
    """What a run did."""

    scenes: int = 0
    """Scenes made by this run."""
    skipped_shards: int = 0
    """Shards already whole (resumed)."""
    shards: int = 0
    """Shards made by this run."""
    seconds: float = 0.0
    objects_placed: int = 0
    objects_requested: int = 0
    drops: Counter = field(default_factory=Counter)
    """Drop reason -> count, over the scenes made."""
    index_written: bool = False
    """Whether OUT/index.jsonl was written (every shard of the plan is whole)."""
    retries: int = 0
    """Restarts after a worker died or a task failed (local: the worker pool started
    again, its unfinished shards made again; Ray: shard tasks submitted again)."""
    first_scene_seconds: float = 0.0
    """Seconds from the start to the first scene made (workers started, models loaded)."""
    _seen: set = field(default_factory=set, repr=False)

    def add(self, record: dict) -> bool:
        """Count a scene once (a shard made again reports its scenes again); whether it
        was new."""
        if record["id"] in self._seen:
            return False
        self._seen.add(record["id"])
        self.scenes += 1
        self.objects_placed += record["objects_placed"]
        self.objects_requested += record["objects_requested"]
        for reason, n in record["drops"].items():  # (the candidates' tallies left out)
            self.drops[_MEASURE.sub("#", _DETAIL.sub("", reason))] += n
        return True

    @property
    def scenes_per_minute(self) -> float:
        return 60.0 * self.scenes / self.seconds if self.seconds > 0 else 0.0

    def lines(self) -> list[str]:
        """The summary printed at the end."""
        out = [
            f"{self.scenes} scenes in {self.shards} shards ({self.skipped_shards} shards already "
            f"done) in {self.seconds:.1f} s: {self.scenes_per_minute:.1f} scenes per minute; "
            f"{self.objects_placed} of {self.objects_requested} objects placed"
        ]
        if self.retries:
            tries = "retry" if self.retries == 1 else "retries"
            out.append(f"{self.retries} {tries} after a worker died or a task failed")
        if self.drops:
            top = ", ".join(f"{reason}: {n}" for reason, n in self.drops.most_common(8))
            out.append(f"drops by reason: {top}")
        return out


# --- workers ---------------------------------------------------------------------------

_GENERATOR = None
"""This process's generator (loaded once: in a worker's initializer, or on first use)."""
_REPORTS = None
"""The queue a local worker reports its scenes on."""


def _generator():
    global _GENERATOR
    if _GENERATOR is None:
        from pair2scene.generate import Pair2Scene, set_threads

        set_threads(1)
        _GENERATOR = Pair2Scene.from_pretrained()
    return _GENERATOR


def _init_worker(reports) -> None:
    """A local worker's initializer: the model, once; the progress queue."""
    global _REPORTS
    _REPORTS = reports
    _generator()


def _worker_shard(out: str, config: DatasetConfig, index: int, items: list[PlannedScene]) -> list:
    """A local worker's task: make one shard, reporting each scene."""

    def report(record: dict) -> None:
        if _REPORTS is not None:
            _REPORTS.put(record)

    return make_shard(Path(out), config, index, items, _generator(), report)


class _ShardActor:
    """A Ray actor: the model, once; a task is a shard."""

    def __init__(self) -> None:
        _generator()

    def make(self, out: str, config: DatasetConfig, index: int, items: list, reports) -> list:
        return make_shard(Path(out), config, index, items, _generator(), reports.put)


# --- the run ---------------------------------------------------------------------------


def pending_shards(
    out: Path, config: DatasetConfig, part: tuple[int, int]
) -> tuple[list[tuple[int, list[PlannedScene]]], int]:
    """The shards of slice ``part`` still to make (missing, partial or corrupt) and how
    many of the slice are whole already."""
    plan = plan_shards(config)
    todo, done = [], 0
    for i in slice_shards(len(plan), part):
        if shard_problem(out, config, i, plan[i]) is None:
            done += 1
        else:
            todo.append((i, plan[i]))
    return todo, done


def run_dataset(
    out: str | Path,
    config: DatasetConfig,
    executor: str = "local",
    jobs: int = 1,
    part: tuple[int, int] = (0, 1),
    ray_address: str | None = None,
    progress: bool = True,
) -> RunSummary:
    """Make the dataset ``config`` in ``out`` (or the slice ``part`` = (i, N) of its
    shards): shards already whole are kept, others made; ``OUT/index.jsonl`` is written
    once every shard of the plan is whole. Returns what the run did."""
    if executor not in EXECUTORS:
        raise UserError(f"--executor {executor!r}: choose one of {', '.join(EXECUTORS)}")
    ray = _import_ray() if executor == "ray" else None
    if ray is not None and not ray.is_initialized():
        check_ray_address(ray_address)  # (before OUT is made)
    out = Path(out)
    open_dataset(out, config)
    summary = RunSummary()
    start = time.monotonic()
    with dataset_lock(out, shared=part[1] > 1):
        todo, summary.skipped_shards = pending_shards(out, config, part)
        total = sum(len(items) for _, items in todo)
        with _Bar(total, progress) as bar:

            def done(record: dict) -> None:
                if summary.add(record):
                    if summary.scenes == 1:
                        summary.first_scene_seconds = time.monotonic() - start
                    bar.advance()

            if not todo:
                pass
            elif executor == "ray":
                summary.retries = _run_ray(ray, out, config, todo, jobs, ray_address, done)
            elif jobs == 1:
                generator = _generator()
                for index, items in todo:
                    make_shard(out, config, index, items, generator, done)
            else:
                summary.retries = _run_local(out, config, todo, jobs, done)
        summary.shards = len(todo)
        summary.seconds = time.monotonic() - start
        summary.index_written = write_index(out, config) is not None
    return summary


def _run_local(out: Path, config: DatasetConfig, todo: list, jobs: int, done) -> int:
    """Shards on ``jobs`` worker processes; the pool is started again when a worker dies.
    Returns how many times it was."""
    import multiprocessing

    context = multiprocessing.get_context("spawn")
    left = dict(todo)  # shard index -> its scenes, until the shard is whole
    restarts = 0
    while True:
        lost = _local_round(context, out, config, left, jobs, done)
        if not left:
            return restarts
        restarts += 1
        if restarts > WORKER_RESTARTS:
            raise UserError(
                f"local workers died {restarts} times ({lost}); {len(left)} shards not made: "
                "rerun the same command to resume"
            )


def _local_round(context, out: Path, config: DatasetConfig, left: dict, jobs: int, done) -> str:
    """One pool's run over the shards of ``left``, removing each shard it makes; returns
    what broke the pool ('' when nothing did). A shard's own error ends the run."""
    from concurrent.futures import ProcessPoolExecutor
    from concurrent.futures.process import BrokenProcessPool

    reports = context.Queue()  # (a new one: a killed worker may leave the old one torn)
    pool = ProcessPoolExecutor(min(jobs, len(left)), mp_context=context,
                               initializer=_init_worker, initargs=(reports,))  # fmt: skip
    lost = ""
    try:
        futures = {pool.submit(_worker_shard, str(out), config, i, items): i
                   for i, items in left.items()}  # fmt: skip
        pending = set(futures)
        while pending:
            _drain(reports, done)
            finished = {f for f in pending if f.done()}
            pending -= finished
            for f in finished:
                try:
                    f.result()  # (a worker's error ends the run; a rerun resumes)
                except BrokenProcessPool as e:
                    lost = _first_line(e)
                else:
                    del left[futures[f]]
        _drain(reports, done, wait=False)
    finally:
        pool.shutdown(wait=True, cancel_futures=True)
        reports.close()
        reports.cancel_join_thread()
    return lost


def _drain(reports, done, wait: bool = True) -> None:
    """Hand the workers' scene reports to ``done`` (progress only: a report torn by a
    killed worker is dropped; the shard's index on disk is what counts)."""
    try:
        record = reports.get(timeout=POLL_SECONDS) if wait else reports.get_nowait()
        done(record)
        while True:
            done(reports.get_nowait())
    except (queue_module.Empty, EOFError, OSError, ValueError, pickle.UnpicklingError):
        pass


def _import_ray():
    try:
        import ray
    except ImportError:
        raise UserError(RAY_HINT) from None
    return ray


def _run_ray(ray, out: Path, config: DatasetConfig, todo: list, jobs: int,
             address: str | None, done) -> None:  # fmt: skip
    """Shards on ``jobs`` Ray actors, each scene reported as it is made; a failed shard is
    retried. Returns how many tasks were submitted again."""
    started = not ray.is_initialized()
    if started:
        _connect(ray, address)
    try:
        from ray.util.queue import Queue

        reports = Queue(actor_options={"num_cpus": 0})
        # (tasks are retried here, not by Ray, so that the summary counts the retries)
        actor_class = ray.remote(num_cpus=1, max_restarts=ACTOR_RESTARTS,
                                 max_task_retries=0)(_ShardActor)  # fmt: skip
        actors = [actor_class.remote() for _ in range(min(jobs, len(todo)))]
        queue = list(todo)
        attempts: Counter = Counter()
        lost = 0
        running: dict = {}  # ref -> (actor, index, items)
        idle = list(actors)
        while queue or running:
            while queue and idle:
                index, items = queue.pop(0)
                actor = idle.pop()
                ref = actor.make.remote(str(out), config, index, items, reports)
                running[ref] = (actor, index, items)
            ready, _ = ray.wait(list(running), num_returns=1, timeout=POLL_SECONDS)
            for record in _reported(ray, reports):
                done(record)
            if not ready:
                continue
            ref = ready[0]
            actor, index, items = running.pop(ref)
            idle.append(actor)
            try:
                records = ray.get(ref)
            except ray.exceptions.RayTaskError as e:  # the shard's own error
                attempts[index] += 1
                if attempts[index] >= SHARD_ATTEMPTS:
                    raise UserError(
                        f"shard {index} failed {SHARD_ATTEMPTS} times; last: {_first_line(e)}"
                    ) from None
                queue.append((index, items))
                continue
            except (ray.exceptions.RayError, OSError) as e:  # its actor lost (restarting)
                lost += 1
                if lost > ACTOR_RESTARTS * len(actors):
                    raise UserError(
                        f"Ray workers lost {lost} times; last: {_first_line(e)}; rerun the "
                        "same command to resume"
                    ) from None
                queue.append((index, items))
                continue
            for record in records:  # (those the queue has not brought yet)
                done(record)
    finally:
        if started:
            ray.shutdown()
    return sum(attempts.values()) + lost


def _reported(ray, reports) -> list:
    """The scenes the actors reported since the last look (progress only: a lost queue
    actor leaves the bar to the shards' own records)."""
    try:
        return reports.get_nowait_batch(reports.size())
    except (ray.exceptions.RayError, queue_module.Empty):
        return []


RAY_CONNECT_SECONDS = 10.0
"""How long ``--ray-address host:port`` may take to answer before the run is refused."""


def check_ray_address(address: str | None) -> None:
    """A ``host:port`` address (``ray://`` too) nothing answers on is refused at once with
    one line, not left to Ray's reconnection loop; other forms (``auto``, None) pass."""
    hostport = (address or "").removeprefix("ray://")
    host, sep, port = hostport.rpartition(":")
    if not (sep and host and port.isdigit()):
        return
    import socket

    try:
        socket.create_connection((host.strip("[]"), int(port)), RAY_CONNECT_SECONDS).close()
    except (OSError, OverflowError) as e:
        raise UserError(
            f"--ray-address {address}: no Ray cluster answers there ({_first_line(e)})"
        ) from None


def _connect(ray, address: str | None) -> None:
    """``ray.init`` on ``address`` (None: a Ray instance of this machine's own), or one
    line why not."""
    check_ray_address(address)
    try:
        ray.init(address=address, include_dashboard=False, log_to_driver=False)
    except (ConnectionError, RuntimeError, ValueError) as e:
        raise UserError(f"--ray-address {address}: {_first_line(e)}") from None


def _first_line(e: BaseException) -> str:
    text = str(e).strip().splitlines()
    return text[-1] if text else type(e).__name__


class _Bar:
    """One progress bar over all workers: scenes done, scenes per minute, time left."""

    def __init__(self, total: int, enabled: bool) -> None:
        self.total, self.enabled = total, enabled and total > 0
        self.progress = self.task = None

    def __enter__(self) -> _Bar:
        if self.enabled:
            from pair2scene.progress import progress_bar

            self.progress = progress_bar("{task.fields[rate]}", description="scenes")
            self.progress.__enter__()
            self.task = self.progress.add_task("scenes", total=self.total, rate="")
            self.start = time.monotonic()
        return self

    def advance(self, n: int = 1) -> None:
        if self.progress is None:
            return
        task = self.progress.tasks[0]
        elapsed = time.monotonic() - self.start
        rate = 60.0 * (task.completed + n) / elapsed if elapsed > 0 else 0.0
        self.progress.update(self.task, advance=n, rate=f"{rate:.1f}/min")

    def __exit__(self, *exc) -> None:
        if self.progress is not None:
            self.progress.__exit__(*exc)

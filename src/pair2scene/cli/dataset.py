"""``pair2scene dataset``: build a sharded dataset of scenes (the group's own command) and
``pair2scene dataset verify OUT`` (recheck its digests). Calls :mod:`pair2scene.dataset`.

Before it is wired into ``pair2scene``, run it as ``python -m pair2scene.cli.dataset ...``
(:func:`run`: the same one-line errors and exit codes).
"""

from __future__ import annotations

import sys
from pathlib import Path
from typing import Annotated

import typer

from pair2scene.cli.checks import MAX_NUM, SEED_LIMIT, check_choice, check_count, writable_folder
from pair2scene.dataset.plan import (
    DEFAULT_DATASET_FORMATS,
    DEFAULT_SHARD_SIZE,
    MAX_SHARD_SIZE,
    SHARD_FORMATS,
)
from pair2scene.errors import UserError

MAX_JOBS = 256
"""The most workers ``--jobs`` may ask for."""

dataset_app = typer.Typer(
    help="Datasets of scenes at scale: shards with digests, an index, resumable.",
    invoke_without_command=True,
    add_completion=False,
    pretty_exceptions_enable=False,
)


@dataset_app.callback()
def dataset_command(
    ctx: typer.Context,
    out: Annotated[
        Path | None,
        typer.Option(help="Dataset folder (resumed if it holds this dataset).", metavar="DIR"),
    ] = None,
    room: Annotated[
        list[str] | None,
        typer.Option(help="A room type (repeatable); equal shares unless --mix is given."),
    ] = None,
    num: Annotated[int, typer.Option(help=f"Scenes in the dataset, 1 .. {MAX_NUM:,}.")] = 0,
    mix: Annotated[
        str | None,
        typer.Option(help="Shares of room types: bedroom=0.4,kitchen=0.3,living_room=0.3."),
    ] = None,
    mode: Annotated[str, typer.Option(help="fit (training-like counts) or beyond.")] = "fit",
    max_objects: Annotated[
        int | None, typer.Option(help="beyond: objects to reach; fit: a cap.")
    ] = None,
    formats: Annotated[
        str, typer.Option(help="Files per scene: json (always), glb, png, html.")
    ] = DEFAULT_DATASET_FORMATS,
    shard_size: Annotated[
        int, typer.Option(help=f"Scenes per shard, 1 .. {MAX_SHARD_SIZE:,}.")
    ] = DEFAULT_SHARD_SIZE,
    shard_format: Annotated[
        str, typer.Option(help="dir (a folder per shard) or tar (WebDataset-style).")
    ] = "dir",
    executor: Annotated[str, typer.Option(help="local (processes) or ray (actors).")] = "local",
    jobs: Annotated[int, typer.Option(help=f"Workers, 1 .. {MAX_JOBS}.")] = 1,
    ray_address: Annotated[
        str | None, typer.Option(help="Ray cluster address (default: start a local Ray).")
    ] = None,
    shard: Annotated[
        str | None,
        typer.Option(help="Make only slice i/N of the shards (e.g. a SLURM array task)."),
    ] = None,
    seed: Annotated[
        int, typer.Option(help=f"First seed; scene k has seed+k < 2**32 ({SEED_LIMIT:,}).")
    ] = 0,
    quiet: Annotated[bool, typer.Option("--quiet", help="No progress bar.")] = False,
) -> None:
    """Build a dataset: OUT/manifest.json, OUT/shards/shard-NNNNN(/ or .tar) with
    shard-NNNNN.index.jsonl each, and OUT/index.jsonl once every shard is whole. Rerun the
    same command to resume; 'pair2scene dataset verify OUT' rechecks the digests."""
    if ctx.invoked_subcommand is not None:
        return
    from pair2scene.dataset.executors import EXECUTORS, RAY_HINT, run_dataset
    from pair2scene.dataset.plan import (
        DatasetConfig,
        check_config,
        check_rooms,
        parse_formats,
        parse_mix,
        parse_slice,
    )

    if out is None:
        raise UserError("give --out DIR (the dataset folder)")
    if num == 0:
        raise UserError("give --num N (scenes in the dataset)")
    check_count(jobs, "--jobs", MAX_JOBS)
    check_choice(executor, "--executor", EXECUTORS)
    check_choice(shard_format, "--shard-format", SHARD_FORMATS)
    config = DatasetConfig(
        mix=parse_mix(mix, room or []), num=num, mode=mode, max_objects=max_objects,
        formats=parse_formats(formats), shard_size=shard_size, shard_format=shard_format,
        seed=seed,
    )  # fmt: skip
    check_config(config)
    part = parse_slice(shard)
    if ray_address is not None and executor != "ray":
        raise UserError("--ray-address goes with --executor ray")
    if executor == "ray":
        try:
            import ray  # noqa: F401
        except ImportError:
            raise UserError(RAY_HINT) from None
    out = writable_folder(out, "--out")
    check_rooms(config, mix)
    summary = run_dataset(out, config, executor, jobs, part, ray_address, progress=not quiet)
    for line in summary.lines():
        typer.echo(line)
    if summary.index_written:
        typer.echo(f"index: {out / 'index.jsonl'}")


@dataset_app.command("verify")
def verify_command(
    out: Annotated[Path, typer.Argument(help="The dataset folder.")],
) -> None:
    """Recheck every shard's files against the digests of its index; exit 1 when a shard
    is missing or corrupt, 0 when all are whole."""
    from pair2scene.dataset.verify import verify_dataset

    report = verify_dataset(out)
    for line in report.lines():
        typer.echo(line)
    if not report.clean:
        raise typer.Exit(1)


def run(argv: list[str] | None = None) -> int:
    """The group as a command of its own (``python -m pair2scene.cli.dataset ...``): the
    main command line's ``pair2scene dataset ...``, with its one-line errors (exit 2)."""
    from pair2scene.cli import main

    return main(["dataset", *(sys.argv[1:] if argv is None else argv)])


if __name__ == "__main__":
    sys.exit(run())

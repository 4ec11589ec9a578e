"""``pair2scene curate``: sources -> 3D-Pairs, statistics and a report.

Thin: parses its arguments and calls :func:`pair2scene.curation.pipeline.curate`,
which a Python user can call the same way.
"""

from __future__ import annotations

import sys
from pathlib import Path
from typing import Annotated

import typer

from pair2scene.cli.checks import (
    MAX_WORKERS,
    SEED_LIMIT,
    check_count,
    check_seed,
    out_option,
    writable_folder,
)


def curate(
    source: Annotated[
        list[str],
        typer.Option(
            "--source",
            help="ai2thor, procthor:PATH (.jsonl.gz or folder), 3dfront:PATH or scenes:DIR (a "
            "folder of scene.json files); repeat for more.",
        ),
    ],
    out: Annotated[
        Path,
        out_option("Output folder (an earlier run there resumes)."),
    ],
    functional: Annotated[
        str, typer.Option(help="Functional proposer: offline (built-in table) or llm.")
    ] = "offline",
    physics: Annotated[
        bool, typer.Option("--physics/--no-physics", help="Drop what does not stay put (MuJoCo).")
    ] = True,
    exclude_floor_only: Annotated[
        list[str] | None,
        typer.Option(
            "--exclude-floor-only",
            help="Leave out floor-only tuples of this source (ai2thor, procthor...); repeatable.",
        ),
    ] = None,
    seed: Annotated[
        int,
        typer.Option(
            help=f"Seed of the procedural assets physics builds; 0 .. 2**32 - 1 "
            f"({SEED_LIMIT - 1:,})."
        ),
    ] = 0,
    workers: Annotated[
        int | None,
        typer.Option(help=f"Processes for the per-scene stages, 1 .. {MAX_WORKERS} (default 2)."),
    ] = None,
    fresh: Annotated[
        bool, typer.Option("--fresh", help="Redo everything instead of resuming.")
    ] = False,
) -> None:
    """Curate scenes into relation tuples (3D-Pairs): support from geometry, physics check,
    functional anchors. Writes OUT/manifest.json and OUT/shards/ (the tuples),
    OUT/stats.json (hierarchy statistics) and OUT/report.json (counts, drop rates, support
    precision/recall/F1 under "support_eval", timings).

    A source that cannot be read is reported and skipped; the others are curated. An
    interrupted run continues where it stopped when run again with the same arguments.
    """
    check_seed(seed)
    check_count(workers, "--workers", MAX_WORKERS)
    out = writable_folder(out, "--out")
    from pair2scene.curation.pipeline import REPORT_FILE, CurateConfig
    from pair2scene.curation.pipeline import curate as run_curate

    config = CurateConfig(
        sources=tuple(source),
        out=out,
        functional=functional.strip().lower(),
        physics=physics,
        exclude_floor_only=frozenset(exclude_floor_only or ()),
        seed=seed,
        workers=workers,
        fresh=fresh,
    )
    report = run_curate(config, progress=True)
    for s in report.skipped:
        print(f"warning: skipped source {s.spec}: {s.reason}", file=sys.stderr)
    for s in report.sources:
        kinds = ", ".join(f"{k} {n}" for k, n in s.tuples.items() if k != "total")
        line = (
            f"{s.label}: {s.rooms} rooms, {s.objects} objects, {s.dropped} dropped "
            f"({100 * s.drop_rate:.1f}%), {s.tuples['total']} tuples ({kinds})"
        )
        if s.support_eval is not None:
            e = s.support_eval
            line += f"; support P {e.precision:.3f} R {e.recall:.3f} F1 {e.f1:.3f}"
        if s.chunks_reused:
            line += f"; {s.chunks_reused}/{s.chunks} chunks reused"
        typer.echo(line)
    typer.echo(
        f"{report.tuples} tuples in {out} ({report.seconds:.1f} s); report: {out / REPORT_FILE}"
    )

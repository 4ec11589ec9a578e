"""``pair2scene evaluate``: calls :func:`pair2scene.evaluate.evaluate`."""

from __future__ import annotations

import json
from pathlib import Path
from typing import Annotated

import typer

from pair2scene.cli.checks import (
    MAX_THREADS,
    SEED_LIMIT,
    check_range,
    check_seed,
    check_threads,
    out_option,
    writable_file,
)
from pair2scene.metrics.sca import MAX_REPEATS, REPEATS


def evaluate_command(
    scenes: Annotated[Path, typer.Option(help="Folder of generated scenes (pair2scene generate).")],
    out: Annotated[
        Path,
        out_option(
            "Report JSON to write (a file, not a folder; OUT.cache.json beside it).", "FILE"
        ),
    ],
    reference: Annotated[
        list[str] | None,
        typer.Option(
            help="Real rooms: ai2thor:val, procthor:PATH[:val], a scene folder; repeatable."
        ),  # fmt: skip
    ] = None,
    physics: Annotated[bool, typer.Option(help="Mesh collision and floating.")] = True,
    simulate: Annotated[bool, typer.Option(help="Stability: 2 s of MuJoCo per scene.")] = True,
    images: Annotated[bool, typer.Option(help="FID, KID and SCA on top views.")] = True,
    seed: Annotated[
        int,
        typer.Option(
            help=f"Seeds subsets (KID, SCA, pose MMD); 0 .. 2**32 - 1 ({SEED_LIMIT - 1:,})."
        ),
    ] = 0,
    threads: Annotated[
        int | None,
        typer.Option(help=f"Torch threads for FID and SCA, 1 .. {MAX_THREADS} (default: torch's)."),
    ] = None,
    sca_repeats: Annotated[
        int,
        typer.Option(
            help=f"Repeats of SCA's 5-fold cross-validation, averaged, 1 .. {MAX_REPEATS} "
            "(one run's accuracy moves by ~0.05 with the seed on 30 rooms a class)."
        ),
    ] = REPEATS,
    as_json: Annotated[bool, typer.Option("--json", help="Print the report as JSON.")] = False,
) -> None:
    """Evaluate generated scenes against real rooms of the same type: physical, process
    and distribution metrics, FID/KID/SCA on top views; writes the report to OUT."""
    check_seed(seed)
    check_threads(threads)
    check_range(sca_repeats, "--sca-repeats", 1, MAX_REPEATS)
    out = writable_file(out, "--out")
    from pair2scene.evaluate import HEADLINE, SECTIONS, evaluate, section_rows
    from pair2scene.metrics.significance import p_label, stat_label

    report = evaluate(scenes, reference or ["ai2thor:val"], out, physics=physics,
                      simulate=simulate, images=images, seed=seed,
                      progress=not as_json, threads=threads,
                      sca_repeats=sca_repeats)  # fmt: skip
    if as_json:
        typer.echo(json.dumps(report, indent=1))
        return
    typer.echo(
        f"{report['n_generated']} scenes vs {report['n_reference']} reference rooms "
        f"({', '.join(report['room_types'])}) -> {out}"
    )
    for key in HEADLINE:
        value = report.get(key)
        typer.echo(f"  {key:<22}{'-' if value is None else f'{value:.4g}'}")
    tested = False
    for name in SECTIONS:
        section = report.get(name, {})
        rows = [r for r in section_rows(section) if r[1]["rate"] is not None
                or r[2]["rate"] is not None]  # fmt: skip
        if rows:
            typer.echo(f"{name:<34}{'generated':<18}{'reference':<18}differ?")
        for measure, gen, ref in rows:
            p = section[measure].get("p_value")
            tested |= p is not None
            typer.echo(f"  {measure:<32}{stat_label(gen):<18}{stat_label(ref):<18}{p_label(p)}")
    if tested:
        typer.echo(
            "differ?: two-sided exact test of one rate for both (Fisher's for shares, "
            "Poisson rates for counts per room); p < 0.05: beyond these rooms' noise"
        )
    for note in report.get("notes", []):
        typer.echo(f"note: {note}")

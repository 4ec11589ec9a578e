"""``pair2scene score``: the mean NLL of a layout model on a split of a 3D-Pairs folder.

Thin: parses its arguments and calls :func:`pair2scene.model.scoring.load_model` and
:func:`pair2scene.model.scoring.score`, which a Python user can call the same way.
Registered by :mod:`pair2scene.cli` as ``app.command("score")(score_command)``.
"""

from __future__ import annotations

import json
from pathlib import Path
from typing import Annotated

import typer


def score_command(
    data: Annotated[
        Path, typer.Option("--data", help="3D-Pairs folder (the output of pair2scene curate).")
    ],
    model: Annotated[
        str,
        typer.Option(
            help="gaussian (the baseline, fitted on the train split of --data), default "
            "(the learned model), or a path: a saved baseline JSON or a checkpoint."
        ),
    ] = "default",
    split: Annotated[str, typer.Option(help="Split to score: val or train.")] = "val",
    as_json: Annotated[bool, typer.Option("--json", help="Print JSON (see below).")] = False,
    seed: Annotated[int, typer.Option(help="Seed of the baseline's EM (--model gaussian).")] = 0,
    save_baseline: Annotated[
        Path | None,
        typer.Option(help="With --model gaussian: also write the fitted baseline as JSON here."),
    ] = None,
) -> None:
    """Score a layout model: mean negative log-likelihood (nats per tuple) of each tuple's
    box in its support anchor's canonical frame, exactly as 3D-Pairs stores it (centre,
    size, 6D rotation), computed the same way for every model.

    --json prints one object: {"nll", "n", "model", "split", "median_nll", "nonfinite",
    "per_kind": {kind: {"nll", "n"}}, "per_source": {source: {"nll", "n"}}}; an NLL that
    is not finite is null.
    """
    from pair2scene.curation.dataset import load_pairs
    from pair2scene.errors import UserError
    from pair2scene.model.baseline import GaussianBaseline, GaussianConfig
    from pair2scene.model.scoring import load_model, score

    if save_baseline is not None and model != "gaussian":
        raise UserError("--save-baseline needs --model gaussian")
    pairs = load_pairs(data)
    scorer = load_model(model, pairs, baseline_config=GaussianConfig(seed=seed))
    if save_baseline is not None:
        assert isinstance(scorer, GaussianBaseline)
        scorer.save(save_baseline)
    result = score(scorer, pairs, split)
    if as_json:
        typer.echo(json.dumps({**result.to_dict(), "model": model}, indent=1))
        return
    typer.echo(
        f"{model} on {split}: NLL {result.nll:.3f} nats/tuple over {result.n} tuples "
        f"(median {result.median_nll:.3f})"
    )
    for title, groups in (("kind", result.per_kind), ("source", result.per_source)):
        for name, g in groups.items():
            typer.echo(f"  {title} {name}: NLL {g.nll:.3f} ({g.n})")
    if result.nonfinite:
        typer.echo(f"  {result.nonfinite} tuples with zero density")

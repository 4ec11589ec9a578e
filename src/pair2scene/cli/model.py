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

from pair2scene.cli.checks import (
    MAX_BATCH,
    MAX_EPOCHS,
    MAX_STEPS,
    SEED_LIMIT,
    check_count,
    check_seed,
    out_option,
    path_parser,
    writable_file,
    writable_folder,
)

SEED_HELP = f"0 .. 2**32 - 1 ({SEED_LIMIT - 1:,})"


def score_command(
    data: Annotated[
        Path, typer.Option("--data", help="3D-Pairs folder (the output of pair2scene curate).")
    ],
    model: Annotated[
        str,
        typer.Option(
            help="gaussian (the baseline, fitted on the train split of --data or --fit-on), "
            "default (the learned model), or a path: a saved baseline JSON or a checkpoint."
        ),
    ] = "default",
    split: Annotated[str, typer.Option(help="Split to score: val or train.")] = "val",
    as_json: Annotated[bool, typer.Option("--json", help="Print JSON (see below).")] = False,
    seed: Annotated[
        int, typer.Option(help=f"Seed of the baseline's EM (--model gaussian); {SEED_HELP}.")
    ] = 0,
    anchor_frames: Annotated[
        bool,
        typer.Option(
            help="With --model gaussian: fit each tuple in its governing anchor's frame (a "
            "wall, a functional anchor), as the learned model does; --no-anchor-frames: "
            "every tuple in its support's frame."
        ),
    ] = True,
    save_baseline: Annotated[
        Path | None,
        typer.Option(
            parser=path_parser("--save-baseline"),
            metavar="FILE",
            help="With --model gaussian: also write the fitted baseline as JSON here.",
        ),
    ] = None,
    fit_on: Annotated[
        Path | None,
        typer.Option(
            help="With --model gaussian: fit it on the train split of this 3D-Pairs folder "
            "instead of --data's (score your data with a baseline of another)."
        ),
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

    check_seed(seed)
    for flag, value in (("--save-baseline", save_baseline), ("--fit-on", fit_on)):
        if value is not None and model != "gaussian":
            raise UserError(f"{flag} needs --model gaussian")
    if save_baseline is not None:
        save_baseline = writable_file(save_baseline, "--save-baseline")
    pairs = load_pairs(data)
    fit = pairs if fit_on is None else load_pairs(fit_on)
    scorer = load_model(
        model, fit, baseline_config=GaussianConfig(seed=seed, anchor_frames=anchor_frames)
    )
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


def pretrain_command(
    out: Annotated[
        Path,
        out_option("Folder for the encoder's files."),
    ],
    preset_name: Annotated[
        str, typer.Option("--preset", help="Encoder sizes: tiny, cpu (default) or paper.")
    ] = "cpu",
    steps: Annotated[
        int | None,
        typer.Option(help=f"Optimiser steps, 1 .. {MAX_STEPS:,} (default: the preset's schedule)."),
    ] = None,
    batch_size: Annotated[
        int | None, typer.Option(help=f"Clouds per step, 1 .. {MAX_BATCH:,}.")
    ] = None,
    seed: Annotated[
        int, typer.Option(help=f"Seeds the assets, weights, batches, masks; {SEED_HELP}.")
    ] = 0,
    as_json: Annotated[bool, typer.Option("--json", help="Print the result as JSON.")] = False,
) -> None:
    """Pre-train the Point-MAE encoder by masked autoencoding (mask 0.6, Chamfer-L2) on
    the procedural asset library's clouds; writes encoder.safetensors + pointmae.json."""
    check_count(steps, "--steps", MAX_STEPS)
    check_count(batch_size, "--batch-size", MAX_BATCH)
    check_seed(seed)
    out = writable_folder(out, "--out")
    from pair2scene.model.pretrain import pretrain, pretrain_config

    config = pretrain_config(preset_name, steps=steps, batch_size=batch_size, seed=seed)
    result = pretrain(config, out, progress=True)
    doc = {
        "out": str(out),
        "steps": config.steps,
        "clouds": result.n_train,
        "val_chamfer": [list(v) for v in result.val_losses],
        "seconds": round(result.seconds, 1),
    }
    if as_json:
        typer.echo(json.dumps(doc, indent=1))
        return
    first, last = result.val_losses[0][1], result.val_losses[-1][1]
    typer.echo(
        f"encoder -> {out} ({config.steps} steps, {result.seconds:.0f} s); held-out "
        f"Chamfer-L2 {first:.4f} -> {last:.4f}"
    )


def train_command(
    data: Annotated[
        Path, typer.Option("--data", help="3D-Pairs folder (the output of pair2scene curate).")
    ],
    out: Annotated[
        Path,
        out_option("Checkpoint folder (resumed if present)."),
    ],
    preset_name: Annotated[
        str, typer.Option("--preset", help="tiny, cpu (default) or paper.")
    ] = "cpu",
    variant: Annotated[
        str, typer.Option(help="full (the method), class-only, no-pretrain or global.")
    ] = "full",
    encoder: Annotated[
        Path | None,
        typer.Option(help="Pre-trained encoder folder (pair2scene pretrain); default: bundled."),
    ] = None,
    epochs: Annotated[
        int | None, typer.Option(help=f"Override the preset's epochs, 1 .. {MAX_EPOCHS:,}.")
    ] = None,
    max_steps: Annotated[
        int | None, typer.Option(help=f"Stop after this many steps, 1 .. {MAX_STEPS:,}.")
    ] = None,
    seed: Annotated[
        int, typer.Option(help=f"Seeds the weights and the batch order; {SEED_HELP}.")
    ] = 0,
    anchor_frames: Annotated[
        bool,
        typer.Option(
            help="Predict each tuple in its governing anchor's frame (a wall, a functional "
            "anchor); --no-anchor-frames: every tuple in its support's frame (the paper)."
        ),
    ] = True,
    yaw_modes: Annotated[
        int,
        typer.Option(
            help="Right-angle yaw turns per mixture component: 4 (quarter turns), 2, or 1 "
            "(off: one yaw per component, as the paper)."
        ),
    ] = 4,
    pair_prior: Annotated[
        bool,
        typer.Option(
            help="Add each category pair's median centre over the train tuples to the "
            "network's output (a rare pair keeps its own placement); --no-pair-prior: the "
            "network alone."
        ),
    ] = True,
    pair_modes: Annotated[
        bool,
        typer.Option(
            help="Give each category pair one centre per mixture component: its train "
            "tuples' k-means clusters and their shares (a pair that lies in two places keeps "
            "both); --no-pair-modes: the pair's median alone. Needs --pair-prior."
        ),
    ] = False,
    pair_turns: Annotated[
        bool | None,
        typer.Option(
            "--pair-turns/--no-pair-turns",
            help="Add each category pair's share of each right-angle yaw turn over the train "
            "tuples to the network's turn logits (a pair keeps its own split of yaws, as the "
            "bundled model); --no-pair-turns: the network alone (docs/model.md). Default: on "
            "wherever --yaw-modes leaves turns to share out (2 or 4).",
            show_default=False,
        ),
    ] = None,
    as_json: Annotated[bool, typer.Option("--json", help="Print the result as JSON.")] = False,
) -> None:
    """Train the layout model on the train split, measuring validation NLL every epoch.

    Writes OUT/model.safetensors + OUT/config.json (the best epoch by validation NLL) and
    a resumable training state: running the same command again continues an interrupted
    run.
    """
    check_count(epochs, "--epochs", MAX_EPOCHS)
    check_count(max_steps, "--max-steps", MAX_STEPS)
    check_seed(seed)
    out = writable_folder(out, "--out")
    from pair2scene.model.train import TrainConfig, train

    config = TrainConfig(
        preset=preset_name,
        variant=variant,
        encoder=None if encoder is None else str(encoder),
        epochs=epochs,
        max_steps=max_steps,
        seed=seed,
        anchor_frames=anchor_frames,
        yaw_modes=yaw_modes,
        pair_prior=pair_prior,
        pair_modes=pair_modes,
        pair_turns=pair_turns,
    )
    result = train(config, data, out, progress=not as_json)
    doc = {
        "out": str(out),
        "best_epoch": result.best_epoch,
        "val_nll": result.best_val_nll,
        "epochs": len(result.history),
        "seconds": round(result.seconds, 1),
        "peak_rss_mb": round(result.peak_rss_mb, 1),
    }
    if as_json:
        typer.echo(json.dumps(doc, indent=1))
        return
    typer.echo(
        f"{variant} -> {out}: best val NLL {result.best_val_nll:.3f} nats/tuple at epoch "
        f"{result.best_epoch} ({result.seconds:.0f} s, peak {result.peak_rss_mb:.0f} MB)"
    )

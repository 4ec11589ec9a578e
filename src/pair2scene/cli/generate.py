"""``pair2scene generate``: the main job: calls :func:`pair2scene.generate.generate_scenes`."""

from __future__ import annotations

import json
from pathlib import Path
from typing import Annotated

import typer

from pair2scene.cli.checks import (
    MAX_NUM,
    MAX_THREADS,
    SEED_LIMIT,
    check_choice,
    check_count,
    check_max_objects,
    check_seed,
    check_threads,
    existing_file,
    out_option,
    writable_folder,
)
from pair2scene.cli.options import field_help, with_config
from pair2scene.generate import GenerateConfig
from pair2scene.hierarchy.build import LLM_CHOICES
from pair2scene.hierarchy.synthesis import MAX_OBJECTS_LIMIT, MODES
from pair2scene.io.export import ExportConfig


@with_config(GenerateConfig)
def generate_command(
    out: Annotated[
        Path,
        out_option(
            "Output folder (resumed if present); made if missing, its folder must be writable."
        ),
    ],
    room: Annotated[
        str | None,
        typer.Option(
            help="Room type: bedroom, living_room, kitchen, bathroom, apartment (trained), or "
            "office, study, dining_room, kids_room (composed from them; see README)."
        ),
    ] = None,
    text: Annotated[str | None, typer.Option(help="A description of the room.")] = None,
    num: Annotated[
        int,
        typer.Option(help=f"Scenes to generate (seeds seed .. seed+num-1), 1 .. {MAX_NUM:,}."),
    ] = 1,
    seed: Annotated[
        int,
        typer.Option(
            help=f"First seed; same seed, same scene. 0 <= seed and seed+num-1 < 2**32 "
            f"({SEED_LIMIT:,})."
        ),
    ] = 0,
    mode: Annotated[str, typer.Option(help="fit (training-like counts) or beyond.")] = "fit",
    max_objects: Annotated[
        int | None,
        typer.Option(
            help=f"beyond: objects to reach (default 80); fit: a cap. 1 .. {MAX_OBJECTS_LIMIT}."
        ),
    ] = None,
    model: Annotated[
        str,
        typer.Option(
            help="default (bundled), a checkpoint folder, or a baseline: random, "
            "gaussian:PAIRS_DIR (fitted on a 3D-Pairs folder) or gaussian:FILE.json (saved)."
        ),
    ] = "default",
    llm: Annotated[str, typer.Option(help="--text: auto, never (offline) or always.")] = "auto",
    keep: Annotated[
        Path | None,
        typer.Option(help="A partial scene.json: its room and objects stay, the rest is added."),
    ] = None,
    settle: Annotated[
        bool, typer.Option("--settle", help="End with a short MuJoCo settle of the scene.")
    ] = False,
    ablation: Annotated[
        list[str] | None,
        typer.Option(
            help="Switch a placement step off: no-rejection (take each object's first "
            "candidate), no-gravity (keep its drawn height) or no-confine (draw floor "
            "candidates out of the room's reach too, as plain rejection sampling); "
            "repeatable."
        ),
    ] = None,
    stats: Annotated[
        Path | None,
        typer.Option(
            help="stats.json of your own curation (pair2scene curate --out DIR): its room "
            "types, categories and sizes instead of the bundled ones."
        ),
    ] = None,
    threads: Annotated[
        int | None,
        typer.Option(
            help=f"CPU threads of numpy's BLAS, and of torch where it is loaded, 1 .. "
            f"{MAX_THREADS} (default 1). The layout model runs without torch, on one thread "
            "whatever this says, so that a scene's bytes do not depend on the cores: run "
            "processes side by side for more scenes."
        ),
    ] = None,
    formats: Annotated[
        str, typer.Option(help=field_help(ExportConfig, "formats"))
    ] = ExportConfig.formats,
    dynamic: Annotated[
        str, typer.Option(help=field_help(ExportConfig, "dynamic"))
    ] = ExportConfig.dynamic,
    as_json: Annotated[bool, typer.Option("--json", help="Print the summary as JSON.")] = False,
    config: GenerateConfig | None = None,
) -> None:
    """Generate scenes: OUT/<scene_id>/scene.json, scene.glb, bev.png, scene.html (and the
    --formats asked for), OUT/index.html (a gallery) and OUT/summary.json.

    Every setting of generation (how hierarchies are drawn and placed) is an option below,
    named by its place in the config: --hierarchy.k, --assembly.temperature...
    """
    # Every value is checked before the model loads: a bad one costs no time, writes nothing.
    check_count(num, "--num", MAX_NUM)
    check_seed(seed, count=num)
    check_max_objects(max_objects)
    check_threads(threads)
    check_choice(mode, "--mode", MODES)
    check_choice(llm, "--llm", LLM_CHOICES)
    existing_file(keep, "--keep")
    existing_file(stats, "--stats")
    export = ExportConfig(formats, dynamic)
    export.format_list()
    out = writable_folder(out, "--out")
    from pair2scene.generate import generate_scenes, set_threads

    set_threads(threads)
    summary = generate_scenes(out, room, text, num, seed, mode, max_objects, model, llm,
                              progress=not as_json, keep=keep, settle=settle,
                              ablation=ablation, config=config, stats=stats,
                              export=export)  # fmt: skip
    if as_json:
        typer.echo(json.dumps(summary.to_dict(), indent=1))
        return
    t = summary.totals
    # A folder that held the scenes already is resumed: say so, or its old scenes pass
    # for new ones.
    kept = f" ({summary.kept} of them already there, kept)" if summary.kept else ""
    typer.echo(
        f"{t['scenes']} scene{'' if t['scenes'] == 1 else 's'} in {out}{kept}: "
        f"{t['objects_per_scene']:.1f} objects each, "
        f"acceptance {t['acceptance_rate']:.2f}, {t['resamples_per_object']:.2f} resamples per "
        f"object, {t['seconds_per_scene']:.2f} s per scene"
    )

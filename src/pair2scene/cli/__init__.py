"""The ``pair2scene`` command line. Thin: each command parses, calls one library function.

User errors end in one line on stderr and exit code 2; a traceback means a bug. Every
option is checked before any work (:mod:`pair2scene.cli.checks`); an error of the
operating system that still comes later (a full disk, a folder made read-only while the
command runs) is one line too, naming the path. A message is cut to
:data:`MAX_ERROR_CHARS` characters.
"""

from __future__ import annotations

import inspect
import json
import os
import sys
from pathlib import Path
from typing import Annotated

import typer

from pair2scene.cli.assets import assets_app
from pair2scene.cli.curate import curate
from pair2scene.cli.dataset import dataset_app
from pair2scene.cli.evaluate import evaluate_command
from pair2scene.cli.export import export_command
from pair2scene.cli.generate import generate_command
from pair2scene.cli.hierarchy import hierarchy_command
from pair2scene.cli.model import pretrain_command, score_command, train_command
from pair2scene.errors import UserError

MAX_ERROR_CHARS = 300
"""Longest error message printed; the rest is cut (a message may quote the user's input,
which may be megabytes long)."""

app = typer.Typer(
    name="pair2scene",
    help="Dense, physically plausible 3D indoor scenes from learned pairwise placement rules.",
    no_args_is_help=True,
    add_completion=False,
    pretty_exceptions_enable=False,
)
data_app = typer.Typer(help="Scene corpora: fetch them, inspect them.", no_args_is_help=True)
app.add_typer(data_app, name="data")
app.add_typer(assets_app, name="assets")
app.add_typer(dataset_app, name="dataset")
app.command("curate")(curate)

app.command("pretrain")(pretrain_command)
app.command("train")(train_command)
app.command("score")(score_command)
app.command("hierarchy")(hierarchy_command)
app.command("generate")(generate_command)
app.command("evaluate")(evaluate_command)
app.command("export")(export_command)


@data_app.command("fetch")
def data_fetch(
    source: Annotated[
        str, typer.Argument(help="What to fetch: ai2thor, or inception (FID weights).")
    ],
    force: Annotated[bool, typer.Option(help="Download again even when cached.")] = False,
) -> None:
    """Download a source into the cache ($PAIR2SCENE_CACHE, default ~/.cache/pair2scene)."""
    from pair2scene.data.fetch import fetch

    path = fetch(source, force=force)
    typer.echo(f"{source}: {path}")


@data_app.command("stats")
def data_stats(
    source: Annotated[
        str,
        typer.Argument(
            help="ai2thor, procthor:PATH (.jsonl.gz), 3dfront:PATH or scenes:DIR "
            "(a folder of scene.json files)."
        ),
    ],
    split: Annotated[str | None, typer.Option(help="train or val; both when omitted.")] = None,
    as_json: Annotated[bool, typer.Option("--json", help="Print JSON.")] = False,
) -> None:
    """Count rooms, objects, categories and support edges of a source."""
    from pair2scene.data.sources import load_source
    from pair2scene.data.stats import corpus_stats, format_stats

    corpus = load_source(source, split=split, progress=not as_json)
    stats = corpus_stats(corpus, split=split)
    typer.echo(json.dumps(stats, indent=1) if as_json else format_stats(stats))


@app.command("validate")
def validate(
    files: Annotated[list[Path], typer.Argument(help="scene.json files to check.")],
) -> None:
    """Check scene.json files against the contract; the first bad one stops with exit 2."""
    from pair2scene.io.scene_json import read_scene

    for f in files:
        scene = read_scene(f)
        typer.echo(f"{f}: ok ({len(scene.objects)} objects, room {scene.room.type})")


def reflowed(doc: str | None) -> str | None:
    """A docstring as help text: dedented, each paragraph's lines joined into one, so that
    ``--help`` wraps a paragraph to the terminal's width instead of breaking it where the
    source did (typer keeps a later paragraph's line breaks)."""
    if doc is None:
        return None
    paragraphs = inspect.cleandoc(doc).split("\n\n")
    return "\n\n".join(" ".join(line.strip() for line in p.splitlines()) for p in paragraphs)


def _reflow_commands(group: typer.Typer) -> None:
    """Give every command of ``group`` and its subgroups its reflowed docstring as help."""
    for command in group.registered_commands:
        if command.help is None and command.callback is not None:
            command.help = reflowed(command.callback.__doc__)
    for sub in group.registered_groups:
        _reflow_commands(sub.typer_instance)


_reflow_commands(app)


def error_line(message: str, suffix: str = "") -> str:
    """``error: <message><suffix>`` as one line (line breaks and control characters
    become spaces), the message cut to :data:`MAX_ERROR_CHARS` characters saying how many
    were cut."""
    message = message.strip()
    cut = len(message) - MAX_ERROR_CHARS
    text = "".join(c if c.isprintable() else " " for c in message[:MAX_ERROR_CHARS])
    if cut > 0:
        text += f"... ({cut} more characters)"
    return f"error: {text}{suffix}"


def os_error_message(e: OSError) -> str:
    """``<path>: <reason>`` of an error of the operating system (the target of a rename:
    the file being written, not its temporary)."""
    reason = e.strerror or str(e) or type(e).__name__
    path = e.filename2 if e.filename2 is not None else e.filename
    if path is None:
        return reason
    name = os.fsdecode(path) if isinstance(path, str | bytes | os.PathLike) else str(path)
    return f"{name}: {reason}"


TORCH_HINT = "pip install torch==2.13.0 (the CPU build; pair2scene[model] pins it)"
"""How to get torch, which only training, scoring and the learned metrics (FID, SCA) need."""


def main(argv: list[str] | None = None) -> int:
    """Console entry point: maps user errors and errors of the operating system (a full
    disk, a missing permission) to one line and exit code 2."""
    try:
        rv = app(args=argv, standalone_mode=False)
        if isinstance(rv, int) and rv:  # some typer releases return 130 on Ctrl-C
            if rv == 130:
                print("interrupted", file=sys.stderr)
            return rv
    except UserError as e:
        print(error_line(str(e)), file=sys.stderr)
        return e.exit_code
    except typer.Exit as e:
        return e.exit_code
    except (typer.Abort, KeyboardInterrupt):
        print("interrupted", file=sys.stderr)
        return 130
    except OSError as e:
        print(error_line(os_error_message(e)), file=sys.stderr)
        return 2
    except ModuleNotFoundError as e:
        if e.name != "torch":
            raise
        # Generation runs without torch; training, scoring and the learned metrics need it.
        print(error_line(f"this needs torch, not installed here: {TORCH_HINT}"), file=sys.stderr)
        return 2
    except Exception as e:
        # Usage errors of the argument parser (click's or typer's own vendored copy,
        # depending on the typer release): same one-line treatment.
        if not (hasattr(e, "format_message") and hasattr(e, "exit_code")):
            raise
        if not e.format_message():  # bare command: help was already printed
            return 2
        ctx = getattr(e, "ctx", None)
        hint = f" (see '{ctx.command_path} --help')" if ctx is not None else ""
        print(error_line(e.format_message(), hint), file=sys.stderr)
        return 2
    return 0


def run() -> None:
    sys.exit(main())

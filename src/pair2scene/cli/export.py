"""``pair2scene export``: simulator files and viewer pages for scenes written earlier
(calls :func:`pair2scene.io.export.export_scene` per scene)."""

from __future__ import annotations

from pathlib import Path
from typing import Annotated

import typer

from pair2scene.cli.options import field_help
from pair2scene.errors import UserError
from pair2scene.io.export import ExportConfig

EXPORT_DEFAULT = "mjcf,urdf,html"
"""What ``export`` writes unless asked: the simulator formats that need nothing beyond
the core install, and the viewer page."""


def export_command(
    scenes: Annotated[
        list[Path],
        typer.Argument(
            help="Scene folders (with scene.json) or scene.json files, or an "
            "output folder of generate (every scene folder in it)."
        ),
    ],
    formats: Annotated[
        str, typer.Option(help=field_help(ExportConfig, "formats"))
    ] = EXPORT_DEFAULT,
    dynamic: Annotated[str, typer.Option(help=field_help(ExportConfig, "dynamic"))] = "small",
    out: Annotated[
        Path | None,
        typer.Option(help="Write here instead of beside each scene.json (one scene only)."),
    ] = None,
) -> None:
    """Write MuJoCo (mjcf/scene.xml), USD (scene.usdc), URDF (urdf/) or viewer pages
    (scene.html; index.html for an output folder) for scenes already generated."""
    from pair2scene.io.export import export_scene
    from pair2scene.io.viewer import write_index
    from pair2scene.progress import track

    config = ExportConfig(formats, dynamic)
    names = [f for f in config.format_list() if f != "json" or out is not None]
    targets: list[Path] = []
    galleries: list[Path] = []
    for s in scenes:
        if s.is_dir() and not (s / "scene.json").is_file():
            found = sorted(
                p.parent for p in s.glob("*/scene.json") if not p.parent.name.startswith(".")
            )
            if not found:
                raise UserError(f"{s}: neither a scene folder nor a folder of scene folders")
            targets += found
            galleries.append(s)
        elif not s.exists():
            raise UserError(f"{s}: no such file or folder")
        else:
            targets.append(s)
    if out is not None and len(targets) != 1:
        raise UserError(f"--out takes one scene; {len(targets)} given")
    for t in track(targets, "exporting", enabled=len(targets) > 1):
        export_scene(t, names, config.dynamic, out)
    if "html" in names:
        for g in galleries:
            write_index(g)
    typer.echo(f"{len(targets)} scene(s): {', '.join(names)} written")

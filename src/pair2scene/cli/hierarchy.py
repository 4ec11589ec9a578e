"""``pair2scene hierarchy``: a scene hierarchy from a room type or a description.

Thin: parses its arguments and calls :func:`pair2scene.hierarchy.build.build_hierarchy`.
"""

from __future__ import annotations

import json
from pathlib import Path
from typing import Annotated

import typer

from pair2scene.cli.checks import SEED_LIMIT, check_choice, check_max_objects, check_seed
from pair2scene.cli.options import with_config
from pair2scene.errors import UserError
from pair2scene.hierarchy.build import LLM_CHOICES
from pair2scene.hierarchy.synthesis import MAX_OBJECTS_LIMIT, MODES, HierarchyConfig


@with_config(HierarchyConfig, prefix=("hierarchy",))
def hierarchy_command(
    room: Annotated[
        str | None,
        typer.Option(
            help="Room type: bedroom, living_room, kitchen, bathroom, apartment (trained), or "
            "office, study, dining_room, kids_room (composed from them; see README)."
        ),
    ] = None,
    text: Annotated[str | None, typer.Option(help="A description of the room.")] = None,
    file: Annotated[
        Path | None,
        typer.Option("--file", help="A hierarchy JSON (this command's --json) to validate."),
    ] = None,
    mode: Annotated[
        str, typer.Option(help="fit (counts like the training rooms) or beyond (denser).")
    ] = "fit",
    max_objects: Annotated[
        int | None,
        typer.Option(
            help=f"beyond: objects to reach (default 80); fit: a cap. 1 .. {MAX_OBJECTS_LIMIT}."
        ),
    ] = None,
    seed: Annotated[
        int, typer.Option(help=f"Same seed, same hierarchy. 0 .. 2**32 - 1 ({SEED_LIMIT - 1:,}).")
    ] = 0,
    stats: Annotated[
        Path | None, typer.Option(help="stats.json of a curation run (default: bundled).")
    ] = None,
    llm: Annotated[
        str, typer.Option(help="auto (LLM when configured), never (offline parser), always.")
    ] = "auto",
    as_json: Annotated[bool, typer.Option("--json", help="Print the hierarchy as JSON.")] = False,
    config: HierarchyConfig | None = None,
) -> None:
    """Build a scene hierarchy: which objects, what rests on what (support tree), what is
    placed relative to what (functional trees), and the placement order (sequence).
    With --file, read one (e.g. edited by hand), validate it and print it.

    --json prints {"room_type", "objects", "category_counts", "nodes", "support_tree":
    {"root", "edges": [{"parent", "child"}]}, "functional_trees": [{"support_anchor",
    "edges": [{"anchor", "dependent"}]}], "sequence": [{"dependent", "support",
    "functional_anchor"}], "notes"}; every reference is {"id", "category"}.
    """
    check_seed(seed)
    check_max_objects(max_objects)
    check_choice(mode, "--mode", MODES)
    check_choice(llm, "--llm", LLM_CHOICES)
    from pair2scene.hierarchy.build import build_hierarchy, read_hierarchy

    if file is not None:
        if room is not None or text is not None:
            raise UserError("give one of --room, --text or --file")
        h = read_hierarchy(file)
    else:
        h = build_hierarchy(room, text, mode, max_objects, seed, stats, llm, config)
    if as_json:
        typer.echo(json.dumps(h.to_dict(mode=mode, seed=seed), indent=1))
        return
    typer.echo(f"{h.room_type}: {len(h)} objects ({mode}, seed {seed})")

    def show(parent: str, depth: int) -> None:
        for child in h.children(parent):
            func = h.functional.get(child.id)
            way = ("over" if child.id in h.over else "across from" if child.id in h.across
                   else "facing" if child.id in h.facing else "at")  # fmt: skip
            at = f"  [{way} {func}]" if func else ""
            mid = "  [mid-room]" if child.id in h.mid_room else ""
            typer.echo(f"{'  ' * depth}- {child.id}{at}{mid}")
            show(child.id, depth + 1)

    for root in h.roots():  # the floor, then the walls
        typer.echo(root)
        show(root, 1)
    for note in h.notes:
        typer.echo(f"note: {note}")

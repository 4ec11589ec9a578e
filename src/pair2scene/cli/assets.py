"""``pair2scene assets``: list the procedural asset library, draw its contact sheet,
encode it into the token store.

Thin: each command parses its arguments and calls one function of
:mod:`pair2scene.assets.catalog` or :mod:`pair2scene.assets.sheet`, which a Python user
can call the same way.
"""

from __future__ import annotations

import json
import sys
from pathlib import Path
from typing import Annotated

import typer

from pair2scene.cli.checks import (
    MAX_COLUMNS,
    SEED_LIMIT,
    check_seed,
    out_option,
    writable_file,
)

assets_app = typer.Typer(
    help="Procedural assets: list the library, draw its contact sheet, encode its tokens.",
    no_args_is_help=True,
)


@assets_app.command("list")
def assets_list(
    categories: Annotated[
        str | None, typer.Option(help="Comma-separated categories; all when omitted.")
    ] = None,
    as_json: Annotated[bool, typer.Option("--json", help="Print JSON (see below).")] = False,
) -> None:
    """Every asset category (all canonical categories but room structure): its generator
    module, variants, whether it fits support heights, its typical size, and whether it
    falls back to a labelled box.

    --json prints one object: {"assets": [{"category", "super_category", "module"
    (null for a box fallback), "variants", "fits_support_heights", "typical_size"
    ([x, y, z] metres), "size_source" (ai2thor | procthor | hand | default),
    "box_fallback"}, ...], "counts": {"categories": N, "procedural": P,
    "box_fallback": B}} with N = P + B.
    """
    from pair2scene.assets.catalog import asset_catalog

    entries = asset_catalog(categories)
    n_box = sum(e.box_fallback for e in entries)
    counts = {"categories": len(entries), "procedural": len(entries) - n_box, "box_fallback": n_box}
    if as_json:
        doc = {"assets": [e.to_dict() for e in entries], "counts": counts}
        typer.echo(json.dumps(doc, indent=1))
        return
    header = f"{'category':<20} {'super':<16} {'generator':<12} {'var':>3} {'fits':>4}  size (m)"
    lines = [header, "-" * len(header)]
    for e in entries:
        module = e.module.rsplit(".", 1)[-1] if e.module else "(box)"
        size = " x ".join(f"{x:.3f}" for x in e.typical_size) + f"  [{e.size_source}]"
        fits = "yes" if e.fits_support_heights else "-"
        name, sup = f"{e.category:<20}", f"{e.super_category:<16}"
        lines.append(f"{name} {sup} {module:<12} {e.variants:>3} {fits:>4}  {size}")
    lines.append(
        f"{counts['categories']} categories: {counts['procedural']} procedural, "
        f"{counts['box_fallback']} box fallback"
    )
    typer.echo("\n".join(lines))


@assets_app.command("sheet")
def assets_sheet(
    out: Annotated[
        Path,
        out_option("PNG to write (a file).", "FILE"),
    ] = Path("asset_sheet.png"),
    seed: Annotated[
        int,
        typer.Option(help=f"Seed of every generator's draws; 0 .. 2**32 - 1 ({SEED_LIMIT - 1:,})."),
    ] = 0,
    categories: Annotated[
        str | None, typer.Option(help="Comma-separated categories; all when omitted.")
    ] = None,
    columns: Annotated[
        int | None, typer.Option(min=1, max=MAX_COLUMNS, help=f"Cells per row, 1 .. {MAX_COLUMNS}.")
    ] = None,
) -> None:
    """Draw a contact sheet: per category its top and 3/4 views at its typical size.

    Box fallbacks are captioned in red. A generator that raises gets a red error cell,
    a warning on stderr, and exit code 1 once the sheet is written.
    """
    check_seed(seed)
    out = writable_file(out, "--out")
    from pair2scene.assets.sheet import asset_sheet

    result = asset_sheet(out, categories=categories, seed=seed, columns=columns, progress=True)
    w, h = result.image_size
    typer.echo(
        f"{result.path}: {len(result.categories)} categories "
        f"({len(result.box_fallback)} box fallback), {w}x{h} px, {result.seconds:.1f} s"
    )
    if result.errors:
        for name, message in result.errors.items():
            print(f"warning: {name}: generator failed: {message}", file=sys.stderr)
        raise typer.Exit(1)


@assets_app.command("tokens")
def assets_tokens(
    model: Annotated[
        Path | None,
        typer.Option(help="A checkpoint folder; the bundled model when omitted.", metavar="DIR"),
    ] = None,
) -> None:
    """Encode the asset library into the token store, once: every size the bundled size
    table observed for a category, one mesh each, as generation builds them (1,551 sizes,
    about 40 s), and work out their support surfaces into the surface store. Generation
    keeps each asset's encoder tokens in $PAIR2SCENE_CACHE/tokens and its surfaces in
    $PAIR2SCENE_CACHE/surfaces as it meets the asset; after this, a machine's first rooms
    compute neither. Run it again after changing the model: another checkpoint keeps its
    own tokens. Scenes are the same bytes with or without it."""
    from pair2scene.assembly.place import library_assets
    from pair2scene.assembly.sizes import SizeTable
    from pair2scene.model.api import LayoutModel

    layout = LayoutModel.from_pretrained(model)
    sizes = SizeTable.load()
    rows = sum(len(v) for v in sizes.sizes.values())
    total, new = layout.store_tokens(
        library_assets(sizes, surfaces=True), progress=True, total=rows
    )
    store = layout.token_store
    typer.echo(f"{store.folder}: {total} library assets, {new} encoded now, "
               f"{total - new} there already")  # fmt: skip

"""The asset contact sheet behind ``pair2scene assets sheet``: per asset category its top
and 3/4 views at its typical size, captioned, on one PNG."""

from __future__ import annotations

import io
import time
import zlib
from collections.abc import Sequence
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from pair2scene.assets.catalog import parse_categories
from pair2scene.assets.typical_sizes import typical_size
from pair2scene.render import RGB, Caption, GridCell, compose_grid, render_meshes

__all__ = [
    "SHEET_CELL_PX",
    "SheetResult",
    "asset_cell",
    "asset_sheet",
    "category_rng",
    "generate_variants",
]

SUPER_COLORS: dict[str, RGB] = {
    "large_furniture": (205, 165, 115),
    "fixture": (160, 190, 200),
    "part": (215, 190, 130),
    "wall_object": (185, 160, 200),
    "small_object": (135, 175, 215),
}
"""Asset colour by super-category, so the sheet reads by kind at a glance."""
FALLBACK_COLOR: RGB = (190, 190, 190)
ERROR_RED: RGB = (200, 0, 0)
CAPTION_GREY: RGB = (110, 110, 110)
SHEET_CELL_PX = 160
"""Side of each of the two views in a sheet cell."""


@dataclass(frozen=True)
class SheetResult:
    path: Path
    categories: list[str]
    box_fallback: list[str]
    errors: dict[str, str]
    """Category -> ``ExceptionType: message`` for generators that raised."""
    seconds: float
    image_size: tuple[int, int]
    timings: dict[str, float] = field(default_factory=dict)
    """Seconds spent generating and rendering, in total."""


def category_rng(seed: int, category: str) -> np.random.Generator:
    """A generator fixed by (seed, category): adding categories changes no other cell."""
    return np.random.default_rng([seed, zlib.crc32(category.encode())])


def asset_cell(
    category: str, seed: int = 0, cell_px: int = SHEET_CELL_PX, timings: dict | None = None
) -> tuple[GridCell, bool, str | None]:
    """One sheet cell: the top and 3/4 views of ``category`` at its typical size.

    Returns (cell, is_box_fallback, error message or None)."""
    from PIL import Image

    from pair2scene.assets.registry import generate
    from pair2scene.categories import super_category

    ts = typical_size(category)
    dims = " x ".join(f"{x:.2f}" for x in ts.size) + " m"
    t0 = time.perf_counter()
    error = None
    try:
        asset = generate(category, ts.size, rng=category_rng(seed, category))
    except Exception as e:  # a broken generator must not hide the rest of the sheet
        error = f"{type(e).__name__}: {e}".splitlines()[0]
    t1 = time.perf_counter()
    cell = Image.new("RGB", (2 * cell_px, cell_px), (255, 255, 255))
    if error is None:
        fallback = asset.is_fallback
        color = (
            FALLBACK_COLOR
            if fallback
            else SUPER_COLORS.get(super_category(category).value, FALLBACK_COLOR)
        )
        meshes = [p.mesh for p in asset.parts]
        for k, view in enumerate(("top", "three_quarter")):
            img = render_meshes(meshes, [color] * len(meshes), view, size=cell_px)
            cell.paste(img, (k * cell_px, 0))
        if fallback:
            status = Caption("(box fallback)", ERROR_RED)
        else:
            n_var = generate_variants(category)
            status = Caption(f"style {asset.style} ({n_var} variants)", CAPTION_GREY)
    else:
        fallback = False
        status = Caption(f"(error) {error}", ERROR_RED)
    t2 = time.perf_counter()
    if timings is not None:
        timings["generate"] = timings.get("generate", 0.0) + (t1 - t0)
        timings["render"] = timings.get("render", 0.0) + (t2 - t1)
    captions = (Caption(category), Caption(dims, CAPTION_GREY), status)
    return GridCell(cell, captions), fallback, error


def generate_variants(category: str) -> int:
    """Number of style variants of ``category``'s generator (1 for a box fallback)."""
    from pair2scene.assets.registry import generators

    gen = generators().get(category)
    return gen.variants if gen else 1


def asset_sheet(
    out_path: str | Path,
    categories: str | Sequence[str] | None = None,
    seed: int = 0,
    cell_px: int = SHEET_CELL_PX,
    columns: int | None = None,
    progress: bool = False,
) -> SheetResult:
    """Write a PNG contact sheet of every asset category (or ``categories``): per category
    its top and 3/4 views at its typical size, its name, size and style below; box
    fallbacks and generator errors captioned in red. Same seed, same sheet."""
    from pair2scene.io.atomic import atomic_write_bytes
    from pair2scene.progress import track

    names = parse_categories(categories)
    t0 = time.perf_counter()
    cells, fallbacks, errors = [], [], {}
    timings: dict[str, float] = {}
    for name in track(names, "Rendering assets", enabled=progress):
        cell, fallback, error = asset_cell(name, seed, cell_px, timings)
        cells.append(cell)
        if fallback:
            fallbacks.append(name)
        if error is not None:
            errors[name] = error
    n_proc = len(names) - len(fallbacks) - len(errors)
    title = (
        f"pair2scene assets, seed {seed}: {len(names)} categories, {n_proc} procedural, "
        f"{len(fallbacks)} box fallback"
        + (f", {len(errors)} errors" if errors else "")
        + ". Each cell: top view (+y up), 3/4 view from the front-right; own scale per view."
    )
    sheet = compose_grid(cells, columns=columns, title=title)
    buf = io.BytesIO()
    sheet.save(buf, format="PNG", optimize=False)
    atomic_write_bytes(out_path, buf.getvalue())
    return SheetResult(
        Path(out_path), names, fallbacks, errors, time.perf_counter() - t0, sheet.size, timings
    )

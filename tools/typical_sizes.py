"""Rewrite the bundled typical-size table (src/pair2scene/resources/typical_sizes.json).

Per asset category the per-axis median box size in the AI2-THOR designed rooms, else in
the ProcTHOR train houses, else a hand value (HAND_SIZES). Run from the repository root:

    python tools/typical_sizes.py [--procthor PATH/train.jsonl.gz] [--out FILE]
"""

from __future__ import annotations

import argparse
import json
import sys
from collections.abc import Sequence
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from pair2scene.assets.typical_sizes import TypicalSize, asset_categories, typical_sizes
from pair2scene.errors import UserError
from pair2scene.resources import TABLES, table_path

if TYPE_CHECKING:
    from pair2scene.data.base import Corpus

DEFAULT_PROCTHOR = Path("/work/shared/data/procthor-1k/train.jsonl.gz")
"""Where the project's ProcTHOR sample lives."""

HAND_SIZES: dict[str, tuple[float, float, float]] = {
    # Categories neither AI2-THOR nor ProcTHOR has (x width, y depth, z height; metres).
    "cabinet": (1.2, 0.45, 0.85),  # a sideboard: counter height, shallow
    "ceiling_lamp": (0.45, 0.45, 0.5),  # a pendant shade with its drop
    "dressing_table": (1.0, 0.45, 0.76),  # desk height, shallower than a desk
    "keyboard": (0.44, 0.14, 0.03),  # full-size keyboard
    "monitor": (0.55, 0.2, 0.45),  # 24-inch screen on its stand foot
    "wall_lamp": (0.15, 0.2, 0.3),  # a sconce: 20 cm off the wall
    "wardrobe": (1.0, 0.6, 2.0),  # 60 cm deep to hang clothes across
}


def _median_sizes(corpus: Corpus) -> dict[str, tuple[np.ndarray, int]]:
    sizes: dict[str, list[np.ndarray]] = {}
    for scene in corpus.scenes:
        for obj in scene.objects:
            sizes.setdefault(obj.category, []).append(np.asarray(obj.box.size, dtype=float))
    return {k: (np.median(np.stack(v), axis=0), len(v)) for k, v in sizes.items()}


def compute_typical_sizes(
    ai2thor: Corpus, procthor: Corpus | None = None
) -> dict[str, TypicalSize]:
    """Per asset category the per-axis median box size in AI2-THOR, else in ProcTHOR,
    else :data:`HAND_SIZES`, rounded to millimetres."""
    first = _median_sizes(ai2thor)
    second = _median_sizes(procthor) if procthor is not None else {}
    table = {}
    for name in asset_categories():
        for source, medians in (("ai2thor", first), ("procthor", second)):
            if name in medians:
                med, n = medians[name]
                table[name] = TypicalSize(tuple(round(float(x), 3) for x in med), source, n)
                break
        else:
            if name in HAND_SIZES:
                table[name] = TypicalSize(HAND_SIZES[name], "hand", 0)
    return table


def write_typical_sizes(
    path: str | Path | None = None, procthor_path: str | Path = DEFAULT_PROCTHOR
) -> Path:
    """Measure the corpora and write the typical-size table (default: the bundled one);
    returns the path written."""
    from pair2scene.data.ai2thor import load_ai2thor
    from pair2scene.data.procthor import load_procthor
    from pair2scene.io.atomic import atomic_write_text

    table = compute_typical_sizes(load_ai2thor(), load_procthor(procthor_path))
    missing = sorted(set(asset_categories()) - set(table))
    if missing:
        raise UserError(f"no typical size for {missing}: add them to HAND_SIZES")
    header = {
        "format": TABLES["typical_sizes"].format,
        "version": TABLES["typical_sizes"].version,
        "note": "Per-axis median box size (x width, y depth, z height; metres) per asset "
        "category: AI2-THOR designed rooms, else ProcTHOR train houses, else a hand value. "
        "Written by `python tools/typical_sizes.py`.",
    }
    # one category per line: the table reads (and diffs) as a table
    rows = [
        f"  {json.dumps(k)}: "
        + json.dumps({"count": v.count, "size": list(v.size), "source": v.source})
        for k, v in sorted(table.items())
    ]
    head = json.dumps(header, indent=1, sort_keys=True)[:-2]
    text = head + ',\n "sizes": {\n' + ",\n".join(rows) + "\n }\n}\n"
    json.loads(text)  # the hand-made layout must stay valid JSON
    out = Path(path) if path is not None else table_path("typical_sizes")
    atomic_write_text(out, text)
    typical_sizes.cache_clear()
    return out


def main(argv: Sequence[str] | None = None) -> int:
    parser = argparse.ArgumentParser(prog="python tools/typical_sizes.py", description=__doc__)
    parser.add_argument("--procthor", default=str(DEFAULT_PROCTHOR), help="ProcTHOR .jsonl.gz")
    parser.add_argument("--out", default=None, help="Write the table here instead.")
    args = parser.parse_args(argv)
    try:
        path = write_typical_sizes(args.out, args.procthor)
    except UserError as e:
        print(f"error: {e}", file=sys.stderr)
        return 1
    print(f"typical sizes: {path}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())

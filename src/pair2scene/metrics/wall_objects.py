"""What hangs on a room's walls, measured alike in generated and real rooms (issue 19).

Real rooms of the training data hold 2.4-4.4 wall objects each (paintings, mirrors,
curtains, blinds, wall lamps); a generated room without them is the first thing a person
notices. Per set of rooms:

- ``wall_objects_per_room``: objects of a wall-object category
  (:attr:`~pair2scene.categories.SuperCategory.WALL_OBJECT`, parts left out) per room;
- ``windows_per_room``: the room's windows per room;
- ``wall_share/<category>``: that category's share of all the rooms' objects (the share
  a category KL sees; structure and parts left out of both counts).

Each row is a stat as in :func:`pair2scene.metrics.layout.pool`: ``rate`` (a mean per
room, or a share), ``count`` [numerator, denominator] and ``rooms``.
"""

from __future__ import annotations

from collections.abc import Sequence

from pair2scene.categories import BY_NAME, SuperCategory
from pair2scene.metrics.layout import counted, stat
from pair2scene.scene.model import Scene

WALL_CATEGORIES = tuple(
    sorted(c for c, v in BY_NAME.items() if v.super is SuperCategory.WALL_OBJECT)
)
"""The wall-object categories of the canonical vocabulary."""


def wall_report(scenes: Sequence[Scene]) -> dict[str, dict]:
    """Every row of the module docstring over ``scenes``."""
    rooms = len(scenes)
    cats = [[o.category for o in s.objects if counted(o)] for s in scenes]
    total = sum(len(c) for c in cats)
    on_walls = sum(c in WALL_CATEGORIES for row in cats for c in row)
    out = {
        "wall_objects_per_room": stat(on_walls, rooms, rooms),
        "windows_per_room": stat(sum(len(s.room.windows) for s in scenes), rooms, rooms),
    }
    for category in WALL_CATEGORIES:
        n = sum(c == category for row in cats for c in row)
        out[f"wall_share/{category}"] = stat(n, total, rooms)
    return out


def wall_section(reference: Sequence[Scene], generated: Sequence[Scene]) -> dict:
    """The evaluation report's ``walls`` section: ``{row: {"generated": stat,
    "reference": stat}}`` for every row of :func:`wall_report`."""
    gen, ref = wall_report(generated), wall_report(reference)
    return {k: {"generated": gen[k], "reference": ref[k]} for k in gen}

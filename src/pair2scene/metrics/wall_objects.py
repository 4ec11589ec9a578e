"""What hangs on a room's walls, measured alike in generated and real rooms (issue 19).

Real rooms of the training data hold 2.4-4.4 wall objects each (paintings, mirrors,
curtains, blinds, wall lamps); a generated room without them is the first thing a person
notices. Per set of rooms:

- ``wall_objects_per_room``: objects hung on a wall per room (parts left out): with a
  ``wall:<i>`` support (generated rooms, curated ones), or, in a room as its source gives
  it (nothing known to carry the object), of a category that hangs and touching a wall
  (:func:`~pair2scene.curation.wall_objects.hung_on`, the rule curation mounts them by): a
  painting, a mirror, a television or a towel rail on a wall; :func:`is_wall_object`;
- ``over_openings``: the share of those that cover a door or a window on their wall
  (their extent along the wall and in height overlapping the opening's; curtains and
  blinds at a window are not counted: that is where they hang);
- ``covered``: the share of those (curtains and blinds left out) more than
  :data:`~pair2scene.assembly.mounting.MAX_COVER` of whose face something standing within
  :data:`~pair2scene.assembly.mounting.COVER_DEPTH_M` in front of it covers (a vase on
  the sideboard in front of a television; :func:`~pair2scene.assembly.mounting.covered_share`;
  what rests on it, a towel on its rail, does not count);
- ``windows_per_room``: the room's windows per room;
- ``wall_share/<category>``: that category's share of all the rooms' objects (the share
  a category KL sees; structure and parts left out of both counts).

Each row is a stat as in :func:`pair2scene.metrics.layout.pool`: ``rate`` (a mean per
room, or a share), ``count`` [numerator, denominator] and ``rooms``.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from pair2scene.assembly.mounting import MAX_COVER, covered_shares, outlines, wall_openings
from pair2scene.categories import BY_NAME, WINDOW_DRESSINGS, SuperCategory
from pair2scene.curation.wall_objects import hung_on
from pair2scene.metrics.layout import counted, stat
from pair2scene.scene.model import Room, Scene, SceneObject, on_wall
from pair2scene.scene.walls import Wall, walls_of

WALL_CATEGORIES = tuple(
    sorted(c for c, v in BY_NAME.items() if v.super is SuperCategory.WALL_OBJECT)
)
"""The wall-object categories of the canonical vocabulary."""


def is_wall_object(o: SceneObject, walls: list[Wall]) -> bool:
    """Whether ``o`` hangs on one of the room's ``walls`` (see the module docstring)."""
    return on_wall(o.support) or hung_on(o, walls) is not None


def covers_opening(o: SceneObject, wall: Wall, room: Room) -> bool:
    """Whether ``o``, hung on ``wall``, covers a door or (unless it is curtains or
    blinds) a window of it: overlapping it along the wall and in height."""
    lo, hi = wall.extent(o.box)
    openings = [*room.doors, *(() if o.category in WINDOW_DRESSINGS else room.windows)]
    return any(
        hi > a and lo < b and o.box.bottom < z_max and o.box.top > z_min
        for a, b, z_min, z_max, _ in wall_openings(wall, openings)
    )


def wall_report(scenes: Sequence[Scene]) -> dict[str, dict]:
    """Every row of the module docstring over ``scenes``."""
    rooms = len(scenes)
    kept = [[o for o in s.objects if counted(o)] for s in scenes]
    cats = [[o.category for o in row] for row in kept]
    total = sum(len(c) for c in cats)
    on_walls = over = faces = covered = 0
    for scene, row in zip(scenes, kept, strict=True):
        walls = walls_of(scene.room.floor_polygon)
        hung = [(o, hung_on(o, walls)) for o in row]
        standing = [o for o, wall in hung if wall is None]
        seen = outlines([o.box for o in standing])
        for o, wall in hung:
            if wall is None:
                continue
            on_walls += 1
            over += covers_opening(o, wall, scene.room)
            if o.category not in WINDOW_DRESSINGS:
                faces += 1
                shares = covered_shares(o.box, wall, *seen)
                on_it = np.array([s.support == o.id for s in standing], bool)
                covered += bool((shares[~on_it] > MAX_COVER).any())
    out = {
        "wall_objects_per_room": stat(on_walls, rooms, rooms),
        "over_openings": stat(over, on_walls, rooms),
        "covered": stat(covered, faces, rooms),
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

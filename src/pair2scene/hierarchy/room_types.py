"""Room types the training data lacks (an office, a study, a dining room, a kids' room),
composed from the learned local rules and the room types the statistics have, as the
Pair2Scene paper composes new scene types.

What rests on what and what stands at what (``sup_dep``, ``func_dep``: a laptop on a
desk, a chair at its desk) is local and shared by every room; only the room-level part of
a room type (which furniture it holds, how many objects, its size, windows and wall
objects) needs a recipe. The recipes are the bundled table ``resources/room_types.json``
(:data:`TABLE`): per composed type its base types with weights, the furniture it must hold
(category -> count range, optionally per piece of another category and anchored at one),
the categories it never takes from its bases, aliases and a note of why.

:func:`compose` turns a recipe into a :class:`~pair2scene.curation.stats.RoomTypeStats`
that synthesis draws from as from a trained type's (:meth:`Statistics.room
<pair2scene.hierarchy.synthesis.Statistics.room>`):

- **Templates and object counts**: :data:`COMPOSED_ROOMS` composed rooms, drawn with a
  seeded generator. Each is a training room of a base type (the type drawn by its weight,
  the room by how many training rooms had its furniture and object count): its pieces of
  excluded categories go (floor furniture and wall objects alike), its floor pieces of
  required categories are replaced by a drawn number of them (uniform in the range; with
  ``per``, that many per piece of the named category), and its object count becomes the
  room's count less what the removed pieces carried and plus what the added ones carry,
  each piece counted as itself and the mean number of objects a piece of its category
  carried in training (:func:`carried`). Wall objects of the templates (paintings,
  curtains) are thus the base rooms'.
- **Windows** (count and shapes) and the wall rates of floor categories: the base types'
  pooled, each weighted by its share (:meth:`HierarchyStats.room_type
  <pair2scene.curation.stats.HierarchyStats.room_type>`).
- **Room sizes**: the base types' training rooms, each type weighted by its share
  (:meth:`RoomTable.draw <pair2scene.assembly.rooms.RoomTable.draw>`).
- **Anchors and exclusions in expansion** (:func:`room_view`): a required piece with an
  ``anchor`` (a chair at the desk) takes a piece of that category as its functional
  anchor whenever the room has one (the training rooms alone give 0.27 for a chair
  beside a desk, because most of those stood at a dining table in the same room), and
  an excluded category is not added on furniture either (no television on a kids' room's
  dresser).

A statistics file that has rooms of a type uses them, not the recipe.
"""

from __future__ import annotations

import math
from collections import Counter
from dataclasses import dataclass, replace
from functools import lru_cache

import numpy as np

from pair2scene.categories import BY_NAME
from pair2scene.curation.stats import (
    TEMPLATE_SUPER_CATEGORIES,
    HierarchyStats,
    RoomTypeStats,
    instances,
    split_member,
)
from pair2scene.errors import UserError
from pair2scene.resources import load_table, table_path
from pair2scene.scene.model import FLOOR

TABLE = "room_types"
"""The bundled table of recipes (:data:`pair2scene.resources.TABLES`)."""
COMPOSED_ROOMS = 1000
"""Composed rooms drawn per type: the composed statistics' "training rooms" (several
thousand distinct combinations of base room and required furniture exist; 1000 draws keep
the common ones in their proportions and take about 10 ms)."""
COMPOSE_SEED = 0
"""The generator seed :meth:`Statistics.room <pair2scene.hierarchy.synthesis.Statistics.room>`
composes with: the composed statistics are fixed, each scene's seed draws from them."""


@dataclass(frozen=True)
class Requirement:
    """Furniture a composed type must hold."""

    category: str
    count: tuple[int, int]
    """[min, max] pieces (uniform), per piece of :attr:`per` when given."""
    per: str | None = None
    """Count per piece of this category (chairs per desk); None: per room."""
    anchor: str | None = None
    """Each piece takes a piece of this category as its functional anchor (on the floor)
    when the room has one; None: the shared functional statistics decide."""


@dataclass(frozen=True)
class ComposedType:
    """One recipe of ``resources/room_types.json``."""

    name: str
    bases: tuple[tuple[str, float], ...]
    """(trained room type, weight > 0), in the table's order."""
    require: tuple[Requirement, ...]
    """Drawn in this order: counts per room first, then those ``per`` another category."""
    exclude: frozenset[str]
    """Categories never taken from a base room (on the floor or on a wall)."""
    aliases: tuple[str, ...]
    """Other names (normalised with :func:`normalise`)."""
    note: str


def normalise(room: str) -> str:
    """'Kids' room' / 'living-room' / 'Living room' -> 'kids_room' / 'living_room':
    lower case, apostrophes dropped, spaces and hyphens as single underscores."""
    text = room.strip().lower().replace("'", "").replace("\u2019", "")
    return "_".join(text.replace("-", " ").replace("_", " ").split())


def is_furniture(category: str) -> bool:
    """Whether ``category`` can be a floor piece of a template."""
    info = BY_NAME.get(category)
    return info is not None and info.super in TEMPLATE_SUPER_CATEGORIES


def _category(name: object, where: str) -> str:
    if not isinstance(name, str) or name not in BY_NAME:
        raise UserError(f"{where}: unknown category {name!r}")
    return name


def _requirement(category: str, doc: object, where: str) -> Requirement:
    if not isinstance(doc, dict) or set(doc) - {"count", "per", "anchor"}:
        raise UserError(f"{where}: a requirement is {{'count': [min, max], 'per'?, 'anchor'?}}")
    count = doc.get("count")
    if (
        not isinstance(count, list)
        or len(count) != 2
        or not all(isinstance(v, int) and not isinstance(v, bool) for v in count)
        or not 0 <= count[0] <= count[1]
    ):
        raise UserError(f"{where}: count must be [min, max] with 0 <= min <= max")
    per, anchor = doc.get("per"), doc.get("anchor")
    return Requirement(
        category,
        (count[0], count[1]),
        None if per is None else _category(per, where),
        None if anchor is None else _category(anchor, where),
    )


def _parse(name: str, doc: object, where: str) -> ComposedType:
    where = f"{where}: {name}"
    if not isinstance(doc, dict):
        raise UserError(f"{where}: not an object")
    bases = doc.get("bases")
    if (
        not isinstance(bases, dict)
        or not bases
        or not all(isinstance(w, (int, float)) and w > 0 for w in bases.values())
    ):
        raise UserError(f"{where}: bases must be {{room type: weight > 0}}, at least one")
    require = []
    for cat, r in doc.get("require", {}).items():
        if not is_furniture(_category(cat, where)):
            raise UserError(f"{where}: {cat} is not floor furniture")
        require.append(_requirement(cat, r, f"{where}: {cat}"))
    required = {r.category for r in require}
    for r in require:
        if r.per is not None and (r.per == r.category or any(
            q.category == r.per and q.per is not None for q in require
        )):  # fmt: skip
            raise UserError(f"{where}: {r.category}: 'per' names a category counted per room")
    exclude = frozenset(_category(c, where) for c in doc.get("exclude", []))
    if required & exclude:
        raise UserError(f"{where}: required and excluded: {', '.join(sorted(required & exclude))}")
    for r in require:
        if r.anchor in exclude or r.per in exclude:
            raise UserError(f"{where}: {r.category}: its anchor or 'per' category is excluded")
    aliases = tuple(normalise(a) for a in doc.get("aliases", []))
    return ComposedType(
        name=name,
        bases=tuple((str(b), float(w)) for b, w in bases.items()),
        require=tuple(sorted(require, key=lambda r: r.per is not None)),  # stable
        exclude=exclude,
        aliases=aliases,
        note=str(doc.get("note", "")),
    )


@lru_cache(maxsize=1)
def composed_types() -> dict[str, ComposedType]:
    """The recipes of the bundled table, by type name (a malformed table is a UserError
    naming the file)."""
    doc = load_table(TABLE)
    where = str(table_path(TABLE))
    types = doc.get("types")
    if not isinstance(types, dict):
        raise UserError(f"{where}: 'types' must be an object")
    out = {normalise(name): _parse(normalise(name), d, where) for name, d in types.items()}
    aliases()  # an alias naming two types is an error too
    return out


@lru_cache(maxsize=1)
def aliases() -> dict[str, str]:
    """Normalised alias -> composed type name."""
    doc = load_table(TABLE)
    out: dict[str, str] = {}
    for name, d in doc.get("types", {}).items():
        for alias in d.get("aliases", []) if isinstance(d, dict) else []:
            key = normalise(alias)
            if out.get(key, normalise(name)) != normalise(name):
                raise UserError(f"{table_path(TABLE)}: alias {alias!r} names two room types")
            out[key] = normalise(name)
    return out


def resolve(room: str) -> str:
    """A user's room name -> the room type: normalised (:func:`normalise`), an alias
    replaced by its type ('home office' -> 'office', "children's room" -> 'kids_room')."""
    key = normalise(room)
    return aliases().get(key, key)


def _bases(stats: HierarchyStats, spec: ComposedType) -> list[tuple[str, float]]:
    """The recipe's base types the statistics have rooms with furniture of."""
    return [(b, w) for b, w in spec.bases if b in stats.room_types and stats.room_types[b].layouts]


def composable(stats: HierarchyStats) -> list[str]:
    """Composed types these statistics can give: not trained (a type the statistics have
    rooms of uses them), with at least one base type the statistics have; sorted."""
    trained = {t for t, rs in stats.room_types.items() if rs.layouts}
    return sorted(
        name for name, spec in composed_types().items()
        if name not in trained and _bases(stats, spec)
    )  # fmt: skip


def unknown_message(stats: HierarchyStats, room_type: str) -> str:
    """The one-line error for a room type neither trained nor composable."""
    known = ", ".join(sorted(stats.room_types)) or "nothing"
    composed = ", ".join(composable(stats)) or "none"
    return (
        f"unknown room type {room_type!r}; the statistics know: {known}; "
        f"composed from them: {composed}"
    )


def carried(stats: HierarchyStats) -> dict[str, float]:
    """Category -> mean number of objects a piece of it carried in the training rooms
    (objects resting on it, over its instances on any support)."""
    count = instances(stats.sup_dep)
    return {
        cat: sum(deps.values()) / count[cat]
        for cat, deps in stats.sup_dep.items()
        if count.get(cat)
    }


def _entries(rs: RoomTypeStats) -> tuple[list[tuple[tuple[str, ...], int | None]], np.ndarray]:
    """A base type's rooms as ((layout, object count), weights); statistics without the
    joint counts give (layout, None) and the count is drawn later."""
    if rs.layout_counts:
        keys = sorted(rs.layout_counts)
        return [(k[0], int(k[1])) for k in keys], np.array(
            [rs.layout_counts[k] for k in keys], float
        )
    keys = sorted(rs.layouts)
    return [(k, None) for k in keys], np.array([rs.layouts[k] for k in keys], float)


def compose(
    stats: HierarchyStats, name: str, seed: int = COMPOSE_SEED, rooms: int = COMPOSED_ROOMS
) -> RoomTypeStats:
    """The statistics of composed type ``name`` (see the module docstring): ``rooms``
    composed rooms drawn with ``numpy.random.default_rng(seed)``; same statistics and
    seed, same result. A UserError when ``name`` is not composable from ``stats``."""
    spec = composed_types().get(name)
    bases = [] if spec is None else _bases(stats, spec)
    if spec is None or not bases:
        raise UserError(unknown_message(stats, name))
    rng = np.random.default_rng(seed)
    weights = np.array([w for _, w in bases], float)
    which = rng.choice(len(bases), size=rooms, p=weights / weights.sum())
    drawn: list[tuple[tuple[str, ...], int | None, str]] = [((), None, "")] * rooms
    for i, (base, _) in enumerate(bases):
        rows = np.flatnonzero(which == i)
        entries, w = _entries(stats.room_types[base])
        for row, e in zip(rows, rng.choice(len(entries), size=len(rows), p=w / w.sum())):
            drawn[row] = (*entries[e], base)
    carry = carried(stats)

    def load(members: list[str]) -> float:  # pieces and what they carry on average
        return sum(1.0 + carry.get(split_member(m)[0], 0.0) for m in members)

    required = {r.category for r in spec.require}
    out = RoomTypeStats(rooms=rooms)
    for layout, count, base in drawn:
        if count is None:  # old statistics: a count of a room with at least this furniture
            counts = stats.room_types[base].object_counts
            fit = sorted(k for k in counts if k >= len(layout)) or sorted(counts)
            p = np.array([counts[k] for k in fit], float)
            count = int(fit[int(rng.choice(len(fit), p=p / p.sum()))])
        new = []
        for member in layout:  # excluded pieces go, required ones are drawn anew
            cat, mounted = split_member(member)
            if cat not in spec.exclude and (cat not in required or mounted):
                new.append(member)
        for r in spec.require:
            times = 1 if r.per is None else new.count(r.per)
            n = sum(int(rng.integers(r.count[0], r.count[1] + 1)) for _ in range(times))
            new += [r.category] * n
        target = count - load(list(layout)) + load(new)
        objects = max(len(new), math.floor(target + 0.5))
        key = tuple(sorted(new))
        out.layouts[key] += 1
        out.object_counts[objects] += 1
        out.layout_counts[key, objects] += 1
    pooled = stats.room_type(name)  # the base types' room-level statistics, weighted
    out.window_counts = Counter(pooled.window_counts)
    out.window_shapes = Counter(pooled.window_shapes)
    out.floor_shapes = Counter(pooled.floor_shapes)
    out.on_floor = Counter(pooled.on_floor)
    out.against_wall = Counter(pooled.against_wall)
    out.sup_dep = {a: Counter(d) for a, d in pooled.sup_dep.items()}
    return out


def room_view(stats: HierarchyStats, name: str) -> HierarchyStats:
    """``stats`` as composed type ``name`` uses them: a required piece with an ``anchor``
    takes a piece of that category, and only that category, whenever the room has one
    (the floor's ``func_dep`` and ``func_present`` changed for those pairs), and an
    excluded category is never added as a dependent either (no television on a kids'
    room's dresser: it leaves ``sup_dep``). Everything else is ``stats``' own, shared,
    not copied; ``stats`` itself is not changed."""
    spec = composed_types().get(name)
    if spec is None:
        return stats
    pairs = [(r.category, r.anchor) for r in spec.require if r.anchor]
    floor = {a: Counter(d) for a, d in stats.func_dep.get(FLOOR, {}).items()}
    present = {a: Counter(d) for a, d in stats.func_present.get(FLOOR, {}).items()}
    for dep, anchor in pairs:
        took = max(floor.get(anchor, Counter()).get(dep, 0), 1)
        for deps in floor.values():
            deps.pop(dep, None)
        floor.setdefault(anchor, Counter())[dep] = took
        present.setdefault(anchor, Counter())[dep] = took  # took / beside = 1
    sup_dep = {
        a: Counter({d: n for d, n in deps.items() if d not in spec.exclude})
        for a, deps in stats.sup_dep.items()
    }
    return replace(
        stats,
        sup_dep=sup_dep,
        func_dep={**stats.func_dep, FLOOR: floor},
        func_present={**stats.func_present, FLOOR: present},
    )


def describe(name: str) -> str:
    """One line: a composed type's bases, required and excluded furniture."""
    spec = composed_types()[name]
    bases = ", ".join(f"{b} {w:g}" for b, w in spec.bases)
    req = ", ".join(
        f"{r.category} {r.count[0]}-{r.count[1]}"
        + (f" per {r.per}" if r.per else "")
        + (f" (at a {r.anchor})" if r.anchor else "")
        for r in spec.require
    )
    return f"{name}: from {bases}; holds {req}; never {', '.join(sorted(spec.exclude))}"

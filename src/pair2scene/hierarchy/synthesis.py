"""Statistical hierarchy synthesis: the method's Algorithm 1 over the curated statistics.

``synthesize(stats, "bedroom", SynthesisConfig(mode="fit", seed=0))``:

1. **Base template**: a multiset of floor furniture, small objects standing on the floor
   (a basketball, a box) and wall objects (``painting@wall``) drawn from the room type's
   curated templates, weighted by how many training rooms had
   it. Functional anchors among the floor furniture (chairs at the desk) are drawn from
   the floor's functional statistics; wall objects rest on ``wall`` (placement picks
   which) and take a floor object as their anchor with the walls' statistics (a painting
   above the bed).
2. **Expansion queue**: breadth-first over the nodes. For a popped leaf ``a`` every
   dependent category ``d`` the statistics have seen resting on ``a``'s category is a
   candidate, added with probability ``k * freq / total`` where ``freq`` is how often
   ``d`` rested on an ``a`` and ``total`` how many ``a`` there were (rates above 1 add
   ``floor(rate)`` copies and one more with the remainder's probability: four books per
   shelf stay four). Both counts are the room type's, shrunk towards those of every
   room type (:data:`ROOM_PRIOR`), and only categories the room type's training rooms
   held are candidates: a bathroom's counter takes soap, not a kitchen's bread
   (:class:`Statistics`). Each added node gets a functional anchor among the objects
   already on the same support with the functional statistics' frequencies, and joins
   the queue.
3. **Cap**: at most ``N_max`` objects (when a generation of the queue draws more than
   that leaves room for, a random share of its draws is kept, not the first ones in the
   queue: :func:`_keep_some`), and never more than :data:`MAX_OBJECTS_LIMIT`
   (``max_objects`` above it is a UserError; a count drawn from statistics of your own
   above it is cut, with a note).

Modes:

- ``fit``: ``N_max`` is drawn from the room type's distribution of objects per training
  room, and expansion passes repeat (each pass offers every node's candidates again) until
  the scene has ``N_max`` objects or a pass adds nothing: object counts follow the
  training distribution.
- ``beyond``: ``N_max`` is ``max_objects`` (default 80); extra floor furniture that holds
  objects (shelves, tables, dressers seen in that room type) is added to the template
  until its pieces can carry ``N_max`` objects (:func:`capacity`) or would cover more
  floor than the type's largest training room is drawn for (:func:`floor_budget`), and
  passes repeat until ``N_max``: scenes denser than any training room.

Everything draws from one ``numpy.random.Generator`` seeded by ``seed``: same seed, same
statistics, same hierarchy.
"""

from __future__ import annotations

from collections import Counter
from collections.abc import Callable, Iterable, Mapping
from dataclasses import dataclass
from functools import lru_cache
from pathlib import Path

import numpy as np

from pair2scene.categories import BY_NAME, WINDOW_DRESSINGS, SuperCategory
from pair2scene.curation.stats import (
    TEMPLATE_SUPER_CATEGORIES,
    HierarchyStats,
    RoomTypeStats,
    draw_counted,
    instances,
    split_member,
)
from pair2scene.errors import UserError
from pair2scene.hierarchy.tree import NOT_OBJECTS, Hierarchy, Node
from pair2scene.resources import load_table, table_path
from pair2scene.scene.model import FLOOR, WALL

MODES = ("fit", "beyond")
DEFAULT_BEYOND_OBJECTS = 80
MAX_OBJECTS_LIMIT = 500
"""The most objects a scene may be asked for (``max_objects``): dense ProcTHOR rooms hold
about 150 and a 320-object bedroom takes ~5 s to place (docs/benchmarks.md); beyond this a
request is refused rather than left to run for hours."""
MAX_PASSES = 50
"""Expansion passes before giving up on reaching the target count."""
MAX_K_BOOST = 64.0
"""A pass that adds nothing doubles k for the next one (rare dependents of few anchors,
as in bathrooms), up to this factor: the proportions between candidates stay the
statistics', only the pace changes."""
BEYOND_LOAD = 1.5
"""``beyond``: a piece of furniture is counted on to carry this many times the objects a
piece of its category carried in the training rooms (a dresser 3.7 x 1.5 = 5.5, a side
table 3.1, a bed 0.7). Placement finds full surfaces at about that load: in 40 beyond
bedrooms, dressers its balance step found full carried 3-10 objects, side tables 3-7.
Counting each template piece as carrying 10 left bedrooms of eight pieces (beds, chairs,
one dresser) without extra furniture, and up to half of their 80 objects without a
surface."""


@dataclass(frozen=True)
class HierarchyConfig:
    """How hierarchies are drawn from the statistics (the settings a user may tune; the
    request itself, room type, mode, object cap and seed, is given per call)."""

    k: float = 1.0
    """Scales every candidate dependent's probability in the expansion (the method's k):
    above 1 a scene reaches its object count with fewer passes, below 1 with more."""
    beyond_load: float = BEYOND_LOAD
    """``beyond``: a piece of furniture is counted on to carry this many times the objects
    its category carried in the training rooms; extra furniture is added until the pieces
    can carry ``--max-objects`` (see :data:`BEYOND_LOAD` for the measurements)."""
    template_anchors: bool = True
    """A drawn template's floor members take functional anchors as in its training rooms
    (all four chairs at the table, or none, as the room had them); off: each member
    draws one on its own from the pooled shares (0.935 for a chair beside a dining
    table), and a four-chair table kept all four 0.76 of the time."""

    def __post_init__(self) -> None:
        if not self.k > 0 or not np.isfinite(self.k):
            raise UserError(f"--hierarchy.k must be a finite number > 0, got {self.k}")
        if not self.beyond_load > 0 or not np.isfinite(self.beyond_load):
            raise UserError(
                f"--hierarchy.beyond-load must be a finite number > 0, got {self.beyond_load}"
            )


@dataclass(frozen=True)
class SynthesisConfig:
    """How :func:`synthesize` builds a hierarchy."""

    mode: str = "fit"
    """``fit`` (counts follow the training rooms) or ``beyond`` (up to ``max_objects``)."""
    max_objects: int | None = None
    """N_max. ``beyond``: the target (default 80); ``fit``: a cap on the drawn count."""
    k: float = 1.0
    """Scales every candidate's probability (the method's k)."""
    seed: int = 0
    beyond_load: float = BEYOND_LOAD
    """:attr:`HierarchyConfig.beyond_load`."""
    template_anchors: bool = True
    """:attr:`HierarchyConfig.template_anchors`."""

    def __post_init__(self) -> None:
        if self.mode not in MODES:
            raise UserError(f"unknown mode {self.mode!r}; choose one of {', '.join(MODES)}")
        check_max_objects(self.max_objects)
        if isinstance(self.seed, bool) or not isinstance(self.seed, int | np.integer):
            raise UserError(f"--seed must be a whole number, got {self.seed!r}")
        if self.seed < 0:
            raise UserError(f"--seed must be >= 0, got {self.seed}")
        if not self.k > 0:
            raise UserError("k must be > 0")


def check_max_objects(max_objects: int | None) -> None:
    """A UserError unless ``max_objects`` is None or a whole number from 1 to
    :data:`MAX_OBJECTS_LIMIT`: every way to a hierarchy (the CLI, :func:`synthesize`,
    text) is bounded by the limit, not only the command line."""
    if max_objects is None:
        return
    if isinstance(max_objects, bool) or not isinstance(max_objects, int | np.integer):
        raise UserError(f"--max-objects must be a whole number, got {max_objects!r}")
    if max_objects < 1:
        raise UserError("--max-objects must be >= 1")
    if max_objects > MAX_OBJECTS_LIMIT:
        raise UserError(
            f"--max-objects {max_objects}: a scene may have at most {MAX_OBJECTS_LIMIT} objects "
            f"(MAX_OBJECTS_LIMIT); ask for {MAX_OBJECTS_LIMIT} or fewer"
        )


@lru_cache(maxsize=4)
def _load_stats(path: str) -> HierarchyStats:
    if Path(path) == table_path("hierarchy_stats"):
        return HierarchyStats.from_dict(load_table("hierarchy_stats", path), path)
    # a user's file: the bounded reader (size, depth, UTF-8; every problem one line)
    return HierarchyStats.from_file(path)


def load_stats(path: str | Path | None = None) -> HierarchyStats:
    """Hierarchy statistics from a ``stats.json`` (None: the bundled ones, those of the
    curated AI2-THOR + ProcTHOR-1k train rooms; ``pair2scene curate ... --out DIR``
    writes the same file as ``DIR/stats.json``)."""
    return _load_stats(str(table_path("hierarchy_stats") if path is None else Path(path)))


ROOM_PRIOR = 5.0
"""Pseudo-instances of the pooled rates in a room type's dependent rates: what rests on
an ``a`` in a room of type r is drawn at (n_r(d on a) + ROOM_PRIOR * rate(d | a)) /
(n_r(a) + ROOM_PRIOR), ``rate`` over every room type. A type with many ``a`` keeps its
own rates (a kitchen's counters); one with few leans on the pooled ones (the 25 training
bathrooms' 3 side tables)."""


class Statistics:
    """Rates and choices derived from :class:`HierarchyStats` (all plain lookups).

    room : the room type's statistics (``RoomTypeStats``, a composed type's included), or
        None. With them, what rests on what is drawn the room type's way: only categories
        its training rooms held, at its own rates shrunk towards the pooled ones
        (:data:`ROOM_PRIOR`): soap on a bathroom's counter, bread on a kitchen's. Without
        them (or with statistics written before rooms kept their own ``sup_dep``) every
        room type draws from the pooled rates."""

    def __init__(self, stats: HierarchyStats, room: RoomTypeStats | None = None) -> None:
        self.stats = stats
        own = {} if room is None else room.sup_dep
        self._own: dict[str, Counter[str]] = own
        self._own_rooms = 0 if room is None else room.rooms
        self._own_instances = instances(own)
        """category -> objects of it (on any support) in the room type's training rooms."""
        self.instances = instances(stats.sup_dep)
        """category -> how many objects of it the training rooms held (on any support)."""
        on_floor = stats.sup_dep.get(FLOOR, {})
        self.floor_standing = frozenset(
            c for c, n in self.instances.items() if 2 * on_floor.get(c, 0) > n
        )
        """Categories that rest on the floor in most of their training instances (furniture,
        counters): never expanded onto another object."""

    @classmethod
    def for_room(cls, stats: HierarchyStats, room_type: str) -> tuple[Statistics, RoomTypeStats]:
        """The statistics a ``room_type`` room is drawn with, and its room-level ones
        (templates, object counts): a trained type's own; for a composed type
        (:mod:`pair2scene.hierarchy.room_types`: an office from living rooms and bedrooms
        with desks and no bed) its view of the shared statistics (a chair takes the desk,
        no excluded category is added: :func:`~pair2scene.hierarchy.room_types.room_view`)
        and its composed rooms. A type neither trained nor composable is a UserError
        listing both."""
        from pair2scene.hierarchy import room_types as composed

        rs = stats.room_types.get(room_type)
        if rs is not None and rs.layouts:
            return cls(stats, rs), rs
        if room_type not in composed.composable(stats):
            raise UserError(composed.unknown_message(stats, room_type))
        rs = composed.compose(stats, room_type)
        return cls(composed.room_view(stats, room_type), rs), rs

    def room(self, room_type: str):
        """The room-level statistics of ``room_type`` (:meth:`for_room`)."""
        return Statistics.for_room(self.stats, room_type)[1]

    def dependents(self, anchor: str, pooled: bool = False) -> list[tuple[str, float]]:
        """(category, rate per anchor instance) of every object seen resting on ``anchor``:
        in the room type's rooms (see the class docstring), or in any room (``pooled``, or
        without the room type's statistics)."""
        deps = self.stats.sup_dep.get(anchor, {})
        total = self.instances.get(anchor, 0) if anchor != FLOOR else self.stats.rooms
        if not total:
            return []
        rates = {d: n / total for d, n in deps.items()}
        if self._own and not pooled:  # the room type's own, shrunk towards the pooled ones
            mine = self._own.get(anchor, {})
            n = self._own_instances.get(anchor, 0) if anchor != FLOOR else self._own_rooms
            rates = {d: (mine.get(d, 0) + ROOM_PRIOR * r) / (n + ROOM_PRIOR)
                     for d, r in rates.items() if self._own_instances.get(d, 0) > 0}  # fmt: skip
        return [
            (d, rate)
            for d, rate in sorted(rates.items())
            if d in BY_NAME
            and BY_NAME[d].super not in NOT_OBJECTS
            and BY_NAME[d].super is not SuperCategory.WALL_OBJECT  # they hang on walls
            and (anchor == FLOOR or d not in self.floor_standing)
        ]

    def functional_choice(
        self,
        support: str,
        category: str,
        siblings: list[Node],
        rng: np.random.Generator,
        shares: Mapping[str, float] | None = None,
    ) -> Node | None:
        """A functional anchor for a new ``category`` object among ``siblings`` on a
        ``support`` category, drawn with the statistics' frequencies (or none).

        ``shares``: anchor category -> the chance that this object takes one of it (the
        shares summing to at most 1); they replace the pooled frequencies below, and
        siblings of a category share its chance evenly. :func:`add_floor_furniture` gives
        them from a template's training room, whose chairs all sat at its table or none.

        Whether it gets one at all is conditioned on what stands there: with ``r_a`` the
        share of ``category`` objects that took an ``a`` as their anchor among those
        beside an ``a`` in the training rooms that took no other category's
        (``func_present``), the chance is ``1 - prod(1 - r_a)`` over the siblings'
        categories (a chair in a room with a dining table: 0.9 and more, where the share
        over all chairs, tables or not, was 0.75). Statistics without those counts fall
        back to the share over all ``category`` objects."""
        if shares is not None:
            present = Counter(s.category for s in siblings)
            weights = [shares.get(s.category, 0.0) / present[s.category] for s in siblings]
            return self._pick(siblings, weights, sum(weights), rng)
        per_anchor = self.stats.func_dep.get(support, {})
        weights = [per_anchor.get(s.category, {}).get(category, 0) for s in siblings]
        if not any(weights):
            return None
        present = self.stats.func_present.get(support, {})
        if present:
            miss = 1.0
            for a in {s.category for s, w in zip(siblings, weights) if w}:
                beside = present.get(a, {}).get(category, 0)
                took = per_anchor.get(a, {}).get(category, 0)
                miss *= 1.0 - min(1.0, took / beside) if beside else 1.0
            chance = 1.0 - miss
        else:
            with_anchor = sum(per_anchor.get(a, {}).get(category, 0) for a in per_anchor)
            placed = self.stats.sup_dep.get(support, {}).get(category, 0)
            chance = min(1.0, with_anchor / placed) if placed else 0.0
        return self._pick(siblings, weights, chance, rng)

    @staticmethod
    def _pick(
        siblings: list[Node], weights: list[float], chance: float, rng: np.random.Generator
    ) -> Node | None:
        """One of ``siblings`` by ``weights`` with probability ``chance``, else None."""
        if not any(weights) or rng.random() >= chance:
            return None
        w = np.asarray(weights, dtype=float)
        return siblings[int(rng.choice(len(siblings), p=w / w.sum()))]


def _stochastic_round(x: float, rng: np.random.Generator) -> int:
    x = x if x == x else 0.0  # (nan: an infinite k times a zero rate)
    whole = int(np.floor(x))
    return whole + int(rng.random() < x - whole)


def anchor_depths(categories: Iterable[str], stats: Statistics) -> dict[str, int]:
    """category -> how many floor anchors stand above it among ``categories``: 0 for one
    that takes none of them as a functional anchor on the floor, else one more than its
    deepest anchor's (a sofa 0, the coffee table in front of it 1). A cycle of categories
    anchoring each other is cut where it closes, walked in name order, so the depths do
    not depend on the order given."""
    floor_anchors = stats.stats.func_dep.get(FLOOR, {})
    present = sorted(set(categories))
    depth: dict[str, int] = {}

    def level(c: str, seen: frozenset[str]) -> int:
        if c not in depth:
            seen = seen | {c}
            above = [a for a in present if a not in seen and floor_anchors.get(a, {}).get(c)]
            depth[c] = max((level(a, seen) + 1 for a in above), default=0)
        return depth[c]

    for c in present:
        level(c, frozenset())
    return depth


def anchor_first(categories: list[str], stats: Statistics) -> list[str]:
    """Template order: each category after the categories present that it takes a
    functional anchor among (:func:`anchor_depths`: a sofa before the coffee table in
    front of it, a table before the chairs at it), anchors before the rest at the same
    depth, then by name. A category is added once its anchors stand, so it can take one
    (in name order alone a coffee table came before its sofa and never stood at it)."""
    floor_anchors = stats.stats.func_dep.get(FLOOR, {})
    depth = anchor_depths(categories, stats)
    return sorted(categories, key=lambda c: (depth[c], 0 if c in floor_anchors else 1, c))


def add_floor_furniture(
    h: Hierarchy,
    members: list[str],
    stats: Statistics,
    rng,
    anchors: Mapping[str, Mapping[str, int]] | None = None,
) -> None:
    """Add a template's members: floor furniture in anchor-first order, each with a drawn
    functional anchor, then its wall objects (``<category>@wall``) on ``wall``, each with
    a floor object as its anchor drawn from the walls' statistics (or none). ``anchors``:
    one of the template's rooms' anchor pattern (:meth:`RoomTypeStats.template_anchors
    <pair2scene.curation.stats.RoomTypeStats.template_anchors>`; category -> anchor
    category -> members that took one): the floor members take exactly those anchors
    (where the anchors are there), drawn without replacement, none of the others'."""
    split = [split_member(m) for m in members]
    floor = [c for c, mounted in split if not mounted]
    left = Counter(floor)  # members of each category not yet added
    taken = {c: Counter(a) for c, a in (anchors or {}).items()}  # anchors still to take
    for cat in anchor_first(floor, stats):
        siblings = [n for n in h.children(FLOOR) if n.id not in h.functional]
        shares = None
        if anchors is not None:
            shares = {a: n / left[cat] for a, n in taken.get(cat, {}).items()}
            left[cat] -= 1
        anchor = stats.functional_choice(FLOOR, cat, siblings, rng, shares)
        if anchor is not None and shares is not None:
            taken[cat][anchor.category] -= 1
        h.add(cat, FLOOR, None if anchor is None else anchor.id)
    for cat in sorted(c for c, mounted in split if mounted):
        anchor = None
        if cat not in WINDOW_DRESSINGS:  # those hang at a window
            anchor = stats.functional_choice(WALL, cat, h.children(FLOOR), rng)
        h.add(cat, WALL, None if anchor is None else anchor.id)


def expand(
    h: Hierarchy,
    stats: Statistics,
    target: int,
    rng: np.random.Generator,
    k: float = 1.0,
    fixed: frozenset[str] = frozenset(),
    passes: int = MAX_PASSES,
    skip: frozenset[str] = frozenset(),
    once: frozenset[str] = frozenset(),
) -> int:
    """Expansion passes (the module docstring's step 2) until ``target`` objects; returns
    how many passes ran. Nodes in ``fixed`` get no dependents, categories in ``skip`` are
    never added; the floor is never expanded here. A pass that adds nothing doubles k (up
    to :data:`MAX_K_BOOST` times). Categories in ``once`` are offered on the first pass
    only (``beyond``'s fixtures: a counter takes its sink at the training rate once, where
    later passes, boosted, had put 15 sinks on the counters of a 500-object bathroom).

    A pass draws its nodes' dependents a generation at a time (the first pass goes on to
    the dependents it added); when a generation draws more than the target leaves room
    for, it keeps a random share of them (:func:`_keep_some`), not the first in the queue."""
    boost = 1.0
    for done in range(passes):
        if len(h) >= target:
            return done
        if done == 1:
            skip = skip | once
        before = len(h)
        generation = [n for n in h.nodes if n.id not in fixed]
        while generation and len(h) < target:
            room = target - len(h)
            drawn: list[tuple[Node, str]] = []  # (anchor, category) of each copy drawn
            for anchor in generation:
                candidates = [c for c in stats.dependents(anchor.category) if c[0] not in skip]
                for i in rng.permutation(len(candidates)):
                    cat, rate = candidates[i]
                    # (never more copies than there is room for: a huge k stays a finite count)
                    copies = _stochastic_round(min(k * boost * rate, room), rng)
                    drawn += [(anchor, cat)] * copies
            added = []
            for anchor, cat in _keep_some(drawn, room, rng):
                func = stats.functional_choice(anchor.category, cat, h.children(anchor.id), rng)
                added.append(h.add(cat, anchor.id, None if func is None else func.id))
            generation = added if done == 0 else []
        if len(h) == before:
            offered = (
                c for n in h.nodes if n.id not in fixed for c in stats.dependents(n.category)
            )
            if not any(c[0] not in skip for c in offered):
                return done + 1
            boost = min(2 * boost, MAX_K_BOOST)
    return passes


def _keep_some(drawn: list, room: int, rng: np.random.Generator) -> list:
    """``drawn`` (the (anchor, category) of each dependent drawn), in its order, cut to a
    random ``room`` of them when it holds more. Cut in queue order, as Algorithm 1 is, the
    anchors met first kept all they drew and the last ones nothing: a TV stand (sorted
    after the sofa and the tables) held a television in 0.68 of 200 living-room
    hierarchies where 0.93 of the training rooms' stands do (0.89 in the training rooms
    with the fewest objects, 5-20), while beds, met first, held a book in 0.39 (train
    0.26). Cut at random, 0.83 and 0.28; over the (support, dependent) pairs held by at
    least a tenth of their supports in the training rooms, the mean gap between the share
    of supports holding one in the hierarchies and in the training rooms went 0.074 ->
    0.060 (bedrooms), 0.065 -> 0.056 (living rooms), 0.060 -> 0.051 (kitchens), 0.235 ->
    0.219 (bathrooms). Keeping the likeliest copies first (a dependent of rate r, its
    j-th copy by min(r - j, 1)) put a television on 0.99 of the stands but widened the
    gaps (0.077 / 0.071 / 0.074 / 0.231): the ones of middling rate crowded out the
    rest."""
    if len(drawn) <= room:
        return drawn
    return [drawn[i] for i in sorted(rng.permutation(len(drawn))[:room])]


def synthesize(
    stats: HierarchyStats | None, room_type: str, config: SynthesisConfig = SynthesisConfig()
) -> Hierarchy:
    """A hierarchy for ``room_type`` (see the module docstring); ``stats`` None: bundled."""
    st, rs = Statistics.for_room(load_stats() if stats is None else stats, room_type)
    rng = np.random.default_rng(config.seed)
    h = Hierarchy(room_type)
    # A training room with no furniture would give an empty scene: a room is drawn from
    # the furnished ones. In fit mode its furniture and object count are a training
    # room's, drawn together (a one-dresser template with another room's 30 objects
    # piled them on the dresser); statistics without the joint counts give the count
    # from the rooms that hold at least the drawn furniture.
    template, target = _draw_room(rs, config.mode == "fit", rng)
    anchors = rs.template_anchors(template, rng) if config.template_anchors else None
    if config.mode == "fit":
        if config.max_objects is not None:
            target = min(target, config.max_objects)
        if target > MAX_OBJECTS_LIMIT:  # (statistics of your own: a room of any count)
            h.notes.append(
                f"object count cut from {target} to {MAX_OBJECTS_LIMIT} (MAX_OBJECTS_LIMIT)"
            )
            target = MAX_OBJECTS_LIMIT
    else:
        target = config.max_objects or DEFAULT_BEYOND_OBJECTS
        template += extra_furniture(st, rs, target, template, rng, config.beyond_load)
    if len(template) > target:
        template = [template[i] for i in sorted(rng.permutation(len(template))[:target])]
        h.notes.append(f"template cut to {target} pieces by the object cap")
    add_floor_furniture(h, template, st, rng, anchors)
    expand(h, st, target, rng, config.k, once=offered_once(config.mode))
    if len(h) < target:
        h.notes.append(
            f"{len(h)} of {target} objects: the statistics offer no more dependents for this "
            "furniture"
        )
    return h.validate()


def capacity(st: Statistics, category: str, load: float = BEYOND_LOAD) -> float:
    """``beyond``: how many objects a piece of ``category`` is counted on to carry,
    ``load`` (:data:`BEYOND_LOAD`) times its training mean (0 for furniture nothing
    rests on)."""
    return load * sum(rate for _, rate in st.dependents(category))


def furnished(layout: tuple[str, ...]) -> bool:
    """Whether a template holds floor furniture (not only wall objects or small objects on
    the floor)."""
    return any(
        not mounted and cat in BY_NAME and BY_NAME[cat].super in TEMPLATE_SUPER_CATEGORIES
        for cat, mounted in map(split_member, layout)
    )


def _draw_room(rs, with_count: bool, rng) -> tuple[list[str], int]:
    """A furnished training room's template and (``with_count``) object count."""
    joint = Counter({k: v for k, v in rs.layout_counts.items() if furnished(k[0])})
    if with_count and joint:
        layout, count = draw_counted(joint, rng)
        return list(layout), int(count)
    rooms = Counter({k: v for k, v in rs.layouts.items() if furnished(k)}) or rs.layouts
    template = list(draw_counted(rooms, rng))
    if not with_count:
        return template, 0
    counts = Counter({k: v for k, v in rs.object_counts.items() if k >= len(template)})
    return template, int(draw_counted(counts or rs.object_counts, rng))


def extra_furniture(
    st: Statistics,
    rs,
    target: int,
    have: list[str],
    rng,
    load: float = BEYOND_LOAD,
    footprint: Callable[[str], float] | None = None,
) -> list[str]:
    """``beyond``: furniture of this room type that holds objects, added until the scene's
    pieces (``have``'s and the extra ones, each counting itself and its
    :func:`capacity`) can carry ``target`` objects. A category is drawn by how many
    training rooms of the type had it; furniture counted on for less than one object is
    not added (chairs), nor beds, fixtures and appliances (:func:`holder`).

    The floor bounds it too: the pieces' footprints (``footprint``, m2 by category; the
    bundled size table's medians by default) stay within :func:`floor_budget`, what the
    type's largest training room holds. A drawn category that no longer fits leaves the
    draw, smaller ones may still come; what the pieces cannot carry then goes on them as
    far as placement finds room. Without a budget a 320-object bedroom was asked for
    12-22 dressers and 5-10 dining tables, 0.65-0.71 of its 57 m2 of floor: a third of
    them failed to fit, and most of the scene's time went into trying."""
    counts = rs.furniture_counts()
    pool = Counter(
        {c: sum(n for k, n in hist.items() if k > 0)
         for c, hist in counts.items() if capacity(st, c, load) >= 1 and holder(c)}
    )  # fmt: skip
    area = footprint or _bundled_footprint
    budget = floor_budget(rs)
    used = sum(area(c) for c, mounted in map(split_member, have) if not mounted)
    carried = sum(1 + capacity(st, c, load) for c in have)
    extra: list[str] = []
    while pool and carried < target and len(have) + len(extra) < target:
        cat = draw_counted(pool, rng)
        if budget is not None and used + area(cat) > budget:
            del pool[cat]
            continue
        extra.append(cat)
        used += area(cat)
        carried += 1 + capacity(st, cat, load)
    return extra


FIXTURES = frozenset(c for c, known in BY_NAME.items() if known.super == SuperCategory.FIXTURE)
"""Categories built into the room or into their support (toilets, sinks, counters)."""
EXTRA_FIXTURES = frozenset({"counter_top"})
"""Fixtures ``beyond`` may add more of: a longer counter run. The others (a toilet, a
sink, a stove, a bathtub) carry things only by the way."""
NOT_EXTRA = frozenset({"fridge", "bed"})
"""Furniture ``beyond`` never adds: appliances (a second fridge for the magnets on top)
and beds, whose number the room's use sets, not what they carry (a training bed carries
2.4 objects, its pillows among them, where it carried 0.5 while curation dropped the
pillows: a beyond bedroom was then given four beds). Chairs carry too little to be added;
a second sofa in a large living room is common."""


def offered_once(mode: str) -> frozenset[str]:
    """The dependents :func:`expand` offers on its first pass only in ``mode``: in
    ``beyond``, fixtures (a counter's sink, at the training rate once); none in ``fit``,
    whose repeated passes keep the training rate (bathroom sinks 1.28 a room, 1.09 if
    offered once)."""
    return FIXTURES if mode == "beyond" else frozenset()


def holder(category: str) -> bool:
    """Whether ``beyond`` may add a piece of ``category`` to carry objects: furniture
    and counters, not fixtures (toilets: 8-11 in a beyond bathroom of 80 objects, whose
    rolls and brushes they carried) or appliances."""
    if category in NOT_EXTRA:
        return False
    return category not in FIXTURES or category in EXTRA_FIXTURES


def floor_budget(rs) -> float | None:
    """m2 of floor furniture footprint the room type's largest training room holds at
    :data:`~pair2scene.assembly.rooms.MAX_FLOOR_SHARE` (the share a drawn room is sized
    for; None when the statistics keep no room shapes)."""
    from pair2scene.assembly.rooms import MAX_FLOOR_SHARE
    from pair2scene.scene.geometry import polygon_area

    if not rs.floor_shapes:
        return None
    largest = max(abs(polygon_area(np.asarray(k[1:], float).reshape(-1, 2)))
                  for k in rs.floor_shapes)  # fmt: skip
    return MAX_FLOOR_SHARE * largest


@lru_cache(maxsize=1)
def _bundled_sizes():
    from pair2scene.assembly.sizes import SizeTable

    return SizeTable.load()


def _bundled_footprint(category: str) -> float:
    return _bundled_sizes().footprint(category)


def stats_summary(stats: HierarchyStats) -> str:
    """Room types and mean objects per room, for messages."""
    parts = []
    for rtype, rs in sorted(stats.room_types.items()):
        mean = sum(k * n for k, n in rs.object_counts.items()) / max(rs.rooms, 1)
        parts.append(f"{rtype} ({rs.rooms} rooms, {mean:.1f} objects)")
    return ", ".join(parts)


def training_mean(stats: HierarchyStats, room_type: str) -> float:
    """Mean placed objects per training room of ``room_type``."""
    rs = Statistics(stats).room(room_type)
    return sum(k * n for k, n in rs.object_counts.items()) / max(rs.rooms, 1)

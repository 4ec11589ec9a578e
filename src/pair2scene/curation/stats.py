"""Statistics of curated scenes for hierarchy synthesis.

- ``sup_dep[anchor][dependent]``: how often a dependent category rests on an anchor
  category (the floor included, as ``floor``);
- ``func_dep[support][functional anchor][dependent]``: how often a dependent has a
  functional anchor of a category, among objects on a support of a category;
- per room type: templates, the multisets of what stands on the floor (furniture and
  small objects) and of objects mounted on walls (``painting@wall``, :data:`WALL_MARK`;
  with counts) that rooms of that type hold, from which each category's count
  distribution follows, and the distribution of the number of placed objects per room;
- per room type and floor category: how many stand on the floor and how many of those
  stand against a wall (:func:`~pair2scene.curation.tuples.wall_anchor`), from which
  placement decides which objects take a wall as an anchor;
- per room type: how many windows a room has, and their shapes (width, sill, top), from
  which generated rooms get their windows (:func:`pair2scene.assembly.rooms.make_room`);
- per (dependent, functional anchor) pair: how often the dependent faces its anchor and
  how far their footprints stand apart (:mod:`pair2scene.scene.relations`), and how many
  dependents stood beside an object of the anchor's category at all, from which the
  hierarchy decides how often a chair gets a table when the room has one and placement
  keeps chairs at their table, facing it;
- per (dependent, support) pair: how often the dependent faces its support's way and
  where on the support it stands, from which placement keeps a television centred on its
  stand, facing the way the stand does;
- per pair of floor categories: how often two floor objects stood one over or under the
  other (their footprints overlapping: a chair tucked under its table), from which
  placement keeps the pairs the training rooms never show so apart.

"Placed objects" are those that give relation tuples (pair2scene.curation.tuples):
objects with a support that are neither structure nor parts. Statistics are plain
counts, so the statistics of disjoint scene sets add up exactly (:meth:`merge`).
"""

from __future__ import annotations

import json
from collections import Counter
from collections.abc import Iterable, Iterator, Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from pair2scene.assets.forms import form_key
from pair2scene.categories import (
    HANGS_OVER,
    SEATED_AT,
    SEATS,
    TURN_FREE,
    WINDOW_DRESSINGS,
    SuperCategory,
)
from pair2scene.curation.tuples import SKIPPED_SUPER_CATEGORIES, wall_anchor
from pair2scene.errors import UserError
from pair2scene.scene.geometry import convex_overlap_area, polygon_area
from pair2scene.scene.model import FLOOR, WALL, Room, Scene, SceneObject, on_wall, wall_index
from pair2scene.scene.relations import (
    alone_in_room,
    by_back_half,
    faces,
    footprint,
    footprint_gap,
)
from pair2scene.scene.walls import (
    AGAINST_GAP_M,
    Wall,
    against_wall,
    in_corner,
    wall_contact,
    walls_near,
    walls_of,
)

STATS_FORMAT = "pair2scene.hierarchy_stats"
STATS_VERSION = 1

FIXTURE_WALL_GAP_M = 0.3
"""A fixture (toilet, shower, bathtub, counter) this near a wall counts as standing against
it in the wall statistics (:attr:`RoomTypeStats.against_wall`, and which face is against
it for the sideways count), where other floor objects count at
:data:`~pair2scene.scene.walls.AGAINST_GAP_M` (0.15 m); a corner still needs both walls
within that (a toilet keeps its side clearance). The AI2-THOR bathrooms' toilets stand
0.17-0.27 m off their floor polygon (plumbing, the polygon's edge under the wall): at
0.15 m, 5 of the 25 training toilets counted as standing free, and placement stood a fifth
of the generated toilets mid-room. At 0.3 m, 24 of 25; showers 5 -> 10 of 13, bathroom
counters 19 -> 21 of 21, kitchen counters 211 -> 216 of 234, kitchen stoves 2 -> 7 of 7.
Placement stands them flush, so `evaluate`'s 0.15 m counts them against the wall."""

ANCHORED_MARK = "~anchored"
"""Suffix of the wall statistics' key counting apart a category's floor objects that have a
functional anchor (:func:`anchored_key`)."""


def anchored_key(category: str) -> str:
    """The key under which the wall counts (:attr:`RoomTypeStats.on_floor` and the three
    after it) also count ``category``'s floor objects that have a functional anchor: a
    chair at its table, a floor lamp beside its armchair. The category's other objects
    stand alone, and alone they stand against a wall far more often (the training rooms'
    kitchen chairs 47 of 227 at a table, 24 of 30 alone; living-room floor lamps 31 of
    114 and 47 of 54)."""
    return f"{category}{ANCHORED_MARK}"


UNDER_MARK = "~under"
"""Suffix of the wall statistics' key counting apart a category's floor objects that a
painting, mirror or wall lamp hangs over (:func:`under_key`)."""


ANCHOR_PAIR_MARK = ">"
AnchorPattern = tuple[tuple[str, int], ...]
"""A room's :attr:`RoomTypeStats.layout_anchors` pattern: sorted (pair, count) pairs."""


def anchor_pair(dependent: str, anchor: str) -> str:
    """The key of a (dependent, functional anchor) pair of categories in
    :attr:`RoomTypeStats.layout_anchors` (``chair>dining_table``)."""
    return f"{dependent}{ANCHOR_PAIR_MARK}{anchor}"


SEATS_MARK = "~seats"
MAX_SEATS = 4
"""Seats at a table counted apart (:func:`seats_key`); more are counted with these."""


def seats_key(category: str, seats: int) -> str:
    """The key under which the wall counts also count ``category``'s floor objects of
    :data:`~pair2scene.categories.SEATED_AT` with ``seats`` seats
    (:data:`~pair2scene.categories.SEATS`) taking them as their functional anchor, up to
    :data:`MAX_SEATS` (``dining_table~seats4``: four or more): a table with no chair
    stands against a wall, one with four stands free of every wall."""
    return f"{category}{SEATS_MARK}{min(int(seats), MAX_SEATS)}"


def under_key(key: str) -> str:
    """The key under which the wall counts also count the floor objects of ``key`` (a
    category, a form's key or :func:`anchored_key`) that a wall object of
    :data:`~pair2scene.categories.HANGS_OVER` relates to and hangs over: one whose
    functional anchor is the floor object and which that object does not face (a painting
    over the sofa, not the television across from it). Such an object stands with its
    back to the wall the other hangs on, and placement stands it there for the wall
    object; the shares of the others leave it out. The training living rooms' sofas: 36
    of 220 under a painting or mirror, all 36 with their back to a wall; of the other 184,
    145 against a wall, 37 of them sideways."""
    return f"{key}{UNDER_MARK}"


TEMPLATE_SUPER_CATEGORIES = (SuperCategory.LARGE_FURNITURE, SuperCategory.FIXTURE)
"""Template members: floor-standing large furniture, and fixtures because bathrooms and
kitchens are laid out around toilets, bathtubs and counters (a bathroom holds almost no
large furniture)."""


def is_placed(obj: SceneObject) -> bool:
    """True for objects that give a relation tuple (a support, not structure, not a part,
    not part of another object: a faucet of a sink)."""
    return (
        obj.support is not None
        and obj.super not in SKIPPED_SUPER_CATEGORIES
        and obj.part_of is None
    )


def draw_counted(counter: Counter, rng: np.random.Generator):
    """A key of ``counter`` drawn with probability proportional to its count (keys taken
    in sorted order, so equal seeds draw equal keys)."""
    keys = sorted(counter)
    w = np.array([counter[k] for k in keys], dtype=float)
    return keys[int(rng.choice(len(keys), p=w / w.sum()))]


WALL_MARK = "@" + WALL
"""Suffix of a template member mounted on a wall (``painting@wall``): the template holds
a room's wall objects beside its furniture, so how many paintings, mirrors and curtains
a room has goes with its furniture (and a mounted TV is told from one on a stand)."""


def instances(sup_dep: Mapping[str, Counter[str]]) -> Counter[str]:
    """Category -> how many objects of it a support count table (``sup_dep``) holds,
    on any support: the instances its rates are per."""
    out: Counter[str] = Counter()
    for deps in sup_dep.values():
        out.update(deps)
    return out


def template_member(obj: SceneObject) -> str | None:
    """``obj``'s entry in its room's template: its category for floor-standing furniture,
    fixtures and small objects on the floor (a basketball, a box: 6 % of the val
    bedrooms' objects, which expansion, offering only what rests on objects, never
    adds), ``<category>@wall`` for an object mounted on a wall; None otherwise."""
    if on_wall(obj.support):
        return obj.category + WALL_MARK
    if obj.support == FLOOR and obj.super in (
        *TEMPLATE_SUPER_CATEGORIES,
        SuperCategory.SMALL_OBJECT,
    ):
        return obj.category
    return None


def split_member(member: str) -> tuple[str, bool]:
    """A template entry -> (category, mounted on a wall)."""
    if member.endswith(WALL_MARK):
        return member[: -len(WALL_MARK)], True
    return member, False


ON_TOP_M = 0.05
"""A dependent whose bottom is within this of its support's box top rests on the top
(:attr:`HierarchyStats.on_top`)."""
ALIGNED_DEG = 45.0
"""A dependent whose yaw is within this of its support's faces the support's way
(:attr:`HierarchyStats.sup_geometry`)."""
CLOSE_WALL_M = 0.3
"""Two neighbouring objects on one wall whose extents along it are less than this apart
(or overlap: one above the other) hang close together (:attr:`HierarchyStats.wall_gaps`)."""
FLOOR_OVERLAP_SHARE = 0.1
"""Two floor objects whose footprints overlap by more than this share of the smaller one's
stand one over or under the other (:func:`footprint_overlap`,
:attr:`HierarchyStats.floor_overlaps`): a chair tucked under its table, not two pieces
touching, nor a box's overhang over a neighbour by a few centimetres."""
SUP_SUMS = 9
"""Running sums per (dependent, support) pair in :attr:`HierarchyStats.sup_geometry`
(statistics written before the ninth, :func:`parallel`, have 8)."""
MOUNT_SUMS = 3
"""Running sums per mounted category in :attr:`HierarchyStats.mount_height`."""
FUNC_SUMS = 6
"""Running sums per (dependent, functional anchor) pair in
:attr:`HierarchyStats.func_geometry` (five in statistics written before the last)."""


def aligned(relative_yaw: float) -> bool:
    """Whether a yaw relative to the support's (radians) faces the support's way."""
    wrapped = (relative_yaw + np.pi) % (2 * np.pi) - np.pi
    return bool(abs(wrapped) < np.radians(ALIGNED_DEG))


def parallel(relative_yaw: float) -> bool:
    """Whether a yaw relative to the support's (radians) lies along the support's way or
    its reverse, within :data:`ALIGNED_DEG`: the dependent's width parallel to the
    support's width (a pillow across the head of its bed, either face up front)."""
    wrapped = (relative_yaw + np.pi / 2) % np.pi - np.pi / 2
    return bool(abs(wrapped) < np.radians(ALIGNED_DEG))


ASKEW_BINS_DEG = (5.0, 10.0, 15.0, 20.0, 30.0, 45.0)
"""Upper edges (degrees) of the bins :attr:`HierarchyStats.askew` counts a floor object's
turn off the walls' axes in: square (within 5 degrees), then 5-10, 10-15, 15-20, 20-30 and
30-45."""


def askew_bin(yaw: float) -> int:
    """The :data:`ASKEW_BINS_DEG` bin of a yaw's turn off the nearest of the axes every 90
    degrees (0: square to them)."""
    turn = abs(float(np.degrees(yaw) + 45.0) % 90.0 - 45.0)
    return min(int(np.searchsorted(ASKEW_BINS_DEG, turn)), len(ASKEW_BINS_DEG) - 1)


def _summed_rows(
    acc: dict[str, list[int]] | None, rows: dict[str, list[int]] | None, width: int
) -> dict[str, list[int]] | None:
    """``acc`` with ``rows`` (category -> ``width`` counts) added to it, category by
    category; None when either is None (statistics written before the rows were kept)."""
    if acc is None or rows is None:
        return None
    for cat, counts in rows.items():
        acc[cat] = [a + b for a, b in zip(acc.setdefault(cat, [0] * width), counts)]
    return acc


def wall_gaps(walls: list[Wall], placed: list[SceneObject]) -> tuple[int, int]:
    """(pairs of neighbouring objects on one wall, of those hanging close together) among
    ``placed`` on a room's ``walls``: per wall, its mounted objects (curtains and blinds
    left out) in order of their extents along it, each with the next; close when less
    than :data:`CLOSE_WALL_M` apart or overlapping."""
    spans: dict[int, list[tuple[float, float]]] = {}
    for o in placed:
        i = wall_index(o.support)
        if i is None or not 0 <= i < len(walls) or o.category in WINDOW_DRESSINGS:
            continue
        spans.setdefault(i, []).append(walls[i].extent(o.box))
    pairs = close = 0
    for row in spans.values():
        row.sort()
        for (_, hi), (lo, _) in zip(row, row[1:]):
            pairs += 1
            close += int(lo - hi < CLOSE_WALL_M)
    return pairs, close


def footprint_overlap(a: np.ndarray, b: np.ndarray) -> float:
    """The area two convex footprints (counter-clockwise, (K, 2):
    :func:`~pair2scene.scene.relations.footprint`) share, as a share of the smaller one's
    area (0 for a degenerate one)."""
    smaller = min(polygon_area(a), polygon_area(b))
    return convex_overlap_area(a, b) / smaller if smaller > 1e-9 else 0.0


def one_over_other(a: np.ndarray, b: np.ndarray) -> bool:
    """Whether two convex footprints overlap by more than :data:`FLOOR_OVERLAP_SHARE`
    (:func:`footprint_overlap`): one stands over or under the other. Their bounds are
    compared first."""
    if (b.min(0) > a.max(0)).any() or (b.max(0) < a.min(0)).any():
        return False
    return footprint_overlap(a, b) > FLOOR_OVERLAP_SHARE


def overlap_key(a: str, b: str) -> str:
    """The key of a pair of categories in :attr:`HierarchyStats.floor_overlaps`:
    ``"chair|dining_table"``, the two in alphabetical order."""
    return "|".join(sorted((a, b)))


def one_over_another(footprints: list[np.ndarray]) -> Iterator[tuple[int, int]]:
    """The index pairs (i < j) of ``footprints`` that stand one over or under the other
    (:func:`one_over_other`)."""
    for i, a in enumerate(footprints):
        for j in range(i + 1, len(footprints)):
            if one_over_other(a, footprints[j]):
                yield i, j


def floor_overlaps(placed: list[SceneObject]) -> Counter[str]:
    """:func:`overlap_key` -> pairs of the floor objects among ``placed`` whose footprints
    overlap by more than :data:`FLOOR_OVERLAP_SHARE` (:func:`footprint_overlap`)."""
    floor = [o for o in placed if o.support == FLOOR]
    pairs = one_over_another([footprint(o.box) for o in floor])
    return Counter(overlap_key(floor[i].category, floor[j].category) for i, j in pairs)


def footprint_share(room: Room, objects: Iterable[SceneObject]) -> float:
    """How much of ``room``'s floor the footprints (box width x depth) of ``objects``
    cover, summed (overlaps counted twice; 0 for a room without floor area)."""
    area = abs(room.area)
    if area <= 0:
        return 0.0
    return sum(float(o.box.size[0] * o.box.size[1]) for o in objects) / area


def furniture_share(room: Room, placed: Iterable[SceneObject]) -> float:
    """:func:`footprint_share` of the objects of ``placed`` standing on the floor."""
    return footprint_share(room, (o for o in placed if o.support == FLOOR))


def floor_shape(room: Room) -> tuple[float, ...]:
    """(height, x0, y0, x1, y1, ...) of ``room`` for :attr:`RoomTypeStats.floor_shapes`:
    its floor polygon counter-clockwise from the vertex nearest its bounds' lower-left
    corner, moved so that corner is the origin, to the centimetre."""
    poly = np.asarray(room.floor_polygon, float)
    poly = poly - poly.min(axis=0)
    start = int(np.argmin(np.round(poly, 2) @ (1.0, 1.0 + 1e-6)))
    poly = np.roll(poly, -start, axis=0)
    return (round(float(room.height), 2), *(round(float(v), 2) + 0.0 for v in poly.ravel()))


@dataclass
class RoomTypeStats:
    """Counts over the rooms of one type."""

    rooms: int = 0
    layouts: Counter[tuple[str, ...]] = field(default_factory=Counter)
    """Sorted multiset of template members (:func:`template_member`, repeats kept) ->
    number of rooms with it."""
    layout_anchors: Counter[tuple[tuple[str, ...], AnchorPattern]] = field(default_factory=Counter)
    """(layout, a room's anchor pattern) -> number of rooms: which of a room's floor
    members took which other as their functional anchor, as sorted (:func:`anchor_pair`,
    count) pairs (``(("chair>dining_table", 4),)``: its four chairs at its table; ``()``:
    none at any). A template's rooms are kept apart this way, so a drawn template seats
    its chairs as one of its rooms did, not each chair on its own with a pooled share.
    Empty in statistics written before it was kept (then every member draws its anchor
    from the pooled :attr:`HierarchyStats.func_dep`)."""
    object_counts: Counter[int] = field(default_factory=Counter)
    """Number of placed objects in a room -> number of rooms."""
    layout_counts: Counter[tuple[tuple[str, ...], int]] = field(default_factory=Counter)
    """(layout, number of placed objects) of a room -> number of rooms: which counts went
    with which furniture (a room of one dresser held 12 objects, not 30). Empty in
    statistics written before it was kept (then only the two marginals are known)."""
    on_floor: Counter[str] = field(default_factory=Counter)
    """Category -> objects of it standing on the floor. This and the three wall counts
    below also count the objects of a form apart, under its key
    (:func:`~pair2scene.assets.forms.form_key`: ``counter_top#shaped``, L and C counters),
    those with a functional anchor, under :func:`anchored_key` (``chair~anchored``), and
    tables by the seats at them, under :func:`seats_key` (``dining_table~seats4``),
    besides their category; and, of each of those, the objects a painting, mirror or wall
    lamp hangs over under :func:`under_key` (``sofa~under``, ``chair~anchored~under``)."""
    against_wall: Counter[str] = field(default_factory=Counter)
    """Category -> of those, how many stand against a wall. Empty in statistics written
    before it was kept (then no object takes a wall anchor)."""
    in_corner: Counter[str] = field(default_factory=Counter)
    """Category -> of those against a wall, how many stand in a corner: against two walls
    at once (:func:`~pair2scene.scene.walls.in_corner`; a kitchen's counters and fridge,
    a bedroom's dresser). Empty in statistics written before it was kept (then no object
    is put in a corner)."""
    sideways: Counter[str] = field(default_factory=Counter)
    """Category -> of those against a wall, how many have no back face against one: a
    side (the arm of a sofa turned to face along the wall, 37 of the 181 living-room sofas
    against a wall in the training rooms), rarely the front. Empty in statistics written
    before it was kept (then every object against a wall stands with its back to it)."""
    window_counts: Counter[int] = field(default_factory=Counter)
    """Windows in a room -> number of rooms. Empty in statistics written before it was
    kept (then generated rooms have no windows)."""
    window_shapes: Counter[tuple[float, float, float]] = field(default_factory=Counter)
    """(width, sill height, top height) of a window, metres to the centimetre -> how many
    windows had it."""
    floor_shapes: Counter[tuple[float, ...]] = field(default_factory=Counter)
    """A room's (height, x0, y0, x1, y1, ...): its height and its floor polygon,
    counter-clockwise, moved to start at the origin corner of its bounds, metres to the
    centimetre -> how many rooms had it (a third of the ProcTHOR rooms are L-shaped or
    more). Empty in statistics written before it was kept (then generated rooms are
    rectangles of the room table's sizes)."""
    share_sums: list[float] = field(default_factory=lambda: [0.0, 0.0, 0.0])
    """[rooms, sum, sum of squares] of the log of :func:`furniture_share` over the rooms
    with floor objects: how much of its floor a room's furniture covers (AI2-THOR +
    ProcTHOR-1k train: a median 0.24 in bedrooms, 0.21 in living rooms and kitchens, a
    log standard deviation of 0.38-0.47; larger rooms hold more furniture). Generated
    rooms are drawn to match it (:func:`~pair2scene.assembly.rooms.draw_floor`). Zeros
    in statistics written before it was kept (then any training room large enough for
    the furniture is drawn, by its count alone)."""
    sup_dep: dict[str, Counter[str]] = field(default_factory=dict)
    """Support category (``floor`` and ``wall`` included) -> dependent category -> count
    in the rooms of this type: what a bathroom's counter holds (soap, a towel), not what
    counters hold in general (a kitchen's bread and lettuce). Empty in statistics written
    before it was kept (then every room type draws dependents from the pooled
    :attr:`HierarchyStats.sup_dep`)."""

    def wall_rate(self, category: str, prior: float = 1.0) -> float:
        """Share of ``category``'s floor objects that stand against a wall, with ``prior``
        pseudo-counts split evenly (0.5 for a category never seen on the floor)."""
        n = self.on_floor.get(category, 0)
        return (self.against_wall.get(category, 0) + 0.5 * prior) / (n + prior)

    def templates(self, top: int | None = None) -> list[tuple[dict[str, int], int]]:
        """The ``top`` most frequent furniture multisets as ({category: count}, rooms),
        most frequent first (ties by the sorted category list)."""
        ranked = sorted(self.layouts.items(), key=lambda kv: (-kv[1], kv[0]))
        return [(dict(sorted(Counter(k).items())), n) for k, n in ranked[:top]]

    def template_anchors(
        self, layout: Sequence[str], rng: np.random.Generator
    ) -> dict[str, Counter[str]] | None:
        """One of ``layout``'s training rooms' anchor patterns (:attr:`layout_anchors`),
        drawn by rooms: dependent category -> anchor category -> how many of its members
        took one. None when these statistics do not keep them or have no such layout (a
        composed room type's, or one a text changed); then nothing is drawn."""
        key = tuple(sorted(layout))
        patterns = sorted((p, n) for (k, p), n in self.layout_anchors.items() if k == key)
        if not patterns:
            return None
        weights = np.array([n for _, n in patterns], float)
        pattern = patterns[int(rng.choice(len(patterns), p=weights / weights.sum()))][0]
        out: dict[str, Counter[str]] = {}
        for pair, n in pattern:
            dependent, _, anchor = pair.partition(ANCHOR_PAIR_MARK)
            out.setdefault(dependent, Counter())[anchor] += n
        return out

    def furniture_counts(self) -> dict[str, dict[int, int]]:
        """Per template category: instances in a room -> number of rooms (0 included)."""
        cats = sorted({c for layout in self.layouts for c in layout})
        out: dict[str, dict[int, int]] = {}
        for cat in cats:
            hist: Counter[int] = Counter()
            for layout, n in self.layouts.items():
                hist[layout.count(cat)] += n
            out[cat] = dict(sorted(hist.items()))
        return out

    def add(self, other: RoomTypeStats) -> None:
        self.rooms += other.rooms
        self.layouts.update(other.layouts)
        self.object_counts.update(other.object_counts)
        self.layout_counts.update(other.layout_counts)
        self.layout_anchors.update(other.layout_anchors)
        self.on_floor.update(other.on_floor)
        self.against_wall.update(other.against_wall)
        self.in_corner.update(other.in_corner)
        self.sideways.update(other.sideways)
        self.window_counts.update(other.window_counts)
        self.window_shapes.update(other.window_shapes)
        self.floor_shapes.update(other.floor_shapes)
        self.share_sums = [a + b for a, b in zip(self.share_sums, other.share_sums)]
        for anchor, deps in other.sup_dep.items():
            self.sup_dep.setdefault(anchor, Counter()).update(deps)

    def share_normal(self) -> tuple[float, float] | None:
        """(mean, standard deviation) of the rooms' log :func:`furniture_share`; None
        with fewer than two rooms or no spread (statistics written before it was kept)."""
        n, total, squares = self.share_sums
        if n < 2:
            return None
        mean, sd = mean_std(n, total, squares)
        return (mean, sd) if sd > 0 else None


def _add_sums(table: dict[str, dict[str, list[float]]], dependent: str, anchor: str, sums) -> None:
    """Add ``sums`` to the running sums of the (``dependent``, ``anchor``) pair in
    ``table`` (dependent -> anchor -> sums; zeros for a new pair)."""
    per_anchor = table.setdefault(dependent, {})
    old = per_anchor.get(anchor, [0.0] * len(sums))
    per_anchor[anchor] = [a + b for a, b in zip(old, sums)]


def mean_std(n: float, total: float, squares: float) -> tuple[float, float]:
    """(mean, standard deviation) of ``n`` values from their running sum and sum of
    squares (the sums the tables of :class:`HierarchyStats` keep)."""
    mean = total / n
    return mean, float(np.sqrt(max(squares / n - mean * mean, 0.0)))


def _sums(table: dict[str, dict[str, list[float]]]) -> dict:
    """dependent -> anchor -> running sums, sorted and rounded for JSON."""
    return {
        d: {a: [round(v, 6) for v in acc] for a, acc in sorted(pa.items())}
        for d, pa in sorted(table.items())
    }


def _anchor_pattern(pattern: Mapping[str, int], layout: tuple[str, ...]) -> AnchorPattern:
    """A template's ``anchored`` pattern as read from JSON, checked against its layout:
    each pair two of its members, no more dependents than it has (ValueError)."""
    out = []
    for pair, n in sorted(pattern.items()):
        dep, _, anchor = pair.partition(ANCHOR_PAIR_MARK)
        if dep not in layout or anchor not in layout:
            raise ValueError(f"anchored {pair!r}: not two of the template's members as "
                             "'dependent>anchor'")  # fmt: skip
        if not 0 < int(n) <= layout.count(dep):
            raise ValueError(f"anchored {pair!r}: {n} of its {layout.count(dep)} members")
        out.append((pair, int(n)))
    return tuple(out)


def _layout_key(furniture: dict[str, int]) -> tuple[str, ...]:
    """{category: count} -> the sorted multiset :attr:`RoomTypeStats.layouts` is keyed by."""
    return tuple(sorted(c for c, n in furniture.items() for _ in range(int(n))))


def _joint_counts(rs: RoomTypeStats, furniture: dict[str, int]) -> dict:
    """A template's ``object_counts`` entry: placed objects -> rooms, for the rooms with
    exactly that furniture, and its ``anchored`` one (:attr:`RoomTypeStats.layout_anchors`)
    (each left out when the statistics do not have it)."""
    key = _layout_key(furniture)
    joint = {count: n for (layout, count), n in rs.layout_counts.items() if layout == key}
    patterns = sorted((p, n) for (layout, p), n in rs.layout_anchors.items() if layout == key)
    out: dict = {}
    if joint:
        out["object_counts"] = {str(k): joint[k] for k in sorted(joint)}
    if patterns:
        out["anchored"] = [[dict(p), n] for p, n in patterns]
    return out


@dataclass
class HierarchyStats:
    """Support and functional dependency frequencies, templates and object counts."""

    rooms: int = 0
    sup_dep: dict[str, Counter[str]] = field(default_factory=dict)
    """anchor category (``floor`` included) -> dependent category -> count."""
    func_dep: dict[str, dict[str, Counter[str]]] = field(default_factory=dict)
    """support category -> functional anchor category -> dependent category -> count."""
    room_types: dict[str, RoomTypeStats] = field(default_factory=dict)
    wall_anchor: dict[str, dict[str, list[float]]] = field(default_factory=dict)
    """dependent category -> functional anchor category -> [n, sum, sum of squares] of
    the anchor's distance (m) from the wall the dependent stands against, its centre
    measured along that wall's inward normal: a nightstand's bed is about a bed's half
    length from the nightstand's wall, a TV stand's sofa a room's depth. Placement picks
    the wall of an object with both anchors by it."""
    func_geometry: dict[str, dict[str, list[float]]] = field(default_factory=dict)
    """dependent category -> functional anchor category -> [n, facing, faced, sum, sum
    of squares of the footprint gap (m), behind]: how many dependents face their anchor
    (:func:`~pair2scene.scene.relations.faces`), how many stand where their anchor faces
    them (a TV stand in front of its sofa), how far apart they stand, and how many of
    those the anchor does not face stand by its back half (their centre behind the
    anchor's middle, in its frame: a nightstand by the head of its bed). Statistics
    written before ``behind`` was kept have five sums (then placement takes either
    half)."""
    func_present: dict[str, dict[str, Counter[str]]] = field(default_factory=dict)
    """support category -> anchor category -> dependent category -> dependents on that
    support in rooms where another object of the anchor category stands on the same
    support, and that took no anchor of another category: the denominator of "a chair
    takes the room's table as its anchor". A chair at the dining table is not counted
    beside the room's desk: it was not free to take it, and counting it made a desk
    keep its chair in 27 of 97 chairs beside one, where the bedrooms with a desk and no
    dining table had theirs at it in 29 of 34."""
    on_top: Counter[str] | None = field(default_factory=Counter)
    """support category -> its dependents resting on the top of its box (their bottom
    within :data:`ON_TOP_M` of it), out of ``sup_dep[support]``'s total: a table's things
    all do, a fridge's never (they are inside), a sofa's never (on the seat, below the
    backrest's top). None in statistics written before it was kept."""

    same_model: dict[str, list[int]] = field(default_factory=dict)
    """floor category -> [rooms with two or more floor objects of it (with asset ids),
    rooms where they are all one model (one asset id)]: the chairs of a room match (0.85
    of rooms in the training data), its dining tables never (0 of 6). Empty in statistics
    written before it was kept (then no object shares another's model)."""

    sup_geometry: dict[str, dict[str, list[float]]] = field(default_factory=dict)
    """dependent category -> support category -> [n, aligned, sum u, sum u², sum v, sum
    v², sum w, sum w², parallel]: how many dependents face their support's way (yaws within
    :data:`ALIGNED_DEG`) and how many lie parallel to it, that way or its reverse
    (:func:`parallel`), where their centres stand on it, ``u`` along its width and ``v``
    along its depth, both in its canonical frame (-1 to 1 edge to edge), and how wide they
    are against it, ``w`` the ratio of the long sides of their footprints: a television
    stands centred on its stand facing its way and about as wide (``w`` 1.00 on average,
    up to 1.69), a cup anywhere on a table, any way."""

    mount_height: dict[str, dict[str, list[float]]] = field(default_factory=dict)
    """dependent category -> ``wall`` -> [n, sum z, sum z²]: the heights of the centres of
    the objects mounted on a wall above the floor (m): paintings at 1.64 m on average
    (standard deviation 0.31), a microwave over the counter at 1.76 m (0.11), a toilet
    paper hanger at 0.89 m (0.11) in the training rooms. Empty in statistics written
    before it was kept (then mounted objects hang at any height the model draws)."""

    wall_gaps: list[int] | None = field(default_factory=lambda: [0, 0])
    """[pairs of neighbouring objects on one wall, of those hanging close together]
    (within :data:`CLOSE_WALL_M` along the wall, or one above the other), curtains and
    blinds left out: 0.28 of the training living rooms' pairs, their median gap 0.87 m.
    None in statistics written before it was kept."""

    floor_overlaps: Counter[str] | None = field(default_factory=Counter)
    """:func:`overlap_key` of two floor categories -> pairs of floor objects of them that
    stood one over or under the other (:func:`floor_overlaps`): in the curated training
    rooms, 691 chairs under dining tables and 19 under desks, 7 plungers and 6 brushes by
    the toilet, and every other pair at most twice. None in statistics written before it
    was kept (then placement keeps no floor objects apart by footprint)."""

    askew: dict[str, list[int]] | None = field(default_factory=dict)
    """floor category -> how many of its objects standing free of the walls (of
    :data:`~pair2scene.categories.TURN_FREE`'s, all) turned off the walls' axes by how
    much (:func:`askew_bin`'s bins): in the training rooms 0.75 of the
    chairs (most by 5-30 degrees: left as pulled out), 0.78 of the floor lamps, 0.96 of
    the house plants, 0.66 of the armchairs (most by 20-45 degrees: turned to the room),
    0.04 of the sofas, no table or dresser. None in statistics written before it was kept
    (then floor objects stand square to the walls)."""

    isolated: dict[str, list[int]] | None = field(default_factory=dict)
    """floor category -> [its objects standing alone in the room, its floor objects]
    (:func:`~pair2scene.scene.relations.stands_alone`: further than 0.5 m from every wall
    and every other floor object). In the training rooms none of the 248 beds, 243
    dressers and 156 house plants did, 7 of the 296 side tables, 11 of the 868 chairs, 22
    of the 74 coffee tables, 17 of the 46 basketballs and 29 of the 49 dog beds. None in
    statistics written before it was kept (then placement lets any floor object stand
    alone)."""

    # -- fitting ------------------------------------------------------------------
    @classmethod
    def fit(cls, scenes: Iterable[Scene]) -> HierarchyStats:
        """Count over ``scenes`` (curated: ``support`` and ``functional_anchor`` set)."""
        stats = cls()
        for scene in scenes:
            stats._add_scene(scene)
        return stats

    def _add_scene(self, scene: Scene) -> None:
        by_id = scene.by_id()

        def cat_of(ref: str) -> str | None:
            if ref == FLOOR:
                return FLOOR
            if on_wall(ref):
                return WALL
            obj = by_id.get(ref)
            return None if obj is None else obj.category

        placed = [o for o in scene.objects if is_placed(o)]
        room = self.room_types.setdefault(scene.room.type, RoomTypeStats())
        for o in placed:
            anchor = cat_of(o.support)
            if anchor is None:
                continue
            self.sup_dep.setdefault(anchor, Counter())[o.category] += 1
            room.sup_dep.setdefault(anchor, Counter())[o.category] += 1
            if anchor == WALL:
                z = float(o.box.center[2])
                _add_sums(self.mount_height, o.category, WALL, (1.0, z, z * z))
            holder = by_id.get(o.support)
            if holder is not None:
                if self.on_top is not None:
                    self.on_top[anchor] += int(o.box.bottom >= holder.box.top - ON_TOP_M)
                self._add_seat(o, holder)
            func = None if o.functional_anchor is None else cat_of(o.functional_anchor)
            if func is not None:
                per_support = self.func_dep.setdefault(anchor, {})
                per_support.setdefault(func, Counter())[o.category] += 1
                self._add_geometry(o, by_id[o.functional_anchor])
        self._add_present(placed, cat_of)
        walls = walls_of(scene.room.floor_polygon)
        if self.wall_gaps is not None:
            pairs, close = wall_gaps(walls, placed)
            self.wall_gaps[0] += pairs
            self.wall_gaps[1] += close
        if self.floor_overlaps is not None:
            self.floor_overlaps.update(floor_overlaps(placed))
        room.rooms += 1
        layout = tuple(sorted(m for m in map(template_member, placed) if m is not None))
        room.layouts[layout] += 1
        room.object_counts[len(placed)] += 1
        room.layout_counts[layout, len(placed)] += 1
        pattern: Counter[str] = Counter()
        for o in placed:
            anchor = by_id.get(o.functional_anchor) if o.functional_anchor else None
            if (
                anchor is not None
                and o.support == FLOOR
                and anchor.support == FLOOR
                and template_member(o) is not None
                and template_member(anchor) is not None
            ):
                pattern[anchor_pair(o.category, anchor.category)] += 1
        room.layout_anchors[layout, tuple(sorted(pattern.items()))] += 1
        room.window_counts[len(scene.room.windows)] += 1
        for w in scene.room.windows:
            shape = (w.width, max(w.z_min, 0.0), w.z_max)
            room.window_shapes[tuple(round(float(v), 2) for v in shape)] += 1
        room.floor_shapes[floor_shape(scene.room)] += 1
        share = furniture_share(scene.room, placed)
        if share > 0:
            log_share = float(np.log(share))
            room.share_sums = [a + b for a, b in
                                zip(room.share_sums, (1.0, log_share, log_share**2))]  # fmt: skip
        models: dict[str, list[str]] = {}
        for o in placed:
            if o.support == FLOOR and o.asset is not None and o.asset.id:
                models.setdefault(o.category, []).append(o.asset.id)
        for cat, ids in models.items():
            if len(ids) >= 2:
                acc = self.same_model.setdefault(cat, [0, 0])
                acc[0] += 1
                acc[1] += int(len(set(ids)) == 1)
        under = {  # floor objects a painting, mirror or wall lamp hangs over
            o.functional_anchor
            for o in placed
            if on_wall(o.support) and o.category in HANGS_OVER and o.functional_anchor in by_id
            and not faces(by_id[o.functional_anchor].box, o.box)
        }  # fmt: skip
        seated = Counter(  # floor object -> seats at it
            o.functional_anchor for o in placed
            if o.category in SEATS and o.support == FLOOR and o.functional_anchor
        )  # fmt: skip
        floor = [o for o in placed if o.support == FLOOR]
        if self.isolated is not None:
            alone = alone_in_room([footprint(o.box) for o in floor], scene.room.floor_polygon)
            for o, lone in zip(floor, alone):
                acc = self.isolated.setdefault(o.category, [0, 0])
                acc[0] += int(lone)
                acc[1] += 1
        for o in floor:
            wall = wall_anchor(scene, o, walls)
            gap = FIXTURE_WALL_GAP_M if o.super is SuperCategory.FIXTURE else AGAINST_GAP_M
            backed = against_wall(o.box, walls, gap)  # (its box may reach into the wall)
            # (a pot has no side to turn to the wall: by one, it stands in a corner or not)
            turn_free = o.category in TURN_FREE
            near = walls_near(o.box, walls, gap) if turn_free else set()
            by_wall = (backed or wall is not None or wall_contact(o.box, walls, gap) is not None
                       or bool(near))  # fmt: skip
            cornered = by_wall and (in_corner(o.box, walls) or len(near) >= 2)
            anchor = by_id.get(o.functional_anchor) if o.functional_anchor else None
            form = form_key(o.category, o.box.size)  # an L counter, counted apart too
            keys = [o.category] + ([] if form is None else [form])
            if anchor is not None:  # and a chair at a table apart from one alone
                keys.append(anchored_key(o.category))
            if o.category in SEATED_AT:  # and a table by its chairs
                keys.append(seats_key(o.category, seated[o.id]))
            if o.id in under:  # and each of those under a painting apart
                keys += [under_key(k) for k in keys]
            if (not by_wall or turn_free) and self.askew is not None:  # (by a wall too)
                bins = self.askew.setdefault(o.category, [0] * len(ASKEW_BINS_DEG))
                bins[askew_bin(o.box.yaw)] += 1
            for key in keys:
                room.on_floor[key] += 1
                room.against_wall[key] += int(by_wall)
                room.in_corner[key] += int(cornered)
                room.sideways[key] += int(by_wall and not backed and not turn_free)
            if wall is not None and anchor is not None:
                d = float(anchor.box.in_frame_of(wall.box).center[1])  # frame y is metres
                _add_sums(self.wall_anchor, o.category, anchor.category, (1.0, d, d * d))
        self.rooms += 1

    def _add_geometry(self, dep: SceneObject, anchor: SceneObject) -> None:
        gap = footprint_gap(footprint(dep.box), footprint(anchor.box))
        faced = faces(anchor.box, dep.box)
        behind = not faced and by_back_half(dep.box, anchor.box)
        new = (1.0, float(faces(dep.box, anchor.box)), float(faced), gap, gap * gap,
               float(behind))  # fmt: skip
        _add_sums(self.func_geometry, dep.category, anchor.category, new)

    def _add_seat(self, dep: SceneObject, support: SceneObject) -> None:
        local = dep.box.in_frame_of(support.box)
        u, v = (float(c) for c in local.center[:2])
        w = float(max(dep.box.size[:2]) / max(max(support.box.size[:2]), 1e-6))
        new = (1.0, float(aligned(local.yaw)), u, u * u, v, v * v, w, w * w,
               float(parallel(local.yaw)))  # fmt: skip
        _add_sums(self.sup_geometry, dep.category, support.category, new)

    def _add_present(self, placed: list[SceneObject], cat_of) -> None:
        by_support: dict[str, list[SceneObject]] = {}
        for o in placed:
            by_support.setdefault(WALL if on_wall(o.support) else o.support, []).append(o)
        floor = Counter(o.category for o in by_support.get(FLOOR, []))
        for support, group in by_support.items():
            sup_cat = cat_of(support)
            if sup_cat is None:
                continue
            # A wall object's anchor stands on the floor (a painting above the bed).
            cats = floor if support == WALL else Counter(o.category for o in group)
            per_support = self.func_present.setdefault(sup_cat, {})
            for o in group:
                took = None if o.functional_anchor is None else cat_of(o.functional_anchor)
                for a, n in cats.items():
                    if took is not None and took != a:
                        continue  # taken by another anchor: it was not free to take an a
                    if n - (a == o.category and support != WALL) > 0:  # another object
                        per_support.setdefault(a, Counter())[o.category] += 1

    @classmethod
    def merge(cls, parts: Iterable[HierarchyStats]) -> HierarchyStats:
        """The statistics of the union of the (disjoint) scene sets of ``parts``."""
        out = cls()
        for p in parts:
            out.rooms += p.rooms
            for anchor, deps in p.sup_dep.items():
                out.sup_dep.setdefault(anchor, Counter()).update(deps)
            for sup, per_func in p.func_dep.items():
                dst = out.func_dep.setdefault(sup, {})
                for func, deps in per_func.items():
                    dst.setdefault(func, Counter()).update(deps)
            for rtype, rs in p.room_types.items():
                out.room_types.setdefault(rtype, RoomTypeStats()).add(rs)
            for own, theirs in ((out.wall_anchor, p.wall_anchor),
                                (out.func_geometry, p.func_geometry),
                                (out.sup_geometry, p.sup_geometry),
                                (out.mount_height, p.mount_height)):  # fmt: skip
                for dep, per_anchor in theirs.items():
                    for anchor, acc in per_anchor.items():
                        _add_sums(own, dep, anchor, acc)
            for cat, (n, same) in p.same_model.items():
                acc = out.same_model.setdefault(cat, [0, 0])
                acc[0] += n
                acc[1] += same
            for sup, per_anchor in p.func_present.items():
                dst = out.func_present.setdefault(sup, {})
                for anchor, deps in per_anchor.items():
                    dst.setdefault(anchor, Counter()).update(deps)
            if p.on_top is None or out.on_top is None:
                out.on_top = None
            else:
                out.on_top.update(p.on_top)
            if p.wall_gaps is None or out.wall_gaps is None:
                out.wall_gaps = None
            else:
                out.wall_gaps = [a + b for a, b in zip(out.wall_gaps, p.wall_gaps)]
            if p.floor_overlaps is None or out.floor_overlaps is None:
                out.floor_overlaps = None
            else:
                out.floor_overlaps.update(p.floor_overlaps)
            out.askew = _summed_rows(out.askew, p.askew, len(ASKEW_BINS_DEG))
            out.isolated = _summed_rows(out.isolated, p.isolated, 2)
        return out

    def top_kept_free(self, min_dependents: int = 20, max_share: float = 0.02) -> frozenset:
        """Support categories whose box top holds nothing in the data (at most
        ``max_share`` of at least ``min_dependents`` dependents rest there): a fridge, a
        sofa, a bed. Empty when ``on_top`` was not kept or ``max_share`` is negative."""
        if self.on_top is None or max_share < 0:
            return frozenset()
        out = set()
        for sup, deps in self.sup_dep.items():
            n = sum(deps.values())
            if sup not in (FLOOR, WALL) and n >= min_dependents:
                if self.on_top.get(sup, 0) <= max_share * n:
                    out.add(sup)
        return frozenset(out)

    def askew_shares(self, min_objects: int = 20) -> dict[str, np.ndarray]:
        """Floor category -> the share of its free-standing objects in each of
        :data:`ASKEW_BINS_DEG`'s bins (:attr:`askew`), for categories with at least
        ``min_objects`` of them; empty when ``askew`` was not kept."""
        out = {}
        for cat, bins in sorted((self.askew or {}).items()):
            n = sum(bins)
            if n >= min_objects:
                out[cat] = np.asarray(bins, float) / n
        return out

    def isolated_shares(self, min_objects: int = 20) -> dict[str, float]:
        """Floor category -> the share of its floor objects that stood alone in the room
        (:attr:`isolated`), for categories with at least ``min_objects`` of them; empty
        when ``isolated`` was not kept."""
        return {
            cat: alone / n
            for cat, (alone, n) in sorted((self.isolated or {}).items())
            if n >= min_objects
        }

    def same_model_shares(self, min_rooms: int = 5) -> dict[str, float]:
        """Floor category -> the share of rooms (of at least ``min_rooms`` with two or
        more of it) whose objects of it are all one model (:attr:`same_model`)."""
        return {c: same / n for c, (n, same) in sorted(self.same_model.items())
                if n >= min_rooms}  # fmt: skip

    # -- queries ------------------------------------------------------------------
    def room_type(self, room_type: str) -> RoomTypeStats:
        """The statistics of ``room_type``. When no training room had it: for a composed
        type (``resources/room_types.json``, :mod:`pair2scene.hierarchy.room_types`) those
        of its base types pooled, each weighted by its share of the recipe (counts scaled,
        so not whole numbers; an office gets windows of living rooms and bedrooms, its
        templates are composed in the hierarchy stage); otherwise of every room type
        pooled (a garage described in text gets the windows of rooms in general)."""
        rs = self.room_types.get(room_type)
        if rs is not None:
            return rs
        from pair2scene.resources import load_table

        recipe = load_table("room_types")["types"].get(room_type, {})
        bases = {b: float(w) for b, w in sorted(recipe.get("bases", {}).items())
                 if b in self.room_types and self.room_types[b].rooms}  # fmt: skip
        pooled = RoomTypeStats()
        if not bases:
            for other in self.room_types.values():
                pooled.add(other)
            return pooled
        pooled.rooms = sum(self.room_types[b].rooms for b in bases)
        for base, weight in bases.items():
            part = self.room_types[base]
            scale = weight / sum(bases.values()) * pooled.rooms / part.rooms
            for name in ("layouts", "object_counts", "layout_counts", "layout_anchors", "on_floor",
                         "against_wall", "in_corner", "sideways", "window_counts", "window_shapes",
                         "floor_shapes"):  # fmt: skip
                counts = getattr(pooled, name)
                for key, n in getattr(part, name).items():
                    counts[key] += n * scale
            share = zip(pooled.share_sums, part.share_sums)
            pooled.share_sums = [a + b * scale for a, b in share]
            for anchor, deps in part.sup_dep.items():
                counts = pooled.sup_dep.setdefault(anchor, Counter())
                for key, n in deps.items():
                    counts[key] += n * scale
        return pooled

    def templates(self, room_type: str, top: int | None = None) -> list[tuple[dict[str, int], int]]:
        """Most frequent furniture multisets of ``room_type`` (see RoomTypeStats.templates)."""
        rs = self.room_types.get(room_type)
        return [] if rs is None else rs.templates(top)

    # -- JSON ---------------------------------------------------------------------
    def to_dict(self) -> dict:
        """Plain JSON-able dict with sorted keys (integer keys written as strings)."""

        def counts(c: Counter) -> dict:
            return {str(k): int(v) for k, v in sorted(c.items())}

        room_types = {}
        for rtype, rs in sorted(self.room_types.items()):
            room_types[rtype] = {
                "rooms": rs.rooms,
                "templates": [
                    {"furniture": f, "rooms": n, **_joint_counts(rs, f)} for f, n in rs.templates()
                ],
                "furniture_counts": {
                    cat: {str(k): v for k, v in hist.items()}
                    for cat, hist in rs.furniture_counts().items()
                },
                "object_counts": counts(rs.object_counts),
                "walls": {
                    cat: {
                        "on_floor": n,
                        "against_wall": rs.against_wall.get(cat, 0),
                        "in_corner": rs.in_corner.get(cat, 0),
                        "sideways": rs.sideways.get(cat, 0),
                    }
                    for cat, n in sorted(rs.on_floor.items())
                },
                "window_counts": counts(rs.window_counts),
                "window_shapes": [[*k, n] for k, n in sorted(rs.window_shapes.items())],
                "floor_shapes": [[*k, n] for k, n in sorted(rs.floor_shapes.items())],
                "share_sums": [round(v, 6) for v in rs.share_sums],
                "sup_dep": {a: counts(d) for a, d in sorted(rs.sup_dep.items())},
            }
        return {
            "format": STATS_FORMAT,
            "version": STATS_VERSION,
            "rooms": self.rooms,
            "template_super_categories": [s.value for s in TEMPLATE_SUPER_CATEGORIES],
            "sup_dep": {a: counts(d) for a, d in sorted(self.sup_dep.items())},
            "func_dep": {
                s: {f: counts(d) for f, d in sorted(pf.items())}
                for s, pf in sorted(self.func_dep.items())
            },
            "room_types": room_types,
            "wall_anchor": _sums(self.wall_anchor),
            "func_geometry": _sums(self.func_geometry),
            "sup_geometry": _sums(self.sup_geometry),
            "mount_height": _sums(self.mount_height),
            "same_model": {c: list(acc) for c, acc in sorted(self.same_model.items())},
            "func_present": {
                s: {a: counts(d) for a, d in sorted(pa.items())}
                for s, pa in sorted(self.func_present.items())
            },
            **({} if self.on_top is None else {"on_top": counts(self.on_top)}),
            **({} if self.wall_gaps is None else {"wall_gaps": list(self.wall_gaps)}),
            **(
                {}
                if self.floor_overlaps is None
                else {"floor_overlaps": counts(self.floor_overlaps)}
            ),
            **(
                {}
                if self.askew is None
                else {"askew": {c: list(b) for c, b in sorted(self.askew.items())}}
            ),
            **(
                {}
                if self.isolated is None
                else {"isolated": {c: list(v) for c, v in sorted(self.isolated.items())}}
            ),
        }

    def to_json(self) -> str:
        return json.dumps(self.to_dict(), indent=1) + "\n"

    @classmethod
    def from_dict(cls, doc: dict, where: str = "stats") -> HierarchyStats:
        """Inverse of :meth:`to_dict`; a wrong format or version is a UserError."""
        if not isinstance(doc, dict) or doc.get("format") != STATS_FORMAT:
            raise UserError(f"{where}: not a {STATS_FORMAT} file")
        if doc.get("version") != STATS_VERSION:
            raise UserError(
                f"{where}: version {doc.get('version')!r} not supported (expected {STATS_VERSION})"
            )
        try:
            out = cls(rooms=int(doc["rooms"]))
            for a, deps in doc["sup_dep"].items():
                out.sup_dep[a] = Counter({k: int(v) for k, v in deps.items()})
            for s, pf in doc["func_dep"].items():
                out.func_dep[s] = {
                    f: Counter({k: int(v) for k, v in d.items()}) for f, d in pf.items()
                }
            for rtype, rd in doc["room_types"].items():
                rs = RoomTypeStats(rooms=int(rd["rooms"]))
                for t in rd["templates"]:
                    key = _layout_key(t["furniture"])
                    rs.layouts[key] += int(t["rooms"])
                    for k, v in t.get("object_counts", {}).items():
                        rs.layout_counts[key, int(k)] += int(v)
                    for pattern, rooms in t.get("anchored", []):
                        rs.layout_anchors[key, _anchor_pattern(pattern, key)] += int(rooms)
                rs.object_counts = Counter({int(k): int(v) for k, v in rd["object_counts"].items()})
                for cat, w in rd.get("walls", {}).items():
                    n, by_wall = int(w["on_floor"]), int(w["against_wall"])
                    corner, side = int(w.get("in_corner", 0)), int(w.get("sideways", 0))
                    if not (0 <= by_wall <= n and 0 <= corner <= by_wall and 0 <= side <= by_wall):
                        raise ValueError(f"walls of {cat}: {by_wall} of {n} against a wall, "
                                         f"{corner} in a corner, {side} sideways")  # fmt: skip
                    rs.on_floor[cat], rs.against_wall[cat] = n, by_wall
                    rs.in_corner[cat], rs.sideways[cat] = corner, side
                for k, v in rd.get("window_counts", {}).items():
                    rs.window_counts[int(k)] = int(v)
                for width, sill, top, n in rd.get("window_shapes", []):
                    rs.window_shapes[float(width), float(sill), float(top)] += int(n)
                for *shape, n in rd.get("floor_shapes", []):
                    if len(shape) < 7 or len(shape) % 2 == 0:
                        raise ValueError(f"a floor shape of {len(shape)} numbers")
                    rs.floor_shapes[tuple(float(v) for v in shape)] += int(n)
                share = [float(v) for v in rd.get("share_sums", (0.0, 0.0, 0.0))]
                if len(share) != 3 or not np.isfinite(share).all() or share[0] < 0:
                    raise ValueError(f"share_sums {share}: not [rooms, sum, sum of squares]")
                rs.share_sums = share
                for a, deps in rd.get("sup_dep", {}).items():
                    rs.sup_dep[a] = Counter({k: int(v) for k, v in deps.items()})
                out.room_types[rtype] = rs
            for d, pa in doc.get("wall_anchor", {}).items():
                out.wall_anchor[d] = {a: [float(v) for v in acc][:3] for a, acc in pa.items()}
            for d, pa in doc.get("func_geometry", {}).items():
                out.func_geometry[d] = {a: [float(v) for v in acc][:FUNC_SUMS]
                                        for a, acc in pa.items()}  # fmt: skip
                if any(len(acc) < FUNC_SUMS - 1 for acc in out.func_geometry[d].values()):
                    raise ValueError(f"func_geometry of {d}: {FUNC_SUMS} sums per anchor expected")
            exact = (("sup_geometry", out.sup_geometry, (SUP_SUMS - 1, SUP_SUMS)),
                     ("mount_height", out.mount_height, (MOUNT_SUMS,)))  # fmt: skip
            for name, table, lengths in exact:
                for d, pa in doc.get(name, {}).items():
                    table[d] = {a: [float(v) for v in acc] for a, acc in pa.items()}
                    if any(len(acc) not in lengths for acc in table[d].values()):
                        raise ValueError(f"{name} of {d}: {lengths[-1]} sums per support expected")
            for sup, pa in doc.get("func_present", {}).items():
                out.func_present[sup] = {
                    a: Counter({k: int(v) for k, v in d.items()}) for a, d in pa.items()
                }
            for cat, acc in doc.get("same_model", {}).items():
                n, same = (int(v) for v in acc)
                if not 0 <= same <= n:
                    raise ValueError(f"same_model of {cat}: {same} of {n} rooms")
                out.same_model[cat] = [n, same]
            top = doc.get("on_top")
            out.on_top = None if top is None else Counter({k: int(v) for k, v in top.items()})
            gaps = doc.get("wall_gaps")
            out.wall_gaps = None
            if gaps is not None:
                pairs, close = (int(v) for v in gaps)
                if not 0 <= close <= pairs:
                    raise ValueError(f"wall_gaps: {close} close of {pairs} pairs")
                out.wall_gaps = [pairs, close]
            overlaps = doc.get("floor_overlaps")
            out.floor_overlaps = None
            if overlaps is not None:
                out.floor_overlaps = Counter({str(k): int(v) for k, v in overlaps.items()})
                if any(v < 0 for v in out.floor_overlaps.values()):
                    raise ValueError("floor_overlaps: a negative count")
            askew = doc.get("askew")
            out.askew = None
            if askew is not None:
                out.askew = {str(c): [int(v) for v in b] for c, b in askew.items()}
                for cat, bins in out.askew.items():
                    if len(bins) != len(ASKEW_BINS_DEG) or min(bins) < 0:
                        raise ValueError(f"askew of {cat}: {len(ASKEW_BINS_DEG)} counts expected")
            isolated = doc.get("isolated")
            out.isolated = None
            if isolated is not None:
                out.isolated = {str(c): [int(v) for v in pair] for c, pair in isolated.items()}
                for cat, (alone, n) in out.isolated.items():
                    if not 0 <= alone <= n:
                        raise ValueError(f"isolated of {cat}: {alone} alone of {n}")
        except (KeyError, TypeError, ValueError, AttributeError) as e:
            raise UserError(f"{where}: malformed statistics ({type(e).__name__}: {e})") from None
        return out

    @classmethod
    def from_json(cls, text: str, where: str = "stats") -> HierarchyStats:
        """:meth:`from_dict` of a JSON text (at most 64 levels deep, numbers finite)."""
        from pair2scene.io.jsondoc import parse_json

        return cls.from_dict(parse_json(text, where), where)

    @classmethod
    def from_file(cls, path: str | Path) -> HierarchyStats:
        """The statistics in a ``stats.json`` (``--stats``): read by
        :func:`~pair2scene.io.jsondoc.read_json_file` (at most
        :data:`~pair2scene.io.jsondoc.MAX_STATS_BYTES`, 256 MiB; UTF-8; 64 levels deep;
        finite numbers), then :meth:`from_dict`; every problem is one UserError."""
        from pair2scene.io.jsondoc import MAX_STATS_BYTES, read_json_file

        doc = read_json_file(path, "statistics", MAX_STATS_BYTES)
        return cls.from_dict(doc, str(path))

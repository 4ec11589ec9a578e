"""Text-guided hierarchies: what the text names is always present, the rest is statistics.

:func:`hierarchy_from_spec` turns a parsed description (:class:`~.text.TextSpec`, from the
offline parser) into a :class:`~.tree.Hierarchy`:

1. the room type is the one the text names, else the one whose training rooms hold the
   named furniture best, else ``other``;
2. every mention becomes ``count`` nodes (``each``: per instance of its anchor, otherwise
   spread over the anchor's instances in turn); supports and functional anchors follow the
   text's relations; an object the text puts nowhere stands on the floor if its category
   mostly does, else on a named or template object that the statistics say holds it
   (adding its most common holder when none is there); one whose name says what it
   stands at ("nightstands", "bar stools": :data:`~.text.IMPLIED_ANCHORS`) and that the
   text relates to nothing stands at the room's object of that category, and so does one
   named with an object of a category its own took as anchor in the training rooms ("a
   desk and a chair": the chair at the desk; with a dining table named too, at the
   table, the pair made most often); one the text
   wants mid-room ("a kitchen island", "in the middle of the room") stands clear of the
   walls (:attr:`~.tree.Hierarchy.mid_room`), an island besides the counters the
   statistics give the room; what the text stands face to face ("two sofas facing each
   other") faces its anchor from in front of it (:attr:`~.tree.Hierarchy.facing`);
3. walls: a mention the text hangs on a wall (:attr:`~.text.TextSpec.on_wall`: "a TV on
   the wall") and a wall object (painting, mirror, curtains, blinds, wall lamp) the text
   puts on nothing rest on ``wall`` (placement picks which). The text's anchor, or the
   floor-standing object under it, is its functional anchor ("a painting above the
   sofa": above or over it, it hangs over that floor object, :attr:`~.tree.Hierarchy.over`;
   "a TV on the wall opposite the sofa": opposite, across from or facing it, it hangs
   across the room where that object faces it, :attr:`~.tree.Hierarchy.across`);
   without one it has none ("a mirror on the wall"). Curtains and blinds never
   have one: placement hangs each at a window and gives the room a window for each. A
   floor object the text places relative to a wall object ("a sofa facing the TV on the
   wall") stands on the floor and becomes the wall object's anchor instead. A note names
   every wall object the text asked for;
4. the room is completed from the statistics: the furniture and wall objects of a
   training template of that room type (one holding the type's key furniture, a bed for a
   bedroom) that the text does not name, then the expansion of :mod:`.synthesis` up to the
   drawn object count (``fit``) or ``max_objects`` (``beyond``). Categories the text names
   are never added by the statistics: "two lamps" stays two, "a painting" one painting;
   nor are those the text asks for none of (:attr:`~.text.TextSpec.excluded`: "no desk",
   "0 beds": a bedroom without a bed).

A text's hierarchy has at most :data:`~.synthesis.MAX_OBJECTS_LIMIT` objects: a phrase
asks for at most :data:`MAX_COUNT`, and the objects past the limit are not added, with a
note naming the phrase (as are the text's own notes: a description cut at
:data:`~.text.MAX_TEXT_CHARS`).
"""

from __future__ import annotations

from collections import Counter
from dataclasses import replace

import numpy as np

from pair2scene.categories import BY_NAME, WINDOW_DRESSINGS, SuperCategory
from pair2scene.curation.stats import HierarchyStats, draw_counted, split_member
from pair2scene.curation.support import HANGER_CATEGORIES
from pair2scene.hierarchy.synthesis import (
    DEFAULT_BEYOND_OBJECTS,
    MAX_OBJECTS_LIMIT,
    Statistics,
    SynthesisConfig,
    add_floor_furniture,
    anchor_depths,
    expand,
    extra_furniture,
    load_stats,
    offered_once,
)
from pair2scene.hierarchy.text import (
    MOUNTABLE,
    WALL_OBJECTS,
    Mention,
    TextSpec,
    implied_anchor,
    named_mid_room,
)
from pair2scene.hierarchy.tree import Hierarchy, HierarchyError, Node
from pair2scene.scene.model import FLOOR, WALL, is_root, on_wall

OTHER_ROOM = "other"
MAX_COUNT = 100
"""Objects one phrase may ask for ("1000 books" gives 100, with a note)."""


def infer_room_type(spec: TextSpec, st: Statistics) -> str:
    """The named room type, else the type whose templates hold the named categories most
    often (summed over categories), else ``other``."""
    if spec.room_type:
        return spec.room_type
    named = {m.category for m in spec.mentions}
    best, best_score = OTHER_ROOM, 0.0
    for rtype, rs in sorted(st.stats.room_types.items()):
        hist = rs.furniture_counts()  # a wall object's members are "<category>@wall"
        score = sum(
            1.0 - hist[c].get(0, 0) / max(rs.rooms, 1)
            for c in sorted(hist)
            if split_member(c)[0] in named
        )
        if score > best_score:
            best, best_score = rtype, score
    return best


def key_furniture(rs) -> str | None:
    """The furniture category most rooms of a type hold (bed, sofa, ...; never a wall
    object or a small object on the floor)."""
    hist = {c: n for c, n in rs.furniture_counts().items()
            if not split_member(c)[1] and _is_furniture(c)}  # fmt: skip
    if not hist:
        return None
    return max(sorted(hist), key=lambda c: rs.rooms - hist[c].get(0, 0))


def _order(spec: TextSpec, st: Statistics) -> list:
    """Mentions with every anchor before its dependents; a cycle is a HierarchyError. The
    text's relations first, then the statistics' (:func:`anchor_depths`): in "two chairs
    and a dining table" the table is added first, so the chairs can take it as their
    anchor; else in the text's order."""
    anchors: dict[str, set[str]] = {m.ref: set() for m in spec.mentions}
    for r in spec.relations:
        anchors[r.dependent].add(r.anchor)
    by_ref = {m.ref: m for m in spec.mentions}
    out, done, visiting = [], set(), set()

    def visit(ref: str) -> None:
        if ref in done:
            return
        if ref in visiting:
            raise HierarchyError(f"the text's relations form a cycle at {by_ref[ref].phrase!r}")
        visiting.add(ref)
        for a in sorted(anchors[ref]):
            visit(a)
        visiting.discard(ref)
        done.add(ref)
        out.append(by_ref[ref])

    depth = anchor_depths([m.category for m in spec.mentions], st)
    for m in sorted(spec.mentions, key=lambda m: depth[m.category]):
        visit(m.ref)
    return out


def hierarchy_from_spec(
    spec: TextSpec, stats: HierarchyStats | None = None, config: SynthesisConfig | None = None
) -> Hierarchy:
    """The hierarchy of a parsed description (see the module docstring)."""
    config = config or SynthesisConfig()
    st = Statistics(load_stats() if stats is None else stats)
    rng = np.random.default_rng(config.seed)
    room_type = infer_room_type(spec, st)
    rs = st.stats.room_types.get(room_type)
    if rs is None:  # a composed type (a study): its view of the statistics, its rooms
        from pair2scene.hierarchy.room_types import composable

        if room_type in composable(st.stats):
            st, rs = Statistics.for_room(st.stats, room_type)
    else:  # what rests on what, the room type's way
        st = Statistics(st.stats, rs)
    h = Hierarchy(room_type)
    h.notes.extend(spec.notes)
    if spec.unparsed:
        h.notes.append("not understood: " + ", ".join(spec.unparsed))
    support_of = {r.dependent: r for r in spec.relations if r.kind == "support"}
    functional_of = {r.dependent: r for r in spec.relations if r.kind == "functional"}
    instances: dict[str, list[Node]] = {}
    # an island is a counter besides the room's: it leaves the statistics their counters
    named = frozenset(m.category for m in spec.mentions if not named_mid_room(m.phrase))
    avoid = named | frozenset(spec.excluded)  # what the statistics never add
    hung = frozenset(spec.on_wall)
    mid_room = frozenset(spec.mid_room)
    facing = frozenset(spec.facing)

    if rs is not None:  # the room's furniture first: unanchored named objects can use it
        key = key_furniture(rs)
        with_key = Counter({k: v for k, v in rs.layouts.items() if key in k}) or rs.layouts
        template = [c for c in draw_counted(with_key, rng) if split_member(c)[0] not in avoid]
        if config.max_objects is not None:
            asked = sum(min(m.count, MAX_COUNT) for m in spec.mentions)
            template = template[: max(0, config.max_objects - asked)]
        template = template[:MAX_OBJECTS_LIMIT]  # (statistics of your own: any template)
        add_floor_furniture(h, template, st, rng)

    for m in _order(spec, st):
        if m.count > MAX_COUNT:
            h.notes.append(f"{m.phrase!r}: count capped at {MAX_COUNT}")
            m = replace(m, count=MAX_COUNT)
        sup_rel, func_rel = support_of.get(m.ref), functional_of.get(m.ref)
        nodes: list[Node] = []
        wall = m.ref in hung or (sup_rel is None and m.category in WALL_OBJECTS | HANGER_CATEGORIES)
        if wall:
            nodes = _hang(h, m, func_rel, instances)
            sup_rel = None
        elif sup_rel is not None:
            anchors = instances[sup_rel.anchor]
            n = _room_for(h, m, m.count * len(anchors) if sup_rel.each else m.count, anchors)
            for i in range(n):
                nodes.append(h.add(m.category, anchors[i % len(anchors)].id))
        elif func_rel is not None:
            anchors = instances[func_rel.anchor]
            n = _room_for(h, m, m.count * len(anchors) if func_rel.each else m.count, anchors)
            on_floor = m.category in st.floor_standing or _is_furniture(m.category)
            for i in range(n):
                a = anchors[i % len(anchors)]
                if on_floor:  # a sofa facing a tv on a stand faces the stand, on the floor
                    a = _root_ancestor(h, a)
                if on_wall(h.support[a.id]) and (on_floor or m.category not in MOUNTABLE):
                    nodes.append(_beside_wall_object(h, st, m.category, a, on_floor, rng,
                                                     func_rel.across))  # fmt: skip
                    continue
                nodes.append(h.add(m.category, h.support[a.id], a.id))
                if on_wall(h.support[a.id]):  # "a TV beside the painting" hangs beside it
                    h.notes.append(f"on a wall: {nodes[-1].id} by {a.id}")
        else:
            implied = implied_anchor(m.phrase)  # the room's bed for "two nightstands"
            named_ids = {n.id for ns in instances.values() for n in ns}  # earlier mentions'
            for k in range(_room_for(h, m, m.count)):
                if len(h) >= MAX_OBJECTS_LIMIT:  # (a holder added for the object took it)
                    h.notes.append(f"{m.phrase!r}: not all added, {MAX_OBJECTS_LIMIT} objects")
                    break
                support = _default_support(h, st, m.category, rng, avoid)
                siblings = [n for n in h.children(support) if n.id not in h.functional]
                on = h.by_id()[support].category if support != FLOOR else FLOOR
                at = [n for n in siblings if n.category == implied] or _named_anchors(
                    st, on, m.category, siblings, named_ids
                )
                func = (
                    at[k % len(at)] if at else st.functional_choice(on, m.category, siblings, rng)
                )
                nodes.append(h.add(m.category, support, None if func is None else func.id))
        if sup_rel is not None and func_rel is not None and instances[func_rel.anchor]:
            anchors = instances[func_rel.anchor]
            for i, node in enumerate(nodes):
                a = anchors[i % len(anchors)]
                if h.support[a.id] == h.support[node.id]:
                    h.functional[node.id] = a.id
                else:
                    h.notes.append(
                        f"{node.id}: dropped the functional anchor {a.id} (not on the same support)"
                    )
        instances[m.ref] = nodes
        if m.ref in mid_room:  # "a kitchen island": clear of every wall
            h.mid_room.update(n.id for n in nodes if h.support[n.id] == FLOOR)
        if m.ref in facing:  # "two sofas facing each other"
            _face(h, nodes, func_rel is None)

    if config.mode == "beyond":
        target = config.max_objects or DEFAULT_BEYOND_OBJECTS
        if rs is not None:
            extra = extra_furniture(st, rs, target, [n.category for n in h.nodes], rng)
            extra = [c for c in extra if c not in avoid][: max(0, MAX_OBJECTS_LIMIT - len(h))]
            add_floor_furniture(h, extra, st, rng)
    elif rs is not None:
        target = int(draw_counted(rs.object_counts, rng))
    else:  # a room the statistics do not know: the named objects and their dependents
        target = len(h) + sum(
            round(sum(rate for _, rate in st.dependents(n.category))) for n in h.nodes
        )
    if config.max_objects is not None:
        target = min(target, config.max_objects)
    target = min(target, MAX_OBJECTS_LIMIT)
    expand(h, st, max(target, len(h)), rng, config.k, skip=avoid, once=offered_once(config.mode))
    return h.validate()


def _named_anchors(
    st: Statistics, support: str, category: str, siblings: list[Node], named: set[str]
) -> list[Node]:
    """The named objects among ``siblings`` of the category that ``category`` objects on
    ``support`` took as their anchor most often in the training rooms (a chair: the named
    dining table, else the named desk); empty when none is of a category they took. Named
    together, a chair and a desk are a desk and its chair: the statistics' chance alone
    (a chair beside a desk took it in 27 of 55) stood the chair elsewhere in half the
    rooms."""
    took = st.stats.func_dep.get(support, {})
    at = [n for n in siblings if n.id in named and took.get(n.category, {}).get(category)]
    if not at:
        return []
    best = max(at, key=lambda n: (took[n.category][category], n.category)).category
    return [n for n in at if n.category == best]


def _room_for(h: Hierarchy, m: Mention, n: int, anchors: list[Node] | None = None) -> int:
    """How many of the ``n`` objects of ``m`` are added: all while the hierarchy stays within
    :data:`MAX_OBJECTS_LIMIT` (else as many as fit, with a note); none without anchors (the
    anchor's own objects were past the limit)."""
    if anchors is not None and not anchors:
        return 0
    room = max(0, MAX_OBJECTS_LIMIT - len(h))
    if n > room:
        h.notes.append(
            f"{m.phrase!r}: {room} of {n} objects added, a scene has at most "
            f"{MAX_OBJECTS_LIMIT} (MAX_OBJECTS_LIMIT)"
        )
    return min(n, room)


def _face(h: Hierarchy, nodes: list[Node], each_other: bool) -> None:
    """Stand ``nodes`` of one mention face to face (:attr:`~.tree.Hierarchy.facing`): with
    ``each_other`` ("two sofas facing each other") the second and later face the first, else
    ("an armchair facing the sofa") each faces its functional anchor; floor objects with a
    floor anchor only."""
    if each_other and len(nodes) > 1 and h.support[nodes[0].id] == FLOOR:
        for node in nodes[1:]:
            if h.support[node.id] == FLOOR and node.id not in h.functional:
                h.functional[node.id] = nodes[0].id
    for node in nodes:
        anchor = h.functional.get(node.id)
        if h.support[node.id] == FLOOR and anchor is not None and h.support[anchor] == FLOOR:
            h.facing.add(node.id)


def _is_furniture(category: str) -> bool:
    cat = BY_NAME.get(category)
    return cat is not None and cat.super in (SuperCategory.LARGE_FURNITURE, SuperCategory.FIXTURE)


def _root_ancestor(h: Hierarchy, node: Node) -> Node:
    """The node itself if it stands on the floor or hangs on a wall, else the node below it
    that does."""
    by_id = h.by_id()
    while not is_root(h.support[node.id]):
        node = by_id[h.support[node.id]]
    return node


def _hang(h: Hierarchy, m: Mention, func_rel, instances: dict[str, list[Node]]) -> list[Node]:
    """``m``'s nodes on ``wall``, each placed relative to the text's anchor (or the object
    on the floor or a wall under it), curtains and blinds relative to nothing. One the
    text put above its anchor (:attr:`Relation.over`) hangs over it, one it put opposite
    (:attr:`Relation.across`) across the room from it, when the anchor stands on the floor
    (:attr:`Hierarchy.over`, :attr:`Hierarchy.across`). A note says what hangs where."""
    anchors = [] if func_rel is None else instances[func_rel.anchor]
    window = m.category in WINDOW_DRESSINGS
    if window and anchors:
        h.notes.append(
            f"{m.phrase!r}: {m.category} hang at a window, not relative to {anchors[0].id}"
        )
        anchors = []
    n = _room_for(h, m, m.count * len(anchors) if anchors and func_rel.each else m.count)
    nodes = []
    for i in range(n):
        a = _root_ancestor(h, anchors[i % len(anchors)]) if anchors else None
        nodes.append(h.add(m.category, WALL, None if a is None else a.id))
        if func_rel is not None and a is not None and h.support[a.id] == FLOOR:
            if func_rel.over:
                h.over.add(nodes[-1].id)
            elif func_rel.across:
                h.across.add(nodes[-1].id)
    if not nodes:
        return nodes
    ids = ", ".join(node.id for node in nodes)
    where = "on walls" if len(nodes) > 1 else "on a wall"
    if window:
        h.notes.append(f"{where}: {ids}, at a window each")
    elif anchors:
        by = sorted({h.functional[node.id] for node in nodes})
        how = "by"
        for way, chosen in (("over", h.over), ("across from", h.across)):
            if all(node.id in chosen for node in nodes):
                how = way
        h.notes.append(f"{where}: {ids} {how} {', '.join(by)}")
    else:
        h.notes.append(f"{where}: {ids}")
    return nodes


def _beside_wall_object(
    h: Hierarchy, st: Statistics, category: str, wall_object: Node, on_floor: bool, rng,
    across: bool = False,
) -> Node:  # fmt: skip
    """A new ``category`` node the text places relative to a wall object: it stands on the
    floor (``on_floor``) or where its category rests; a floor object becomes the wall
    object's anchor when that has none, and with ``across`` (the text put it opposite or
    facing the wall object) the wall object hangs across the room from it ("a sofa facing
    the TV on the wall": the TV hangs where the sofa faces it); else the relation is
    dropped with a note."""
    support = FLOOR if on_floor else _default_support(h, st, category, rng)
    node = h.add(category, support)
    free = wall_object.id not in h.functional and wall_object.category not in WINDOW_DRESSINGS
    if support == FLOOR and free:
        h.functional[wall_object.id] = node.id
        if across:
            h.across.add(wall_object.id)
        how = "across from" if across else "relative to"
        h.notes.append(f"{wall_object.id} (on a wall) is placed {how} {node.id}")
    else:
        h.notes.append(
            f"{node.id}: dropped the functional anchor {wall_object.id} (it hangs on a wall)"
        )
    return node


def _default_support(
    h: Hierarchy, st: Statistics, category: str, rng, avoid: frozenset[str] = frozenset()
) -> str:
    """Where an object the text puts nowhere rests (see the module docstring); a holder is
    never of an ``avoid`` category (one the text asks for none of), nor added past
    :data:`MAX_OBJECTS_LIMIT`."""
    if category in st.floor_standing or category not in st.instances:
        return FLOOR
    rates = []
    for pooled in (False, True):  # the room type's rates; any room's for a stranger to it
        for node in h.nodes:
            rate = dict(st.dependents(node.category, pooled)).get(category, 0.0)
            if rate > 0:
                rates.append((node, rate))
        if rates:
            break
    if rates:
        w = np.array([r for _, r in rates])
        return rates[int(rng.choice(len(rates), p=w / w.sum()))][0].id
    holders = {a: deps[category] for a, deps in st.stats.sup_dep.items()
               if a != FLOOR and category in deps and a in st.floor_standing
               and a not in avoid}  # fmt: skip
    if not holders or len(h) + 2 > MAX_OBJECTS_LIMIT:
        return FLOOR
    holder = max(sorted(holders), key=holders.get)
    node = h.add(holder, FLOOR)
    h.notes.append(f"added {node.id} to hold the {category}")
    return node.id

"""Text-guided hierarchies: what the text names is always present, the rest is statistics.

:func:`hierarchy_from_spec` turns a parsed description (:class:`~.text.TextSpec`, from the
offline parser) into a :class:`~.tree.Hierarchy`:

1. the room type is the one the text names, else the one whose training rooms hold the
   named furniture best, else ``other``;
2. every mention becomes ``count`` nodes (``each``: per instance of its anchor, otherwise
   spread over the anchor's instances in turn); supports and functional anchors follow the
   text's relations; an object the text puts nowhere stands on the floor if its category
   mostly does, else on a named or template object that the statistics say holds it
   (adding its most common holder when none is there);
3. the room is completed from the statistics: the furniture of a training template of
   that room type (one holding the type's key furniture, a bed for a bedroom) that the
   text does not name, then the expansion of :mod:`.synthesis` up to the drawn object
   count (``fit``) or ``max_objects`` (``beyond``). Categories the text names are never
   added by the statistics: "two lamps" stays two.
"""

from __future__ import annotations

from collections import Counter
from dataclasses import replace

import numpy as np

from pair2scene.categories import BY_NAME, SuperCategory
from pair2scene.curation.stats import HierarchyStats, draw_counted
from pair2scene.hierarchy.synthesis import (
    DEFAULT_BEYOND_OBJECTS,
    Statistics,
    SynthesisConfig,
    add_floor_furniture,
    expand,
    extra_furniture,
    load_stats,
)
from pair2scene.hierarchy.text import TextSpec
from pair2scene.hierarchy.tree import Hierarchy, HierarchyError, Node
from pair2scene.scene.model import FLOOR

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
        hist = rs.furniture_counts()
        score = sum(1.0 - hist[c].get(0, 0) / max(rs.rooms, 1) for c in named if c in hist)
        if score > best_score:
            best, best_score = rtype, score
    return best


def key_furniture(rs) -> str | None:
    """The furniture category most rooms of a type hold (bed, sofa, ...)."""
    hist = rs.furniture_counts()
    if not hist:
        return None
    return max(sorted(hist), key=lambda c: rs.rooms - hist[c].get(0, 0))


def _order(spec: TextSpec) -> list:
    """Mentions with every anchor before its dependents; a cycle is a HierarchyError."""
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

    for m in spec.mentions:
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
    h = Hierarchy(room_type)
    if spec.unparsed:
        h.notes.append("not understood: " + ", ".join(spec.unparsed))
    support_of = {r.dependent: r for r in spec.relations if r.kind == "support"}
    functional_of = {r.dependent: r for r in spec.relations if r.kind == "functional"}
    instances: dict[str, list[Node]] = {}
    named = frozenset(m.category for m in spec.mentions)
    rs = st.stats.room_types.get(room_type)

    if rs is not None:  # the room's furniture first: unanchored named objects can use it
        key = key_furniture(rs)
        with_key = Counter({k: v for k, v in rs.layouts.items() if key in k}) or rs.layouts
        template = [c for c in draw_counted(with_key, rng) if c not in named]
        if config.max_objects is not None:
            asked = sum(min(m.count, MAX_COUNT) for m in spec.mentions)
            template = template[: max(0, config.max_objects - asked)]
        add_floor_furniture(h, template, st, rng)

    for m in _order(spec):
        if m.count > MAX_COUNT:
            h.notes.append(f"{m.phrase!r}: count capped at {MAX_COUNT}")
            m = replace(m, count=MAX_COUNT)
        sup_rel, func_rel = support_of.get(m.ref), functional_of.get(m.ref)
        nodes: list[Node] = []
        if sup_rel is not None:
            anchors = instances[sup_rel.anchor]
            n = m.count * len(anchors) if sup_rel.each else m.count
            for i in range(n):
                nodes.append(h.add(m.category, anchors[i % len(anchors)].id))
        elif func_rel is not None:
            anchors = instances[func_rel.anchor]
            n = m.count * len(anchors) if func_rel.each else m.count
            on_floor = m.category in st.floor_standing or _is_furniture(m.category)
            for i in range(n):
                a = anchors[i % len(anchors)]
                if on_floor:  # a sofa facing a tv on a stand faces the stand, on the floor
                    a = _floor_ancestor(h, a)
                nodes.append(h.add(m.category, h.support[a.id], a.id))
        else:
            for _ in range(m.count):
                support = _default_support(h, st, m.category, rng)
                siblings = [n for n in h.children(support) if n.id not in h.functional]
                func = st.functional_choice(
                    h.by_id()[support].category if support != FLOOR else FLOOR,
                    m.category, siblings, rng,
                )  # fmt: skip
                nodes.append(h.add(m.category, support, None if func is None else func.id))
        if sup_rel is not None and func_rel is not None:
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

    if config.mode == "beyond":
        target = config.max_objects or DEFAULT_BEYOND_OBJECTS
        if rs is not None:
            extra = extra_furniture(st, rs, target, [n.category for n in h.nodes], rng)
            add_floor_furniture(h, [c for c in extra if c not in named], st, rng)
    elif rs is not None:
        target = int(draw_counted(rs.object_counts, rng))
    else:  # a room the statistics do not know: the named objects and their dependents
        target = len(h) + sum(
            round(sum(rate for _, rate in st.dependents(n.category))) for n in h.nodes
        )
    if config.max_objects is not None:
        target = min(target, config.max_objects)
    expand(h, st, max(target, len(h)), rng, config.k, skip=named)
    return h.validate()


def _is_furniture(category: str) -> bool:
    cat = BY_NAME.get(category)
    return cat is not None and cat.super in (SuperCategory.LARGE_FURNITURE, SuperCategory.FIXTURE)


def _floor_ancestor(h: Hierarchy, node: Node) -> Node:
    """The node itself if it stands on the floor, else the floor-standing node below it."""
    by_id = h.by_id()
    while h.support[node.id] != FLOOR:
        node = by_id[h.support[node.id]]
    return node


def _default_support(h: Hierarchy, st: Statistics, category: str, rng) -> str:
    """Where an object the text puts nowhere rests (see the module docstring)."""
    if category in st.floor_standing or category not in st.instances:
        return FLOOR
    rates = []
    for node in h.nodes:
        rate = dict(st.dependents(node.category)).get(category, 0.0)
        if rate > 0:
            rates.append((node, rate))
    if rates:
        w = np.array([r for _, r in rates])
        return rates[int(rng.choice(len(rates), p=w / w.sum()))][0].id
    holders = {a: deps[category] for a, deps in st.stats.sup_dep.items()
               if a != FLOOR and category in deps and a in st.floor_standing}  # fmt: skip
    if not holders:
        return FLOOR
    holder = max(sorted(holders), key=holders.get)
    node = h.add(holder, FLOOR)
    h.notes.append(f"added {node.id} to hold the {category}")
    return node.id

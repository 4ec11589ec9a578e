"""Scene hierarchies: a support tree rooted at the floor and one functional tree per support.

A :class:`Hierarchy` is the structure of a scene before any placement: which objects
(:class:`Node`), what each rests on (``support``: the floor or another node) and what
it is placed relative to (``functional``: an object on the same support, optional).

- The **support tree** has the floor as its root and an edge support -> dependent for
  every node. Wall-mounted objects (a painting, a mirror, curtains) rest on a wall: ``wall``
  (placement picks which) or ``wall:<i>`` (the room's wall i); walls are roots beside the
  floor, after it in every order.
- A **functional tree** exists for every support node (the floor included) that has
  dependents. It is rooted at that support; a dependent with a functional anchor hangs
  under its anchor, one without hangs under the root. Every node of it rests on its
  root. A wall-mounted dependent whose edge says ``"over": true`` hangs over its anchor,
  a floor object, within its width (:attr:`Hierarchy.over`: "a painting above the sofa").
  A floor dependent whose edge says ``"mid_room": true`` stands clear of every wall
  (:attr:`Hierarchy.mid_room`: "a kitchen island"); one whose edge says ``"facing": true``
  faces its anchor from in front of it (:attr:`Hierarchy.facing`: "two sofas facing each
  other").
- The **sequence** (:meth:`Hierarchy.sequence`) orders the relation tuples for
  placement: breadth-first over the support tree, and at each support a depth-first walk
  of its functional tree. Every anchor (support or functional) comes before its
  dependents.

:meth:`Hierarchy.validate` checks everything a placement relies on and raises a
:class:`HierarchyError` (a one-line :class:`UserError`) naming the problem: unknown or
structural categories, duplicate ids, missing or cyclic supports, chains of more than
:data:`MAX_SUPPORT_DEPTH` objects standing on each other, functional anchors on another
support, cyclic functional anchors. Validation and the orders are linear in the number of
nodes.

A hierarchy file (:meth:`Hierarchy.from_dict`, ``pair2scene hierarchy --file``) may hold
at most :data:`MAX_NODES` nodes, ids, categories and the room type of at most
:data:`MAX_ID_CHARS` characters; the file itself is read by
:func:`pair2scene.io.jsondoc.read_json_file` (at most 64 MiB, 64 levels of nesting).
"""

from __future__ import annotations

from collections import deque
from collections.abc import Iterable, Mapping
from dataclasses import dataclass, field

from pair2scene.categories import BY_NAME, SuperCategory
from pair2scene.errors import UserError
from pair2scene.scene.model import FLOOR, WALL, is_root, on_wall, wall_index

HIERARCHY_FORMAT = "pair2scene.hierarchy"
HIERARCHY_VERSION = 1
MAX_NODES = 2000
"""Nodes a hierarchy file may hold (four times the most objects a scene may be asked for)."""
MAX_ID_CHARS = 200
"""Characters a node id, a category or a room type of a hierarchy file may have."""
MAX_SUPPORT_DEPTH = 32
"""Objects that may stand on each other in one chain (floor -> table -> tray -> cup is 3)."""
NOT_OBJECTS = (SuperCategory.STRUCTURE, SuperCategory.PART)
"""Super-categories that are never nodes: the room itself, and parts of furniture (the
generator builds drawers and shelves with their owner)."""


class HierarchyError(UserError):
    """An invalid hierarchy (from a file, an LLM or a user): one line naming the problem."""


@dataclass(frozen=True)
class Node:
    """One object of a hierarchy."""

    id: str
    """Unique within the hierarchy; never ``floor``."""
    category: str
    """Canonical category (:mod:`pair2scene.categories`)."""


@dataclass(frozen=True)
class SequenceItem:
    """One relation tuple of the placement order."""

    dependent: Node
    support: str
    """``floor``, a wall (``wall``, ``wall:<i>``) or a node id placed earlier in the
    sequence."""
    functional: str | None
    """A node id placed earlier, resting on the same support (a wall-mounted object's may
    stand on the floor); None without one."""


@dataclass(frozen=True)
class FunctionalTree:
    """The objects resting on one support, as a tree rooted at that support."""

    support: str
    """The root: ``floor`` or a node id."""
    edges: tuple[tuple[str, str], ...]
    """(anchor, dependent) pairs; the anchor is the root for dependents without a
    functional anchor."""


@dataclass
class Hierarchy:
    """Nodes, their supports and functional anchors (see the module docstring)."""

    room_type: str
    nodes: list[Node] = field(default_factory=list)
    support: dict[str, str] = field(default_factory=dict)
    """node id -> ``floor``, a wall (``wall``: placement picks it; ``wall:<i>``) or the id
    of the node it rests on."""
    functional: dict[str, str] = field(default_factory=dict)
    """node id -> the id of its functional anchor (only nodes that have one)."""
    notes: list[str] = field(default_factory=list)
    """What a builder wants the user to know (unparsed words, completions, caps)."""
    over: set[str] = field(default_factory=set)
    """Wall-mounted nodes that hang over their functional anchor, a floor object, within
    its width ("a painting above the sofa"); placement hangs them on the wall behind it.
    Without this or :attr:`across`, a wall object relates to its anchor as the training
    rooms' pairs did (over it or across the room, each with the pair's share)."""
    across: set[str] = field(default_factory=set)
    """Wall-mounted nodes that hang across the room from their functional anchor, a floor
    object, where it faces them ("a TV on the wall opposite the sofa"); placement tries
    only the walls it faces first."""
    mid_room: set[str] = field(default_factory=set)
    """Floor nodes that stand clear of every wall ("a kitchen island", "a table in the
    middle of the room"); placement draws no wall for them and rejects a candidate that
    comes near one (``at_wall``). Without this, the wall rules decide, as for any floor
    object."""
    facing: set[str] = field(default_factory=set)
    """Floor nodes that face their functional anchor, a floor object, from in front of it
    ("two sofas facing each other"); placement rejects a candidate that does not face the
    anchor or stands off its front (``faces_away``, ``not_in_front``), nearer than
    :data:`~pair2scene.assembly.place.FACING_MIN_GAP_M` to it or farther than
    :data:`~pair2scene.assembly.place.FACING_GAP_M`. Without this, the training
    rooms' pairs decide how a floor object stands at its anchor."""

    # -- building -------------------------------------------------------------------------

    def add(self, category: str, support: str, functional: str | None = None) -> Node:
        """Add a node of ``category`` resting on ``support``; its id is ``<category>_<n>``."""
        n = sum(1 for node in self.nodes if node.category == category)
        node_id = f"{category}_{n}"
        while node_id in self.support:
            n += 1
            node_id = f"{category}_{n}"
        node = Node(node_id, category)
        self.nodes.append(node)
        self.support[node_id] = support
        if functional is not None:
            self.functional[node_id] = functional
        return node

    def by_id(self) -> dict[str, Node]:
        return {n.id: n for n in self.nodes}

    def children(self, parent: str) -> list[Node]:
        """Nodes resting on ``parent``, in insertion order."""
        return [n for n in self.nodes if self.support.get(n.id) == parent]

    def category_counts(self) -> dict[str, int]:
        out: dict[str, int] = {}
        for n in self.nodes:
            out[n.category] = out.get(n.category, 0) + 1
        return dict(sorted(out.items()))

    def __len__(self) -> int:
        return len(self.nodes)

    # -- validation -----------------------------------------------------------------------

    def validate(self) -> Hierarchy:
        """Raise :class:`HierarchyError` on the first problem; return self when valid."""
        seen: set[str] = set()
        for n in self.nodes:
            if not isinstance(n.id, str) or not n.id:
                raise HierarchyError("a node has an empty id")
            if n.id == FLOOR:
                raise HierarchyError("'floor' is the root of the support tree, not a node id")
            if n.id in seen:
                raise HierarchyError(f"node id {n.id!r} appears twice")
            seen.add(n.id)
            cat = BY_NAME.get(n.category)
            if cat is None:
                raise HierarchyError(f"node {n.id!r}: unknown category {n.category!r}")
            if cat.super in NOT_OBJECTS:
                raise HierarchyError(
                    f"node {n.id!r}: {n.category!r} is {cat.super.value}, not an object"
                )
        for node_id in self.support:
            if node_id not in seen:
                raise HierarchyError(f"support given for {node_id!r}, which is not a node")
        for node_id in self.functional:
            if node_id not in seen:
                raise HierarchyError(f"functional anchor given for {node_id!r}, not a node")
        for n in self.nodes:
            parent = self.support.get(n.id)
            if parent is None:
                raise HierarchyError(f"node {n.id!r} has no support")
            if parent.startswith(WALL) and not on_wall(parent) and parent not in seen:
                raise HierarchyError(
                    f"node {n.id!r} rests on {parent!r}: a wall is 'wall' or 'wall:<index>'"
                )
            if not is_root(parent) and parent not in seen:
                raise HierarchyError(f"node {n.id!r} rests on {parent!r}, which is not a node")
            if parent == n.id:
                raise HierarchyError(f"node {n.id!r} rests on itself")
        depth: dict[str, int] = {}  # node id -> objects in its chain of supports
        for n in self.nodes:  # grounded: every chain of supports reaches the floor or a wall
            chain, at = {n.id: None}, self.support[n.id]
            while not is_root(at) and at not in depth:
                if at in chain:
                    ids = list(chain)
                    cycle = " -> ".join([*ids[ids.index(at) :], at])
                    raise HierarchyError(f"support cycle: {cycle} (never reaches the floor)")
                chain[at] = None
                at = self.support[at]
            base = 0 if is_root(at) else depth[at]
            for k, node_id in enumerate(reversed(chain)):
                depth[node_id] = base + k + 1
            if depth[n.id] > MAX_SUPPORT_DEPTH:
                raise HierarchyError(
                    f"node {n.id!r} tops a stack of {depth[n.id]} objects resting on each "
                    f"other: at most {MAX_SUPPORT_DEPTH} may"
                )
        for node_id, anchor in self.functional.items():
            if anchor == node_id:
                raise HierarchyError(f"node {node_id!r} is its own functional anchor")
            if anchor not in seen:
                raise HierarchyError(
                    f"node {node_id!r}: functional anchor {anchor!r} is not a node"
                )
            mounted = on_wall(self.support[node_id]) and self.support[anchor] == FLOOR
            if self.support[anchor] != self.support[node_id] and not mounted:
                raise HierarchyError(
                    f"node {node_id!r} rests on {self.support[node_id]!r} but its functional "
                    f"anchor {anchor!r} rests on {self.support[anchor]!r}: a functional "
                    "anchor must share the support"
                )
        acyclic: set[str] = set()  # ids whose chain of functional anchors ends
        for node_id in self.functional:
            chain, at = {node_id: None}, self.functional[node_id]
            while at in self.functional and at not in acyclic:
                if at in chain:
                    ids = list(chain)
                    cycle = " -> ".join([*ids[ids.index(at) :], at])
                    raise HierarchyError(f"functional cycle: {cycle}")
                chain[at] = None
                at = self.functional[at]
            acyclic.update(chain)
        for way, hung in (("over", self.over), ("across from", self.across)):
            for node_id in sorted(hung):
                anchor = self.functional.get(node_id)
                if node_id not in seen or not on_wall(self.support[node_id]) or anchor is None:
                    raise HierarchyError(
                        f"{node_id!r} hangs {way} its anchor, so it must be a node on a wall "
                        "with a functional anchor"
                    )
                if self.support[anchor] != FLOOR:
                    raise HierarchyError(
                        f"{node_id!r} hangs {way} {anchor!r}, which must stand on the floor"
                    )
        for node_id in sorted(self.mid_room):
            if self.support.get(node_id) != FLOOR:
                raise HierarchyError(
                    f"{node_id!r} stands mid-room, so it must be a node on the floor"
                )
        for node_id in sorted(self.facing):
            anchor = self.functional.get(node_id)
            if self.support.get(node_id) != FLOOR or anchor is None:
                raise HierarchyError(
                    f"{node_id!r} faces its anchor, so it must be a node on the floor with "
                    "a functional anchor"
                )
        both = sorted(self.over & self.across)
        if both:
            raise HierarchyError(f"{both[0]!r} cannot hang both over and across from its anchor")
        return self

    # -- trees and order ------------------------------------------------------------------

    def roots(self) -> list[str]:
        """The roots of the support tree: the floor, then every wall a node rests on
        (``wall`` before ``wall:<i>`` by index)."""
        walls = {s for s in self.support.values() if on_wall(s)}
        return [FLOOR, *sorted(walls, key=lambda w: (wall_index(w) or -1, w))]

    def _children_map(self) -> dict[str, list[Node]]:
        """parent id -> the nodes resting on it, in insertion order (:meth:`children` for
        every parent at once)."""
        out: dict[str, list[Node]] = {}
        for n in self.nodes:
            parent = self.support.get(n.id)
            if parent is not None:
                out.setdefault(parent, []).append(n)
        return out

    def support_edges(self) -> list[tuple[str, str]]:
        """(parent, child) edges of the support tree, breadth-first from the roots."""
        below = self._children_map()
        out, queue = [], deque(self.roots())
        while queue:
            parent = queue.popleft()
            for child in below.get(parent, ()):
                out.append((parent, child.id))
                queue.append(child.id)
        return out

    def functional_tree(self, support: str) -> FunctionalTree:
        """The functional tree rooted at ``support`` (see the module docstring)."""
        return self._functional_tree(support, self.children(support))

    def _functional_tree(self, support: str, children: Iterable[Node]) -> FunctionalTree:
        edges = tuple((self.functional.get(n.id, support), n.id) for n in children)
        return FunctionalTree(support, edges)

    def functional_trees(self) -> list[FunctionalTree]:
        """One tree per support that has dependents, in breadth-first support order."""
        below = self._children_map()
        supports = [*self.roots(), *(child for _, child in self.support_edges())]
        return [self._functional_tree(s, below[s]) for s in supports if below.get(s)]

    def sequence(self) -> list[SequenceItem]:
        """The placement order: BFS over supports, DFS over each functional tree."""
        by_id = self.by_id()
        children = self._children_map()
        out: list[SequenceItem] = []
        queue = deque(self.roots())
        while queue:
            support = queue.popleft()
            tree = self._functional_tree(support, children.get(support, ()))
            below: dict[str, list[str]] = {}
            for anchor, dep in tree.edges:
                if self.support.get(anchor) != support:  # a floor anchor of a wall object
                    anchor = support
                below.setdefault(anchor, []).append(dep)
            stack = list(reversed(below.get(support, [])))
            while stack:
                node_id = stack.pop()
                out.append(SequenceItem(by_id[node_id], support, self.functional.get(node_id)))
                queue.append(node_id)
                stack.extend(reversed(below.get(node_id, [])))
        return out

    # -- JSON -----------------------------------------------------------------------------

    def edge_flags(self) -> tuple[tuple[str, set[str]], ...]:
        """The flags a functional edge of the JSON may carry (``"over": true``), each with
        the set of dependents it marks."""
        return (("over", self.over), ("across", self.across), ("mid_room", self.mid_room),
                ("facing", self.facing))  # fmt: skip

    def to_dict(self, **extra) -> dict:
        """The hierarchy as JSON types: nodes, support_tree, functional_trees, sequence."""
        cat = {n.id: n.category for n in self.nodes}
        cat[FLOOR] = FLOOR
        cat.update({w: WALL for w in self.roots()[1:]})

        def ref(node_id: str | None) -> dict | None:
            return None if node_id is None else {"id": node_id, "category": cat[node_id]}

        return {
            "format": HIERARCHY_FORMAT,
            "version": HIERARCHY_VERSION,
            "room_type": self.room_type,
            **extra,
            "objects": len(self.nodes),
            "category_counts": self.category_counts(),
            "nodes": [{"id": n.id, "category": n.category} for n in self.nodes],
            "support_tree": {
                "root": FLOOR,
                "edges": [{"parent": ref(p), "child": ref(c)} for p, c in self.support_edges()],
            },
            "functional_trees": [
                {
                    "support_anchor": ref(t.support),
                    "edges": [
                        {"anchor": ref(a), "dependent": ref(d)}
                        | {key: True for key, marked in self.edge_flags() if d in marked}
                        for a, d in t.edges
                    ],
                }
                for t in self.functional_trees()
            ],
            "sequence": [
                {
                    "dependent": ref(s.dependent.id),
                    "support": ref(s.support),
                    "functional_anchor": ref(s.functional),
                }
                for s in self.sequence()
            ],
            "notes": list(self.notes),
        }

    @classmethod
    def from_dict(cls, doc: Mapping, where: str = "hierarchy") -> Hierarchy:
        """Read :meth:`to_dict`'s ``nodes`` + ``support_tree`` + ``functional_trees`` (the
        sequence is derived, never read) and validate."""
        try:
            raw = doc["nodes"]
            edges = doc["support_tree"]["edges"]
            trees = doc.get("functional_trees", [])
            for name, items in (("nodes", raw), ("support_tree.edges", edges)):
                if not isinstance(items, list):
                    raise TypeError(f"{name} is not a list")
                if len(items) > MAX_NODES:
                    raise HierarchyError(
                        f"{where}: {len(items)} {name}, more than the {MAX_NODES} a hierarchy "
                        "may hold"
                    )
            if not isinstance(trees, list):
                raise TypeError("functional_trees is not a list")
            nodes = [Node(_text(n["id"]), _text(n["category"])) for n in raw]
            h = cls(_text(doc.get("room_type") or "other"), nodes)
            for e in edges:
                h.support[_text(_ref_id(e["child"]))] = _text(_ref_id(e["parent"]))
            functional = 0
            for t in trees:
                root = _text(_ref_id(t["support_anchor"]))
                functional += len(t["edges"])
                if functional > MAX_NODES:
                    raise HierarchyError(
                        f"{where}: more than {MAX_NODES} functional edges, the most a "
                        "hierarchy may hold"
                    )
                for e in t["edges"]:
                    anchor, dep = _text(_ref_id(e["anchor"])), _text(_ref_id(e["dependent"]))
                    if anchor != root:
                        h.functional[dep] = anchor
                    for key, marked in h.edge_flags():
                        flag = e.get(key, False)
                        if not isinstance(flag, bool):
                            raise TypeError(f"{key!r} of {dep!r} is not true or false")
                        if flag:
                            marked.add(dep)
        except (KeyError, TypeError, AttributeError, ValueError) as e:
            msg = f"{where}: malformed hierarchy ({type(e).__name__}: {_short(str(e))})"
            raise HierarchyError(msg) from None
        return h.validate()


def _ref_id(ref) -> str:
    return ref["id"] if isinstance(ref, Mapping) else ref


def _text(value) -> str:
    """An id, category or room type of a hierarchy file: a string (numbers are taken as
    their text) of at most :data:`MAX_ID_CHARS` characters."""
    if isinstance(value, bool) or not isinstance(value, (str, int, float)):
        raise TypeError(f"expected a string, got {type(value).__name__}")
    text = str(value)
    if len(text) > MAX_ID_CHARS:
        raise ValueError(f"{len(text)} characters, more than {MAX_ID_CHARS}: {_short(text)}")
    return text


def _short(text: str, most: int = 60) -> str:
    """``text`` on one line, cut to ``most`` characters."""
    text = repr(text)[1:-1]
    return text if len(text) <= most else text[: most - 3] + "..."


def object_categories() -> list[str]:
    """Every category a hierarchy may hold (not structure, not parts, not unknown)."""
    return [c.name for c in BY_NAME.values() if c.super not in NOT_OBJECTS]


def check_categories(names: Iterable[str]) -> None:
    """Raise HierarchyError for the first name that is not an object category."""
    for name in names:
        cat = BY_NAME.get(name)
        if cat is None or cat.super in NOT_OBJECTS:
            raise HierarchyError(f"unknown object category {name!r}")

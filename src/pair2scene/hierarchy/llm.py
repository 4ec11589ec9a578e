"""Text-guided hierarchies through an LLM (any OpenAI-compatible chat-completions endpoint).

The prompt follows the method's published structure: the model lists the objects, the
support tree as edges from ``"Floor"`` and the functional trees, each with its
``support_anchor`` and ``(anchor, dependent)`` edges. Wall-mounted objects (paintings,
mirrors, curtains, blinds, wall lamps, mounted TVs) rest on ``"Wall"`` (placement picks
which wall; ``wall:<i>`` names wall i, as in hierarchy files) and may take a Floor object
as their functional anchor (a painting above the bed); curtains and blinds take none
(placement hangs each at a window); an edge with ``"over": true`` hangs it over that
anchor (:attr:`Hierarchy.over`), one with ``"across": true`` across the room where that
anchor faces it (:attr:`Hierarchy.across`). The reply is checked twice: against a JSON schema (by
:class:`pair2scene.llm.LLMClient`) and as a hierarchy (:meth:`Hierarchy.validate`: known
categories, grounded, acyclic, functional anchors on the same support, a wall object's on
the floor). A reply that fails either gets one repair round, the problem quoted back to
the model; a second failure is a one-line :class:`HierarchyError`.
"""

from __future__ import annotations

import json

from pair2scene.categories import WINDOW_DRESSINGS, RoomType
from pair2scene.errors import UserError
from pair2scene.hierarchy.tree import Hierarchy, HierarchyError, Node, object_categories
from pair2scene.scene.model import FLOOR, WALL, on_wall

LLM_FLOOR = "Floor"
"""The floor's name in the prompt's trees (the method's)."""
LLM_WALL = "Wall"
"""A wall's name in the prompt's trees: the support of wall-mounted objects."""
WALL_EXAMPLES = "paintings, mirrors, curtains, blinds, wall lamps and wall-mounted TVs"
MAX_OBJECTS_IN_REPLY = 300
SCHEMA_NAME = "scene_hierarchy"
ROOM_TYPES = tuple(r.value for r in RoomType)


def reply_schema() -> dict:
    """JSON schema of a reply (the subset :func:`pair2scene.llm.validate_json` checks)."""
    ident = {"type": "string", "maxLength": 80}
    support = {
        **ident,
        "description": f"'{LLM_FLOOR}', '{LLM_WALL}' (wall-mounted objects) or an object id",
    }
    edge = {
        "type": "object",
        "properties": {"parent": support, "child": ident},
        "required": ["parent", "child"],
        "additionalProperties": False,
    }
    func_edge = {
        "type": "object",
        "properties": {
            "anchor": ident,
            "dependent": ident,
            "over": {
                "type": "boolean",
                "description": "a wall object hung right above its Floor anchor",
            },
            "across": {
                "type": "boolean",
                "description": "a wall object hung across the room, facing its Floor anchor",
            },
            "mid_room": {
                "type": "boolean",
                "description": "a Floor object standing clear of every wall (a kitchen island)",
            },
            "facing": {
                "type": "boolean",
                "description": "a Floor object facing its Floor anchor from in front of it",
            },
        },
        "required": ["anchor", "dependent"],
        "additionalProperties": False,
    }
    obj = {
        "type": "object",
        "properties": {"id": ident, "category": {"type": "string", "maxLength": 80}},
        "required": ["id", "category"],
        "additionalProperties": False,
    }
    tree = {
        "type": "object",
        "properties": {
            "support_anchor": support,
            "edges": {"type": "array", "items": func_edge, "maxItems": MAX_OBJECTS_IN_REPLY},
        },
        "required": ["support_anchor", "edges"],
        "additionalProperties": False,
    }
    return {
        "type": "object",
        "properties": {
            "room_type": {"type": "string", "enum": list(ROOM_TYPES)},
            "objects": {"type": "array", "items": obj, "maxItems": MAX_OBJECTS_IN_REPLY},
            "support_tree": {"type": "array", "items": edge, "maxItems": MAX_OBJECTS_IN_REPLY},
            "functional_trees": {"type": "array", "items": tree, "maxItems": MAX_OBJECTS_IN_REPLY},
        },
        "required": ["room_type", "objects", "support_tree", "functional_trees"],
        "additionalProperties": False,
    }


def messages(text: str, max_objects: int | None = None) -> list[dict]:
    """The chat messages asking for the hierarchy of ``text``."""
    cats = ", ".join(sorted(object_categories()))
    limit = f" Use at most {max_objects} objects." if max_objects else ""
    example = {
        "room_type": "office",
        "objects": [
            {"id": "desk_0", "category": "desk"},
            {"id": "chair_0", "category": "chair"},
            {"id": "laptop_0", "category": "laptop"},
            {"id": "painting_0", "category": "painting"},
            {"id": "curtains_0", "category": "curtains"},
        ],
        "support_tree": [
            {"parent": LLM_FLOOR, "child": "desk_0"},
            {"parent": LLM_FLOOR, "child": "chair_0"},
            {"parent": "desk_0", "child": "laptop_0"},
            {"parent": LLM_WALL, "child": "painting_0"},
            {"parent": LLM_WALL, "child": "curtains_0"},
        ],
        "functional_trees": [
            {"support_anchor": LLM_FLOOR, "edges": [{"anchor": "desk_0", "dependent": "chair_0"}]},
            {
                "support_anchor": LLM_WALL,
                "edges": [
                    {"anchor": "desk_0", "dependent": "painting_0", "over": True},
                    {"anchor": LLM_WALL, "dependent": "curtains_0"},
                ],
            },
        ],
    }
    system = (
        "You plan indoor scenes for a 3D scene generator. A scene is a support tree (what "
        "rests on what, rooted at the Floor; wall-mounted objects rest on the Wall) and, for "
        "every support with dependents, a functional tree (which object each dependent is "
        "placed relative to, among objects on the same support; an object on the Wall may be "
        "placed relative to an object on the Floor). Reply with one JSON object and nothing "
        "else."
    )
    user = (
        f"Describe this room as a scene hierarchy: {json.dumps(text)}\n\n"
        f"Rules:\n"
        f"- objects: every object once, id '<category>_<n>', category from: {cats}.\n"
        f"- support_tree: one edge per object, parent '{LLM_FLOOR}', '{LLM_WALL}' or an "
        "object id; furniture rests on the Floor, small objects on furniture, and "
        f"{WALL_EXAMPLES} hang on the Wall (parent '{LLM_WALL}'; the generator picks which "
        "wall). A TV on a TV stand or a table rests on it, not on the Wall.\n"
        "- functional_trees: one per support anchor that has dependents; an edge "
        "(anchor, dependent) when the dependent is placed relative to the anchor (a chair "
        "at a desk, a nightstand beside a bed); both must rest on that support_anchor, "
        f"except on the '{LLM_WALL}': a wall object's anchor is an object on the Floor (a "
        "painting above the bed, a mirror above the dresser, a TV on the wall opposite the "
        'sofa, a wall lamp beside the bed) or on the Wall; "over": true on the edge of one '
        'hung right above its Floor anchor (a painting above the bed), "across": true on '
        'one hung across the room facing it (a TV opposite the sofa); "mid_room": true on '
        "the edge of a Floor object standing clear of every wall (a kitchen island, a table "
        'in the middle of the room; the anchor may be the Floor); "facing": true on the '
        "edge of a Floor object facing its Floor anchor (two sofas facing each other: the "
        "second anchored to the first). Curtains and blinds "
        "hang at windows, one object per window (curtains on two windows: two curtains "
        "objects), placed relative to no object.\n"
        "- Include everything the description names, with its counts, and complete the "
        f"room with what such a room usually holds.{limit}\n"
        f"- room_type: one of {', '.join(ROOM_TYPES)}.\n\n"
        f"Example reply: {json.dumps(example)}"
    )
    return [{"role": "system", "content": system}, {"role": "user", "content": user}]


def hierarchy_from_reply(reply: dict) -> Hierarchy:
    """A validated hierarchy from a schema-valid reply; HierarchyError naming the problem."""
    objects = reply["objects"]
    h = Hierarchy(reply["room_type"], [Node(o["id"], o["category"]) for o in objects])
    names = {o["id"] for o in objects}
    category = {o["id"]: o["category"] for o in objects}

    def node_ref(name: str) -> str:
        low = name.strip().lower()
        if low == FLOOR:
            return FLOOR
        if low == WALL or low.startswith(WALL + ":"):
            if not on_wall(low):
                raise HierarchyError(
                    f"{name!r} is not a wall: a wall is '{LLM_WALL}' (or 'wall:<index>')"
                )
            return low
        if name not in names:
            raise HierarchyError(f"{name!r} is used in a tree but is not among the objects")
        return name

    for e in reply["support_tree"]:
        child = node_ref(e["child"])
        if _room_part(child):
            raise HierarchyError(f"the {child.capitalize()} cannot rest on anything")
        if child in h.support:
            raise HierarchyError(f"{child!r} has two supports in support_tree")
        h.support[child] = node_ref(e["parent"])
    for t in reply["functional_trees"]:
        root = node_ref(t["support_anchor"])
        where = f"functional tree of {t['support_anchor']!r}"
        for e in t["edges"]:
            anchor, dep = node_ref(e["anchor"]), node_ref(e["dependent"])
            if _room_part(dep):
                raise HierarchyError(f"the {dep.capitalize()} cannot be a functional dependent")
            if h.support.get(dep) != root:
                raise HierarchyError(f"{where}: {dep!r} does not rest on it")
            if e.get("mid_room", False):
                h.mid_room.add(dep)  # (validate: on the Floor)
            if anchor == root:
                continue
            if on_wall(root) and category[dep] in WINDOW_DRESSINGS:
                h.notes.append(
                    f"{dep}: dropped the functional anchor {anchor} ({category[dep]} hang at "
                    "a window)"
                )
                continue
            below = h.support.get(anchor)
            if on_wall(root) and below is not None and below not in (FLOOR, root):
                raise HierarchyError(
                    f"{where}: {dep!r} hangs on a wall, its anchor must stand on the "
                    f"{LLM_FLOOR} or hang on that wall, but {anchor!r} rests on {below!r}"
                )
            h.functional[dep] = anchor
            for key, marked in h.edge_flags():  # (validate checks where each may be)
                if key != "mid_room" and e.get(key, False):  # (mid_room: above, anchored or not)
                    marked.add(dep)
    return h.validate()


def _room_part(ref: str) -> bool:
    """Whether a tree reference is the floor or a wall (as :func:`hierarchy_from_reply`'s
    references come: ``floor``, ``wall``, ``wall:...``), not an object."""
    return ref in (FLOOR, WALL) or ref.startswith(WALL + ":")


def hierarchy_from_llm(client, text: str, max_objects: int | None = None) -> Hierarchy:
    """Ask ``client`` (:class:`pair2scene.llm.LLMClient`) for the hierarchy of ``text``;
    one repair round, then a HierarchyError."""
    from pair2scene.llm import LLMReplyError

    msgs = messages(text, max_objects)
    problem = ""
    for attempt in range(2):
        reply = None
        try:
            reply = client.complete_json(msgs, reply_schema(), SCHEMA_NAME)
            h = hierarchy_from_reply(reply)
            if max_objects is not None and len(h) > max_objects:
                raise HierarchyError(f"{len(h)} objects, more than the {max_objects} asked for")
            h.notes.append("hierarchy from the LLM" + (" (after one repair)" if attempt else ""))
            return h
        except (LLMReplyError, HierarchyError) as e:
            problem = str(e)
            previous = json.dumps(reply)[:20000] if reply is not None else "(not valid JSON)"
            msgs = [
                *msgs,
                {"role": "assistant", "content": previous},
                {"role": "user", "content": f"That reply is invalid: {problem}. "
                 "Reply again with the corrected JSON object only."},
            ]  # fmt: skip
    raise HierarchyError(f"the LLM's hierarchy is invalid after one repair round: {problem}")


def llm_client_from_env():
    """An LLMClient when an endpoint is configured (environment), else None."""
    from pair2scene.llm import LLMClient, LLMConfig

    try:
        config = LLMConfig.from_env()
    except ValueError as e:
        raise UserError(f"LLM configuration: {e}") from None
    return None if config is None else LLMClient(config)

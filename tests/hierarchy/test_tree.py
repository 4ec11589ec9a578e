"""Hierarchies: validation errors, trees, serialisation order (also on random trees), JSON."""

from __future__ import annotations

import numpy as np
import pytest

from pair2scene.hierarchy.tree import Hierarchy, HierarchyError, Node
from pair2scene.scene.model import FLOOR


def office() -> Hierarchy:
    h = Hierarchy("office")
    desk = h.add("desk", FLOOR)
    h.add("chair", FLOOR, desk.id)
    h.add("bed", FLOOR)
    laptop = h.add("laptop", desk.id)
    h.add("cell_phone", desk.id, laptop.id)
    h.add("mug", desk.id)
    return h.validate()


def test_ids_follow_categories():
    h = office()
    assert [n.id for n in h.nodes] == [
        "desk_0",
        "chair_0",
        "bed_0",
        "laptop_0",
        "cell_phone_0",
        "mug_0",
    ]
    assert h.add("chair", FLOOR).id == "chair_1"


def test_support_tree_and_functional_trees():
    h = office()
    assert h.support_edges() == [
        (FLOOR, "desk_0"), (FLOOR, "chair_0"), (FLOOR, "bed_0"),
        ("desk_0", "laptop_0"), ("desk_0", "cell_phone_0"), ("desk_0", "mug_0"),
    ]  # fmt: skip
    trees = {t.support: t.edges for t in h.functional_trees()}
    assert trees[FLOOR] == ((FLOOR, "desk_0"), ("desk_0", "chair_0"), (FLOOR, "bed_0"))
    assert trees["desk_0"] == (
        ("desk_0", "laptop_0"),
        ("laptop_0", "cell_phone_0"),
        ("desk_0", "mug_0"),
    )


def test_sequence_is_bfs_over_supports_and_dfs_over_functional_trees():
    seq = office().sequence()
    assert [s.dependent.id for s in seq] == [
        "desk_0", "chair_0", "bed_0", "laptop_0", "cell_phone_0", "mug_0"
    ]  # fmt: skip
    assert seq[1].functional == "desk_0" and seq[4].functional == "laptop_0"
    assert seq[3].support == "desk_0"


@pytest.mark.parametrize(
    "edit, message",
    [
        (lambda h: h.nodes.append(Node("desk_0", "desk")), "appears twice"),
        (lambda h: h.nodes.append(Node("floor", "desk")), "root of the support tree"),
        (lambda h: h.nodes.append(Node("x", "spaceship")), "unknown category 'spaceship'"),
        (lambda h: h.nodes.append(Node("w", "wall")), "is structure, not an object"),
        (lambda h: h.nodes.append(Node("d", "drawer")), "is part, not an object"),
        (lambda h: h.nodes.append(Node("lamp_9", "table_lamp")), "has no support"),
        (lambda h: h.support.update(mug_0="shelf_7"), "rests on 'shelf_7', which is not a node"),
        (lambda h: h.support.update(desk_0="mug_0"), "support cycle: desk_0 -> mug_0 -> desk_0"),
        (lambda h: h.support.update(desk_0="desk_0"), "rests on itself"),
        (lambda h: h.functional.update(mug_0="chair_0"), "must share the support"),
        (lambda h: h.functional.update(mug_0="mug_0"), "its own functional anchor"),
        (lambda h: h.functional.update(mug_0="ghost"), "'ghost' is not a node"),
        (lambda h: h.functional.update(laptop_0="cell_phone_0"), "functional cycle"),
        (lambda h: h.support.update(ghost="floor"), "not a node"),
    ],
)
def test_validation_names_the_problem(edit, message):
    h = office()
    edit(h)
    with pytest.raises(HierarchyError, match=message):
        h.validate()


def random_hierarchy(rng: np.random.Generator, n: int) -> Hierarchy:
    """A random valid hierarchy: each node rests on the floor or an earlier node, and may
    take an earlier sibling as its functional anchor; node order is then shuffled."""
    cats = ["desk", "table_lamp", "book", "chair", "mug", "vase", "plate", "bowl"]
    h = Hierarchy("other")
    for _ in range(n):
        support = (
            FLOOR if not h.nodes or rng.random() < 0.3 else h.nodes[rng.integers(len(h.nodes))].id
        )
        siblings = h.children(support)
        func = siblings[rng.integers(len(siblings))].id if siblings and rng.random() < 0.5 else None
        h.add(str(rng.choice(cats)), support, func)
    order = rng.permutation(len(h.nodes))
    h.nodes = [h.nodes[i] for i in order]
    return h.validate()


@pytest.mark.parametrize("seed", range(40))
def test_every_anchor_comes_before_its_dependents_on_random_trees(seed):
    rng = np.random.default_rng(seed)
    h = random_hierarchy(rng, int(rng.integers(1, 60)))
    seq = h.sequence()
    assert sorted(s.dependent.id for s in seq) == sorted(n.id for n in h.nodes)
    position = {s.dependent.id: i for i, s in enumerate(seq)}
    for i, s in enumerate(seq):
        assert s.support == FLOOR or position[s.support] < i
        assert s.functional is None or position[s.functional] < i
        assert s.support == h.support[s.dependent.id]
        assert s.functional == h.functional.get(s.dependent.id)


def test_json_round_trip():
    h = office()
    doc = h.to_dict(mode="fit", seed=0)
    assert doc["objects"] == 6 and doc["category_counts"]["desk"] == 1
    assert doc["support_tree"]["edges"][0] == {
        "parent": {"id": "floor", "category": "floor"},
        "child": {"id": "desk_0", "category": "desk"},
    }
    assert doc["sequence"][1]["functional_anchor"] == {"id": "desk_0", "category": "desk"}
    back = Hierarchy.from_dict(doc)
    assert back.support == h.support and back.functional == h.functional
    with pytest.raises(HierarchyError, match="malformed"):
        Hierarchy.from_dict({"nodes": [{"id": "a"}]})

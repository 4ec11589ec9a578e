"""Wall objects spaced along their wall as the training rooms' were: the share of
neighbouring pairs hanging close together, the draw, the test and placement."""

from __future__ import annotations

import numpy as np
import pytest

from pair2scene.assembly.mounting import crowds, hang
from pair2scene.assembly.place import AssemblyConfig, Placer
from pair2scene.assembly.walls import WallRules
from pair2scene.curation.stats import CLOSE_WALL_M, HierarchyStats, wall_gaps
from pair2scene.errors import UserError
from pair2scene.hierarchy.tree import Hierarchy
from pair2scene.scene.model import FLOOR, Room, Scene, SceneObject, wall_index, wall_support
from pair2scene.scene.walls import walls_of

SQUARE = np.array([[0.0, 0.0], [5.0, 0.0], [5.0, 4.0], [0.0, 4.0]])
WALLS = walls_of(SQUARE)  # 0: y = 0, 1: x = 5, 2: y = 4, 3: x = 0
ROOM = Room("living_room", SQUARE, 2.6)
FRAME = (0.6, 0.04, 0.5)


def _hung(wall: int, along: float, z: float = 1.5, size=FRAME):
    return hang(WALLS[wall], along, z, np.array(size))


def _room(i: int) -> Scene:
    """Three paintings on wall 0: two 0.1 m apart (close), the third 1.0 m on; one on
    wall 1 alone; curtains on wall 0 beside them, which are not counted; a sofa."""
    objects = [
        SceneObject("sofa", "sofa", _hung(2, 0.0, 0.4, (2.0, 0.9, 0.8)), None, FLOOR),
        SceneObject("p0", "painting", _hung(0, -1.5 + 0.01 * i), None, wall_support(0)),
        SceneObject("p1", "painting", _hung(0, -0.8), None, wall_support(0)),
        SceneObject("p2", "painting", _hung(0, 0.8), None, wall_support(0)),
        SceneObject("p3", "painting", _hung(1, 0.0), None, wall_support(1)),
        SceneObject("c0", "curtains", _hung(0, 1.5, 1.6, (0.8, 0.1, 2.0)), None, wall_support(0)),
    ]
    return Scene(f"l{i}", ROOM, objects)


def test_statistics_count_neighbouring_pairs_and_the_close_ones():
    scene = _room(0)
    assert wall_gaps(WALLS, scene.objects) == (2, 1)  # p0-p1 close, p1-p2 1.0 m apart
    stats = HierarchyStats.fit([_room(i) for i in range(10)])
    assert stats.wall_gaps == [20, 10]
    back = HierarchyStats.from_json(stats.to_json())
    assert back.wall_gaps == [20, 10]
    merged = HierarchyStats.merge([HierarchyStats.fit([_room(i)]) for i in range(3)])
    assert merged.wall_gaps == [6, 3]
    doc = stats.to_dict()
    doc["wall_gaps"] = [2, 3]
    with pytest.raises(UserError, match="wall_gaps"):
        HierarchyStats.from_dict(doc)
    del doc["wall_gaps"]  # written before it was kept: loaded, and nothing is kept apart
    old = HierarchyStats.from_dict(doc)
    assert old.wall_gaps is None
    assert WallRules.from_stats(old).close_share is None
    assert not any(WallRules.from_stats(old).keeps_apart(s) for s in range(20))


def test_each_object_keeps_apart_with_one_minus_the_close_share():
    rules = WallRules.from_stats(HierarchyStats.fit([_room(i) for i in range(10)]))
    assert rules.close_share == pytest.approx(0.5)
    apart = [rules.keeps_apart(s) for s in range(2000)]
    assert np.mean(apart) == pytest.approx(0.5, abs=0.03)
    few = WallRules.from_stats(HierarchyStats.fit([_room(i) for i in range(5)]))
    assert few.close_share is None  # 10 pairs: too few to say


def test_crowds_along_the_wall_beside_or_above_another_on_it():
    shown = [("p0", _hung(0, 0.0), WALLS[0])]
    beside = 0.6 + CLOSE_WALL_M - 0.01  # centre to centre: 0.6 m of frame, less than the gap
    assert crowds(_hung(0, beside), WALLS[0], shown)
    assert not crowds(_hung(0, 0.6 + CLOSE_WALL_M + 0.01), WALLS[0], shown)
    assert crowds(_hung(0, 0.1, 2.2), WALLS[0], shown)  # above it
    assert not crowds(_hung(1, 0.0), WALLS[1], shown)  # another wall
    assert not crowds(_hung(0, 0.0), WALLS[0], [])


@pytest.mark.parametrize("spacing", [True, False])
def test_placement_keeps_paintings_apart_when_the_data_says_so(spacing):
    pytest.importorskip("torch")
    from pair2scene.model import from_pretrained

    rules = WallRules(close_share=0.0)  # every pair in the data hung apart
    placer = Placer(from_pretrained(), config=AssemblyConfig(wall_spacing=spacing), walls=rules)
    closest = []
    for seed in range(6):
        h = Hierarchy("living_room")
        sofa = h.add("sofa", FLOOR)
        for _ in range(3):
            h.add("painting", "wall", sofa.id)
        result = placer.place(h.validate(), ROOM, seed=seed)
        hung = [o for o in result.scene.objects if o.category == "painting"]
        assert len(hung) + len(result.stats.dropped) == 3
        for a in hung:
            for b in hung:
                if a.id < b.id and a.support == b.support:
                    w = WALLS[wall_index(a.support)]
                    xa, xb = (w.local(o.box.corners()[:, :2])[:, 0] for o in (a, b))
                    closest.append(max(xb.min() - xa.max(), xa.min() - xb.max()))
    assert closest, "some paintings share a wall"
    if spacing:
        assert min(closest) >= CLOSE_WALL_M - 1e-6
    else:
        assert min(closest) < CLOSE_WALL_M  # the model hangs them side by side

"""Generated rooms as the training rooms are: their shapes (L-shaped ones too), every
floor object inside the floor; a fridge's food inside it, on its shelves."""

from __future__ import annotations

import pytest

from pair2scene.assembly.rest import on_floor
from pair2scene.generate import Pair2Scene
from pair2scene.scene.model import FLOOR


@pytest.fixture(scope="module")
def p2s():
    return Pair2Scene.from_pretrained()


@pytest.mark.slow  # (CI runs the slow tests too: .ci/run; ~15-25 s)
def test_rooms_take_training_shapes_and_keep_their_furniture_inside(p2s):
    corners = set()
    for seed in range(4):
        scene = p2s.generate(room="bedroom", seed=seed).scene
        corners.add(len(scene.room.floor_polygon))
        poly = scene.room.floor_polygon
        outside = [o.id for o in scene.objects if o.support == FLOOR and not on_floor(o.box, poly)]
        assert not outside, (seed, outside)
    assert 4 in corners and max(corners) >= 6  # rectangles and L-shapes


def test_a_fridge_s_food_is_inside_it(p2s):
    inside = 0
    for seed in range(2):
        scene = p2s.generate(room="kitchen", seed=seed).scene
        by_id = scene.by_id()
        for o in scene.objects:
            fridge = by_id.get(o.support)
            if fridge is None or fridge.category != "fridge":
                continue
            assert fridge.box.bottom + 0.05 < o.box.bottom < fridge.box.top - 0.05, o.id
            inside += 1
    assert inside >= 3


def test_which_tops_stay_free_is_a_setting():
    from pair2scene.assembly.place import AssemblyConfig
    from pair2scene.errors import UserError
    from pair2scene.generate import GenerateConfig

    default = Pair2Scene.from_pretrained("random")
    assert {"fridge", "sofa"} <= default.placer.top_free
    off = Pair2Scene.from_pretrained(
        "random", GenerateConfig(assembly=AssemblyConfig(top_free_share=-1.0))
    )
    assert off.placer.top_free == frozenset()
    with pytest.raises(UserError, match="top-free-share"):
        AssemblyConfig(top_free_share=1.5)

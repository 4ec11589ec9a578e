"""Floor objects stand alone mid-room only as often as their category's objects did in the
training rooms (AssemblyConfig.isolation)."""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest

from pair2scene.scene.relations import footprint, stands_alone

SQUARE = np.array([[0, 0], [5.0, 0], [5.0, 5.0], [0, 5.0]], float)


def _placer(isolation: bool = True, shares=None):
    from pair2scene.assembly.place import AssemblyConfig, Placer
    from pair2scene.model import from_pretrained

    cfg = AssemblyConfig(candidates=16, batches=2, isolation=isolation, walls=False)
    return Placer(from_pretrained(), config=cfg, isolated=shares)


def test_an_object_draws_once_whether_it_may_stand_alone():
    pytest.importorskip("torch")
    placer = _placer(shares={"house_plant": 0.0, "dog_bed": 1.0, "box": 0.5})
    assert not any(placer._may_stand_alone("house_plant", s) for s in range(40))
    assert all(placer._may_stand_alone("dog_bed", s) for s in range(40))
    draws = [placer._may_stand_alone("box", s) for s in range(200)]
    assert 70 < sum(draws) < 130
    assert draws == [placer._may_stand_alone("box", s) for s in range(200)]  # seeded
    assert placer._may_stand_alone("sofa", 0)  # no statistics: anywhere
    assert _placer(False, placer.isolated)._may_stand_alone("house_plant", 0)


def test_house_plants_keep_to_the_walls_or_company_and_stray_without_the_rule():
    """Drawn free of the walls (no wall rules), a plant whose category never stood alone
    ends within 0.5 m of a wall or of the table; without the rule some stand mid-room."""
    pytest.importorskip("torch")
    from pair2scene.assembly.rooms import make_room
    from pair2scene.hierarchy.tree import Hierarchy
    from pair2scene.scene.model import FLOOR

    room = replace(make_room("living_room", np.random.default_rng(0)), floor_polygon=SQUARE)
    h = Hierarchy("living_room")
    h.add("dining_table", FLOOR)
    h.add("house_plant", FLOOR)
    h.add("house_plant", FLOOR)
    h.validate()

    def alone(isolation: bool) -> int:
        placer = _placer(isolation, {"house_plant": 0.0})
        total = 0
        for seed in range(6):
            scene = placer.place(h, room, seed=seed).scene
            plants = [o for o in scene.objects if o.category == "house_plant"]
            assert len(plants) == 2, seed  # kept to company, not dropped
            floor = [o for o in scene.objects if o.support == FLOOR]
            for p in plants:
                others = [footprint(o.box) for o in floor if o.id != p.id]
                total += stands_alone(footprint(p.box), SQUARE, others)
        return total

    assert alone(True) == 0
    assert alone(False) > 0

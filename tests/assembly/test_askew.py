"""Floor objects free of the walls turned off the walls' axes as the training rooms' were
(AssemblyConfig.askew)."""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest

from pair2scene.curation.stats import askew_bin


def _placer(askew: bool = True, shares=None):
    from pair2scene.assembly.place import AssemblyConfig, Placer
    from pair2scene.model import from_pretrained

    cfg = AssemblyConfig(candidates=16, batches=2, askew=askew, walls=False)
    return Placer(from_pretrained(), config=cfg, askew=shares)


def test_an_object_draws_its_turn_within_its_bin_and_either_way():
    pytest.importorskip("torch")
    placer = _placer(shares={"chair": np.array([0, 0, 0, 1.0, 0, 0])})
    turns = [placer._tilt("chair", seed) for seed in range(40)]
    assert all(15 <= abs(np.degrees(t)) <= 20 for t in turns)
    assert min(turns) < 0 < max(turns)
    assert turns == [placer._tilt("chair", seed) for seed in range(40)]  # seeded
    assert placer._tilt("sofa", 0) == 0.0  # no statistics: square
    assert _placer(askew=False, shares=placer.askew)._tilt("chair", 0) == 0.0


def test_a_free_standing_chair_stands_turned_and_square_without_the_rule():
    pytest.importorskip("torch")
    from pair2scene.assembly.rooms import make_room
    from pair2scene.hierarchy.tree import Hierarchy
    from pair2scene.scene.model import FLOOR

    room = make_room("living_room", np.random.default_rng(0))
    room = replace(room, floor_polygon=np.array([[0, 0], [4.0, 0], [4.0, 4.0], [0, 4.0]], float))
    h = Hierarchy("living_room")
    h.add("chair", FLOOR)
    h.add("armchair", FLOOR)
    h.validate()
    shares = {"chair": np.array([0, 0, 0, 0, 1.0, 0]), "armchair": np.array([1.0, 0, 0, 0, 0, 0])}

    def bins(askew):
        scene = _placer(askew, shares).place(h, room, seed=3).scene
        return {o.category: askew_bin(o.box.yaw) for o in scene.objects}

    assert bins(True) == {"chair": 4, "armchair": 0}  # 20-30 degrees; square by its share
    assert bins(False) == {"chair": 0, "armchair": 0}


def test_a_pot_by_a_wall_stands_turned_with_its_footprint_at_the_wall():
    """A house plant the wall rules put against a wall (every one, none in a corner) is
    turned 30-45 degrees off the walls' axes as a free one would be, and stands with its
    footprint at the wall: by it (walls_near), though no face is parallel to it."""
    pytest.importorskip("torch")
    from pair2scene.assembly.place import AssemblyConfig, Placer
    from pair2scene.assembly.rooms import make_room
    from pair2scene.assembly.walls import WallRules
    from pair2scene.hierarchy.tree import Hierarchy
    from pair2scene.model import from_pretrained
    from pair2scene.scene.model import FLOOR
    from pair2scene.scene.walls import face_contacts, walls_near, walls_of

    room = make_room("living_room", np.random.default_rng(0))
    room = replace(room, floor_polygon=np.array([[0, 0], [4.0, 0], [4.0, 4.0], [0, 4.0]], float))
    h = Hierarchy("living_room")
    h.add("house_plant", FLOOR)
    h.validate()
    rules = WallRules(rates={"living_room": {"house_plant": (1.0, 1.0)}},
                      corners={"living_room": {"house_plant": (0.0, 1.0)}})  # fmt: skip
    shares = {"house_plant": np.array([0, 0, 0, 0, 0, 1.0])}
    cfg = AssemblyConfig(candidates=16, batches=2)
    for seed in range(4):
        scene = (
            Placer(from_pretrained(), config=cfg, walls=rules, askew=shares)
            .place(h, room, seed=seed)
            .scene
        )
        (pot,) = scene.objects
        walls = walls_of(room.floor_polygon)
        assert askew_bin(pot.box.yaw) == 5, seed  # 30-45 degrees off the axes
        assert walls_near(pot.box, walls) and not face_contacts(pot.box, walls), seed

"""Functional anchors in placement and hierarchies: what the statistics learn of each
(dependent, anchor) pair, the chairs they keep at their table, and how often a chair
takes the room's table as its anchor."""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest

from pair2scene.assembly.anchors import AnchorRules
from pair2scene.assembly.place import AssemblyConfig, Placer
from pair2scene.curation.stats import HierarchyStats
from pair2scene.hierarchy.synthesis import Statistics
from pair2scene.hierarchy.tree import Hierarchy
from pair2scene.scene.geometry import OrientedBox
from pair2scene.scene.model import FLOOR, Opening, Room, Scene, SceneObject
from pair2scene.scene.relations import angle_to_footprint, faces, footprint, footprint_gap

ROOM = Room(
    "living_room",
    np.array([[0, 0], [6, 0], [6, 5], [0, 5]], float),
    2.6,
    (Opening("door", (0.5, 0.0), (1.4, 0.0), 0.0, 2.1),),
)
TABLE = OrientedBox.from_yaw([3.0, 2.5, 0.375], [1.6, 0.9, 0.75])
"""A dining table in the middle of the room, long side along x."""


def _dining(i: int, turned: bool = False) -> Scene:
    """A table with four chairs at its long sides, facing it (``turned``: the last one
    sideways), a lone chair by the wall and an armchair."""
    chairs = [
        OrientedBox.from_yaw([2.5, 1.75, 0.45], [0.5, 0.5, 0.9], 0.0),  # south side, faces +y
        OrientedBox.from_yaw([3.5, 1.75, 0.45], [0.5, 0.5, 0.9], 0.0),
        OrientedBox.from_yaw([2.5, 3.25 + 0.01 * i, 0.45], [0.5, 0.5, 0.9], np.pi),
        OrientedBox.from_yaw([3.5, 3.25, 0.45], [0.5, 0.5, 0.9], np.pi / 2 if turned else np.pi),
    ]
    objects = [SceneObject("table_0", "dining_table", TABLE, None, FLOOR)]
    objects += [
        SceneObject(f"chair_{k}", "chair", b, None, FLOOR, functional_anchor="table_0")
        for k, b in enumerate(chairs)
    ]
    lone = OrientedBox.from_yaw([5.7, 4.7, 0.45], [0.5, 0.5, 0.9], np.pi)
    objects.append(SceneObject("chair_9", "chair", lone, None, FLOOR))
    arm = OrientedBox.from_yaw([1.0, 4.0, 0.4], [0.8, 0.8, 0.8], np.pi)
    objects.append(SceneObject("armchair_0", "armchair", arm, None, FLOOR))
    return Scene(f"s{i}", ROOM, objects)


def test_facing_is_measured_towards_the_nearest_side_of_the_anchor():
    # a chair at the long side near the table's end looks square at that side: towards
    # the table's centre it would be 40 degrees off, towards the nearest point 0
    chair = OrientedBox.from_yaw([3.7, 1.75, 0.45], [0.5, 0.5, 0.9], 0.0)
    assert angle_to_footprint(chair, footprint(TABLE)) == pytest.approx(0.0, abs=1e-6)
    assert faces(chair, TABLE)
    sideways = OrientedBox.from_yaw([3.7, 1.75, 0.45], [0.5, 0.5, 0.9], np.pi / 2)
    assert angle_to_footprint(sideways, footprint(TABLE)) == pytest.approx(90.0)
    assert not faces(sideways, TABLE)
    under = OrientedBox.from_yaw([3.0, 2.2, 0.45], [0.5, 0.5, 0.9], 0.0)  # pushed in
    assert faces(under, TABLE)  # towards the table's centre


def test_statistics_learn_facing_shares_gaps_and_who_stood_beside_an_anchor():
    scenes = [_dining(i, turned=i == 0) for i in range(4)]
    stats = HierarchyStats.fit(scenes)
    n, facing, faced, total, squares, behind = stats.func_geometry["chair"]["dining_table"]
    assert (n, facing) == (16, 15)  # one of the 16 turned sideways
    assert faced == 8  # the table's +y points at the north side's chairs
    assert behind == 8  # the others stand by its back half (south, its -y)
    assert total / n == pytest.approx(0.05, abs=0.01)  # 5 cm from the table's edge
    # chairs beside a table: all 5 per room (the lone one too); the armchair as well
    assert stats.func_present[FLOOR]["dining_table"]["chair"] == 20
    assert stats.func_present[FLOOR]["dining_table"]["armchair"] == 4
    # another chair beside each, but those at the table were not free to take a chair
    assert stats.func_present[FLOOR]["chair"]["chair"] == 4
    back = HierarchyStats.from_json(stats.to_json())
    learned = [16, 15, 8, total, squares, 8]
    assert back.func_geometry["chair"]["dining_table"] == pytest.approx(learned)
    assert back.func_present == stats.func_present
    merged = HierarchyStats.merge([HierarchyStats.fit(scenes[:2]), HierarchyStats.fit(scenes[2:])])
    assert merged.func_geometry["chair"]["dining_table"] == pytest.approx(learned)
    assert merged.func_present == stats.func_present

    rules = AnchorRules.from_stats(stats)
    rule = rules.rule("chair", "dining_table")
    assert rule.facing == pytest.approx(15 / 16)
    assert rule.max_gap == pytest.approx(rule.gap_mean + 2 * rule.gap_std + 0.15)
    assert rules.rule("armchair", "dining_table") is None  # never anchored there
    draws = [rules.check("chair", "dining_table", TABLE, s).must_face for s in range(400)]
    assert 0.88 < np.mean(draws) < 0.98


def test_a_chair_takes_the_table_as_anchor_as_often_as_chairs_beside_tables_did():
    """Over all chairs (the lone ones in rooms without a table counted too) 4 of 5 had a
    table as anchor; beside a table, 4 of 5 as well here, but rooms without a table
    lower the plain share: the conditioned chance must not."""
    scenes = [_dining(i) for i in range(4)]
    alone = Scene("alone", ROOM, [SceneObject(
        f"chair_{k}", "chair", OrientedBox.from_yaw([1 + k, 4.7, 0.45], [0.5, 0.5, 0.9], np.pi),
        None, FLOOR) for k in range(4)])  # fmt: skip
    stats = HierarchyStats.fit(scenes + [alone] * 4)
    h = Hierarchy("living_room")
    table = h.add("dining_table", FLOOR)
    st = Statistics(stats)
    took = [st.functional_choice(FLOOR, "chair", [table], np.random.default_rng(s)) is not None
            for s in range(2000)]  # fmt: skip
    assert np.mean(took) == pytest.approx(16 / 20, abs=0.03)  # not 16 / 36
    plain = HierarchyStats.fit(scenes + [alone] * 4)
    plain.func_present = {}  # statistics written before the counts: the plain share
    took = [Statistics(plain).functional_choice(FLOOR, "chair", [table],
                                                np.random.default_rng(s)) is not None
            for s in range(2000)]  # fmt: skip
    assert np.mean(took) == pytest.approx(16 / 36, abs=0.03)


def test_a_chair_at_the_dining_table_does_not_count_against_the_desk():
    """Rooms with a dining table and a desk: four chairs at the table, one at the desk;
    one room with a desk alone and a chair standing free. Of the chairs free to take the
    desk, 4 of 5 did; counting the table's chairs beside the desk too made it 4 of 21,
    and a new chair in a room with only a desk sat at it once in five."""
    desk = OrientedBox.from_yaw([5.3, 4.6, 0.375], [1.2, 0.6, 0.75], np.pi)
    at_desk = OrientedBox.from_yaw([5.3, 3.9, 0.45], [0.5, 0.5, 0.9], 0.0)
    scenes = []
    for i in range(4):
        room = _dining(i)
        objects = [o for o in room.objects if o.id not in ("chair_9", "armchair_0")]
        objects += [SceneObject("desk_0", "desk", desk, None, FLOOR),
                    SceneObject("chair_8", "chair", at_desk, None, FLOOR,
                                functional_anchor="desk_0")]  # fmt: skip
        scenes.append(Scene(f"d{i}", ROOM, objects))
    free = OrientedBox.from_yaw([1.0, 1.0, 0.45], [0.5, 0.5, 0.9], 0.0)
    alone = [SceneObject("desk_0", "desk", desk, None, FLOOR),
             SceneObject("chair_0", "chair", free, None, FLOOR)]  # fmt: skip
    scenes.append(Scene("free", ROOM, alone))
    stats = HierarchyStats.fit(scenes)
    assert stats.func_present[FLOOR]["desk"]["chair"] == 5
    assert stats.func_present[FLOOR]["dining_table"]["chair"] == 16
    h = Hierarchy("bedroom")
    st = Statistics(stats)
    took = [st.functional_choice(FLOOR, "chair", [h.add("desk", FLOOR)], np.random.default_rng(s))
            is not None for s in range(2000)]  # fmt: skip
    assert np.mean(took) == pytest.approx(4 / 5, abs=0.03)


class _Chairs:
    """A stand-in model: the table where given; a chair's candidates at the table's north
    side, the first ``bad`` of them turned sideways (or 0.9 m off, ``far``)."""

    honours_temperature = False
    draws_in_frames = True  # (the rules hold only models that draw at the anchor)

    def __init__(self, bad: int, far: bool = False):
        self.bad, self.far = bad, far

    def draw(self, query, n, temperature, generator):
        if query.category == "dining_table":
            return np.repeat(TABLE.to_vector()[None], n, axis=0), None
        # at the north side, where the table's front (+y) points: in front of it too
        good = OrientedBox.from_yaw([2.5, 3.25, 0.45], query.size, np.pi).to_vector()
        y = 4.4 if self.far else 3.25  # 4.4 m: 0.9 m from the table's edge
        yaw = np.pi if self.far else np.pi / 2
        bad = OrientedBox.from_yaw([2.5, y, 0.45], query.size, yaw).to_vector()
        out = np.repeat(good[None], n, axis=0)
        out[: self.bad] = bad
        return out, None


def _rules() -> AnchorRules:
    return AnchorRules.from_stats(HierarchyStats.fit([_dining(i) for i in range(8)]))


def _chair_at_table() -> Hierarchy:
    h = Hierarchy("living_room")
    table = h.add("dining_table", FLOOR)
    h.add("chair", FLOOR, table.id)
    return h.validate()


@pytest.mark.parametrize("far", [False, True])
def test_placement_keeps_a_chair_at_its_table_facing_it(far):
    config = AssemblyConfig(walls=False, navigable=False, candidates=8, batches=2)
    placer = Placer(_Chairs(bad=5, far=far), config=config, anchors=_rules())
    result = placer.place(_chair_at_table(), ROOM, seed=0)
    assert result.stats.placed == 2
    chair = next(o for o in result.scene.objects if o.category == "chair")
    assert faces(chair.box, TABLE) and chair.box.center[1] == pytest.approx(3.25, abs=0.01)
    assert result.stats.rejections == {("far_from_anchor" if far else "faces_away"): 5}

    loose = Placer(placer.model, config=AssemblyConfig(walls=False, navigable=False,
                                                       anchors=False))  # fmt: skip
    chair = next(o for o in loose.place(_chair_at_table(), ROOM, seed=0).scene.objects
                 if o.category == "chair")  # fmt: skip
    assert far or not faces(chair.box, TABLE)  # the first candidate, as drawn


@pytest.mark.parametrize("far", [False, True])
def test_a_chair_drawn_only_aside_or_off_its_table_is_seated_at_it(far):
    """Every candidate turned aside (or 0.9 m off, facing away): none passes as drawn,
    and the chair is seated at the table's nearest side, facing it (``seated_at``);
    without the rule it is dropped with the reasons."""
    config = AssemblyConfig(walls=False, navigable=False, candidates=8, batches=2)
    placer = Placer(_Chairs(bad=16, far=far), config=config, anchors=_rules())
    result = placer.place(_chair_at_table(), ROOM, seed=0)
    assert result.stats.dropped == [] and result.stats.resamples[-1] == 16  # all tried first
    chair = next(o for o in result.scene.objects if o.category == "chair")
    assert faces(chair.box, TABLE)
    assert chair.box.center[1] > TABLE.center[1] + TABLE.half_size[1]  # its north side
    table = next(o for o in result.scene.objects if o.category == "dining_table")
    assert footprint_gap(footprint(chair.box), footprint(table.box)) < 0.01  # at the edge

    config = replace(config, seat_at_anchor=False)
    result = Placer(placer.model, config=config, anchors=_rules()).place(
        _chair_at_table(), ROOM, seed=0
    )
    assert [d.category for d in result.stats.dropped] == ["chair"]
    reason = "far_from_anchor 16" if far else "faces_away 16"
    assert reason in result.stats.dropped[0].reason


def test_an_object_that_must_stand_in_front_of_its_anchor():
    """A TV stand drawn behind or beside its sofa is ``not_in_front``; in front of it,
    whichever way the stand itself turns, it passes that test."""
    from pair2scene.assembly.anchors import AnchorCheck

    sofa = OrientedBox.from_yaw([3.0, 0.5, 0.45], [2.2, 0.9, 0.9], 0.0)  # faces +y
    check = AnchorCheck(sofa, max_gap=4.0, must_face=False, in_front=True)
    ahead = OrientedBox.from_yaw([3.0, 4.7, 0.3], [1.4, 0.45, 0.6], np.pi)
    beside = OrientedBox.from_yaw([5.5, 0.5, 0.3], [1.4, 0.45, 0.6], np.pi / 2)
    assert check.reason(ahead) is None
    assert check.reason(beside) == "not_in_front"
    assert AnchorCheck(sofa, 4.0, must_face=True).reason(beside) is None  # it faces the sofa
    away = OrientedBox.from_yaw([5.5, 0.5, 0.3], [1.4, 0.45, 0.6], -np.pi / 2)
    assert AnchorCheck(sofa, 4.0, must_face=True, in_front=True).reason(away) == "faces_away"
    assert AnchorCheck(sofa, 1.0, must_face=False).reason(ahead) == "far_from_anchor"


def test_across_draws_with_the_pairs_faced_share():
    """A mounted object hangs across from its anchor with the share of the pair's
    training objects its anchor faced; same seed, same draw; a pair without a rule never."""
    stats = HierarchyStats()
    stats.func_geometry = {"television": {"sofa": [40.0, 20.0, 30.0, 80.0, 200.0]}}
    rules = AnchorRules.from_stats(stats)
    draws = [rules.across("television", "sofa", seed) for seed in range(2000)]
    assert np.mean(draws) == pytest.approx(0.75, abs=0.03)
    assert draws == [rules.across("television", "sofa", seed) for seed in range(2000)]
    assert not any(rules.across("television", "bed", seed) for seed in range(50))
    # the draw is check()'s in_front draw: one decision per object
    box = OrientedBox.from_yaw([1.0, 1.0, 0.4], [2.0, 0.9, 0.8])
    assert all(rules.check("television", "sofa", box, s).in_front == draws[s] for s in range(50))

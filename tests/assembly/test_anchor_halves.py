"""By which half of its functional anchor a floor object stands: what the statistics
count (``behind``), when a pair keeps its dependents to a half, the test itself, and
placement preferring the drawn half without leaving an object out for it."""

from __future__ import annotations

import numpy as np
import pytest

from pair2scene.assembly.anchors import HALF_MIN_SHARE, AnchorCheck, AnchorRules
from pair2scene.assembly.place import AssemblyConfig, Placer
from pair2scene.curation.stats import HierarchyStats
from pair2scene.hierarchy.tree import Hierarchy
from pair2scene.scene.geometry import OrientedBox
from pair2scene.scene.model import FLOOR, Opening, Room, Scene, SceneObject
from pair2scene.scene.relations import by_back_half

ROOM = Room(
    "bedroom",
    np.array([[0, 0], [5, 0], [5, 5], [0, 5]], float),
    2.6,
    (Opening("door", (4.0, 5.0), (4.9, 5.0), 0.0, 2.1),),
)
BED = OrientedBox.from_yaw([2.5, 1.0, 0.3], [1.6, 2.0, 0.6])
"""A bed with its headboard (-y) against the south wall, its foot towards +y."""
STAND = (0.5, 0.4, 0.55)
HEAD = OrientedBox.from_yaw([3.6, 0.3, 0.275], STAND)  # beside the head, right
FOOT = OrientedBox.from_yaw([3.6, 1.7, 0.275], STAND)  # beside the foot, right


def _bedroom(i: int, at_foot: bool = False) -> Scene:
    """A bed with two nightstands anchored to it beside its head (``at_foot``: the second
    beside its foot)."""
    left = OrientedBox.from_yaw([1.4 - 0.01 * i, 0.3, 0.275], STAND)
    right = FOOT if at_foot else HEAD
    objects = [SceneObject("bed_0", "bed", BED, None, FLOOR)]
    objects += [
        SceneObject(f"side_table_{k}", "side_table", b, None, FLOOR, functional_anchor="bed_0")
        for k, b in enumerate([left, right])
    ]
    return Scene(f"s{i}", ROOM, objects)


def test_statistics_count_who_stood_by_the_anchors_back_half():
    scenes = [_bedroom(i, at_foot=i == 0) for i in range(5)]
    stats = HierarchyStats.fit(scenes)
    n, facing, faced, _, _, behind = stats.func_geometry["side_table"]["bed"]
    assert (n, faced, behind) == (10, 0, 9)  # one of ten beside the foot
    rule = AnchorRules.from_stats(stats).rule("side_table", "bed")
    assert rule.behind == pytest.approx(0.9)
    back = HierarchyStats.from_json(stats.to_json())
    assert back.func_geometry["side_table"]["bed"] == pytest.approx(
        stats.func_geometry["side_table"]["bed"]
    )
    merged = HierarchyStats.merge([HierarchyStats.fit(scenes[:2]), HierarchyStats.fit(scenes[2:])])
    assert merged.func_geometry["side_table"]["bed"] == pytest.approx([10, facing, 0, *[
        stats.func_geometry["side_table"]["bed"][k] for k in (3, 4)], 9])  # fmt: skip


@pytest.mark.parametrize(
    ("sums", "behind"),
    [
        ([20, 0, 0, 2.0, 1.0, 20], 1.0),
        ([20, 0, 0, 2.0, 1.0, 1], 0.05),  # by the front half: as decided
        ([20, 0, 0, 2.0, 1.0, 10], None),  # either half: no rule
        ([20, 0, 16, 2.0, 1.0, 4], None),  # only 4 not faced: too few to say
        ([20, 0, 0, 2.0, 1.0], None),  # statistics written before the count
    ],
)
def test_a_pair_keeps_to_a_half_only_when_its_training_pairs_decided(sums, behind):
    stats = HierarchyStats()
    stats.func_geometry = {"side_table": {"bed": [float(v) for v in sums]}}
    stats = HierarchyStats.from_json(stats.to_json())  # five sums read back as written
    rules = AnchorRules.from_stats(stats)
    assert rules.rule("side_table", "bed").behind == (None if behind is None else
                                                      pytest.approx(behind))  # fmt: skip
    halves = [rules.check("side_table", "bed", BED, s).half for s in range(400)]
    if behind is None:
        assert set(halves) == {0}
    else:
        assert np.mean(np.array(halves) < 0) == pytest.approx(behind, abs=0.04)
        assert 0 not in halves
    assert HALF_MIN_SHARE == 0.8


def test_an_object_drawn_in_front_of_its_anchor_keeps_no_half():
    """The in-front draw comes first; an object drawn there stands by the anchor's front
    half already and is not held to the back one (a bench at the foot of a bed)."""
    stats = HierarchyStats()
    stats.func_geometry = {"side_table": {"bed": [40.0, 0.0, 20.0, 2.0, 1.0, 20.0]}}
    rules = AnchorRules.from_stats(stats)
    checks = [rules.check("side_table", "bed", BED, s) for s in range(300)]
    assert all(c.half == 0 for c in checks if c.in_front)
    assert all(c.half == -1 for c in checks if not c.in_front)
    assert 0.4 < np.mean([c.in_front for c in checks]) < 0.6


def test_the_half_test_looks_at_the_centre_in_the_anchors_frame():
    behind = AnchorCheck(BED, max_gap=1.0, must_face=False, half=-1)
    ahead = AnchorCheck(BED, max_gap=1.0, must_face=False, half=1)
    assert behind.reason(HEAD) is None and behind.reason(FOOT) == "wrong_half"
    assert ahead.reason(FOOT) is None and ahead.reason(HEAD) == "wrong_half"
    assert AnchorCheck(BED, max_gap=1.0, must_face=False).reason(FOOT) is None
    turned = OrientedBox.from_yaw(BED.center, BED.size, np.pi)  # headboard to +y now
    assert AnchorCheck(turned, 1.0, False, half=-1).reason(FOOT) is None


class _Nightstands:
    """A stand-in model: the bed where given; a nightstand's candidates beside its foot
    (the first ``foot`` of them), then beside its head."""

    honours_temperature = False
    draws_in_frames = True

    def __init__(self, foot: int):
        self.foot = foot

    def draw(self, query, n, temperature, generator):
        if query.category == "bed":
            return np.repeat(BED.to_vector()[None], n, axis=0), None
        out = np.repeat(HEAD.to_vector()[None], n, axis=0)
        out[: self.foot] = FOOT.to_vector()
        return out, None


def _rules() -> AnchorRules:
    return AnchorRules.from_stats(HierarchyStats.fit([_bedroom(i) for i in range(5)]))


def _nightstand_at_bed() -> Hierarchy:
    h = Hierarchy("bedroom")
    bed = h.add("bed", FLOOR)
    h.add("side_table", FLOOR, bed.id)
    return h.validate()


def _by_head(box: OrientedBox) -> bool:
    return by_back_half(box, BED)


def _placed(model, **config):
    config = AssemblyConfig(walls=False, navigable=False, candidates=8, batches=2, **config)
    result = Placer(model, config=config, anchors=_rules()).place(_nightstand_at_bed(), ROOM, 0)
    stand = next(o for o in result.scene.objects if o.category == "side_table")
    return stand, result.stats


def test_placement_stands_a_nightstand_by_the_head_of_its_bed():
    stand, stats = _placed(_Nightstands(foot=5))
    assert _by_head(stand.box)
    assert stats.rejections == {"wrong_half": 5}
    loose, _ = _placed(_Nightstands(foot=5), anchors=False)
    assert not _by_head(loose.box)  # the first candidate, as drawn


def test_a_nightstand_drawn_only_by_the_foot_stands_there_rather_than_nowhere():
    stand, stats = _placed(_Nightstands(foot=16))
    assert stats.placed == 2 and not stats.dropped
    assert not _by_head(stand.box)
    assert stats.rejections == {"wrong_half": 16}

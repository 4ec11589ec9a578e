"""The run-time front fix: the yaw tables and turn_front, as the adapters apply them."""

from collections import Counter

import numpy as np
import pytest

from pair2scene.data.ai2thor import load_ai2thor
from pair2scene.data.orientation import (
    FRONT_YAW_OFFSET_BY_ASSET_DEG,
    FRONT_YAW_OFFSET_DEG,
    front_offset_deg,
    turn_front,
)
from pair2scene.scene.geometry import OrientedBox, corner_distance, yaw_to_matrix


@pytest.fixture(scope="module")
def ai2thor_raw(ai2thor_databases):
    return load_ai2thor(ai2thor_databases, correct_front=False)


@pytest.mark.parametrize("offset", [0, 90, 180, 270])
def test_turn_front_keeps_the_box_and_turns_the_front(offset):
    box = OrientedBox.from_yaw([1.0, 2.0, 0.4], [1.6, 0.8, 0.8], np.radians(30))
    turned = turn_front(box, offset)
    assert corner_distance(turned.corners(), box.corners()) < 1e-9
    assert np.allclose(turned.rotation, box.rotation @ yaw_to_matrix(np.radians(offset)))
    assert np.allclose(turned.size, box.size if offset in (0, 180) else [0.8, 1.6, 0.8])
    # the new front is the old +y (0), -x (90), -y (180) or +x (270)
    old = {0: box.rotation[:, 1], 90: -box.rotation[:, 0], 180: -box.rotation[:, 1]}
    old[270] = box.rotation[:, 0]
    assert np.allclose(turned.rotation[:, 1], old[offset])


def test_turn_front_rejects_other_angles():
    with pytest.raises(ValueError, match="one of"):
        turn_front(OrientedBox.from_yaw([0, 0, 0], [1, 1, 1]), 45)


def test_asset_override_beats_its_category():
    assert front_offset_deg("ai2thor", "bed", "Bed_3") == 180
    assert front_offset_deg("ai2thor", "bed", "RoboTHOR_bed_kritter") == 0
    assert front_offset_deg("ai2thor", "bed") == 180
    assert front_offset_deg("procthor", "bed", "Bed_3") == 0
    assert front_offset_deg("nowhere", "bed") == 0


def test_procthor_needs_no_correction():
    assert not FRONT_YAW_OFFSET_DEG["procthor"] and not FRONT_YAW_OFFSET_BY_ASSET_DEG["procthor"]


def test_the_correction_turns_frames_and_keeps_boxes(ai2thor_raw, ai2thor_corpus):
    turned: Counter[str] = Counter()
    for a, b in zip(ai2thor_raw.scenes, ai2thor_corpus.scenes):
        for o, p in zip(a.objects, b.objects):
            assert o.id == p.id
            assert corner_distance(o.box.corners(), p.box.corners()) < 1e-9
            offset = front_offset_deg("ai2thor", o.category, o.asset.id)
            expect = o.box.rotation @ yaw_to_matrix(np.radians(offset))
            assert np.allclose(p.box.rotation, expect, atol=1e-12)
            turned[o.category] += offset != 0
    # iTHOR-modelled beds (all but RoboTHOR's own) and five TV stands
    assert +turned == {"bed": 52, "tv_stand": 5}


def test_the_fixture_bed_has_its_pillows_at_its_head(fixtures):
    for correct, side in ((False, 1.0), (True, -1.0)):
        bedroom = load_ai2thor(fixtures / "ai2thor", correct_front=correct).scenes[1]
        bed, pillow = bedroom.get("bed_0"), bedroom.get("pillow_0")
        assert pillow.support == "bed_0"
        local_y = bed.box.to_local(pillow.box.center[None])[0, 1]
        assert np.sign(local_y) == side  # raw: Unity forward points at the headboard

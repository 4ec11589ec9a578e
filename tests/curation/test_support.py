"""Support extraction: hand-made scenes with known answers, and the sources' own annotations."""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest

from pair2scene.curation.support import (
    SupportConfig,
    extract_support,
    find_supports,
    support_scores,
)
from pair2scene.scene.geometry import OrientedBox
from pair2scene.scene.model import FLOOR, Room, Scene, SceneObject

ROOM = Room("living_room", np.array([[0.0, 0.0], [5.0, 0.0], [5.0, 4.0], [0.0, 4.0]]))


def obj(oid: str, cat: str, center, size, yaw: float = 0.0, **kw) -> SceneObject:
    return SceneObject(oid, cat, OrientedBox.from_yaw(center, size, yaw), **kw)


def on(z_bottom: float, size) -> float:
    """Centre height of a box of ``size`` whose bottom is at ``z_bottom``."""
    return z_bottom + size[2] / 2


def supports(objects, **kw) -> dict[str, str | None]:
    return find_supports(Scene("test/room", ROOM, objects), **kw)


def test_book_on_second_tier_of_a_bookcase_is_on_the_bookcase():
    case = (0.9, 0.35, 1.6)
    book = (0.2, 0.15, 0.25)
    found = supports(
        [
            obj("shelving_unit_0", "shelving_unit", (1.0, 3.7, 0.8), case, yaw=np.pi),
            obj("book_0", "book", (1.1, 3.7, on(0.42, book)), book),
            obj("book_1", "book", (0.8, 3.7, on(0.82, book)), book),
        ]
    )
    assert found == {"shelving_unit_0": FLOOR, "book_0": "shelving_unit_0",
                     "book_1": "shelving_unit_0"}  # fmt: skip


def test_mug_on_a_table_and_chairs_tucked_under_it_on_the_floor():
    table = (1.2, 0.8, 0.75)
    chair = (0.45, 0.5, 0.9)  # its backrest rises above the table top
    mug = (0.08, 0.08, 0.1)
    plate = (0.22, 0.22, 0.02)
    found = supports(
        [
            obj("dining_table_0", "dining_table", (2.0, 2.0, on(0.0, table)), table),
            obj("chair_0", "chair", (2.0, 1.75, on(-0.004, chair)), chair),
            obj("mug_0", "mug", (1.7, 2.1, on(0.75, mug)), mug),
            # a plate at the table's edge, over the tucked-in chair's backrest
            obj("plate_0", "plate", (2.0, 1.7, on(0.745, plate)), plate),
            obj("apple_0", "apple", (2.0, 1.7, on(0.765, mug)), mug),
        ]
    )
    assert found["dining_table_0"] == FLOOR
    assert found["chair_0"] == FLOOR
    assert found["mug_0"] == "dining_table_0"
    assert found["plate_0"] == "dining_table_0"
    assert found["apple_0"] == "plate_0"  # a plate carries what lies on it


def test_painting_on_a_wall_is_unsupported_and_curtains_stand_on_the_floor():
    dresser = (1.0, 0.5, 0.8)
    painting = (0.8, 0.03, 0.6)
    curtains = (1.2, 0.1, 2.2)
    found = supports(
        [
            obj("dresser_0", "dresser", (2.5, 3.74, on(0.0, dresser)), dresser, yaw=np.pi),
            obj("painting_0", "painting", (2.5, 3.98, on(1.2, painting)), painting, yaw=np.pi),
            obj("curtains_0", "curtains", (4.0, 3.94, on(0.03, curtains)), curtains),
        ]
    )
    assert found["painting_0"] is None
    assert found["curtains_0"] == FLOOR


def test_parts_belong_to_their_owner_and_carry_for_it():
    dresser = (1.0, 0.5, 0.8)
    drawer = (0.9, 0.45, 0.2)
    spoon = (0.03, 0.18, 0.02)
    found = supports(
        [
            obj("dresser_0", "dresser", (2.0, 1.0, on(0.0, dresser)), dresser),
            obj("drawer_0", "drawer", (2.0, 1.02, on(0.5, drawer)), drawer),
            obj("spoon_0", "spoon", (2.1, 1.0, on(0.52, spoon)), spoon),
        ]
    )
    assert found == {"dresser_0": FLOOR, "drawer_0": "dresser_0", "spoon_0": "dresser_0"}


def test_towel_hangs_from_its_rail_and_pot_sits_on_a_small_burner():
    rail = (0.6, 0.08, 0.04)
    towel = (0.5, 0.06, 0.55)
    burner = (0.2, 0.2, 0.03)
    pot = (0.3, 0.3, 0.15)
    found = supports(
        [
            obj("towel_holder_0", "towel_holder", (1.0, 3.95, 1.2), rail),
            obj("towel_0", "towel", (1.0, 3.95, 1.2 + 0.02 - 0.55 / 2), towel),
            obj("stove_0", "stove", (3.0, 3.7, on(0.9, burner)), burner),
            obj("pot_0", "pot", (3.1, 3.7, on(0.93, pot)), pot),
        ]
    )
    assert found["towel_0"] == "towel_holder_0"
    assert found["pot_0"] == "stove_0"


def test_extract_support_ignores_the_annotations_and_keeps_them():
    table = (1.0, 0.6, 0.7)
    cup = (0.08, 0.08, 0.1)
    objects = [
        obj("coffee_table_0", "coffee_table", (2.0, 2.0, on(0.0, table)), table),
        obj("cup_0", "cup", (2.0, 2.0, on(0.7, cup)), cup),
    ]
    wrong = [replace(o, support="cup_0", source_support="cup_0") for o in objects]
    out = extract_support(Scene("test/room", ROOM, wrong))
    assert [o.support for o in out.objects] == [FLOOR, "coffee_table_0"]
    assert [o.source_support for o in out.objects] == ["cup_0", "cup_0"]
    assert [o.support for o in wrong] == ["cup_0", "cup_0"]  # the input is not changed


def test_config_thresholds_are_used():
    table = (1.0, 0.6, 0.7)
    book = (0.2, 0.15, 0.03)
    objects = [
        obj("desk_0", "desk", (2.0, 2.0, on(0.0, table)), table),
        obj("book_0", "book", (2.0, 2.0, on(0.8, book)), book),  # 10 cm above (a stack)
    ]
    assert supports(objects)["book_0"] == "desk_0"
    assert supports(objects, config=SupportConfig(max_gap_m=0.05))["book_0"] is None


def test_support_scores_counts_floor_edges_only_when_asked():
    table = (1.0, 0.6, 0.7)
    cup = (0.08, 0.08, 0.1)
    objects = [
        obj("desk_0", "desk", (2.0, 2.0, on(0.0, table)), table, source_support=FLOOR,
            support=FLOOR),
        obj("cup_0", "cup", (2.0, 2.0, on(0.7, cup)), cup, source_support="desk_0",
            support=FLOOR),
        obj("cup_1", "cup", (2.2, 2.0, on(0.7, cup)), cup, source_support="desk_0",
            support="desk_0"),
        obj("cup_2", "cup", (2.4, 2.0, on(0.7, cup)), cup, source_support=None,
            support="desk_0"),  # unannotated: not scored
    ]  # fmt: skip
    scene = Scene("test/room", ROOM, objects)
    s = support_scores([scene])
    assert (s.n_true, s.n_pred, s.n_correct) == (3, 3, 2)
    assert s.f1 == pytest.approx(2 / 3)
    assert [e.object_id for e in s.errors] == ["cup_0"]
    s = support_scores([scene], include_floor=False)
    assert (s.n_true, s.n_pred, s.n_correct) == (2, 1, 1)
    assert (s.precision, s.recall) == (1.0, 0.5)


def test_ai2thor_val_f1(ai2thor_corpus):
    scenes = [extract_support(s) for s in ai2thor_corpus.scenes if s.split == "val"]
    assert len(scenes) == 35
    scores = support_scores(scenes)
    assert scores.n_true > 900
    assert scores.f1 >= 0.95, scores  # measured 0.969
    assert support_scores(scenes, include_floor=False).f1 >= 0.95  # measured 0.973


@pytest.mark.shared_data
def test_procthor_val_f1(procthor_1k):
    from pair2scene.data.procthor import load_procthor

    corpus = load_procthor(procthor_1k / "val.jsonl.gz")
    scores = support_scores([extract_support(s) for s in corpus.scenes])
    assert scores.n_true > 2000
    assert scores.f1 >= 0.99, scores  # measured 0.9955

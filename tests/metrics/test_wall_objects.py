"""The ``walls`` section of the evaluation: wall objects and windows per room, and each
wall category's share, on hand-built rooms with known answers."""

from __future__ import annotations

import numpy as np
import pytest

from pair2scene.evaluate import SECTIONS, section_rows
from pair2scene.metrics.wall_objects import WALL_CATEGORIES, wall_report, wall_section
from pair2scene.scene.geometry import OrientedBox
from pair2scene.scene.model import FLOOR, Opening, Room, Scene, SceneObject

SQUARE = np.array([[0, 0], [4, 0], [4, 4], [0, 4]], float)
WINDOW = Opening("window", (4.0, 1.0), (4.0, 2.2), 0.9, 2.1)


def _obj(oid: str, category: str, support=FLOOR, part_of=None) -> SceneObject:
    box = OrientedBox.from_yaw([1, 0.03, 1.5], [0.6, 0.05, 0.5])  # its back 5 mm off wall 0
    return SceneObject(oid, category, box, None, support, part_of=part_of)


def test_counts_per_room_and_shares():
    hung = Scene("a", Room("bedroom", SQUARE, windows=(WINDOW, WINDOW)), [
        _obj("bed_0", "bed"), _obj("painting_0", "painting", None),
        _obj("painting_1", "painting", None), _obj("curtains_0", "curtains", None),
        _obj("drawer_0", "drawer", "bed_0", part_of="bed_0"),  # a part: not counted
    ])  # fmt: skip
    bare = Scene("b", Room("bedroom", SQUARE), [_obj("bed_0", "bed"), _obj("mug_0", "mug")])
    report = wall_report([hung, bare])
    assert report["wall_objects_per_room"] == {"rate": 1.5, "count": [3, 2], "rooms": 2}
    assert report["windows_per_room"]["rate"] == 1.0
    assert report["wall_share/painting"]["count"] == [2, 6]  # of 6 objects, parts left out
    assert report["wall_share/curtains"]["rate"] == pytest.approx(1 / 6)
    assert {f"wall_share/{c}" for c in WALL_CATEGORIES} <= report.keys()
    assert wall_report([])["wall_objects_per_room"]["rate"] is None


def test_the_walls_section_is_in_the_report_side_by_side():
    real = [Scene("r", Room("bedroom", SQUARE, windows=(WINDOW,)),
                  [_obj("bed_0", "bed"), _obj("mirror_0", "mirror", None)])]  # fmt: skip
    gen = [Scene("g", Room("bedroom", SQUARE), [_obj("bed_0", "bed")])]
    assert SECTIONS["walls"] is not None
    rows = {m: (g, r) for m, g, r in section_rows(wall_section(real, gen))}
    g, r = rows["wall_objects_per_room"]
    assert (g["rate"], r["rate"]) == (0.0, 1.0)
    assert rows["wall_share/mirror"][1]["rate"] == 0.5

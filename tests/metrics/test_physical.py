"""Mesh-level collision and floating metrics on scenes with known answers."""

from __future__ import annotations

import numpy as np
import pytest

from pair2scene.assets.mesh import Asset, Part, box
from pair2scene.metrics.physical import floating, intersecting, physical_report
from pair2scene.scene.geometry import OrientedBox
from pair2scene.scene.model import FLOOR, Room, Scene, SceneObject

ROOM = Room("bedroom", np.array([[0, 0], [5, 0], [5, 4], [0, 4]], float), 2.7)


def cube(size) -> Asset:
    return Asset("box", np.asarray(size, float), (Part("b", box([0, 0, 0], size)),))


def scene_of(*objs: tuple[str, list, list, str]) -> tuple[Scene, dict]:
    objects, assets = [], {}
    for oid, center, size, support in objs:
        objects.append(SceneObject(oid, "box", OrientedBox.from_yaw(center, size), support=support))
        assets[oid] = cube(size)
    return Scene("s", ROOM, objects), assets


def test_one_known_collision_and_one_floating_object():
    scene, assets = scene_of(
        ("a", [1.0, 1.0, 0.5], [1, 1, 1], FLOOR),
        ("b", [1.95, 1.0, 0.5], [1, 1, 1], FLOOR),  # 5 cm into a
        ("c", [4.0, 3.0, 0.25], [0.5, 0.5, 0.5], FLOOR),
        ("d", [4.0, 3.0, 0.58], [0.1, 0.1, 0.1], "c"),  # 3 cm above c's top
        ("e", [1.0, 1.0, 1.05], [0.1, 0.1, 0.1], "a"),  # resting on a
    )
    inter = intersecting(scene, assets)
    assert set(inter) == {"a", "b"} and inter["a"][0] == "b"
    assert inter["a"][1] == pytest.approx(0.05, abs=1e-3)
    assert set(floating(scene, assets)) == {"d"}
    report = physical_report(scene, assets)
    assert report["collision_rate"] == pytest.approx(2 / 5)
    assert report["floating_rate"] == pytest.approx(1 / 5)


def test_touching_is_not_colliding_and_a_raised_floor_object_floats():
    scene, assets = scene_of(
        ("a", [1.0, 1.0, 0.5], [1, 1, 1], FLOOR),
        ("b", [2.001, 1.0, 0.5], [1, 1, 1], FLOOR),  # 1 mm apart
        ("c", [4.0, 3.0, 0.27], [0.5, 0.5, 0.5], FLOOR),  # 2 cm up
    )
    assert intersecting(scene, assets) == {}
    assert set(floating(scene, assets)) == {"c"}


def test_stability_counts_what_falls_or_topples():
    from pair2scene.metrics.physical import stability

    scene, assets = scene_of(
        ("table", [1.0, 1.0, 0.4], [1, 1, 0.8], FLOOR),
        ("cup", [1.0, 1.0, 0.85], [0.1, 0.1, 0.1], "table"),  # resting: stays
        ("held", [3.0, 2.0, 0.6], [0.2, 0.2, 0.2], FLOOR),  # 0.5 m up: falls
        # a tall thin slab on a corner of the table, mostly over the edge: topples off
        ("slab", [1.55, 1.0, 0.95], [0.2, 0.05, 0.3], "table"),
    )
    motion, notes = stability(scene, assets)
    assert not notes
    assert set(motion) == {"table", "cup", "held", "slab"}
    assert motion["table"] < 0.02 and motion["cup"] < 0.02
    assert motion["held"] > 0.4 and motion["slab"] > 0.05
    report = physical_report(scene, assets)
    assert report["stability"] == pytest.approx(2 / 4)
    assert set(report["unstable"]) == {"held", "slab"}
    assert physical_report(scene, assets, simulate=False).keys() >= {"collision_rate"}


def test_a_thin_object_on_a_thin_support_is_not_floating():
    # a 4 mm card resting on a 6 mm slab: lowered 1 cm in one jump it would pass through
    scene, assets = scene_of(
        ("slab", [1.0, 1.0, 0.5], [0.3, 0.3, 0.006], FLOOR),
        ("card", [1.0, 1.0, 0.505], [0.09, 0.05, 0.004], "slab"),
        ("high", [1.5, 1.5, 0.5], [0.3, 0.3, 0.006], FLOOR),
        ("above", [1.5, 1.5, 0.52], [0.09, 0.05, 0.004], "high"),  # 1.5 cm up
    )
    assert set(floating(scene, assets)) == {"slab", "high", "above"}  # the slabs hang mid-air

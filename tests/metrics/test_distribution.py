"""Category KL and relative-pose MMD on sets with known answers."""

from __future__ import annotations

import numpy as np
import pytest

from pair2scene.metrics.distribution import category_kl, mmd2, pose_mmd, relative_poses
from pair2scene.scene.geometry import OrientedBox
from pair2scene.scene.model import FLOOR, Room, Scene, SceneObject

ROOM = Room("bedroom", np.array([[0, 0], [4, 0], [4, 4], [0, 4]], float), 2.7)


def obj(oid, cat, center, size, support=FLOOR, yaw=0.0, functional=None) -> SceneObject:
    return SceneObject(oid, cat, OrientedBox.from_yaw(center, size, yaw), support=support,
                       functional_anchor=functional)  # fmt: skip


def bedroom(i: int, book_dx: float = 0.0) -> Scene:
    """A bed and a nightstand (rotated by 90 degrees) with a book on it."""
    objs = [
        obj("bed", "bed", [2, 2, 0.3], [1.6, 2.0, 0.6]),
        obj("ns", "nightstand", [0.5, 1, 0.3], [0.5, 0.4, 0.6], yaw=np.pi / 2),
        obj("book", "book", [0.5 + 0.01 * (i % 3), 1 + book_dx, 0.62], [0.2, 0.15, 0.04], "ns"),
    ]
    return Scene(f"s{i}", ROOM, objs)


def test_kl_is_zero_for_identical_sets_and_known_otherwise():
    a = [bedroom(i) for i in range(4)]
    assert category_kl(a, a) == pytest.approx(0.0, abs=1e-9)
    # generated: only beds and nightstands, one each: p = (1/3, 1/3, 1/3), q = (1/2, 1/2, ~0)
    b = [Scene("g", ROOM, bedroom(0).objects[:2])]
    expected = 2 * (1 / 3) * np.log((1 / 3) / 0.5) + (1 / 3) * np.log((1 / 3) / 1e-6)
    assert category_kl(a, b) == pytest.approx(expected, rel=1e-3)


def test_relative_pose_is_in_the_anchor_frame():
    poses = relative_poses([bedroom(0)])
    (book,) = poses[("nightstand", "book")]
    # the nightstand is turned by +90 degrees: world +x offset is its local -y
    np.testing.assert_allclose(book[:3], [0.0, 0.0, 0.32], atol=1e-9)
    np.testing.assert_allclose(book[3:], [np.cos(-np.pi / 2), np.sin(-np.pi / 2)], atol=1e-9)
    shifted = relative_poses([bedroom(0, book_dx=0.1)])[("nightstand", "book")][0]
    np.testing.assert_allclose(shifted[:3], [0.1, 0.0, 0.32], atol=1e-9)


def test_mmd_zero_for_identical_larger_when_shifted():
    rng = np.random.default_rng(0)
    x = rng.normal(size=(80, 3))
    assert mmd2(x, x) == pytest.approx(0.0, abs=1e-12)
    near = mmd2(x, rng.normal(size=(80, 3)))
    far = mmd2(x, rng.normal(size=(80, 3)) + 2.0)
    assert near < 0.05 < far
    ref = [bedroom(i) for i in range(6)]
    same = pose_mmd(ref, ref)
    assert same["mean"] == pytest.approx(0.0, abs=1e-12) and not same["missing"]
    moved = pose_mmd(ref, [bedroom(i, book_dx=0.15) for i in range(6)])
    assert moved["mean"] > 0.1
    none = pose_mmd(ref, [Scene("g", ROOM, bedroom(0).objects[:2])])
    assert none["missing"] == ["nightstand/book"] and none["mean"] == 2.0

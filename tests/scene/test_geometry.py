"""Rotations (matrix <-> 6D <-> yaw), oriented boxes and 2D polygon helpers."""

from __future__ import annotations

import numpy as np
import pytest

from pair2scene.scene.geometry import (
    UNIT_CORNERS,
    OrientedBox,
    corner_distance,
    euler_to_matrix,
    is_rotation,
    matrix_to_6d,
    matrix_to_yaw,
    orthonormalize,
    points_in_polygon,
    polygon_area,
    sixd_to_matrix,
    sixd_x_axis,
    yaw_to_matrix,
)

N = 500
EX, EY, EZ = np.eye(3)


def random_rotations(rng: np.random.Generator, n: int) -> np.ndarray:
    """(n, 3, 3) uniformly random proper rotations (QR of a Gaussian matrix, signs fixed)."""
    q, r = np.linalg.qr(rng.normal(size=(n, 3, 3)))
    q = q * np.sign(np.diagonal(r, axis1=-2, axis2=-1))[:, None, :]
    flip = np.linalg.det(q) < 0
    q[flip, :, 0] *= -1
    return q


def random_boxes(rng: np.random.Generator, n: int) -> list[OrientedBox]:
    centers = rng.uniform(-5, 5, size=(n, 3))
    sizes = rng.uniform(0.05, 3.0, size=(n, 3))
    rots = random_rotations(rng, n)
    return [OrientedBox(c, s, r) for c, s, r in zip(centers, sizes, rots, strict=True)]


def wrap(angle: np.ndarray) -> np.ndarray:
    """Angle difference wrapped to [-pi, pi)."""
    return (np.asarray(angle) + np.pi) % (2 * np.pi) - np.pi


def assert_rotations(r: np.ndarray, atol: float = 1e-9) -> None:
    eye = np.broadcast_to(np.eye(3), r.shape)
    np.testing.assert_allclose(np.swapaxes(r, -1, -2) @ r, eye, atol=atol)
    np.testing.assert_allclose(np.linalg.det(r), 1.0, atol=atol)


# -- the helper itself -----------------------------------------------------------------
def test_random_rotations_are_rotations():
    r = random_rotations(np.random.default_rng(0), N)
    assert r.shape == (N, 3, 3)
    assert_rotations(r, atol=1e-12)
    assert all(is_rotation(m) for m in r)


# -- yaw -------------------------------------------------------------------------------
def test_yaw_known_values():
    r = yaw_to_matrix(np.pi / 2)
    np.testing.assert_allclose(r @ EX, EY, atol=1e-12)  # +x -> +y (counter-clockwise)
    np.testing.assert_allclose(r @ EY, -EX, atol=1e-12)
    np.testing.assert_allclose(r @ EZ, EZ, atol=1e-12)
    np.testing.assert_allclose(yaw_to_matrix(0.0), np.eye(3))
    np.testing.assert_allclose(yaw_to_matrix(np.pi) @ EX, -EX, atol=1e-12)
    assert matrix_to_yaw(yaw_to_matrix(np.pi / 2)) == pytest.approx(np.pi / 2)
    assert matrix_to_yaw(np.eye(3)) == 0.0


def test_yaw_matrix_yaw_round_trip_batched():
    rng = np.random.default_rng(1)
    yaws = rng.uniform(-np.pi, np.pi, size=(20, 25))
    r = yaw_to_matrix(yaws)
    assert r.shape == (20, 25, 3, 3)
    assert_rotations(r, atol=1e-12)
    back = matrix_to_yaw(r)
    assert back.shape == (20, 25)
    np.testing.assert_allclose(back, yaws, atol=1e-12)
    assert np.all((back > -np.pi) & (back <= np.pi))


def test_one_yaws_matrix_is_the_general_paths_bit_for_bit():
    """One float's matrix is built without np.stack (placement asks for thousands a
    scene), in the same numbers as the general path gives a 0-d yaw."""
    rng = np.random.default_rng(4)
    for yaw in [*rng.uniform(-20, 20, 500), 0.0, -0.0, np.pi, -np.pi / 2, 1e-300]:
        fast, general = yaw_to_matrix(float(yaw)), yaw_to_matrix(np.asarray(yaw))
        assert fast.shape == general.shape == (3, 3) and fast.dtype == general.dtype
        assert fast.tobytes() == general.tobytes()
    assert yaw_to_matrix(np.float64(0.3)).tobytes() == yaw_to_matrix(np.asarray(0.3)).tobytes()


def test_sixd_x_axis_is_the_matrix_first_column_bit_for_bit():
    """A drawn candidate is turned upright from its x axis alone: the same numbers as the
    whole rotation's first column, batched or one at a time."""
    rng = np.random.default_rng(5)
    v = rng.normal(size=(300, 6)) * rng.uniform(0.01, 10, size=(300, 1))
    column = np.ascontiguousarray(sixd_to_matrix(v)[..., :, 0])
    assert sixd_x_axis(v).tobytes() == column.tobytes()
    for row in v[:50]:
        one = np.ascontiguousarray(sixd_to_matrix(row)[:, 0])
        assert sixd_x_axis(row).tobytes() == one.tobytes()


def test_yaw_wraps_angles_outside_pi():
    rng = np.random.default_rng(2)
    yaws = rng.uniform(-20, 20, size=N)
    back = matrix_to_yaw(yaw_to_matrix(yaws))
    np.testing.assert_allclose(wrap(back - yaws), 0.0, atol=1e-9)


def test_matrix_to_yaw_of_tilted_rotation_is_heading_of_projected_x():
    rng = np.random.default_rng(3)
    r = random_rotations(rng, N)
    yaw = matrix_to_yaw(r)
    # Undoing the yaw puts the projected x axis on world +x.
    x_unyawed = np.einsum("nji,nj->ni", yaw_to_matrix(yaw), r[:, :, 0])
    np.testing.assert_allclose(x_unyawed[:, 1], 0.0, atol=1e-9)
    assert np.all(x_unyawed[:, 0] >= -1e-12)


# -- 6D --------------------------------------------------------------------------------
def test_6d_is_first_two_columns():
    r = random_rotations(np.random.default_rng(4), 10)
    sixd = matrix_to_6d(r)
    assert sixd.shape == (10, 6)
    np.testing.assert_array_equal(sixd[:, :3], r[:, :, 0])
    np.testing.assert_array_equal(sixd[:, 3:], r[:, :, 1])
    np.testing.assert_array_equal(matrix_to_6d(np.eye(3)), [1, 0, 0, 0, 1, 0])


def test_matrix_6d_matrix_round_trip_exact():
    r = random_rotations(np.random.default_rng(5), N)
    back = sixd_to_matrix(matrix_to_6d(r))
    assert back.shape == (N, 3, 3)
    np.testing.assert_allclose(back, r, atol=1e-12)


def test_6d_round_trip_keeps_leading_dims():
    r = random_rotations(np.random.default_rng(6), 24).reshape(4, 6, 3, 3)
    sixd = matrix_to_6d(r)
    assert sixd.shape == (4, 6, 6)
    np.testing.assert_allclose(sixd_to_matrix(sixd), r, atol=1e-12)


def test_6d_is_scale_invariant_per_column():
    rng = np.random.default_rng(7)
    r = random_rotations(rng, N)
    sixd = matrix_to_6d(r)
    k = rng.uniform(0.1, 10.0, size=(N, 2))
    scaled = np.concatenate([sixd[:, :3] * k[:, :1], sixd[:, 3:] * k[:, 1:]], axis=-1)
    np.testing.assert_allclose(sixd_to_matrix(scaled), r, atol=1e-12)


def test_6d_of_noisy_vectors_is_a_proper_rotation():
    rng = np.random.default_rng(8)
    sixd = rng.normal(size=(N, 6)) * rng.uniform(0.01, 100.0, size=(N, 1))
    r = sixd_to_matrix(sixd)
    assert_rotations(r, atol=1e-9)
    assert all(is_rotation(m) for m in r)
    a, b = sixd[:, :3], sixd[:, 3:]
    # Gram-Schmidt: column 0 along a; column 1 in span(a, b) on b's side of a.
    np.testing.assert_allclose(r[:, :, 0], a / np.linalg.norm(a, axis=1, keepdims=True))
    np.testing.assert_allclose(np.einsum("ni,ni->n", r[:, :, 1], np.cross(a, b)), 0, atol=1e-9)
    assert np.all(np.einsum("ni,ni->n", r[:, :, 1], b) > 0)


def test_6d_of_slightly_perturbed_rotation_stays_close():
    rng = np.random.default_rng(9)
    r = random_rotations(rng, N)
    noisy = matrix_to_6d(r) + rng.normal(scale=1e-4, size=(N, 6))
    back = sixd_to_matrix(noisy)
    assert_rotations(back, atol=1e-9)
    np.testing.assert_allclose(back, r, atol=1e-3)


# -- Euler -----------------------------------------------------------------------------
def test_euler_single_axes_are_right_handed():
    q = np.pi / 2
    np.testing.assert_allclose(euler_to_matrix([q, 0, 0], "x") @ EY, EZ, atol=1e-12)
    np.testing.assert_allclose(euler_to_matrix([0, q, 0], "y") @ EZ, EX, atol=1e-12)
    np.testing.assert_allclose(euler_to_matrix([0, 0, q], "z") @ EX, EY, atol=1e-12)
    np.testing.assert_allclose(euler_to_matrix([0, 0, 0.3], "z"), yaw_to_matrix(0.3))
    np.testing.assert_allclose(euler_to_matrix([0.1, 0.2, 0.3], ""), np.eye(3))


def test_euler_first_letter_is_applied_first():
    q = np.pi / 2
    # "xz": +y -> (x by 90) +z -> (z by 90) +z.   "zx": +y -> (z by 90) -x -> (x by 90) -x.
    np.testing.assert_allclose(euler_to_matrix([q, 0, q], "xz") @ EY, EZ, atol=1e-12)
    np.testing.assert_allclose(euler_to_matrix([q, 0, q], "zx") @ EY, -EX, atol=1e-12)


def test_euler_order_composition_random():
    rng = np.random.default_rng(10)
    for angles in rng.uniform(-np.pi, np.pi, size=(50, 3)):
        rx = euler_to_matrix([angles[0], 0, 0], "x")
        ry = euler_to_matrix([0, angles[1], 0], "y")
        rz = euler_to_matrix([0, 0, angles[2]], "z")
        np.testing.assert_allclose(euler_to_matrix(angles, "zxy"), ry @ rx @ rz, atol=1e-12)
        np.testing.assert_allclose(euler_to_matrix(angles, "xyz"), rz @ ry @ rx, atol=1e-12)
        np.testing.assert_allclose(euler_to_matrix(angles, "yxz"), rz @ rx @ ry, atol=1e-12)
        assert is_rotation(euler_to_matrix(angles, "zxy"))
        # Only the per-axis angle is read, never another axis' angle.
        np.testing.assert_allclose(rx, euler_to_matrix([angles[0], 9.0, 9.0], "x"))


# -- is_rotation / orthonormalize ------------------------------------------------------
def test_is_rotation_rejects_non_rotations():
    assert is_rotation(np.eye(3))
    assert not is_rotation(np.diag([1.0, 1.0, -1.0]))  # reflection
    assert not is_rotation(2 * np.eye(3))
    assert not is_rotation(np.eye(3) + 1e-3)
    assert not is_rotation(np.eye(2))
    bad = np.eye(3)
    bad[0, 0] = np.nan
    assert not is_rotation(bad)
    assert is_rotation(np.eye(3) + 1e-7)  # float32-rounded files pass


def test_orthonormalize_projects_to_nearest_rotation():
    rng = np.random.default_rng(11)
    for r in random_rotations(rng, 50):
        noisy = r + rng.normal(scale=1e-3, size=(3, 3))
        fixed = orthonormalize(noisy)
        assert is_rotation(fixed, atol=1e-9)
        np.testing.assert_allclose(fixed, r, atol=1e-2)
        np.testing.assert_allclose(orthonormalize(r), r, atol=1e-12)


# -- OrientedBox -----------------------------------------------------------------------
def test_box_corners_axis_aligned_known_values():
    box = OrientedBox([1.0, 2.0, 3.0], [2.0, 4.0, 6.0])
    c = box.corners()
    assert c.shape == (8, 3)
    np.testing.assert_allclose(c, [1, 2, 3] + UNIT_CORNERS * [1, 2, 3])
    np.testing.assert_allclose(c[0], [0, 0, 0])
    np.testing.assert_allclose(c[6], [2, 4, 6])
    # Bottom face first (z min), counter-clockwise seen from above, then the top face.
    assert np.all(c[:4, 2] == 0) and np.all(c[4:, 2] == 6)
    assert polygon_area(c[:4, :2]) > 0
    np.testing.assert_allclose(c[4:, :2], c[:4, :2])


def test_box_corners_yaw_90():
    box = OrientedBox.from_yaw([0, 0, 0.5], [2.0, 1.0, 1.0], np.pi / 2)
    c = box.corners()
    np.testing.assert_allclose(c[1] - c[0], [0, 2, 0], atol=1e-12)  # local +x is world +y
    np.testing.assert_allclose(c[3] - c[0], [-1, 0, 0], atol=1e-12)  # local +y is world -x
    np.testing.assert_allclose(c[4] - c[0], [0, 0, 1], atol=1e-12)
    assert box.yaw == pytest.approx(np.pi / 2)


def test_box_corner_edges_match_size_for_random_boxes():
    for box in random_boxes(np.random.default_rng(12), 100):
        c = box.corners()
        edges = np.linalg.norm(c[[1, 3, 4]] - c[0], axis=1)
        np.testing.assert_allclose(edges, box.size, atol=1e-9)
        np.testing.assert_allclose(c.mean(axis=0), box.center, atol=1e-9)
        np.testing.assert_allclose((c[1] - c[0]) / box.size[0], box.rotation[:, 0], atol=1e-9)
        np.testing.assert_allclose((c[3] - c[0]) / box.size[1], box.rotation[:, 1], atol=1e-9)


def test_to_world_to_local_inverse():
    rng = np.random.default_rng(13)
    for box in random_boxes(rng, 50):
        pts = rng.normal(size=(20, 3))
        np.testing.assert_allclose(box.to_local(box.to_world(pts)), pts, atol=1e-9)
        np.testing.assert_allclose(box.to_world(box.to_local(pts)), pts, atol=1e-9)
        np.testing.assert_allclose(box.to_world(np.zeros((1, 3))), [box.center], atol=1e-12)


def test_to_world_known_value():
    box = OrientedBox.from_yaw([1.0, 0.0, 0.0], [1, 1, 1], np.pi / 2)
    np.testing.assert_allclose(box.to_world([[1.0, 0.0, 0.0]]), [[1.0, 1.0, 0.0]], atol=1e-12)
    np.testing.assert_allclose(box.to_local([[1.0, 1.0, 0.0]]), [[1.0, 0.0, 0.0]], atol=1e-12)


def test_aabb():
    box = OrientedBox.from_yaw([1.0, 2.0, 3.0], [2.0, 4.0, 6.0], np.pi / 2)
    lo, hi = box.aabb()
    np.testing.assert_allclose(lo, [-1, 1, 0], atol=1e-12)
    np.testing.assert_allclose(hi, [3, 3, 6], atol=1e-12)
    assert box.bottom == pytest.approx(0.0)
    assert box.top == pytest.approx(6.0)
    lo, hi = OrientedBox.from_yaw([0, 0, 0], [2.0, 2.0, 2.0], np.pi / 4).aabb()
    np.testing.assert_allclose(hi, [np.sqrt(2), np.sqrt(2), 1.0], atol=1e-12)
    np.testing.assert_allclose(lo, -hi, atol=1e-12)


def test_aabb_equals_corner_bounds_for_random_boxes():
    for box in random_boxes(np.random.default_rng(14), 100):
        lo, hi = box.aabb()
        c = box.corners()
        np.testing.assert_allclose(lo, c.min(axis=0), atol=1e-9)
        np.testing.assert_allclose(hi, c.max(axis=0), atol=1e-9)


def test_contains():
    box = OrientedBox.from_yaw([1.0, 1.0, 0.5], [2.0, 1.0, 1.0], np.pi / 2)
    # Local x runs along world y: the box spans y in [0, 2], x in [0.5, 1.5].
    pts = [[1.0, 1.0, 0.5], [1.0, 1.9, 0.5], [1.4, 1.0, 0.5], [1.9, 1.0, 0.5], [1.0, 1.0, 1.1]]
    np.testing.assert_array_equal(box.contains(pts), [True, True, True, False, False])
    np.testing.assert_array_equal(box.contains(pts, margin=0.5), [True] * 5)
    assert box.contains([1.0, 1.0, 0.5]).shape == (1,)
    assert np.all(box.contains(box.corners(), margin=1e-9))
    assert not np.any(box.contains(box.corners() + 10.0))


def test_contains_random_local_points():
    rng = np.random.default_rng(15)
    for box in random_boxes(rng, 30):
        local = rng.uniform(-1, 1, size=(50, 3))
        inside = box.to_world(local * 0.99 * box.half_size)
        outside = box.to_world(
            local / np.abs(local).max(axis=1, keepdims=True) * 1.01 * box.half_size
        )
        assert np.all(box.contains(inside))
        assert not np.any(box.contains(outside))


def test_anchor_in_its_own_frame_is_the_unit_cube():
    for anchor in random_boxes(np.random.default_rng(16), 50):
        canon = anchor.in_frame_of(anchor)
        np.testing.assert_allclose(canon.center, 0.0, atol=1e-9)
        np.testing.assert_allclose(canon.size, 2.0, atol=1e-9)
        np.testing.assert_allclose(canon.rotation, np.eye(3), atol=1e-9)
        np.testing.assert_allclose(canon.corners(), UNIT_CORNERS, atol=1e-9)


def test_in_frame_of_from_frame_of_round_trip():
    rng = np.random.default_rng(17)
    boxes = random_boxes(rng, 100)
    for anchor, box in zip(boxes[::2], boxes[1::2], strict=True):
        canon = box.in_frame_of(anchor)
        assert is_rotation(canon.rotation)
        assert canon.from_frame_of(anchor).allclose(box, atol=1e-9)
        # Rotation-free part of the map: anchor-local coordinates divided by half-size.
        np.testing.assert_allclose(
            canon.center, anchor.to_local([box.center])[0] / anchor.half_size, atol=1e-9
        )


def test_in_frame_of_known_value():
    anchor = OrientedBox.from_yaw([1.0, 0.0, 0.0], [2.0, 2.0, 2.0], np.pi / 2)
    box = OrientedBox.from_yaw([1.0, 1.0, 0.0], [1.0, 0.5, 0.2], np.pi / 2)
    canon = box.in_frame_of(anchor)
    np.testing.assert_allclose(canon.center, [1.0, 0.0, 0.0], atol=1e-12)  # anchor's right face
    np.testing.assert_allclose(canon.size, [1.0, 0.5, 0.2], atol=1e-12)
    np.testing.assert_allclose(canon.rotation, np.eye(3), atol=1e-12)


def test_to_vector_from_vector_round_trip():
    for box in random_boxes(np.random.default_rng(18), 100):
        vec = box.to_vector()
        assert vec.shape == (12,)
        np.testing.assert_array_equal(vec[:3], box.center)
        np.testing.assert_array_equal(vec[3:6], box.size)
        assert OrientedBox.from_vector(vec).allclose(box, atol=1e-12)


def test_from_transform_and_transform():
    for box in random_boxes(np.random.default_rng(19), 20):
        t = box.transform
        np.testing.assert_array_equal(t[3], [0, 0, 0, 1])
        assert OrientedBox.from_transform(t, box.size).allclose(box, atol=0)


def test_box_validates_shapes_and_is_read_only():
    with pytest.raises(ValueError, match="center"):
        OrientedBox([0.0, 0.0], [1.0, 1.0, 1.0])
    with pytest.raises(ValueError, match="rotation"):
        OrientedBox([0.0, 0.0, 0.0], [1.0, 1.0, 1.0], np.eye(2))
    src = np.array([1.0, 2.0, 3.0])
    box = OrientedBox(src, [1.0, 1.0, 1.0])
    src[0] = 99.0  # the box keeps its own copy
    assert box.center[0] == 1.0
    with pytest.raises(ValueError):
        box.center[0] = 5.0
    np.testing.assert_array_equal(box.rotation, np.eye(3))
    np.testing.assert_array_equal(box.half_size, [0.5, 0.5, 0.5])


def test_allclose():
    a = OrientedBox.from_yaw([0, 0, 0], [1, 1, 1], 0.3)
    assert a.allclose(OrientedBox.from_yaw([0, 0, 1e-8], [1, 1, 1], 0.3))
    assert not a.allclose(OrientedBox.from_yaw([0, 0, 0], [1, 1, 1], 0.31))
    assert not a.allclose(OrientedBox.from_yaw([0, 0, 0], [1, 1, 1.1], 0.3))
    assert "OrientedBox(" in repr(a)


# -- corner_distance -------------------------------------------------------------------
def test_corner_distance_is_order_free():
    rng = np.random.default_rng(20)
    for box in random_boxes(rng, 20):
        c = box.corners()
        assert corner_distance(c, c[rng.permutation(8)]) == pytest.approx(0.0, abs=1e-12)
        shift = np.array([0.0, 0.03, -0.04])
        assert corner_distance(c, c[rng.permutation(8)] + shift) == pytest.approx(0.05)


def test_corner_distance_is_symmetric_and_takes_the_worst_corner():
    a = OrientedBox([0, 0, 0], [2, 2, 2]).corners()
    b = a.copy()
    b[5] += [0.0, 0.0, 0.3]
    assert corner_distance(a, b) == pytest.approx(0.3)
    assert corner_distance(b, a) == pytest.approx(0.3)


# -- polygons --------------------------------------------------------------------------
SQUARE = [[0, 0], [1, 0], [1, 1], [0, 1]]
L_SHAPE = [[0, 0], [2, 0], [2, 1], [1, 1], [1, 2], [0, 2]]


def test_polygon_area_sign():
    assert polygon_area(SQUARE) == pytest.approx(1.0)
    assert polygon_area(SQUARE[::-1]) == pytest.approx(-1.0)
    assert polygon_area(L_SHAPE) == pytest.approx(3.0)
    assert polygon_area(L_SHAPE[::-1]) == pytest.approx(-3.0)
    assert polygon_area([[0, 0], [1, 1], [2, 2]]) == pytest.approx(0.0)
    assert polygon_area(np.array(L_SHAPE) + [10.0, -7.0]) == pytest.approx(3.0)


@pytest.mark.parametrize("polygon", [L_SHAPE, L_SHAPE[::-1]], ids=["ccw", "cw"])
def test_points_in_l_shaped_polygon(polygon):
    pts = [
        [0.5, 0.5],  # corner square
        [1.5, 0.5],  # lower arm
        [0.5, 1.5],  # upper arm
        [1.5, 1.5],  # the notch
        [-0.5, 0.5],
        [2.5, 0.5],
        [0.5, 2.5],
        [0.5, -0.1],
    ]
    expected = [True, True, True, False, False, False, False, False]
    np.testing.assert_array_equal(points_in_polygon(pts, polygon), expected)
    assert points_in_polygon([0.5, 0.5], polygon).shape == (1,)


def test_points_in_l_shaped_polygon_random():
    rng = np.random.default_rng(21)
    pts = rng.uniform(-0.5, 2.5, size=(2000, 2))
    x, y = pts[:, 0], pts[:, 1]
    expected = ((0 < x) & (x < 2) & (0 < y) & (y < 1)) | ((0 < x) & (x < 1) & (0 < y) & (y < 2))
    np.testing.assert_array_equal(points_in_polygon(pts, L_SHAPE), expected)

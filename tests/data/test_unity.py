import numpy as np

from pair2scene.data import unity
from pair2scene.scene.geometry import is_rotation


def test_positions_swap_y_and_z():
    assert np.allclose(unity.vec({"x": 1.0, "y": 2.0, "z": 3.0}), [1.0, 3.0, 2.0])


def test_rotation_is_proper_for_random_euler_angles():
    rng = np.random.default_rng(0)
    for angles in rng.uniform(0, 360, size=(50, 3)):
        r = unity.rotation(dict(zip("xyz", angles)))
        assert is_rotation(r)


def test_unity_yaw_is_clockwise_seen_from_above():
    # Unity: Euler y = +90 turns forward (+z) into +x. In pair2scene the front
    # (+y local) must then point to world +x: a clockwise turn seen from above.
    r = unity.rotation({"x": 0.0, "y": 90.0, "z": 0.0})
    assert np.allclose(r[:, 1], [1.0, 0.0, 0.0], atol=1e-12)
    assert np.allclose(r[:, 2], [0.0, 0.0, 1.0], atol=1e-12)


def test_size_from_aabb_unmixes_a_yawed_box():
    rot = unity.rotation({"x": 0.0, "y": 30.0, "z": 0.0})
    size = np.array([1.2, 0.4, 0.8])
    aabb = np.abs(rot) @ size
    assert np.allclose(unity.size_from_aabb(aabb, rot), size)


def test_size_from_aabb_falls_back_at_45_degrees():
    rot = unity.rotation({"x": 0.0, "y": 45.0, "z": 0.0})
    aabb = np.array([1.0, 1.0, 0.5])
    assert np.allclose(unity.size_from_aabb(aabb, rot), aabb)


def test_fit_box_to_corners_is_tight():
    rot = unity.rotation({"x": 0.0, "y": 20.0, "z": 0.0})
    local = np.array([[x, y, z] for x in (-0.5, 0.5) for y in (-0.2, 0.2) for z in (0, 1)])
    world = local @ rot.T + [1.0, 2.0, 0.0]
    box = unity.fit_box_to_corners(world, rot)
    assert np.allclose(box.size, [1.0, 0.4, 1.0])
    assert np.allclose(box.center, [1.0, 2.0, 0.5])

"""Model inputs: the model frame, its Jacobians (checked numerically), clouds, room points."""

from __future__ import annotations

import numpy as np
import pytest

torch = pytest.importorskip("torch")

from pair2scene.curation.dataset import load_pairs  # noqa: E402
from pair2scene.model.features import (  # noqa: E402
    MIN_ANCHOR_HALF_M,
    box_of,
    dataset_features,
    frame_factor,
    from_model_frame,
    room_cloud,
    room_points,
    target_of,
    to_model_frame,
)
from pair2scene.model.mixture import (  # noqa: E402
    MixtureParams,  # noqa: E402
    condition,
    log_prob,
    logistic_log_pdf,
)
from pair2scene.scene.geometry import OrientedBox, matrix_to_6d, rot_z  # noqa: E402
from synthetic_pairs import write_synthetic_pairs  # noqa: E402


@pytest.fixture(scope="module")
def data(tmp_path_factory):
    return load_pairs(write_synthetic_pairs(tmp_path_factory.mktemp("pairs")))


def _log_abs_det(fn, x: np.ndarray, h: float = 1e-6) -> float:
    """log |det J| of fn at x by central differences."""
    jac = np.stack([(fn(x + h * e) - fn(x - h * e)) / (2 * h) for e in np.eye(len(x))], 1)
    return float(np.linalg.slogdet(jac)[1])


def test_frame_factor_floors_only_thin_axes():
    f = frame_factor(np.array([[1.2, 0.6, 0.017], [5.0, 4.0, 2.5]]))
    np.testing.assert_allclose(f[1], 1.0)
    np.testing.assert_allclose(f[0, :2], 1.0)
    assert f[0, 2] == pytest.approx(0.0085 / MIN_ANCHOR_HALF_M)


def test_model_frame_round_trip_and_target_round_trip():
    rng = np.random.default_rng(0)
    x = np.concatenate([rng.normal(size=3), rng.uniform(0.1, 3, 3), rng.normal(size=6)])
    f = np.array([1.0, 0.5, 0.17])
    np.testing.assert_allclose(from_model_frame(to_model_frame(x, f), f), x)
    np.testing.assert_allclose(box_of(target_of(x)), x)


def test_log_jacobian_of_the_model_frame_matches_finite_differences(data):
    # A thin support (a 2 cm slab): the model frame differs from the canonical one.
    slab = np.array([0.0, 0, 0.5, 1.0, 0.6, 0.02, *matrix_to_6d(rot_z(0.3))])
    cup = OrientedBox.from_yaw([0.1, 0.05, 0.56], [0.08, 0.08, 0.1], 0.7)
    x = cup.in_frame_of(OrientedBox.from_vector(slab)).to_vector()
    f = frame_factor(slab[3:6])

    def fn(v):
        return target_of(to_model_frame(v, f))

    expected = np.log(f).sum() - np.log(x[3:6]).sum()
    assert _log_abs_det(fn, x) == pytest.approx(expected, abs=1e-5)

    feats = dataset_features(data, "full", with_clouds=False).arrays
    for i in range(5):
        xi = data.canonical[i].astype(np.float64)
        fi = feats.factor[i]
        got = _log_abs_det(lambda v, fi=fi: target_of(to_model_frame(v, fi)), xi)
        assert feats.log_jacobian[i] == pytest.approx(got, abs=1e-4)
        np.testing.assert_allclose(feats.target[i], target_of(to_model_frame(xi, fi)), atol=1e-5)


def test_log_jacobian_of_global_matches_finite_differences(data):
    feats = dataset_features(data, "global", with_clouds=False).arrays
    for i in range(6):
        sup = OrientedBox.from_vector(data.support.box[i].astype(np.float64))

        def world_target(v, sup=sup):  # stored canonical vector -> world target
            box = np.concatenate([v[:3], v[3:6], v[6:12]])
            center = sup.rotation @ (box[:3] * sup.half_size) + sup.center
            size = box[3:6] * sup.half_size
            c0, c1 = sup.rotation @ box[6:9], sup.rotation @ box[9:12]
            return target_of(np.concatenate([center, size, c0, c1]))

        xi = data.canonical[i].astype(np.float64)
        got = _log_abs_det(world_target, xi)
        assert feats.log_jacobian[i] == pytest.approx(got, abs=1e-4)
        np.testing.assert_allclose(feats.target[i], world_target(xi), atol=1e-4)


def test_features_per_variant(data):
    full = dataset_features(data, "full")
    assert full.arrays.member_mask[:, :2].all()
    has_func = data.functional.category >= 0
    np.testing.assert_array_equal(full.arrays.member_mask[:, 2], has_func)
    assert (full.arrays.cloud_index[full.arrays.member_mask] >= 0).all()
    assert (full.arrays.cloud_index[~full.arrays.member_mask] == -1).all()
    rooms = [c for c in full.clouds if c.room]
    assert rooms and all(c.category == "floor" for c in rooms)
    assert dataset_features(data, "class-only").clouds == []
    glob = dataset_features(data, "global").arrays
    assert not glob.member_mask[:, 2].any()
    room_size = glob.anchor_boxes[:, 0, 3:6]
    np.testing.assert_allclose(room_size[:, :2], np.broadcast_to([5.0, 4.0], (len(data), 2)))


def test_room_points_lie_on_the_floor_and_walls():
    pts = room_points([5.0, 4.0, 2.5], 4000, 0)
    on_floor = np.isclose(pts[:, 2], -1.25)
    on_wall = np.isclose(np.abs(pts[:, 0]), 2.5) | np.isclose(np.abs(pts[:, 1]), 2.0)
    assert (on_floor | on_wall).all() and on_floor.any() and on_wall.any()
    # floor share ~ floor area / (floor + walls) = 20 / (20 + 45)
    assert on_floor.mean() == pytest.approx(20 / 65, abs=0.03)
    cloud = room_cloud([5.0, 4.0, 2.5], 512)
    assert cloud.shape == (512, 3) and np.linalg.norm(cloud, axis=1).max() <= 1.0 + 1e-6


def test_condition_is_bayes_on_the_given_dims():
    g = torch.Generator().manual_seed(0)
    params = MixtureParams(
        torch.randn(2, 3, generator=g, dtype=torch.float64),
        torch.randn(2, 3, 4, generator=g, dtype=torch.float64),
        torch.randn(2, 3, 4, generator=g, dtype=torch.float64) * 0.3,
    )
    values = torch.randn(2, 2, generator=g, dtype=torch.float64)
    cond = condition(params, [1, 3], values)
    # posterior weights: w_k p_k(values) / sum
    given = params.loc[..., [1, 3]], params.log_scale[..., [1, 3]]
    lp = logistic_log_pdf(values[:, None, :], *given)
    post = torch.softmax(params.logits + lp.sum(-1), -1)
    torch.testing.assert_close(torch.softmax(cond.logits, -1), post)
    # the free dims keep their per-component distributions
    torch.testing.assert_close(cond.loc[..., [0, 2]], params.loc[..., [0, 2]])
    # the density of the free dims given the values is p(all) / p(given)
    x = torch.randn(2, 4, generator=g, dtype=torch.float64)
    x[:, [1, 3]] = values
    free = MixtureParams(cond.logits, cond.loc[..., [0, 2]], cond.log_scale[..., [0, 2]])
    marg = MixtureParams(params.logits, params.loc[..., [1, 3]], params.log_scale[..., [1, 3]])
    torch.testing.assert_close(
        log_prob(free, x[:, [0, 2]]), log_prob(params, x) - log_prob(marg, values)
    )


def test_bearing_turns_a_chair_facing_its_table_to_yaw_zero():
    from pair2scene.model.features import from_bearing, to_bearing

    half = np.array([0.8, 0.5, 1.35])
    for pos, yaw in (
        ((0, -1.4), 0.0),
        ((1.5, 0), np.pi / 2),
        ((0, 1.4), np.pi),
        ((-1.5, 0), -np.pi / 2),
    ):
        chair = OrientedBox.from_yaw([pos[0] / half[0], pos[1] / half[1], -0.7], [0.5] * 3, yaw)
        rel = to_bearing(chair.to_vector(), half)
        np.testing.assert_allclose(rel[6:12], [1, 0, 0, 0, 1, 0], atol=1e-9)
        np.testing.assert_allclose(from_bearing(rel, half), chair.to_vector(), atol=1e-9)


def test_anchor_frames_keep_scores_densities_of_the_stored_vector(data):
    """Wall and functional frames: target and log Jacobian against finite differences of
    the map stored canonical vector -> the frame's model target."""
    from pair2scene.curation.frames import (
        FRAME_FUNCTIONAL,
        FRAME_SUPPORT,
        FRAME_WALL,
        tuple_frames,
    )

    kinds, frame_boxes = tuple_frames(data)
    assert {FRAME_WALL, FRAME_FUNCTIONAL, FRAME_SUPPORT} <= set(kinds.tolist())
    feats = dataset_features(data, "full", with_clouds=False, anchor_frames=True).arrays
    np.testing.assert_array_equal(feats.frames, kinds)
    for kind in (FRAME_WALL, FRAME_FUNCTIONAL):
        for i in np.flatnonzero(kinds == kind)[:3]:
            sup = OrientedBox.from_vector(data.support.box[i].astype(np.float64))
            frame = OrientedBox.from_vector(frame_boxes[i])
            f = frame_factor(frame.size)

            def fn(v, sup=sup, frame=frame, f=f, kind=kind):
                world = OrientedBox(
                    sup.rotation @ (v[:3] * sup.half_size) + sup.center,
                    v[3:6] * sup.half_size,
                    np.eye(3),
                )
                rel_c = frame.rotation.T @ (world.center - frame.center) / frame.half_size
                rel_s = world.size / frame.half_size
                c0 = frame.rotation.T @ sup.rotation @ v[6:9]
                c1 = frame.rotation.T @ sup.rotation @ v[9:12]
                own = np.concatenate([rel_c, rel_s, c0, c1])
                if kind == FRAME_FUNCTIONAL:  # the rotation relative to the anchor's bearing
                    yaw = np.arctan2(*(rel_c[:2] * frame.half_size[:2] * [1, -1]))
                    own[6:9], own[9:12] = rot_z(-yaw) @ own[6:9], rot_z(-yaw) @ own[9:12]
                return target_of(to_model_frame(own, f))

            xi = data.canonical[i].astype(np.float64)
            assert feats.log_jacobian[i] == pytest.approx(_log_abs_det(fn, xi), abs=1e-4)
            np.testing.assert_allclose(feats.target[i], fn(xi), atol=1e-4)
    # support-frame tuples are unchanged by the option
    plain = dataset_features(data, "full", with_clouds=False).arrays
    same = kinds == FRAME_SUPPORT
    np.testing.assert_allclose(feats.target[same], plain.target[same], atol=1e-6)
    np.testing.assert_allclose(feats.log_jacobian[same], plain.log_jacobian[same])

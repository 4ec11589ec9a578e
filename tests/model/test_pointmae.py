"""Point-MAE: grouping, Chamfer-L2, encoder shapes, masking, determinism, a short fit."""

from __future__ import annotations

import itertools
import math

import numpy as np
import pytest

torch = pytest.importorskip("torch")

from pair2scene.model.pointmae import (  # noqa: E402
    PointMAE,
    PointMAEConfig,
    PointMAEEncoder,
    chamfer_l2,
    farthest_point_sample,
    gather_points,
    knn_group,
    knn_indices,
    normalise_points,
    random_mask,
)

TINY = PointMAEConfig.tiny()


def cube_corners() -> torch.Tensor:
    return torch.tensor(list(itertools.product((0.0, 1.0), repeat=3)))  # (8, 3)


def synthetic_clouds(n_clouds: int, n: int, seed: int) -> torch.Tensor:
    """(n_clouds, n, 3) surface points of random boxes and spheres, in the unit ball."""
    g = torch.Generator().manual_seed(seed)
    out = []
    for i in range(n_clouds):
        if i % 2:  # sphere of radius r
            p = torch.randn(n, 3, generator=g)
            p = p / p.norm(dim=1, keepdim=True) * (0.5 + 0.5 * torch.rand(1, generator=g))
        else:  # box surface: a random point of the box pushed onto one face
            half = 0.2 + 0.4 * torch.rand(3, generator=g)
            p = (2 * torch.rand(n, 3, generator=g) - 1) * half
            axis = torch.randint(3, (n,), generator=g)
            sign = torch.where(torch.rand(n, generator=g) < 0.5, -1.0, 1.0)
            p[torch.arange(n), axis] = sign * half[axis]
        out.append(p)
    return torch.stack(out)


# -- normalisation ---------------------------------------------------------------------
def test_normalise_points_puts_box_corners_on_the_unit_sphere():
    size = torch.tensor([2.0, 1.0, 0.5])
    corners = (cube_corners() - 0.5) * size  # (8, 3) corners of the box around the origin
    out, half = normalise_points(corners, size)
    assert half.item() == pytest.approx(0.5 * math.sqrt(4 + 1 + 0.25))
    torch.testing.assert_close(out.norm(dim=-1), torch.ones(8))
    shifted, half2 = normalise_points(corners + torch.tensor([1.0, 2.0, 3.0]), size,
                                      center=torch.tensor([1.0, 2.0, 3.0]))  # fmt: skip
    torch.testing.assert_close(shifted, out)
    assert half2 == half


def test_normalise_points_batches():
    size = torch.tensor([[2.0, 2.0, 1.0], [0.2, 0.2, 0.1]])
    pts = torch.tensor([[[1.0, 1.0, 0.5]], [[0.1, 0.1, 0.05]]])  # (2, 1, 3): a corner each
    out, half = normalise_points(pts, size)
    torch.testing.assert_close(half, torch.tensor([1.5, 0.15]))
    torch.testing.assert_close(out, torch.tensor([[[2 / 3, 2 / 3, 1 / 3]]] * 2))


# -- farthest point sampling -----------------------------------------------------------
def test_fps_on_a_line_known_order():
    points = torch.stack([torch.arange(11.0), torch.zeros(11), torch.zeros(11)], dim=1)[None]
    # from 0: the far end 10, the middle 5, then the tie {2, 3, 7, 8} goes to the lowest index
    assert farthest_point_sample(points, 4).tolist() == [[0, 10, 5, 2]]


def test_fps_picks_the_cube_corners_first():
    g = torch.Generator().manual_seed(0)
    inner = 0.25 + 0.5 * torch.rand(200, 3, generator=g)  # strictly inside the cube
    corners = cube_corners()
    points = torch.cat([corners[:1], inner, corners[1:]])  # start (index 0) at a corner
    perm = torch.cat([torch.zeros(1, dtype=torch.long),
                      1 + torch.randperm(len(points) - 1, generator=g)])  # fmt: skip
    points = points[perm][None]  # (1, 208, 3)
    idx = farthest_point_sample(points, 8)
    chosen = {tuple(p) for p in points[0, idx[0]].tolist()}
    assert chosen == {tuple(c) for c in corners.tolist()}
    assert idx[0, 1].item() == (perm == 208 - 1).nonzero().item()  # the opposite corner (1,1,1)


def test_fps_is_vectorised_over_the_batch_and_unique():
    clouds = synthetic_clouds(3, 100, seed=1)
    batched = farthest_point_sample(clouds, 20)
    for b in range(3):
        assert torch.equal(batched[b], farthest_point_sample(clouds[b : b + 1], 20)[0])
        assert len(set(batched[b].tolist())) == 20


def test_fps_generator_start_is_seeded():
    clouds = synthetic_clouds(4, 64, seed=2)
    a = farthest_point_sample(clouds, 8, torch.Generator().manual_seed(5))
    b = farthest_point_sample(clouds, 8, torch.Generator().manual_seed(5))
    c = farthest_point_sample(clouds, 8, torch.Generator().manual_seed(6))
    assert torch.equal(a, b)
    assert not torch.equal(a, c)
    assert not torch.equal(a[:, 0], torch.zeros(4, dtype=torch.long))


def test_fps_rejects_more_samples_than_points():
    with pytest.raises(ValueError, match="m <= N"):
        farthest_point_sample(torch.zeros(1, 4, 3), 5)


# -- kNN grouping ----------------------------------------------------------------------
def test_knn_group_holds_the_nearest_points_relative_to_the_centre():
    clouds = synthetic_clouds(2, 128, seed=3)
    centers = gather_points(clouds, torch.tensor([[0, 5, 9], [1, 2, 3]]))  # (2, 3, 3)
    groups = knn_group(clouds, centers, 10)
    assert groups.shape == (2, 3, 10, 3)
    for b in range(2):
        for g in range(3):
            d = np.linalg.norm(clouds[b].numpy() - centers[b, g].numpy(), axis=1)
            nearest = clouds[b].numpy()[np.argsort(d, kind="stable")[:10]]
            np.testing.assert_allclose(
                groups[b, g].numpy(), nearest - centers[b, g].numpy(), atol=1e-6
            )
    # the centre is a cloud point: it is its own nearest neighbour, at offset 0
    torch.testing.assert_close(groups[:, :, 0], torch.zeros(2, 3, 3))


def test_knn_indices_known_case():
    points = torch.tensor([[[0.0, 0, 0], [1, 0, 0], [3, 0, 0], [6, 0, 0]]])
    centers = torch.tensor([[[2.9, 0, 0], [0.2, 0, 0]]])
    assert knn_indices(points, centers, 2).tolist() == [[[2, 1], [0, 1]]]


def test_gather_points_shapes():
    points = torch.arange(24.0).reshape(2, 4, 3)
    idx = torch.tensor([[[3, 0]], [[1, 1]]])  # (2, 1, 2)
    out = gather_points(points, idx)
    assert out.shape == (2, 1, 2, 3)
    assert out[0, 0, 0].tolist() == [9.0, 10.0, 11.0]
    assert out[1, 0, 1].tolist() == [15.0, 16.0, 17.0]


# -- Chamfer ---------------------------------------------------------------------------
def test_chamfer_of_identical_and_permuted_sets_is_zero():
    a = synthetic_clouds(2, 48, seed=4).reshape(2, 3, 16, 3)
    assert torch.equal(chamfer_l2(a, a), torch.zeros(2))
    perm = torch.randperm(16, generator=torch.Generator().manual_seed(0))
    assert torch.equal(chamfer_l2(a, a[:, :, perm]), torch.zeros(2))


def test_chamfer_known_values():
    one = torch.tensor([[[[0.0, 0, 0]]]])  # (1, 1, 1, 3)
    assert chamfer_l2(one, torch.tensor([[[[1.0, 0, 0]]]])).item() == pytest.approx(2.0)
    # {0, (2,0,0)} against {0}: a->b means (0 + 4) / 2 = 2, b->a is 0
    two = torch.tensor([[[[0.0, 0, 0], [2.0, 0, 0]]]])
    assert chamfer_l2(two, one).item() == pytest.approx(2.0)
    assert chamfer_l2(one, two).item() == pytest.approx(2.0)
    # M = 2 sets: the mean over sets (0 and 2 -> 1)
    a = torch.cat([one, one], dim=1)  # (1, 2, 1, 3)
    b = torch.tensor([[[[0.0, 0, 0]], [[0.0, 1, 0]]]])
    assert chamfer_l2(a, b).tolist() == [pytest.approx(1.0)]


# -- encoder ---------------------------------------------------------------------------
def test_encoder_shapes_and_centres_are_cloud_points():
    enc = PointMAEEncoder(TINY, torch.Generator().manual_seed(0))
    clouds = synthetic_clouds(3, TINY.n_points, seed=5)
    tokens, centers = enc(clouds)
    assert tokens.shape == (3, TINY.n_groups, TINY.width)
    assert centers.shape == (3, TINY.n_groups, 3)
    assert enc.width == TINY.width
    idx = farthest_point_sample(clouds, TINY.n_groups)
    torch.testing.assert_close(centers, gather_points(clouds, idx))
    assert torch.isfinite(tokens).all()


def test_encoder_mask_encodes_only_visible_groups():
    enc = PointMAEEncoder(TINY, torch.Generator().manual_seed(0)).eval()
    clouds = synthetic_clouds(2, TINY.n_points, seed=6)
    mask = random_mask(2, TINY.n_groups, TINY.n_masked, torch.Generator().manual_seed(1))
    tokens, centers = enc(clouds, mask)
    v = TINY.n_groups - TINY.n_masked
    assert tokens.shape == (2, v, TINY.width) and centers.shape == (2, v, 3)
    _, all_centers = enc(clouds)
    torch.testing.assert_close(centers, all_centers[~mask].reshape(2, v, 3))
    # nothing masked: the same as no mask
    none = torch.zeros(2, TINY.n_groups, dtype=torch.bool)
    torch.testing.assert_close(enc(clouds, none)[0], enc(clouds)[0])
    uneven = none.clone()
    uneven[0, 0] = True
    with pytest.raises(ValueError, match="same number"):
        enc(clouds, uneven)


def test_encoder_accepts_other_cloud_sizes():
    enc = PointMAEEncoder(TINY, torch.Generator().manual_seed(0))
    tokens, _ = enc(synthetic_clouds(1, 100, seed=7))
    assert tokens.shape == (1, TINY.n_groups, TINY.width)


def test_config_validation_and_presets():
    assert TINY.n_masked == 9  # floor(0.6 * 16)
    assert PointMAEConfig().n_masked == 38  # floor(0.6 * 64)
    assert PointMAEConfig.point_mae().width == 384
    with pytest.raises(ValueError, match="divisible"):
        PointMAEConfig(width=30, heads=4)
    with pytest.raises(ValueError, match="mask_ratio"):
        PointMAEConfig(mask_ratio=1.0)


# -- masking ---------------------------------------------------------------------------
def test_random_mask_ratio_and_seed():
    a = random_mask(50, 64, 38, torch.Generator().manual_seed(0))
    assert a.dtype == torch.bool and a.shape == (50, 64)
    assert (a.sum(1) == 38).all()
    assert torch.equal(a, random_mask(50, 64, 38, torch.Generator().manual_seed(0)))
    assert not torch.equal(a, random_mask(50, 64, 38, torch.Generator().manual_seed(1)))
    assert len({tuple(row) for row in a.tolist()}) == 50  # rows draw independently
    freq = a.float().mean(0)  # every group is masked about 60 % of the time
    assert freq.min() > 0.35 and freq.max() < 0.85


# -- the masked autoencoder ------------------------------------------------------------
def test_mae_forward_masks_the_configured_ratio():
    mae = PointMAE(TINY, torch.Generator().manual_seed(0))
    clouds = synthetic_clouds(4, TINY.n_points, seed=8)
    loss, out = mae(clouds, torch.Generator().manual_seed(1))
    m = TINY.n_masked
    assert loss.shape == () and loss.item() > 0
    assert (out.mask.sum(1) == m).all()
    assert out.predicted.shape == out.target.shape == (4, m, TINY.group_size, 3)
    assert out.chamfer.shape == (4,)
    assert loss.item() == pytest.approx(out.chamfer.mean().item())
    # the targets are the masked groups of the encoder's own grouping
    groups, _ = mae.encoder.group(clouds)
    torch.testing.assert_close(out.target, groups[out.mask].reshape(4, m, -1, 3))


def test_mae_is_deterministic_given_seeds():
    clouds = synthetic_clouds(2, TINY.n_points, seed=9)

    def run(init: int, mask: int) -> float:
        mae = PointMAE(TINY, torch.Generator().manual_seed(init))
        return mae(clouds, torch.Generator().manual_seed(mask))[0].item()

    assert run(0, 0) == run(0, 0)
    assert run(0, 0) != run(1, 0)
    assert run(0, 0) != run(0, 1)
    a = PointMAE(TINY, torch.Generator().manual_seed(3)).state_dict()
    b = PointMAE(TINY, torch.Generator().manual_seed(3)).state_dict()
    assert a.keys() == b.keys() and all(torch.equal(a[k], b[k]) for k in a)


KNOWN_INITIAL_LOSS = 0.03223097
"""The tiny model's loss at init seed 0, mask seed 0, on ``synthetic_clouds(2, 256, 10)``
(torch 2.13 CPU): small because predictions start near the centre and the true groups
are ~0.1 across."""


def test_mae_known_initial_loss():
    """Pins the tiny model's numbers: a change here means the model or its init changed."""
    torch.manual_seed(12345)  # the default generator must not matter
    mae = PointMAE(TINY, torch.Generator().manual_seed(0))
    loss, _ = mae(synthetic_clouds(2, TINY.n_points, seed=10), torch.Generator().manual_seed(0))
    assert loss.item() == pytest.approx(KNOWN_INITIAL_LOSS, rel=1e-4)


def test_a_few_steps_reduce_the_loss():
    g = torch.Generator().manual_seed(0)
    mae = PointMAE(TINY, g)
    train = synthetic_clouds(16, TINY.n_points, seed=11)
    opt = torch.optim.AdamW(mae.parameters(), lr=3e-3, weight_decay=0.0)

    def evaluate() -> float:
        with torch.no_grad():
            return mae(train, torch.Generator().manual_seed(99))[0].item()

    before = evaluate()
    for _ in range(200):
        batch = train[torch.randint(len(train), (8,), generator=g)]
        loss, _ = mae(batch, g)
        opt.zero_grad()
        loss.backward()
        opt.step()
    after = evaluate()
    assert after < 0.6 * before  # 0.042 -> 0.019; a centred blob alone gets 0.029

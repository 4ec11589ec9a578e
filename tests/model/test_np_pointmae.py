"""The numpy Point-MAE encoder against the torch one: same centres, same groups, tokens
within 1e-4; its state checks; and that it runs without importing torch."""

from __future__ import annotations

import itertools
import json
import subprocess
import sys

import numpy as np
import pytest

torch = pytest.importorskip("torch")

from pair2scene.model.checkpoint import DEFAULT_DIR, WEIGHTS_FILE, encoder_shapes  # noqa: E402
from pair2scene.model.np_pointmae import (  # noqa: E402
    NumpyPointMAE,
    encoder_state,
    knn_indices,
    squared_distances,
)
from pair2scene.model.pointmae import PointMAEConfig, PointMAEEncoder  # noqa: E402
from pair2scene.model.pointmae import knn_indices as torch_knn_indices  # noqa: E402

CONFIGS = {"tiny": PointMAEConfig.tiny(), "default": PointMAEConfig()}


def surface_clouds(n_clouds: int, n: int, seed: int) -> np.ndarray:
    """(n_clouds, n, 3) float32 points on the surfaces of random boxes, in the unit ball
    (normalised by the box's half-diagonal, as the encoder's inputs are)."""
    rng = np.random.default_rng(seed)
    out = np.empty((n_clouds, n, 3), np.float32)
    for i in range(n_clouds):
        half = rng.uniform(0.05, 0.6, 3)
        p = rng.uniform(-1.0, 1.0, (n, 3)) * half
        axis = rng.integers(3, size=n)
        p[np.arange(n), axis] = np.where(rng.random(n) < 0.5, -1.0, 1.0) * half[axis]
        out[i] = p / np.linalg.norm(half)
    return out


def cloud_cases(c: PointMAEConfig) -> dict[str, np.ndarray]:
    """Inputs (B, N, 3) float32 that exercise the grouping's corner cases."""
    fewest = max(c.n_groups, c.group_size)
    duplicated = surface_clouds(1, c.n_points, 2)
    duplicated[:, c.n_points // 2 :] = duplicated[:, : c.n_points - c.n_points // 2]
    corners = np.array(list(itertools.product((-0.5, 0.5), repeat=3)), np.float32)  # (8, 3)
    return {
        "batch": surface_clouds(3, c.n_points, 1),
        "odd size": surface_clouds(1, c.n_points + 37, 3),
        # ties: each point twice (in the k-th distance too), equidistant corners for the
        # farthest point sampling (the lowest index wins in both)
        "duplicates": duplicated,
        "corners": np.tile(corners, (fewest // 8 + 1, 1))[None, :fewest],
        "fewest points": surface_clouds(1, fewest, 4),
    }


def random_encoder(c: PointMAEConfig, seed: int = 0) -> PointMAEEncoder:
    """A seeded encoder, every parameter moved off its initial value (zero biases, unit
    layer norms would hide a mistake in how they are folded)."""
    generator = torch.Generator().manual_seed(seed)
    encoder = PointMAEEncoder(c, generator).eval()
    with torch.no_grad():
        for p in encoder.parameters():
            p.add_(0.1 * torch.randn(p.shape, generator=generator))
    return encoder


def numpy_state(encoder: torch.nn.Module) -> dict[str, np.ndarray]:
    return {k: v.numpy() for k, v in encoder.state_dict().items()}


def assert_same_encoding(encoder: PointMAEEncoder, ours: NumpyPointMAE, clouds: np.ndarray):
    with torch.no_grad():
        tokens, centers = encoder(torch.from_numpy(clouds))
    got_tokens, got_centers = ours(clouds)
    assert got_tokens.dtype == got_centers.dtype == np.float32
    np.testing.assert_array_equal(got_centers, centers.numpy())
    np.testing.assert_allclose(got_tokens, tokens.numpy(), rtol=1e-4, atol=1e-4)


@pytest.mark.parametrize("name", CONFIGS)
def test_encoder_shapes_are_the_torch_state_dicts(name):
    c = CONFIGS[name]
    expected = {k: tuple(v.shape) for k, v in PointMAEEncoder(c).state_dict().items()}
    assert list(encoder_shapes(c).items()) == list(expected.items())


@pytest.mark.parametrize("name", CONFIGS)
def test_matches_the_torch_encoder(name):
    c = CONFIGS[name]
    encoder = random_encoder(c)
    ours = NumpyPointMAE(c, numpy_state(encoder))
    for case, clouds in cloud_cases(c).items():
        try:
            assert_same_encoding(encoder, ours, clouds)
        except AssertionError as e:
            raise AssertionError(f"{case}: {e}") from None


def test_matches_the_bundled_model():
    """The trained encoder inside the bundled predictor, picked out by its prefix."""
    safetensors = pytest.importorskip("safetensors.numpy")
    doc = json.loads((DEFAULT_DIR / "config.json").read_text())
    c = PointMAEConfig(**doc["encoder"])
    state = encoder_state(safetensors.load_file(DEFAULT_DIR / WEIGHTS_FILE))
    encoder = PointMAEEncoder(c).eval()
    encoder.load_state_dict({k: torch.from_numpy(v) for k, v in state.items()})
    assert_same_encoding(encoder, NumpyPointMAE(c, state), surface_clouds(2, c.n_points, 5))


def test_empty_batch():
    c = CONFIGS["tiny"]
    tokens, centers = NumpyPointMAE(c, numpy_state(random_encoder(c)))(
        np.zeros((0, c.n_points, 3), np.float32)
    )
    assert tokens.shape == (0, c.n_groups, c.width) and centers.shape == (0, c.n_groups, 3)


def test_squared_distances_round_as_torch_cdist():
    """Bit for bit the matmul expansion torch.cdist takes (its square roots are MKL's)."""
    points = torch.from_numpy(surface_clouds(2, 300, 6))
    centers = points[:, :16]
    norm_c = centers.pow(2).sum(-1, keepdim=True)
    norm_p = points.pow(2).sum(-1, keepdim=True)
    left = torch.cat([centers.mul(-2), norm_c, torch.ones_like(norm_c)], -1)
    right = torch.cat([points, torch.ones_like(norm_p), norm_p], -1)
    expected = left.matmul(right.mT).clamp_min(0)
    np.testing.assert_array_equal(squared_distances(centers.numpy(), points.numpy()), expected)
    np.testing.assert_array_equal(expected.sqrt(), torch.cdist(centers, points))


def test_knn_is_torchs_on_sampled_clouds():
    clouds = surface_clouds(4, 2048, 7)
    centers = clouds[:, :: 2048 // 32]  # (4, 32, 3)
    for k in (32, 64):
        expected = torch_knn_indices(torch.from_numpy(clouds), torch.from_numpy(centers), k)
        np.testing.assert_array_equal(
            knn_indices(clouds, centers, k), np.sort(expected.numpy(), axis=-1)
        )


def test_knn_ties_go_to_the_lowest_index():
    # around the origin: itself, then four points at exactly 1, then one far away
    points = np.array(
        [[0, 0, 0], [9, 0, 0], [1, 0, 0], [0, -1, 0], [-1, 0, 0], [0, 1, 0]], np.float32
    )
    got = knn_indices(points[None], points[None, :1], 3)
    np.testing.assert_array_equal(got, [[[0, 2, 3]]])


@pytest.mark.parametrize(
    ("key", "change"),
    [
        ("embed.first.0.weight", "drop"),
        ("transformer.blocks.1.mlp.2.bias", "drop"),
        ("transformer.ln_f.weight", "drop"),
        ("embed.second.0.weight", "reshape"),
        ("transformer.blocks.0.attn.qkv.weight", "reshape"),
    ],
)
def test_state_checks_name_the_key(key, change):
    c = CONFIGS["tiny"]
    state = numpy_state(PointMAEEncoder(c))
    if change == "drop":
        del state[key]
    else:
        state[key] = state[key][..., :-1]
    with pytest.raises(ValueError, match=key.replace(".", r"\.")):
        NumpyPointMAE(c, state)


def test_state_extra_keys_are_ignored_and_the_prefix_stripped():
    c = CONFIGS["tiny"]
    state = numpy_state(PointMAEEncoder(c))
    whole = {f"point_encoder.{k}": v for k, v in state.items()} | {"head.weight": np.ones(2)}
    picked = encoder_state(whole)
    assert list(picked) == list(state)
    assert encoder_state({"enc.a": 1, "point_encoder.b": 2}, prefix="enc.") == {"a": 1}
    NumpyPointMAE(c, whole | picked)  # the prefixed and foreign keys: ignored


@pytest.mark.parametrize("shape", [(2, 256), (1, 256, 2), (1, 15, 3)])
def test_rejects_malformed_clouds(shape):
    c = CONFIGS["tiny"]  # 16 groups of 16: at least 16 points
    ours = NumpyPointMAE(c, numpy_state(PointMAEEncoder(c)))
    with pytest.raises(ValueError, match="clouds"):
        ours(np.zeros(shape, np.float32))


def test_does_not_import_torch():
    code = "import sys, pair2scene.model.np_pointmae; assert 'torch' not in sys.modules"
    subprocess.run([sys.executable, "-c", code], check=True)

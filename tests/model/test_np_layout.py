"""The numpy layout predictor and mixture functions (np_layout) against their torch originals:
the forward pass of every variant, conditioning, window masses, the sampler's distribution,
seeding and errors; and that the module imports no torch."""

from __future__ import annotations

import math
import subprocess
import sys

import numpy as np
import pytest
from scipy import stats

torch = pytest.importorskip("torch")

from pair2scene.curation.dataset import CATEGORY_VOCAB  # noqa: E402
from pair2scene.model import mixture as tm  # noqa: E402
from pair2scene.model import np_layout as npl  # noqa: E402
from pair2scene.model.checkpoint import load_checkpoint  # noqa: E402
from pair2scene.model.config import (  # noqa: E402
    FLOOR_INDEX,
    MAX_ABS_LOCATION,
    WALL_INDEX,
    InvalidDistribution,
    LayoutConfig,
    LayoutVariant,
    MixtureConfig,
)
from pair2scene.model.layout import LayoutBatch, LayoutPredictor  # noqa: E402

GROUPS, POINT_DIM = 5, 8


@pytest.fixture(autouse=True, scope="module")
def one_torch_thread():
    """Torch on one thread, as generation runs it: these tiny operations only pay for a
    thread pool (several times slower on a busy two-core machine)."""
    before = torch.get_num_threads()
    torch.set_num_threads(1)
    yield
    torch.set_num_threads(before)


def tiny_config(variant: str = "full", **kw) -> LayoutConfig:
    kw = {"width": 32, "depth": 2, "heads": 4, "queries": 2, "point_dim": POINT_DIM, **kw}
    return LayoutConfig(variant=LayoutVariant(variant), **kw)


def perturbed_model(config: LayoutConfig, seed: int = 0) -> LayoutPredictor:
    """A predictor in eval mode with every parameter moved off its initialisation (layer
    norms off 1 and 0, biases off 0, the head off ~0), so that every weight shows."""
    model = LayoutPredictor(config, None, torch.Generator().manual_seed(seed)).eval()
    g = torch.Generator().manual_seed(seed + 100)
    with torch.no_grad():
        for p in model.parameters():
            p.add_(0.3 * torch.randn(p.shape, generator=g))
        if config.uses_pair_prior:  # a table with every pair's own centre
            model.pair_centre.copy_(torch.randn(model.pair_centre.shape, generator=g))
        if config.uses_pair_turns:  # and its own split of yaw turns
            model.pair_turn.copy_(torch.randn(model.pair_turn.shape, generator=g))
        if config.uses_pair_modes:  # and its own clusters
            model.pair_mode.copy_(torch.randn(model.pair_mode.shape, generator=g))
    return model


def random_inputs(b: int, seed: int, functional: np.ndarray | None = None) -> dict:
    """Numpy inputs of B tuples (LayoutBatch's fields); the functional anchor present in
    every other row unless ``functional`` (B,) says otherwise, absent ones' inputs NaN.
    Supports include the floor and a wall, sizes below MIN_ANCHOR_HALF_M."""
    rng = np.random.default_rng(seed)
    functional = np.arange(b) % 2 == 0 if functional is None else functional
    mask = np.ones((b, 3), bool)
    mask[:, 2] = functional
    cats = rng.integers(0, len(CATEGORY_VOCAB), (b, 3))
    cats[::3, 1], cats[1::3, 1] = FLOOR_INDEX, WALL_INDEX
    cats[~functional, 2] = -1
    scales = rng.uniform(0.02, 2.0, (b, 3, 3)).astype(np.float32)
    boxes = rng.standard_normal((b, 2, 12)).astype(np.float32)
    boxes[..., 3:6] = rng.uniform(0.1, 2.0, (b, 2, 3))
    tokens = rng.standard_normal((b, 3, GROUPS, POINT_DIM)).astype(np.float32)
    centers = rng.standard_normal((b, 3, GROUPS, 3)).astype(np.float32)
    scales[~functional, 2] = boxes[~functional, 1] = np.nan
    tokens[~functional, 2] = centers[~functional, 2] = np.nan
    return {
        "categories": cats,
        "scales": scales,
        "anchor_boxes": boxes,
        "member_mask": mask,
        "point_tokens": tokens,
        "point_centers": centers,
        "frames": rng.integers(0, 3, b),
        "frame_sizes": rng.uniform(0.05, 3.0, (b, 3)).astype(np.float32),
    }


def torch_params(model: LayoutPredictor, inputs: dict) -> tm.MixtureParams:
    fields = {k: None if v is None else torch.from_numpy(np.asarray(v)) for k, v in inputs.items()}
    with torch.no_grad():
        return model(LayoutBatch(**fields))[0]


def numpy_predictor(model: LayoutPredictor) -> npl.NumpyPredictor:
    return npl.NumpyPredictor(model.config, {k: v.numpy() for k, v in model.state_dict().items()})


def assert_same_params(ours: npl.MixtureArrays, theirs: tm.MixtureParams) -> None:
    for name, a, t in zip(ours._fields, ours, theirs):
        assert a.dtype == np.float32 and a.shape == t.shape, name
        np.testing.assert_allclose(a, t.numpy(), atol=1e-4, rtol=1e-4, err_msg=name)


# -- the forward pass ------------------------------------------------------------------

VARIANTS = {
    "full": tiny_config("full"),
    "no-pretrain": tiny_config("no-pretrain"),
    "class-only": tiny_config("class-only"),
    "global": tiny_config("global"),
    "full, no anchor frames": tiny_config("full", anchor_frames=False),
    "one yaw mode": tiny_config(
        mixture=MixtureConfig(num_components=3, yaw_modes=1, rotation_base=False)
    ),
    "two yaw modes": tiny_config(mixture=MixtureConfig(num_components=2, yaw_modes=2)),
    "pair prior": tiny_config("full", pair_prior=True),
    "pair prior, no anchor frames": tiny_config("full", pair_prior=True, anchor_frames=False),
    "pair prior, class-only": tiny_config("class-only", pair_prior=True),
    "pair turns": tiny_config("full", pair_prior=True, pair_turns=True),
    "pair turns, no anchor frames": tiny_config("full", pair_turns=True, anchor_frames=False),
    "pair modes": tiny_config("full", pair_prior=True, pair_modes=True),
    "pair modes and turns, class-only": tiny_config(
        "class-only", pair_prior=True, pair_modes=True, pair_turns=True
    ),
    "pair modes, one yaw mode": tiny_config(
        pair_prior=True,
        pair_modes=True,
        mixture=MixtureConfig(num_components=3, yaw_modes=1, rotation_base=False),
    ),
}


@pytest.mark.parametrize("name", list(VARIANTS))
def test_forward_equals_the_torch_predictor(name):
    """Every variant, with frames given and left out; absent functional anchors' NaN
    inputs (and, class-only, the point tokens) are never read."""
    model = perturbed_model(VARIANTS[name])
    ours = numpy_predictor(model)
    inputs = random_inputs(6, seed=1)
    params = ours.forward(**inputs)
    assert all(np.isfinite(a).all() for a in params)
    assert_same_params(params, torch_params(model, inputs))
    inputs.update(frames=None, frame_sizes=None)
    assert_same_params(ours.forward(**inputs), torch_params(model, inputs))


@pytest.mark.parametrize(
    "functional", [[True], [False], [True, True, True], [False, False, True]], ids=str
)
def test_forward_batches_of_one_and_every_member_present_or_not(functional):
    model = perturbed_model(tiny_config(depth=3), seed=2)
    inputs = random_inputs(len(functional), seed=3, functional=np.array(functional))
    assert_same_params(numpy_predictor(model).forward(**inputs), torch_params(model, inputs))


def test_forward_with_the_bundled_checkpoint():
    """The trained weights (width 128, 8 components in 4 turns) at B = 1, float64 inputs
    as generation builds them."""
    predictor = load_checkpoint(None).predictor.eval()
    c, groups = predictor.config, predictor.point_encoder.config.n_groups
    rng = np.random.default_rng(4)
    ours = numpy_predictor(predictor)
    for functional in (True, False):
        inputs = random_inputs(1, seed=5, functional=np.array([functional]))
        inputs["point_tokens"] = rng.standard_normal((1, 3, groups, c.point_dim))
        inputs["point_centers"] = 0.5 * rng.standard_normal((1, 3, groups, 3))
        theirs = torch_params(predictor, {**inputs, **_float32(inputs)})
        assert_same_params(ours.forward(**inputs), theirs)


def _float32(inputs: dict) -> dict:
    return {k: inputs[k].astype(np.float32) for k in ("point_tokens", "point_centers")}


def test_from_mixture_space_equals_the_predictors():
    y = np.random.default_rng(6).standard_normal((2, 5, 12)).astype(np.float32)
    for config in (tiny_config(), VARIANTS["one yaw mode"]):
        model = perturbed_model(config)
        theirs = model.from_mixture_space(torch.from_numpy(y)).numpy()
        np.testing.assert_array_equal(numpy_predictor(model).from_mixture_space(y), theirs)


def test_state_entries_are_checked_by_name():
    model = perturbed_model(tiny_config())
    state = {k: v.numpy() for k, v in model.state_dict().items()}
    npl.NumpyPredictor(model.config, {**state, "point_encoder.blocks.0.w": np.zeros(3)})
    missing = {k: v for k, v in state.items() if k != "blocks.1.mlp.fc.bias"}
    with pytest.raises(ValueError, match=r"no entry 'blocks\.1\.mlp\.fc\.bias'"):
        npl.NumpyPredictor(model.config, missing)
    with pytest.raises(ValueError, match=r"'head\.proj\.weight' has shape \(3, 32\)"):
        npl.NumpyPredictor(model.config, {**state, "head.proj.weight": np.zeros((3, 32))})
    with pytest.raises(ValueError, match=r"'point_proj\.weight' is not one of"):
        npl.NumpyPredictor(tiny_config("class-only"), state)
    ours = npl.NumpyPredictor(model.config, state)
    inputs = random_inputs(2, seed=7)
    with pytest.raises(ValueError, match="scales has shape"):
        ours.forward(**{**inputs, "scales": inputs["scales"][:, 0]})
    with pytest.raises(ValueError, match="needs point_tokens"):
        ours.forward(**{**inputs, "point_tokens": None})


# -- the mixture -----------------------------------------------------------------------


def random_params(seed: int, b: int, k: int, d: int, dtype=np.float64) -> npl.MixtureArrays:
    rng = np.random.default_rng(seed)
    return npl.MixtureArrays(
        rng.standard_normal((b, k)).astype(dtype),
        (2.0 * rng.standard_normal((b, k, d))).astype(dtype),
        rng.uniform(-1.5, 0.5, (b, k, d)).astype(dtype),
    )


def to_torch(params: npl.MixtureArrays) -> tm.MixtureParams:
    return tm.MixtureParams(*(torch.from_numpy(a.copy()) for a in params))


def to_torch_window(window: npl.Window) -> tm.Window:
    low, high = (torch.from_numpy(np.asarray(a)) for a in (window.low, window.high))
    return tm.Window(window.dims, low, high)


@pytest.mark.parametrize("dtype", [np.float64, np.float32])
def test_condition_equals_torch(dtype):
    params = random_params(8, b=3, k=4, d=12, dtype=dtype)
    values = np.random.default_rng(9).standard_normal((3, 3)).astype(dtype)
    ours = npl.condition(params, [3, 4, 5], values)
    theirs = tm.condition(to_torch(params), [3, 4, 5], torch.from_numpy(values))
    tol = 1e-12 if dtype == np.float64 else 1e-5
    for a, t in zip(ours, theirs):
        assert a.dtype == dtype
        np.testing.assert_allclose(a, t.numpy(), rtol=tol, atol=tol)
    assert (ours.loc[..., 3:6] == values[:, None]).all() and (ours.log_scale[..., 3:6] == -70).all()


WINDOWS = {
    "box": ([0, 1], [[-1.0, -0.5], [0.0, -2.0], [-3.0, 1.0]], [[1.0, 0.5], [2.0, 2.0], [3.0, 1.5]]),
    "far tail": ([0], [[30.0], [-31.0], [20.0]], [[31.0], [-30.0], [20.5]]),
    "empty": ([1], [[1.0], [0.5], [0.0]], [[0.0], [0.5], [-1.0]]),
}


@pytest.mark.parametrize("dtype", [np.float64, np.float32])
@pytest.mark.parametrize("window", list(WINDOWS))
@pytest.mark.parametrize("temperature", [1.0, 0.6])
def test_window_log_mass_equals_torch(window, temperature, dtype):
    params = random_params(10, b=3, k=3, d=2, dtype=dtype)
    dims, low, high = WINDOWS[window]
    ours = npl.Window(dims, np.array(low, dtype), np.array(high, dtype))
    mass = npl.window_log_mass(params, ours, temperature)
    theirs = tm.window_log_mass(to_torch(params), to_torch_window(ours), temperature)
    assert mass.dtype == np.float64 and mass.shape == (3,)
    tol = 1e-9 if dtype == np.float64 else 1e-5
    np.testing.assert_allclose(mass, theirs.numpy(), rtol=tol, atol=tol)
    assert np.isinf(mass).all() == (window == "empty")


def test_same_generator_state_same_draws_and_the_documented_calls():
    params = random_params(11, b=2, k=3, d=4, dtype=np.float32)
    window = npl.Window([0, 2], np.full((2, 2), -1.0), np.full((2, 2), 1.5))
    for w in (None, window):
        a = npl.sample(params, 50, 0.8, np.random.default_rng(3), w)
        assert a.shape == (2, 50, 4) and a.dtype == np.float32
        np.testing.assert_array_equal(a, npl.sample(params, 50, 0.8, np.random.default_rng(3), w))
        assert not np.array_equal(a, npl.sample(params, 50, 0.8, np.random.default_rng(4), w))
    # Exactly what the docstring lists is taken from the generator.
    used, replay = np.random.default_rng(5), np.random.default_rng(5)
    npl.sample(params, 7, 1.0, used, window)
    replay.random((2, 7))
    replay.random((2, 7, 4), dtype=np.float32)
    assert used.random() == replay.random()


def test_zero_temperature_is_the_mode():
    params = random_params(12, b=3, k=4, d=5)
    x = npl.sample(params, 6, 0.0, np.random.default_rng(0))
    mode = tm.mode(to_torch(params)).numpy()
    assert x.shape == (3, 6, 5)
    np.testing.assert_array_equal(x, np.broadcast_to(mode[:, None], x.shape))
    np.testing.assert_array_equal(npl.mode(params), mode)


@pytest.mark.parametrize("temperature", [1.0, 0.5])
def test_windowed_draws_fall_inside_and_an_empty_window_draws_unconfined(temperature):
    params = random_params(13, b=3, k=3, d=3, dtype=np.float32)
    dims, low, high = WINDOWS["box"]
    window = npl.Window(dims, np.array(low), np.array(high))
    x = npl.sample(params, 2000, temperature, np.random.default_rng(6), window)
    inside = (x[..., dims] >= window.low[:, None]) & (x[..., dims] <= window.high[:, None])
    assert inside.all()
    dims, low, high = WINDOWS["empty"]
    empty = npl.Window(dims, np.array(low), np.array(high))
    free = npl.sample(params, 50, temperature, np.random.default_rng(7))
    confined = npl.sample(params, 50, temperature, np.random.default_rng(7), empty)
    np.testing.assert_allclose(confined, free, rtol=1e-5, atol=1e-5)


def _two_modes() -> npl.MixtureArrays:
    """Two rows of three 2D components."""
    return npl.MixtureArrays(
        np.array([[0.3, -0.2, 0.5], [1.0, 0.0, -1.0]]),
        np.array([[[0.2, -0.4], [2.5, 0.3], [-1.5, 1.0]], [[0.0, 0.0], [1.0, -1.0], [-2.0, 2.0]]]),
        np.array(
            [[[-0.8, -1.0], [-0.2, -1.2], [-1.0, 0.0]], [[-1.0, -1.0], [-0.5, -0.5], [0.0, -2.0]]]
        ),
    )


@pytest.mark.parametrize("windowed", [False, True])
@pytest.mark.parametrize("temperature", [1.0, 0.7])
def test_draws_follow_the_distribution_of_torchs_sampler(temperature, windowed):
    """Many draws of both samplers from the same mixtures: each row's and dim's draws pass a
    two-sample KS test, and the means and quartiles agree within their sampling error
    (fixed seeds: deterministic)."""
    params, n = _two_modes(), 20_000
    window = npl.Window([0, 1], np.array([[-1.0, -1.0], [-1.5, -0.5]]), np.ones((2, 2)))
    window = window if windowed else None
    ours = npl.sample(params, n, temperature, np.random.default_rng(8), window)
    theirs = tm.sample(
        to_torch(params),
        n,
        temperature,
        torch.Generator().manual_seed(9),
        None if window is None else to_torch_window(window),
    ).numpy()
    for row in range(2):
        for dim in range(2):
            a, t = ours[row, :, dim], theirs[row, :, dim]
            assert stats.ks_2samp(a, t).pvalue > 1e-3
            spread = t.std() * math.sqrt(2.0 / n)
            assert abs(a.mean() - t.mean()) < 5 * spread
            qa, qt = np.quantile(a, [0.25, 0.5, 0.75]), np.quantile(t, [0.25, 0.5, 0.75])
            assert np.abs(qa - qt).max() < 10 * spread


BROKEN = {
    "nan logit": (0, (0, 1), math.nan),
    "inf logit": (0, (0, 1), math.inf),
    "all logits -inf": (0, (0,), -math.inf),
    "nan location": (1, (0, 1), math.nan),
    "inf location": (1, (0, 1), math.inf),
    "far location": (1, (0, 1), 10 * MAX_ABS_LOCATION),
    "nan log scale": (2, (0, 1), math.nan),
    "zero scale": (2, (0, 1), -math.inf),
}


def _torch_message(call) -> str:
    with pytest.raises(InvalidDistribution) as info:
        call()
    return str(info.value)


@pytest.mark.parametrize("case", list(BROKEN))
@pytest.mark.parametrize("temperature", [1.0, 0.0])
def test_invalid_mixtures_raise_torchs_message(case, temperature):
    which, index, value = BROKEN[case]
    arrays = [a.copy() for a in random_params(14, b=2, k=3, d=2, dtype=np.float32)]
    arrays[which][index] = value
    params = npl.MixtureArrays(*arrays)
    window = npl.Window([0, 1], np.full((2, 2), -1.0, np.float32), np.ones((2, 2), np.float32))
    for w in (None, window):
        expected = _torch_message(
            lambda w=w: tm.sample(
                to_torch(params),
                5,
                temperature,
                torch.Generator().manual_seed(0),
                None if w is None else to_torch_window(w),
            )
        )
        with pytest.raises(InvalidDistribution) as info:
            npl.sample(params, 5, temperature, np.random.default_rng(0), w)
        assert str(info.value) == expected


def test_overflowing_weights_and_draws_raise_torchs_message():
    params = random_params(15, b=2, k=3, d=2, dtype=np.float32)
    huge = npl.MixtureArrays(params.logits * 1e30, params.loc, params.log_scale)
    wide = npl.MixtureArrays(params.logits, params.loc, np.full_like(params.log_scale, 88.0))
    for p, t in ((huge, 1e-10), (wide, 1.0)):
        expected = _torch_message(
            lambda p=p, t=t: tm.sample(to_torch(p), 200, t, torch.Generator().manual_seed(0))
        )
        with pytest.raises(InvalidDistribution) as info:
            npl.sample(p, 200, t, np.random.default_rng(0))
        assert str(info.value) == expected and "temperature" in expected


def test_bad_arguments():
    params = random_params(16, b=1, k=2, d=2)
    with pytest.raises(ValueError, match="temperature"):
        npl.sample(params, 3, -1.0, np.random.default_rng(0))
    with pytest.raises(ValueError, match="n must"):
        npl.sample(params, 0, 1.0, np.random.default_rng(0))


def test_the_module_imports_no_torch():
    code = "import sys, pair2scene.model.np_layout; assert 'torch' not in sys.modules"
    subprocess.run([sys.executable, "-c", code], check=True)

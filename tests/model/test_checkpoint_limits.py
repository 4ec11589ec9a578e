"""Bad checkpoints are one-line errors (issue 21): configs out of range, sizes that would
allocate terabytes, weights that do not fit, extreme weights, and distributions nothing can
be drawn from. Each refusal is a :class:`UserError` of one line naming the file (and the
field), raised before any large allocation. Tiny preset, untrained: seconds."""

from __future__ import annotations

import dataclasses
import json
import math
import os
import shutil
import time

import numpy as np
import pytest

torch = pytest.importorskip("torch")
st = pytest.importorskip("safetensors.torch")

from clitools import run_cli  # noqa: E402
from pair2scene.errors import UserError  # noqa: E402
from pair2scene.model import from_pretrained  # noqa: E402
from pair2scene.model.api import Anchor, LayoutModel, PlacementQuery  # noqa: E402
from pair2scene.model.checkpoint import (  # noqa: E402
    CONFIG_FILE,
    DEFAULT_DIR,
    FORMAT,
    MAX_PARAMETERS,
    VERSION,
    WEIGHTS_FILE,
    check_model_config,
    check_parameter_count,
    expected_shapes,
    layout_config_to_dict,
    load_checkpoint,
    save_checkpoint,
    skeleton,
)
from pair2scene.model.layout import LayoutPredictor, LayoutVariant  # noqa: E402
from pair2scene.model.mixture import (  # noqa: E402
    MAX_ABS_LOCATION,
    InvalidDistribution,
    MixtureParams,
    Window,
    check_params,
    sample,
)
from pair2scene.model.pointmae import PointMAEEncoder  # noqa: E402
from pair2scene.model.presets import PRESETS, preset  # noqa: E402
from pair2scene.scene.geometry import OrientedBox  # noqa: E402

ROOM = OrientedBox.from_yaw([2.5, 2.0, 1.25], [5.0, 4.0, 2.5])


@pytest.fixture(scope="module")
def good(tmp_path_factory):
    """A valid tiny checkpoint (random weights: only its loading and drawing matter)."""
    p = preset("tiny")
    encoder = PointMAEEncoder(p.encoder, torch.Generator().manual_seed(0))
    predictor = LayoutPredictor(p.layout, encoder, torch.Generator().manual_seed(0))
    folder = tmp_path_factory.mktemp("good")
    return save_checkpoint(
        folder, predictor, preset="tiny", n_points=p.n_points, encoder_config=p.encoder
    )


def _copy(good, dst):
    dst.mkdir()
    for name in (CONFIG_FILE, WEIGHTS_FILE):
        shutil.copyfile(good / name, dst / name)
    return dst


def _with_config(good, dst, edit):
    folder = _copy(good, dst)
    doc = json.loads((folder / CONFIG_FILE).read_text())
    edit(doc)
    (folder / CONFIG_FILE).write_text(json.dumps(doc))
    return folder


def _with_weights(good, dst, edit):
    folder = _copy(good, dst)
    state = st.load_file(str(good / WEIGHTS_FILE))
    state = edit(state)
    (folder / WEIGHTS_FILE).write_bytes(st.save(state))
    return folder


def _refused(folder, *words) -> str:
    """load_checkpoint(folder) raises a one-line UserError holding ``words``, quickly."""
    t0 = time.perf_counter()
    with pytest.raises(UserError) as info:
        load_checkpoint(folder)
    message = str(info.value)
    assert "\n" not in message and len(message) < 400, message
    for word in words:
        assert word in message, message
    assert time.perf_counter() - t0 < 10  # nothing big was built or read
    return message


def _set(path: str, value):
    def edit(doc):
        *parents, last = path.split(".")
        node = doc
        for key in parents:
            node = node[key]
        node[last] = value

    return edit


def _drop(path: str):
    def edit(doc):
        *parents, last = path.split(".")
        node = doc
        for key in parents:
            node = node[key]
        del node[last]

    return edit


# -- config.json ------------------------------------------------------------------------

CONFIG_CASES = [
    ("layout.mixture.num_components", 1_000_000_000, "over the limit"),
    ("layout.mixture.num_components", 0, "at least 1"),
    ("layout.width", -32, "at least 1"),
    ("layout.width", "32", "must be an integer"),
    ("layout.depth", 2.0, "must be an integer"),
    ("layout.depth", True, "must be an integer"),
    ("layout.depth", 10**9, "over the limit"),
    ("layout.depth", 2**70, "over the limit"),
    ("layout.heads", 3, "does not divide"),
    ("layout.queries", None, "must be an integer"),
    ("layout.mlp_ratio", [4], "must be an integer"),
    ("layout.point_dim", 64, "encoder's width"),
    ("layout.n_categories", 5, "at least"),
    ("layout.n_categories", 10**12, "over the limit"),
    ("layout.dropout", 1e308, "below 1"),
    ("layout.dropout", "0", "must be a number"),
    ("layout.variant", "sideways", "must be one of"),
    ("layout.anchor_frames", 1, "true or false"),
    ("layout.mixture.dim", 3, "at least 12"),
    ("layout.mixture.min_log_scale", 6.0, "not below max_log_scale"),
    ("layout.mixture.max_log_scale", 1e30, "over the limit"),
    ("layout.mixture.yaw_modes", 3, "must be one of"),
    ("layout.mixture.entropy_regulariser", "both", "must be one of"),
    ("layout.mixture", "mixture", "must be an object"),
    ("layout", None, "must be an object"),
    ("encoder.n_points", 10**12, "over the limit"),
    ("encoder.n_groups", 10**6, "over the limit"),
    ("encoder.group_size", -1, "at least 1"),
    ("encoder.width", 10**9, "over the limit"),
    ("encoder.depth", 100_000, "over the limit"),
    ("encoder.heads", 0, "at least 1"),
    ("encoder.mlp_ratio", 0.0, "above 0"),
    ("encoder.pointnet_hidden", 4096, "parameters"),
    ("encoder", None, "needs an encoder"),
    ("encoder", [], "must be an object"),
    ("n_points", 3, "groups"),
    ("n_points", 10**12, "over the limit"),
    ("n_points", "256", "must be an integer"),
    ("variant", "global", "is not layout.variant"),
    ("version", True, "integer 1"),
    ("preset", "x" * 5000, "longer than"),
    ("weights", "/dev/zero", "not a file name"),
    ("weights", "../other/model.safetensors", "not a file name"),
    ("training", "lots", "must be an object"),
    ("min_anchor_half_m", 0.5, "this version uses"),
    ("layout.wdith", 32, "unknown field"),
    ("encoder.colour", "red", "unknown field"),
]


@pytest.mark.parametrize(("field", "value", "problem"), CONFIG_CASES)
def test_config_fields_out_of_range_are_one_line_errors(good, tmp_path, field, value, problem):
    folder = _with_config(good, tmp_path / "bad", _set(field, value))
    message = _refused(folder, CONFIG_FILE, problem)
    assert field.rsplit(".", 1)[-1] in message  # names the field


@pytest.mark.parametrize("field", ["layout.width", "layout.mixture", "encoder.depth", "n_points"])
def test_missing_fields_are_named(good, tmp_path, field):
    folder = _with_config(good, tmp_path / "bad", _drop(field))
    _refused(folder, CONFIG_FILE, field, "missing")


def test_nan_and_huge_numbers_in_config_json_are_refused(good, tmp_path):
    folder = _copy(good, tmp_path / "nan")
    text = (folder / CONFIG_FILE).read_text()
    (folder / CONFIG_FILE).write_text(text.replace('"dropout": 0.0', '"dropout": NaN', 1))
    _refused(folder, CONFIG_FILE, "finite")
    (folder / CONFIG_FILE).write_text(text.replace('"dropout": 0.0', '"dropout": 1e999', 1))
    _refused(folder, CONFIG_FILE, "finite")
    (folder / CONFIG_FILE).write_text(text.replace('"depth": 2', '"depth": 1' + "0" * 5000, 1))
    _refused(folder, CONFIG_FILE)


def test_sizes_within_range_but_too_many_parameters_name_the_fields(good, tmp_path):
    """Every field in range, 13 billion parameters together: counted on the meta device
    (no memory), refused naming the fields of the largest part."""

    def edit(doc):
        doc["layout"].update(width=4096, depth=64, heads=64, point_dim=4096)
        doc["encoder"]["width"] = 4096

    message = _refused(_with_config(good, tmp_path / "big", edit), "parameters", "layout.depth")
    assert f"{MAX_PARAMETERS / 1e6:.0f} M" in message


def test_point_groups_too_wide_for_memory_are_refused(good, tmp_path):
    def edit(doc):
        doc["encoder"].update(n_groups=256, group_size=256, pointnet_hidden=512)

    _refused(_with_config(good, tmp_path / "wide", edit), "pointnet_hidden", "activations")


def test_unknown_top_level_keys_are_ignored(good, tmp_path):
    folder = _with_config(good, tmp_path / "note", _set("note", {"by": "someone"}))
    assert load_checkpoint(folder).preset == "tiny"


def test_config_json_that_is_a_pipe_does_not_hang(good, tmp_path):
    if not hasattr(os, "mkfifo"):
        pytest.skip("no named pipes here")
    folder = tmp_path / "pipe"
    folder.mkdir()
    os.mkfifo(folder / CONFIG_FILE)
    _refused(folder, CONFIG_FILE, "not a regular file")


# -- model.safetensors -------------------------------------------------------------------


def _fill(value):
    return lambda state: {k: torch.full_like(v, value) for k, v in state.items()}


WEIGHT_CASES = {
    "all 1e38": (_fill(1e38), "beyond"),
    "all inf": (_fill(math.inf), "non-finite"),
    "all nan": (_fill(math.nan), "non-finite"),
    "one nan": (lambda s: {**s, "ln_f.weight": s["ln_f.weight"] * math.nan}, "ln_f.weight"),
    "float64 beyond float32": (
        lambda s: {**s, "ln_f.weight": s["ln_f.weight"].double() * 1e300},
        "non-finite",
    ),
    "integers": (lambda s: {**s, "ln_f.weight": s["ln_f.weight"].long()}, "floating-point"),
    "extra tensor": (lambda s: {**s, "evil": torch.zeros(3)}, "unexpected tensor"),
    "missing tensor": (
        lambda s: {k: v for k, v in s.items() if k != "head.proj.bias"},
        "missing tensor",
    ),
    "wrong shape": (lambda s: {**s, "ln_f.bias": torch.zeros(7)}, "has shape"),
}


@pytest.mark.parametrize("case", list(WEIGHT_CASES))
def test_bad_weights_are_one_line_errors(good, tmp_path, case):
    edit, problem = WEIGHT_CASES[case]
    folder = _with_weights(good, tmp_path / "bad", edit)
    _refused(folder, WEIGHTS_FILE, problem)


def test_weights_that_are_no_regular_file_are_refused(good, tmp_path):
    folder = _copy(good, tmp_path / "dir")
    (folder / WEIGHTS_FILE).unlink()
    (folder / WEIGHTS_FILE).mkdir()
    _refused(folder, WEIGHTS_FILE, "not a regular file")
    if hasattr(os, "mkfifo"):
        (folder / WEIGHTS_FILE).rmdir()
        os.mkfifo(folder / WEIGHTS_FILE)
        _refused(folder, WEIGHTS_FILE, "not a regular file")


def test_float64_weights_load_as_float32_and_sample(good, tmp_path):
    folder = _with_weights(good, tmp_path / "f64", lambda s: {k: v.double() for k, v in s.items()})
    model = from_pretrained(folder)
    assert {p.dtype for p in model.predictor.parameters()} == {torch.float32}
    boxes = model.sample(_query(), n=4, generator=np.random.default_rng(0))
    assert np.isfinite(boxes).all()


def test_loading_builds_no_throwaway_model_and_matches_a_fresh_one(good):
    """The skeleton is filled in place: same weights, eval mode, nothing left on meta, the
    encoder frozen as a freshly built predictor's is."""
    ckpt = load_checkpoint(good)
    state = st.load_file(str(good / WEIGHTS_FILE))
    loaded = ckpt.predictor.state_dict()
    assert loaded.keys() == state.keys()
    assert all(torch.equal(loaded[k], state[k]) for k in state)
    assert not any(t.is_meta for t in [*ckpt.predictor.parameters(), *ckpt.predictor.buffers()])
    assert not ckpt.predictor.training
    frozen = [p.requires_grad for p in ckpt.predictor.point_encoder.parameters()]
    assert frozen and not any(frozen)


# -- the limits admit every preset and the bundled model ------------------------------------


@pytest.mark.parametrize("name", list(PRESETS))
@pytest.mark.parametrize("variant", [v.value for v in LayoutVariant])
def test_every_preset_is_within_the_limits(name, variant):
    p = preset(name, variant)
    doc = {
        "format": FORMAT,
        "version": VERSION,
        "variant": variant,
        "preset": name,
        "layout": layout_config_to_dict(p.layout),
        "encoder": dataclasses.asdict(p.encoder),
        "n_points": p.n_points,
    }
    spec = check_model_config(doc, "preset")
    assert spec.layout == p.layout and spec.encoder == p.encoder
    net = skeleton(spec.layout, spec.encoder)
    shapes = expected_shapes(spec.layout, spec.encoder)
    # the shapes worked out without torch are the network's, in its order
    assert list(shapes.items()) == [(k, tuple(t.shape)) for k, t in net.state_dict().items()]
    count = check_parameter_count(shapes, spec, "preset")
    assert count == sum(p.numel() for p in net.parameters())
    assert count <= MAX_PARAMETERS / 3  # room to grow
    assert next(net.parameters()).is_meta


def test_the_bundled_config_is_within_the_limits():
    doc = json.loads((DEFAULT_DIR / CONFIG_FILE).read_text())
    spec = check_model_config(doc, DEFAULT_DIR / CONFIG_FILE)
    assert spec.preset == "cpu"


# -- drawing from distributions that cannot be drawn from ---------------------------------


def _query():
    desk = OrientedBox.from_yaw([2.0, 2.0, 0.375], [1.2, 0.6, 0.75], np.pi / 2)
    return PlacementQuery("mug", [0.1, 0.1, 0.1], Anchor("desk", desk), room=ROOM)


def _params(k=3, d=12, seed=0):
    g = torch.Generator().manual_seed(seed)
    return MixtureParams(
        torch.randn(2, k, generator=g),
        torch.randn(2, k, d, generator=g),
        0.1 * torch.randn(2, k, d, generator=g),
    )


def _broken(params, which, value, index=(0, 1)):
    tensors = [t.clone() for t in params]
    tensors[which][index] = value
    return MixtureParams(*tensors)


BROKEN = {
    "nan logit": (0, math.nan, "weights are not finite"),
    "inf logit": (0, math.inf, "weights are not finite"),
    "all logits -inf": (0, -math.inf, "weights are not finite"),
    "nan location": (1, math.nan, "non-finite locations"),
    "inf location": (1, math.inf, "non-finite locations"),
    "far location": (1, 10 * MAX_ABS_LOCATION, "beyond"),
    "nan log scale": (2, math.nan, "scales"),
    "zero scale": (2, -math.inf, "scales"),
}


@pytest.mark.parametrize("case", list(BROKEN))
@pytest.mark.parametrize("temperature", [1.0, 0.0])
def test_sampling_broken_mixtures_is_a_user_error_not_a_torch_error(case, temperature):
    which, value, problem = BROKEN[case]
    index = (0,) if case == "all logits -inf" else (0, 1)
    params = _broken(_params(), which, value, index)
    with pytest.raises(InvalidDistribution, match=problem) as info:
        sample(params, 5, temperature, torch.Generator().manual_seed(0))
    assert isinstance(info.value, UserError) and "invalid distributions" in str(info.value)
    window = Window([0, 1], torch.full((2, 2), -1.0), torch.full((2, 2), 1.0))
    with pytest.raises(InvalidDistribution):
        sample(params, 5, 1.0, torch.Generator().manual_seed(0), window)


def test_valid_mixtures_still_sample_and_single_minus_inf_logits_are_zero_weights():
    params = _params()
    check_params(params)
    params = _broken(params, 0, -math.inf)  # component 1 of row 0 switched off
    x = sample(params, 200, 1.0, torch.Generator().manual_seed(1))
    assert torch.isfinite(x).all()
    near = (x[0, :, None, :] - params.loc[0, None]).abs().amax(-1) < 1e-3
    assert not near[:, 1].any()


def test_overflowing_temperature_is_a_user_error():
    params = _broken(_params(), 0, 1e30)
    with pytest.raises(InvalidDistribution, match="temperature"):
        sample(params, 3, 1e-10, torch.Generator().manual_seed(0))


def test_drawing_from_a_model_with_extreme_weights_names_its_folder(good):
    """Weights pushed to 1e30 after loading (past the load-time check): the draw is a
    one-line UserError naming the checkpoint folder, not a numpy or torch error."""
    ckpt = load_checkpoint(good)
    with torch.no_grad():
        ckpt.predictor.head.proj.weight.fill_(1e30)
    with pytest.raises(UserError) as info:
        LayoutModel(ckpt).draw(_query(), 8, 1.0, np.random.default_rng(0))
    message = str(info.value)
    assert str(good) in message and "invalid distributions" in message and "\n" not in message
    with torch.no_grad():
        for p in ckpt.predictor.parameters():
            p.fill_(1e38)
    with pytest.raises(InvalidDistribution, match=str(good.name)):
        LayoutModel(ckpt).sample(_query(), 8, 0.0)


def _far_weights(state):
    """Weights within the load-time bound whose mixture locations land ~3e9 away: every
    hidden unit of the head ~1e4 (its bias), each output 1e4 times their sum. (Not
    through a layer norm's gain: its outputs sum to zero, and the sign of what rounding
    leaves of that sum differs between CPUs.)"""
    for key in ("head.fc.bias", "head.proj.weight"):
        state[key] = torch.full_like(state[key], 1e4)
    return state


def test_weights_within_bounds_but_absurd_distributions_fail_at_the_draw(good, tmp_path):
    folder = _with_weights(good, tmp_path / "far", _far_weights)
    model = from_pretrained(folder)  # every weight finite and <= 1e4
    with pytest.raises(InvalidDistribution, match="beyond") as info:
        model.draw(_query(), 8, 1.0, np.random.default_rng(0))
    assert str(folder) in str(info.value)


# -- the command line ----------------------------------------------------------------------


def _one_error_line(proc):
    assert proc.returncode == 2, proc.stderr[-2000:]
    assert "Traceback" not in proc.stderr
    lines = [line for line in proc.stderr.splitlines() if line.strip()]
    assert len(lines) == 1 and lines[0].startswith("error: "), proc.stderr[-2000:]
    return lines[0]


@pytest.mark.slow  # (CI runs the slow tests too: .ci/run)
def test_cli_generate_with_bad_checkpoints_exits_2_in_one_line(good, tmp_path):
    out = tmp_path / "out"
    huge = _with_config(good, tmp_path / "huge", _set("layout.mixture.num_components", 10**9))
    extreme = _with_weights(good, tmp_path / "extreme", _fill(1e38))
    far = _with_weights(good, tmp_path / "far", _far_weights)
    for folder, words in [
        (huge, ["num_components", "over the limit"]),
        (extreme, [WEIGHTS_FILE, "beyond"]),
        (far, ["invalid distributions"]),  # found at the first draw
    ]:
        t0 = time.perf_counter()
        args = ["generate", "--room", "bedroom", "--model", str(folder), "--out", str(out)]
        proc = run_cli(*args, "--num", "1", "--json", timeout=120)
        line = _one_error_line(proc)
        assert str(folder) in line and all(w in line for w in words), line
        assert time.perf_counter() - t0 < 60

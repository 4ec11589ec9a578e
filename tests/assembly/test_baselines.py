"""Baselines and ablations through the generate path: Gaussian and random placement,
no rejection, no gravity."""

from __future__ import annotations

import json

import numpy as np
import pytest
from scipy.stats import multivariate_normal

torch = pytest.importorskip("torch")

from pair2scene import Pair2Scene  # noqa: E402
from pair2scene.assembly.baselines import GaussianPlacement, RandomPlacement  # noqa: E402
from pair2scene.errors import UserError  # noqa: E402
from pair2scene.generate import ablation_config, generate_scenes  # noqa: E402
from pair2scene.io.scene_json import dumps_scene  # noqa: E402
from pair2scene.metrics.physical import physical_report  # noqa: E402
from pair2scene.model.api import Anchor, PlacementQuery  # noqa: E402
from pair2scene.model.baseline import GaussianBaseline, GaussianConfig, GaussianMixture  # noqa: E402
from pair2scene.scene.geometry import OrientedBox  # noqa: E402
from pair2scene.scene.model import FLOOR  # noqa: E402
from synthetic_pairs import write_synthetic_pairs  # noqa: E402

UPRIGHT_6D = [1.0, 0.0, 0.0, 0.0, 1.0, 0.0]


def one_key(x: np.ndarray, config: GaussianConfig) -> GaussianBaseline:
    n = len(x)
    return GaussianBaseline.fit_arrays(x, ["mug"] * n, ["desk"] * n, [""] * n, config)


def test_sampling_reproduces_a_fitted_gaussian():
    rng = np.random.default_rng(0)
    n = 4000
    x = np.zeros((n, 12))
    x[:, :2] = rng.multivariate_normal([0.4, -0.2], [[0.04, 0.03], [0.03, 0.09]], n)  # 2-D
    x[:, 2] = rng.normal(1.5, 0.1, n)  # 1-D
    x[:, 3:6] = [0.2, 0.3, 0.25]
    x[:, 6:] = UPRIGHT_6D
    config = GaussianConfig(components=1, covariance="full", log_size=False)
    baseline = one_key(x, config)
    draws = baseline.sample_arrays("mug", "desk", "", 40000, np.random.default_rng(1))
    np.testing.assert_allclose(draws[:, :3].mean(0), x[:, :3].mean(0), atol=0.01)
    np.testing.assert_allclose(np.cov(draws[:, :3].T), np.cov(x[:, :3].T), atol=0.004)
    assert np.cov(draws[:, :3].T)[0, 1] == pytest.approx(0.03, abs=0.005)  # correlation kept
    # temperature: covariances times T^2; T = 0 gives the mean
    half = baseline.sample_arrays("mug", "desk", "", 40000, np.random.default_rng(2),
                                  temperature=0.5)  # fmt: skip
    assert half[:, 2].std() == pytest.approx(0.05, rel=0.05)
    zero = baseline.sample_arrays("mug", "desk", "", 3, np.random.default_rng(3), temperature=0)
    np.testing.assert_allclose(zero[:, 2], x[:, 2].mean(), atol=1e-9)
    # diagonal covariances: the same marginals, no correlation
    diag = one_key(x, GaussianConfig(components=1, log_size=False))
    d = diag.sample_arrays("mug", "desk", "", 40000, np.random.default_rng(4))
    np.testing.assert_allclose(d[:, :3].std(0), x[:, :3].std(0), rtol=0.03)
    assert abs(np.corrcoef(d[:, :2].T)[0, 1]) < 0.03


def test_conditioning_is_the_exact_gaussian_conditional():
    means = np.array([[0.0, 1.0, -1.0], [2.0, 0.0, 0.5]])
    a = np.array([[1.0, 0.3, 0.5], [0.3, 2.0, -0.4], [0.5, -0.4, 1.5]])
    b = np.array([[0.5, 0.1, 0.0], [0.1, 0.3, 0.2], [0.0, 0.2, 0.8]])
    mix = GaussianMixture(np.array([0.3, 0.7]), means, np.stack([a, b]))
    given = np.array([0.4])
    cond = mix.condition([1], given)
    free = [0, 2]
    fit = [w * multivariate_normal(m[1], c[1, 1]).pdf(given[0])
           for w, m, c in zip(mix.weights, means, (a, b))]  # fmt: skip
    np.testing.assert_allclose(cond.weights, np.array(fit) / sum(fit), rtol=1e-10)
    for k, cov in enumerate((a, b)):
        # the same conditional through the precision matrix, another route
        prec = np.linalg.inv(cov)
        p_ff = prec[np.ix_(free, free)]
        want_cov = np.linalg.inv(p_ff)
        want_mean = means[k, free] - want_cov @ prec[np.ix_(free, [1])] @ (given - means[k, [1]])
        np.testing.assert_allclose(cond.covariances[k], want_cov, atol=1e-12)
        np.testing.assert_allclose(cond.means[k], want_mean, atol=1e-12)
    # diagonal: only the weights move
    diag = GaussianMixture(np.array([0.5, 0.5]), means, np.array([[1.0, 0.1, 2.0], [1, 1, 1]]))
    dc = diag.condition([1], given)
    np.testing.assert_allclose(dc.means, means[:, free])
    np.testing.assert_allclose(dc.covariances, diag.covariances[:, free])
    assert dc.weights[0] < dc.weights[1]  # 0.4 is 6 sd from component 0's 1.0


def test_sample_arrays_conditions_on_the_size():
    rng = np.random.default_rng(0)
    n = 2000
    x = np.zeros((n, 12))
    s = np.exp(rng.normal(np.log(0.3), 0.2, n))
    x[:, 3:6] = s[:, None] * [1.0, 1.0, 2.0] * np.exp(rng.normal(0, 0.05, (n, 3)))
    x[:, 2] = 1.0 + 2.0 * np.log(s) + rng.normal(0, 0.01, n)  # height tied to the log size
    x[:, 6:] = UPRIGHT_6D
    baseline = one_key(x, GaussianConfig(components=1, covariance="full"))
    size = np.array([0.5, 0.5, 1.0])
    draws = baseline.sample_arrays("mug", "desk", "", 500, np.random.default_rng(1), size)
    assert (draws[:, 3:6] == size).all()
    # the regression of the height on the log sizes, from the data's own moments
    y = np.column_stack([x[:, 2], np.log(x[:, 3:6])])
    mu, cov = y.mean(0), np.cov(y.T, bias=True)
    want = mu[0] + cov[0, 1:] @ np.linalg.solve(cov[1:, 1:], np.log(size) - mu[1:])
    assert want == pytest.approx(1.0 + 2.0 * np.log(0.5), abs=0.05)
    assert draws[:, 2].mean() == pytest.approx(want, abs=0.003)


def support_query(category: str, size, support: Anchor) -> PlacementQuery:
    return PlacementQuery(category, size, support, None, None)


def test_gaussian_placement_maps_into_the_support_frame():
    rng = np.random.default_rng(0)
    n = 60
    x = np.zeros((n, 12))
    x[:, :3] = [0.5, 0.0, 1.3]
    x[:, 3:6] = [0.2, 0.3, 0.25] * np.exp(rng.normal(0, 0.05, (n, 3)))
    x[:, 6:] = UPRIGHT_6D
    model = GaussianPlacement(one_key(x, GaussianConfig()))
    yaw = np.radians(30)
    desk = OrientedBox.from_yaw([2.0, 3.0, 0.4], [1.2, 0.6, 0.8], yaw)
    size = [0.12, 0.09, 0.1]
    query = support_query("mug", size, Anchor("desk", desk))
    out = model.sample(query, 64, 0.8, np.random.default_rng(0))
    want = desk.center + desk.rotation @ (np.array([0.5, 0.0, 1.3]) * desk.half_size)
    np.testing.assert_allclose(out[:, :3], np.broadcast_to(want, (64, 3)), atol=0.01)
    assert want[0] == pytest.approx(2.0 + 0.3 * np.cos(yaw))  # along the desk's x
    np.testing.assert_allclose(out[:, 3:6], np.broadcast_to(size, (64, 3)))
    np.testing.assert_allclose(out[:, 6:9], np.broadcast_to(desk.rotation[:, 0], (64, 3)),
                               atol=0.01)  # fmt: skip
    again = model.sample(query, 64, 0.8, np.random.default_rng(0))
    assert (again == out).all()
    # on the floor the support box is the room's bounds, as the dataset stores it
    floor = model.sample(support_query("mug", size, Anchor.floor(
        OrientedBox.from_yaw([2.5, 2.0, 1.4], [5.0, 4.0, 2.8]))), 8, 0.8, None)  # fmt: skip
    np.testing.assert_allclose(floor[:, :3].mean(0), [2.5 + 1.25, 2.0, 1.4 + 1.82], atol=0.02)


def test_gaussian_placement_draws_in_the_learned_models_frame(tmp_path):
    """A sofa to stand against a wall is drawn in that wall's frame (as the learned model
    draws it): against a wall of another room, facing as the training sofas do; without
    anchor frames the query's wall changes nothing. Random placement ignores it."""
    from pair2scene.curation.dataset import load_pairs
    from pair2scene.model.baseline import FRAME_FUNCTIONAL, FRAME_SUPPORT, FRAME_WALL
    from pair2scene.scene.walls import Wall

    pairs = load_pairs(write_synthetic_pairs(tmp_path / "pairs"))
    framed = GaussianPlacement(GaussianBaseline.fit(pairs, "train"))
    plain = GaussianPlacement(
        GaussianBaseline.fit(pairs, "train", GaussianConfig(anchor_frames=False))
    )
    room = OrientedBox.from_yaw([3.0, 2.5, 1.4], [6.0, 5.0, 2.8])
    wall = Wall(3, np.array([0.0, 5.0]), np.array([0.0, 0.0])).frame(2.8)  # x = 0, inward +x
    size = [2.0, 0.9, 0.8]
    query = PlacementQuery("sofa", size, Anchor.floor(room), wall=wall)
    assert framed.frame(query) == (FRAME_WALL, wall)
    assert plain.frame(query) == (FRAME_SUPPORT, room)
    out = framed.sample(query, 200, 1.0, np.random.default_rng(0))
    # training sofas: back at their wall (the centre half the 0.9 m depth out, and the
    # few centimetres they leave behind them), front (+y) towards the room
    assert 0.45 < np.median(out[:, 0]) < 0.55
    np.testing.assert_allclose(np.median(out[:, 6:8], axis=0), [0.0, 1.0], atol=0.05)
    np.testing.assert_allclose(np.median(out[:, 9:11], axis=0), [-1.0, 0.0], atol=0.05)
    np.testing.assert_allclose(out[:, 3:6], np.broadcast_to(size, (200, 3)))
    assert np.median(out[:, 2]) == pytest.approx(0.4, abs=0.03)  # on the floor
    # without anchor frames: the room's frame, the wall is not looked at
    gen = np.random.default_rng(0)
    no_wall = plain.sample(PlacementQuery("sofa", size, Anchor.floor(room)), 200, 1.0, gen)
    gen = np.random.default_rng(0)
    assert (plain.sample(query, 200, 1.0, gen) == no_wall).all()
    assert np.median(no_wall[:, 0]) > 1.0
    # a chair at a desk is drawn in the desk's footprint frame
    desk = OrientedBox.from_yaw([3.0, 2.0, 0.375], [1.2, 0.6, 0.75], 0.3)
    chair = PlacementQuery("chair", [0.5, 0.5, 0.9], Anchor.floor(room), Anchor("desk", desk))
    kind, frame = framed.frame(chair)
    assert kind == FRAME_FUNCTIONAL and frame.size[2] == pytest.approx(2.8)
    np.testing.assert_allclose(frame.center[:2], [3.0, 2.0])
    near = framed.sample(chair, 100, 1.0, np.random.default_rng(0))
    assert np.median(np.linalg.norm(near[:, :2] - [3.0, 2.0], axis=1)) < 1.0
    # the null model stays uniform whatever anchors the query names
    rand = RandomPlacement()
    gen = np.random.default_rng(0)
    want = rand.sample(PlacementQuery("sofa", size, Anchor.floor(room)), 50, 1.0, gen)
    gen = np.random.default_rng(0)
    assert (rand.sample(query, 50, 1.0, gen) == want).all()


def test_random_placement_stays_in_the_room_and_over_the_support():
    model = RandomPlacement()
    bounds = OrientedBox.from_yaw([2.5, 2.0, 1.4], [5.0, 4.0, 2.8])
    gen = np.random.default_rng(0)
    bed = model.sample(support_query("bed", [2.0, 1.6, 0.5], Anchor.floor(bounds)), 200, 1, gen)
    for vec in bed:
        box = OrientedBox.from_vector(vec)
        assert box.bottom == pytest.approx(0.0, abs=1e-9)
        corners = box.corners()[:, :2]
        assert (corners >= [-1e-9, -1e-9]).all() and (corners <= [5 + 1e-9, 4 + 1e-9]).all()
    yaws = np.arctan2(bed[:, 7], bed[:, 6])
    assert yaws.min() < -2.5 and yaws.max() > 2.5  # any yaw
    shelf = OrientedBox.from_yaw([1.0, 1.0, 0.9], [0.8, 0.4, 1.8], 0.7)
    books = model.sample(support_query("book", [0.2, 0.15, 0.03], Anchor("shelf", shelf)), 200)
    local = shelf.to_local(books[:, :3])
    assert (np.abs(local[:, :2]) <= shelf.half_size[:2] + 1e-9).all()
    bottom = books[:, 2] - 0.015
    assert (bottom >= -1e-9).all() and (bottom <= 1.8 + 1e-9).all() and np.ptp(bottom) > 1.0
    np.testing.assert_allclose(np.abs(books[:, 8]), 0.0, atol=1e-12)  # upright


@pytest.fixture(scope="module")
def random_p2s():
    return Pair2Scene.from_pretrained("random")


def test_random_scenes_are_placed_collision_free_and_seeded(random_p2s):
    g = random_p2s.generate(room="bedroom", seed=0)
    assert g.stats.objects_placed == len(g.scene.objects) > 5
    report = physical_report(g.scene, g.assets, simulate=False)
    assert report["collision_rate"] == 0 and report["floating_rate"] == 0, report
    again = random_p2s.generate(room="bedroom", seed=0)
    assert dumps_scene(again.scene) == dumps_scene(g.scene)


def test_ablations(random_p2s):
    default = random_p2s.generate(room="bedroom", seed=1)
    loose = Pair2Scene(random_p2s.model, random_p2s.stats, random_p2s.placer.sizes,
                       random_p2s.rooms, ablation_config("no-rejection"))  # fmt: skip
    g = loose.generate(room="bedroom", seed=1)
    assert g.stats.assembly.resamples_per_object == 0 and g.stats.assembly.rejections == {}
    assert g.stats.objects_placed == default.stats.objects_placed
    afloat = Pair2Scene(random_p2s.model, random_p2s.stats, random_p2s.placer.sizes,
                        random_p2s.rooms, ablation_config(["no-gravity"]))  # fmt: skip
    g = afloat.generate(room="bedroom", seed=1)
    report = physical_report(g.scene, g.assets, simulate=False)
    supported = {o.id for o in g.scene.objects if o.support != FLOOR}
    assert set(report["floating"]) & supported  # drawn above the surface, left there
    assert report["collision_rate"] == 0  # still rejected
    assert dumps_scene(afloat.generate(room="bedroom", seed=1).scene) == dumps_scene(g.scene)
    with pytest.raises(UserError, match="unknown"):
        ablation_config("no-walls")


def test_gaussian_and_random_through_generate_scenes(tmp_path):
    pairs = tmp_path / "pairs"
    write_synthetic_pairs(pairs)
    spec = f"gaussian:{pairs}"  # (the synthetic pairs furnish a kitchen; few bedrooms)
    seed, name = 2, "kitchen_0002"  # (their Gaussian fits few kitchens: seed 0 places none)
    out = tmp_path / "g"
    summary = generate_scenes(out, room="kitchen", model=spec, ablation=["no-gravity"],
                              progress=False, seed=seed)  # fmt: skip
    assert summary.request["model"] == spec and summary.request["ablation"] == ["no-gravity"]
    assert summary.scenes[name]["objects_placed"] > 0
    first = (out / name / "scene.json").read_text()
    again = tmp_path / "again"
    generate_scenes(
        again, room="kitchen", model=spec, ablation="no-gravity", progress=False, seed=seed
    )
    assert (again / name / "scene.json").read_text() == first
    # a saved baseline loads as gaussian:FILE.json
    model = GaussianPlacement.from_spec(pairs)
    model.baseline.save(tmp_path / "b.json")
    saved = generate_scenes(tmp_path / "s", room="kitchen", model=f"gaussian:{tmp_path / 'b.json'}",
                            ablation="no-gravity", progress=False, seed=seed)  # fmt: skip
    placed = summary.scenes[name]["objects_placed"]
    assert saved.scenes[name]["objects_placed"] == placed
    # the default request keeps its old keys
    plain = generate_scenes(tmp_path / "r", room="kitchen", model="random", progress=False)
    assert set(plain.request) == {"room", "text", "mode", "max_objects", "model", "llm"}
    doc = json.loads((tmp_path / "r" / "summary.json").read_text())
    assert doc["request"]["model"] == "random"
    for bad, msg in [("gaussian", "gaussian:PAIRS_DIR"), ("nonsense", "no such model"),
                     (f"gaussian:{tmp_path / 'nope'}", "no such file")]:  # fmt: skip
        with pytest.raises(UserError, match=msg):
            generate_scenes(tmp_path / "bad", room="bedroom", model=bad, progress=False)


@pytest.mark.slow  # (CI runs the slow tests too: .ci/run)
def test_cli_model_and_ablation(tmp_path):
    from clitools import run_cli

    out = tmp_path / "o"
    ablate = ["--ablation", "no-rejection", "--ablation", "no-gravity"]
    proc = run_cli("generate", "--room", "bedroom", "--model", "random", *ablate,
                   "--out", str(out), "--json")  # fmt: skip
    assert proc.returncode == 0, proc.stderr
    summary = json.loads(proc.stdout)
    assert summary["request"]["ablation"] == ["no-gravity", "no-rejection"]
    assert summary["totals"]["resamples_per_object"] == 0
    for args, msg in [(["--model", "bogus"], "no such model"),
                      (["--ablation", "no-walls"], "unknown")]:  # fmt: skip
        proc = run_cli("generate", "--room", "bedroom", *args, "--out", str(tmp_path / "x"))
        assert proc.returncode == 2 and msg in proc.stderr, proc.stderr
        assert proc.stderr.count("\n") == 1 and "Traceback" not in proc.stderr

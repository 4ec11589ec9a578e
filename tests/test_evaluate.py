"""pair2scene evaluate: the harness on generated scenes, and its bad inputs."""

from __future__ import annotations

import json
import shutil

import numpy as np
import pytest

from clitools import run_cli

pytest.importorskip("torch")

from pair2scene.assembly.keep import keep_assets  # noqa: E402
from pair2scene.errors import UserError  # noqa: E402
from pair2scene.evaluate import evaluate, load_reference, parse_reference  # noqa: E402
from pair2scene.generate import Pair2Scene, generate_scenes  # noqa: E402
from pair2scene.io.scene_json import read_scene, write_scene  # noqa: E402


@pytest.fixture(scope="module")
def scenes(tmp_path_factory):
    out = tmp_path_factory.mktemp("gen") / "scenes"
    # five: the pose MMD needs an anchor/dependent pair seen three times (MIN_PAIR_SAMPLES)
    generate_scenes(out, room="bedroom", num=5, seed=0, progress=False)
    return out


def test_scene_json_rebuilds_the_exact_assets(tmp_path):
    g = Pair2Scene.from_pretrained().generate(room="bedroom", seed=5)
    write_scene(g.scene, tmp_path / "s.json")
    rebuilt = keep_assets(read_scene(tmp_path / "s.json"))
    for oid, asset in g.assets.items():
        np.testing.assert_allclose(rebuilt[oid].mesh.vertices, asset.mesh.vertices, atol=1e-5)


def test_against_itself_distribution_metrics_are_zero(scenes, tmp_path):
    report = evaluate(scenes, [str(scenes)], tmp_path / "r.json", images=False, progress=False)
    doc = json.loads((tmp_path / "r.json").read_text())
    assert doc == report
    assert report["n_generated"] == report["n_reference"] == 5
    assert report["category_kl"] == pytest.approx(0.0, abs=1e-9)
    assert report["pose_mmd"] == pytest.approx(0.0, abs=1e-9)
    assert report["collision_rate"] == 0.0 and report["floating_rate"] == 0.0
    assert 0.8 <= report["stability"] <= 1.0
    summary = json.loads((scenes / "summary.json").read_text())["totals"]
    assert report["acceptance_rate"] == pytest.approx(summary["acceptance_rate"], abs=1e-3)
    assert report["objects_per_scene"] == pytest.approx(summary["objects_per_scene"], abs=1e-3)
    assert (tmp_path / "r.json.cache.json").is_file()  # resumable per-scene physics
    # The same rooms on both sides: no row differs beyond noise (each exact test's p is 1).
    tested = [(name, row) for section in ("layout", "navigation", "walls")
              for name, row in report[section].items() if isinstance(row, dict)
              and row.get("p_value") is not None]  # fmt: skip
    assert len(tested) >= 10
    assert all(row["p_value"] == pytest.approx(1.0) for _, row in tested)
    per_room = dict(tested)["wall_objects_per_room"]
    assert per_room["test"] == "poisson" and per_room["generated_ci"] is None


def test_cli_against_ai2thor_val_and_a_shifted_set(scenes, tmp_path):
    # A "generated" set with every object lifted by 10 cm: the floor's float (what rests
    # on them rises with them), and everything falls.
    lifted = tmp_path / "lifted"
    shutil.copytree(scenes, lifted)
    on_floor = total = 0
    for f in lifted.glob("*/scene.json"):
        doc = json.loads(f.read_text())
        for o in doc["objects"]:
            o["center"][2] += 0.1
            on_floor += o["support"] == "floor"
            total += 1
        f.write_text(json.dumps(doc))
    out = tmp_path / "report.json"
    proc = run_cli("evaluate", "--scenes", str(lifted), "--reference", "ai2thor:val",
                   "--out", str(out), "--no-images")  # fmt: skip
    assert proc.returncode == 0, proc.stderr
    report = json.loads(out.read_text())
    assert report["floating_rate"] == pytest.approx(on_floor / total)
    assert report["stability"] < 0.5
    assert report["category_kl"] > 0 and report["n_reference"] == 5  # 5 val bedrooms
    for key in ("collision_rate", "floating_rate", "stability", "acceptance_rate",
                "resamples_per_object", "objects_per_scene", "seconds_per_scene",
                "category_kl", "sca", "fid", "kid"):  # fmt: skip
        assert key in report and key in proc.stdout
    assert "differ?" in proc.stdout and "Fisher's for shares" in proc.stdout


def test_reference_specs():
    assert parse_reference("ai2thor:val") == ("ai2thor", "val")
    assert parse_reference("ai2thor") == ("ai2thor", None)
    assert parse_reference("procthor:/a/b.jsonl.gz:train") == ("procthor:/a/b.jsonl.gz", "train")
    assert parse_reference("procthor:/a/b.jsonl.gz") == ("procthor:/a/b.jsonl.gz", None)


def test_a_bad_reference_says_what_was_wrong_once(tmp_path):
    """A spec of no known form lists the forms; a known form that is incomplete or whose
    file is bad says what is wrong, without the list of forms (which it followed)."""
    bad = tmp_path / "houses.jsonl"
    bad.write_text("not json\n")
    forms = "use ai2thor[:val], procthor:PATH[:val]"
    for spec in ("nonsense:val", "ai2thor:tran", "procthor"):
        with pytest.raises(UserError) as e:
            load_reference([spec])
        assert str(e.value).startswith(f"--reference {spec}: ")
        assert str(e.value).count("use ") == (spec != "procthor"), str(e.value)
        assert (forms in str(e.value)) == (spec != "procthor")
    with pytest.raises(UserError) as e:
        load_reference([f"procthor:{bad}:val"])
    wrong = f"{bad}: line 1: not valid JSON (Expecting value)"
    assert str(e.value) == f"--reference procthor:{bad}:val: {wrong}"


@pytest.mark.parametrize(
    "args, message",
    [
        (["--scenes", "MISSING"], "no such folder"),
        (["--reference", "nonsense:val"], "unknown source"),
        (["--reference", "EMPTY"], "no scene.json files"),
    ],
)
def test_bad_input_is_one_line_and_exit_2(scenes, tmp_path, args, message):
    (tmp_path / "EMPTY").mkdir()
    args = [a.replace("MISSING", str(tmp_path / "nope")).replace("EMPTY", str(tmp_path / "EMPTY"))
            for a in args]  # fmt: skip
    base = {"--scenes": str(scenes), "--reference": "ai2thor:val"}
    for k in range(0, len(args), 2):
        base[args[k]] = args[k + 1]
    flat = [x for kv in base.items() for x in kv]
    proc = run_cli("evaluate", *flat, "--out", str(tmp_path / "r.json"), "--no-images")
    assert proc.returncode == 2
    assert message in proc.stderr and len(proc.stderr.strip().splitlines()) == 1
    assert not (tmp_path / "r.json").exists()


def test_corrupt_scene_and_wrong_room_type(scenes, tmp_path):
    bad = tmp_path / "bad"
    shutil.copytree(scenes, bad)
    next(bad.glob("*/scene.json")).write_text("{not json")
    proc = run_cli("evaluate", "--scenes", str(bad), "--out", str(tmp_path / "r.json"))
    assert proc.returncode == 2 and len(proc.stderr.strip().splitlines()) == 1
    kitchen = tmp_path / "kitchens"
    generate_scenes(kitchen, room="kitchen", num=1, progress=False)
    proc = run_cli("evaluate", "--scenes", str(kitchen), "--reference", str(scenes),
                   "--out", str(tmp_path / "r.json"))  # fmt: skip
    assert proc.returncode == 2 and "no kitchen rooms" in proc.stderr

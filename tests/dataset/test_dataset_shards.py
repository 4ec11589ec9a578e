"""Shards on disk: same bytes whoever makes them, resume after SIGKILL, verify, tar."""

from __future__ import annotations

import json
import os
import signal
import subprocess
import sys
import tarfile
import time
from pathlib import Path

import pytest

from pair2scene.cli.dataset import run
from pair2scene.dataset import DatasetConfig, run_dataset, verify_dataset
from pair2scene.dataset.shards import INDEX, MANIFEST, PARQUET_INDEX

MIX = (("bedroom", 0.5), ("kitchen", 0.5))
TINY = DatasetConfig(mix=MIX, num=6, max_objects=6, formats=("json",), shard_size=2)
"""Three shards of two small scenes."""
ARGS = ["--room", "bedroom", "--room", "kitchen", "--num", "6", "--max-objects", "6",
        "--formats", "json", "--shard-size", "2", "--quiet"]  # fmt: skip
"""TINY on the command line."""
KILL_TIMEOUT = 120
"""Seconds to wait for the first shard of the run that is killed."""


def scene_bytes(out: Path) -> dict[str, bytes]:
    """Every scene.json of a dataset (folder or tar shards), by member name."""
    found: dict[str, bytes] = {}
    for path in sorted((out / "shards").iterdir()):
        if path.name.startswith("."):
            continue
        if path.suffix == ".tar":
            with tarfile.open(path) as tar:
                for m in tar:
                    if m.name.endswith(".scene.json"):
                        assert m.name not in found
                        found[m.name] = tar.extractfile(m).read()
        elif path.is_dir():
            for f in path.glob("*.scene.json"):
                assert f.name not in found
                found[f.name] = f.read_bytes()
    return found


@pytest.fixture(scope="module")
def reference(tmp_path_factory) -> Path:
    """TINY made in this process, uninterrupted."""
    out = tmp_path_factory.mktemp("reference") / "ds"
    summary = run_dataset(out, TINY, progress=False)
    assert summary.scenes == 6 and summary.index_written
    return out


def test_dataset_layout_and_index(reference):
    manifest = json.loads((reference / MANIFEST).read_text())
    assert manifest["settings"]["num"] == 6
    assert any(k.startswith("model/default/") for k in manifest["bundled_digests"])
    assert len(manifest["shards"]) == 3
    rows = [json.loads(line) for line in (reference / INDEX).read_text().splitlines()]
    assert [r["id"] for r in rows] == [s[0] for v in manifest["shards"].values() for s in v]
    assert {r["room"] for r in rows} == {"bedroom", "kitchen"}
    assert all(r["objects_placed"] <= r["objects_requested"] <= 6 for r in rows)
    assert len(scene_bytes(reference)) == 6
    assert verify_dataset(reference).clean


def test_parquet_index_filters_like_the_jsonl_one(reference):
    pq = pytest.importorskip("pyarrow.parquet")
    table = pq.read_table(reference / PARQUET_INDEX)
    rows = [json.loads(line) for line in (reference / INDEX).read_text().splitlines()]
    assert table.column("id").to_pylist() == [r["id"] for r in rows]
    assert table.column("shard").to_pylist() == [r["shard"] for r in rows]
    assert table.column("dropped").to_pylist() == [sum(r["drops"].values()) for r in rows]
    assert [json.loads(d) for d in table.column("drops").to_pylist()] == [r["drops"] for r in rows]
    bedrooms = [r for r in table.to_pylist() if r["room"] == "bedroom" and r["objects_placed"] >= 1]
    assert len(bedrooms) == sum(r["room"] == "bedroom" and r["objects_placed"] >= 1 for r in rows)


def test_rerun_skips_and_other_settings_are_refused(reference, capsys):
    summary = run_dataset(reference, TINY, progress=False)
    assert summary.scenes == 0 and summary.skipped_shards == 3
    code = run([*ARGS[:-1], "--seed", "1", "--quiet", "--out", str(reference)])
    err = capsys.readouterr().err
    assert code == 2 and err.count("\n") == 1 and "other settings" in err


def test_verify_catches_corruption_and_a_rerun_repairs(reference, tmp_path, capsys):
    import shutil

    out = tmp_path / "ds"
    shutil.copytree(reference, out)
    victim = next((out / "shards" / "shard-00001").glob("*.scene.json"))
    victim.write_bytes(victim.read_bytes().replace(b"{", b"[", 1))
    (out / "shards" / "shard-00002.index.jsonl").unlink()
    assert run(["verify", str(out)]) == 1
    lines = capsys.readouterr().out.splitlines()
    assert any(line.startswith("shard-00001: corrupt") for line in lines)
    assert "shard-00002: missing" in lines
    summary = run_dataset(out, TINY, progress=False)
    assert summary.shards == 2 and summary.skipped_shards == 1
    assert run(["verify", str(out)]) == 0
    assert scene_bytes(out) == scene_bytes(reference)


def test_tar_members(reference, tmp_path):
    # the plan does not depend on the shard size: the same scenes, in two shards of 3
    config = DatasetConfig(mix=MIX, num=6, max_objects=6, formats=("json", "png"),
                           shard_size=3, shard_format="tar")  # fmt: skip
    out = tmp_path / "ds"
    run_dataset(out, config, progress=False)
    with tarfile.open(out / "shards" / "shard-00000.tar") as tar:
        members = tar.getmembers()
    ids = [json.loads(line)["id"] for line in (out / INDEX).read_text().splitlines()][:3]
    assert [m.name for m in members] == [f"{i}.{e}" for i in ids for e in ("scene.json", "bev.png")]
    assert all(m.mtime == 0 and m.uid == 0 for m in members)
    assert scene_bytes(out) == scene_bytes(reference)
    assert verify_dataset(out).clean


def cli(*args: str) -> list[str]:
    return [sys.executable, "-m", "pair2scene.cli.dataset", *args]


def test_two_jobs_give_the_same_bytes(reference, tmp_path):
    out = tmp_path / "ds"
    done = subprocess.run(cli(*ARGS, "--jobs", "2", "--out", str(out)), capture_output=True,
                          text=True, timeout=300)  # fmt: skip
    assert done.returncode == 0, done.stderr
    assert "6 scenes in 3 shards" in done.stdout
    assert scene_bytes(out) == scene_bytes(reference)


@pytest.mark.slow  # (CI runs the slow tests too: .ci/run)
def test_sigkill_part_way_then_resume(reference, tmp_path):
    out = tmp_path / "ds"
    proc = subprocess.Popen(cli(*ARGS, "--out", str(out)), stdout=subprocess.DEVNULL,
                            stderr=subprocess.DEVNULL)  # fmt: skip
    first = out / "shards" / "shard-00000.index.jsonl"
    deadline = time.monotonic() + KILL_TIMEOUT
    while not first.exists() and proc.poll() is None and time.monotonic() < deadline:
        time.sleep(0.05)
    os.kill(proc.pid, signal.SIGKILL)
    proc.wait()
    assert first.exists()
    assert not (out / INDEX).exists()  # (killed before the end)
    again = subprocess.run(cli(*ARGS, "--out", str(out)), capture_output=True, text=True,
                           timeout=300)  # fmt: skip
    assert again.returncode == 0, again.stderr
    assert verify_dataset(out).clean
    assert scene_bytes(out) == scene_bytes(reference)  # every scene once, same bytes
    hidden = [p.name for p in (out / "shards").iterdir() if p.name.startswith(".")]
    assert hidden == []


def pool_workers(parent: int) -> list[int]:
    """The pids of the worker processes ``parent`` spawned (not its resource tracker)."""
    children = Path(f"/proc/{parent}/task/{parent}/children").read_text().split()
    return [int(c) for c in children if b"spawn_main" in Path(f"/proc/{c}/cmdline").read_bytes()]


@pytest.mark.slow  # (CI runs the slow tests too: .ci/run)
@pytest.mark.slow  # (CI runs the slow tests too: .ci/run)
@pytest.mark.skipif(not Path("/proc/self/task").exists(), reason="needs Linux /proc")
def test_a_killed_local_worker_costs_only_a_retry(tmp_path):
    config = DatasetConfig(mix=MIX, num=16, max_objects=6, formats=("json",), shard_size=2)
    whole = tmp_path / "whole"
    run_dataset(whole, config, progress=False)
    out = tmp_path / "ds"
    args = [*ARGS, "--num", "16", "--jobs", "2", "--out", str(out)]  # (the later --num wins)
    proc = subprocess.Popen(cli(*args), stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                            text=True)  # fmt: skip
    first = out / "shards" / "shard-00000.index.jsonl"
    deadline = time.monotonic() + KILL_TIMEOUT
    while not first.exists() and proc.poll() is None and time.monotonic() < deadline:
        time.sleep(0.02)
    workers = pool_workers(proc.pid)
    assert workers, "no worker processes found"
    os.kill(workers[0], signal.SIGKILL)
    stdout, stderr = proc.communicate(timeout=300)
    assert proc.returncode == 0, stderr
    assert "16 scenes in 8 shards" in stdout
    assert "1 retry after a worker died" in stdout
    assert verify_dataset(out).clean
    assert scene_bytes(out) == scene_bytes(whole)  # every scene once, same bytes


@pytest.mark.slow  # (CI runs the slow tests too: .ci/run)
def test_ray_gives_the_same_bytes(reference, tmp_path):
    ray = pytest.importorskip("ray")
    # a fresh instance of its own, even when a cluster already runs on this machine
    ray.init(address="local", num_cpus=2, include_dashboard=False, log_to_driver=False)
    try:
        out = tmp_path / "ds"
        summary = run_dataset(out, TINY, executor="ray", jobs=2, progress=False)
    finally:
        ray.shutdown()
    assert summary.scenes == 6
    assert scene_bytes(out) == scene_bytes(reference)
    assert verify_dataset(out).clean


def test_summary_counts_a_scene_once_and_groups_drop_reasons():
    from pair2scene.dataset.executors import RunSummary

    summary = RunSummary(seconds=2.0)
    tally = "no valid placement among 256 candidates"
    record = {"id": "bedroom-fit-00000001", "objects_placed": 9, "objects_requested": 10,
              "drops": {f"{tally} (collision 200, outside 56)": 1}}  # fmt: skip
    assert summary.add(record)
    assert not summary.add(record)  # (its shard made again after a worker died)
    other = dict(record, id="kitchen-fit-00000002", drops={f"{tally} (faces_away 256)": 2})
    assert summary.add(other)
    assert (summary.scenes, summary.objects_placed) == (2, 18)
    big = dict(record, id="kitchen-fit-00000003", drops={"too large: its base is 1.14 x 0.03 m": 1})
    assert summary.add(big)
    assert summary.drops == {tally: 3, "too large: its base is # x # m": 1}
    assert summary.lines()[1] == f"drops by reason: {tally}: 3, too large: its base is # x # m: 1"

"""Issue 21: work bounded by construction, and no debris in an output folder.

A killed write leaves hidden temporary folders; the next run removes them, and no reader
counts them. Scene folders get a plain mkdir's mode. A malformed summary.json is one line
naming the field. ``max_objects`` past the limit is refused by the library itself.
"""

from __future__ import annotations

import json
import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest

from clitools import ROOT, run_cli
from pair2scene.data.scene_folder import load_scene_dir
from pair2scene.errors import UserError
from pair2scene.evaluate import scene_files
from pair2scene.hierarchy.build import build_hierarchy
from pair2scene.hierarchy.synthesis import MAX_OBJECTS_LIMIT, SynthesisConfig
from pair2scene.io.export import stale_scene_folders
from pair2scene.io.scene_json import read_scene
from pair2scene.io.summary import SUMMARY_FORMAT, SUMMARY_VERSION

FAST = ("--room", "bedroom", "--model", "random", "--max-objects", "3")
"""A cheap request: uniform placement of three objects (about 0.1 s a scene)."""
REQUEST = {"room": "bedroom", "text": None, "mode": "fit", "max_objects": 3,
           "model": "random", "llm": "auto"}  # fmt: skip
"""The request FAST makes, as summary.json records it."""


def umask() -> int:
    mask = os.umask(0)
    os.umask(mask)
    return mask


def visible_scenes(out: Path) -> list[str]:
    return sorted(p.name for p in out.iterdir() if p.is_dir() and not p.name.startswith("."))


def check_clean(out: Path) -> None:
    """No hidden entries, every scene folder whole and readable, and every reader counts
    exactly the scene folders."""
    assert [p.name for p in out.iterdir() if p.name.startswith(".")] == []
    names = visible_scenes(out)
    for name in names:
        files = sorted(p.name for p in (out / name).iterdir())
        assert files == ["bev.png", "scene.glb", "scene.html", "scene.json"], (name, files)
        assert read_scene(out / name / "scene.json").id == name
    assert len(scene_files(out)) == len(names)
    assert len(load_scene_dir(out).scenes) == len(names)


def test_stale_temporaries_are_removed_and_scene_folders_get_a_plain_mode(tmp_path):
    out = tmp_path / "out"
    debris = out / ".bedroom_0000.xyz123"
    debris.mkdir(parents=True)
    (debris / "scene.json").write_text('{"format": "pair2scene.sce')  # cut mid-write
    (debris / ".scene.glb.a1b2c3d4.tmp").write_bytes(b"glTF")
    holder = out / ".bedroom_0001.old.k9f2x1zz" / "x"  # a replaced folder, killed mid-swap
    holder.mkdir(parents=True)
    (holder / "scene.json").write_text("{}")
    (out / ".summary.json.q7w8e9r0.tmp").write_text('{"format"')
    # hidden things that are not the package's temporaries stay as they are
    (out / ".git").mkdir()
    mine = out / ".notes.backup"
    mine.mkdir()
    (mine / "todo.txt").write_text("mine")
    (out / ".summary.json.bak").write_text("mine")
    assert [p.name for p in stale_scene_folders(out)] == [
        ".bedroom_0000.xyz123",
        ".bedroom_0001.old.k9f2x1zz",
    ]
    with pytest.raises(UserError, match="no scene.json files"):
        scene_files(out)  # the debris is never taken for a scene, even before a run

    proc = run_cli("generate", *FAST, "--num", "2", "--out", str(out))
    assert proc.returncode == 0, proc.stderr
    left = sorted(p.name for p in out.iterdir() if p.name.startswith("."))
    assert left == [".git", ".notes.backup", ".summary.json.bak"]
    assert (mine / "todo.txt").read_text() == "mine"
    for name in left:
        (out / name).rename(tmp_path / name)
    check_clean(out)
    assert visible_scenes(out) == ["bedroom_0000", "bedroom_0001"]
    summary = json.loads((out / "summary.json").read_text())
    assert summary["totals"]["scenes"] == 2

    mask = umask()
    for name in visible_scenes(out):
        assert (out / name).stat().st_mode & 0o777 == 0o777 & ~mask
        for f in (out / name).iterdir():
            assert f.stat().st_mode & 0o777 == 0o666 & ~mask
    assert (out / "summary.json").stat().st_mode & 0o777 == 0o666 & ~mask


def kill_mid_write(out: Path, sig: int) -> tuple[subprocess.CompletedProcess, list[str]]:
    """Start ``generate --num 50``; once its first scene folder is there, send ``sig`` the
    moment a scene is being written (a temporary folder exists). Returns the finished
    process and the hidden entries seen when the signal went."""
    cmd = [sys.executable, "-m", "pair2scene", "generate", *FAST, "--num", "50", "--out",
           str(out)]  # fmt: skip
    proc = subprocess.Popen(cmd, cwd=ROOT, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE)
    seen: list[str] = []
    try:
        deadline = time.monotonic() + 120
        while time.monotonic() < deadline and proc.poll() is None:
            if out.is_dir() and visible_scenes(out):
                break
            time.sleep(0.01)
        deadline = time.monotonic() + 30
        while time.monotonic() < deadline and proc.poll() is None:
            seen = [n for n in os.listdir(out) if n.startswith(".")]
            if seen:
                break
            time.sleep(0.001)
        proc.send_signal(sig)
        _, err = proc.communicate(timeout=60)
    finally:
        if proc.poll() is None:
            proc.kill()
            proc.wait()
    return subprocess.CompletedProcess(cmd, proc.returncode, "", err.decode()), seen


@pytest.mark.slow  # (CI runs the slow tests too: .ci/run)
def test_a_killed_run_leaves_debris_the_rerun_removes(tmp_path):
    out = tmp_path / "out"
    proc, seen = kill_mid_write(out, signal.SIGKILL)
    assert proc.returncode == -signal.SIGKILL, proc.stderr
    assert seen, "the run ended before a scene was being written"
    # whatever the kill left, readers count only whole scene folders
    names = visible_scenes(out)
    assert names and len(scene_files(out)) == len(names)

    rerun = run_cli("generate", *FAST, "--num", "3", "--out", str(out))
    assert rerun.returncode == 0, rerun.stderr
    check_clean(out)
    summary = json.loads((out / "summary.json").read_text())
    ids = [s["id"] for s in summary["scenes"]]
    assert {"bedroom_0000", "bedroom_0001", "bedroom_0002"} <= set(ids)
    assert set(ids) <= set(visible_scenes(out))


def test_sigterm_unwinds_and_removes_the_scene_being_written(tmp_path):
    out = tmp_path / "out"
    proc, seen = kill_mid_write(out, signal.SIGTERM)
    assert proc.returncode == 128 + signal.SIGTERM, proc.stderr
    assert "Traceback" not in proc.stderr
    assert seen
    check_clean(out)


def write_summary(out: Path, scenes) -> bytes:
    out.mkdir(parents=True, exist_ok=True)
    doc = {"format": SUMMARY_FORMAT, "version": SUMMARY_VERSION, "request": REQUEST,
           "scenes": scenes}  # fmt: skip
    (out / "summary.json").write_text(json.dumps(doc))
    return (out / "summary.json").read_bytes()


RECORD = {"id": "bedroom_0000", "objects_placed": 3, "acceptance_rate": 1.0,
          "resamples_per_object": 0.0, "seconds": {"total": 0.1}}  # fmt: skip
"""A scene record with the figures a summary's totals are computed from."""


@pytest.mark.parametrize(
    "scenes, field",
    [
        ("oops", "scenes: must be a list"),
        (["oops"], r"scenes\[0\]: must be an object"),
        ([{**RECORD, "id": 7}], r"scenes\[0\]\.id: must be a scene id"),
        ([{"id": "bedroom_0000"}], r"scenes\[0\]\.objects_placed: must be a number"),
        ([RECORD, {**RECORD, "resamples_per_object": "x"}], r"scenes\[1\]\.resamples_per"),
        ([{**RECORD, "acceptance_rate": True}], r"scenes\[0\]\.acceptance_rate: must be"),
        ([{**RECORD, "seconds": 2}], r"scenes\[0\]\.seconds\.total: must be a number"),
    ],
)
def test_a_malformed_summary_stops_a_resume_in_one_line(tmp_path, scenes, field):
    from pair2scene.generate import generate_scenes

    out = tmp_path / "out"
    before = write_summary(out, scenes)
    with pytest.raises(UserError, match=field) as err:
        generate_scenes(out, room="bedroom", max_objects=3, model="random", progress=False)
    msg = str(err.value)
    assert "\n" not in msg and "summary.json" in msg and "delete it" in msg
    assert (out / "summary.json").read_bytes() == before  # never overwritten
    assert sorted(p.name for p in out.iterdir()) == ["summary.json"]


def test_max_objects_past_the_limit_is_refused_by_the_library(tmp_path):
    from pair2scene.generate import generate_scenes

    for n in (MAX_OBJECTS_LIMIT + 1, 100_000, 1_000_000):
        with pytest.raises(UserError, match=f"at most {MAX_OBJECTS_LIMIT}"):
            SynthesisConfig("beyond", max_objects=n)
        start = time.monotonic()
        with pytest.raises(UserError, match=f"--max-objects {n}: .*at most {MAX_OBJECTS_LIMIT}"):
            build_hierarchy("bedroom", mode="beyond", max_objects=n)
        with pytest.raises(UserError, match=f"at most {MAX_OBJECTS_LIMIT}"):
            build_hierarchy(text="a bedroom", max_objects=n, llm="never")
        assert time.monotonic() - start < 5
    for bad in (0, -3, 2.5, "80", True):
        with pytest.raises(UserError, match="--max-objects"):
            SynthesisConfig(max_objects=bad)
    with pytest.raises(UserError, match="--seed must be >= 0"):
        build_hierarchy("bedroom", seed=-1)
    # a refused request writes nothing, not even the output folder
    out = tmp_path / "out"
    with pytest.raises(UserError, match=f"at most {MAX_OBJECTS_LIMIT}"):
        generate_scenes(out, room="bedroom", mode="beyond", max_objects=100_000,
                        model="random", progress=False)  # fmt: skip
    assert not out.exists()
    h = build_hierarchy("bedroom", mode="beyond", max_objects=MAX_OBJECTS_LIMIT)
    assert len(h) <= MAX_OBJECTS_LIMIT


def test_a_huge_k_stays_bounded():
    from pair2scene.hierarchy.synthesis import HierarchyConfig

    for k in (1e300, 1.7e308):
        h = build_hierarchy("bedroom", mode="beyond", max_objects=60,
                            config=HierarchyConfig(k=k))  # fmt: skip
        assert len(h) <= 60


def test_a_second_run_into_the_same_folder_is_refused(tmp_path):
    import fcntl

    from pair2scene.generate import generate_scenes

    out = tmp_path / "out"
    out.mkdir()
    fd = os.open(out, os.O_RDONLY)
    try:
        fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)  # as a running generate holds it
        with pytest.raises(UserError, match="another pair2scene generate is writing there"):
            generate_scenes(out, room="bedroom", max_objects=3, model="random", progress=False)
    finally:
        os.close(fd)
    assert list(out.iterdir()) == []


def test_an_output_folder_that_cannot_be_made_is_one_line(tmp_path):
    from pair2scene.generate import generate_scenes

    (tmp_path / "file").write_text("not a folder")
    with pytest.raises(UserError, match="cannot create the folder") as err:
        generate_scenes(tmp_path / "file" / "out", room="bedroom", max_objects=3,
                        model="random", progress=False)  # fmt: skip
    assert "\n" not in str(err.value)

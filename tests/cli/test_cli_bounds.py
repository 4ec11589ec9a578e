"""Every option is checked at the command line's boundary (issue 21): a bad value is one
``error:`` line and exit code 2, before any work (no model loads, no scene is drawn,
nothing is written), and an error of the operating system that still comes later is one
line naming the path."""

from __future__ import annotations

import os
import time
from pathlib import Path

import pytest

from clitools import run_cli
from pair2scene.cli import MAX_ERROR_CHARS, main
from pair2scene.cli.checks import (
    MAX_NUM,
    MAX_THREADS,
    MAX_WORKERS,
    SEED_LIMIT,
    writable_file,
    writable_folder,
)
from pair2scene.errors import UserError
from pair2scene.hierarchy.synthesis import MAX_OBJECTS_LIMIT

HUGE = str(2**70)  # 1180591620717411303424

WORK = [
    "pair2scene.generate.generate_scenes",
    "pair2scene.generate.set_threads",
    "pair2scene.generate.Pair2Scene.from_pretrained",
    "pair2scene.hierarchy.build.build_hierarchy",
    "pair2scene.evaluate.evaluate",
    "pair2scene.assets.sheet.asset_sheet",
    "pair2scene.curation.pipeline.curate",
    "pair2scene.curation.dataset.load_pairs",
    "pair2scene.model.pretrain.pretrain",
    "pair2scene.model.train.train",
]
"""What a command calls to do its work (load a model, draw, write): none of it may run."""


@pytest.fixture
def no_work(monkeypatch):
    def refuse(*args, **kwargs):
        raise AssertionError("work started before the options were checked")

    for target in WORK:
        monkeypatch.setattr(target, refuse)


def refused(argv: list[str], capsys) -> str:
    """Run the command in this process; it must fail at once with one error line."""
    start = time.monotonic()
    code = main(argv)
    seconds = time.monotonic() - start
    out, err = capsys.readouterr()
    assert code == 2, (argv, err)
    assert "Traceback" not in err and out == ""
    lines = err.splitlines()
    assert len(lines) == 1 and lines[0].startswith("error: "), err
    assert seconds < 2, seconds
    return lines[0]


def only(folder: Path, *names: str) -> None:
    """Nothing but ``names`` in ``folder``: no output folder, no temporary file."""
    assert sorted(p.name for p in folder.iterdir()) == sorted(names)


def generate(out: Path, *args: str) -> list[str]:
    return ["generate", "--room", "bedroom", "--out", str(out), *args]


def test_seed_range_on_every_command(tmp_path, capsys, no_work):
    out = tmp_path / "o"
    commands = [
        ["hierarchy", "--room", "bedroom"],
        generate(out),
        ["curate", "--source", "ai2thor", "--out", str(out)],
        ["evaluate", "--scenes", str(tmp_path), "--out", str(out / "r.json")],
        ["score", "--data", str(tmp_path)],
        ["pretrain", "--out", str(out)],
        ["train", "--data", str(tmp_path), "--out", str(out)],
        ["assets", "sheet", "--out", str(out / "s.png")],
    ]
    for argv in commands:
        for seed in ("-1", HUGE, str(SEED_LIMIT)):
            line = refused([*argv, "--seed", seed], capsys)
            assert "--seed must be in 0 .. 2**32 - 1" in line, line
    # the last scene's seed counts too
    line = refused(generate(out, "--seed", str(SEED_LIMIT - 1), "--num", "2"), capsys)
    assert "below 2**32" in line
    only(tmp_path)


def test_largest_seed_works_downstream(capsys):
    assert main(["hierarchy", "--room", "bedroom", "--seed", str(SEED_LIMIT - 1)]) == 0
    assert f"seed {SEED_LIMIT - 1}" in capsys.readouterr().out


def test_num_range(tmp_path, capsys, no_work):
    for num in ("0", "-5", str(MAX_NUM + 1), HUGE):
        line = refused(generate(tmp_path / "o", "--num", num), capsys)
        assert f"--num must be in 1 .. {MAX_NUM}" in line
    only(tmp_path)


def test_max_objects_range(tmp_path, capsys, no_work):
    for argv in (["hierarchy", "--room", "bedroom"], generate(tmp_path / "o")):
        for n in ("0", "-1", str(MAX_OBJECTS_LIMIT + 1), HUGE):
            line = refused([*argv, "--mode", "beyond", "--max-objects", n], capsys)
            assert f"--max-objects must be in 1 .. {MAX_OBJECTS_LIMIT}" in line
    only(tmp_path)


def test_threads_and_workers_range(tmp_path, capsys, no_work):
    for argv in (
        generate(tmp_path / "o"),
        ["evaluate", "--scenes", str(tmp_path), "--out", str(tmp_path / "r.json")],
    ):
        for n in ("-1", "0", str(MAX_THREADS + 1), "1000", HUGE):
            line = refused([*argv, "--threads", n], capsys)
            assert f"--threads must be in 1 .. {MAX_THREADS}" in line
    for n in ("0", str(MAX_WORKERS + 1), "100000"):
        line = refused(["curate", "--source", "ai2thor", "--out", str(tmp_path / "c"),
                        "--workers", n], capsys)  # fmt: skip
        assert f"--workers must be in 1 .. {MAX_WORKERS}" in line
    only(tmp_path)


def test_other_counts_and_choices(tmp_path, capsys, no_work):
    out = tmp_path / "o"
    cases = [
        (["pretrain", "--out", str(out), "--steps", "-1"], "--steps must be in 1 .."),
        (["pretrain", "--out", str(out), "--batch-size", HUGE], "--batch-size must be in 1 .."),
        (["train", "--data", str(tmp_path), "--out", str(out), "--epochs", "0"], "--epochs"),
        (["train", "--data", str(tmp_path), "--out", str(out), "--max-steps", HUGE], "--max-steps"),
        (["assets", "sheet", "--out", str(out / "s.png"), "--columns", HUGE], "--columns"),
        (generate(out, "--mode", "sideways"), "unknown mode 'sideways' (--mode)"),
        (generate(out, "--llm", "sometimes"), "unknown llm 'sometimes' (--llm)"),
        (["hierarchy", "--room", "bedroom", "--mode", ""], "unknown mode ''"),
        (generate(out, "--keep", str(tmp_path / "missing.json")), "no such file"),
        (generate(out, "--stats", str(tmp_path / "missing.json")), "no such file"),
        (generate(out, "--assembly.candidates", HUGE), "--assembly.candidates"),
        # Values that made work without bound (a candidate pushed back and forth 10**9
        # times, a floor grid of 60 GiB) or passed collisions off as contact.
        (generate(out, "--assembly.push-attempts", "1000000000"),
         "--assembly.push-attempts must be in 0 .. 20"),
        (generate(out, "--assembly.dense-push-attempts", "21"),
         "--assembly.dense-push-attempts must be in 0 .. 20 or none"),
        (generate(out, "--assembly.navigation.resolution-m", "1e-9"),
         "--assembly.navigation.resolution-m must be in 0.01 .. 0.5"),
        (generate(out, "--assembly.navigation.agent-radius-m", "1e9"),
         "--assembly.navigation.agent-radius-m must be at most 2.0"),
        (generate(out, "--assembly.tolerances.touch", "0.5"),
         "--assembly.tolerances.touch must be in 0 .. 0.005"),
        (generate(out, "--assembly.tolerances.touch", "-1"),
         "--assembly.tolerances.touch must be in 0 .. 0.005"),
        (generate(out, "--assembly.tolerances.box-margin", "-1"),
         "--assembly.tolerances.box-margin must be in 0 .. 0.005"),
        (generate(out, "--assembly.tolerances.thin-fraction", "2"),
         "--assembly.tolerances.thin-fraction must be in 0 .. 1.0"),
    ]  # fmt: skip
    for argv, expected in cases:
        assert expected in refused(argv, capsys), argv
    only(tmp_path)


def out_commands(tmp_path: Path) -> dict[str, list[str]]:
    """Commands whose ``--out`` is a folder, without the value of --out."""
    return {
        "generate": ["generate", "--room", "bedroom", "--num", "1"],
        "curate": ["curate", "--source", "ai2thor"],
        "pretrain": ["pretrain"],
        "train": ["train", "--data", str(tmp_path)],
    }


def file_commands(tmp_path: Path) -> dict[str, list[str]]:
    """Commands whose ``--out`` is a file."""
    return {
        "evaluate": ["evaluate", "--scenes", str(tmp_path)],
        "assets sheet": ["assets", "sheet"],
    }


def test_out_under_a_file_or_empty(tmp_path, capsys, no_work):
    blocker = tmp_path / "blocker"
    blocker.write_text("x")
    for argv in [*out_commands(tmp_path).values(), *file_commands(tmp_path).values()]:
        line = refused([*argv, "--out", str(blocker / "sub" / "x.png")], capsys)
        assert f"{blocker} is a file, not a folder" in line, line
        line = refused([*argv, "--out", ""], capsys)
        assert "--out: the path is empty" in line, line
    for argv in out_commands(tmp_path).values():  # an existing file as an output folder
        assert "exists and is not a folder" in refused([*argv, "--out", str(blocker)], capsys)
    only(tmp_path, "blocker")


def test_out_in_proc_is_refused(tmp_path, capsys, no_work):
    for argv in [*out_commands(tmp_path).values(), *file_commands(tmp_path).values()]:
        line = refused([*argv, "--out", "/proc/pair2scene/out"], capsys)
        assert "/proc" in line and "not a place for files" in line, line


def test_out_in_a_read_only_folder(tmp_path, capsys, no_work):
    locked = tmp_path / "locked"
    locked.mkdir()
    locked.chmod(0o555)
    try:
        if os.access(locked, os.W_OK):
            pytest.skip("running as root: a 0o555 folder is writable (see the /proc test)")
        for argv in [*out_commands(tmp_path).values(), *file_commands(tmp_path).values()]:
            line = refused([*argv, "--out", str(locked / "out" / "r.json")], capsys)
            assert f"{locked} is not writable" in line, line
        assert list(locked.iterdir()) == []
    finally:
        locked.chmod(0o755)


def test_file_outputs_refuse_a_folder(tmp_path, capsys, no_work):
    for argv in file_commands(tmp_path).values():
        line = refused([*argv, "--out", str(tmp_path)], capsys)
        assert "is a folder; give a file name in it" in line
        assert "not a regular file" in refused([*argv, "--out", os.devnull], capsys)
    line = refused(["score", "--data", str(tmp_path), "--model", "gaussian",
                    "--save-baseline", str(tmp_path)], capsys)  # fmt: skip
    assert "--save-baseline" in line and "is a folder" in line
    only(tmp_path)


def test_checks_create_nothing(tmp_path):
    assert writable_folder(tmp_path / "a" / "b", "--out") == tmp_path / "a" / "b"
    assert writable_folder(tmp_path, "--out") == tmp_path
    assert writable_file(tmp_path / "c" / "r.json", "--out") == tmp_path / "c" / "r.json"
    (tmp_path / "r.json").write_text("{}")
    assert writable_file(tmp_path / "r.json", "--out") == tmp_path / "r.json"  # replaced
    only(tmp_path, "r.json")
    (tmp_path / "dangling").symlink_to(tmp_path / "nowhere")
    with pytest.raises(UserError, match="broken link"):
        writable_folder(tmp_path / "dangling" / "x", "--out")
    with pytest.raises(UserError, match="too long"):
        writable_folder(tmp_path / ("x" * 300), "--out")


def test_os_errors_later_are_one_line_naming_the_path(monkeypatch, capsys):
    def disk_full(*args, **kwargs):
        raise OSError(28, "No space left on device", "/data/out/bedroom_0000/scene.glb")

    monkeypatch.setattr("pair2scene.generate.generate_scenes", disk_full)
    monkeypatch.setattr("pair2scene.generate.set_threads", lambda threads: None)
    line = refused(["generate", "--room", "bedroom", "--out", "/tmp/p2s-never-made"], capsys)
    assert line == "error: /data/out/bedroom_0000/scene.glb: No space left on device"

    def rename_refused(*args, **kwargs):  # an atomic write's rename: the target is named
        raise PermissionError(13, "Permission denied", "/d/.r.json.x.tmp", None, "/d/r.json")

    monkeypatch.setattr("pair2scene.generate.generate_scenes", rename_refused)
    line = refused(["generate", "--room", "bedroom", "--out", "/tmp/p2s-never-made"], capsys)
    assert line == "error: /d/r.json: Permission denied"

    def interrupted(*args, **kwargs):
        raise KeyboardInterrupt

    monkeypatch.setattr("pair2scene.generate.generate_scenes", interrupted)
    assert main(["generate", "--room", "bedroom", "--out", "/tmp/p2s-never-made"]) == 130
    assert capsys.readouterr().err == "interrupted\n"
    assert not Path("/tmp/p2s-never-made").exists()


def test_long_and_multiline_messages_are_cut_to_one_line(capsys):
    name = "x" * 10_000_000
    line = refused(["assets", "list", "--categories", name], capsys)
    assert len(line) < MAX_ERROR_CHARS + 100
    assert line.endswith(" more characters)")
    line = refused(["assets", "list", "--categories", "bad\nname\r\x1b[31mred"], capsys)
    assert "bad name" in line and "\x1b" not in line
    line = refused(["--bogus" + "y" * 5000], capsys)  # a usage error keeps its hint
    assert "more characters" in line and line.endswith("--help')")


def test_a_real_run_fails_fast(tmp_path):
    blocker = tmp_path / "blocker"
    blocker.write_text("x")
    start = time.monotonic()
    proc = run_cli("generate", "--room", "bedroom", "--seed", "-1", "--out", str(tmp_path / "o"),
                   cwd=tmp_path)  # fmt: skip
    assert proc.returncode == 2 and "Traceback" not in proc.stderr
    assert proc.stderr.splitlines() == [
        "error: --seed must be in 0 .. 2**32 - 1 (4294967295), got -1"
    ]
    proc = run_cli("generate", "--room", "bedroom", "--out", str(blocker / "o"), cwd=tmp_path)
    assert proc.returncode == 2 and len(proc.stderr.splitlines()) == 1
    assert "is a file, not a folder" in proc.stderr
    # two interpreter starts, no model load (which alone takes longer)
    assert time.monotonic() - start < 20
    only(tmp_path, "blocker")

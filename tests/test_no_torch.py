"""Generation runs without torch (issue 22): the layout model's numpy twins draw the
scenes, so a process never pays torch's import, and a machine without torch generates the
same bytes. What needs torch (training, scoring, FID / SCA) says so in one line."""

from __future__ import annotations

import subprocess
import sys

from clitools import ROOT

BLOCK = "import sys; sys.modules['torch'] = None; from pair2scene.cli import main; "


def _without_torch(*args: str) -> subprocess.CompletedProcess:
    """The command line in a process where ``import torch`` fails as if not installed."""
    code = BLOCK + f"sys.exit(main({list(args)!r}))"
    return subprocess.run(
        [sys.executable, "-c", code], cwd=ROOT, capture_output=True, text=True, timeout=300
    )


def test_generating_without_torch_gives_the_same_scene(tmp_path):
    from pair2scene.generate import Pair2Scene
    from pair2scene.io.scene_json import dumps_scene

    out = tmp_path / "out"
    done = _without_torch("generate", "--room", "bedroom", "--seed", "4", "--out", str(out))
    assert done.returncode == 0, done.stderr
    written = (out / "bedroom_0004" / "scene.json").read_text(encoding="utf-8")
    here = Pair2Scene.from_pretrained().generate(room="bedroom", seed=4).scene
    assert written == dumps_scene(here)


def test_generate_does_not_import_torch():
    code = (
        "import sys; from pair2scene.generate import Pair2Scene; "
        "Pair2Scene.from_pretrained().generate(room='kitchen', seed=1); "
        "print('torch' in sys.modules)"
    )
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=300)
    assert done.returncode == 0, done.stderr
    assert done.stdout.strip() == "False"


def test_what_needs_torch_says_so_in_one_line(tmp_path):
    done = _without_torch("train", "--data", str(tmp_path), "--out", str(tmp_path / "model"))
    assert done.returncode == 2
    line = done.stderr.strip()
    assert "\n" not in line and "torch" in line and "pip install torch==2.13.0" in line

"""The README's "Use the scene in a simulator" commands and MuJoCo example run as written."""

from __future__ import annotations

import re
import subprocess
import sys
from pathlib import Path

import pytest
from tests.clitools import ROOT, run_cli

SECTION = "## Use the scene in a simulator"


def _blocks(kind: str) -> list[str]:
    text = (ROOT / "README.md").read_text()
    part = text[text.index(SECTION) :]
    part = part[: part.index("\n## ", 1)]
    return re.findall(rf"```{kind}\n(.*?)```", part, re.S)


@pytest.mark.slow  # (CI runs the slow tests too: .ci/run)
def test_the_mujoco_example_loads_and_steps_a_generated_room(tmp_path: Path):
    (example,) = [b for b in _blocks("python") if "import mujoco" in b]
    assert len(example.strip().splitlines()) <= 11  # "a ten-line MuJoCo example"
    command = _blocks("bash")[0].splitlines()[0].split()
    assert command[:2] == ["pair2scene", "generate"]
    done = run_cli(*command[1:], cwd=tmp_path)
    assert done.returncode == 0, done.stderr
    ran = subprocess.run([sys.executable, "-c", example], cwd=tmp_path, capture_output=True,
                         text=True, timeout=300)  # fmt: skip
    assert ran.returncode == 0, ran.stderr
    bodies, motion = re.fullmatch(
        r"(\d+) bodies, largest motion ([\d.]+) cm\n", ran.stdout
    ).groups()
    assert int(bodies) >= 10 and float(motion) < 2.0

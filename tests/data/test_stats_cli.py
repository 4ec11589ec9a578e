"""`pair2scene data stats` as a user runs it (subprocess, JSON on stdout)."""

import json
from pathlib import Path

import pytest

from clitools import run_cli

ROOT = Path(__file__).resolve().parents[2]


def stats(*args: str) -> dict:
    proc = run_cli("data", "stats", *args, "--json")
    assert proc.returncode == 0, proc.stderr
    return json.loads(proc.stdout)


@pytest.mark.usefixtures("ai2thor_databases")
def test_ai2thor_reports_195_rooms():
    s = stats("ai2thor")
    # 8293 source objects; counter slabs cut into runs, free-standing ranges made from
    # their burners and fixture parts with no fixture dropped (pair2scene.data.fixtures)
    assert s["rooms"] == 195 and s["objects"] == 8278
    assert s["room_types"] == {
        "apartment": 75,
        "bathroom": 30,
        "bedroom": 30,
        "kitchen": 30,
        "living_room": 30,
    }
    assert s["support_edges"] > 4000
    assert sum(s["categories"].values()) == s["objects"]
    assert s["labels"] == {"mapped": 118, "unknown": 0, "unknown_objects": 0}
    val = stats("ai2thor", "--split", "val")
    assert val["rooms"] == 35 and val["split"] == "val"


@pytest.mark.shared_data
@pytest.mark.usefixtures("ai2thor_databases")
def test_procthor_train_reports_500_rooms(procthor_1k):
    s = stats(f"procthor:{procthor_1k / 'train.jsonl.gz'}")
    assert s["rooms"] == 500
    assert set(s["room_types"]) == {"bedroom", "kitchen", "living_room"}
    assert s["support_edges"] > 2000


@pytest.mark.parametrize(
    "args, needle",
    [
        (("nope",), "unknown source 'nope'"),
        (("procthor",), "needs a path"),
        (("procthor:/does/not/exist.jsonl.gz",), "no such file"),
        (("ai2thor", "--split", "test"), "unknown split 'test'"),
    ],
)
def test_bad_sources_give_one_line_and_exit_2(args, needle):
    proc = run_cli("data", "stats", *args)
    assert proc.returncode == 2
    lines = proc.stderr.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("error:") and needle in lines[0]
    assert "Traceback" not in proc.stderr

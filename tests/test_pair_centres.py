"""benchmarks/pair_centres.py: the model's centre of each dependent on a support, and the data's."""

from __future__ import annotations

import sys
from pathlib import Path

import pytest

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "benchmarks"))
sys.path.insert(0, str(Path(__file__).resolve().parent))

import pair_centres  # noqa: E402

from synthetic_pairs import write_synthetic_pairs  # noqa: E402


@pytest.fixture(scope="module")
def pairs(tmp_path_factory):
    return write_synthetic_pairs(tmp_path_factory.mktemp("pairs"))


def run(monkeypatch, capsys, *args: str) -> tuple[int, str]:
    monkeypatch.setattr(sys, "argv", ["pair_centres.py", *args])
    code = pair_centres.main()
    return code, capsys.readouterr().out


def test_one_row_per_dependent_with_the_data_median(pairs, monkeypatch, capsys):
    code, out = run(monkeypatch, capsys, "--data", str(pairs), "--support", "desk",
                    "--dependent", "mug", "--dependent", "chair")  # fmt: skip
    assert code == 0
    rows = [line for line in out.splitlines() if line.startswith("| mug |")]
    assert len(rows) == 1
    cells = [c.strip() for c in rows[0].strip("|").split("|")]
    assert int(cells[1]) == 18  # 24 rooms, every 4th one val, a mug on the desk in each
    # the mugs lie within 0.1 m of the desk's centre: a small fraction of its half size
    assert abs(float(cells[2])) < 0.3 and abs(float(cells[3])) < 0.3
    assert "head input: norm" in out


def test_no_tuple_of_the_pair_is_one_line_and_exit_2(pairs, monkeypatch, capsys):
    code, out = run(monkeypatch, capsys, "--data", str(pairs), "--support", "bed")
    assert code == 2
    assert out.strip() == "no train tuples of pillow, book, laptop on a bed"

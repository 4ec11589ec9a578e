"""Exact tests of generated against real rates: known answers, scipy's, report rows."""

from __future__ import annotations

import random

import pytest

from pair2scene.metrics.significance import (
    add_tests,
    compare,
    fisher_exact,
    p_label,
    poisson_rates_exact,
    rows_of,
    stat_label,
    wilson_interval,
)


def test_fisher_known_answers():
    # Fisher's tea-tasting table [[3, 1], [1, 3]]: p = 34/70.
    assert fisher_exact(3, 4, 1, 4) == pytest.approx(34 / 70, rel=1e-12)
    # Identical shares, and one side all hits against none: both ends of the scale.
    assert fisher_exact(5, 10, 5, 10) == pytest.approx(1.0)
    assert fisher_exact(10, 10, 0, 10) == pytest.approx(2 / 184756, rel=1e-9)
    # 4 of 4 against 4 of 5 (TV stands against a wall): these rooms cannot tell them.
    assert fisher_exact(4, 4, 4, 5) == pytest.approx(1.0)
    # [[1, 8], [7, 2]]: the tables as or less likely sum to 0.01522.
    assert fisher_exact(1, 9, 7, 9) == pytest.approx(0.015220, abs=1e-6)


def test_poisson_known_answers():
    # Equal rooms: k_a | total ~ Binomial(total, 1/2); 0 of 4 has p = 2 / 16.
    assert poisson_rates_exact(0, 10, 4, 10) == pytest.approx(2 / 16)
    assert poisson_rates_exact(3, 10, 3, 10) == pytest.approx(1.0)
    assert poisson_rates_exact(0, 5, 0, 7) == 1.0
    assert poisson_rates_exact(3, 0, 1, 4) is None


def test_wilson_known_answers():
    lo, hi = wilson_interval(0, 10)
    assert lo == 0.0 and hi == pytest.approx(0.27753, abs=1e-5)
    lo, hi = wilson_interval(4, 5)
    assert (lo, hi) == (pytest.approx(0.37553, abs=1e-5), pytest.approx(0.96378, abs=1e-5))
    lo, hi = wilson_interval(10, 10)
    assert hi == pytest.approx(1.0) and lo == pytest.approx(1 - 0.27753, abs=1e-5)
    assert wilson_interval(0, 0) is None


def test_against_scipy():
    stats = pytest.importorskip("scipy.stats")
    rng = random.Random(0)
    for _ in range(300):
        na, nb = rng.randint(1, 50), rng.randint(1, 50)
        ka, kb = rng.randint(0, na), rng.randint(0, nb)
        want = stats.fisher_exact([[ka, na - ka], [kb, nb - kb]]).pvalue
        assert fisher_exact(ka, na, kb, nb) == pytest.approx(want, abs=1e-12)
        ka, kb = rng.randint(0, 120), rng.randint(0, 120)
        if ka + kb:
            want = stats.binomtest(ka, ka + kb, na / (na + nb)).pvalue
            assert poisson_rates_exact(ka, na, kb, nb) == pytest.approx(want, abs=1e-12)


def test_bad_counts_are_refused():
    with pytest.raises(ValueError, match="not a count"):
        fisher_exact(5, 4, 1, 4)
    with pytest.raises(ValueError, match="not a count"):
        poisson_rates_exact(-1, 4, 1, 4)
    assert fisher_exact(0, 0, 1, 4) is None


def _stat(k, n):
    return {"rate": k / n if n else None, "count": [k, n], "rooms": n}


def test_report_rows_get_tests_nested_groups_included():
    section = {
        "against_wall/sofa": {"generated": _stat(24, 32), "reference": _stat(22, 36)},
        "wall_objects_per_room": {"generated": _stat(0, 30), "reference": _stat(91, 38)},
        "reachable_free_floor": {"generated": {"rate": 0.99, "count": None, "rooms": 30},
                                 "reference": {"rate": 0.98, "count": None, "rooms": 38}},
        "against_wall_other": {"armchair": {"generated": _stat(1, 9),
                                            "reference": _stat(7, 9)}},
        "pooled": {"generated rooms": {"rooms": 30}},  # not a row: left alone
    }  # fmt: skip
    add_tests(section, per_room={"wall_objects_per_room"})
    sofa = section["against_wall/sofa"]
    assert sofa["test"] == "fisher" and sofa["p_value"] == pytest.approx(0.3005, abs=1e-4)
    assert sofa["generated_ci"][0] < 0.75 < sofa["generated_ci"][1]
    walls = section["wall_objects_per_room"]
    assert walls["test"] == "poisson" and walls["p_value"] < 1e-20
    assert walls["generated_ci"] is None
    assert section["reachable_free_floor"]["p_value"] is None  # a mean: no counts
    assert section["against_wall_other"]["armchair"]["p_value"] == pytest.approx(0.01522, abs=1e-5)
    assert section["pooled"] == {"generated rooms": {"rooms": 30}}


def test_nothing_measured_has_no_p():
    row = compare(_stat(0, 0), _stat(3, 4))
    assert row["p_value"] is None and row["generated_ci"] is None
    assert row["reference_ci"] is not None


@pytest.mark.parametrize(
    ("p", "label"), [(None, "-"), (0.0004, "p < 0.001"), (0.0042, "p 0.004"), (0.3005, "p 0.30")]
)
def test_labels(p, label):
    assert p_label(p) == label


@pytest.mark.parametrize(
    ("stat", "label"),
    [
        (None, "-"),
        ({"rate": None, "count": [0, 0], "rooms": 0}, "-"),
        ({"rate": 0.75, "count": [24, 32], "rooms": 30}, "0.75 (24/32)"),
        ({"rate": 4 / 553, "count": [4, 553], "rooms": 30}, "0.007 (4/553)"),
        ({"rate": 0.0, "count": [0, 553], "rooms": 30}, "0.00 (0/553)"),
        ({"rate": 0.9987, "count": None, "rooms": 30}, "0.999 (30 rooms)"),
    ],
)
def test_stat_labels(stat, label):
    assert stat_label(stat) == label


def test_rows_of_walks_nested_groups_and_skips_named_ones():
    row = {"generated": _stat(1, 2), "reference": _stat(1, 2)}
    section = {"a": row, "group": {"b": row, "deeper": {"c": row}}, "skipped": {"d": row},
               "pooled": {"generated rooms": {"rooms": 3}}, "note": 1.0}  # fmt: skip
    assert [p for p, _ in rows_of(section, skip={"skipped"})] == [
        "a", "group/b", "group/deeper/c"
    ]  # fmt: skip

"""Is a generated room's rate told from the real rooms' by more than sampling noise?

The realism measures (:mod:`pair2scene.metrics.layout`, the navigation and wall rows of
``pair2scene evaluate``) are counts: 24 of 32 sofas against a wall, 4 of 4 TV stands, 78
wall objects in 30 rooms. With 30 generated and about 38 real rooms a type, many cells
rest on a handful of objects (4 of 4 generated TV stands against 4 of 5 real ones), so a
gap between two rates says little unless its size is set against its noise. Every row
of the report gets:

- ``p_value``: the two-sided exact test of "both sides draw from one rate":
  - **shares** (k of n objects; ``test: "fisher"``): Fisher's exact test on the 2 x 2
    table [[k_gen, n_gen - k_gen], [k_ref, n_ref - k_ref]], the p-value summing every
    table of the same margins no more likely than the one seen;
  - **per-room counts** (k objects in n rooms; ``test: "poisson"``): the conditional test
    of two Poisson rates: given k_gen + k_ref, k_gen is binomial with p = n_gen /
    (n_gen + n_ref) under the null, tested two-sided the same way;
- ``generated_ci`` / ``reference_ci``: 95 % Wilson score intervals of each share (None
  for per-room counts).

Small p (below 0.05, say) means the rates differ by more than these rooms' noise; a
large p does not mean they are equal, only that these rooms cannot tell. Each counted
object is taken as independent of the others (objects of one room are not quite: a
room whose one wall is free puts all its furniture against it), so the p-values are a
little small where rooms hold several of the objects counted. Means without counts (the
reachable share of the free floor) get no test.
"""

from __future__ import annotations

import math
from collections.abc import Collection, Iterator, Sequence

Z_95 = 1.959963984540054
"""The standard normal's 97.5 % quantile: a two-sided 95 % interval."""
RELATIVE_TIE = 1e-7
"""Outcomes whose probability is within this factor of the observed one's count as
equally likely (the ``minlike`` rule with float noise allowed for, as exact tests do)."""
TESTS = ("fisher", "poisson")


def wilson_interval(k: int, n: int, z: float = Z_95) -> tuple[float, float] | None:
    """The Wilson score interval of a share k / n (95 % by default); None for n = 0."""
    if n <= 0:
        return None
    p = k / n
    denom = 1 + z * z / n
    centre = (p + z * z / (2 * n)) / denom
    half = z / denom * math.sqrt(p * (1 - p) / n + z * z / (4 * n * n))
    return max(0.0, centre - half), min(1.0, centre + half)


def _log_choose(n: int, k: int) -> float:
    return math.lgamma(n + 1) - math.lgamma(k + 1) - math.lgamma(n - k + 1)


def _two_sided(log_pmf: Sequence[float], observed: int) -> float:
    """The two-sided p-value of ``observed`` under a discrete law given by its log
    probabilities over 0..len-1: the mass of every outcome no more likely than it."""
    top = max(log_pmf)
    mass = [math.exp(v - top) for v in log_pmf]
    limit = mass[observed] * (1 + RELATIVE_TIE)
    return min(1.0, sum(m for m in mass if m <= limit) / sum(mass))


def fisher_exact(k_a: int, n_a: int, k_b: int, n_b: int) -> float | None:
    """Two-sided Fisher exact p-value of k_a of n_a against k_b of n_b; None when a side
    has nothing counted."""
    _check(k_a, n_a, share=True)
    _check(k_b, n_b, share=True)
    if n_a == 0 or n_b == 0:
        return None
    hits, total = k_a + k_b, n_a + n_b
    lo, hi = max(0, hits - n_b), min(hits, n_a)
    log_pmf = [_log_choose(n_a, x) + _log_choose(n_b, hits - x) - _log_choose(total, hits)
               for x in range(lo, hi + 1)]  # fmt: skip
    return _two_sided(log_pmf, k_a - lo)


def poisson_rates_exact(k_a: int, n_a: int, k_b: int, n_b: int) -> float | None:
    """Two-sided exact p-value of k_a events in n_a rooms against k_b in n_b (two
    Poisson rates, tested conditionally on k_a + k_b); None when a side has no rooms."""
    _check(k_a, n_a, share=False)
    _check(k_b, n_b, share=False)
    if n_a == 0 or n_b == 0:
        return None
    total = k_a + k_b
    if total == 0:
        return 1.0
    p = n_a / (n_a + n_b)
    log_p, log_q = math.log(p), math.log1p(-p)
    log_pmf = [_log_choose(total, x) + x * log_p + (total - x) * log_q
               for x in range(total + 1)]  # fmt: skip
    return _two_sided(log_pmf, k_a)


def _check(k: int, n: int, share: bool) -> None:
    if k < 0 or n < 0 or (share and k > n):
        raise ValueError(f"not a count: {k} of {n}")


def compare(generated: dict | None, reference: dict | None, per_room: bool = False) -> dict:
    """``{"p_value", "test", "generated_ci", "reference_ci"}`` of two stats
    (``{"rate", "count": [k, n], ...}`` as :func:`pair2scene.metrics.layout.stat` makes
    them); the p-value None when either side has no counts or nothing measured."""
    test = "poisson" if per_room else "fisher"
    out: dict = {"p_value": None, "test": test, "generated_ci": None, "reference_ci": None}
    counts = [None if s is None else s.get("count") for s in (generated, reference)]
    if any(c is None for c in counts):
        return out
    (k_a, n_a), (k_b, n_b) = ((int(k), int(n)) for k, n in counts)  # type: ignore[union-attr]
    if per_room:
        out["p_value"] = poisson_rates_exact(k_a, n_a, k_b, n_b)
        return out
    out["p_value"] = fisher_exact(k_a, n_a, k_b, n_b)
    for key, (k, n) in (("generated_ci", (k_a, n_a)), ("reference_ci", (k_b, n_b))):
        ci = wilson_interval(k, n)
        out[key] = None if ci is None else [round(ci[0], 4), round(ci[1], 4)]
    return out


def rows_of(
    section: dict, skip: Collection[str] = (), prefix: str = ""
) -> Iterator[tuple[str, dict]]:
    """(path, row) of every row (a dict holding ``generated`` and ``reference`` stats) of a
    report section, rows of nested groups included (path ``group/name``), in order;
    groups named in ``skip`` are left out."""
    for name, row in section.items():
        if not isinstance(row, dict):
            continue
        if {"generated", "reference"} <= row.keys():
            yield prefix + name, row
        elif name not in skip:
            yield from rows_of(row, skip, f"{prefix}{name}/")


def add_tests(section: dict, per_room: Collection[str] = ()) -> dict:
    """Add :func:`compare`'s entries to every row of a report section (:func:`rows_of`),
    in place; rows named in ``per_room`` are per-room counts. Returns ``section``."""
    for path, row in rows_of(section):
        row.update(compare(row["generated"], row["reference"], path in per_room))
    return section


def stat_label(stat: dict | None) -> str:
    """``0.85 (17/20)`` (``0.007 (4/553)`` below 0.1): a stat's rate and its counts;
    ``0.999 (30 rooms)`` for a mean; ``-`` when not measurable."""
    if not stat or stat.get("rate") is None:
        return "-"
    rate = stat["rate"]
    if stat.get("count") is None:  # a mean, not a count
        return f"{rate:.3f} ({stat.get('rooms', 0)} rooms)"
    k, n = stat["count"]
    return f"{rate:.2f} ({k}/{n})" if rate == 0 or rate >= 0.095 else f"{rate:.3f} ({k}/{n})"


def p_label(p: float | None) -> str:
    """``p 0.33``, ``p < 0.001`` or ``-``: a p-value as the tables print it."""
    if p is None:
        return "-"
    return "p < 0.001" if p < 0.001 else f"p {p:.3f}" if p < 0.01 else f"p {p:.2f}"


__all__ = [
    "TESTS",
    "add_tests",
    "compare",
    "fisher_exact",
    "p_label",
    "poisson_rates_exact",
    "rows_of",
    "stat_label",
    "wilson_interval",
]

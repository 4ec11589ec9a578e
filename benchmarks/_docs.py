"""Shared by the benchmark scripts: the machine line, one section of docs/benchmarks.md and
the median timer."""

from __future__ import annotations

import os
import platform
import re
import statistics
import time
from collections.abc import Callable
from pathlib import Path


def median_seconds(fn: Callable[[], object], runs: int) -> float:
    """Median wall time of ``runs`` calls of ``fn`` after one warm-up call."""
    fn()
    times = []
    for _ in range(runs):
        t0 = time.perf_counter()
        fn()
        times.append(time.perf_counter() - t0)
    return statistics.median(times)


NOTES_MARK = "<!-- notes: kept when a benchmark script rewrites this section -->"
"""In a section, the line after which hand-written notes survive :func:`replace_section`."""


def replace_section(doc: Path, heading: str, text: str) -> None:
    """Replace the ``heading`` section of ``doc`` (up to the next ``## ``) with ``text``,
    or append it; other sections are kept, and so are the section's notes after
    :data:`NOTES_MARK`. Written atomically."""
    from pair2scene.io.atomic import atomic_write_text

    old = doc.read_text(encoding="utf-8") if doc.exists() else "# Benchmarks\n"
    pattern = re.compile(rf"^{re.escape(heading)}\s*$.*?(?=^## |\Z)", re.MULTILINE | re.DOTALL)
    found = pattern.search(old)
    if found:
        notes = found.group(0).partition(NOTES_MARK)[2].strip("\n")
        if notes:
            text = f"{text.rstrip()}\n\n{NOTES_MARK}\n{notes}"
        new = pattern.sub(lambda _: text.rstrip("\n") + "\n\n", old, count=1)
    else:
        new = old.rstrip("\n") + "\n\n" + text
    atomic_write_text(doc, new.rstrip("\n") + "\n")


def machine() -> str:
    """One line naming the machine: CPUs available to this process, CPU model, Python."""
    cpus = len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else os.cpu_count()
    model = platform.processor() or "unknown CPU"
    try:
        text = Path("/proc/cpuinfo").read_text(encoding="utf-8", errors="replace")
        found = re.search(r"^model name\s*:\s*(.+)$", text, re.MULTILINE)
        model = found.group(1).strip() if found else model
    except OSError:
        pass
    return f"{cpus} CPUs (nproc), {model}, Python {platform.python_version()}"

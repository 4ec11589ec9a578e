"""Shared by the benchmark scripts: write one section of docs/benchmarks.md."""

from __future__ import annotations

import re
from pathlib import Path


def replace_section(doc: Path, heading: str, text: str) -> None:
    """Replace the ``heading`` section of ``doc`` (up to the next ``## ``) with ``text``,
    or append it; other sections are kept. Written atomically."""
    from pair2scene.io.atomic import atomic_write_text

    old = doc.read_text(encoding="utf-8") if doc.exists() else "# Benchmarks\n"
    pattern = re.compile(rf"^{re.escape(heading)}\s*$.*?(?=^## |\Z)", re.MULTILINE | re.DOTALL)
    if pattern.search(old):
        new = pattern.sub(lambda _: text + "\n", old, count=1)
    else:
        new = old.rstrip("\n") + "\n\n" + text
    atomic_write_text(doc, new.rstrip("\n") + "\n")

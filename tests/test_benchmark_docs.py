"""benchmarks/_docs.py: a benchmark rewrites its own section and keeps the notes under it."""

from __future__ import annotations

import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "benchmarks"))

from _docs import NOTES_MARK, replace_section  # noqa: E402


def test_a_section_is_replaced_and_its_notes_kept(tmp_path):
    doc = tmp_path / "benchmarks.md"
    notes = f"{NOTES_MARK}\nwhy it is so\n\n## C\n\nc\n"
    doc.write_text(f"# B\n\n## A\n\nold table\n\n{notes}")
    replace_section(doc, "## A", "## A\n\nnew table\n")
    assert doc.read_text() == f"# B\n\n## A\n\nnew table\n\n{notes}"
    replace_section(doc, "## C", "## C\n\nnew c\n")  # the last section: no notes
    replace_section(doc, "## D", "## D\n\nd\n")  # a new one is appended
    assert doc.read_text().endswith("## C\n\nnew c\n\n## D\n\nd\n")
    assert doc.read_text().count("why it is so") == 1

"""The bundled tables: one folder, one loader checking format and version."""

from __future__ import annotations

import json

import pytest

from pair2scene.errors import UserError
from pair2scene.resources import TABLES, load_table, table_path


@pytest.mark.parametrize("name", sorted(TABLES))
def test_every_bundled_table_loads(name):
    assert table_path(name).is_file()
    doc = load_table(name)
    if TABLES[name].format is None:
        assert isinstance(doc, list) and doc
    else:
        assert doc["format"] == TABLES[name].format
        assert doc["version"] == TABLES[name].version


@pytest.mark.parametrize(
    "text, words",
    [
        ("{", "not valid JSON"),
        ('{"format": "other", "version": 1}', "format is not 'pair2scene.rooms'"),
        ('{"format": "pair2scene.rooms", "version": 9}', "version 9 not supported"),
    ],
)
def test_bad_user_files_are_one_line_user_errors(tmp_path, text, words):
    path = tmp_path / "rooms.json"
    path.write_text(text)
    with pytest.raises(UserError) as info:
        load_table("rooms", path)
    assert words in str(info.value) and str(path) in str(info.value)
    assert "\n" not in str(info.value)


def test_missing_file_and_unknown_table():
    with pytest.raises(UserError, match="cannot read"):
        load_table("sizes", "/nonexistent/sizes.json")
    with pytest.raises(ValueError, match="no bundled table"):
        table_path("nope")


def test_user_file_of_the_same_kind_loads(tmp_path):
    path = tmp_path / "stats.json"
    path.write_text(table_path("hierarchy_stats").read_text())
    assert load_table("hierarchy_stats", path) == json.loads(path.read_text())

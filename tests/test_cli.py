"""Command-line usage errors: one ``error:`` line on stderr, exit code 2, no traceback."""

from __future__ import annotations

import pytest

from clitools import run_cli
from pair2scene.cli import main

USAGE_ERRORS = {
    "missing-argument": (["validate"], "Missing argument"),
    "unknown-option": (["validate", "--bogus", "x.json"], "No such option: --bogus"),
    "unknown-command": (["frobnicate"], "No such command 'frobnicate'"),
    "unknown-subcommand": (["data", "frobnicate"], "No such command 'frobnicate'"),
    "unknown-global-option": (["--bogus"], "No such option: --bogus"),
    "missing-source": (["data", "fetch"], "Missing argument"),
}


@pytest.mark.parametrize("argv, expected", USAGE_ERRORS.values(), ids=USAGE_ERRORS.keys())
def test_usage_errors_in_process(argv, expected, capsys):
    assert main(argv) == 2
    out, err = capsys.readouterr()
    assert out == ""
    lines = err.splitlines()
    assert len(lines) == 1, err
    assert lines[0].startswith("error: ")
    assert expected in lines[0]
    assert "--help" in lines[0]  # points at the help of the command that failed


@pytest.mark.parametrize("name", ["missing-argument", "unknown-option", "unknown-command"], ids=str)
def test_usage_errors_in_subprocess(name, tmp_path):
    argv, expected = USAGE_ERRORS[name]
    proc = run_cli(*argv, cwd=tmp_path)
    assert proc.returncode == 2, proc.stderr
    assert "Traceback" not in proc.stderr
    lines = proc.stderr.splitlines()
    assert len(lines) == 1, proc.stderr
    assert lines[0].startswith("error:")
    assert expected in lines[0]
    assert proc.stdout == ""


def test_help_exits_0(tmp_path):
    proc = run_cli("--help", cwd=tmp_path)
    assert proc.returncode == 0, proc.stderr
    assert proc.stderr == ""
    assert "validate" in proc.stdout and "data" in proc.stdout


@pytest.mark.parametrize("argv", [["--help"], ["validate", "--help"], ["data", "--help"]], ids=str)
def test_help_in_process(argv, capsys):
    assert main(argv) == 0
    out, err = capsys.readouterr()
    assert "Usage" in out
    assert err == ""


def test_bare_command_shows_help_and_exits_2(capsys):
    assert main([]) == 2
    out, err = capsys.readouterr()
    assert "Usage" in out and "validate" in out
    assert "Traceback" not in err


def test_reflowed_joins_a_paragraphs_lines_and_keeps_paragraphs():
    from pair2scene.cli import reflowed

    doc = """First line,
        second line.

        Next paragraph,
        its end.
        """
    assert reflowed(doc) == "First line, second line.\n\nNext paragraph, its end."
    assert reflowed(None) is None


def _commands(group, prefix=()):
    for command in group.registered_commands:
        yield (*prefix, command.name), command
    for sub in group.registered_groups:
        yield from _commands(sub.typer_instance, (*prefix, sub.name))


def test_every_command_help_wraps_whole_paragraphs(capsys, monkeypatch):
    """A command's help is its docstring with each paragraph on one line, so that the
    terminal, not the source's line breaks, wraps it: at a width of 200 columns the second
    paragraph of ``generate --help`` is one line (typer joins a first paragraph's lines
    itself, not a later one's)."""
    from pair2scene.cli import app

    names = []
    for path, command in _commands(app):
        names.append(path)
        assert command.help, path
        for paragraph in command.help.split("\n\n"):
            assert "\n" not in paragraph, path
    assert ("generate",) in names and ("assets", "tokens") in names
    monkeypatch.setenv("COLUMNS", "200")
    assert main(["generate", "--help"]) == 0
    out = capsys.readouterr().out
    assert "is an option below, named by its place in the config" in out

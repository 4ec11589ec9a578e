"""Typed configs -> command-line options: names, docstrings as help, parsing, defaults."""

from __future__ import annotations

import json
from dataclasses import dataclass

import pytest
from typer.testing import CliRunner

from clitools import run_cli
from pair2scene.assembly.place import AssemblyConfig
from pair2scene.cli import app, main
from pair2scene.cli.options import apply_options, config_options, field_docs
from pair2scene.errors import UserError
from pair2scene.generate import GenerateConfig
from pair2scene.hierarchy.synthesis import HierarchyConfig


@dataclass(frozen=True)
class _Inner:
    depth: float = 0.5
    """How deep.

    More text that help leaves out."""


@dataclass(frozen=True)
class _Outer:
    count: int = 3
    """How many."""
    limit: float | None = None
    flag: bool = True
    """Whether."""
    inner: _Inner = _Inner()


def test_field_docs_are_the_strings_under_the_fields():
    assert field_docs(_Outer) == {"count": "How many.", "flag": "Whether."}
    assert field_docs(_Inner)["depth"].startswith("How deep.\n\nMore text")


def _docs_by_getsource(cls) -> dict[str, str]:
    """What ``field_docs`` gave before its fast path: the class by ``inspect.getsource``."""
    import ast
    import inspect
    import textwrap

    body = ast.parse(textwrap.dedent(inspect.getsource(cls))).body[0].body
    return {
        node.target.id: inspect.cleandoc(after.value.value)
        for node, after in zip(body, body[1:])
        if isinstance(node, ast.AnnAssign) and isinstance(node.target, ast.Name)
        and isinstance(after, ast.Expr) and isinstance(after.value, ast.Constant)
        and isinstance(after.value.value, str)
    }  # fmt: skip


def test_field_docs_read_each_config_class_as_getsource_does():
    """The class found by its ``class`` line gives the docs ``inspect.getsource`` gives:
    every config class of the command line, and the fallbacks (a class made in a
    function, a name defined twice in a module)."""
    import dataclasses
    import typing

    seen, todo = [], [GenerateConfig, HierarchyConfig, _Outer]
    while todo:
        cls = todo.pop()
        seen.append(cls)
        hints = typing.get_type_hints(cls)
        todo += [hints[f.name] for f in dataclasses.fields(cls)
                 if dataclasses.is_dataclass(hints[f.name])]  # fmt: skip
    assert {c.__name__ for c in seen} >= {"AssemblyConfig", "NavigationConfig", "Tolerances"}
    for cls in seen:
        assert field_docs(cls) == _docs_by_getsource(cls), cls

    @dataclass(frozen=True)
    class _Local:
        size: int = 1
        """Local."""

    assert field_docs(_Local) == {"size": "Local."}
    assert field_docs(_Twice) == _docs_by_getsource(_Twice) != {}


def test_options_are_the_leaf_fields_by_path():
    opts = {o.flag: o for o in config_options(_Outer)}
    assert list(opts) == ["--count", "--limit", "--flag", "--inner.depth"]
    assert opts["--inner.depth"].path == ("inner", "depth") and opts["--inner.depth"].default == 0.5
    assert opts["--limit"].optional and opts["--limit"].parse("none") is None
    assert opts["--count"].parse("7") == 7
    with pytest.raises(UserError, match="--count: expected an integer, got 'x'"):
        opts["--count"].parse("x")
    with pytest.raises(UserError, match="finite"):
        opts["--inner.depth"].parse("nan")


def test_apply_options_rebuilds_nested_configs():
    out = apply_options(_Outer(), {("inner", "depth"): 2.0, ("count",): 1})
    assert out == _Outer(count=1, inner=_Inner(depth=2.0))


def test_every_generation_setting_is_an_option_with_a_docstring():
    opts = config_options(GenerateConfig)
    flags = {o.flag for o in opts}
    assert {"--assembly.max-load", "--assembly.temperature", "--hierarchy.k",
            "--hierarchy.beyond-load", "--assembly.tolerances.touch"} <= flags  # fmt: skip
    assert [o.flag for o in opts if not o.help] == []
    # the defaults are the dataclasses' own: one default per setting
    by_path = {o.path: o.default for o in opts}
    assert by_path[("assembly", "max_load")] == AssemblyConfig().max_load
    assert by_path[("hierarchy", "beyond_load")] == HierarchyConfig().beyond_load


def test_out_of_range_settings_are_one_line_errors():
    with pytest.raises(UserError, match="--assembly.max-load must be a share"):
        AssemblyConfig(max_load=2.0)
    with pytest.raises(UserError, match="--assembly.candidates must be > 0"):
        AssemblyConfig(candidates=0)
    with pytest.raises(UserError, match="at most"):
        AssemblyConfig(candidates=10_000, batches=1_000)
    with pytest.raises(UserError, match="--hierarchy.k"):
        HierarchyConfig(k=0.0)


def test_generate_help_lists_the_settings_with_their_docstrings():
    result = CliRunner().invoke(app, ["generate", "--help"], env={"COLUMNS": "200"})
    assert result.exit_code == 0
    assert "--assembly.max-load" in result.output and "--hierarchy.k" in result.output
    assert "Sampling temperature of floor and wall-mounted objects" in result.output
    assert "--assembly.support-temperature" in result.output
    assert "Sampling temperature of objects resting on another" in result.output
    assert "(default: 0.4)" in result.output


def test_a_setting_reaches_placement_and_the_summary(tmp_path, capsys):
    """--assembly.max-load 0.5 lets the supports of bedroom seed 52 carry more: fewer objects
    move off them (none against 2), and the scene differs from the default's."""

    def generate(out, *settings):
        code = main(["generate", "--room", "bedroom", "--seed", "52", "--out", str(out), "--json",
                     "--threads", "1", *settings])  # fmt: skip
        captured = capsys.readouterr()
        return code, captured

    code, base = generate(tmp_path / "a")
    assert code == 0, base.err
    code, more = generate(tmp_path / "b", "--assembly.max-load", "0.5")
    assert code == 0, more.err
    a, b = json.loads(base.out), json.loads(more.out)
    assert "settings" not in a["request"]
    assert b["request"]["settings"] == {"assembly.max_load": 0.5}
    assert len(b["scenes"][0]["moved"]) < len(a["scenes"][0]["moved"])
    scene = "bedroom_0052/scene.json"
    assert (tmp_path / "a" / scene).read_bytes() != (tmp_path / "b" / scene).read_bytes()
    # a rerun with other settings is another request: refused in one line, exit 2
    code, again = generate(tmp_path / "b", "--assembly.max-load", "0.3")
    assert code == 2 and again.err.strip().startswith("error:") and "another request" in again.err


@pytest.mark.parametrize(
    ("args", "message"),
    [
        (["--assembly.max-load", "2"], "--assembly.max-load must be a share in (0, 1]"),
        (["--assembly.temperature", "abc"], "--assembly.temperature: expected a number"),
        (["--model", "random", "--assembly.temperature", "0.5"], "draws uniformly"),
    ],
)
def test_bad_settings_exit_2_with_one_line(tmp_path, args, message):
    proc = run_cli("generate", "--room", "bedroom", "--out", str(tmp_path / "x"), *args)
    assert proc.returncode == 2, proc.stderr
    assert len(proc.stderr.strip().splitlines()) == 1 and message in proc.stderr
    assert not (tmp_path / "x").exists()


def test_hierarchy_takes_the_hierarchy_settings_by_the_same_names(capsys):
    """A lower beyond load counts on each piece for fewer objects: more furniture."""

    def floor_pieces(*settings):
        assert main(["hierarchy", "--room", "bedroom", "--mode", "beyond", "--json",
                     *settings]) == 0  # fmt: skip
        doc = json.loads(capsys.readouterr().out)
        return sum(1 for t in doc["sequence"] if t["support"]["id"] == "floor")

    assert floor_pieces("--hierarchy.beyond-load", "0.5") > floor_pieces()


@dataclass(frozen=True)
class _Twice:
    first: int = 1
    """The earlier one."""


@dataclass(frozen=True)  # (the same name again: field_docs finds it by inspect.getsource)
class _Twice:  # noqa: F811
    second: int = 2
    """The later one."""

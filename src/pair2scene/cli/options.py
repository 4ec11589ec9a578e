"""Typed config dataclasses -> command-line options, each field's docstring as its help.

A config tree such as :class:`~pair2scene.generate.GenerateConfig` (frozen dataclasses
nested in frozen dataclasses, a docstring under every field) becomes one option per leaf
field, named by its path: ``--assembly.temperature``, ``--assembly.tolerances.touch``,
``--hierarchy.k``. Booleans are switches (``--assembly.reject/--assembly.no-reject``).
An option not given keeps the config's default, so the defaults live in one place: the
dataclass. :func:`with_config` adds the options to a typer command and hands it the
config built from them.
"""

from __future__ import annotations

import ast
import contextlib
import dataclasses
import functools
import inspect
import linecache
import math
import re
import textwrap
import types
import typing
from collections.abc import Callable
from typing import Annotated, Any

import typer

from pair2scene.errors import UserError

PANEL = "Settings"
"""Where ``--help`` lists the config's options, apart from the command's own."""
INT_LIMIT = 2**31
"""An integer setting lies in ``-INT_LIMIT .. INT_LIMIT - 1`` (what C code takes); each
config's own checks bound it further."""


@dataclasses.dataclass(frozen=True)
class ConfigOption:
    """One leaf field of a config tree as a command-line option."""

    path: tuple[str, ...]
    """Field names from the root config down: ``("assembly", "max_load")``."""
    kind: type
    """float, int, bool or str."""
    optional: bool
    """The field may be None (written ``none`` on the command line)."""
    default: Any
    help: str

    @property
    def flag(self) -> str:
        return "--" + ".".join(p.replace("_", "-") for p in self.path)

    @property
    def param(self) -> str:
        """The Python parameter name of the option (dots are not identifiers)."""
        return "__".join(self.path)

    def parse(self, text: str) -> Any:
        """The field's value from its command-line text; one-line error when it is not
        one."""
        if self.optional and text.strip().lower() == "none":
            return None
        if self.kind is str:
            return text
        try:
            value = self.kind(text)
        except ValueError:
            noun = "an integer" if self.kind is int else "a number"
            none = " or none" if self.optional else ""
            raise UserError(f"{self.flag}: expected {noun}{none}, got {text!r}") from None
        if self.kind is float and not math.isfinite(value):
            raise UserError(f"{self.flag}: expected a finite number, got {text!r}")
        if self.kind is int and not -INT_LIMIT <= value < INT_LIMIT:
            raise UserError(f"{self.flag}: expected an integer of 32 bits, got {text!r}")
        return value


def _class_node(cls: type) -> ast.ClassDef:
    """``cls``'s class statement, parsed. Its module's lines are searched
    for the one ``class <name>`` line and read to the first line indented no deeper
    (``inspect.getsource`` parses the whole module to find a class: 20-25 ms for the
    larger config modules, paid by every command at start); anything else (no such line,
    several, a nested class, a body that does not parse so) goes to
    ``inspect.getsource``."""
    lines = linecache.getlines(inspect.getsourcefile(cls) or "")
    pattern = re.compile(rf"class\s+{re.escape(cls.__name__)}\b")
    starts = [i for i, line in enumerate(lines) if pattern.match(line)]
    if cls.__qualname__ == cls.__name__ and len(starts) == 1:
        end = starts[0] + 1
        while end < len(lines) and (
            not lines[end].strip() or lines[end].startswith((" ", "\t", "#", ")"))
        ):
            end += 1
        with contextlib.suppress(SyntaxError):
            return ast.parse("".join(lines[starts[0] : end])).body[0]
    return ast.parse(textwrap.dedent(inspect.getsource(cls))).body[0]


def field_docs(cls: type) -> dict[str, str]:
    """Field name -> the docstring written under it in the class body (as tyro reads
    attribute docstrings); fields without one are left out."""
    try:
        body = _class_node(cls).body
    except (OSError, TypeError):  # pragma: no cover - classes without source
        return {}
    docs = {}
    for node, after in zip(body, body[1:]):
        if (
            isinstance(node, ast.AnnAssign)
            and isinstance(node.target, ast.Name)
            and isinstance(after, ast.Expr)
            and isinstance(after.value, ast.Constant)
            and isinstance(after.value.value, str)
        ):
            docs[node.target.id] = inspect.cleandoc(after.value.value)
    return docs


def _leaf_type(hint: Any) -> tuple[type, bool]:
    """(base type, may be None) of a field's annotation; TypeError for what a command
    line cannot hold."""
    args = typing.get_args(hint)
    optional = False
    if typing.get_origin(hint) in (typing.Union, types.UnionType):
        rest = [a for a in args if a is not type(None)]
        optional = len(rest) < len(args)
        if len(rest) != 1:
            raise TypeError(f"unsupported config field type {hint!r}")
        hint = rest[0]
    if hint not in (float, int, bool, str):
        raise TypeError(f"unsupported config field type {hint!r}")
    return hint, optional


def config_options(cls: type, prefix: tuple[str, ...] = ()) -> list[ConfigOption]:
    """Every leaf field of the config tree ``cls`` (nested dataclasses are walked)."""
    hints = typing.get_type_hints(cls)
    docs = field_docs(cls)
    out: list[ConfigOption] = []
    for f in dataclasses.fields(cls):
        if not f.init:
            continue
        hint = hints[f.name]
        if dataclasses.is_dataclass(hint):
            out += config_options(hint, (*prefix, f.name))
            continue
        kind, optional = _leaf_type(hint)
        default = f.default if f.default is not dataclasses.MISSING else f.default_factory()
        out.append(ConfigOption((*prefix, f.name), kind, optional, default, docs.get(f.name, "")))
    return out


def apply_options(config: Any, values: dict[tuple[str, ...], Any]) -> Any:
    """``config`` with the fields at the given paths replaced (nested dataclasses are
    rebuilt, so their own checks run)."""
    by_head: dict[str, dict[tuple[str, ...], Any]] = {}
    direct: dict[str, Any] = {}
    for path, value in values.items():
        if len(path) == 1:
            direct[path[0]] = value
        else:
            by_head.setdefault(path[0], {})[path[1:]] = value
    for head, sub in by_head.items():
        direct[head] = apply_options(getattr(config, head), sub)
    return dataclasses.replace(config, **direct) if direct else config


def field_help(cls: type, name: str) -> str:
    """The docstring of one field of a config class as plain help text (roles and
    backquotes removed), for commands that list such a field as an option of their own."""
    text = re.sub(r":\w+:`~?([^`]+)`", r"\1", " ".join(field_docs(cls)[name].split()))
    return text.replace("``", "").replace("`", "")


def _help(option: ConfigOption) -> str:
    """The docstring's first sentence (the rest, with its measurements, is in the code and
    the API docs) and the default."""
    text = re.sub(r":\w+:`~?([^`]+)`", r"\1", " ".join(option.help.split()))
    text = text.replace("``", "").replace("`", "")
    first = re.split(r"(?<=[a-z0-9)\]])\. (?=[A-Z0-9(])", text, maxsplit=1)[0].rstrip(".")
    default = "none" if option.default is None else option.default
    return f"{first}. (default: {default})" if first else f"(default: {default})"


def _typer_param(option: ConfigOption) -> inspect.Parameter:
    if option.kind is bool:
        negative = option.flag.rsplit(".", 1)
        off = f"{negative[0]}.no-{negative[1]}" if len(negative) == 2 else f"--no-{option.flag[2:]}"
        annotation = Annotated[
            bool | None,
            typer.Option(f"{option.flag}/{off}", help=_help(option), rich_help_panel=PANEL,
                         show_default=False),
        ]  # fmt: skip
    else:
        metavar = {float: "FLOAT", int: "INT", str: "TEXT"}[option.kind]
        annotation = Annotated[
            str | None,
            typer.Option(option.flag, help=_help(option), metavar=metavar + ("|none" if
                         option.optional else ""), rich_help_panel=PANEL, show_default=False),
        ]  # fmt: skip
    return inspect.Parameter(
        option.param, inspect.Parameter.KEYWORD_ONLY, default=None, annotation=annotation
    )


def with_config(
    config_cls: type, name: str = "config", prefix: tuple[str, ...] = ()
) -> Callable[[Callable], Callable]:
    """Decorate a typer command taking ``name: config_cls``: the command gets one option
    per leaf field of ``config_cls`` instead, and is called with the config they give
    (the dataclass's defaults for options not given). ``prefix``: the path of
    ``config_cls`` in a larger tree, so that a part of it keeps the same names
    (``pair2scene hierarchy`` takes ``--hierarchy.k`` as ``generate`` does)."""
    options = config_options(config_cls, prefix)

    def decorate(command: Callable) -> Callable:
        sig = inspect.signature(command, eval_str=True)
        own = [p for p in sig.parameters.values() if p.name != name]

        @functools.wraps(command)
        def wrapper(**kwargs: Any) -> Any:
            given = {}
            for option in options:
                value = kwargs.pop(option.param, None)
                if value is None:
                    continue
                path = option.path[len(prefix) :]
                given[path] = value if option.kind is bool else option.parse(value)
            try:
                config = apply_options(config_cls(), given)
            except (TypeError, ValueError) as e:
                raise UserError(str(e)) from None
            return command(**kwargs, **{name: config})

        wrapper.__signature__ = sig.replace(  # type: ignore[attr-defined]
            parameters=[*own, *(_typer_param(o) for o in options)]
        )
        wrapper.__annotations__ = {}
        return wrapper

    return decorate

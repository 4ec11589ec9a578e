"""Checks of command-line values at the boundary, before any work is done.

Every command calls these first, so that a bad value ends in one ``error:`` line (a
:class:`~pair2scene.errors.UserError`, exit code 2) within a moment: before a model loads,
a scene is generated or a folder is created. Nothing here creates or changes a file.

The ranges (also in each option's ``--help``):

- seeds: ``0 <= seed < 2**32`` (:data:`SEED_LIMIT`); with ``generate --num N`` the last
  scene's seed ``seed + N - 1`` too. Every consumer takes them: numpy's ``default_rng``,
  ``torch.manual_seed`` (< 2**64, also ``train``'s ``seed * 100_003 + epoch``) and
  :func:`pair2scene.assets.identity.asset_seed` (which mixes the seed into 32 bits).
- ``--num``: 1 .. :data:`MAX_NUM` scenes.
- ``--max-objects``: 1 .. :data:`pair2scene.hierarchy.synthesis.MAX_OBJECTS_LIMIT`.
- ``--threads``: 1 .. :data:`MAX_THREADS`; ``curate --workers``: 1 .. :data:`MAX_WORKERS`.
- output folders (:func:`writable_folder`) and output files (:func:`writable_file`):
  not empty, no part of the path a file, the first existing folder on the way writable.
"""

from __future__ import annotations

import errno
import os
import stat
from collections.abc import Callable, Iterable
from pathlib import Path

import typer

from pair2scene.errors import UserError

SEED_LIMIT = 2**32
"""Seeds are integers with ``0 <= seed < SEED_LIMIT``."""
MAX_NUM = 1_000_000
"""The most scenes one ``generate`` run is asked for."""
MAX_THREADS = 256
"""The most CPU threads an option may ask for (``--threads``)."""
MAX_WORKERS = 64
"""The most worker processes ``curate --workers`` may start."""
MAX_STEPS = 1_000_000_000
"""The most optimiser steps (``pretrain --steps``, ``train --max-steps``)."""
MAX_EPOCHS = 100_000
"""The most epochs (``train --epochs``)."""
MAX_BATCH = 65_536
"""The largest batch (``pretrain --batch-size``)."""
MAX_COLUMNS = 1_000
"""The most cells per row of ``assets sheet``."""
NAME_MAX = 255
"""Longest file name, in bytes (ext4, xfs, btrfs, APFS...)."""
FILE_NAME_RESERVE = 32
"""Characters an output file's name leaves free for the files written beside it (the
temporary ``.<name>.<random>.tmp`` of an atomic write, ``<name>.cache.json``)."""


def check_range(value: int | None, flag: str, low: int, high: int) -> None:
    """``low <= value <= high`` (None: the option was not given, nothing to check)."""
    if value is None:
        return
    if not low <= value <= high:
        raise UserError(f"{flag} must be in {low} .. {high}, got {_short(value)}")


def check_seed(seed: int | None, flag: str = "--seed", count: int = 1) -> None:
    """``0 <= seed`` and ``seed + count - 1 < 2**32`` (:data:`SEED_LIMIT`): the seeds of
    ``count`` runs ``seed .. seed + count - 1`` are all in range."""
    if seed is None:
        return
    if not 0 <= seed < SEED_LIMIT:
        raise UserError(f"{flag} must be in 0 .. 2**32 - 1 ({SEED_LIMIT - 1}), got {_short(seed)}")
    if seed + count - 1 >= SEED_LIMIT:
        raise UserError(
            f"{flag} {seed} with --num {count}: the last seed {seed + count - 1} must be "
            f"below 2**32 ({SEED_LIMIT})"
        )


def check_count(value: int | None, flag: str, high: int) -> None:
    """A count: ``1 <= value <= high`` (None: not given)."""
    check_range(value, flag, 1, high)


def check_threads(threads: int | None, flag: str = "--threads") -> None:
    """``1 <= threads <= MAX_THREADS`` (None: the command's default)."""
    check_range(threads, flag, 1, MAX_THREADS)


def check_max_objects(max_objects: int | None, flag: str = "--max-objects") -> None:
    """``1 <= max_objects <= MAX_OBJECTS_LIMIT`` (None: the mode's default)."""
    from pair2scene.hierarchy.synthesis import MAX_OBJECTS_LIMIT

    check_range(max_objects, flag, 1, MAX_OBJECTS_LIMIT)


def check_choice(value: str, flag: str, choices: Iterable[str]) -> None:
    """``value`` is one of ``choices``."""
    choices = tuple(choices)
    if value not in choices:
        noun = flag.lstrip("-").replace("-", " ")
        raise UserError(
            f"unknown {noun} {_short(repr(value))} ({flag}); choose one of {', '.join(choices)}"
        )


def path_parser(flag: str) -> Callable[[str], Path]:
    """A typer ``parser=`` for a path option that refuses an empty text (which
    :class:`~pathlib.Path` would read as the current folder)."""

    def parse(text: str | Path) -> Path:
        return _nonempty(text, flag)

    return parse


def out_option(help: str, metavar: str = "DIR") -> typer.models.OptionInfo:
    """The ``--out`` option of a command: a path, never empty (:func:`path_parser`)."""
    return typer.Option("--out", parser=path_parser("--out"), metavar=metavar, help=help)


def existing_file(path: str | Path | None, flag: str) -> Path | None:
    """An input file that must exist (None: not given)."""
    if path is None:
        return None
    p = _nonempty(path, flag)
    if not p.is_file():
        what = "a folder, not a file" if p.is_dir() else "no such file"
        raise UserError(f"{flag} {p}: {what}")
    return p


def writable_folder(path: str | Path, flag: str) -> Path:
    """An output folder that exists or can be made: an existing one must be a folder and
    writable; otherwise the nearest existing folder above it must be writable and no part
    of the path a file. Nothing is created. Returns it as a :class:`~pathlib.Path`."""
    p = _nonempty(path, flag)
    found, missing = _first_existing(p, flag)
    if not missing and not stat.S_ISDIR(found.st_mode):
        raise UserError(f"{flag} {p}: exists and is not a folder")
    _check_missing_names(p, flag, missing)
    return p


def writable_file(path: str | Path, flag: str) -> Path:
    """An output file: not an existing folder (nor a device or other special file), and
    its folder writable or makeable as for :func:`writable_folder`. Nothing is created."""
    p = _nonempty(path, flag)
    if str(path).endswith(("/", os.sep)):
        raise UserError(f"{flag} {p}: a file name is needed, not a folder")
    found, missing = _first_existing(p, flag)
    if not missing:
        if stat.S_ISDIR(found.st_mode):
            raise UserError(f"{flag} {p}: is a folder; give a file name in it")
        if not stat.S_ISREG(found.st_mode):
            raise UserError(f"{flag} {p}: exists and is not a regular file")
    else:
        _check_missing_names(p, flag, missing, reserve=FILE_NAME_RESERVE)
    return p


def _nonempty(path: str | Path, flag: str) -> Path:
    text = os.fspath(path)
    if not text.strip():
        raise UserError(f"{flag}: the path is empty")
    if "\0" in text:
        raise UserError(f"{flag}: the path contains a NUL character")
    return Path(text)


def _first_existing(p: Path, flag: str) -> tuple[os.stat_result, list[str]]:
    """The status of ``p`` or of the nearest existing folder above it, and the names of the
    missing parts below that folder; a part that is a file, a broken link, or a folder that
    cannot be written is refused."""
    absolute = Path(os.path.abspath(p))
    missing: list[str] = []
    for candidate in (absolute, *absolute.parents):
        try:
            st = os.stat(candidate)
        except OSError as e:
            if e.errno not in (errno.ENOENT, errno.ENOTDIR):
                raise UserError(f"{flag} {p}: {candidate}: {e.strerror}") from None
            if os.path.islink(candidate):
                raise UserError(f"{flag} {p}: {candidate} is a broken link") from None
            missing.insert(0, candidate.name)
            continue
        if missing and not stat.S_ISDIR(st.st_mode):
            raise UserError(f"{flag} {p}: {candidate} is a file, not a folder")
        folder = candidate if stat.S_ISDIR(st.st_mode) else candidate.parent
        _check_writable(folder, p, flag)
        return st, missing
    raise UserError(f"{flag} {p}: no folder of it exists")  # pragma: no cover - '/' exists


def _check_writable(folder: Path, p: Path, flag: str) -> None:
    if _virtual(folder):
        raise UserError(f"{flag} {p}: {folder} is a virtual file system, not a place for files")
    try:
        read_only = bool(os.statvfs(folder).f_flag & os.ST_RDONLY)
    except (OSError, AttributeError):  # pragma: no cover - no statvfs
        read_only = False
    if read_only:
        raise UserError(f"{flag} {p}: {folder} is on a read-only file system")
    if not os.access(folder, os.W_OK | os.X_OK):
        raise UserError(f"{flag} {p}: {folder} is not writable")


def _virtual(folder: Path) -> bool:
    """On the file system of /proc or /sys (where root passes ``os.access`` but nothing
    can be created)."""
    try:
        dev = os.stat(folder).st_dev
    except OSError:  # pragma: no cover - checked just before
        return False
    for root in ("/proc", "/sys"):
        try:
            if os.stat(root).st_dev == dev and os.path.ismount(root):
                return True
        except OSError:
            continue
    return False


def _check_missing_names(p: Path, flag: str, missing: list[str], reserve: int = 0) -> None:
    """Each part still to be made fits the file system's name length (the last one with
    ``reserve`` characters to spare)."""
    for i, name in enumerate(missing):
        spare = reserve if i == len(missing) - 1 else 0
        if len(os.fsencode(name)) + spare > NAME_MAX:
            raise UserError(f"{flag} {p}: the name {_short(name)} is too long")


def _short(value: object, limit: int = 60) -> str:
    text = value if isinstance(value, str) else repr(value)
    if isinstance(value, int) and not isinstance(value, bool) and abs(value) >= 10**limit:
        return f"an integer of about {int(value.bit_length() * 0.30103) + 1} digits"
    return text if len(text) <= limit else f"{text[: limit - 3]}..."

"""Atomic file writes: write to a temporary file beside the target, then rename.

The temporary file is ``.<name>.<random>.tmp`` beside ``<name>`` (hidden, so no reader of
a folder takes it for a result). An exception removes it; a process killed while writing
(SIGKILL, a power cut) cannot, and :func:`remove_stale_temporaries` removes what such a
write left, by that name pattern only, when the writer next starts.
"""

from __future__ import annotations

import contextlib
import os
import re
import secrets
import shutil
import stat
from collections.abc import Callable, Iterator
from pathlib import Path
from typing import IO, TypeVar

T = TypeVar("T")


@contextlib.contextmanager
def atomic_open(path: str | os.PathLike, mode: str = "w", **kwargs) -> Iterator[IO]:
    """Open a temporary file in ``path``'s folder; on success rename it onto ``path``.

    On any exception the temporary file is removed and ``path`` is untouched.
    """
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    made: list[Path] = []  # the temporary file, listed before it exists
    flags = os.O_RDWR | os.O_CREAT | os.O_EXCL | getattr(os, "O_BINARY", 0)
    try:
        tmp, fd = _new_temporary(path.parent, f".{path.name}.", TEMP_SUFFIX, made,
                                 lambda p: os.open(p, flags, 0o600))  # fmt: skip
        os.chmod(tmp, 0o666 & ~current_umask())  # made 0600; give what open() would
        with os.fdopen(fd, mode, **kwargs) as fh:
            yield fh
            fh.flush()
            os.fsync(fh.fileno())
        os.replace(tmp, path)
    except BaseException:
        for tmp in made:
            with contextlib.suppress(FileNotFoundError):
                os.unlink(tmp)
        raise


TEMP_SUFFIX = ".tmp"
_RANDOM = "[a-z0-9_]+"
"""What a temporary name's random part is made of: 8 of :data:`_NAME_CHARS` (the letters
:mod:`tempfile` uses, which made the names of earlier versions)."""


def current_umask() -> int:
    """The process's umask (read by setting it and back)."""
    mask = os.umask(0)
    os.umask(mask)
    return mask


_umask = current_umask


def is_temporary(name: str, target: str) -> bool:
    """Whether the file name ``name`` is one :func:`atomic_open` gives a temporary file of
    ``target`` (a file name): ``.<target>.<random>.tmp``."""
    pattern = rf"\.{re.escape(target)}\.{_RANDOM}{re.escape(TEMP_SUFFIX)}"
    return re.fullmatch(pattern, name) is not None


def remove_stale_temporaries(folder: str | os.PathLike, target: str) -> list[str]:
    """Remove the temporary files an interrupted :func:`atomic_open` of ``folder/target``
    left (regular files named by :func:`is_temporary`, nothing else); returns their names.
    Call it only while no other process writes ``target`` there."""
    removed = []
    try:
        entries = list(os.scandir(folder))
    except OSError:
        return removed
    for entry in entries:
        if not is_temporary(entry.name, target):
            continue
        with contextlib.suppress(OSError):
            if stat.S_ISREG(entry.stat(follow_symlinks=False).st_mode):
                os.unlink(entry.path)
                removed.append(entry.name)
    return removed


def atomic_write_text(path: str | os.PathLike, text: str) -> None:
    with atomic_open(path, "w", encoding="utf-8") as fh:
        fh.write(text)


def atomic_write_bytes(path: str | os.PathLike, data: bytes) -> None:
    with atomic_open(path, "wb") as fh:
        fh.write(data)


OLD_HOLDER = "old."
"""The part of a temporary folder's name that marks the holder of a folder being
replaced (``.<name>.old.<random>``, the folder inside as ``x``)."""


_NAME_CHARS = "abcdefghijklmnopqrstuvwxyz0123456789_"
_NAME_TRIES = 100


def _new_temporary(
    parent: Path, prefix: str, suffix: str, made: list[Path], create: Callable[[Path], T]
) -> tuple[Path, T]:
    """(``parent/<prefix><random><suffix>``, what ``create(path)`` returned), ``create``
    making it new (a folder, a file opened exclusively; FileExistsError when the name is
    taken). The path is appended to ``made`` before it is created: an exception raised
    between its creation and the caller's next line (a SIGTERM turned into SystemExit)
    still finds it there to remove, where ``tmp = tempfile.mkdtemp()`` would lose it."""
    for _ in range(_NAME_TRIES):
        token = "".join(secrets.choice(_NAME_CHARS) for _ in range(8))
        path = parent / f"{prefix}{token}{suffix}"
        made.append(path)
        try:
            return path, create(path)
        except FileExistsError:
            made.remove(path)  # someone else's: never ours to remove
    raise FileExistsError(f"{parent}: no free temporary name {prefix}<random>{suffix}")


def _new_folder(parent: Path, prefix: str, made: list[Path]) -> Path:
    """A new empty folder ``parent/<prefix><random>`` (mode 0700), listed in ``made``
    before it exists (:func:`_new_temporary`)."""
    return _new_temporary(parent, prefix, "", made, lambda p: os.mkdir(p, 0o700))[0]


def replace_folder(folder: str | os.PathLike, fill: Callable[[Path], object]) -> Path:
    """Make ``folder`` whole or not at all: ``fill(tmp)`` writes its content into a hidden
    temporary folder beside it (``.<name>.<random>``), which is then renamed into place;
    a folder already there is moved aside first (into ``.<name>.old.<random>/x``) and
    removed after. On any exception (a SIGTERM the caller turns into one included,
    however early) the temporary folder is removed and the previous folder put back. The
    new folder gets the mode a plain mkdir gives."""
    folder = Path(folder)
    folder.parent.mkdir(parents=True, exist_ok=True)
    made: list[Path] = []  # [tmp, old], each listed before it exists
    try:
        tmp = _new_folder(folder.parent, f".{folder.name}.", made)
        fill(tmp)
        os.chmod(tmp, 0o777 & ~current_umask())  # made 0700
        if folder.exists():
            old = _new_folder(folder.parent, f".{folder.name}.{OLD_HOLDER}", made)
            folder.rename(old / "x")
        tmp.rename(folder)
    except BaseException:
        if len(made) > 1 and not folder.exists():  # interrupted between the renames
            with contextlib.suppress(OSError):
                (made[1] / "x").rename(folder)  # the previous folder goes back
        for path in made:
            shutil.rmtree(path, ignore_errors=True)
        raise
    if len(made) > 1:
        shutil.rmtree(made[1], ignore_errors=True)
    return folder


@contextlib.contextmanager
def folder_lock(folder: str | os.PathLike, busy: str, shared: bool = False) -> Iterator[None]:
    """Hold a lock on ``folder`` itself while writing into it (flock on the folder: no lock
    file, released when the process ends however it ends): exclusive, or ``shared`` with
    other shared holders. A conflicting holder is a one-line UserError, ``"<folder>:
    <busy>"``. Where locks are not supported (no fcntl, a folder that cannot be opened, a
    file system without locks), it runs unlocked."""
    from pair2scene.errors import UserError

    try:
        import fcntl
    except ImportError:  # (not POSIX)
        yield
        return
    try:
        fd = os.open(folder, os.O_RDONLY)
    except OSError:
        yield
        return
    try:
        try:
            fcntl.flock(fd, (fcntl.LOCK_SH if shared else fcntl.LOCK_EX) | fcntl.LOCK_NB)
        except BlockingIOError:
            raise UserError(f"{folder}: {busy}") from None
        except OSError:
            pass  # (a file system without locks)
        yield
    finally:
        os.close(fd)

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
import shutil
import stat
import tempfile
from collections.abc import Callable, Iterator
from pathlib import Path
from typing import IO


@contextlib.contextmanager
def atomic_open(path: str | os.PathLike, mode: str = "w", **kwargs) -> Iterator[IO]:
    """Open a temporary file in ``path``'s folder; on success rename it onto ``path``.

    On any exception the temporary file is removed and ``path`` is untouched.
    """
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    fd, tmp = tempfile.mkstemp(dir=path.parent, prefix=f".{path.name}.", suffix=TEMP_SUFFIX)
    try:
        os.chmod(tmp, 0o666 & ~current_umask())  # mkstemp makes 0600; give what open() would
        with os.fdopen(fd, mode, **kwargs) as fh:
            yield fh
            fh.flush()
            os.fsync(fh.fileno())
        os.replace(tmp, path)
    except BaseException:
        with contextlib.suppress(FileNotFoundError):
            os.unlink(tmp)
        raise


TEMP_SUFFIX = ".tmp"
_RANDOM = "[a-z0-9_]+"
"""What :mod:`tempfile` puts in its names (8 of these characters)."""


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


def replace_folder(folder: str | os.PathLike, fill: Callable[[Path], object]) -> Path:
    """Make ``folder`` whole or not at all: ``fill(tmp)`` writes its content into a hidden
    temporary folder beside it (``.<name>.<random>``), which is then renamed into place;
    a folder already there is moved aside first (into ``.<name>.old.<random>/x``) and
    removed after. On any exception the temporary folder is removed and the previous
    folder put back. The new folder gets the mode a plain mkdir gives."""
    folder = Path(folder)
    folder.parent.mkdir(parents=True, exist_ok=True)
    tmp = Path(tempfile.mkdtemp(dir=folder.parent, prefix=f".{folder.name}."))
    old: Path | None = None
    try:
        fill(tmp)
        os.chmod(tmp, 0o777 & ~current_umask())  # mkdtemp makes 0700
        if folder.exists():
            old = Path(tempfile.mkdtemp(dir=folder.parent, prefix=f".{folder.name}.{OLD_HOLDER}"))
            folder.rename(old / "x")
        tmp.rename(folder)
    except BaseException:
        if old is not None and not folder.exists():  # interrupted between the renames
            with contextlib.suppress(OSError):
                (old / "x").rename(folder)  # the previous folder goes back
        shutil.rmtree(tmp, ignore_errors=True)
        if old is not None:
            shutil.rmtree(old, ignore_errors=True)
        raise
    if old is not None:
        shutil.rmtree(old, ignore_errors=True)
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

"""Atomic file output: write to a temporary file beside the target, then rename."""

from __future__ import annotations

__all__ = ["atomic_write", "check_writable", "check_distinct"]

import contextlib
import os
import tempfile
from collections.abc import Iterator
from pathlib import Path

from shapegen.errors import InputFormatError


def _umask() -> int:
    mask = os.umask(0)
    os.umask(mask)
    return mask


_CREATE_MODE = 0o666 & ~_umask()  # what open() would give a new file


@contextlib.contextmanager
def atomic_write(path: str | os.PathLike, mode: str = "w") -> Iterator:
    """Open a temporary file for writing; on success it replaces ``path``, on failure it vanishes.

    A failed run never leaves a half-written output file.
    """
    target = Path(path)
    directory = target.parent if str(target.parent) else Path(".")
    if not directory.is_dir():
        raise InputFormatError(f"{target}: directory {directory} does not exist")
    fd, tmp = tempfile.mkstemp(prefix=f".{target.name}.", suffix=".tmp", dir=directory)
    try:
        encoding = None if "b" in mode else "utf-8"
        with os.fdopen(fd, mode, encoding=encoding) as handle:
            yield handle
        os.chmod(tmp, _CREATE_MODE)  # mkstemp makes owner-only files; outputs are ordinary files
        os.replace(tmp, target)
    except BaseException:
        with contextlib.suppress(FileNotFoundError):
            os.unlink(tmp)
        raise


def check_writable(path: str | os.PathLike) -> Path:
    """``path`` as a Path, after checking, before any work, that a file can be written there:
    its folder exists and is writable, and it is not itself a folder."""
    target = Path(path)
    directory = target.parent if str(target.parent) else Path(".")
    if not directory.is_dir():
        raise InputFormatError(f"{target}: folder {directory} does not exist")
    if target.is_dir():
        raise InputFormatError(f"{target}: is a folder; name a file to write")
    if not os.access(directory, os.W_OK | os.X_OK):
        raise InputFormatError(f"{target}: folder {directory} is not writable")
    if target.exists() and not os.access(target, os.W_OK):
        raise InputFormatError(f"{target}: the file is not writable")
    return target


def check_distinct(**paths: str | os.PathLike | None) -> None:
    """Refuse two outputs naming the same file (one would silently replace the other).

    ``paths`` maps what each output is (``model``, ``report``...) to its path or None.
    """
    seen: dict[Path, str] = {}
    for role, path in paths.items():
        if path is None:
            continue
        resolved = Path(path).resolve()
        if resolved in seen:
            raise InputFormatError(
                f"{path}: the {role} and the {seen[resolved]} would be the same file; name two"
                " different files"
            )
        seen[resolved] = role

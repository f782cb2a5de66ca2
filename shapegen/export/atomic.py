"""Atomic file output: write to a temporary file beside the target, then rename."""

from __future__ import annotations

__all__ = ["atomic_write"]

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

"""Atomic file output: write to a temporary file beside the target, then rename.

A failed or interrupted run never leaves a half-written output nor a temporary file: each
temporary file is removed when its write fails (any exception, Ctrl-C included), and every
temporary file still open is removed by :func:`remove_temporaries`, which the handlers that
:func:`stop_on_signals` installs call on SIGINT, SIGTERM and SIGHUP before stopping the run.

A process killed outright (SIGKILL, a power cut) runs no cleanup, so its temporary file stays.
Each one is named for its writer: ``.NAME.HOST-PID.xxxxxxxx.tmp`` (``HOST`` a short hash of the
machine's name), and the first write of a later process into that folder removes those whose
writer is gone (a process of this machine that no longer runs) or that have not changed for
:data:`ABANDONED_SECONDS` (a writer on another machine, or a process number used again).
"""

from __future__ import annotations

__all__ = [
    "ABANDONED_SECONDS",
    "Interrupted",
    "abandoned_entries",
    "atomic_write",
    "check_distinct",
    "check_writable",
    "is_abandoned",
    "remove_abandoned",
    "remove_temporaries",
    "stop_on_signals",
    "writer_name",
]

import contextlib
import hashlib
import os
import re
import signal
import socket
import tempfile
import threading
import time
from collections.abc import Iterator, Mapping
from pathlib import Path

from shapegen.errors import InputFormatError

# The temporary files of the writes under way, each with the process that writes it, removed by
# remove_temporaries() on a signal (a forked child's signal must not remove its parent's files).
_TEMPORARIES: set[tuple[int, str]] = set()


def _umask() -> int:
    mask = os.umask(0)
    os.umask(mask)
    return mask


_CREATE_MODE = 0o666 & ~_umask()  # what open() would give a new file

#: A temporary file unchanged for this long (s) is abandoned whoever wrote it: no write of
#: shapegen's stalls for a day, and a process number may be used again after a restart.
ABANDONED_SECONDS = 24 * 3600.0

# .NAME.HOST-PID.xxxxxxxx.tmp: the writer's machine (a hash of its name) and process number
_TEMPORARY_NAME = re.compile(r"\.(?P<name>.+)\.(?P<host>[0-9a-f]{6})-(?P<pid>[0-9]+)\.[^.]+\.tmp")
_HOST = hashlib.blake2b(socket.gethostname().encode(), digest_size=3).hexdigest()
_SWEPT: set[tuple[int, str]] = set()  # the folders this process has swept (with its pid)
_SWEPT_LOCK = threading.Lock()


class Interrupted(KeyboardInterrupt):
    """The run was stopped by a signal (``signum``); a KeyboardInterrupt, so every cleanup that
    runs for Ctrl-C runs for SIGTERM and SIGHUP too. The exit status is ``128 + signum``."""

    def __init__(self, signum: int):
        super().__init__(signum)
        self.signum = signum

    @property
    def exit_status(self) -> int:
        return 128 + self.signum


def _folder(target: Path) -> Path:
    return target.parent if str(target.parent) else Path(".")


@contextlib.contextmanager
def atomic_write(path: str | os.PathLike, mode: str = "w") -> Iterator:
    """Open a temporary file for writing; on success it replaces ``path``, on failure it vanishes.

    A failed run never leaves a half-written output file, nor the temporary file.
    """
    target = Path(path)
    directory = _folder(target)
    if not directory.is_dir():
        raise InputFormatError(f"{target}: folder {directory} does not exist")
    _sweep_once(directory)
    with _signals_held():  # a signal between creating and registering would orphan the file
        fd, tmp = _temporary_file(target, directory)
        entry = (os.getpid(), tmp)
        _TEMPORARIES.add(entry)
    try:
        encoding = None if "b" in mode else "utf-8"
        with os.fdopen(fd, mode, encoding=encoding) as handle:
            yield handle
        os.chmod(tmp, _CREATE_MODE)  # mkstemp makes owner-only files; outputs are ordinary files
        try:
            os.replace(tmp, target)
        except OSError as exc:
            raise InputFormatError(f"{target}: cannot replace it: {exc.strerror or exc}") from None
    except BaseException:
        with contextlib.suppress(FileNotFoundError):
            os.unlink(tmp)
        raise
    finally:
        _TEMPORARIES.discard(entry)


def remove_temporaries() -> list[str]:
    """Remove the temporary files of every write this process has under way; returns their
    names."""
    removed = []
    pid = os.getpid()
    for entry in list(_TEMPORARIES):
        owner, tmp = entry
        if owner != pid:
            continue
        with contextlib.suppress(OSError):
            os.unlink(tmp)
            removed.append(tmp)
        _TEMPORARIES.discard(entry)
    return removed


_STOP_SIGNALS = tuple(
    getattr(signal, name) for name in ("SIGINT", "SIGTERM", "SIGHUP") if hasattr(signal, name)
)


def _stop(signum, frame) -> None:
    remove_temporaries()
    raise Interrupted(signum)


@contextlib.contextmanager
def stop_on_signals() -> Iterator[None]:
    """While open, SIGINT, SIGTERM and SIGHUP remove the temporary files of the writes under way
    and raise :class:`Interrupted` (a KeyboardInterrupt) in the main thread, so the run stops
    through its normal cleanup; the previous handlers are restored on leaving. Outside the main
    thread (where Python cannot set handlers) it does nothing."""
    if threading.current_thread() is not threading.main_thread():
        yield
        return
    previous = {}
    try:
        for signum in _STOP_SIGNALS:
            previous[signum] = signal.signal(signum, _stop)
        yield
    finally:
        for signum, handler in previous.items():
            signal.signal(signum, handler if handler is not None else signal.SIG_DFL)


@contextlib.contextmanager
def _signals_held() -> Iterator[None]:
    """Hold the stop signals (delivered on leaving) in the main thread, where Python runs its
    handlers; elsewhere, or without pthread_sigmask, do nothing."""
    can_hold = hasattr(signal, "pthread_sigmask") and (
        threading.current_thread() is threading.main_thread()
    )
    if not can_hold:
        yield
        return
    previous = signal.pthread_sigmask(signal.SIG_BLOCK, _STOP_SIGNALS)
    try:
        yield
    finally:
        signal.pthread_sigmask(signal.SIG_SETMASK, previous)


def check_writable(path: str | os.PathLike) -> Path:
    """``path`` as a Path, after checking, before any work, that a file can be written there:
    it is not a folder, its folder exists, and a file can be created in that folder (tried, so
    a read-only file system, ``/proc`` or a full disk is found now, whoever runs it)."""
    target = Path(path)
    directory = _folder(target)
    if target.is_dir():
        raise InputFormatError(f"{target}: is a folder; name a file to write")
    if not directory.is_dir():
        what = "is not a folder" if directory.exists() else "does not exist"
        raise InputFormatError(f"{target}: folder {directory} {what}")
    if target.exists() and not os.access(target, os.W_OK):
        raise InputFormatError(f"{target}: the file is not writable")
    with _signals_held():  # the probe is created and removed with the stop signals held
        fd, probe = _temporary_file(target, directory)
        os.close(fd)
        os.unlink(probe)
    return target


def check_distinct(
    paths: Mapping[str, str | os.PathLike | None] | None = None,
    /,
    **named: str | os.PathLike | None,
) -> None:
    """Refuse two outputs naming the same file (one would silently replace the other).

    ``paths`` (or keyword arguments) map what each output is (``"-o"``, ``"--report"``, or
    ``model``, ``report``...) to its path or None. Paths are compared resolved (``./x`` and
    ``x``, symbolic links) and, for existing files, by identity (hard links).
    """
    seen: list[tuple[str, str | os.PathLike, Path]] = []
    for role, path in {**(paths or {}), **named}.items():
        if path is None:
            continue
        resolved = Path(path).resolve()
        for other_role, other_path, other in seen:
            if other == resolved or _same_existing_file(other, resolved):
                raise InputFormatError(
                    f"{other_role} {other_path} and {role} {path} name the same file (one would"
                    " replace the other); name two different files"
                )
        seen.append((role, path, resolved))


def _same_existing_file(first: Path, second: Path) -> bool:
    try:
        return first.exists() and second.exists() and os.path.samefile(first, second)
    except OSError:
        return False


def _temporary_file(target: Path, directory: Path) -> tuple[int, str]:
    """A new hidden temporary file beside ``target`` in ``directory``, named for this process
    (its descriptor and path); a folder that cannot be written in is an InputFormatError naming
    the target."""
    prefix = f".{target.name}.{_HOST}-{os.getpid()}."
    try:
        return tempfile.mkstemp(prefix=prefix, suffix=".tmp", dir=directory)
    except OSError as exc:
        raise InputFormatError(
            f"{target}: cannot write in folder {directory}: {exc.strerror or exc}"
        ) from None


def _sweep_once(directory: Path) -> None:
    """:func:`remove_abandoned` in ``directory``, on this process's first write there."""
    key = (os.getpid(), os.path.abspath(directory))
    with _SWEPT_LOCK:
        if key in _SWEPT:
            return
        _SWEPT.add(key)
    remove_abandoned(directory)


def abandoned_entries(directory: str | os.PathLike, pattern: re.Pattern) -> list[os.DirEntry]:
    """The entries of ``directory`` whose names ``pattern`` matches (with its groups ``host``
    and ``pid``, as :func:`writer_name` writes them) and whose writer is gone
    (:func:`is_abandoned`): what a killed write or unpacking left. Another process's work
    under way is not among them."""
    now = time.time()
    try:
        entries = list(os.scandir(directory))
    except OSError:
        return []
    found = []
    for entry in entries:
        named = pattern.fullmatch(entry.name)
        if named is None:
            continue
        try:
            changed = entry.stat(follow_symlinks=False).st_mtime
        except OSError:
            continue
        if is_abandoned(named["host"], int(named["pid"]), changed, now):
            found.append(entry)
    return found


def remove_abandoned(directory: str | os.PathLike) -> list[str]:
    """Remove the temporary files in ``directory`` that a killed write left (see the module's
    docstring); returns their names. Another process's write under way is left alone."""
    removed = []
    for entry in abandoned_entries(directory, _TEMPORARY_NAME):
        with contextlib.suppress(OSError):
            os.unlink(entry.path)
            removed.append(entry.path)
    return removed


def writer_name() -> str:
    """``HOST-PID``: the part of a temporary file's or folder's name that says which process of
    which machine (a short hash of its name) writes it."""
    return f"{_HOST}-{os.getpid()}"


def is_abandoned(host: str, pid: int, changed: float, now: float | None = None) -> bool:
    """Whether a temporary file or folder that process ``pid`` of machine ``host`` (as in
    :func:`writer_name`) writes, last changed at ``changed`` (s since the epoch), is abandoned:
    its writer, of this machine, no longer runs, or it has not changed for
    :data:`ABANDONED_SECONDS`."""
    gone = host == _HOST and pid != os.getpid() and not _running(pid)
    return gone or (time.time() if now is None else now) - changed > ABANDONED_SECONDS


def _running(pid: int) -> bool:
    """Whether process ``pid`` of this machine runs (where that cannot be asked: yes)."""
    if os.name != "posix":
        return True  # os.kill(pid, 0) would end it on Windows
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except (PermissionError, OverflowError, OSError):
        return True  # another user's
    return True

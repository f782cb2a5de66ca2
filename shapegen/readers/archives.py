"""7z archives (CityEngine rule packages, ``.rpk``) unpacked as untrusted input.

:func:`unpack_7z` writes an archive's files into an empty folder, or refuses it in one line
naming the archive: a member whose name would land outside the folder (``../``, an absolute
path), a member that is neither a file nor a folder (a symbolic link, a device), more members
than ``max_archive_members``, a member deeper than ``max_archive_depth`` folders, more than
``max_file_bytes`` x :data:`UNPACKED_FACTOR` bytes once unpacked (declared, or found while
unpacking: a size in the header may lie), a damaged stream (LZMA, CRC) or a header py7zr cannot
read. py7zr decompresses; every byte it produces goes through a writer of this module
(py7zr's writer factory), which counts it and stops the unpacking as soon as the total is over
the limit, so nothing larger than the limit is ever written or held. What an archive leaves
half-unpacked is the caller's to remove (it unpacks into a staging folder).
"""

from __future__ import annotations

__all__ = ["UNPACKED_FACTOR", "package_cache", "unpack_7z", "unpacked_package", "within"]

import os
import stat
from pathlib import Path, PurePosixPath

from shapegen.errors import InputFormatError, ShapegenError
from shapegen.limits import current_limits, limit_hint

UNPACKED_FACTOR = 16
"""An unpacked archive may hold this many ``max_file_bytes``."""

_WHAT = "not a readable CityEngine rule package (a 7z archive)"


def package_cache() -> Path:
    """The folder rule packages are unpacked in, one folder each: ``$SHAPEGEN_CACHE/packages``,
    else under ``$XDG_CACHE_HOME/shapegen``, else ``~/.cache/shapegen``."""
    configured = os.environ.get("SHAPEGEN_CACHE")
    if configured:
        return Path(configured) / "packages"
    base = os.environ.get("XDG_CACHE_HOME") or str(Path.home() / ".cache")
    return Path(base) / "shapegen" / "packages"


def unpacked_package(path: str | os.PathLike) -> Path | None:
    """The unpacked rule package that holds ``path`` (resolved), or None. What a package's
    rules read (imports, assets, tables) stays inside it, as in CityEngine, where a package
    resolves its names in its own files only: a ``../../etc/passwd`` is not found."""
    try:
        cache = package_cache().resolve()
        relative = Path(path).resolve().relative_to(cache)
    except (OSError, ValueError, RuntimeError):
        return None
    return cache / relative.parts[0] if relative.parts else None


def within(path: Path, folders) -> bool:
    """Whether ``path``, resolved (links followed), lies in one of ``folders`` (resolved)."""
    try:
        resolved = path.resolve()
    except (OSError, RuntimeError):
        return False
    return any(resolved.is_relative_to(Path(folder).resolve()) for folder in folders)


def unpack_7z(archive_path: Path, folder: Path) -> None:
    """Unpack the 7z archive ``archive_path`` into the existing, empty ``folder``.

    Raises
    ------
    InputFormatError
        One line naming the archive (see the module's documentation).
    """
    import py7zr

    limits = current_limits()
    budget = _Budget(archive_path, UNPACKED_FACTOR * limits.max_file_bytes)
    try:
        status = archive_path.stat()
        if not stat.S_ISREG(status.st_mode):
            raise InputFormatError(f"{archive_path}: not a rule package (not a regular file)")
        with open(archive_path, "rb") as handle:
            # an open file, not a name: py7zr then unpacks in this thread, so that what stops
            # it (the budget, a damaged stream) is raised here
            with py7zr.SevenZipFile(handle, mode="r") as archive:
                members = list(archive.files)
                _check_members(members, archive_path, budget)
                for member in members:
                    if member.is_directory:
                        _make_folder(folder, member.filename, archive_path)
                writers = _Writers(folder, archive_path, budget)
                try:
                    archive.extractall(factory=writers)
                finally:
                    writers.close_all()
    except ShapegenError:
        raise
    except MemoryError:
        raise InputFormatError(f"{archive_path}: {_WHAT}: it needs more memory to unpack than "
                               "there is") from None  # fmt: skip
    except OSError as exc:
        if exc.errno is not None:  # the file system's refusal, not the data's
            raise InputFormatError(
                f"{archive_path}: cannot unpack it: {exc.strerror or exc}"
            ) from None
        raise InputFormatError(f"{archive_path}: {_WHAT}: {_reason(exc)}") from None
    except Exception as exc:  # noqa: BLE001 (any failure of the decoder on damaged data)
        raise InputFormatError(f"{archive_path}: {_WHAT}: {_reason(exc)}") from None


def _reason(exc: BaseException) -> str:
    """What went wrong with the archive's data, in words, on one line."""
    import lzma
    import zlib

    from py7zr.exceptions import ArchiveError, CrcError

    if isinstance(exc, CrcError):
        name = exc.args[2] if len(exc.args) > 2 else "a member"
        return f"the member {str(name)!r} is damaged (its checksum does not match)"
    kind = type(exc).__name__
    text = " ".join(str(exc).split())[:200]
    if isinstance(exc, lzma.LZMAError | zlib.error):
        return f"damaged compressed data ({text or kind})"
    if isinstance(exc, EOFError):
        return "it ends before its data does"
    if isinstance(exc, ArchiveError) and text:
        return text
    return f"{kind}: {text}" if text else kind


class _Budget:
    """Bytes unpacked so far, against the limit."""

    def __init__(self, archive_path: Path, limit: int):
        self.archive_path = archive_path
        self.limit = limit
        self.used = 0

    def spend(self, size: int) -> None:
        self.used += size
        if self.used > self.limit:
            raise InputFormatError(
                f"{self.archive_path}: it unpacks to more than {self.limit} bytes "
                f"({UNPACKED_FACTOR} x max_file_bytes) " + limit_hint("max_file_bytes")
            )


def _member_path(name: str, archive_path: Path) -> PurePosixPath:
    """The member's name as a relative path, checked: inside the folder, not too deep."""
    relative = PurePosixPath(name.replace("\\", "/"))
    parts = [part for part in relative.parts if part not in ("", ".")]
    if (
        relative.is_absolute()
        or ".." in parts
        or not parts
        or "\x00" in name
        or (len(parts[0]) == 2 and parts[0][1] == ":")  # C:
    ):
        raise InputFormatError(
            f"{archive_path}: the member {name!r} would be unpacked outside the package's folder"
        )
    depth = current_limits().max_archive_depth
    if len(parts) > depth + 1:
        raise InputFormatError(
            f"{archive_path}: the member {name[:80]!r}... lies {len(parts) - 1} folders deep, "
            f"more than {depth} " + limit_hint("max_archive_depth")
        )
    return PurePosixPath(*parts)


def _check_members(members, archive_path: Path, budget: _Budget) -> None:
    limit = current_limits().max_archive_members
    if len(members) > limit:
        raise InputFormatError(
            f"{archive_path}: it holds {len(members)} members, more than {limit} "
            + limit_hint("max_archive_members")
        )
    declared = 0
    for member in members:
        name = str(member.filename)
        _member_path(name, archive_path)
        if not (member.is_directory or member.is_file) or member.is_symlink:
            raise InputFormatError(
                f"{archive_path}: the member {name!r} is a link or a special file; a rule "
                "package holds files and folders only"
            )
        declared += int(member.uncompressed or 0)
    if declared > budget.limit:
        budget.spend(declared)  # refused before anything is unpacked


def _make_folder(folder: Path, name: str, archive_path: Path) -> Path:
    target = folder.joinpath(*_member_path(name, archive_path).parts)
    os.makedirs(target, exist_ok=True)
    return target


class _Writers:
    """py7zr's writer factory: each member's bytes go to its file under ``folder``, counted."""

    def __init__(self, folder: Path, archive_path: Path, budget: _Budget):
        self.folder = folder
        self.archive_path = archive_path
        self.budget = budget
        self.opened: list[_MemberFile] = []

    def create(self, filename: str) -> _MemberFile:
        relative = _member_path(filename, self.archive_path)
        target = self.folder.joinpath(*relative.parts)
        os.makedirs(target.parent, exist_ok=True)
        writer = _MemberFile(target, self.budget)
        self.opened.append(writer)
        return writer

    def close_all(self) -> None:
        for writer in self.opened:
            writer.close()


class _MemberFile:
    """One member's file being written (py7zr's ``Py7zIO`` interface, write side)."""

    def __init__(self, target: Path, budget: _Budget):
        self.budget = budget
        self.handle = open(target, "wb")  # noqa: SIM115 (closed by close(), or close_all)
        self.written = 0

    def write(self, data) -> int:
        self.budget.spend(len(data))
        self.written += len(data)
        return self.handle.write(data)

    def read(self, size=None) -> bytes:
        return b""

    def seek(self, offset: int, whence: int = 0) -> int:
        return self.written  # written in one pass; py7zr rewinds only to read back

    def seekable(self) -> bool:
        return False

    def flush(self) -> None:
        if not self.handle.closed:
            self.handle.flush()

    def size(self) -> int:
        return self.written

    def close(self) -> None:
        if not self.handle.closed:
            self.handle.close()

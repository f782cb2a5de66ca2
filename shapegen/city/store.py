"""Where a city run's files go: a local folder, or an object store or file system that fsspec
understands (``s3://bucket/city``, ``gs://...``, ``memory://city``; ``file://`` is a local
folder).

A :class:`CityStore` is plain, picklable data (its location), so the workers that write their own
lots' files, in this machine's processes or on a Dask cluster, each open it for themselves. Every
file is written atomically: under a temporary name beside it, then renamed, so a file that is
there is whole (a reader never sees half a batch). On an object store the rename is a copy and a
delete; the object that appears under the final name is whole either way.

``memory://`` is one process's memory: the local worker processes cannot share it, so a run into
``memory://`` derives its lots in the parent process (``workers`` is then ignored); it is meant
for tests and notebooks.
"""

from __future__ import annotations

__all__ = ["CityStore", "open_store"]

import os
import uuid
from dataclasses import dataclass
from pathlib import Path

from shapegen.errors import InputFormatError, OptionError


@dataclass(frozen=True)
class CityStore:
    """The output location of one run: ``folder`` (a local path) or ``url`` (fsspec)."""

    location: str
    url: bool = False

    @property
    def folder(self) -> Path | None:
        """The local folder, or None for a URL."""
        return None if self.url else Path(self.location)

    @property
    def shared_between_processes(self) -> bool:
        """Whether another process of this machine sees the same files (not ``memory://``)."""
        return not self.location.startswith("memory://")

    def name(self, relative: str) -> str:
        """The full path or URL of ``relative`` (for messages and readers)."""
        return f"{self.location.rstrip('/')}/{relative}"

    def path_of(self, relative: str) -> Path | str:
        """``relative`` as a Path in the local folder, or its URL."""
        return self.name(relative) if self.url else Path(self.location) / relative

    def _fs(self):
        return _filesystem(self.location)[0]

    def _path(self, relative: str) -> str:
        if not self.url:
            return str(Path(self.location) / relative)
        return f"{_filesystem(self.location)[1].rstrip('/')}/{relative}"

    def prepare(self, *folders: str) -> None:
        """Create the location and its ``folders``; check a file can be written there."""
        if not self.url:
            folder = Path(self.location)
            if folder.exists() and not folder.is_dir():
                raise InputFormatError(f"{folder}: exists and is not a folder")
            try:
                for sub in folders or ("",):
                    (folder / sub).mkdir(parents=True, exist_ok=True)
            except OSError as exc:
                raise InputFormatError(
                    f"{folder}: cannot create it ({exc.strerror or exc})"
                ) from None
            from shapegen.export.atomic import check_writable

            check_writable(folder / (folders[0] if folders else "") / ".shapegen")
            return
        fs = self._fs()
        try:
            for sub in folders or ("",):
                fs.makedirs(self._path(sub).rstrip("/"), exist_ok=True)
            probe = f".shapegen-{uuid.uuid4().hex}"
            self.write(probe, b"")
            fs.rm(self._path(probe))
        except OSError as exc:
            raise InputFormatError(f"{self.location}: cannot write there ({exc})") from None

    def write(self, relative: str, data: bytes) -> None:
        """Write ``data`` to ``relative`` atomically (temporary name, then rename)."""
        if not self.url:
            from shapegen.export.atomic import atomic_write

            with atomic_write(Path(self.location) / relative, "wb") as handle:
                handle.write(data)
            return
        fs = self._fs()
        target = self._path(relative)
        head, _, tail = target.rpartition("/")
        temporary = f"{head}/.{tail}.{uuid.uuid4().hex[:12]}.tmp"
        fs.pipe_file(temporary, data)
        try:
            fs.mv(temporary, target)
        except BaseException:
            try:
                fs.rm(temporary)
            except OSError:
                pass
            raise

    def read(self, relative: str) -> bytes | None:
        """The bytes of ``relative``, or None when it is not there."""
        try:
            if not self.url:
                return (Path(self.location) / relative).read_bytes()
            return self._fs().cat_file(self._path(relative))
        except (OSError, FileNotFoundError):
            return None

    def list(self, folder: str, suffix: str = "") -> list[str]:
        """The names (relative to the location) of the files in ``folder`` ending in ``suffix``,
        sorted; temporary files are not listed."""
        if not self.url:
            try:
                entries = os.listdir(Path(self.location) / folder)
            except OSError:
                return []
        else:
            try:
                entries = [
                    entry.rstrip("/").rpartition("/")[2]
                    for entry in self._fs().ls(self._path(folder), detail=False)
                ]
            except (OSError, FileNotFoundError):
                return []
        return sorted(
            f"{folder}/{entry}"
            for entry in entries
            if entry.endswith(suffix) and not entry.startswith(".")
        )


def open_store(location: str | os.PathLike) -> CityStore:
    """The store for ``location``: a folder path, a ``file://`` URL (a folder) or any other URL
    that fsspec understands; an unknown protocol, or fsspec missing, is one line."""
    text = os.fspath(location)
    if "://" not in text:
        return CityStore(text)
    protocol = text.split("://", 1)[0].lower()
    if protocol == "file":
        return CityStore(text.split("://", 1)[1] or "/")
    _filesystem(text)  # refuse now, before any work, what cannot be opened
    return CityStore(text.rstrip("/"), url=True)


_FILESYSTEMS: dict[str, tuple] = {}


def _filesystem(url: str):
    if url not in _FILESYSTEMS:
        try:
            import fsspec
        except ImportError:
            raise OptionError(
                f"{url}: writing to a URL needs fsspec: pip install 'shapegen[city]'"
            ) from None
        try:
            _FILESYSTEMS[url] = fsspec.core.url_to_fs(url)
        except (ValueError, ImportError) as exc:
            raise OptionError(f"{url}: cannot open it ({' '.join(str(exc).split())})") from None
    return _FILESYSTEMS[url]

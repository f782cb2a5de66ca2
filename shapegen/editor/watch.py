"""Notices when the grammar file changes on disk: a thread that polls its modification time.

Polling one file every :data:`POLL_S` seconds costs nothing measurable and works the same for
editors that write in place and those that save to a temporary file and rename it over the
original; a file that is briefly missing during such a save is simply looked at again later. A
change is read once the file has stayed the same for one more poll, so a reload starts 0.2-0.4 s
after the save.
"""

from __future__ import annotations

__all__ = ["POLL_S", "FileWatcher"]

import os
import threading
from collections.abc import Callable
from pathlib import Path

POLL_S = 0.2  # seconds between two looks at the file


class FileWatcher:
    """Calls ``on_change()`` (in its own thread) after ``path`` changes."""

    def __init__(self, path: str | os.PathLike, on_change: Callable[[], None], *, poll=POLL_S):
        self.path = Path(path)
        self._on_change = on_change
        self._poll = poll
        self._stop = threading.Event()
        self._seen = self._signature()
        self._thread = threading.Thread(target=self._run, name="grammar-watch", daemon=True)
        self._thread.start()

    def _signature(self) -> tuple | None:
        try:
            stat = self.path.stat()
        except OSError:
            return None
        return stat.st_mtime_ns, stat.st_size, stat.st_ino

    def _run(self) -> None:
        while not self._stop.wait(self._poll):
            signature = self._signature()
            if signature is None or signature == self._seen:
                continue
            # an editor may truncate the file and write it in several steps: wait until it has
            # stayed the same for one more look, so a half-written file is not read
            if self._stop.wait(self._poll) or self._signature() != signature:
                continue
            self._seen = signature
            try:
                self._on_change()
            except Exception as exc:  # keep watching whatever one reload did
                import sys

                sys.stderr.write(f"shapegen edit: reloading {self.path} failed: {exc}\n")

    def stop(self) -> None:
        self._stop.set()
        self._thread.join(timeout=2)

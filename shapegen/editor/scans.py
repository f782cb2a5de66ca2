"""The stable intervals of the design on screen: which scans run, and what they have found.

:class:`StableRanges` owns the scanning process
(:class:`~shapegen.editor.stability.StabilityScanner`), the generation of the design it scans
and the results published for that design; a result of an older design is dropped. The session
asks it for a new scan after every change and reads its results under its own state lock,
which it shares, so a design and its shading change together.
"""

from __future__ import annotations

__all__ = ["StableRanges", "rule_text", "scan_design"]

import threading
from collections.abc import Callable, Mapping

from shapegen.editor.stability import ScanJob, StabilityScanner
from shapegen.grammar.source_files import read_rule_file


class StableRanges:
    """The scans of one editing session.

    Parameters
    ----------
    lock
        The session's state lock, held while a result is taken and while a scan is asked for.
    published
        Called (under ``lock``) after a result of the current design is taken: the session
        notes a new state version.
    scan
        Run the scanning process; without it nothing is scanned and the results stay empty.
    """

    def __init__(self, lock, published: Callable[[], None], *, scan: bool = True):
        self._lock = lock
        self._published = published
        self._results: dict[str, dict] = {}
        self._generation = 0  # the results of an older generation are dropped
        self._scanner = StabilityScanner(self._publish) if scan else None

    @property
    def idle(self) -> threading.Event | None:
        """Set while no foreground work runs (the scans wait for it); None without scans."""
        return self._scanner.idle if self._scanner is not None else None

    def results(self) -> dict[str, dict]:
        """``attr -> {"status", "range", "intervals", ...}`` of the current design's scans."""
        with self._lock:
            return dict(self._results)

    def restart(self, design: Mapping | None) -> ScanJob | None:
        """Forget the last design's results and make the job that scans ``design`` (the
        keywords of :class:`~shapegen.editor.stability.ScanJob` but ``generation``), or None
        when there is nothing to scan. Call under the lock; hand the job to :meth:`request`
        after releasing it."""
        with self._lock:
            self._results = {}
            self._generation += 1
            if design is None or not design["ranges"]:
                return None
            for name, (low, high) in design["ranges"].items():
                self._results[name] = {"status": "waiting", "range": [low, high], "intervals": []}
            return ScanJob(**design, generation=self._generation)

    def request(self, job: ScanJob | None) -> None:
        """Start scanning ``job`` (a newer job abandons the scan under way)."""
        if job is not None and self._scanner is not None:
            self._scanner.request(job)

    def stop(self) -> None:
        if self._scanner is not None:
            self._scanner.stop()

    def _publish(self, generation: int, name: str, result: dict) -> None:
        with self._lock:
            if generation != self._generation:
                return
            self._results[name] = result
            self._published()


def rule_text(path) -> str | None:
    """The grammar's text the scanning process derives (None: no file, no scan), read as the
    grammar was (a cp1252 file too)."""
    return None if path is None else read_rule_file(path)[0]


def scan_design(grammar, outcome, values: Mapping, free: list[str], text: str | None, *,
                seed: int, lot, path) -> dict | None:  # fmt: skip
    """The design the scans cover (a :class:`~shapegen.editor.stability.ScanJob`'s fields but
    its generation): the design ``outcome`` built from ``grammar`` (its ``text``, read from
    ``path``) at ``values``, each of the ``free`` attrs with a ``@Range`` and a number scanned;
    None when nothing is to be scanned (no verdict, no file)."""
    assessment = outcome.assessment
    if assessment is None or not assessment.ok or text is None:
        return None
    ranges = grammar.catalogue.ranges(values)
    free_ranges = {
        name: (float(ranges[name]["min"]), float(ranges[name]["max"]))
        for name in free
        if name in ranges and isinstance(values.get(name), float)
    }
    return {
        "text": text,
        "name": grammar.name,
        "attrs": {  # arrays are not sent: the scanning process derives them as the editor did
            k: v
            for k, v in values.items()
            if k in grammar.catalogue and isinstance(v, bool | int | float | str)
        },
        "ranges": free_ranges,
        "current": {name: (values[name], bool(assessment.stands)) for name in free_ranges},
        "seed": seed,
        "lot": lot,
        "path": str(path) if path is not None else None,
    }

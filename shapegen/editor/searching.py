"""The page's search: what it was asked, how far it has come, how it ended, and its stop.

:class:`SearchState` owns the search's part of the state (the ``optimization`` object the page
shows) and the designer's request to stop; the session runs the search and tells it each step.
"""

from __future__ import annotations

__all__ = ["Cancelled", "SearchState", "search_options"]

import threading
from collections.abc import Callable
from typing import TYPE_CHECKING

from shapegen.editor.attrs import RequestError
from shapegen.errors import OptionError
from shapegen.json_values import finite_or_none
from shapegen.search.search_options import SearchOptions

if TYPE_CHECKING:
    from shapegen.statics.statics_options import Reserve


class Cancelled(Exception):
    """The designer stopped the search."""


def search_options(payload: object, free: list[str], margin: Reserve) -> SearchOptions:
    """The search a request asks for (``{"objective": "energy"}``, the default, or
    ``"closest"``) over the ``free`` attrs with ``margin``; a 4xx for a bad request."""
    payload = {} if payload is None else payload
    if not isinstance(payload, dict):
        raise RequestError('send a JSON object such as {"objective": "closest"}, or nothing')
    unknown = sorted(set(payload) - {"objective"})
    if unknown:
        raise RequestError(f"optimize takes only 'objective'; got {unknown[0]!r}")
    try:
        options = SearchOptions(free=free, margin=margin, **payload)
    except OptionError as exc:
        raise RequestError(str(exc)) from None
    if not free:
        raise RequestError(
            'no attr is free to search: mark one free (POST /api/settings {"free": [...]})', 422
        )
    return options


class SearchState:
    """The search's progress as the page shows it (``shown``: None before any search and after
    a change of the design) and the request to stop it.

    Parameters
    ----------
    lock
        The session's state lock: every change of the progress is made under it.
    bump
        Called under ``lock`` after each change: a new version of the state.
    """

    def __init__(self, lock, bump: Callable[[], None]):
        self._lock = lock
        self._bump = bump
        self._cancel = threading.Event()
        self.shown: dict | None = None
        self.running = False  # a search holds the session's work lock (read under ``lock``)

    def started(self, objective: str) -> None:
        self._cancel.clear()
        with self._lock:
            self.shown = {"running": True, "objective": objective, "iteration": 0}
            self._bump()

    def step(self, record) -> None:
        """One iteration's record; raises :class:`Cancelled` once the designer asked to stop."""
        with self._lock:
            self.shown = {
                **(self.shown or {}),
                "running": True,
                "iteration": record.iteration,
                "measure": finite_or_none(record.infeasibility),
                "stands": bool(record.feasible),
                "evaluations": record.evaluations,
                "seconds": record.seconds,
                "parameters": dict(record.parameters),
            }
            self._bump()
        if self._cancel.is_set():
            raise Cancelled

    def stopped(self) -> None:
        with self._lock:
            self.shown = {**self.shown, "running": False, "message": "stopped"}
            self._bump()

    def ended(self, objective: str, result) -> None:
        """The search's ``result`` (a :class:`~shapegen.search.result.OptimizationResult`);
        call under the lock, with the design it found."""
        self.shown = {
            "running": False,
            "objective": objective,
            "iteration": result.iterations,
            "evaluations": result.evaluations,
            "measure": finite_or_none(result.final_infeasibility),
            "stands": bool(result.feasible),
            "seconds": result.seconds,
            "message": result.message,
        }

    def cancel(self) -> dict:
        """Stop a running search after its current iteration."""
        running = self.shown is not None and self.shown.get("running")
        if running:
            self._cancel.set()
        return {"cancelled": bool(running)}

    def close(self) -> None:
        self._cancel.set()

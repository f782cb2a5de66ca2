"""Undo, redo and reset of the designer's changes.

:class:`History` is a list of :class:`~shapegen.editor.inputs.Inputs` before each change (a drag
of a slider, sent with one gesture, is one change; a search's result, a reset, a new seed or
lot, a free or fixed attr and the search's margin are changes too) and one of those undone. The
session asks it what to apply and tells it what was applied; it holds nothing else.
"""

from __future__ import annotations

__all__ = ["History", "reset_names"]

from shapegen.editor.attrs import RequestError
from shapegen.editor.inputs import Inputs


class History:
    """The undo and redo steps of one session, and the gesture the last change belonged to."""

    def __init__(self):
        self._undo: list[Inputs] = []  # the design's inputs before each change
        self._redo: list[Inputs] = []  # ... and after each undone one
        self._gesture: str | None = None

    def counts(self) -> dict:
        """``{"undo": n, "redo": n}``: the steps each way, for the page's buttons."""
        return {"undo": len(self._undo), "redo": len(self._redo)}

    def joins(self, gesture: str | None) -> bool:
        """Whether a change of ``gesture`` continues the last change (the same drag)."""
        return gesture is not None and gesture == self._gesture and bool(self._undo)

    def changed(self, before: Inputs, after: Inputs, *, record: bool, gesture: str | None) -> None:
        """A change from ``before`` to ``after`` was applied; with ``record`` (and a real
        change) ``before`` is the next undo step and the redo steps are dropped."""
        if record and after != before:
            self._undo.append(before)
            self._redo.clear()
        self._gesture = gesture

    def searched(self, before: Inputs) -> None:
        """A search's result replaced ``before``: one undo step."""
        self._undo.append(before)
        self._redo.clear()
        self._gesture = None

    def next_step(self, what: str) -> Inputs:
        """The inputs ``what`` (``"undo"`` or ``"redo"``) goes back to; a 409 when none."""
        steps = self._undo if what == "undo" else self._redo
        if not steps:
            raise RequestError(f"nothing to {what}", 409)
        return steps[-1]

    def stepped(self, what: str, left: Inputs) -> None:
        """``what`` was applied, leaving the inputs ``left``: they are a step the other way."""
        source, target = (self._undo, self._redo) if what == "undo" else (self._redo, self._undo)
        source.pop()
        target.append(left)


def reset_names(grammar, payload: object) -> list[str] | None:
    """The attrs a reset request names (``{"attrs": ["span", ...]}``), checked; None for
    every attr the designer set (``{}`` or no body)."""
    payload = {} if payload is None else payload
    if not isinstance(payload, dict) or set(payload) - {"attrs"}:
        raise RequestError('send {"attrs": ["name", ...]} to reset those, or {} for all')
    names = payload.get("attrs")
    if names is not None:
        if not isinstance(names, list) or not all(isinstance(n, str) for n in names):
            raise RequestError('"attrs" is a list of attr names, such as ["span"]')
        unknown = grammar.catalogue.first_unknown(names)
        if unknown is not None:
            raise RequestError(grammar.catalogue.no_attr(unknown))
    return names

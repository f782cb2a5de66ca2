"""Undo, redo and reset of the designer's changes.

The history is a list of :class:`~shapegen.editor.inputs.Inputs` before each change (a drag of a
slider, sent with one gesture, is one change; a search's result, a reset, a new seed or lot, a
free or fixed attr and the search's margin are changes too) and one of those undone.
:class:`HistoryMixin` is mixed into :class:`~shapegen.editor.session.EditorSession`, which
provides ``grammar``, ``attrs``, ``_undo``, ``_redo``, ``_last_inputs`` and the change
machinery (``_take_work``, ``_apply``).
"""

from __future__ import annotations

__all__ = ["HistoryMixin"]

from dataclasses import replace

from shapegen.editor.attrs import RequestError
from shapegen.editor.inputs import valid_attrs


class HistoryMixin:
    """Undo, redo and reset (``POST /api/undo``, ``/api/redo``, ``/api/reset``)."""

    def undo(self) -> dict:
        """Take the designer's values back to before the last change (a drag, a typed value, a
        reset, a search's result)."""
        return self._step_history(self._undo, self._redo, "undo")

    def redo(self) -> dict:
        """Make the last undone change again."""
        return self._step_history(self._redo, self._undo, "redo")

    def reset(self, payload: object = None) -> dict:
        """Give attrs back their rule defaults: ``{"attrs": ["span", ...]}``, or every attr the
        designer set for ``{}`` or no body. The defaults then follow the file: a changed default
        saved in it shows at the next reload."""
        payload = {} if payload is None else payload
        if not isinstance(payload, dict) or set(payload) - {"attrs"}:
            raise RequestError('send {"attrs": ["name", ...]} to reset those, or {} for all')
        names = payload.get("attrs")
        if names is not None:
            if not isinstance(names, list) or not all(isinstance(n, str) for n in names):
                raise RequestError('"attrs" is a list of attr names, such as ["span"]')
            unknown = [n for n in names if n not in self.grammar.attrs]
            if unknown:
                raise RequestError(f"the grammar has no attr {unknown[0]!r}")
        if not self._take_work():
            raise RequestError("a search is running; wait for it or POST /api/cancel", 409)
        try:
            gone = set(self.attrs) if names is None else set(names)
            kept = {k: v for k, v in self.attrs.items() if k not in gone}
            return self._apply(replace(self._inputs(), attrs=kept))
        finally:
            self._work.release()

    def _step_history(self, source: list, target: list, what: str) -> dict:
        if not self._take_work():
            raise RequestError("a search is running; wait for it or POST /api/cancel", 409)
        try:
            if not source:
                raise RequestError(f"nothing to {what}", 409)
            entry = source[-1]
            # a value of the history may predate a reload of the file
            self._apply(replace(entry, attrs=valid_attrs(self.grammar, entry.attrs)), record=False)
            with self._state_lock:
                target.append(self._last_inputs)
                source.pop()
                self.version += 1
                return self.state()
        finally:
            self._work.release()

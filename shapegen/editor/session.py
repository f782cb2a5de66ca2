"""The editor's state: a grammar file, the designer's attr values, the design built from them.

Every change goes through the one pipeline (:func:`shapegen.pipeline.design`): a slider change
builds and judges the design at the new values; "optimize" and "closest" run the search from the
current values (a warm start) and take the design it found. The grammar file is re-read when it
changes on disk; a file with errors leaves the last good design in place and the error in the
state. After every change the stable interval of each free attr is scanned in the background
(:mod:`shapegen.editor.stability`).

>>> session = EditorSession("barrel_vault.grammar", scan=False)   # doctest: +SKIP
>>> session.set_attrs({"span": 7.0})["verdict"]["stands"]          # doctest: +SKIP
"""

from __future__ import annotations

__all__ = ["EditorSession"]

import threading
import time
from collections.abc import Mapping, Sequence
from dataclasses import replace
from pathlib import Path

from shapegen import pipeline
from shapegen.editor.attrs import RequestError, checked_values
from shapegen.editor.completion import MeasureFollower
from shapegen.editor.history import HistoryMixin
from shapegen.editor.inputs import UNCHANGED, Inputs, SettingsMixin, valid_attrs
from shapegen.editor.readouts import ReadoutsMixin
from shapegen.editor.stability import ScanJob, StabilityScanner
from shapegen.engine.project.rule_packages import PACKAGE_SUFFIX
from shapegen.errors import GrammarError, OptionError, ShapegenError
from shapegen.json_values import finite_or_none, json_ready
from shapegen.search.defaults import DEFAULT_MARGIN
from shapegen.search.options import SearchOptions


class Cancelled(Exception):
    """The designer stopped the search."""


class EditorSession(HistoryMixin, SettingsMixin, ReadoutsMixin):
    """One grammar being edited: thread-safe; every public method returns the new state.

    Parameters
    ----------
    source
        A rule file, or the name of a bundled one.
    attrs
        Initial attr overrides (checked like a request's).
    seed, lot
        Derivation settings, as ``shapegen build``'s.
    rules_path
        The ``--rules-path`` folders the design is opened with, for the exported command line
        (``shapegen edit`` puts them in ``SHAPEGEN_RULES_PATH``, where every load finds them).
    scan
        Scan the stable intervals of the free attrs in the background.
    measure_follows
        Answer a change that is proven not to stand with its verdict alone, its measure and
        forces following (:mod:`shapegen.editor.completion`); else every answer is complete.
    carry_over
        Judge each change from the last design (:mod:`shapegen.statics.incremental`); False
        judges every design from scratch (the same answers, slower: for comparisons).
    """

    def __init__(
        self,
        source: str,
        *,
        attrs: Mapping[str, object] | None = None,
        seed: int = 0,
        lot: tuple[float, float] | None = None,
        rules_path: Sequence[str] = (),
        scan: bool = True,
        measure_follows: bool = False,
        carry_over: bool = True,
    ):
        self.grammar = pipeline.load(source)
        self.path: Path | None = self.grammar.path  # the rule file read (a package's unpacked)
        self.package: Path | None = _package(source)  # the .rpk opened, if one was
        self.rules_path = tuple(str(folder) for folder in rules_path)
        self.seed = seed
        self.lot = lot
        self._text = _read(self.path)
        self._work = threading.Lock()  # one change at a time
        self._state_lock = threading.RLock()
        self._searching = False  # a search holds ``_work`` (set and read under _state_lock)
        self._reload_pending = False  # the file is to be re-read when the search ends
        self._scanner: StabilityScanner | None = None
        self._idle = threading.Event()  # set while no foreground work runs: the scans wait for it
        self._idle.set()
        self._cancel = threading.Event()
        self.version = 0
        self.model_version = 0
        self._optimization: dict | None = None
        self._error: dict | None = None
        self._stability: dict[str, dict] = {}
        self._glb: tuple[int, bytes] | None = None
        self._scene: tuple[int, dict] | None = None
        self.attrs: dict[str, object] = {}  # the designer's values; the others are the rule's
        # the design's inputs before each change (undo) and after each undone one (redo)
        self._undo: list[Inputs] = []
        self._redo: list[Inputs] = []
        self._gesture: str | None = None  # the drag the last change belonged to
        self._free: list[str] | None = None  # the attrs the search varies; None: the @Free ones
        self.margin = DEFAULT_MARGIN
        self._last_inputs = self._inputs()  # the inputs before the last change
        self._scan_generation = 0  # the scans' results of an older generation are dropped
        initial = checked_values(self.grammar, {}, dict(attrs)) if attrs else {}
        self._follower = MeasureFollower(self._publish_completed) if measure_follows else None
        self._carry_over = carry_over
        self._outcome = None  # nothing to carry over into the first design
        self._outcome = self._design(initial)
        self.attrs = initial
        self._timings = self._last_timings
        if scan:
            self._scanner = StabilityScanner(self._publish_scan)
            self._idle = self._scanner.idle
        self._changed(model=True)

    # ------------------------------------------------------------------ the public operations
    def state(self) -> dict:
        """The page's state (plain JSON): attrs, verdict, timings, stability, search, error."""
        with self._state_lock:
            return json_ready(self._state())

    def set_attrs(self, payload: object, *, gesture: str | None = None) -> dict:
        """Build and judge the design with the attr values in ``payload`` (checked first).

        The changes of one ``gesture`` (a drag of a slider: the page names it) are one step of
        the history: undo takes the design back to before the drag, not to its last pixel.
        """
        if not self._take_work():
            raise RequestError("a search is running; wait for it or POST /api/cancel", 409)
        try:
            values = checked_values(
                self.grammar, self._current_values(), payload, free=self.free_attrs
            )
            same_gesture = gesture is not None and gesture == self._gesture and self._undo
            inputs = replace(self._inputs(), attrs={**self.attrs, **values})
            return self._apply(inputs, record=not same_gesture, gesture=gesture)
        finally:
            self._work.release()

    def _apply(self, inputs: Inputs, *, record: bool = True, gesture: str | None = None) -> dict:
        """Take the designer's ``inputs``: build and judge the design when they build another
        one, restart the scans when the free attrs change; with ``record``, the inputs before
        are the next undo step (and the redo steps are dropped). Holds ``_work``."""
        before = self._inputs()
        build = not inputs.builds_as(before)
        if build:
            self._idle.clear()
            try:
                outcome = self._design(inputs.attrs, seed=inputs.seed, lot=inputs.lot)
            finally:
                self._idle.set()
        with self._state_lock:
            self._last_inputs = before
            if record and inputs != before:
                self._undo.append(before)
                self._redo.clear()
            self._gesture = gesture
            self.attrs = dict(inputs.attrs)
            self.seed, self.lot = inputs.seed, inputs.lot
            self._free, self.margin = inputs.free, inputs.margin
            if build:
                self._optimization = None  # the last search's message no longer applies
                self._outcome = outcome
                self._timings = self._last_timings
                if outcome.assessment is not None and outcome.assessment.pending:
                    self._follower.request(outcome)
            if build or inputs.free != before.free:
                self._changed(model=build)
            self.version += 1
            return self.state()

    def optimize(self, payload: object = None) -> dict:
        """Search the free attrs from the current values (``{"objective": "energy"}``, the
        default, or ``"closest"``) and take the design found; progress shows in the state."""
        payload = {} if payload is None else payload
        if not isinstance(payload, dict):
            raise RequestError('send a JSON object such as {"objective": "closest"}, or nothing')
        unknown = sorted(set(payload) - {"objective"})
        if unknown:
            raise RequestError(f"optimize takes only 'objective'; got {unknown[0]!r}")
        try:
            options = SearchOptions(free=self.free_attrs, margin=self.margin, **payload)
        except OptionError as exc:
            raise RequestError(str(exc)) from None
        if not self.free_attrs:
            raise RequestError(
                'no attr is free to search: mark one free (POST /api/settings {"free": [...]})',
                422,
            )
        if not self._work.acquire(blocking=False):
            raise RequestError("the design is being changed; try again when it is done", 409)
        try:
            with self._state_lock:
                self._searching = True
            answer = self._search(options)
        finally:
            with self._state_lock:
                self._searching = False
                reload_now, self._reload_pending = self._reload_pending, False
            self._work.release()
        # the file changed during the search: the page shows it now, with the values found
        return self.reload() if reload_now else answer

    def _search(self, options: SearchOptions) -> dict:
        objective = options.objective
        self._cancel.clear()
        with self._state_lock:
            self._optimization = {"running": True, "objective": objective, "iteration": 0}
            self.version += 1
        self._idle.clear()
        try:
            outcome = self._design(
                dict(self.attrs),
                search=options,
            )
        except Cancelled:
            with self._state_lock:
                self._optimization = {
                    **self._optimization, "running": False, "message": "stopped"
                }  # fmt: skip
                self.version += 1
                return self.state()
        finally:
            self._idle.set()
        result = outcome.optimization
        with self._state_lock:
            free = set(self.free_attrs)
            self._undo.append(self._inputs())
            self._redo.clear()
            self._gesture = None
            self.attrs = {
                **self.attrs, **{k: v for k, v in result.attrs.items() if k in free}
            }  # fmt: skip
            self._outcome = outcome
            self._timings = self._last_timings
            self._optimization = {
                "running": False,
                "objective": objective,
                "iteration": result.iterations,
                "evaluations": result.evaluations,
                "measure": finite_or_none(result.final_infeasibility),
                "stands": bool(result.feasible),
                "seconds": result.seconds,
                "message": result.message,
            }
            self._changed(model=True)
            return self.state()

    def cancel(self) -> dict:
        """Stop a running search after its current iteration."""
        running = self._optimization is not None and self._optimization.get("running")
        if running:
            self._cancel.set()
        return {"cancelled": bool(running)}

    def reload(self) -> dict:
        """Re-read the grammar file (a package: the ``.rpk``); on an error keep the last good
        design.

        During a search it answers at once: the file is re-read when the search ends (the
        state's ``reload_pending`` is true until then), so a save in the middle of a long
        search neither waits for it nor stops it.
        """
        if self.path is None:
            raise RequestError("this grammar was not read from a file", 422)
        if not self._take_work(defer_reload=True):
            return self.state()
        try:
            return self._reload()
        finally:
            self._work.release()

    def _reload(self) -> dict:
        try:
            # a package is unpacked again: a new one (CityEngine exported it anew) has a
            # folder of its own in the cache
            grammar = pipeline.load(str(self.package or self.path))
            text = _read(grammar.path)
            kept = self._kept_attrs(grammar)
            self._idle.clear()
            try:
                outcome = self._design(kept, grammar=grammar)
            finally:
                self._idle.set()
        except ShapegenError as exc:
            with self._state_lock:
                self._error = _error_json(exc)
                self.version += 1
                return self.state()
        with self._state_lock:
            self.grammar = grammar
            self.path = grammar.path
            self._text = text
            self.attrs = kept
            self._outcome = outcome
            self._timings = self._last_timings
            self._error = None
            self._stability = {}
            self._changed(model=True)
            return self.state()

    def _take_work(self, *, defer_reload: bool = False) -> bool:
        """Wait for the change under way, if any, and hold ``_work``; False (at once) when a
        search holds it, after noting, with ``defer_reload``, that the file is to be re-read
        when it ends."""
        while not self._work.acquire(timeout=0.05):
            with self._state_lock:  # the search notes the reload under the same lock as it ends
                if self._searching:
                    if defer_reload and not self._reload_pending:
                        self._reload_pending = True
                        self.version += 1
                    return False
        return True

    def close(self) -> None:
        """Stop the background scan (and the measures that follow)."""
        self._cancel.set()
        if self._scanner is not None:
            self._scanner.stop()
        if self._follower is not None:
            self._follower.stop()

    # ------------------------------------------------------------------ internals
    def _design(self, attrs: dict, *, grammar=None, search=None, seed=None, lot=UNCHANGED):
        grammar = grammar or self.grammar
        seed = self.seed if seed is None else seed
        lot = self.lot if lot is UNCHANGED else lot
        started = time.perf_counter()
        try:
            outcome = pipeline.design(
                grammar,
                attrs=attrs,
                seed=seed,
                lot=lot,
                search=search,
                assess=True,
                progress=self._progress if search is not None else None,
                # a change of the design on screen: what did not change is carried over
                previous=self._outcome
                if self._carry_over and grammar is self.grammar and search is None
                else None,
                measure_follows=self._follower is not None,
            )
        except RecursionError:
            raise RequestError("the derivation recursed too deeply", 422) from None
        except (GrammarError, ShapegenError) as exc:
            if search is None and grammar is self.grammar:
                raise RequestError(str(exc).splitlines()[0], 422) from None
            raise
        assessment = outcome.assessment
        analysis_s = None
        if assessment is not None:
            analysis_s = assessment.section.get("seconds")
        self._last_timings = {
            "update_s": time.perf_counter() - started,
            "analysis_s": analysis_s,
        }
        return outcome

    def _progress(self, record) -> None:
        with self._state_lock:
            self._optimization = {
                **(self._optimization or {}),
                "running": True,
                "iteration": record.iteration,
                "measure": finite_or_none(record.infeasibility),
                "stands": bool(record.feasible),
                "evaluations": record.evaluations,
                "seconds": record.seconds,
                "parameters": dict(record.parameters),
            }
            self.version += 1
        if self._cancel.is_set():
            raise Cancelled

    def _kept_attrs(self, grammar) -> dict:
        """The designer's values that still mean something in the re-read ``grammar``."""
        return valid_attrs(grammar, self.attrs)

    def _inputs(self) -> Inputs:
        return Inputs(dict(self.attrs), self.seed, self.lot, self._free, self.margin)

    def _current_values(self) -> dict:
        metadata = self._outcome.model.metadata or {}
        return {**dict(metadata.get("attrs", {})), **self.attrs}

    def _changed(self, *, model: bool) -> None:
        """Note a change (of the model, or of what the scans cover) and start the scans."""
        with self._state_lock:
            self.version += 1
            if model:
                self.model_version += 1
            self._stability = {}
            self._scan_generation += 1
            job = self._scan_job()
        if job is not None and self._scanner is not None:
            self._scanner.request(job)

    def _scan_job(self) -> ScanJob | None:
        assessment = self._outcome.assessment
        if assessment is None or not assessment.ok or self._text is None:
            return None
        values = self._current_values()
        ranges = self.grammar.parameter_ranges(values)
        free = {
            name: (float(ranges[name]["min"]), float(ranges[name]["max"]))
            for name in self.free_attrs
            if name in ranges and isinstance(values.get(name), float)
        }
        if not free:
            return None
        for name, (low, high) in free.items():
            self._stability[name] = {"status": "waiting", "range": [low, high], "intervals": []}
        return ScanJob(
            self._text,
            self.grammar.name,
            {  # arrays are not sent: the scanning process derives them as the editor did
                k: v
                for k, v in values.items()
                if k in self.grammar.attrs and isinstance(v, bool | int | float | str)
            },
            free,
            {name: (values[name], bool(assessment.stands)) for name in free},
            seed=self.seed,
            lot=self.lot,
            generation=self._scan_generation,
            path=str(self.path) if self.path is not None else None,
        )

    def _publish_completed(self, pending, completed) -> None:
        """The measure of the design on screen has followed its verdict: a new model version."""
        with self._state_lock:
            if completed is None or self._outcome is not pending:
                return
            self._outcome = completed
        self._changed(model=True)

    def _publish_scan(self, generation: int, name: str, result: dict) -> None:
        with self._state_lock:
            if generation != self._scan_generation:
                return
            self._stability[name] = result
            self.version += 1


def _package(source: str) -> Path | None:
    """The rule package (``.rpk``) ``source`` names, if it names one: the file the designer
    opened, which the exported command line names, rather than its unpacked start rule."""
    path = Path(source)
    if path.suffix.lower() == PACKAGE_SUFFIX and path.is_file():
        return path.resolve()
    return None


def _read(path: Path | None) -> str | None:
    """The grammar's text for the scanning process (None: no file, no scan)."""
    if path is None:
        return None
    from shapegen.grammar.source_files import read_rule_file

    return read_rule_file(path)[0]  # as the grammar was read: a cp1252 file too


def _error_json(exc: ShapegenError) -> dict:
    """A grammar (or build) error for the page: the message, its place and the source excerpt."""
    location = getattr(exc, "location", None)
    return {
        "message": getattr(exc, "message", None) or str(exc).splitlines()[0],
        "text": str(exc),
        "file": location.file if location else None,
        "line": location.line if location else None,
        "column": location.column if location else None,
    }

"""The editor's state: a grammar file, the designer's attr values, the design built from them.

Every change goes through the one pipeline (:func:`shapegen.pipeline.design`): a slider change
builds and judges the design at the new values; "optimize" and "closest" run the search from the
current values (a warm start) and take the design it found. The grammar file is re-read when it
changes on disk; a file with errors leaves the last good design in place and the error in the
state. After every change the stable interval of each free attr is scanned in the background
(:mod:`shapegen.editor.stability`).

The session owns the design on screen and the locks; what it reads out is
:mod:`~shapegen.editor.readouts`' (from a :class:`~shapegen.editor.readouts.Shown` copy), its
undo steps a :class:`~shapegen.editor.history.History`, its scans a
:class:`~shapegen.editor.scans.StableRanges`.

>>> session = EditorSession("barrel_vault.grammar", scan=False)   # doctest: +SKIP
>>> session.set_attrs({"span": 7.0})["verdict"]["stands"]          # doctest: +SKIP
"""

from __future__ import annotations

__all__ = ["EditorSession"]

import contextlib
import threading
import time
from collections.abc import Mapping, Sequence
from dataclasses import replace
from pathlib import Path

from shapegen import pipeline
from shapegen.editor.attrs import RequestError, checked_values
from shapegen.editor.completion import MeasureFollower
from shapegen.editor.history import History, reset_names
from shapegen.editor.inputs import (
    UNCHANGED,
    Inputs,
    free_attrs,
    ranged_numbers,
    valid_attrs,
    with_settings,
)
from shapegen.editor.readouts import (
    ModelFiles,
    Shown,
    attrs_export,
    block_readout,
    error_json,
    state_json,
)
from shapegen.editor.scans import StableRanges, rule_text, scan_design
from shapegen.editor.searching import Cancelled, SearchState, search_options
from shapegen.engine.project.rule_packages import package_named
from shapegen.errors import GrammarError, ShapegenError
from shapegen.json_values import json_ready
from shapegen.limits import work_clock
from shapegen.model.lot import Lot
from shapegen.search.defaults import DEFAULT_MARGIN
from shapegen.search.search_options import SearchOptions
from shapegen.statics.statics_options import Reserve


class EditorSession:
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
        lot: Lot | None = None,
        rules_path: Sequence[str] = (),
        scan: bool = True,
        measure_follows: bool = False,
        carry_over: bool = True,
    ):
        self.grammar = pipeline.load(source)
        self.path: Path | None = self.grammar.path  # the rule file read (a package's unpacked)
        self.package: Path | None = package_named(source)  # the .rpk opened, if any
        self.rules_path = tuple(str(folder) for folder in rules_path)
        self.seed = seed
        self.lot = Lot.of(lot) if lot is not None else None  # checked once, at the edge
        self._text = rule_text(self.path)
        self._work = threading.Lock()  # one change at a time
        self._state_lock = threading.RLock()
        self._state_changed = threading.Condition(self._state_lock)  # notified at each version
        self._reload_pending = False  # the file is to be re-read when the search ends
        self._idle = threading.Event()  # set while no foreground work runs: the scans wait for it
        self._idle.set()
        self.version = 0
        self.model_version = 0
        self.search = SearchState(self._state_lock, self._bump)
        self._error: dict | None = None
        self._files = ModelFiles()
        self.attrs: dict[str, object] = {}  # the designer's values; the others are the rule's
        self.history = History()
        self._free: list[str] | None = None  # the attrs the search varies; None: the @Free ones
        self.margin = Reserve(DEFAULT_MARGIN)
        self._last_inputs = self._inputs()  # the inputs before the last change
        initial = checked_values(self.grammar, {}, dict(attrs)) if attrs else {}
        self._follower = MeasureFollower(self._publish_completed) if measure_follows else None
        self._carry_over = carry_over
        self._outcome = None  # nothing to carry over into the first design
        self._outcome = self._design(initial)
        self.attrs = initial
        self._timings = self._last_timings
        self.scans = StableRanges(self._state_lock, self._bump, scan=scan)
        if self.scans.idle is not None:
            self._idle = self.scans.idle
        self._changed(model=True)

    # ------------------------------------------------------------------ the public operations
    def state(self) -> dict:
        """The page's state (plain JSON): attrs, verdict, timings, stability, search, error."""
        with self._state_lock:
            return state_json(self._shown())

    def wait_for(self, condition, timeout: float | None = None) -> dict:
        """The state, once ``condition(state)`` holds: checked at each new version of the
        state (a scan's result, a search's step, a change), never by the clock. A
        :class:`TimeoutError` after ``timeout`` seconds, a bound on the wait."""
        seen: list[dict] = []

        def holds() -> bool:
            seen.append(self.state())
            return bool(condition(seen[-1]))

        with self._state_changed:
            if not self._state_changed.wait_for(holds, timeout):
                raise TimeoutError(f"the editor's state did not come within {timeout} s")
            return seen[-1]

    def report(self) -> dict:
        """The current design's report, as ``shapegen build --analyze --report`` writes it."""
        self._settled()
        with self._state_lock:
            return json_ready(self._outcome.report)

    def glb(self) -> bytes:
        """The current model as binary glTF (blocks coloured by tension, resultant arrows)."""
        self._settled()
        with self._state_lock:
            version, outcome = self.model_version, self._outcome
        return self._files.glb(version, outcome)

    def scene(self) -> dict:
        """Colours, forces and legend of the current model (see :mod:`shapegen.editor.scene`)."""
        self._settled()
        with self._state_lock:
            version, outcome = self.model_version, self._outcome
        return self._files.scene(version, outcome)

    def attrs_export(self) -> dict:
        """The current design's attrs and the ``shapegen build`` line that builds it again
        (:func:`~shapegen.editor.readouts.attrs_export`)."""
        with self._state_lock:
            shown = self._shown()
        return attrs_export(shown)

    def block(self, block_id: str) -> dict:
        """One block of the current model (:func:`~shapegen.editor.readouts.block_readout`)."""
        self._settled()
        with self._state_lock:
            shown = self._shown()
        return block_readout(shown, block_id)

    def undo(self) -> dict:
        """Take the designer's values back to before the last change (a drag, a typed value, a
        reset, a search's result)."""
        return self._step_history("undo")

    def redo(self) -> dict:
        """Make the last undone change again."""
        return self._step_history("redo")

    def reset(self, payload: object = None) -> dict:
        """Give attrs back their rule defaults: ``{"attrs": ["span", ...]}``, or every attr the
        designer set for ``{}`` or no body. The defaults then follow the file: a changed default
        saved in it shows at the next reload."""
        names = reset_names(self.grammar, payload)
        with self._changing():
            gone = set(self.attrs) if names is None else set(names)
            kept = {k: v for k, v in self.attrs.items() if k not in gone}
            return self._apply(replace(self._inputs(), attrs=kept))

    def set_attrs(self, payload: object, *, gesture: str | None = None) -> dict:
        """Build and judge the design with the attr values in ``payload`` (checked first).

        The changes of one ``gesture`` (a drag of a slider: the page names it) are one step of
        the history: undo takes the design back to before the drag, not to its last pixel.
        """
        with self._changing():
            values = checked_values(
                self.grammar, self._current_values(), payload, free=self.free_attrs
            )
            same_gesture = self.history.joins(gesture)
            inputs = replace(self._inputs(), attrs={**self.attrs, **values})
            return self._apply(inputs, record=not same_gesture, gesture=gesture)

    def _apply(self, inputs: Inputs, *, record: bool = True, gesture: str | None = None) -> dict:
        """Take the designer's ``inputs``: build and judge the design when they build another
        one, restart the scans when the free attrs change; with ``record``, the inputs before
        are the next undo step (and the redo steps are dropped). Holds ``_work``."""
        before = self._inputs()
        build = not inputs.builds_as(before)
        if build:
            outcome = self._design(inputs.attrs, seed=inputs.seed, lot=inputs.lot)
        with self._state_lock:
            self._last_inputs = before
            self.history.changed(before, inputs, record=record, gesture=gesture)
            self.attrs = dict(inputs.attrs)
            self.seed, self.lot = inputs.seed, inputs.lot
            self._free, self.margin = inputs.free, inputs.margin
            if build:
                self.search.shown = None  # the last search's message no longer applies
                self._outcome = outcome
                self._timings = self._last_timings
                if outcome.assessment is not None and outcome.assessment.pending:
                    self._follower.request(outcome)
            if build or inputs.free != before.free:
                self._changed(model=build)
            self._bump()
            return self.state()

    def optimize(self, payload: object = None) -> dict:
        """Search the free attrs from the current values (``{"objective": "energy"}``, the
        default, or ``"closest"``) and take the design found; progress shows in the state."""
        options = search_options(payload, self.free_attrs, self.margin)
        if not self._work.acquire(blocking=False):
            raise RequestError("the design is being changed; try again when it is done", 409)
        try:
            with self._state_lock:
                self.search.running = True
            answer = self._search(options)
        finally:
            with self._state_lock:
                self.search.running = False
                reload_now, self._reload_pending = self._reload_pending, False
            self._work.release()
        # the file changed during the search: the page shows it now, with the values found
        return self.reload() if reload_now else answer

    def _search(self, options: SearchOptions) -> dict:
        self.search.started(options.objective)
        try:
            outcome = self._design(dict(self.attrs), search=options)
        except Cancelled:
            self.search.stopped()
            return self.state()
        result = outcome.optimization
        with self._state_lock:
            free = set(self.free_attrs)
            self.history.searched(self._inputs())
            self.attrs = {
                **self.attrs, **{k: v for k, v in result.attrs.items() if k in free}
            }  # fmt: skip
            self._outcome = outcome
            self._timings = self._last_timings
            self.search.ended(options.objective, result)
            self._changed(model=True)
            return self.state()

    def cancel(self) -> dict:
        """Stop a running search after its current iteration."""
        return self.search.cancel()

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
            text = rule_text(grammar.path)
            kept = self._kept_attrs(grammar)
            outcome = self._design(kept, grammar=grammar)
        except ShapegenError as exc:
            with self._state_lock:
                self._error = error_json(exc)
                self._bump()
                return self.state()
        with self._state_lock:
            self.grammar = grammar
            self.path = grammar.path
            self._text = text
            self.attrs = kept
            self._outcome = outcome
            self._timings = self._last_timings
            self._error = None
            self._changed(model=True)
            return self.state()

    def _take_work(self, *, defer_reload: bool = False) -> bool:
        """Wait for the change under way, if any, and hold ``_work``; False (at once) when a
        search holds it, after noting, with ``defer_reload``, that the file is to be re-read
        when it ends."""
        while not self._work.acquire(timeout=0.05):
            with self._state_lock:  # the search notes the reload under the same lock as it ends
                if self.search.running:
                    if defer_reload and not self._reload_pending:
                        self._reload_pending = True
                        self._bump()
                    return False
        return True

    @contextlib.contextmanager
    def _changing(self):
        """Hold ``_work`` for a change of the design; a 409 while a search holds it."""
        if not self._take_work():
            raise RequestError("a search is running; wait for it or POST /api/cancel", 409)
        try:
            yield
        finally:
            self._work.release()

    def close(self) -> None:
        """Stop the background scan (and the measures that follow)."""
        self.search.close()
        self.scans.stop()
        if self._follower is not None:
            self._follower.stop()

    # ------------------------------------------------------------------ internals
    def _design(self, attrs: dict, *, grammar=None, search=None, seed=None, lot=UNCHANGED):
        grammar = grammar or self.grammar
        seed = self.seed if seed is None else seed
        lot = self.lot if lot is UNCHANGED else lot
        started = time.perf_counter()
        self._idle.clear()  # the scans wait while a design is built
        # One clock for the request (max_seconds over deriving and judging, as for a build on
        # the command line); a search is bounded by its iterations and the page's Stop instead.
        clock = work_clock("the page's request") if search is None else contextlib.nullcontext()
        try:
            with clock:
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
        finally:
            self._idle.set()
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
        self.search.step(record)

    def _kept_attrs(self, grammar) -> dict:
        """The designer's values that still mean something in the re-read ``grammar``."""
        return valid_attrs(grammar, self.attrs)

    @property
    def free_attrs(self) -> list[str]:
        """The attrs the search varies and the stable ranges cover (:func:`free_attrs`)."""
        return free_attrs(self.grammar, self._free, self._current_values())

    def settings(self, payload: object) -> dict:
        """Change the search's settings and the derivation's (``POST /api/settings``, checked
        by :func:`with_settings`): a step of the undo history, as an attr's change is."""
        with self._changing():
            ranged = ranged_numbers(self.grammar, self._current_values())
            return self._apply(with_settings(payload, self._inputs(), self.grammar, ranged))

    def _inputs(self) -> Inputs:
        return Inputs(dict(self.attrs), self.seed, self.lot, self._free, self.margin)

    def _current_values(self) -> dict:
        metadata = self._outcome.model.metadata or {}
        return {**dict(metadata.get("attrs", {})), **self.attrs}

    def _bump(self) -> None:
        """A new version of the state (under ``_state_lock``): :meth:`wait_for` looks again."""
        with self._state_changed:
            self.version += 1
            self._state_changed.notify_all()

    def _changed(self, *, model: bool) -> None:
        """Note a change (of the model, or of what the scans cover) and start the scans."""
        with self._state_lock:
            self._bump()
            if model:
                self.model_version += 1
            job = self.scans.restart(
                scan_design(self.grammar, self._outcome, self._current_values(), self.free_attrs,
                            self._text, seed=self.seed, lot=self.lot, path=self.path)
            )  # fmt: skip
        self.scans.request(job)

    def _shown(self) -> Shown:
        """What is on screen now (call under ``_state_lock``)."""
        return Shown(
            grammar=self.grammar,
            outcome=self._outcome,
            attrs=dict(self.attrs),
            values=self._current_values(),
            free=self.free_attrs,
            free_from_file=self._free is None,
            margin=self.margin,
            seed=self.seed,
            lot=self.lot,
            path=self.path,
            package=self.package,
            rules_path=self.rules_path,
            version=self.version,
            model_version=self.model_version,
            timings=dict(self._timings),
            stability=self.scans.results(),
            optimization=self.search.shown,
            reload_pending=self._reload_pending,
            history=self.history.counts(),
            error=self._error,
        )

    def _settled(self) -> None:
        """Wait until the design on screen is complete: a pending verdict's measure and forces
        followed (:mod:`shapegen.editor.completion`)."""
        with self._state_lock:
            outcome = self._outcome
        if self._follower is not None and outcome.assessment is not None:
            if outcome.assessment.pending:
                self._follower.wait(outcome)

    def _step_history(self, what: str) -> dict:
        with self._changing():
            entry = self.history.next_step(what)
            # a value of the history may predate a reload of the file
            self._apply(replace(entry, attrs=valid_attrs(self.grammar, entry.attrs)), record=False)
            with self._state_lock:
                self.history.stepped(what, self._last_inputs)
                self._bump()
                return self.state()

    def _publish_completed(self, pending, completed) -> None:
        """The measure of the design on screen has followed its verdict: a new model version."""
        with self._state_lock:
            if completed is None or self._outcome is not pending:
                return
            self._outcome = completed
        self._changed(model=True)

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

__all__ = ["EditorSession", "OBJECTIVES"]

import math
import threading
import time
from collections.abc import Mapping
from dataclasses import dataclass
from pathlib import Path

from shapegen import pipeline
from shapegen.editor.annotations import attr_hints, inspector_sections
from shapegen.editor.attrs import RequestError, attr_specs, checked_values, plain_value
from shapegen.editor.blocks import block_details
from shapegen.editor.exports import command_line
from shapegen.editor.scene import scene_data
from shapegen.editor.stability import ScanJob, StabilityScanner
from shapegen.errors import GrammarError, ShapegenError
from shapegen.json_values import finite_or_none, json_ready
from shapegen.search.defaults import DEFAULT_MARGIN

OBJECTIVES = ("energy", "closest")
_UNCHANGED = object()  # an argument not given (None is a value: the file's @Lot)
MAX_SEED = 2**63 - 1


@dataclass(frozen=True)
class Inputs:
    """What the designer chose of a design: their attr values, the seed, the lot (None: the
    file's ``@Lot``); one step of the undo history."""

    attrs: dict
    seed: int
    lot: object


class Cancelled(Exception):
    """The designer stopped the search."""


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
    scan
        Scan the stable intervals of the free attrs in the background.
    """

    def __init__(
        self,
        source: str,
        *,
        attrs: Mapping[str, object] | None = None,
        seed: int = 0,
        lot: tuple[float, float] | None = None,
        scan: bool = True,
    ):
        self.grammar = pipeline.load(source)
        self.path: Path | None = self.grammar.path
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
        self._last_inputs = Inputs({}, seed, lot)  # the inputs before the last change
        self._free: list[str] | None = None  # the attrs the search varies; None: the @Free ones
        self.margin = DEFAULT_MARGIN
        self._scan_generation = 0  # the scans' results of an older generation are dropped
        initial = checked_values(self.grammar, {}, dict(attrs)) if attrs else {}
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
            return self._apply({**self.attrs, **values}, record=not same_gesture, gesture=gesture)
        finally:
            self._work.release()

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
            return self._apply({k: v for k, v in self.attrs.items() if k not in gone})
        finally:
            self._work.release()

    def _step_history(self, source: list, target: list, what: str) -> dict:
        if not self._take_work():
            raise RequestError("a search is running; wait for it or POST /api/cancel", 409)
        try:
            if not source:
                raise RequestError(f"nothing to {what}", 409)
            entry = source[-1]
            attrs = self._valid_attrs(self.grammar, entry.attrs)
            self._apply(attrs, seed=entry.seed, lot=entry.lot, record=False)
            with self._state_lock:
                target.append(self._last_inputs)
                source.pop()
                self.version += 1
                return self.state()
        finally:
            self._work.release()

    def _apply(
        self,
        attrs: dict,
        *,
        seed: int | None = None,
        lot=_UNCHANGED,
        record: bool = True,
        gesture: str | None = None,
    ) -> dict:
        """Build and judge the design with the designer's values ``attrs`` (and ``seed``,
        ``lot`` when given) and take it; with ``record``, the inputs before are the next undo
        step (and the redo steps are dropped). Holds ``_work``."""
        seed = self.seed if seed is None else seed
        lot = self.lot if lot is _UNCHANGED else lot
        self._idle.clear()
        try:
            outcome = self._design(attrs, seed=seed, lot=lot)
        finally:
            self._idle.set()
        with self._state_lock:
            before = self._inputs()
            self._last_inputs = before
            if record and Inputs(dict(attrs), seed, lot) != before:
                self._undo.append(before)
                self._redo.clear()
            self._gesture = gesture
            self.attrs = dict(attrs)
            self.seed, self.lot = seed, lot
            self._optimization = None  # the last search's message no longer applies
            self._outcome = outcome
            self._timings = self._last_timings
            self._changed(model=True)
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
        objective = payload.get("objective", "energy")
        if objective not in OBJECTIVES:
            raise RequestError(
                f"objective must be one of {', '.join(OBJECTIVES)}; got {objective!r}"
            )
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
            answer = self._search(objective)
        finally:
            with self._state_lock:
                self._searching = False
                reload_now, self._reload_pending = self._reload_pending, False
            self._work.release()
        # the file changed during the search: the page shows it now, with the values found
        return self.reload() if reload_now else answer

    def _search(self, objective: str) -> dict:
        self._cancel.clear()
        with self._state_lock:
            self._optimization = {"running": True, "objective": objective, "iteration": 0}
            self.version += 1
        self._idle.clear()
        try:
            outcome = self._design(
                dict(self.attrs),
                search=pipeline.SearchSettings(
                    objective=objective, free=list(self.free_attrs), margin=self.margin
                ),
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
        """Re-read the grammar file; on an error keep the last good design.

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
            grammar = pipeline.load(str(self.path))
            text = _read(self.path)
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

    def glb(self) -> bytes:
        """The current model as binary glTF (blocks coloured by tension, resultant arrows)."""
        from shapegen.export.gltf import encode_glb

        with self._state_lock:
            version, outcome = self.model_version, self._outcome
            if self._glb is not None and self._glb[0] == version:
                return self._glb[1]
        analysis = _analysis(outcome)
        content = encode_glb(outcome.model, analysis)
        with self._state_lock:
            self._glb = (version, content)
        return content

    def scene(self) -> dict:
        """Colours, forces and legend of the current model (see :mod:`shapegen.editor.scene`)."""
        with self._state_lock:
            version, outcome = self.model_version, self._outcome
            if self._scene is not None and self._scene[0] == version:
                return self._scene[1]
        data = json_ready(scene_data(outcome.model, outcome.assessment))
        data["model_version"] = version
        with self._state_lock:
            self._scene = (version, data)
        return data

    def report(self) -> dict:
        """The current design's report, as ``shapegen build --analyze --report`` writes it."""
        with self._state_lock:
            return json_ready(self._outcome.report)

    def attrs_export(self) -> dict:
        """The current design's attrs: every value (``attrs``), the designer's (``set``), and
        the ``shapegen build`` line that builds the design again (``command``: the designer's
        values; ``command_every_attr``: every value, for a file whose defaults may change)."""
        with self._state_lock:
            values = self._current_values()
            every = {k: plain_value(values[k]) for k in self.grammar.attrs if k in values}
            user = {k: every[k] for k in every if k in self.attrs}
            settable = {k: v for k, v in every.items() if not isinstance(v, list)}
            path, seed, lot = self.path, self.seed, self.lot
            return json_ready({
                "grammar": str(path) if path else None,
                "seed": seed,
                "lot": lot,
                "attrs": every,
                "set": user,
                "command": command_line(path, user, seed=seed, lot=lot),
                "command_every_attr": command_line(path, settable, seed=seed, lot=lot),
            })  # fmt: skip

    @property
    def free_attrs(self) -> list[str]:
        """The attrs the search varies and the stable ranges cover: the ``@Free`` ones, or
        those the designer chose (``POST /api/settings``) that the grammar still has with a
        ``@Range``."""
        if self._free is None:
            return list(self.grammar.free_parameters)
        ranged = self._ranged_numbers()
        return [name for name in self._free if name in ranged]

    def _ranged_numbers(self) -> set[str]:
        try:
            ranges = self.grammar.parameter_ranges(self._current_values())
        except ShapegenError:
            return set()
        defaults = self.grammar.attrs
        return {n for n in ranges if isinstance(defaults.get(n), float)}

    def settings(self, payload: object) -> dict:
        """The search's settings and the derivation's: ``{"free": [names] | null, "margin":
        0.1, "seed": 3, "lot": [width, depth] | [[x, z], ...] | null}``, any of them. ``free``
        null (and ``lot`` null) give back the file's ``@Free`` attrs (its ``@Lot``). A new seed
        or lot rebuilds the design (an undoable change); free attrs and margin do not."""
        if not isinstance(payload, dict) or not payload:
            raise RequestError(
                'send a JSON object with any of "free", "margin", "seed", "lot", such as'
                ' {"margin": 0.2}'
            )  # fmt: skip
        unknown = sorted(set(payload) - {"free", "margin", "seed", "lot"})
        if unknown:
            raise RequestError(
                f"the settings are free, margin, seed and lot; got {unknown[0]!r}"
            )  # fmt: skip
        free, margin = self._free, self.margin
        if "free" in payload:
            free = _checked_free(payload["free"], self.grammar, self._ranged_numbers())
        if "margin" in payload:
            margin = _checked_margin(payload["margin"])
        seed = _checked_seed(payload["seed"]) if "seed" in payload else self.seed
        lot = _checked_lot(payload["lot"]) if "lot" in payload else self.lot
        if not self._take_work():
            raise RequestError("a search is running; wait for it or POST /api/cancel", 409)
        try:
            if (seed, lot) != (self.seed, self.lot):
                self._apply(dict(self.attrs), seed=seed, lot=lot)
            with self._state_lock:
                rescan = free != self._free
                self._free, self.margin = free, margin
                if rescan:
                    self._changed(model=False)
                self.version += 1
                return self.state()
        finally:
            self._work.release()

    def block(self, block_id: str) -> dict:
        """One block of the current model: labels, rule path, the attrs its rules read, its
        joints' forces and the tension it needs (see :mod:`shapegen.editor.blocks`)."""
        with self._state_lock:
            outcome, version = self._outcome, self.model_version
            values, user = self._current_values(), set(self.attrs)
        details = block_details(outcome, block_id, values, user)
        if details is None:
            raise RequestError(f"the current model has no block {block_id!r}", 404)
        details["model_version"] = version
        return json_ready(details)

    def close(self) -> None:
        """Stop the background scan."""
        self._cancel.set()
        if self._scanner is not None:
            self._scanner.stop()

    # ------------------------------------------------------------------ internals
    def _design(self, attrs: dict, *, grammar=None, search=None, seed=None, lot=_UNCHANGED):
        grammar = grammar or self.grammar
        seed = self.seed if seed is None else seed
        lot = self.lot if lot is _UNCHANGED else lot
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
        return self._valid_attrs(grammar, self.attrs)

    @staticmethod
    def _valid_attrs(grammar, attrs: Mapping[str, object]) -> dict:
        """The values of ``attrs`` that mean something in ``grammar``: an attr it has, of the
        same type, within its range (a value of the history may predate a reload)."""
        kept = {}
        defaults = grammar.attrs
        for name, value in attrs.items():
            if name in defaults and type(defaults[name]) is type(value):
                kept[name] = value
        try:
            ranges = grammar.parameter_ranges(kept)
        except ShapegenError:
            return {}
        return {
            name: value
            for name, value in kept.items()
            if name not in ranges
            or not isinstance(value, float)
            or ranges[name]["min"] <= value <= ranges[name]["max"]
        }

    def _inputs(self) -> Inputs:
        return Inputs(dict(self.attrs), self.seed, self.lot)

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

    def _publish_scan(self, generation: int, name: str, result: dict) -> None:
        with self._state_lock:
            if generation != self._scan_generation:
                return
            self._stability[name] = result
            self.version += 1

    def _state(self) -> dict:
        outcome = self._outcome
        assessment = outcome.assessment
        values = self._current_values()
        section = assessment.section if assessment is not None else {}
        verdict = None
        if assessment is not None:
            verdict = {
                "stands": bool(assessment.stands),
                "measure": finite_or_none(assessment.measure),
                "measure_name": outcome.structure.measure_name,
                "status": assessment.status,
                "max_tension": section.get("max_tension"),
            }
        return {
            "version": self.version,
            "model_version": self.model_version,
            "grammar": {
                "name": Path(self.grammar.name).name,
                "path": str(self.path) if self.path else None,
                "structure": outcome.structure.name,
                "blocks": len(outcome.model.blocks),
                "dialect": getattr(self.grammar.ast, "dialect", "grammar"),
            },
            # what the load let through and the derivation warned about (a .cga file's)
            "warnings": [str(w) for w in (outcome.model.metadata or {}).get("warnings", [])],
            "attrs": [
                spec.to_json()
                for spec in attr_specs(self.grammar, values, user=self.attrs, free=self.free_attrs)
            ],
            "sections": inspector_sections(attr_hints(self.grammar)),
            "verdict": verdict,
            "cables": section if outcome.structure.name == "cable" else None,
            "timings": dict(self._timings),
            "stability": dict(self._stability),
            "optimization": self._optimization,
            "reload_pending": self._reload_pending,
            "history": {"undo": len(self._undo), "redo": len(self._redo)},
            "settings": {
                "free": self.free_attrs,
                "free_from_file": self._free is None,
                "margin": self.margin,
                "seed": self.seed,
                "lot": self.lot,
                "file_lot": list(self.grammar.lot),
            },
            "error": self._error,
        }


def _checked_free(value: object, grammar, ranged: set[str]) -> list[str] | None:
    if value is None:
        return None
    if not isinstance(value, list) or not all(isinstance(n, str) for n in value):
        raise RequestError('"free" is a list of attr names, such as ["span"], or null')
    for name in value:
        if name not in grammar.attrs:
            raise RequestError(f"the grammar has no attr {name!r}")
        if name not in ranged:
            raise RequestError(
                f"attr {name!r} cannot be free: the search varies numbers within a @Range"
            )  # fmt: skip
    return list(dict.fromkeys(value))


def _checked_margin(value: object) -> float:
    if isinstance(value, bool) or not isinstance(value, int | float) or not 0 <= value < 1:
        raise RequestError(f'"margin" is a number from 0 to below 1; got {value!r}')
    return float(value)


def _checked_seed(value: object) -> int:
    if isinstance(value, bool) or not isinstance(value, int) or not 0 <= value <= MAX_SEED:
        raise RequestError(f'"seed" is a whole number from 0 to {MAX_SEED}; got {value!r}')
    return value


def _checked_lot(value: object):
    """A lot from JSON: null, ``[width, depth]`` (m, > 0) or ``[[x, z], ...]`` (3 or more
    points, m, counter-clockwise seen from above) as the derivation takes it."""
    if value is None:
        return None

    def finite(v: object) -> bool:
        return not isinstance(v, bool) and isinstance(v, int | float) and math.isfinite(v)

    if isinstance(value, list) and len(value) == 2 and all(finite(v) for v in value):
        if min(value) <= 0:
            raise RequestError(f'"lot" width and depth must be > 0 m; got {value!r}')
        return (float(value[0]), float(value[1]))
    points = value if isinstance(value, list) else None
    if (
        points is None
        or len(points) < 3
        or not all(isinstance(p, list) and len(p) == 2 and all(finite(v) for v in p)
                   for p in points)
    ):  # fmt: skip
        raise RequestError(
            '"lot" is [width, depth] in metres, a polygon [[x, z], [x, z], [x, z], ...], or null'
        )
    return tuple((float(x), float(z)) for x, z in points)


def _read(path: Path | None) -> str | None:
    """The grammar's text for the scanning process (None: no file, no scan)."""
    if path is None:
        return None
    try:
        return path.read_text(encoding="utf-8")
    except (OSError, UnicodeDecodeError) as exc:
        raise GrammarError(f"cannot read {str(path)!r}: {exc}") from None


def _analysis(outcome):
    assessment = outcome.assessment
    if assessment is not None and assessment.structure == "blocks":
        return assessment.detail
    return None


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

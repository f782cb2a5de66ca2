"""Where each free attr's design stands, the others held: the shading on the Inspector's sliders.

For one free attr the structure's verdict is sampled on :data:`SCAN_POINTS` evenly spaced values
of its ``@Range`` (plus the current value, whose verdict is already known), every other attr
held at its current value. Between two neighbouring samples with different verdicts the boundary
is bisected :data:`REFINE_STEPS` times. The standing intervals reported run from standing sample
to standing sample, so every end was judged to stand and lies within ``resolution`` (the range
over ``(SCAN_POINTS - 1) * 2**REFINE_STEPS``) of the true boundary. A standing window narrower
than the sample spacing can be missed. Each design is judged by :class:`~shapegen.search.Evaluator`,
the search's own, so the shading and the search agree.

The scans run in a background process of lower priority, after the designer pauses
(:data:`PAUSE_S`), wait while a change is computed, and are abandoned between two evaluations
as soon as the design changes. An attr's interval depends only on the other attrs, so moving a
free slider keeps its own shading.
"""

from __future__ import annotations

__all__ = [
    "PAUSE_S",
    "REFINE_STEPS",
    "SCAN_POINTS",
    "ScanJob",
    "StabilityScanner",
    "scan",
    "stable_intervals",
]

import dataclasses
import json
import os
import signal
import subprocess
import sys
import threading
from collections.abc import Callable, Mapping
from dataclasses import dataclass

import numpy as np

from shapegen.model.lot import Lot
from shapegen.search import Evaluator, FreeParameter

SCAN_POINTS = 13  # samples over the range, ends included
REFINE_STEPS = 5  # bisections of each verdict change: resolution = range / 12 / 32
PAUSE_S = 0.3  # the design must stay unchanged this long before a scan starts
STOP_WAIT_S = 2.0  # how long the editor waits for the scanning process to end, asked then killed


class Stale(Exception):
    """The design changed during a scan."""


def stable_intervals(
    judge: Callable[[float], bool | None],
    lower: float,
    upper: float,
    *,
    known: Mapping[float, bool] | None = None,
    points: int = SCAN_POINTS,
    refine: int = REFINE_STEPS,
    on_sample: Callable[[list[tuple[float, bool | None]]], None] | None = None,
) -> dict:
    """The standing intervals of a 1-D verdict over ``[lower, upper]``.

    Parameters
    ----------
    judge
        The verdict at a value: True (stands), False, or None (the design cannot be judged,
        counted as not standing).
    known
        Verdicts already known (the current value's).
    on_sample
        Called with the samples so far after each verdict (for progressive display).

    Returns
    -------
    dict
        ``intervals`` (list of ``[low, high]``), ``samples`` (sorted ``[value, stands]``),
        ``resolution`` (the spacing left at each boundary) and ``evaluations``.
    """
    samples: dict[float, bool | None] = dict(known or {})
    evaluations = 0

    def verdict(x: float) -> bool | None:
        nonlocal evaluations
        x = float(x)
        if x not in samples:
            samples[x] = judge(x)
            evaluations += 1
            if on_sample is not None:
                on_sample(sorted(samples.items()))
        return samples[x]

    for x in np.linspace(lower, upper, points):
        verdict(x)
    for _ in range(refine):
        ordered = sorted(samples.items())
        changes = [
            (a, b)
            for (a, sa), (b, sb) in zip(ordered, ordered[1:], strict=False)
            if bool(sa) != bool(sb) and b - a > (upper - lower) / (points - 1) / 2**refine * 1.01
        ]
        if not changes:
            break
        for a, b in changes:
            verdict(0.5 * (a + b))
    ordered = sorted(samples.items())
    intervals: list[list[float]] = []
    run: list[float] | None = None
    for x, stands in ordered:
        if stands:
            run = [x, x] if run is None else [run[0], x]
        elif run is not None:
            intervals.append(run)
            run = None
    if run is not None:
        intervals.append(run)
    return {
        "intervals": intervals,
        "samples": [[x, stands] for x, stands in ordered],
        "resolution": (upper - lower) / (points - 1) / 2**refine,
        "evaluations": evaluations,
    }


@dataclass
class ScanJob:
    """What to scan: the design at ``attrs`` (every override), one scan per free attr.

    Plain data, sent to the scanning process: the grammar travels as its text, and as its
    file's path when it has one (a ``.cga`` file's imports and assets are found from there).
    """

    text: str  # the grammar's source
    name: str  # its file name, for messages
    attrs: dict
    ranges: dict  # name -> (lower, upper) of the free attrs
    current: dict  # name -> (value, stands) of the current design
    seed: int = 0
    lot: Lot | None = None
    generation: int = 0
    path: str | None = None  # the rule file, read again by the scanning process


class StabilityScanner:
    """Scans the free attrs of the latest design in a separate, lower-priority process.

    A process of its own (``python -m shapegen.editor.scan_worker``, spoken to in JSON lines),
    rather than a thread, so that a scan shares neither the interpreter lock nor the processor
    with the designer's next change: the process is stopped while a change is computed (see
    :class:`_RemoteFlag`), and runs at lower priority (``nice`` +10) otherwise.
    ``publish(generation, name, result)`` receives partial and final results (``result`` has
    a ``status``: "scanning" or "done"). :attr:`idle` is set while no foreground work runs: a
    scan waits for it before each evaluation.
    """

    def __init__(self, publish: Callable[[int, str, dict], None], *, pause: float = PAUSE_S):
        self._publish = publish
        self._lock = threading.Lock()
        self._process = subprocess.Popen(
            [sys.executable, "-m", "shapegen.editor.scan_worker", repr(float(pause))],
            stdin=subprocess.PIPE,
            stdout=subprocess.PIPE,
            text=True,
            encoding="utf-8",
            bufsize=1,
        )
        self.idle = _RemoteFlag(self._send, self._process.pid)
        self._reader = threading.Thread(target=self._read, name="stability-results", daemon=True)
        self._reader.start()

    def request(self, job: ScanJob) -> None:
        """Scan ``job``, abandoning any older one."""
        self._send({"job": dataclasses.asdict(job)})

    def stop(self) -> None:
        """End the scanning process: asked first, then killed. It keeps nothing worth saving,
        so a process slow to go (a loaded machine, a long evaluation at low priority) is not
        waited for long, and one the system has not reaped yet is left to it: the editor's
        own exit never fails on it."""
        self.idle.stop_signalling()
        self._send({"stop": True})
        try:
            self._process.stdin.close()
        except OSError:
            pass
        for ask in (None, self._process.kill):
            if ask is not None:
                ask()
            try:
                self._process.wait(timeout=STOP_WAIT_S)
                break
            except subprocess.TimeoutExpired:
                continue
        self._reader.join(timeout=STOP_WAIT_S)

    def _send(self, message: dict) -> None:
        line = json.dumps(message, allow_nan=False) + "\n"
        with self._lock:
            try:
                self._process.stdin.write(line)
                self._process.stdin.flush()
            except (OSError, ValueError):  # the process is gone: no shading, the editor goes on
                pass

    def _read(self) -> None:
        for line in self._process.stdout:
            try:
                generation, name, result = json.loads(line)
            except ValueError:
                continue
            self._publish(generation, name, result)


class _RemoteFlag:
    """An event-like flag whose changes are sent to the scanning process.

    Where the system has job control (POSIX), clearing it also stops the process outright
    (``SIGSTOP``) until it is set again (``SIGCONT``): the analysis it was running waits too,
    so the designer's change has the processor to itself.
    """

    def __init__(self, send: Callable[[dict], None], pid: int):
        self._send = send
        self._pid = pid
        self._set = True
        self._stopping = False

    def _signal(self, name: str) -> None:
        number = getattr(signal, name, None)
        if number is not None:
            try:
                os.kill(self._pid, number)
            except OSError:  # the process is gone
                pass

    def set(self) -> None:
        self._set = True
        self._signal("SIGCONT")
        self._send({"idle": True})

    def clear(self) -> None:
        self._set = False
        self._send({"idle": False})
        if not self._stopping:
            self._signal("SIGSTOP")

    def stop_signalling(self) -> None:
        """Let the process run to its end: it is continued, and no later change stops it."""
        self._stopping = True
        self.set()

    def is_set(self) -> bool:
        return self._set


def scan(job: ScanJob, grammar, structure, cache: dict, emit, stale, wait_idle) -> None:
    """Scan every free attr of ``job`` (in the scanning process).

    ``emit(generation, name, result)`` sends results; ``stale()`` says the design changed (the
    scan then raises :class:`Stale`); ``wait_idle()`` returns once no change is being computed.
    """
    for name, (lower, upper) in job.ranges.items():
        others = {k: v for k, v in job.attrs.items() if k != name}
        key = (job.text, name, lower, upper, _frozen(others), job.seed, job.lot)
        if key in cache:
            emit(job.generation, name, {**cache[key], "status": "done"})
            continue
        evaluator = Evaluator(
            grammar,
            structure,
            [FreeParameter(name, lower, lower, upper)],
            others,
            seed=job.seed,
            lot=job.lot,
        )

        def judge(x: float, evaluator=evaluator) -> bool | None:
            wait_idle()
            if stale():
                raise Stale
            evaluation = evaluator.evaluate(np.array([x]))
            if stale():
                raise Stale
            return bool(evaluation.feasible) if evaluation.ok else None

        def partial(samples, name=name, lower=lower, upper=upper) -> None:
            scanning = {"status": "scanning", "samples": [[x, s] for x, s in samples],
                        "intervals": [], "range": [lower, upper]}  # fmt: skip
            emit(job.generation, name, scanning)

        value, stands = job.current[name]
        known = {float(value): stands} if lower <= value <= upper else {}
        result = stable_intervals(judge, lower, upper, known=known, on_sample=partial)
        result["range"] = [lower, upper]
        if len(cache) > 256:
            cache.clear()
        cache[key] = result
        emit(job.generation, name, {**result, "status": "done"})


def _frozen(attrs: Mapping[str, object]) -> tuple:
    return tuple(sorted((k, repr(v)) for k, v in attrs.items()))

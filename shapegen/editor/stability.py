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
    "stable_intervals",
]

import multiprocessing
import threading
from collections.abc import Callable, Mapping
from dataclasses import dataclass

import numpy as np

from shapegen.search import Evaluator, FreeParameter

SCAN_POINTS = 13  # samples over the range, ends included
REFINE_STEPS = 5  # bisections of each verdict change: resolution = range / 12 / 32
PAUSE_S = 0.3  # the design must stay unchanged this long before a scan starts


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

    Plain data, sent to the scanning process: the grammar travels as its text.
    """

    text: str  # the grammar's source
    name: str  # its file name, for messages
    attrs: dict
    ranges: dict  # name -> (lower, upper) of the free attrs
    current: dict  # name -> (value, stands) of the current design
    seed: int = 0
    lot: tuple[float, float] | None = None
    generation: int = 0


class StabilityScanner:
    """Scans the free attrs of the latest design in a separate, lower-priority process.

    A process of its own, rather than a thread, so that a scan shares neither the interpreter
    lock nor, on a machine with a spare core, the processor with the designer's next change;
    its priority is lowered (``nice`` +10) so the change wins where they do compete.
    ``publish(generation, name, result)`` receives partial and final results (``result`` has a
    ``status``: "scanning" or "done"). :attr:`idle` must be set while no foreground work runs: a
    scan waits for it before each evaluation.
    """

    def __init__(self, publish: Callable[[int, str, dict], None], *, pause: float = PAUSE_S):
        context = multiprocessing.get_context("spawn")  # the server has threads: never fork
        self._publish = publish
        self.idle = context.Event()
        self.idle.set()
        self._generation = context.Value("q", 0)
        self._requests = context.Queue()
        self._results = context.Queue()
        self._process = context.Process(
            target=_work,
            args=(self._requests, self._results, self._generation, self.idle, pause),
            name="shapegen-stability-scan",
            daemon=True,
        )
        self._process.start()
        self._reader = threading.Thread(target=self._read, name="stability-results", daemon=True)
        self._reader.start()

    def request(self, job: ScanJob) -> None:
        """Scan ``job``, abandoning any older one."""
        self._generation.value = job.generation
        self._requests.put(job)

    def stop(self) -> None:
        self._generation.value = -1
        self.idle.set()
        try:
            self._requests.put(None)
            self._process.join(timeout=5)
        finally:
            if self._process.is_alive():
                self._process.terminate()
                self._process.join(timeout=5)
            self._results.put(None)
            self._reader.join(timeout=5)

    def _read(self) -> None:
        while True:
            item = self._results.get()
            if item is None:
                return
            self._publish(*item)


def _work(requests, results, generation, idle, pause: float) -> None:
    """The scanning process: the latest job after a pause in the edits, one attr at a time."""
    import os
    import queue

    try:
        os.nice(10)
    except OSError:
        pass
    grammars: dict[str, object] = {}
    cache: dict[tuple, dict] = {}
    job = None
    while True:
        if job is None:
            job = requests.get()
        try:  # a pause in the designer's edits: take the newest job until none comes for a while
            while True:
                job = requests.get(timeout=pause)
        except queue.Empty:
            pass
        if job is None:
            return
        current, job = job, None
        try:
            _scan(current, grammars, cache, results, generation, idle)
        except Stale:
            continue


def _scan(job: ScanJob, grammars: dict, cache: dict, results, generation, idle) -> None:
    from shapegen.engine.grammar_api import parse_grammar
    from shapegen.structures import make_structure

    def stale() -> bool:
        return generation.value != job.generation

    if job.text not in grammars:
        grammars.clear()
        grammars[job.text] = parse_grammar(job.text, job.name)
    grammar = grammars[job.text]
    structure = make_structure(grammar.structure)
    for name, (lower, upper) in job.ranges.items():
        others = {k: v for k, v in job.attrs.items() if k != name}
        key = (job.text, name, lower, upper, _frozen(others), job.seed, job.lot)
        if key in cache:
            results.put((job.generation, name, {**cache[key], "status": "done"}))
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
            while not idle.wait(0.5):
                if stale():
                    raise Stale
            if stale():
                raise Stale
            evaluation = evaluator.evaluate(np.array([x]))
            if stale():
                raise Stale
            return bool(evaluation.feasible) if evaluation.ok else None

        def partial(samples, name=name, lower=lower, upper=upper) -> None:
            scanning = {"status": "scanning", "samples": [[x, s] for x, s in samples],
                        "intervals": [], "range": [lower, upper]}  # fmt: skip
            results.put((job.generation, name, scanning))

        value, stands = job.current[name]
        known = {float(value): stands} if lower <= value <= upper else {}
        result = stable_intervals(judge, lower, upper, known=known, on_sample=partial)
        result["range"] = [lower, upper]
        if len(cache) > 256:
            cache.clear()
        cache[key] = result
        results.put((job.generation, name, {**result, "status": "done"}))


def _frozen(attrs: Mapping[str, object]) -> tuple:
    return tuple(sorted((k, repr(v)) for k, v in attrs.items()))

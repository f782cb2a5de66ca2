"""Where each free attr's design stands, the others held: the shading on the Inspector's sliders.

For one free attr the structure's verdict is sampled on :data:`SCAN_POINTS` evenly spaced values
of its ``@Range`` (plus the current value, whose verdict is already known), every other attr
held at its current value. Between two neighbouring samples with different verdicts the boundary
is bisected :data:`REFINE_STEPS` times. The standing intervals reported run from standing sample
to standing sample, so every end was judged to stand and lies within ``resolution`` (the range
over ``(SCAN_POINTS - 1) * 2**REFINE_STEPS``) of the true boundary. A standing window narrower
than the sample spacing can be missed. Each design is judged by :class:`~shapegen.search.Evaluator`,
the search's own, so the shading and the search agree.

The scans run in one background thread, after the designer pauses (:data:`PAUSE_S`), and are
abandoned between two evaluations as soon as the design changes. An attr's interval depends only
on the other attrs, so moving a free slider keeps its own shading.
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

import threading
from collections.abc import Callable, Mapping
from dataclasses import dataclass, field

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
    """What to scan: the design at ``attrs`` (every override), one scan per free attr."""

    grammar: object
    structure: object
    attrs: dict
    ranges: dict  # name -> (lower, upper) of the free attrs
    current: dict  # name -> (value, stands) of the current design
    seed: int = 0
    lot: tuple[float, float] | None = None
    generation: int = 0
    cached: dict = field(default_factory=dict)


class StabilityScanner:
    """One background thread that scans the free attrs of the latest design.

    ``publish(generation, name, result)`` receives partial and final results (``result`` has a
    ``status``: "scanning" or "done"). ``idle`` is waited on before each evaluation so that a
    foreground update never shares the processor with a scan for long.
    """

    def __init__(
        self,
        publish: Callable[[int, str, dict], None],
        idle: threading.Event,
        *,
        pause: float = PAUSE_S,
    ):
        self._publish = publish
        self._idle = idle
        self._pause = pause
        self._job: ScanJob | None = None
        self._wake = threading.Condition()
        self._stopped = False
        self._cache: dict[tuple, dict] = {}
        self._thread = threading.Thread(target=self._run, name="stability-scan", daemon=True)
        self._thread.start()

    def request(self, job: ScanJob) -> None:
        """Scan ``job`` (abandoning any older one)."""
        with self._wake:
            self._job = job
            self._wake.notify_all()

    def stop(self) -> None:
        with self._wake:
            self._stopped = True
            self._job = None
            self._wake.notify_all()
        self._thread.join(timeout=5)

    def _current(self, generation: int) -> bool:
        job = self._job
        return not self._stopped and job is not None and job.generation == generation

    def _run(self) -> None:
        while True:
            with self._wake:
                while not self._stopped and self._job is None:
                    self._wake.wait()
                if self._stopped:
                    return
                job = self._job
                # wait for a pause in the designer's edits
                while self._wake.wait(timeout=self._pause):
                    if self._stopped:
                        return
                    job = self._job
                if self._job is not job:
                    continue
            try:
                self._scan(job)
            except Stale:
                continue
            with self._wake:
                if self._job is job:
                    self._job = None

    def _scan(self, job: ScanJob) -> None:
        for name, (lower, upper) in job.ranges.items():
            others = {k: v for k, v in job.attrs.items() if k != name}
            key = (id(job.grammar), name, lower, upper, _frozen(others), job.seed, job.lot)
            if key in self._cache:
                self._publish(job.generation, name, {**self._cache[key], "status": "done"})
                continue
            evaluator = Evaluator(
                job.grammar,
                job.structure,
                [FreeParameter(name, lower, lower, upper)],
                others,
                seed=job.seed,
                lot=job.lot,
            )

            def judge(x: float, evaluator=evaluator) -> bool | None:
                self._idle.wait()
                if not self._current(job.generation):
                    raise Stale
                evaluation = evaluator.evaluate(np.array([x]))
                if not self._current(job.generation):
                    raise Stale
                return bool(evaluation.feasible) if evaluation.ok else None

            def partial(samples, name=name, lower=lower, upper=upper) -> None:
                self._publish(
                    job.generation,
                    name,
                    {"status": "scanning", "samples": [[x, s] for x, s in samples],
                     "intervals": [], "range": [lower, upper]},
                )  # fmt: skip

            value, stands = job.current[name]
            known = {float(value): stands} if lower <= value <= upper else {}
            result = stable_intervals(judge, lower, upper, known=known, on_sample=partial)
            result["range"] = [lower, upper]
            if len(self._cache) > 256:
                self._cache.clear()
            self._cache[key] = result
            self._publish(job.generation, name, {**result, "status": "done"})


def _frozen(attrs: Mapping[str, object]) -> tuple:
    return tuple(sorted((k, repr(v)) for k, v in attrs.items()))

"""The stable interval of a free attr: a scan refined by bisection, checked against closed forms."""

import math
import threading
import time

import numpy as np
import pytest
from editor_stack import STACK_BOUNDARY, WAIT_BOUND_S

from shapegen.editor.stability import (
    REFINE_STEPS,
    SCAN_POINTS,
    ScanJob,
    StabilityScanner,
    stable_intervals,
)


def window(*spans):
    return lambda x: any(a <= x <= b for a, b in spans)


@pytest.mark.parametrize(
    "spans",
    [
        [(2.0, 7.3)],
        [(0.0, 4.4)],
        [(5.55, 10.0)],
        [(0.0, 10.0)],
        [(1.2, 3.1), (6.05, 8.9)],
    ],
)
def test_intervals_are_found_within_the_resolution(spans):
    result = stable_intervals(window(*spans), 0.0, 10.0)
    resolution = 10.0 / (SCAN_POINTS - 1) / 2**REFINE_STEPS
    assert result["resolution"] == pytest.approx(resolution)
    assert len(result["intervals"]) == len(spans)
    for (low, high), (a, b) in zip(result["intervals"], spans, strict=True):
        # the ends were judged to stand, and lie within one resolution inside the true window
        assert a <= low <= a + resolution + 1e-12
        assert b - resolution - 1e-12 <= high <= b
    # a grid plus a few bisections per boundary, not a dense scan
    assert result["evaluations"] <= SCAN_POINTS + 2 * len(spans) * REFINE_STEPS


def test_nowhere_and_unjudgeable_designs():
    assert stable_intervals(lambda x: False, 0.0, 1.0)["intervals"] == []
    # a design that cannot be judged counts as not standing
    result = stable_intervals(lambda x: None if x > 0.5 else True, 0.0, 1.0)
    ((low, high),) = result["intervals"]
    assert low == 0.0 and 0.5 - result["resolution"] <= high <= 0.5


def test_the_known_verdict_is_used_and_not_judged_again():
    judged = []

    def judge(x):
        judged.append(x)
        return x < 0.3

    result = stable_intervals(judge, 0.0, 1.0, known={0.123: True})
    assert 0.123 not in judged and [0.123, True] in result["samples"]


def job(stack_file, generation):
    text = stack_file.read_text()
    ranges, current = {"offset": (0.0, 0.9)}, {"offset": (0.2, True)}
    return ScanJob(text, str(stack_file), {"offset": 0.2}, ranges, current, generation=generation)


def test_the_stack_stands_up_to_half_a_block_of_offset(stack_file):
    published = {}
    done = threading.Event()

    def publish(generation, name, result):
        published[name] = result
        if result["status"] == "done":
            done.set()

    scanner = StabilityScanner(publish, pause=0.0)
    try:
        scanner.request(job(stack_file, 1))
        assert done.wait(WAIT_BOUND_S), "the scan did not finish"
    finally:
        scanner.stop()
    result = published["offset"]
    ((low, high),) = result["intervals"]
    assert low == 0.0
    assert STACK_BOUNDARY - result["resolution"] <= high <= STACK_BOUNDARY + 1e-9
    assert math.isclose(result["resolution"], 0.9 / (SCAN_POINTS - 1) / 2**REFINE_STEPS)


def test_a_newer_design_abandons_the_scan_of_an_older_one(stack_file):
    seen, second_done = [], threading.Event()

    def publish(generation, name, result):
        seen.append((generation, result["status"]))
        if (generation, result["status"]) == (2, "done"):
            second_done.set()

    scanner = StabilityScanner(publish, pause=0.0)
    try:
        scanner.idle.clear()  # hold the first scan before its first evaluation
        scanner.request(job(stack_file, 1))
        # the first job most likely reaches the process first; whichever order they come in,
        # no result of it may be published
        time.sleep(0.5)
        scanner.request(job(stack_file, 2))
        scanner.idle.set()
        assert second_done.wait(WAIT_BOUND_S), "the newer scan did not finish"
    finally:
        scanner.stop()
    assert not any(generation == 1 for generation, _ in seen)


def test_samples_are_sorted_and_cover_the_range():
    result = stable_intervals(window((0.25, 0.75)), 0.0, 1.0)
    xs = np.array([x for x, _ in result["samples"]])
    assert np.all(np.diff(xs) > 0) and xs[0] == 0.0 and xs[-1] == 1.0


def test_stopping_ends_a_held_process_and_one_that_does_not_answer(monkeypatch):
    import shapegen.editor.stability as stability

    # held: a change under way has stopped the process (SIGSTOP); stop() continues and ends it
    scanner = StabilityScanner(lambda g, n, r: None, pause=0.0)
    scanner.idle.clear()
    scanner.stop()
    assert scanner._process.poll() is not None
    scanner.idle.clear()  # a change computed after the stop signals nothing (the pid is gone)

    # deaf: it never hears the stop (its input stays open), so it is killed after the wait
    monkeypatch.setattr(stability, "STOP_WAIT_S", 0.5)
    scanner = StabilityScanner(lambda g, n, r: None, pause=0.0)
    monkeypatch.setattr(scanner, "_send", lambda message: None)
    monkeypatch.setattr(scanner._process.stdin, "close", lambda: None)
    scanner.stop()
    # it did not wait for an answer that never comes: it killed the process after the wait
    assert scanner._process.poll() == -9  # SIGKILL

"""Fuzzing the whole path from text to model, and the model readers, each input in a forked
child capped at 10 s of CPU and 2 GiB: every input must end in a model or in one of the
project's own errors (a ShapegenError), never in another exception, past the caps or hung.

Inputs (tests/fuzz/fuzz_inputs.py) are mutations of the bundled rules, the test examples and
the docs' grammar examples (tokens and characters edited, numbers replaced by extreme values),
grammars written by a random generator, and mutated model files (JSON, OBJ, STL, PLY, glTF).
Every input comes from its number, so a failure names an input that can be replayed:
``python tests/fuzz/test_fuzz.py rule 123`` (or ``random``, ``model``).

The quick lane runs a few hundred inputs; the slow lane a few thousand. A campaign of any size
prints its figures: ``python tests/fuzz/test_fuzz.py 10000`` (or one kind from a given number,
``python tests/fuzz/test_fuzz.py 2500 rule 100000``, to run parts in parallel); the last one is
recorded in docs/journal/performance.md ("Bounded work").
"""

from __future__ import annotations

import sys

import pytest
from fuzz_inputs import (
    mutated_model,
    mutated_rule,
    random_rule,
    run_model,
    run_rule,
    warm_up,
)
from fuzz_sandbox import CPU_SECONDS, MEMORY_BYTES, print_figures, run_campaign, run_limited

KINDS = {
    "rule": (lambda n, small: mutated_rule(n, small), run_rule),
    "random": (lambda n, small: random_rule(n), run_rule),
    "model": (lambda n, small: mutated_model(n), run_model),
}


def campaign(
    counts: dict[str, int], *, small_only: bool, start: int = 0, progress: bool = False
) -> dict:
    """Run ``counts[kind]`` inputs of each kind; return the figures and the failures."""
    warm_up()
    inputs = (
        (f"{kind} {number}", KINDS[kind][1], KINDS[kind][0](number, small_only))
        for kind, count in counts.items()
        for number in range(start, start + count)
    )
    return run_campaign(inputs, progress=progress, every=500)


def _check(figures: dict) -> None:
    shown = "\n".join(figures["failures"][:10])
    assert not figures["failures"], f"{len(figures['failures'])} inputs failed:\n{shown}"
    assert figures["slowest_cpu_s"][0] <= CPU_SECONDS
    assert figures["peak_mib"][0] * 2**20 <= MEMORY_BYTES


def test_quick_fuzz_lane():
    # ~4 s of CPU: small seeds only (parsing costs ~50 us a character); the slow lane runs
    # 3 000 more of each kind from other seeds.
    _check(campaign({"rule": 60, "random": 50, "model": 30}, small_only=True))


@pytest.mark.slow
def test_slow_fuzz_lane():
    _check(campaign({"rule": 1500, "random": 1000, "model": 500}, small_only=False, start=1000))


def test_the_sandbox_reports_what_it_catches():
    # The harness itself must be able to fail: a crash, a runaway loop and a memory hog.
    crash = run_limited(lambda _: [][1], None)
    assert crash.kind == "crash" and "IndexError" in crash.detail
    loop = run_limited(lambda _: [0 for _ in iter(int, 1)], None, cpu_seconds=1)
    assert loop.kind == "killed"
    hog = run_limited(lambda _: bytearray(4 * 2**30), None)
    assert hog.kind == "killed"


def _main(argv: list[str]) -> None:
    if len(argv) == 2 and argv[0] in KINDS:  # replay one input
        make, target = KINDS[argv[0]]
        item = make(int(argv[1]), False)
        print(item if isinstance(item, str) else item[0])
        target(item)
        return
    total = int(argv[0]) if argv else 10_000
    counts = {"rule": total // 2, "random": total * 3 // 10}
    counts["model"] = total - sum(counts.values())
    start = 100_000
    if len(argv) == 3:  # one kind from a given number, to run a campaign in parallel parts
        counts, start = {argv[1]: total}, int(argv[2])
    print_figures(campaign(counts, small_only=False, start=start, progress=True))


if __name__ == "__main__":
    _main(sys.argv[1:])

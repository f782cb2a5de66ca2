"""Derive many generated well-formed CGA programs and count what became of them.

Each seed makes one program (tests/cga/cga_programs.py: random productions of the language,
operations with arguments of the kinds CityEngine's reference lists); the tool parses every file
of it, prints it and parses it again (the trees must be equal), loads it and derives it on a
12 x 8 m lot, in worker processes, each program with a time limit. It prints the first seed and
the count, the number of programs per outcome (``derives``, ``error``: a ShapegenError,
``known refusal``, ``refused``, ``round trip``, ``crash``: a traceback, ``timeout``) and, per
kind of message, how many programs had it with one seed to reproduce it::

    .venv/bin/python tools/cga_generated.py                      # 10 000 programs from seed 0
    .venv/bin/python tools/cga_generated.py --seed 123 --count 500 --jobs 2
    .venv/bin/python tools/cga_generated.py --parse-only         # the parser and printer only
    .venv/bin/python tools/cga_generated.py --show 4711          # print one program's files

Exit status 1 when a program was refused (outside the known gaps), printed back differently,
ended in a traceback or ran out of time; else 0.
"""

from __future__ import annotations

import argparse
import signal
import sys
import tempfile
import time
from collections import Counter, defaultdict
from concurrent.futures import ProcessPoolExecutor
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "tests" / "cga"))
import cga_programs  # noqa: E402

# CPU seconds for one program: counted on the process's CPU clock (SIGPROF), not the wall's, so
# that a loaded machine does not turn a slow program (seed 1698: 8 s) into a timeout
TIME_LIMIT = 60
FAILURES = ("refused", "round trip", "crash", "timeout")
ORDER = ("derives", "parses", "error", "known refusal", *FAILURES)


class _OutOfTime(BaseException):  # not an Exception: check() must not take it for a crash
    pass


def _out_of_time(signum, frame):
    raise _OutOfTime


def _one(seed: int, derive: bool = True) -> cga_programs.Outcome:
    signal.signal(signal.SIGPROF, _out_of_time)
    signal.setitimer(signal.ITIMER_PROF, TIME_LIMIT)
    try:
        with tempfile.TemporaryDirectory() as folder:
            program = cga_programs.generate(seed)
            return cga_programs.check(program, Path(folder), derive=derive)
    except _OutOfTime:
        return cga_programs.Outcome(seed, "timeout", f"no outcome within {TIME_LIMIT} CPU s")
    finally:
        signal.setitimer(signal.ITIMER_PROF, 0)


def _parsed(seed: int) -> cga_programs.Outcome:
    return _one(seed, derive=False)


def run(seeds, jobs: int = 2, progress: int = 0, derive: bool = True) -> list[cga_programs.Outcome]:
    """The outcome of every seed, in seed order; with ``progress``, a line on stderr every
    ``progress`` programs (the counts so far); without ``derive``, parsed and printed back
    only (outcome ``parses``)."""
    seeds = list(seeds)
    outcomes: list[cga_programs.Outcome] = []
    with ProcessPoolExecutor(max_workers=max(jobs, 1)) as pool:
        for outcome in pool.map(_one if derive else _parsed, seeds, chunksize=10):
            outcomes.append(outcome)
            if progress and outcome.stage in ("error", *FAILURES):
                print(f"seed {outcome.seed}: {outcome.stage}: {outcome.message}", file=sys.stderr)
            if progress and len(outcomes) % progress == 0:
                counts = Counter(o.stage for o in outcomes)
                print(f"{len(outcomes)} programs: {dict(counts)}", file=sys.stderr, flush=True)
    return outcomes


def print_summary(outcomes: list[cga_programs.Outcome], seed: int, seconds: float = 0.0) -> None:
    counts = Counter(outcome.stage for outcome in outcomes)
    print(
        f"generated programs: {len(outcomes)} from seed {seed}"
        + (f", {seconds:.0f} s" if seconds else "")
    )
    for stage in ORDER:
        print(f"  {stage:14} {counts.get(stage, 0)}")
    kinds: dict[tuple[str, str], list[cga_programs.Outcome]] = defaultdict(list)
    for outcome in outcomes:
        if outcome.stage not in ("derives", "parses"):
            kinds[(outcome.stage, outcome.kind)].append(outcome)
    for (stage, kind), found in sorted(
        kinds.items(), key=lambda item: (ORDER.index(item[0][0]), -len(item[1]))
    ):
        first = found[0]
        where = f" at {first.where}" if first.where else ""
        print(
            f"  {len(found):6}  {stage}: {kind}\n"
            f"          e.g. seed {first.seed}: {first.message}{where}"
        )


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--seed", type=int, default=0, help="first seed (default 0)")
    parser.add_argument("--count", type=int, default=10_000, help="programs (default 10 000)")
    parser.add_argument("--jobs", type=int, default=2, help="worker processes (default 2)")
    parser.add_argument(
        "--parse-only", action="store_true", help="parse and print back, do not derive"
    )
    parser.add_argument("--progress", type=int, default=500, help="counts every N programs")
    parser.add_argument("--show", type=int, help="print the files of this seed's program and stop")
    options = parser.parse_args(argv)
    if options.show is not None:
        for name, text in cga_programs.generate(options.show).files.items():
            print(f"// ---- {name}\n{text}")
        return 0
    started = time.perf_counter()
    seeds = range(options.seed, options.seed + options.count)
    outcomes = run(seeds, options.jobs, progress=options.progress, derive=not options.parse_only)
    print_summary(outcomes, options.seed, time.perf_counter() - started)
    return 1 if any(outcome.stage in FAILURES for outcome in outcomes) else 0


if __name__ == "__main__":
    sys.exit(main())

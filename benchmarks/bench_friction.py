"""Friction models compared: the cost of one analysis with the 4-sided pyramid and the exact cone.

For each model (running-bond walls of about 1 000 and 10 000 blocks, the bundled Cluny nave
and, with ``--rules``, any other bundled block rule) it prints, per friction model and back-end,
the wall and process CPU seconds of one ``analyze`` (interfaces found once, outside the timing),
the time spent solving, the verdict and ``y/W^2``, and then the exact cone's CPU time over the
4-sided pyramid's, both on the reduced interior point method. The configurations take turns
``--repeat`` times; the median and the least CPU time are printed, since the machine may be
shared. Verdicts that differ between the friction models are the point of the option, not an
error.

Run: ``.venv/bin/python benchmarks/bench_friction.py [--repeat 3] [--walls 1000 10000]
[--rules cluny wall_windows]``
"""

from __future__ import annotations

import argparse
import os
import statistics
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

import shapegen  # noqa: E402
from benchmarks.walls import running_bond_wall  # noqa: E402
from shapegen.statics import analyze, find_interfaces  # noqa: E402

CONFIGURATIONS = [
    ("4", "reduced"),  # the reduced interior point method, linear pyramid rows
    ("cone", "reduced"),  # the same, one second-order cone per vertex (the default)
    ("4", "clarabel"),
    ("cone", "clarabel"),
    ("8", "reduced"),
]


def models(walls: list[int], rules: list[str]):
    for blocks in walls:
        yield f"wall {blocks}", running_bond_wall(blocks)
    for name in rules:
        yield name, shapegen.load_grammar(f"{name}.grammar").build()


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=3)
    parser.add_argument("--walls", nargs="*", type=int, default=[1000, 10000])
    parser.add_argument("--rules", nargs="*", default=["cluny"])
    parser.add_argument("--skip-clarabel", action="store_true", help="the reduced back-end only")
    args = parser.parse_args()
    print(f"# load average before: {os.getloadavg()[0]:.1f}; median of {args.repeat}")
    for label, model in models(args.walls, args.rules):
        interfaces = find_interfaces(model)
        vertices = sum(len(i.vertices) for i in interfaces)
        print(
            f"{label}: {len(model.blocks)} blocks, {len(interfaces)} interfaces, "
            f"{vertices} vertices"
        )
        configurations = [
            (pyramid, solver)
            for pyramid, solver in CONFIGURATIONS
            if not (args.skip_clarabel and solver == "clarabel")
        ]
        runs = {configuration: [] for configuration in configurations}
        # the configurations take turns, so that a change of the machine's load hits them alike
        for _ in range(args.repeat):
            for pyramid, solver in configurations:
                wall, cpu = time.perf_counter(), time.process_time()
                result = analyze(
                    model, interfaces=interfaces, check=False, pyramid=pyramid, solver=solver
                )
                runs[pyramid, solver].append(
                    (time.perf_counter() - wall, time.process_time() - cpu, result)
                )
        cpu_of = {}
        for (pyramid, solver), measured in runs.items():
            walls = [run[0] for run in measured]
            cpus = [run[1] for run in measured]
            result = measured[-1][2]
            cpu_of[pyramid, solver] = (statistics.median(cpus), min(cpus))
            print(
                f"  pyramid {pyramid:4s} solver {solver:8s} -> {result.solver:8s} "
                f"wall {statistics.median(walls):6.2f} s, cpu {statistics.median(cpus):6.2f} s "
                f"(least {min(cpus):5.2f} s), {result.status.value}, "
                f"{result.timings['solve']:.2f} s solving, feasible={result.feasible} "
                f"y/W^2={result.infeasibility_normalized:.3e}",
                flush=True,
            )
        median, least = (cpu_of["cone", "reduced"][k] / cpu_of["4", "reduced"][k] for k in (0, 1))
        print(
            f"  cone / pyramid 4 (reduced), CPU: {median:.2f} (medians), {least:.2f} (least)",
            flush=True,
        )


if __name__ == "__main__":
    main()

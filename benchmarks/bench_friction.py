"""Friction models compared: the cost of one analysis with the 4-sided pyramid and the exact cone.

For each model (running-bond walls of about 1 000 and 10 000 blocks, the bundled Cluny nave
and, with ``--rules``, any other bundled block rule) it prints, per friction model and back-end,
the wall and process CPU seconds of one ``analyze`` (interfaces found once, outside the timing),
the solve's share, the iterations of the last solve, the verdict and ``y/W^2``, and then the
exact cone's CPU time over the 4-sided pyramid's, both on the reduced interior point method.
Each configuration runs ``--repeat`` times and the median is printed, since the machine may be
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
        cpu_of = {}
        for pyramid, solver in CONFIGURATIONS:
            if args.skip_clarabel and solver == "clarabel":
                continue
            walls, cpus, solves = [], [], []
            for _ in range(args.repeat):
                wall, cpu = time.perf_counter(), time.process_time()
                result = analyze(
                    model, interfaces=interfaces, check=False, pyramid=pyramid, solver=solver
                )
                walls.append(time.perf_counter() - wall)
                cpus.append(time.process_time() - cpu)
                solves.append(result.timings["solve"])
            cpu_of[pyramid, solver] = statistics.median(cpus)
            print(
                f"  pyramid {pyramid:4s} solver {solver:8s} -> {result.solver:8s} "
                f"total {statistics.median(walls):6.2f} s (cpu {statistics.median(cpus):6.2f} s, "
                f"solves {statistics.median(solves):6.2f} s, {result.status.value})  "
                f"feasible={result.feasible} y/W^2={result.infeasibility_normalized:.3e}",
                flush=True,
            )
        ratio = cpu_of["cone", "reduced"] / cpu_of["4", "reduced"]
        print(f"  cone / pyramid 4 (reduced), CPU: {ratio:.2f}", flush=True)


if __name__ == "__main__":
    main()

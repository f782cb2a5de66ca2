"""Simulation speed: simulated seconds per wall-clock second on a ~1 000-block model.

The model is the bundled Cluny nave after `--optimize` (so it stands), or, without
rules/cluny.grammar, a 1 000-block wall from the `wall` primitive. Run from the repository root:

    .venv/bin/python benchmarks/bench_simulation.py [--seconds 1.0] [--time-step 0.001]
        [--iterations 100]

Prints the block count, the wall and CPU time of the run (CPU time is the cost on a machine shared
with other work), the speed, and the verdict with its evidence.
"""

from __future__ import annotations

import argparse
import time
from pathlib import Path

from shapegen.model.model import Model
from shapegen.model.scope import Scope
from shapegen.primitives.wall import wall
from shapegen.simulation import SIMULATION_MARGIN, SimulationSettings, simulate

CLUNY = Path(__file__).resolve().parents[1] / "rules" / "cluny.grammar"


def cluny_model() -> tuple[str, Model]:
    from shapegen.engine.grammar_api import load_grammar
    from shapegen.search import optimize

    grammar = load_grammar(CLUNY)
    started = time.perf_counter()
    result = optimize(grammar, margin=SIMULATION_MARGIN)
    print(f"cluny --optimize: {time.perf_counter() - started:.1f} s, stands: {result.feasible}")
    return "cluny (optimized)", grammar.build(attrs=result.values)


def wall_model() -> tuple[str, Model]:
    # 40 blocks of 0.5 m per course, 25 courses of 0.25 m: 1 000 blocks (with half blocks more).
    scope = Scope.axis_aligned((0.0, 0.0, 0.0), (20.0, 6.25, 0.5))
    return "wall 20 x 6.25 x 0.5 m", Model(wall(scope, running_bond=False))


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seconds", type=float, default=1.0, help="simulated seconds")
    parser.add_argument("--time-step", type=float, default=SimulationSettings.time_step)
    parser.add_argument("--iterations", type=int, default=SimulationSettings.solver_iterations)
    parser.add_argument("--model", choices=["auto", "cluny", "wall"], default="auto")
    args = parser.parse_args()
    use_cluny = args.model == "cluny" or (args.model == "auto" and CLUNY.is_file())
    name, model = cluny_model() if use_cluny else wall_model()
    settings = SimulationSettings(
        seconds=args.seconds,
        settle=min(0.5, args.seconds / 2),
        time_step=args.time_step,
        solver_iterations=args.iterations,
    )
    cpu = time.process_time()
    result = simulate(model, settings)
    cpu = time.process_time() - cpu
    print(f"model: {name}, {len(model.blocks)} blocks")
    print(
        f"time step {settings.time_step:g} s, {settings.solver_iterations} solver iterations,"
        f" {result.steps} steps"
    )
    print(f"simulated {result.seconds:.3g} s in {result.wall_seconds:.1f} s wall, {cpu:.1f} s CPU")
    print(
        f"speed: {result.speed:.4f} simulated s per wall s,"
        f" {result.seconds / cpu:.4f} per CPU s; {1000 * cpu / result.steps:.1f} CPU ms per step"
    )
    print(f"verdict: {result.verdict} ({result.explanation()})")
    print(
        f"largest relative displacement {result.max_relative_displacement:.2%},"
        f" max displacement after settling {result.max_displacement * 1000:.3g} mm,"
        f" peak speed {result.peak_speed:.3g} m/s"
    )


if __name__ == "__main__":
    main()

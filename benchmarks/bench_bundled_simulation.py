"""Every bundled rule file, optimized as `shapegen simulate FILE --optimize` does, in the simulator.

For each block-model rule file (a grammar judged by another structure, such as the cable-model
bridge, is skipped) the search runs with the simulator's default safety margin
(``SIMULATION_MARGIN``), the design found is simulated with the default settings for ``--seconds``
(5), and one row is printed: blocks, search time, the largest displacement after settling, the
largest displacement relative to its block's smallest width (a block falls at 10 %), the peak
speed, blocks that fell or are still moving, verdict, and the CPU and wall time of the run (CPU
time is the cost on a machine shared with other work). This is the table of
docs/simulation.md, "Bundled rules after --optimize"; the test suite runs the same check for the
smaller files (tests/simulation/test_bundled_rules.py), this script also for the large ones (Cluny:
about four wall minutes). Run from the repository root:

    .venv/bin/python benchmarks/bench_bundled_simulation.py [--seconds 5] [--only cluny,mosque]
        [--margin 0.1]

``--margin 0`` searches as ``shapegen build --optimize --margin 0`` does (stopping on the statics
boundary).
"""

from __future__ import annotations

import argparse
import time

from shapegen.engine.grammar_api import load_grammar
from shapegen.engine.project.rules_path import bundled_rules, find_bundled_rule
from shapegen.search import optimize
from shapegen.simulation import SIMULATION_MARGIN, simulate


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seconds", type=float, default=5.0, help="simulated seconds")
    parser.add_argument("--only", default="", help="comma-separated file stems to run")
    parser.add_argument(
        "--margin", type=float, default=SIMULATION_MARGIN, help="the search's safety margin"
    )
    args = parser.parse_args()
    only = {name.strip() for name in args.only.split(",") if name.strip()}
    print(f"margin {args.margin:g}, {args.seconds:g} simulated s, default simulator settings")
    header = (
        f"{'file':18} {'blocks':>6} {'search s':>8} {'max mm':>7} {'max rel':>7} {'peak m/s':>8}"
        f" {'moved':>5} {'cpu s':>7} {'wall s':>7}"
    )
    print(f"{header}  verdict   (largest movers)")
    for name in bundled_rules():
        stem = name.removesuffix(".grammar")
        if only and stem not in only:
            continue
        grammar = load_grammar(find_bundled_rule(name))
        if grammar.structure != "blocks":  # judged by another structure, not as blocks
            continue
        started = time.perf_counter()
        optimization = optimize(grammar, margin=args.margin)
        searched = time.perf_counter() - started
        model = grammar.build(attrs=optimization.values)
        cpu = time.process_time()
        result = simulate(model, seconds=args.seconds)
        cpu = time.process_time() - cpu
        largest = ", ".join(
            f"{m.id} {m.relative_displacement:.2%}" for m in result.largest_movers(3)
        )
        print(
            f"{stem:18} {len(model.blocks):6d} {searched:8.1f}"
            f" {result.max_displacement * 1000:7.3f} {result.max_relative_displacement:7.2%}"
            f" {result.peak_speed:8.3g} {result.moved_blocks:5d}"
            f" {cpu:7.1f} {result.wall_seconds:7.1f}  {result.verdict:9} ({largest})"
            + ("" if optimization.feasible else "  [the search found no standing design]"),
            flush=True,
        )


if __name__ == "__main__":
    main()

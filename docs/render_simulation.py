"""Pictures of docs/simulation.md: the Cluny nave before and after a 4 m/s ground shake.

The seed paper's Figure 14: the optimized model stands in the simulator and collapses when the
ground is shaken (a lateral velocity change of 4 m/s over 1/60 s). Also an animation of a thin
arch (t/R = 0.08) collapsing under its own weight. Run from the repository root (the Cluny run
takes several minutes):

    .venv/bin/python docs/render_simulation.py [--seconds 3]
"""

from __future__ import annotations

import argparse
import json
from pathlib import Path

from shapegen.engine.grammar_api import load_grammar
from shapegen.export.atomic import atomic_write
from shapegen.search import optimize
from shapegen.simulation import SIMULATION_MARGIN, simulate
from shapegen.simulation.cases import arch
from shapegen.simulation.pictures import write_gif, write_picture

ROOT = Path(__file__).resolve().parents[1]
IMAGES = ROOT / "docs" / "images" / "simulation"
VIEW = {"elevation": 25.0, "azimuth": -50.0, "size_px": (900, 650)}


def cluny(seconds: float) -> None:
    grammar = load_grammar(ROOT / "rules" / "cluny.grammar")
    optimization = optimize(grammar, margin=SIMULATION_MARGIN)
    model = grammar.build(attrs=optimization.values)
    print(
        f"cluny: {len(model.blocks)} blocks, optimized, stands (statics): {optimization.feasible}"
    )
    result = simulate(model, seconds=seconds, shake=4.0)
    summary = {k: v for k, v in result.to_report().items() if k != "per_block"}
    print(json.dumps(summary, indent=1))
    with atomic_write(IMAGES / "cluny_shake_summary.json", "w") as handle:
        json.dump(summary, handle, indent=1)
    write_picture(result, IMAGES / "cluny_before.png", "start", **VIEW)
    write_picture(result, IMAGES / "cluny_after_shake.png", "final", **VIEW)


def thin_arch() -> None:
    result = simulate(arch(0.08), seconds=2.0, frame_rate=10)
    print(f"arch t/R 0.08: {result.verdict}")
    write_gif(result, IMAGES / "arch_0.08_collapse.gif", size_px=(480, 320))


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seconds", type=float, default=3.0, help="simulated seconds of Cluny")
    parser.add_argument("--skip-cluny", action="store_true")
    args = parser.parse_args()
    IMAGES.mkdir(parents=True, exist_ok=True)
    thin_arch()
    if not args.skip_cluny:
        cluny(args.seconds)


if __name__ == "__main__":
    main()

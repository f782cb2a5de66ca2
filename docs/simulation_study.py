"""Statics verdict against simulation verdict on assemblies around the feasibility boundary.

Builds 32 assemblies with known stability limits (semicircular arches of 40 voussoirs by
thickness and by friction, harmonic stacks, leaning towers), checks each with the statics
(`shapegen.statics.analyze`) and simulates each for 5 s twice:

- as before: a 1/1000 s step, 100 solver iterations, judged by the old fixed bar (a block moved
  when a vertex moved more than 1 mm after the 0.5 s settling window, or settled by more than
  1 cm), and by the new criterion on the same run;
- with the current defaults (1/2000 s, 50 iterations) and the current criterion: each block
  judged by its motion relative to its own smallest width (docs/simulation.md, "Verdict").

Prints the Markdown table of docs/simulation.md, the agreement rates, and the measurements the
criterion's thresholds were chosen from (the largest relative displacement of any block of a
standing model, the smallest of the blocks that fell). Run from the repository root (about ten
CPU minutes):

    .venv/bin/python docs/simulation_study.py
"""

from __future__ import annotations

import time

import numpy as np

from shapegen.simulation import SimulationSettings, simulate
from shapegen.simulation.cases import arch, harmonic_stack, leaning_tower
from shapegen.statics import analyze
from shapegen.tolerances import SIMULATION_FALL_REL

SECONDS = 5.0  # simulated; the first 0.5 s are the settling window
OLD = SimulationSettings(seconds=SECONDS, time_step=1.0 / 1000.0, solver_iterations=100)
NEW = SimulationSettings(seconds=SECONDS)
OLD_BAR, OLD_SETTLE_BAR = 1e-3, 1e-2  # metres: the fixed bar used before


def cases():
    """(family, parameter text, model) for every assembly of the study."""
    for ratio in (0.07, 0.08, 0.09, 0.10, 0.105, 0.11, 0.115, 0.12, 0.13, 0.15):
        yield "arch, 40 voussoirs, mu 0.895", f"t/R = {ratio:g}", arch(ratio)
    for friction in (0.2, 0.3, 0.4, 0.5):
        yield "arch, 40 voussoirs, t/R 0.15", f"mu = {friction:g}", arch(0.15, friction=friction)
    for factor in (0.8, 0.9, 0.95, 0.98, 1.02, 1.05, 1.1, 1.2):
        yield "harmonic stack of 6", f"{factor:g} x critical", harmonic_stack(factor)
    for factor in (0.97, 1.03):
        yield "harmonic stack of 4", f"{factor:g} x critical", harmonic_stack(factor, count=4)
    for factor in (0.8, 0.9, 0.95, 0.98, 1.02, 1.05, 1.1, 1.2):
        yield "leaning tower of 8", f"{factor:g} x critical lean", leaning_tower(factor)


def old_verdict(result) -> str:
    """The verdict by the fixed bar used before the relative criterion."""
    moved = any(
        m.max_displacement > OLD_BAR or m.settlement > OLD_SETTLE_BAR
        for m, block in zip(result.motions, result.model.blocks, strict=True)
        if not block.fixed
    )
    return "collapses" if moved else "stands"


def relative_displacements(result) -> np.ndarray:
    """Every non-fixed block's relative displacement at the end of ``result``."""
    return np.array(
        [
            m.relative_displacement
            for m, block in zip(result.motions, result.model.blocks, strict=True)
            if not block.fixed
        ]
    )


def _mark(verdict: str, statics: str) -> str:
    return verdict if verdict == statics else f"**{verdict}**"


def main() -> None:
    rows = []
    agree = {"old": 0, "criterion": 0, "new": 0}
    stood, fell = [], []  # per-block relative displacements of standing and collapsing runs
    started_cpu = time.process_time()
    for family, parameter, model in cases():
        analysis = analyze(model)
        statics = "stands" if analysis.feasible else "collapses"
        before = simulate(model, OLD)
        after = simulate(model, NEW)
        verdicts = {"old": old_verdict(before), "criterion": before.verdict, "new": after.verdict}
        for key, verdict in verdicts.items():
            agree[key] += verdict == statics
        for result in (before, after):
            (stood if result.stands else fell).append(relative_displacements(result))
        rows.append(
            f"| {family} | {parameter} | {statics} | {analysis.infeasibility_normalized:.2e}"
            f" | {_mark(verdicts['old'], statics)} | {before.max_displacement * 1000:.3g}"
            f" | {_mark(verdicts['criterion'], statics)}"
            f" | {_mark(verdicts['new'], statics)} | {after.max_relative_displacement:.3%}"
            f" | {after.peak_speed:.3g} | {after.final_speed:.2g} |"
        )
    print(
        "| assembly | parameter | statics | y/W² | old verdict (1 ms, 1 mm bar) | old run:"
        " max displacement after settling (mm) | old run, new criterion | new verdict"
        " (0.5 ms, new criterion) | largest relative displacement | peak speed (m/s)"
        " | final speed (m/s) |"
    )
    print("|---|---|---|---|---|---|---|---|---|---|---|")
    print("\n".join(rows))
    print()
    total = len(rows)
    print(
        "Agreement with the statics: "
        + ", ".join(
            f"{name} {count} of {total}"
            for name, count in (
                ("old", agree["old"]),
                ("old run with the new criterion", agree["criterion"]),
                ("new", agree["new"]),
            )
        )
        + f"; {SECONDS:g} s simulated each, {time.process_time() - started_cpu:.0f} CPU s in all."
    )
    stood_all = np.concatenate(stood) if stood else np.zeros(0)
    largest_fallen = [values.max() for values in fell]
    everything_fell = np.concatenate(fell) if fell else np.zeros(1)
    fallen_blocks = everything_fell[everything_fell > SIMULATION_FALL_REL]
    print(
        f"Standing runs: largest relative displacement of any block {stood_all.max():.2%}."
        f" Collapsed runs: the smallest largest relative displacement {min(largest_fallen):.0%};"
        f" of the blocks over the {SIMULATION_FALL_REL:.0%} bar, the least moved"
        f" {fallen_blocks.min():.0%}; blocks of collapsed runs between 2.5% and the bar:"
        f" {int(np.sum((everything_fell > 0.025) & (everything_fell <= SIMULATION_FALL_REL)))}."
    )


if __name__ == "__main__":
    main()

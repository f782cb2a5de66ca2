"""Statics verdict against simulation verdict on assemblies around the feasibility boundary.

Builds 32 assemblies with known stability limits (semicircular arches of 40 voussoirs by
thickness and by friction, harmonic stacks, leaning towers), checks each with the statics
(`shapegen.statics.analyze`) and with the rigid-body simulation (`shapegen.simulation.simulate`,
default settings, 3 s), and prints the Markdown table and the agreement rate used in
docs/simulation.md. Run from the repository root (about two minutes):

    .venv/bin/python docs/simulation_study.py
"""

from __future__ import annotations

import time

from shapegen.simulation import simulate
from shapegen.simulation.cases import arch, harmonic_stack, leaning_tower
from shapegen.statics import analyze

SECONDS = 3.0  # simulated; the first 0.5 s are the settling window


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


def main() -> None:
    rows, agreements = [], 0
    started = time.perf_counter()
    for family, parameter, model in cases():
        analysis = analyze(model)
        result = simulate(model, seconds=SECONDS)
        statics = "stands" if analysis.feasible else "collapses"
        agree = statics == result.verdict
        agreements += agree
        rows.append(
            f"| {family} | {parameter} | {statics} | {analysis.infeasibility_normalized:.2e}"
            f" | {result.verdict} | {result.max_displacement * 1000:.3g}"
            f" | {result.settlement * 1000:.3g} | {'yes' if agree else '**no**'} |"
        )
    print(
        "| assembly | parameter | statics | y/W² | simulation | max displacement after"
        " settling (mm) | settlement (mm) | agree |"
    )
    print("|---|---|---|---|---|---|---|---|")
    print("\n".join(rows))
    print()
    print(
        f"Agreement: {agreements} of {len(rows)} ({100 * agreements / len(rows):.0f}%);"
        f" {SECONDS:g} s simulated each, {time.perf_counter() - started:.0f} s in all."
    )


if __name__ == "__main__":
    main()

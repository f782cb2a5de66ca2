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
criterion's thresholds were chosen from: how far the blocks of standing models moved, in all
and over the last quarter of the run, and how little the most-moved block of a collapse moved,
each relative to the block's smallest width. Run from the repository root (about ten
CPU minutes):

    .venv/bin/python docs/simulation_study.py
"""

from __future__ import annotations

import time

from shapegen.simulation import SimulationSettings, simulate
from shapegen.simulation.cases import arch, harmonic_stack, leaning_tower
from shapegen.statics import analyze

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


def judged(result) -> list:
    """The motions of ``result``'s non-fixed blocks."""
    return [
        m for m, block in zip(result.motions, result.model.blocks, strict=True) if not block.fixed
    ]


def summary(label: str, runs: list) -> str:
    """The margins of the criterion on ``runs``, (case, result) pairs: how far the standing
    models stay from each bar and the collapses from the fall bar."""
    stood = [(case, result) for case, result in runs if result.stands]
    fell = [(case, result) for case, result in runs if not result.stands]
    lines = [f"{label}: {len(stood)} stand, {len(fell)} collapse."]
    if stood:
        case, result = max(stood, key=lambda run: run[1].max_relative_displacement)
        lines.append(
            f"  Standing: the largest block motion is {result.max_relative_displacement:.2%} of"
            f" its width ({case}); "
        )
        case, tail = max(
            ((c, max(m.tail_motion / m.width for m in judged(r))) for c, r in stood),
            key=lambda pair: pair[1],
        )
        lines[-1] += f"over the last quarter of the run at most {tail:.2%} ({case})."
    if fell:
        far = [(c, r) for c, r in fell if r.fallen_blocks]
        case, result = min(far, key=lambda run: run[1].max_relative_displacement)
        lines.append(
            f"  Collapsed: the least largest block motion of a collapse is"
            f" {result.max_relative_displacement:.0%} of its width ({case})."
        )
        only_moving = [c for c, r in fell if not r.fallen_blocks]
        if only_moving:
            lines.append(f"  Called collapsed only as still moving: {', '.join(only_moving)}.")
    return "\n".join(lines)


def _percent(ratio: float) -> str:
    return f"{100 * ratio:.2g} %" if ratio < 0.1 else f"{100 * ratio:.0f} %"


def _mark(verdict: str, statics: str) -> str:
    return verdict if verdict == statics else f"**{verdict}**"


def main() -> None:
    rows = []
    agree = {"old": 0, "criterion": 0, "new": 0}
    old_runs, new_runs = [], []
    started_cpu = time.process_time()
    for family, parameter, model in cases():
        analysis = analyze(model)
        statics = "stands" if analysis.feasible else "collapses"
        before = simulate(model, OLD)
        after = simulate(model, NEW)
        verdicts = {"old": old_verdict(before), "criterion": before.verdict, "new": after.verdict}
        for key, verdict in verdicts.items():
            agree[key] += verdict == statics
        old_runs.append((f"{family}, {parameter}", before))
        new_runs.append((f"{family}, {parameter}", after))
        rows.append(
            f"| {family} | {parameter} | {statics} | {analysis.infeasibility_normalized:.2e}"
            f" | {_mark(verdicts['old'], statics)} | {before.max_displacement * 1000:.3g}"
            f" | {_mark(verdicts['criterion'], statics)}"
            f" | {_mark(verdicts['new'], statics)} | {_percent(after.max_relative_displacement)}"
            f" | {after.peak_speed:.3g} | {after.final_speed:.2g} |"
        )
    print(
        "| assembly | parameter | statics | y/W² | old verdict (1 ms, 1 mm bar) | old run:"
        " max displacement after settling (mm) | old run, new criterion | new verdict"
        " (0.5 ms, new criterion) | largest block motion / its width | peak speed (m/s)"
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
    print()
    print(summary("Old run (1 ms, 100 iterations), new criterion", old_runs))
    print(summary("New run (0.5 ms, 50 iterations), new criterion", new_runs))


if __name__ == "__main__":
    main()

"""Every bundled rule file, after ``--optimize``, in the simulator (issue 8, part 2).

The files are discovered at test time; the suspension bridge (a cable model, not blocks) is
skipped, and so are models of more than ``LARGEST`` blocks (Cluny and Sainte-Chapelle: minutes
per simulated second, see benchmarks/bench_simulation.py; their measured results are in
docs/simulation.md). Models of up to ``SMALL`` blocks run for 5 s; larger ones
for 2 s (0.5 s settling + 1.5 s) to keep the suite within minutes.

The optimizer's "energy" objective stops at the first design that stands, i.e. on the statics
boundary, where the simulator's contact compliance can tip the design over (docs/simulation.md,
"Bundled rules after --optimize"). The rule files measured to collapse there are marked as
expected failures with what was measured; the others must stand.
"""

import pytest

from shapegen.engine.grammar_api import load_grammar
from shapegen.engine.rules_path import bundled_rules, find_bundled_rule
from shapegen.engine.search import optimize
from shapegen.simulation import simulate

SMALL = 100  # blocks
LARGEST = 500  # blocks
SKIP = {"suspension_bridge.grammar": "a cable model, not blocks"}
BOUNDARY_COLLAPSES = {
    "barrel_vault.grammar": "optimized onto the boundary (only `angle` is free): the flying"
    " buttresses give way after about 1.5 s; with --kern 0.8 no standing design is found",
    "bezier_arches.grammar": "optimized onto the boundary: the slender piers lean out by"
    " 0.7 degrees in 1.5 s; only the arch shapes are free, --kern 0.8 finds no standing design",
    "sainte_chapelle.grammar": "optimized onto the boundary: one block moves 1.0-1.2 mm (the"
    " tolerance is 1 mm) in the 1.5 s after settling",
    "wall_windows.grammar": "optimized onto the boundary: four blocks creep 0.7 mm in 1.5 s and"
    " 5.7 mm in 4.5 s after settling",
}


def _cases():
    for name in bundled_rules():
        marks = [pytest.mark.slow]
        if name in SKIP:
            marks.append(pytest.mark.skip(reason=SKIP[name]))
        elif name in BOUNDARY_COLLAPSES:
            # Not run: each costs a minute to confirm a measured collapse (docs/simulation.md).
            marks.append(pytest.mark.xfail(reason=BOUNDARY_COLLAPSES[name], run=False))
        yield pytest.param(name, marks=marks, id=name.removesuffix(".grammar"))


@pytest.mark.parametrize("name", list(_cases()))
def test_optimized_bundled_model_stands(name):
    grammar = load_grammar(find_bundled_rule(name))
    blocks = len(grammar.build().blocks)
    if blocks > LARGEST:
        pytest.skip(f"{blocks} blocks: too slow to simulate in the test suite")
    optimization = optimize(grammar)
    assert optimization.feasible, f"{name}: --optimize found no standing design"
    model = grammar.build(attrs=optimization.values)
    seconds = 5.0 if len(model.blocks) <= SMALL else 2.0
    result = simulate(model, seconds=seconds)
    moved = [m.id for m in result.motions if m.moved][:5]
    assert result.verdict == "stands", (
        f"{name}: {result.moved_blocks} blocks moved (first: {moved}),"
        f" max {result.max_displacement * 1000:.3g} mm after settling"
    )

"""Generated non-convex footprints that failed on their own cut: the slow generators of
footprints other than the lot files' own (thin slivers, corners nearly in line, scales from
1e-2 to 1e2, combs, far from the origin) found these; each is judged as a city lot is. A piece
taken as convex in its scope's frame lay out of convex in the world's (the cut's tolerance now
holds in any frame), and a sliver below the volume tolerance was kept as a block (now left
out)."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from shapegen.engine.grammar_api import parse_grammar
from shapegen.pipeline import design

# the footprints, each with what its cut did (door_footprints.json): (x, z) corners, m
FOOTPRINTS = json.loads((Path(__file__).parent / "door_footprints.json").read_text())


@pytest.mark.parametrize("name", ["scaled", "near_in_line", "star_in_line"])
def test_a_footprint_is_judged_on_its_own_cut(name):
    grammar = parse_grammar("Lot --> extrude(10)\n", "lot.cga")
    outcome = design(grammar, lot=FOOTPRINTS[name]["corners"], assess=True)
    assert outcome.assessment is not None and outcome.assessment.judged

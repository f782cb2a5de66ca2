"""alignScopeToGeometry's ties broken as CityEngine's runtime breaks them.

On a rectangle every edge is equally low, so ``world.lowest`` ties four ways; PyPRT (the
simpleRuleDataset package, which reports the scope's sizes after
``alignScopeToGeometry(yUp, 0, world.lowest)``, run on the 12 x 8 m lot started at each of its
corners) puts x along the lot's first edge: 12, 8, 12, 8 m. Between the two longest edges of an
L, ``longest`` takes the last (tests/engine/test_geometry_scope_ops.py).
"""

from __future__ import annotations

import pytest

import shapegen

RULE = """@StartRule
Lot --> alignScopeToGeometry(yUp, 0, world.lowest) report("sx", scope.sx) report("sz", scope.sz)
"""

CORNERS = [(0, 8), (12, 8), (12, 0), (0, 0)]  # counter-clockwise seen from +y


@pytest.mark.parametrize("start", range(4))
def test_world_lowest_takes_the_first_of_equally_low_edges(tmp_path, start):
    path = tmp_path / "align.cga"
    path.write_text(RULE)
    lot = CORNERS[start:] + CORNERS[:start]
    reports = shapegen.load_grammar(path).build(lot=lot).metadata["reports"]
    first_edge = abs(lot[1][0] - lot[0][0]) + abs(lot[1][1] - lot[0][1])
    assert reports["sx"] == pytest.approx(first_edge)  # PyPRT: 12, 8, 12, 8 m
    assert reports["sz"] == pytest.approx(20 - first_edge)

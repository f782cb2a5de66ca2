"""alignScopeToGeometry's ties broken as CityEngine's runtime breaks them.

On a rectangle every edge is equally low, so ``world.lowest`` ties four ways; PyPRT (the
simpleRuleDataset package, which reports the scope's sizes after
``alignScopeToGeometry(yUp, 0, world.lowest)``, run on the 12 x 8 m lot started at each of its
corners) puts x along the lot's first edge: 12, 8, 12, 8 m. Between the two longest edges of an
L, ``longest`` takes the last (tests/engine/test_geometry_scope_ops.py).
"""

from __future__ import annotations

from pathlib import Path

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


BUILDING = (
    Path(__file__).resolve().parents[1] / "data" / "cga-corpus"
    / "data_Building_From_FootprintSMALL__fc6ce924" / "rules" / "Building_From_FootprintSMALL.cga"
)  # fmt: skip
RECTANGLE = [(0.0, 20.0), (30.0, 20.0), (30.0, 0.0), (0.0, 0.0)]  # (x, z), as PyPRT was given it


@pytest.mark.skipif(not BUILDING.exists(), reason="the CGA corpus test data is missing")
@pytest.mark.parametrize(
    "start, xs",
    # PyPRT 1.12, seed 0, attrs below: the x of the model's vertices. The rule's
    # alignScopeToGeometry(yUp, 0, longest) ties between the two 30 m edges; its split(x) then
    # puts a 7.904 m wing at the scope's origin (and drops the 3.484 m one at its end)
    [(0, [0.0, 7.904, 26.516]), (1, [3.484, 22.096, 30.0]), (2, [3.484, 22.096, 30.0]),
     (3, [0.0, 7.904, 26.516])],
)  # fmt: skip
def test_longest_with_a_face_index_takes_the_first_of_equal_edges(start, xs):
    import shapegen.prt as prt

    corners = RECTANGLE[start:] + RECTANGLE[:start]
    attrs = {"seed": 0, "Building_Form": "setback top", "Roof_Form": "flat", "Eave_Ht": 20.0,
             "Ridge_Ht": 20.0, "Representation": "solid color"}  # fmt: skip
    shape = prt.InitialShape([c for x, z in corners for c in (x, 0.0, z)])
    (model,) = prt.ModelGenerator([shape]).generate_model([attrs], str(BUILDING))
    assert sorted({round(x, 3) + 0.0 for x in model.get_vertices()[0::3]}) == xs

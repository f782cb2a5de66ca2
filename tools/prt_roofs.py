"""Measure CityEngine's roofs on faces with holes with its runtime: writes
``tests/data/prt_roofs.json``.

As tools/prt_setback.py does, the corpus's ``FacesHolesVerticesrule`` package has its start rule
(``Footprint``) rewritten, here into one roof operation (``roofHip(30)``,
``roofRidge(@RoofValueType.byAngle, 30)``: numbers, ``true``/``false``, or ``@Class.FIELD`` for
a constant of the runtime's enum ``com.esri.gc.Class``) followed by reports of the roof's
``geometry.nVertices``, ``nFaces``, ``nHoles``, ``area``, ``volume`` and ``scope.sx`` ...
``scope.tz``, and optionally by a component split ``comp(f|e|h) { selector : Leaf | ... }``
(the selectors fields of ``com.esri.gc.Comp``) whose branches report their shapes'
``geometry.nFaces`` ... ``area`` under ``b<branch>.``: a branch's ``_n`` is the number of shapes
it gets. Without a split, the roof is the model, and its vertices and faces (the PyEncoder's
``points``, ``indices`` and ``encoder_faces``, a hole's ring after its face) are recorded. Run
with PyPRT's Python (a development tool; shapegen never imports it)::

    /tmp/prt-venv/bin/python tools/prt_roofs.py tests/data/prt_roofs.json
"""

from __future__ import annotations

import re
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
from prt_measure import (  # noqa: E402
    FOOTPRINT_PACKAGE,
    Rewriter,
    averages,
    branch_figures,
    cga_errors,
    encoder_figures,
    footprint_patcher,
    generated_model,
    java_strings,
    lot_from_rings,
    measuring_main,
)

GEOMETRY = ("nVertices", "nFaces", "nHoles", "area", "volume")
BRANCH_GEOMETRY = ("nFaces", "nHoles", "nVertices", "area")
SCOPE = ("sx", "sy", "sz", "tx", "ty", "tz")


LOTS = {
    # 12 x 8 m (first edge along +x at z = 8) with a 4 x 2 m courtyard from (4, 3) to (8, 5)
    "courtyard": lot_from_rings(
        [(0, 8), (12, 8), (12, 0), (0, 0)], [(4, 3), (8, 3), (8, 5), (4, 5)]
    ),
    # an L (tools/prt_geometry.py's L-shaped lot) with an L-shaped courtyard in its corner
    "L_courtyard": lot_from_rings(
        [(0, 0), (0, 12), (6, 12), (6, 5), (14, 5), (14, 0)],
        [(2, 2), (11, 2), (11, 3), (3, 3), (3, 10), (2, 10)],
    ),
    # 20 x 10 m with two square courtyards
    "two_holes": lot_from_rings(
        [(0, 10), (20, 10), (20, 0), (0, 0)],
        [(3, 3), (7, 3), (7, 7), (3, 7)],
        [(12, 4), (16, 4), (16, 6), (12, 6)],
    ),  # fmt: skip
    # 16 x 12 m with a small off-centre hole that touches nothing: no edge of the outline, and
    # not roofRidge's ridge line (z = 6)
    "small_hole": lot_from_rings(
        [(0, 12), (16, 12), (16, 0), (0, 0)], [(9, 3), (10, 3), (10, 4), (9, 4)]
    ),
    # the same lot with the hole's edge on roofRidge's ridge line
    "hole_on_ridge": lot_from_rings(
        [(0, 12), (16, 12), (16, 0), (0, 0)], [(9, 5), (10, 5), (10, 6), (9, 6)]
    ),
    # tools/prt_geometry.py's L-shaped lot, without a hole: roofRidge's sides and roofPyramid's
    # angle on a face without holes
    "L": lot_from_rings([(0, 0), (0, 12), (6, 12), (6, 5), (14, 5), (14, 0)]),
    # an L whose arms' edges are not parallel: two ridges at different heights, which an even
    # roof levels each on its own
    "skew_L": lot_from_rings([(0, 0), (0, 12), (5, 12), (6, 5), (14, 4), (14, 0)]),
    # op_roofHip's even example: a trapezoid, whose hip roof's ridge slopes
    "trapezoid": lot_from_rings([(0, 0), (0, 8), (12, 6), (12, 2)]),
}
ROOFS = [
    "roofHip(15)",
    "roofHip(60)",
    "roofGable(15)",
    "roofGable(60)",
    "roofRidge(@RoofValueType.byAngle,15)",
    "roofRidge(@RoofValueType.byAngle,60)",
    "roofRidge(@RoofValueType.byHeight,2)",
    "roofPyramid(30)",
    "roofShed(30)",
]
SPLITS = [
    "",
    "f|top:|bottom:|side:",
    "f|horizontal:|aslant:|vertical:",
    "e|eave:|hip:|valley:|ridge:",
    "h|all:",
]
# overhangs, even ridges, an index, heights: the roof alone
OPTIONS = [
    "roofHip(30,1)",
    "roofHip(30,-0.5)",
    "roofHip(30,0,true)",
    "roofGable(30,1,1)",
    "roofGable(30,1,0.5)",
    "roofGable(30,0,0,true)",
    "roofGable(30,0,0,false,1)",
    "roofHip(@RoofValueType.byHeight,2)",
    "roofGable(@RoofValueType.byHeight,2)",
    "roofShed(30,1)",
]
CASES = [(roof, split) for roof in ROOFS for split in SPLITS] + [(roof, "") for roof in OPTIONS]

# what the fixture's rows are, after its source line
ABOUT = (
    "each roof runs on the named initial shape (PyPRT's InitialShape with holes: (x, 0, z) "
    "coordinates) through PyPRT's PyEncoder; nVertices ... volume are geometry.* of the "
    "roof, scope is scope.sx, sy, sz, tx, ty, tz; with comp, b<k> is the k-th branch: the "
    "shapes it gets and the sums of their geometry.nFaces, nHoles, nVertices and area; "
    "without, points, indices and encoder_faces (vertex counts, a hole's ring after its "
    "face) are what the PyEncoder returns"
)

# The rewriter (tools/prt_measure.py's Footprint one; the case "roof|component|sel:merge|..."):
# Default$Footprint's code becomes the case's roof, reports of its geometry and scope, then a comp
# whose branches report their shape's geometry under "b<k>.".
PATCHER = footprint_patcher(
    2,
    java_strings("GEOMETRY", GEOMETRY)
    + java_strings("SCOPE", SCOPE)
    + r"""
    static void footprint(MethodVisitor mv) {
        call(mv, parts[0]);
        for (String what : GEOMETRY) report(mv, "geometry." + what, "geometry$" + what);
        for (String what : SCOPE) report(mv, "scope." + what, "scope$" + what);
        if (parts.length > FIRST) {
            mv.visitFieldInsn(Opcodes.GETSTATIC, "com/esri/gc/CompSelector", parts[1],
                              "Lcom/esri/gc/CompSelector;");
            splitTree(mv, "Comp");
            mv.visitMethodInsn(Opcodes.INVOKESTATIC, B, "comp",
                               "(Lcom/esri/gc/CompSelector;" + NODE + ")V", false);
        }
    }
""",
    BRANCH_GEOMETRY,
)


def written(roof: str) -> str:
    """The roof call as CGA writes it: ``roofRidge(byAngle, 15)``."""
    return re.sub(r"@\w+\.", "", roof).replace(",", ", ")


def measure(rewriter: Rewriter, lot: dict, case: tuple[str, str]) -> dict:
    roof, split = case
    spec = roof if not split else f"{roof}|{split.replace(':', ':1')}"
    model = generated_model(rewriter, spec, lot)
    report = model.get_report()
    row: dict = {"rule": written(roof), **averages(report, "geometry.", GEOMETRY)}
    row["scope"] = [round(report.get(f"scope.{k}_avg", float("nan")), 4) + 0.0 for k in SCOPE]
    if split:
        component, *selectors = split.split("|")
        row["comp"] = f"comp({component}) {{ {' | '.join(selectors)} }}"
        for k, _ in enumerate(selectors):
            row[f"b{k}"] = branch_figures(report, k, BRANCH_GEOMETRY)
    else:
        row.update(encoder_figures(model, 6))
    row["errors"] = cga_errors(model)
    return row


def main(argv: list[str] | None = None) -> int:
    rewriting = (FOOTPRINT_PACKAGE, PATCHER)
    return measuring_main(argv, __doc__, "prt_roofs", rewriting, LOTS, CASES, measure, ABOUT)


if __name__ == "__main__":
    sys.exit(main())

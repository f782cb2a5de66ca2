"""Measure CityEngine's trim() on faces with holes with its runtime: writes
``tests/data/prt_trim_holes.json``.

The start rule of the corpus's FacesHolesVerticesrule package (tools/prt_roofs.py's) is rewritten
into builtin calls, a ``comp`` with the runtime's own split tree, and in each branch more calls
and reports of the branch shape's ``geometry.nVertices``, ``nFaces``, ``nHoles``, ``area`` and
``volume`` under ``b<k>.``: a case is ``calls|component|selector:merge:calls|...``, the calls
``;``-separated (numbers, ``true``/``false`` or ``@Class.FIELD``, a constant of the runtime's
enum ``com.esri.gc.Class``; ``translate(@Mode.rel,@CoordSystem.world,x,y,z)`` is CGA's
``t(x, y, z)`` in world axes). Here the top of a 5 m extrusion (comp(f) gives it its trim
planes) is extruded 2 m, moved out of its planes or not, and trimmed. Run with PyPRT's Python
(a development tool; shapegen never imports it)::

    /tmp/prt-venv/bin/python tools/prt_trim_holes.py tests/data/prt_trim_holes.json \
        --corpus /work/shared/cga-corpus
"""

from __future__ import annotations

import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
from prt_measure import (  # noqa: E402
    FOOTPRINT_PACKAGE,
    Rewriter,
    branch_figures,
    cga_errors,
    encoder_figures,
    footprint_patcher,
    generated_model,
    measuring_main,
)
from prt_roofs import LOTS as ROOF_LOTS  # noqa: E402

GEOMETRY = ("nVertices", "nFaces", "nHoles", "area", "volume")
LOTS = {name: ROOF_LOTS[name] for name in ("courtyard", "L_courtyard", "two_holes", "L")}
MOVE = "translate(@Mode.rel,@CoordSystem.world,{})"
CASES = [
    "extrude(5)|f|top:1:extrude(2)",
    "extrude(5)|f|top:1:extrude(2);trim()",
    "extrude(5)|f|top:1:extrude(2);" + MOVE.format("3,0,0"),
    "extrude(5)|f|top:1:extrude(2);" + MOVE.format("3,0,0") + ";trim()",
    "extrude(5)|f|top:1:" + MOVE.format("3,0,0") + ";trim()",
    "extrude(5)|f|top:1:" + MOVE.format("1,0,1") + ";trim()",
]

# what the fixture's rows are, after its source line
ABOUT = (
    "each rule runs on the named initial shape (PyPRT's InitialShape with holes: (x, 0, z) "
    "coordinates) through PyPRT's PyEncoder; b<k> is the k-th branch of the comp: the "
    "shapes it gets and the sums of their geometry.* after its calls; points, indices and "
    "encoder_faces (vertex counts, a hole's ring after its face) are what the PyEncoder "
    "returns"
)

# The rewriter (tools/prt_measure.py's Footprint one; the case "calls|component|sel:merge:calls|
# ..."): Default$Footprint's code becomes the case's calls and its comp, each branch its calls
# and reports of its shape's geometry.* under "b<k>.".
PATCHER = footprint_patcher(
    2,
    r"""
    static void footprint(MethodVisitor mv) {
        calls(mv, parts[0]);
        mv.visitFieldInsn(Opcodes.GETSTATIC, "com/esri/gc/CompSelector", parts[1],
                          "Lcom/esri/gc/CompSelector;");
        splitTree(mv, "Comp");
        mv.visitMethodInsn(Opcodes.INVOKESTATIC, B, "comp",
                           "(Lcom/esri/gc/CompSelector;" + NODE + ")V", false);
    }
""",
    GEOMETRY,
)


def rule_text(case: str) -> str:
    """The case as CGA: ``extrude(5) comp(f) { top: extrude(2) t(3, 0, 0) trim() }``."""

    def written(calls: str) -> str:
        out = []
        for call in filter(None, calls.split(";")):
            call = call.replace("@Mode.", "").replace("@CoordSystem.", "")
            out.append(call.replace(",", ", "))
        return " ".join(out)

    before, component, *branches = case.split("|")
    parts = []
    for branch in branches:
        selector, merge, calls = branch.split(":", 2)
        parts.append(f"{selector} {':' if merge == '1' else '='} {written(calls)}".rstrip())
    return f"{written(before)} comp({component}) {{ {' | '.join(parts)} }}"


def measure(rewriter: Rewriter, lot: dict, case: str) -> dict:
    model = generated_model(rewriter, case, lot)
    report = model.get_report()
    row: dict = {"rule": rule_text(case)}
    for k in range(len(case.split("|")) - 2):
        row[f"b{k}"] = branch_figures(report, k, GEOMETRY)
    row.update(encoder_figures(model, 6))
    row["errors"] = cga_errors(model)
    return row


def main(argv: list[str] | None = None) -> int:
    rewriting = (FOOTPRINT_PACKAGE, PATCHER)
    return measuring_main(argv, __doc__, "prt_trim_holes", rewriting, LOTS, CASES, measure, ABOUT)


if __name__ == "__main__":
    sys.exit(main())

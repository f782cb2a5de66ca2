"""Measure CityEngine's component split of faces with holes with its runtime: writes
``tests/data/prt_comp_holes.json``.

As tools/prt_roofs.py does, the corpus's ``FacesHolesVerticesrule`` package has its start rule
(``Footprint``) rewritten: the case's operations (``extrude(10)``, or none), reports of the
shape's ``geometry.nVertices``, ``nFaces`` and ``nHoles``, then a component split
``comp(h|e|fe|v|fv|f [, noAlign]) { selector : ... | ... }`` (the selectors fields of
``com.esri.gc.Comp``; ``:`` or ``=``) whose branches report, per component, under
``b<branch>.<comp.index>.``, its ``geometry.nFaces``, ``nHoles``, ``nVertices``, ``area``, its
``scope.sx``, ``sy``, ``sz`` and, through ``convert(x|y|z, scope, world, pos, ...)``, the world
places of its scope's origin (``p0``) and of the ends of its unit x, y and z axes (``p1``,
``p2``, ``p3``): each component's scope (and pivot: op_comp aligns them) in CityEngine's index
order. The components stay as they are (a face's corners reach the encoder in their order): the
PyEncoder's ``points``, ``indices`` and ``encoder_faces`` are recorded too. Run with PyPRT's
Python (a development tool; shapegen never imports it)::

    PYTHONPATH=. /tmp/prt-venv/bin/python tools/prt_comp_holes.py tests/data/prt_comp_holes.json
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
    cga_errors,
    encoder_figures,
    footprint_patcher,
    generated_model,
    java_strings,
    lot_from_rings,
    measuring_main,
)

GEOMETRY = ("nVertices", "nFaces", "nHoles")

LOTS = {
    # tools/prt_roofs.py's: 12 x 8 m with a 4 x 2 m courtyard from (4, 3) to (8, 5)
    "courtyard": lot_from_rings(
        [(0, 8), (12, 8), (12, 0), (0, 0)], [(4, 3), (8, 3), (8, 5), (4, 5)]
    ),
    # 20 x 10 m with two courtyards, the second a triangle
    "two_holes": lot_from_rings(
        [(0, 10), (20, 10), (20, 0), (0, 0)],
        [(3, 3), (7, 3), (7, 7), (3, 7)],
        [(12, 4), (16, 4), (14, 7)],
    ),
    # PyPRT's own test shape (its pyGeometry_test): a 10 x 10 m square, a triangular hole
    # wound as the outline is
    "square_triangle": lot_from_rings(
        [(0, 0), (0, 10), (10, 10), (10, 0)], [(2, 2), (8, 8), (2, 8)]
    ),
    # no hole
    "square": lot_from_rings([(0, 10), (10, 10), (10, 0), (0, 0)]),
}
# (component, alignment, branches "selector:1" (':') or "selector:0" ('='))
SPLITS = [
    ("h", "", ["all:1"]),
    ("h", "", ["all:0"]),
    ("h", "noAlign", ["all:1"]),
    ("h", "", ["top:1", "bottom:1"]),
    ("h", "", ["border:1", "inside:1"]),
    ("e", "", ["all:1"]),
    ("e", "", ["border:1", "inside:1"]),
    ("e", "", ["eave:1", "hip:1", "valley:1", "ridge:1"]),
    ("fe", "", ["all:1"]),
    ("v", "", ["all:1"]),
    ("v", "", ["border:1", "inside:1"]),
    ("fv", "", ["all:1"]),
    ("f", "", ["all:1"]),
]
CASES = [(ops, *split) for ops in ("", "extrude(10)") for split in SPLITS]

# what the fixture's rows are, after its source line
ABOUT = (
    "each case's operations and component split run on the named initial shape (PyPRT's "
    "InitialShape with holes: (x, 0, z) coordinates) through PyPRT's PyEncoder; nVertices, "
    "nFaces, nHoles are geometry.* before the split; b<k> is the k-th branch: the shapes it "
    "gets and, per component by its comp.index, geometry.nFaces, nHoles, nVertices, area, "
    "scope.sx, sy, sz and the world places of its scope's origin (p0) and of the ends of "
    "its unit x, y, z axes (p1, p2, p3); points, indices and encoder_faces (vertex counts) "
    "are what the PyEncoder returns"
)

# The rewriter (tools/prt_measure.py's Footprint one; the case
# "op;op|component|alignment||sel:merge|..."): Default$Footprint's code becomes the case's
# operations, reports of the shape's geometry, then a comp whose branches report their shape's
# geometry, scope sizes and scope points under "b<k>.<comp.index>.".
PATCHER = footprint_patcher(
    4,
    java_strings("GEOMETRY", GEOMETRY)
    + r"""
    static final String[] BRANCH = {"geometry$nFaces", "geometry$nHoles", "geometry$nVertices",
                                    "geometry$area", "scope$sx", "scope$sy", "scope$sz"};
    static void key(MethodVisitor mv, String prefix, String name) {
        mv.visitLdcInsn(prefix);
        mv.visitMethodInsn(Opcodes.INVOKESTATIC, B, "comp$index", "()D", false);
        mv.visitMethodInsn(Opcodes.INVOKESTATIC, B, "_$add",
                           "(Ljava/lang/String;D)Ljava/lang/String;", false);
        mv.visitLdcInsn("." + name);
        mv.visitMethodInsn(Opcodes.INVOKESTATIC, B, "_$add",
                           "(Ljava/lang/String;Ljava/lang/String;)Ljava/lang/String;", false);
    }
    static void footprint(MethodVisitor mv) {
        calls(mv, parts[0]);
        for (String what : GEOMETRY) report(mv, "geometry." + what, "geometry$" + what);
        mv.visitFieldInsn(Opcodes.GETSTATIC, "com/esri/gc/CompSelector", parts[1],
                          "Lcom/esri/gc/CompSelector;");
        if (!parts[2].isEmpty()) {
            mv.visitFieldInsn(Opcodes.GETSTATIC, "com/esri/gc/ScopeAlignment", parts[2],
                              "Lcom/esri/gc/ScopeAlignment;");
        }
        splitTree(mv, "Comp");
        String align = parts[2].isEmpty() ? "" : "Lcom/esri/gc/ScopeAlignment;";
        mv.visitMethodInsn(Opcodes.INVOKESTATIC, B, "comp",
                           "(Lcom/esri/gc/CompSelector;" + align + NODE + ")V", false);
    }
    static void branch(MethodVisitor mv, int k, String[] branch) {
        String prefix = "b" + k + ".";
        for (String what : BRANCH) {
            key(mv, prefix, what.substring(what.indexOf('$') + 1));
            mv.visitMethodInsn(Opcodes.INVOKESTATIC, B, what, "()D", false);
            mv.visitMethodInsn(Opcodes.INVOKESTATIC, B, "report", "(Ljava/lang/String;D)V",
                               false);
        }
        for (int p = 0; p < 4; p++) {  // the scope's origin and axis ends, world
            for (String c : new String[] {"x", "y", "z"}) {
                key(mv, prefix, "p" + p + c);
                String coord = "Lcom/esri/gc/CoordSelector;";
                String system = "Lcom/esri/gc/CoordSystem;";
                String type = "Lcom/esri/gc/TypeSelector;";
                mv.visitFieldInsn(Opcodes.GETSTATIC, "com/esri/gc/CoordSelector", c, coord);
                mv.visitFieldInsn(Opcodes.GETSTATIC, "com/esri/gc/CoordSystem", "scope", system);
                mv.visitFieldInsn(Opcodes.GETSTATIC, "com/esri/gc/CoordSystem", "world", system);
                mv.visitFieldInsn(Opcodes.GETSTATIC, "com/esri/gc/TypeSelector", "pos", type);
                for (int axis = 1; axis < 4; axis++) {
                    mv.visitInsn(p == axis ? Opcodes.DCONST_1 : Opcodes.DCONST_0);
                }
                mv.visitMethodInsn(Opcodes.INVOKESTATIC, B, "convert",
                                   "(" + coord + system + system + type + "DDD)D", false);
                mv.visitMethodInsn(Opcodes.INVOKESTATIC, B, "report", "(Ljava/lang/String;D)V",
                                   false);
            }
        }
    }
""",
)


def comp_text(kind: str, align: str, branches: list[str]) -> str:
    """The split as CGA writes it: ``comp(e) { border : | inside : }``."""
    written = [f"{b.split(':')[0]} {':' if b.endswith(':1') else '='}" for b in branches]
    alignment = f", {align}" if align else ""
    return f"comp({kind}{alignment}) {{ {' | '.join(written)} }}"


def measure(rewriter: Rewriter, lot: dict, case) -> dict:
    operations, kind, align, branches = case
    spec = "|".join([operations.replace(" ", ""), kind, align, "", *branches])
    model = generated_model(rewriter, spec, lot)
    report = model.get_report()
    row: dict = {"rule": operations, "comp": comp_text(kind, align, branches)}
    row.update(averages(report, "geometry.", GEOMETRY))
    for k, _ in enumerate(branches):
        found: dict = {}
        shapes = 0  # each shape reports its nFaces once: two of one comp.index count twice
        for name, value in report.items():
            parts = re.fullmatch(rf"b{k}\.(\d+)(?:\.0+)?\.(\w+)_(avg|n)", name)
            if parts and parts[3] == "avg":
                found.setdefault(int(parts[1]), {})[parts[2]] = round(value, 6) + 0.0
            elif parts and parts[2] == "nFaces":
                shapes += int(value)
        row[f"b{k}"] = {
            "shapes": shapes,
            "components": [{"index": i, **found[i]} for i in sorted(found)],
        }
    row.update(encoder_figures(model, 6))
    row["errors"] = cga_errors(model)
    return row


def main(argv: list[str] | None = None) -> int:
    rewriting = (FOOTPRINT_PACKAGE, PATCHER)
    return measuring_main(argv, __doc__, "prt_comp_holes", rewriting, LOTS, CASES, measure, ABOUT)


if __name__ == "__main__":
    sys.exit(main())

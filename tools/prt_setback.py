"""Measure CityEngine's ``setback`` with its runtime: writes ``tests/data/prt_setback.json``.

As tools/prt_holes.py does, a corpus package's compiled rule is rewritten and generated through
PyPRT's PyEncoder on chosen initial shapes (with holes where a case says). Here the package is
``FacesHolesVerticesrule`` (one start rule, ``Footprint``, in the runtime's static form), whose
start rule becomes ``setback(distance) { selector : Branch0 | ... }``: the compiled split tree
(``_$createSplitRoot``, one ``_$createSplitNode`` per branch with the ``com.esri.gc.Setback``
selector and its ``:``/``=`` operator, each branch's operations a static method of the class
given by its Methodref's constant-pool index) and ``Builtins.setback``. Each branch's operations
report its shape's ``geometry.nFaces``, ``nHoles``, ``nVertices`` and ``area`` under
``b<branch>.``, so the report's ``_n`` counts the shapes a branch gets, ``_sum`` their totals.
A case may keep only some branches (a setback discards what no branch selects), so that the
encoder's vertices and faces are one branch's geometry. Run with PyPRT's Python (a development
tool; shapegen never imports it)::

    /tmp/prt-venv/bin/python tools/prt_setback.py tests/data/prt_setback.json
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
    lot_from_rings,
    measuring_main,
)

GEOMETRY = ("nFaces", "nHoles", "nVertices", "area")
MAX_POINTS = 40  # the encoder's vertices are kept for results with at most this many
LOTS = {
    # 12 x 8 m, first edge along +x at z = 8 (tools/prt_geometry.py's lot)
    "12x8": {"coordinates": [0, 0, 8, 12, 0, 8, 12, 0, 0, 0, 0, 0]},
    # tools/prt_geometry.py's L-shaped lot
    "L": {"coordinates": [0, 0, 0, 0, 0, 12, 6, 0, 12, 6, 0, 5, 14, 0, 5, 14, 0, 0]},
    # tools/prt_holes.py's courtyard: 12 x 8 m with a 4 x 2 m hole from (4, 3) to (8, 5)
    "courtyard": lot_from_rings(
        [(0, 8), (12, 8), (12, 0), (0, 0)], [(4, 3), (8, 3), (8, 5), (4, 5)]
    ),
}
# (distance, branches): a branch is "selector:" (each polygon a shape) or "selector=" (one
# shape for all), the selector a field of com.esri.gc.Setback (street.front is street$front)
CASES = [
    (3, "all: | remainder:"),
    (3, "all:"),
    (3, "remainder:"),
    (3, "all="),
    (2, "front: | remainder:"),
    (2, "front:"),
    (2, "side: | remainder:"),
    (2, "side:"),
    (2, "side="),
    (2, "front: | side: | remainder:"),
    (2, "back: | left:"),
    (5, "all: | remainder:"),
    (5, "all:"),
    (1, "all: | remainder:"),
    (1, "all:"),
    (1, "remainder:"),
    (1, "front: | remainder:"),
    (1, "side: | remainder:"),
    (2, "remainder: | all:"),
    (2, "left: | back:"),
    (2, "right: | front:"),
    (2, "side: | front: | remainder:"),
    (2, "front: | left: | back: | right: | remainder:"),
    (2, "back: | remainder:"),
    (2, "back="),
    (2, "front: | back: | remainder:"),
    ((1, 3, 2, 0.5), "all: | remainder:"),
    ((1, 3, 2, 0.5), "front: | side: | remainder:"),
    ((1, 3, 2, 0.5), "left: | back: | right: | front: | remainder:"),
    ((3, 0, 1, 2), "all: | remainder:"),
    ((2, 1, 1, 3, 2, 1), "all: | remainder:"),
    ((2, 1, 1, 3, 2, 1), "back: | right: | remainder:"),
]

# what the fixture's rows are, after its source line
ABOUT = (
    "each rule runs on the named initial shape through PyPRT's PyEncoder; b<k> is the k-th "
    "branch: the shapes it gets and the sums of their geometry.nFaces, nHoles, nVertices "
    "and area; encoder_vertices, encoder_faces (vertex counts, holes as their own rings "
    "after their face), points and indices what the PyEncoder returns"
)

# The rewriter (tools/prt_measure.py's Footprint one; the case "distance|selector:merge|...",
# several distances ","-separated): Default$Footprint's code becomes the setback of the case,
# whose branches report their shape's geometry.* under "b<k>.".
PATCHER = footprint_patcher(
    1,
    r"""
    static void footprint(MethodVisitor mv) {
        String[] distances = parts[0].split(",");
        String setback = "(D" + NODE + ")V";
        if (distances.length == 1) {
            mv.visitLdcInsn(Double.valueOf(parts[0]));
        } else {  // an array of distances, one per edge
            mv.visitLdcInsn(Integer.valueOf(distances.length));
            mv.visitIntInsn(Opcodes.NEWARRAY, Opcodes.T_DOUBLE);
            for (int i = 0; i < distances.length; i++) {
                mv.visitInsn(Opcodes.DUP);
                mv.visitLdcInsn(Integer.valueOf(i));
                mv.visitLdcInsn(Double.valueOf(distances[i]));
                mv.visitInsn(Opcodes.DASTORE);
            }
            mv.visitLdcInsn(Integer.valueOf(1));
            mv.visitMethodInsn(Opcodes.INVOKESTATIC, B, "_$createArray",
                               "([DI)Lcom/esri/gc/FloatArray;", false);
            setback = "(Lcom/esri/gc/FloatArray;" + NODE + ")V";
        }
        splitTree(mv, "Setback");
        mv.visitMethodInsn(Opcodes.INVOKESTATIC, B, "setback", setback, false);
    }
""",
    GEOMETRY,
)


def branches(text: str) -> list[tuple[str, str]]:
    """``"all: | remainder="`` as ``[("all", ":"), ("remainder", "=")]``."""
    out = []
    for part in text.split("|"):
        part = part.strip()
        out.append((part[:-1].strip().replace(".", "$"), part[-1]))
    return out


def measure(rewriter: Rewriter, lot: dict, case) -> dict:
    distance, text = case
    values = distance if isinstance(distance, (list, tuple)) else (distance,)
    spec = "|".join([",".join(str(float(v)) for v in values)] + [
        f"{name}:{1 if op == ':' else 0}" for name, op in branches(text)
    ])  # fmt: skip
    model = generated_model(rewriter, spec, lot)
    report = model.get_report()
    written = (
        f"[{', '.join(f'{v:g}' for v in values)}]" if isinstance(distance, (list, tuple))
        else f"{distance:g}"
    )  # fmt: skip
    row: dict = {"rule": f"setback({written}) {{ {text} }}"}
    for k in range(len(branches(text))):
        row[f"b{k}"] = branch_figures(report, k, GEOMETRY)
    row.update(encoder_figures(model, 4, MAX_POINTS, count=True))
    row["errors"] = cga_errors(model)
    return row


def main(argv: list[str] | None = None) -> int:
    rewriting = (FOOTPRINT_PACKAGE, PATCHER)
    return measuring_main(argv, __doc__, "prt_setback", rewriting, LOTS, CASES, measure, ABOUT)


if __name__ == "__main__":
    sys.exit(main())

"""Measure CityEngine's setbackToArea, shapeL, shapeU, shapeO and innerRectangle on faces with
holes with its runtime: writes ``tests/data/prt_setback_holes.json``.

As tools/prt_setback.py does for ``setback``, the start rule of the corpus's
FacesHolesVerticesrule package is rewritten into one operation with its compiled split tree
(``_$createSplitRoot``, one ``_$createSplitNode`` per branch with the operation's selector
enum: ``com.esri.gc.Setback`` for setbackToArea, ``ShapeLUO`` for shapeL/U/O,
``InnerRectangle`` for innerRectangle, as the corpus's compiled envelope2002 and
simpleRuleDataset rules call them) and the builtin (``Builtins.shapeL(DD...)``,
``innerRectangle(AlignmentMode, ...)``, ``setbackToArea(D...)``). Each branch reports its
shape's ``geometry.nFaces``, ``nHoles``, ``nVertices`` and ``area`` under ``b<branch>.``, and
the encoder's vertices and faces are kept. Run with PyPRT's Python (a development tool;
shapegen never imports it)::

    /tmp/prt-venv/bin/python tools/prt_setback_holes.py tests/data/prt_setback_holes.json \
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
    lot_from_rings,
    measuring_main,
)
from prt_setback import GEOMETRY, branches  # noqa: E402

MAX_POINTS = 64  # the encoder's vertices are kept for results with at most this many
LOTS = {
    # the 12 x 8 m lot without its courtyard, for what the same cases give without holes
    "12x8": {
        "coordinates": [0, 0, 8, 12, 0, 8, 12, 0, 0, 0, 0, 0],
        "indices": [0, 1, 2, 3],
        "face_counts": [4],
        "holes": [],
    },
    # tools/prt_holes.py's courtyard: 12 x 8 m with a 4 x 2 m hole from (4, 3) to (8, 5)
    "courtyard": lot_from_rings(
        [(0, 8), (12, 8), (12, 0), (0, 0)], [(4, 3), (8, 3), (8, 5), (4, 5)]
    ),
    # the courtyard with its first edge at the back (z = 0, along -x): which of two equal
    # rectangles innerRectangle takes
    "courtyard_back": lot_from_rings(
        [(12, 0), (0, 0), (0, 8), (12, 8)], [(4, 3), (8, 3), (8, 5), (4, 5)]
    ),
    # a perimeter block: 20 x 16 m, first edge along +x at z = 16, an 8 x 6 m courtyard from
    # (6, 5) to (14, 11)
    "block": lot_from_rings(
        [(0, 16), (20, 16), (20, 0), (0, 0)], [(6, 5), (14, 5), (14, 11), (6, 11)]
    ),
    # a yard off the block's middle, from (6, 4) to (14, 10): one largest rectangle (20 x 6 m
    # at the front)
    "yard": lot_from_rings(
        [(0, 16), (20, 16), (20, 0), (0, 0)], [(6, 4), (14, 4), (14, 10), (6, 10)]
    ),
    # a square yard turned 45 degrees (its diagonals 6 m) in the middle of the block
    "diamond": lot_from_rings(
        [(0, 16), (20, 16), (20, 0), (0, 0)], [(10, 5), (13, 8), (10, 11), (7, 8)]
    ),
}
# (operation, arguments, branches): arguments are numbers, or an AlignmentMode's name
CASES = [
    ("shapeL", (2, 3), "shape: | remainder:"),
    ("shapeL", (2, 3), "shape="),
    ("shapeL", (4, 5), "shape: | remainder:"),
    ("shapeL", (4, 5), "remainder:"),
    ("shapeU", (2, 2, 2), "shape: | remainder:"),
    ("shapeU", (4, 5, 5), "shape: | remainder:"),
    ("shapeU", (4, 5, 5), "shape="),
    ("shapeO", (2, 2, 2, 2), "shape: | remainder:"),
    ("shapeO", (2, 2, 2, 2), "shape:"),
    ("shapeO", (4, 5, 4, 5), "shape: | remainder:"),
    ("shapeO", (4, 5, 4, 5), "remainder="),
    ("shapeO", (1, 2, 3, 4), "shape: | remainder:"),
    ("setbackToArea", (40,), "all: | remainder:"),
    ("setbackToArea", (40,), "remainder:"),
    ("setbackToArea", (60,), "front: | remainder:"),
    ("setbackToArea", (100,), "all= | remainder="),
    ("setbackToArea", (150,), "side: | remainder:"),
    ("setbackToArea", (500,), "front: | remainder:"),
    ("innerRectangle", ("scope",), "shape: | remainder:"),
    ("innerRectangle", ("edge",), "shape: | remainder:"),
    ("innerRectangle", ("scope",), "shape="),
]
ENUMS = {"shapeL": "ShapeLUO", "shapeU": "ShapeLUO", "shapeO": "ShapeLUO",
         "setbackToArea": "Setback", "innerRectangle": "InnerRectangle"}  # fmt: skip

# what the fixture's rows are, after its source line
ABOUT = (
    "each rule runs on the named initial shape (with its holes) through PyPRT's PyEncoder; "
    "b<k> is the k-th branch: the shapes it gets and the sums of their geometry.nFaces, "
    "nHoles, nVertices and area; encoder_vertices, encoder_faces (vertex counts, holes as "
    "their own rings after their face), points and indices what the PyEncoder returns"
)

# The rewriter (tools/prt_measure.py's Footprint one; the case
# "operation|arguments|selector enum|selector:merge|...", the arguments ","-separated numbers or
# @AlignmentMode.NAME): Default$Footprint's code becomes the operation of the case, whose
# branches report their shape's geometry.* under "b<k>.".
PATCHER = footprint_patcher(
    3,
    r"""
    static void footprint(MethodVisitor mv) {
        String desc = "(" + push(mv, parts[1]) + NODE + ")V";
        splitTree(mv, parts[2]);
        mv.visitMethodInsn(Opcodes.INVOKESTATIC, B, parts[0], desc, false);
    }
""",
    GEOMETRY,
)


def rule_text(operation: str, arguments: tuple, text: str) -> str:
    """The case as CGA: ``shapeL(2, 3) { shape: | remainder: }``."""
    written = ", ".join(a if isinstance(a, str) else f"{a:g}" for a in arguments)
    return f"{operation}({written}) {{ {text} }}"


def measure(rewriter: Rewriter, lot: dict, case) -> dict:
    operation, arguments, text = case
    pushed = ",".join(
        f"@AlignmentMode.{a}" if isinstance(a, str) else str(float(a)) for a in arguments
    )
    spec = "|".join(
        [operation, pushed, ENUMS[operation]]
        + [f"{name}:{1 if op == ':' else 0}" for name, op in branches(text)]
    )
    model = generated_model(rewriter, spec, lot)
    report = model.get_report()
    row: dict = {"rule": rule_text(operation, arguments, text)}
    for k in range(len(branches(text))):
        row[f"b{k}"] = branch_figures(report, k, GEOMETRY)
    row.update(encoder_figures(model, 4, MAX_POINTS, count=True))
    row["errors"] = cga_errors(model)
    return row


def main(argv: list[str] | None = None) -> int:
    rewriting = (FOOTPRINT_PACKAGE, PATCHER)
    return measuring_main(
        argv, __doc__, "prt_setback_holes", rewriting, LOTS, CASES, measure, ABOUT
    )


if __name__ == "__main__":
    sys.exit(main())

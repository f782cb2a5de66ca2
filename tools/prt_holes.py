"""Measure CityEngine's faces with holes with its runtime: writes ``tests/data/prt_holes.json``.

As tools/prt_primitives.py does (whose rewriter this tool reuses), the corpus's
``extrusion_rule`` package has its call of ``extrude`` replaced by one case's operations, and
the case is generated through PyPRT's PyEncoder, here on initial shapes with a hole given as
PyPRT takes them (``InitialShape(coordinates, indices, face_counts, holes)``). Per case the JSON
gives the reports ``geometry.nVertices``, ``nFaces``, ``nHoles``, ``area``, ``volume`` and the
scope after the operations, and the vertex and face counts PyPRT's encoder returns. Run with
PyPRT's Python (a development tool; shapegen never imports it)::

    /tmp/prt/bin/python tools/prt_holes.py tests/data/prt_holes.json
"""

from __future__ import annotations

import re
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
from prt_measure import (  # noqa: E402
    Rewriter,
    averages,
    generated_model,
    lot_from_rings,
    measuring_main,
)
from prt_primitives import PACKAGE, PATCHER, SCOPE  # noqa: E402

GEOMETRY = ("nVertices", "nFaces", "nHoles", "area", "volume")
LOTS = {
    # PyPRT's own test shape: a 10 x 10 m square with a triangular hole (its pyGeometry_test)
    "square_triangle": lot_from_rings(
        [(0, 0), (0, 10), (10, 10), (10, 0)], [(2, 2), (8, 8), (2, 8)]
    ),
    # a courtyard lot: 12 x 8 m with a 4 x 2 m hole from (4, 3) to (8, 5)
    "courtyard": lot_from_rings(
        [(0, 8), (12, 8), (12, 0), (0, 0)], [(4, 3), (8, 3), (8, 5), (4, 5)]
    ),
}
CASES = [
    "",
    "extrude(10)",
    "extrude(-4)",
    "deleteHoles()",
    "extrude(10) deleteHoles()",
    "offset(-1)",
    "offset(1)",
    "roofHip(30)",
    "roofGable(30)",
    "roofPyramid(30)",
    "roofShed(30)",
]


# what the fixture's rows are, after its source line
ABOUT = (
    "each rule's operations run on the named initial shape (PyPRT's InitialShape with "
    "holes) through PyPRT's PyEncoder; nVertices ... volume are geometry.* reported after "
    "the operations, scope is scope.sx, sy, sz, tx, ty, tz, encoder_vertices and "
    "encoder_faces what the PyEncoder returns (its faces as vertex counts)"
)


def calls(operations: str) -> str:
    found = [c.replace(" ", "") for c in re.findall(r"\w+\([^)]*\)", operations)]
    found += [f"report:geometry${k}" for k in GEOMETRY]
    found += [f"report:scope${k}" for k in SCOPE]
    return ";".join(found)


def measure(rewriter: Rewriter, lot: dict, operations: str) -> dict:
    model = generated_model(rewriter, calls(operations), lot)
    report = model.get_report()
    row = {"rule": operations, **averages(report, "geometry$", GEOMETRY)}
    row["scope"] = [round(report[f"scope${k}_avg"], 4) + 0.0 for k in SCOPE]
    row["encoder_vertices"] = len(model.get_vertices()) // 3
    row["encoder_faces"] = list(model.get_faces())
    row["errors"] = list(model.get_cga_errors())
    return row


def main(argv: list[str] | None = None) -> int:
    rewriting = (PACKAGE, PATCHER)
    return measuring_main(argv, __doc__, "prt_holes", rewriting, LOTS, CASES, measure, ABOUT)


if __name__ == "__main__":
    sys.exit(main())

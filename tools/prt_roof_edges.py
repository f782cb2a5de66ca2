"""Measure CityEngine's roof-edge classes with its runtime: writes
``tests/data/prt_roof_edges.json``.

Each case runs operations on a lot (a roof, an extrusion, a taper, an envelope, a cube, a
scope turned by ``rotateScope``, or none) and splits the result with
``comp(e) { eave : | hip : | valley : | ridge : }``, through tools/prt_comp_holes.py's rewriter
(its branches report each edge's scope: its origin, the end of its unit x axis and its length);
the JSON keeps, per class, each edge's two ends in the direction the edge runs, and the same of
every edge (``comp(e) { all : }``) and every corner's place (``comp(v) { all : }``). The cases
bracket the rule shapegen.geometry.roof_edges states: shed roofs whose sloping sides are
within 10 degrees of level or not and whose slope is 80 degrees or steeper, tapers whose edges
are within 10 degrees of upright or not, the roofs on the lots of tools/prt_roofs.py. Run with
PyPRT's Python (a development tool; shapegen never imports it)::

    PYTHONPATH=. /tmp/prt-venv/bin/python tools/prt_roof_edges.py tests/data/prt_roof_edges.json
"""

from __future__ import annotations

import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
from prt_comp_holes import PATCHER, measure  # noqa: E402
from prt_measure import (  # noqa: E402
    FOOTPRINT_PACKAGE,
    Rewriter,
    arguments,
    fixture_written,
    lot_from_rings,
    measured_cases,
    rewritable_package,
)
from prt_roofs import LOTS as ROOF_LOTS  # noqa: E402

CLASSES = ("eave", "hip", "valley", "ridge")
LOTS = {
    # 10 x 10 m, first edge along +x at z = 10
    "square": lot_from_rings([(0, 10), (10, 10), (10, 0), (0, 0)]),
    # 12 x 8 m
    "rectangle": lot_from_rings([(0, 8), (12, 8), (12, 0), (0, 0)]),
    **{k: ROOF_LOTS[k] for k in ("courtyard", "L_courtyard", "L", "skew_L", "trapezoid")},
}
# (lot, operations separated by ';', numbers, true/false or @Class.FIELD as arguments)
CASES = [
    ("square", ""),
    ("square", "rotateScope(0,0,30)"),
    ("square", "extrude(10)"),
    ("square", "extrude(10);rotateScope(0,0,30)"),
    ("square", "primitiveCube()"),
    ("square", "taper(5)"),
    ("square", "taper(40)"),
    ("square", "taper(45)"),
    ("square", "roofShed(9.9)"),
    ("square", "roofShed(10)"),
    ("square", "roofShed(80)"),
    ("square", "roofShed(80.05)"),
    ("rectangle", "roofGable(30,1,1)"),
    ("rectangle", "roofShed(30,1)"),
    ("rectangle", "roofHip(30,1)"),
    ("trapezoid", "roofGable(30)"),
    ("trapezoid", "roofShed(30)"),
    ("trapezoid", "roofRidge(@RoofValueType.byAngle,30)"),
    ("trapezoid", "roofHip(30)"),
    ("trapezoid", "roofPyramid(30)"),
    ("courtyard", "extrude(10)"),
    ("courtyard", "roofShed(30)"),
    ("courtyard", "roofHip(30)"),
    ("courtyard", "roofRidge(@RoofValueType.byHeight,3)"),
    ("L", "roofGable(30)"),
    ("L", "roofPyramid(30)"),
    ("L", "taper(5)"),
    ("skew_L", "roofGable(45)"),
    ("skew_L", "roofRidge(@RoofValueType.byHeight,3)"),
    ("L_courtyard", "roofHip(40)"),
    ("L_courtyard", "roofShed(20)"),
    ("square", "envelope(@Direction.normal,10,3,45)"),
    ("courtyard", "envelope(@Direction.normal,10,3,45)"),
    ("L", "envelope(@Direction.normal,10,3,45,2,90)"),
]

# what the fixture's rows are, after its source line
ABOUT = (
    "each case's operations (';' between them) run on the named initial shape ((x, 0, z) "
    "coordinates), then comp(e) { eave : | hip : | valley : | ridge : }; per class, each "
    "edge's start and end (world, m) in comp.index order; all_edges the same of comp(e) "
    "{ all : }, all_corners each corner's place (world, m) of comp(v) { all : }"
)


def _edges(row: dict, branch: int) -> list[list[list[float]]]:
    """The branch's edges by comp.index, each as its start and end (the scope's origin, and
    the origin moved scope.sx along the scope's x)."""
    out = []
    for c in row[f"b{branch}"]["components"]:
        start = [c[f"p0{a}"] for a in "xyz"]
        x_end = [c[f"p1{a}"] for a in "xyz"]
        end = [round(o + c["sx"] * (e - o), 6) + 0.0 for o, e in zip(start, x_end, strict=True)]
        out.append([start, end])
    return out


def measure_edges(rewriter: Rewriter, lot: dict, operations: str):
    branches = [f"{name}:1" for name in CLASSES]
    row = measure(rewriter, lot, (operations, "e", "", branches))
    case = {"operations": operations}
    case.update({name: _edges(row, k) for k, name in enumerate(CLASSES)})
    case["errors"] = row["errors"]
    # every edge and every corner (comp(e) { all : }, comp(v) { all : }) in comp.index order:
    # a roof's sheets share no edge and no corner, so CityEngine lists one once for each
    case["all_edges"] = _edges(measure(rewriter, lot, (operations, "e", "", ["all:1"])), 0)
    corners = measure(rewriter, lot, (operations, "v", "", ["all:1"]))["b0"]["components"]
    case["all_corners"] = [[c[f"p0{a}"] for a in "xyz"] for c in corners]
    return case


def main(argv: list[str] | None = None) -> int:
    args = arguments(__doc__, argv)
    with rewritable_package(args.corpus, "prt_roof_edges", FOOTPRINT_PACKAGE, PATCHER) as rewriter:
        rows = []
        for name, operations in CASES:
            rows += measured_cases(
                "prt_roof_edges",
                {name: LOTS[name]},
                [operations],
                lambda lot, ops: measure_edges(rewriter, lot, ops),
            )
    return fixture_written("prt_roof_edges", args.output, ABOUT, {"lots": LOTS}, "cases", rows)


if __name__ == "__main__":
    sys.exit(main())

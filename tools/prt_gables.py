"""Measure which edges CityEngine's roofGable makes gables where the straight skeleton ties:
writes ``tests/data/prt_gables.json``.

A square's hip roof is a pyramid, so any opposite pair of its edges could be the gables; a
kite's, a rhombus's, a triangle's or a regular polygon's faces all meet at one apex too. Each
case runs one roofGable through tools/prt_roofs.py's rewriter on a lot: squares turned by 0,
30 and 45 degrees, from each corner, facing up and down (clockwise and counter-clockwise seen
from above), and turned by 17, 30 and 45 degrees with corners rounded to the mm and the cm;
near-squares (10 x 10.001 m) and rectangles from two corners; a kite, a rhombus, a 60-degree
rhombus, a hexagon with pointed ends, a square and a rectangle with a fifth corner on an edge,
the regular pentagon, hexagon and octagon; lots near a tie or without one (a square 1 mm out
of square, a parallelogram, trapezoids, a chamfered rectangle, triangles, L, T, U and plus
shapes), from two corners; and the index argument on some of them (every edge of convex lots
of 3 to 8 edges). Per case the JSON keeps the roof's figures, scope and the
PyEncoder's corners and faces, as tools/prt_roofs.py's rows. Run with PyPRT's Python (a
development tool; shapegen never imports it)::

    /tmp/prt-venv/bin/python tools/prt_gables.py tests/data/prt_gables.json
"""

from __future__ import annotations

import math
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
from prt_measure import (  # noqa: E402
    FOOTPRINT_PACKAGE,
    arguments,
    fixture_written,
    lot_from_rings,
    measured_cases,
    rewritable_package,
)
from prt_roofs import PATCHER, measure  # noqa: E402


def _outline(corners, turn=0.0, first: int = 0, up: bool = True, digits: int = 9) -> list:
    """(x, z) corners counter-clockwise in the (x, z) plane, turned by ``turn`` degrees about
    the origin and rounded to ``digits`` decimals, starting at corner ``first``; ``up``:
    reversed, so that the face looks up (+y) as a lot does, else down."""
    c, s = math.cos(math.radians(turn)), math.sin(math.radians(turn))
    ring = [(round(x * c - z * s, digits) + 0.0, round(x * s + z * c, digits) + 0.0)
            for x, z in corners]  # fmt: skip
    if up:
        ring = ring[::-1]
    return ring[first:] + ring[:first]


def _regular(n: int, radius: float = 5.0) -> list:
    return [
        (radius * math.cos(2 * math.pi * k / n), radius * math.sin(2 * math.pi * k / n))
        for k in range(n)
    ]


def _rectangle(a: float, b: float) -> list:
    return [(0, 0), (a, 0), (a, b), (0, b)]


SQUARE = _rectangle(10, 10)
KITE = [(-3, 0), (0, -4), (8, 0), (0, 4)]
RHOMBUS = [(-8, 0), (0, -4), (8, 0), (0, 4)]
RHOMBUS_60 = [(0, 0), (10, 0), (15, 8.660254037844386), (5, 8.660254037844386)]
POINTED = [(0, 0), (10, 0), (13, 5), (10, 10), (0, 10), (-3, 5)]  # a hexagon, pointed ends
SQUARE_5 = [(0, 0), (10, 0), (10, 10), (5, 10), (0, 10)]  # a fifth corner on an edge
RECTANGLE_5 = [(0, 0), (12, 0), (12, 8), (6, 8), (0, 8)]
# lots without a tie, or nearly one: the rule's other side
OTHERS = {
    "square_t17": _outline(SQUARE, 17),
    "near_square": [(0, 0), (10, 0), (10, 10), (0, 10.001)],  # one corner 1 mm out
    "skew_square": [(0, 0), (10, 0), (10.001, 10), (0.001, 10)],  # 1 mm out of square
    "parallelogram": [(0, 0), (12, 0), (16, 6.928203230275509), (4, 6.928203230275509)],
    "isosceles_trapezoid": [(0, 0), (12, 0), (9, 6), (3, 6)],
    "quadrilateral": [(0, 0), (11, 1), (12, 9), (-1, 7)],
    "chamfered": [(0, 0), (12, 0), (12, 6), (10, 8), (0, 8)],
    "triangle": [(0, 0), (10, 0), (5, 8)],
    "scalene_triangle": [(0, 0), (12, 0), (3, 7)],
    "kite_t30": _outline(KITE, 30),
    "rhombus_t30": _outline(RHOMBUS, 30),
    "L": [(0, 0), (14, 0), (14, 5), (6, 5), (6, 12), (0, 12)],
    "even_L": [(0, 0), (12, 0), (12, 4), (4, 4), (4, 12), (0, 12)],
    "T": [(0, 0), (12, 0), (12, 4), (8, 4), (8, 12), (4, 12), (4, 4), (0, 4)],
    "U": [(0, 0), (12, 0), (12, 10), (8, 10), (8, 4), (4, 4), (4, 10), (0, 10)],
    "plus": [(4, 0), (8, 0), (8, 4), (12, 4), (12, 8), (8, 8), (8, 12), (4, 12), (4, 8),
             (0, 8), (0, 4), (4, 4)],
}  # fmt: skip

LOTS: dict[str, dict] = {}
for turn in (0, 30, 45):
    for first in range(4):
        for up in (True, False):
            name = f"square_t{turn}_c{first}_{'up' if up else 'down'}"
            LOTS[name] = lot_from_rings(_outline(SQUARE, turn, first, up))
# turned squares with their corners rounded to the millimetre and the centimetre, as lots
# often are: their angles are no longer right
for turn in (17, 30, 45):
    for digits, unit in ((3, "mm"), (2, "cm")):
        for first in range(4):
            LOTS[f"square_t{turn}_{unit}_c{first}"] = lot_from_rings(
                _outline(SQUARE, turn, first, digits=digits)
            )
for a, b in ((10, 10.001), (10.001, 10), (12, 8), (8, 12)):
    for turn in (0, 30):
        for first in (0, 1):
            LOTS[f"rect_{a}x{b}_t{turn}_c{first}"] = lot_from_rings(
                _outline(_rectangle(a, b), turn, first)
            )
for name, corners, count in (
    ("kite", KITE, 4),
    ("rhombus", RHOMBUS, 4),
    ("rhombus60", RHOMBUS_60, 2),
    ("pointed", POINTED, 6),
    ("square5", SQUARE_5, 5),
    ("rectangle5", RECTANGLE_5, 2),
    ("pentagon", _regular(5), 5),
):
    for first in range(count):
        LOTS[f"{name}_c{first}"] = lot_from_rings(_outline(corners, 0, first))
for n, name in ((6, "hexagon"), (8, "octagon")):
    for turn in (0, 15):
        for first in range(3):
            LOTS[f"{name}_t{turn}_c{first}"] = lot_from_rings(_outline(_regular(n), turn, first))

for name, corners in OTHERS.items():
    ring = corners if name in ("square_t17", "kite_t30", "rhombus_t30") else _outline(corners)
    for first in (0, 1):
        LOTS[f"{name}_c{first}"] = lot_from_rings(ring[first:] + ring[:first])

ROOFS = ["roofGable(30)"]
# the index, overhangs and heights on some of the lots
OPTIONS = {
    "square_t0_c0_up": [
        "roofGable(30,0,0,false,0)",
        "roofGable(30,0,0,false,1)",
        "roofGable(30,0,0,false,2)",
        "roofGable(30,1,0.5)",
        "roofGable(@RoofValueType.byHeight,2)",
    ],
    "square_t30_c1_down": ["roofGable(30,1,0.5)", "roofGable(30,0,0,true)"],
    "square_t0_c1_up": [f"roofGable(30,0,0,false,{k})" for k in range(3)],
    "square_t30_c0_up": [f"roofGable(30,0,0,false,{k})" for k in range(3)],
    "rect_12x8_t0_c0": [f"roofGable(30,0,0,false,{k})" for k in range(3)],
    "kite_c0": ["roofGable(30,0,0,false,0)", "roofGable(30,0,0,false,1)"],
    "hexagon_t0_c0": [f"roofGable(30,0,0,false,{k})" for k in range(3)],
    "octagon_t0_c0": [f"roofGable(30,0,0,false,{k})" for k in range(3)],
    # the index on convex lots of 4 to 8 edges, each edge and one past the last
    "scalene_triangle_c0": [f"roofGable(30,0,0,false,{k})" for k in range(3)],
    "isosceles_trapezoid_c0": [f"roofGable(30,0,0,false,{k})" for k in range(4)],
    "quadrilateral_c0": [f"roofGable(30,0,0,false,{k})" for k in range(4)],
    "parallelogram_c0": [f"roofGable(30,0,0,false,{k})" for k in range(4)],
    "chamfered_c0": [f"roofGable(30,0,0,false,{k})" for k in range(6)],
    "pentagon_c0": [f"roofGable(30,0,0,false,{k})" for k in range(6)],
    "pointed_c0": [f"roofGable(30,0,0,false,{k})" for k in range(6)],
    "hexagon_t15_c0": [f"roofGable(30,0,0,false,{k})" for k in range(6)],
    "octagon_t15_c0": [f"roofGable(30,0,0,false,{k})" for k in range(8)],
}


ABOUT = (
    "each roof runs on the named initial shape ((x, 0, z) coordinates, one face) through "
    "PyPRT's PyEncoder; nVertices ... volume are geometry.* of the roof, scope is scope.sx, "
    "sy, sz, tx, ty, tz, points, indices and encoder_faces (vertex counts: the bottom, then "
    "one face per edge in edge order) what the PyEncoder returns"
)


def main(argv: list[str] | None = None) -> int:
    args = arguments(__doc__, argv)
    with rewritable_package(args.corpus, "prt_gables", FOOTPRINT_PACKAGE, PATCHER) as rewriter:
        rows = []
        for name, lot in LOTS.items():
            rows += measured_cases(
                "prt_gables",
                {name: lot},
                ROOFS + OPTIONS.get(name, []),
                lambda lot, roof: measure(rewriter, lot, (roof, "")),
            )
    return fixture_written("prt_gables", args.output, ABOUT, {"lots": LOTS}, "cases", rows)


if __name__ == "__main__":
    sys.exit(main())

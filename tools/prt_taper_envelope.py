"""Measure CityEngine's taper, envelope and trim on faces with holes with its runtime: writes
``tests/data/prt_taper_envelope.json``.

tools/prt_roofs.py's rewriter (the start rule of the corpus's FacesHolesVerticesrule package
made into one call of a runtime builtin, then reports of ``geometry.nVertices``, ``nFaces``,
``nHoles``, ``area``, ``volume`` and the scope, and the PyEncoder's vertices and faces) runs
``taper(height)``, ``envelope(direction, maxHeight, ...)`` (``com.esri.gc.Direction``'s
``normal`` or ``world$up``) and ``trim()`` on five of tools/prt_roofs.py's lots and on two
lots whose hole meets a crease of the envelope. Run with PyPRT's Python (a development tool;
shapegen never imports it)::

    /tmp/prt-venv/bin/python tools/prt_taper_envelope.py tests/data/prt_taper_envelope.json \
        --corpus /work/shared/cga-corpus
"""

from __future__ import annotations

import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
from prt_measure import FOOTPRINT_PACKAGE, lot_from_rings, measuring_main  # noqa: E402
from prt_roofs import LOTS as ROOF_LOTS  # noqa: E402
from prt_roofs import PATCHER, measure  # noqa: E402

LOTS = {
    **{
        name: ROOF_LOTS[name]
        for name in ("courtyard", "L_courtyard", "two_holes", "small_hole", "L")
    },
    # 20 x 10 m with a hole whose back edge lies on the ridge (z = 5) of a front and back slope
    "ridge_hole": lot_from_rings(
        [(0, 10), (20, 10), (20, 0), (0, 0)], [(3, 3), (7, 3), (7, 5), (3, 5)]
    ),
    # 20 x 10 m with a hole whose edge (z = 3) lies on a part of the flat top's edge when every
    # side slopes at 45 degrees up to 3 m
    "top_partial": lot_from_rings(
        [(0, 10), (20, 10), (20, 0), (0, 0)], [(1, 1), (8, 1), (8, 3), (1, 3)]
    ),
}
CASES = [
    "taper(5)",
    "taper(-2)",
    "envelope(@Direction.normal,10,3,45)",
    "envelope(@Direction.normal,6,0,30)",
    "envelope(@Direction.normal,20,4,60)",
    "envelope(@Direction.normal,2,3,45)",
    "envelope(@Direction.normal,10,3,45,2,90)",
    "envelope(@Direction.normal,10,3,45,3,60,3,30)",
    "envelope(@Direction.world$up,10,3,45)",
    "trim()",
    "envelope(@Direction.normal,20,0,45,0,45)",
    "envelope(@Direction.normal,3,0,45,0,45,0,45)",
]


# what the fixture's rows are, after its source line
ABOUT = (
    "each operation runs on the named initial shape (PyPRT's InitialShape with holes: "
    "(x, 0, z) coordinates) through PyPRT's PyEncoder; nVertices ... volume are geometry.* "
    "after it, scope is scope.sx, sy, sz, tx, ty, tz; points, indices and encoder_faces "
    "(vertex counts, a hole's ring after its face) are what the PyEncoder returns"
)


def main(argv: list[str] | None = None) -> int:
    return measuring_main(
        argv,
        __doc__,
        "prt_taper_envelope",
        (FOOTPRINT_PACKAGE, PATCHER),
        LOTS,
        CASES,
        lambda rewriter, lot, case: measure(rewriter, lot, (case, "")),  # the roof alone
        ABOUT,
    )


if __name__ == "__main__":
    sys.exit(main())

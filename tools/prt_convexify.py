"""Measure CityEngine's ``convexify`` with its runtime (``tests/geometry/prt_convexify.json``).

As tools/prt_primitives.py does, this takes the corpus's ``extrusion_rule`` package and rewrites
its compiled rule so that ``BuildingCreation`` calls ``convexify()`` (or ``convexify(maxLength)``)
instead of ``extrude``; each lot of ``LOTS`` (a polygon in the ground plane, y up) is then
generated through PyPRT's PyEncoder and the faces PyPRT gives are recorded as the parts.

It runs with PyPRT's Python (a development tool; shapegen never imports it) and needs
``javac``/``java``, the ASM bytecode library (Debian's ``libasm-java``) and ``7z``::

    /tmp/prt-venv/bin/python tools/prt_convexify.py tests/geometry/prt_convexify.json
    /tmp/prt-venv/bin/python tools/prt_convexify.py out.json --corpus /work/shared/cga-corpus

(``--corpus`` from a worktree: the default is ``shared/cga-corpus`` beside the checkout.)
"""

from __future__ import annotations

import math
import random
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
from prt_measure import (  # noqa: E402
    Rewriter,
    arguments,
    fixture_written,
    generated_model,
    rewritable_package,
)
from prt_primitives import PACKAGE, PATCHER  # noqa: E402

# (name, outline as (x, z) corners, maxLength or None)
LOTS = [
    ("L", [(0, 0), (10, 0), (10, 4), (4, 4), (4, 10), (0, 10)], None),
    ("L mirrored", [(0, 0), (10, 0), (10, 10), (6, 10), (6, 4), (0, 4)], None),
    ("U", [(0, 0), (12, 0), (12, 10), (8, 10), (8, 4), (4, 4), (4, 10), (0, 10)], None),
    ("T", [(4, 0), (8, 0), (8, 6), (12, 6), (12, 10), (0, 10), (0, 6), (4, 6)], None),
    (
        "H",
        [
            (0, 0),
            (3, 0),
            (3, 4),
            (7, 4),
            (7, 0),
            (10, 0),
            (10, 10),
            (7, 10),
            (7, 6),
            (3, 6),
            (3, 10),
            (0, 10),
        ],
        None,
    ),  # fmt: skip
    (
        "plus",
        [
            (4, 0),
            (8, 0),
            (8, 4),
            (12, 4),
            (12, 8),
            (8, 8),
            (8, 12),
            (4, 12),
            (4, 8),
            (0, 8),
            (0, 4),
            (4, 4),
        ],
        None,
    ),  # fmt: skip
    ("step", [(0, 0), (10, 0), (10, 3), (7, 3), (7, 6), (4, 6), (4, 9), (0, 9)], None),
    ("chevron", [(0, 0), (5, 3), (10, 0), (5, 10)], None),
    ("notch", [(0, 0), (4, 0), (5, 2), (6, 0), (10, 0), (10, 6), (0, 6)], None),
    ("slanted L", [(0, 0), (10, 1), (9, 5), (4, 4), (3, 10), (-1, 9)], None),
    ("star", [(0, 0), (5, 2), (10, 0), (8, 5), (10, 10), (5, 8), (0, 10), (2, 5)], None),
    ("arrow", [(0, 3), (6, 3), (6, 0), (10, 5), (6, 10), (6, 7), (0, 7)], None),
    (
        "comb",
        [
            (0, 0),
            (10, 0),
            (10, 8),
            (8, 8),
            (8, 3),
            (6, 3),
            (6, 8),
            (4, 8),
            (4, 3),
            (2, 3),
            (2, 8),
            (0, 8),
        ],
        None,
    ),  # fmt: skip
    ("L maxLength 3", [(0, 0), (10, 0), (10, 4), (4, 4), (4, 10), (0, 10)], 3.0),
    ("L maxLength 5", [(0, 0), (10, 0), (10, 4), (4, 4), (4, 10), (0, 10)], 5.0),
    ("L maxLength 7", [(0, 0), (10, 0), (10, 4), (4, 4), (4, 10), (0, 10)], 7.0),
    ("U maxLength 5", [(0, 0), (12, 0), (12, 10), (8, 10), (8, 4), (4, 4), (4, 10), (0, 10)], 5.0),
    ("T maxLength 5", [(4, 0), (8, 0), (8, 6), (12, 6), (12, 10), (0, 10), (0, 6), (4, 6)], 5.0),
    ("chevron maxLength 5", [(0, 0), (5, 3), (10, 0), (5, 10)], 5.0),
    ("chevron maxLength 8", [(0, 0), (5, 3), (10, 0), (5, 10)], 8.0),
    ("convex", [(0, 0), (10, 0), (12, 6), (0, 8)], None),
]


def star_outline(seed: int, corners: int) -> list:
    """A star-shaped outline: ``corners`` corners at even angles about the origin, distances
    drawn from 3 to 10 m (a seeded generator, so the lots are the same on every run)."""
    generator = random.Random(seed)
    outline = []
    for k in range(corners):
        angle = 2 * math.pi * k / corners
        radius = generator.uniform(3.0, 10.0)
        outline.append((round(radius * math.cos(angle), 3), round(radius * math.sin(angle), 3)))
    return outline


LOTS += [(f"star-shaped {seed}", star_outline(seed, 6 + seed % 7), None) for seed in range(12)]
LOTS += [(f"star-shaped {seed} maxLength 4", star_outline(seed, 9), 4.0) for seed in range(12, 16)]


# a dent in a 10 m edge turning by ``turn`` degrees: is it cut?
def dent_outline(turn: float) -> list:
    """A 10 x 6 m rectangle whose top edge bends in at its middle by ``turn`` degrees."""
    depth = 5 * math.tan(math.radians(turn / 2))
    return [(0, 0), (10, 0), (10, 6), (5, 6 - depth), (0, 6)]


LOTS += [(f"dent of {turn} degrees", dent_outline(turn), None) for turn in (0.5, 0.9, 1.1, 1.5)]
# a solid: does a cut's new vertex go into the neighbouring side face too?
SOLIDS = [("L extruded", LOTS[0][1], "extrude(5)")]


def lot_vertices(outline: list) -> list:
    """The outline as PyPRT's initial shape: (x, 0, z) corners, the face's normal up (+y)."""
    points = [[float(x), 0.0, float(z)] for x, z in outline]
    twice = sum(
        x0 * z1 - x1 * z0
        for (x0, z0), (x1, z1) in zip(outline, outline[1:] + outline[:1], strict=True)
    )
    # seen from +y with x right, z points down the page: counter-clockwise in (x, z) is down
    return points if twice < 0 else points[::-1]


def measure(rewriter: Rewriter, name, outline, limit, before=None) -> dict:
    call = "convexify()" if limit is None else f"convexify({float(limit)})"
    if before:
        call = f"{before};{call}"
    lot = {"coordinates": [c for p in lot_vertices(outline) for c in p]}
    model = generated_model(rewriter, call, lot, report=False)
    flat = list(model.get_vertices())
    points = [flat[i : i + 3] for i in range(0, len(flat), 3)]
    indices = list(model.get_indices())
    parts, start = [], 0
    for count in model.get_faces():
        face = indices[start : start + count]
        start += count
        axes = (0, 1, 2) if before else (0, 2)
        parts.append([[round(points[i][a], 4) + 0.0 for a in axes] for i in face])
    row = {"name": name, "outline": [list(map(float, p)) for p in outline], "max_length": limit}
    if before:
        row["before"] = before  # the parts' corners are (x, y, z)
    return {**row, "parts": parts}


def main(argv: list[str] | None = None) -> int:
    args = arguments(__doc__, argv)
    with rewritable_package(args.corpus, "prt_convexify", PACKAGE, PATCHER) as rewriter:
        rows = [measure(rewriter, *lot) for lot in LOTS]
        rows += [measure(rewriter, name, outline, None, before) for name, outline, before in SOLIDS]
    about = (
        "the corpus's extrusion_rule package with BuildingCreation's extrude replaced by "
        "convexify() or convexify(max_length) (the compiled rule rewritten with ASM), each "
        "outline generated as one initial shape in the ground plane (x, 0, z), normal up, "
        "through PyPRT's PyEncoder; parts are the faces PyPRT gives, their corners as (x, z) "
        "in PyPRT's order, rounded to 0.1 mm; a row with before ran those operations first and "
        "gives its parts' corners as (x, y, z)"
    )
    return fixture_written("prt_convexify", args.output, about, {}, "lots", rows)


if __name__ == "__main__":
    sys.exit(main())

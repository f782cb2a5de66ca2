"""``column``: a square or round pier in horizontal courses."""

from __future__ import annotations

__all__ = ["column"]

import numpy as np

from shapegen.model.block import Block
from shapegen.model.scope import Scope
from shapegen.primitives.prism import prism_blocks
from shapegen.primitives.registry import (
    Choice,
    primitive,
    require,
    require_blocks,
    require_vertices,
)


@primitive("column", scope_relative=True)
def column(
    scope: Scope,
    *,
    shape: Choice("square", "round") = "square",
    sides: int = 16,
    courses: int = 1,
    course_height: float = 0.0,
) -> list[Block]:
    """A column standing on the scope's bottom face and reaching its top, in courses.

    Parameters
    ----------
    shape
        "square": the section fills the scope's footprint (sx by sz). "round": a regular polygon
        with ``sides`` sides inscribed in the circle of diameter ``min(sx, sz)``, centred on the
        footprint, with a side facing +z (and, when ``sides`` is a multiple of 4, one facing
        each of -z, +x and -x).
    sides
        Number of sides of a round column (at least 3).
    courses
        Number of courses (drums), used when ``course_height`` is 0.
    course_height
        Nominal course height, m; when positive it replaces ``courses`` by the whole number of
        courses nearest to ``scope height / course_height`` (at least one), so that they fill
        the height exactly.
    """
    name = "column"
    width, height, depth = scope.sx, scope.sy, scope.sz
    require(min(width, height, depth) > 0, name, "scope",
            f"needs a positive size, got {scope.size_text}")  # fmt: skip
    require(courses >= 1, name, "courses", f"must be at least 1, got {courses}")
    require(course_height >= 0, name, "course_height",
            f"must be positive (or 0 to use 'courses'), got {course_height:g} m")  # fmt: skip
    require(shape != "round" or sides >= 3, name, "sides",
            f"must be at least 3 for a round column, got {sides}")  # fmt: skip
    if course_height > 0:
        require_blocks(name, height / course_height + 0.5, "scope height / course_height")
        courses = max(1, round(height / course_height))
    require_blocks(name, courses, "courses")
    require_vertices(name, (courses + 1) * (sides if shape == "round" else 4), "sides x courses")
    if shape == "square":
        # Counter-clockwise about +y: seen from above, x to the right and z towards the viewer.
        section = np.array([[0.0, 0.0], [0.0, depth], [width, depth], [width, 0.0]])
    else:
        radius = min(width, depth) / 2.0
        # A rotation about +y by phi takes x to (cos phi, -sin phi) in (x, z): counter-clockwise.
        phi = -np.pi / 2 + np.pi / sides + 2 * np.pi * np.arange(sides) / sides
        section = np.column_stack(
            [width / 2 + radius * np.cos(phi), depth / 2 - radius * np.sin(phi)]
        )
    k = len(section)
    levels = height * np.arange(courses + 1) / courses
    pool = np.zeros(((courses + 1) * k, 3))
    pool[:, 0] = np.tile(section[:, 0], courses + 1)
    pool[:, 1] = np.repeat(levels, k)
    pool[:, 2] = np.tile(section[:, 1], courses + 1)
    rings = [
        (list(range(c * k, (c + 1) * k)), list(range((c + 1) * k, (c + 2) * k)))
        for c in range(courses)
    ]
    return prism_blocks(scope, pool, rings, tags=("column",))

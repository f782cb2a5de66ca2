"""CityEngine's general context queries ``contextCount``, ``contextCompare`` and
``minimumDistance`` (cga_context, func_contextCount, func_contextCompare, func_minimumDistance).

They ask about *labelled shapes*: every ``label("x")`` of the first derivation pass "creates a
labeled copy of the current shape" (cga_context, "Labels"), recorded by
:meth:`~shapegen.engine.derivation.occlusion.Occlusion.label`.
As for the occlusion queries, the first
pass answers the reference's defaults (``contextCount`` 0, ``contextCompare`` 0,
``minimumDistance`` infinity) and the second pass answers from the first pass's labelled shapes.

* ``intra`` looks at the shapes of the same initial shape, ``inter`` at those of other initial
  shapes and ``all`` at both; shapegen derives one lot at a time, so ``inter`` finds none and
  answers the "no shape found" value (0, 0, infinity).
* An empty label answers the same (the reference: "If the label is empty, 0 [infinity] is
  returned").
* ``contextCompare`` ranks the current shape's geometry among the labelled shapes' geometries:
  its rank is the number of labelled shapes strictly ahead of it (0-based; ties take the lowest
  rank). ``world.*`` compares world bounds (north is -z, east +x, up +y), ``area.*`` the
  geometry's surface area.
* ``minimumDistance`` is the least distance (m) between the current scope and a labelled shape's
  scope, two oriented boxes (0 when they meet), found as a bounded least-squares problem.
"""

from __future__ import annotations

__all__ = ["COMPARISONS", "CONTEXT_QUERIES", "context_query"]

import math

import numpy as np

from shapegen.errors import GrammarError
from shapegen.tolerances import COINCIDENT_M

_TARGETS = ("intra", "inter", "all")

#: comparisonType -> the geometry's value; the larger value ranks first
COMPARISONS = {
    "world.northernmost": lambda mesh: -mesh.bounds()[0][2],
    "world.southernmost": lambda mesh: mesh.bounds()[1][2],
    "world.easternmost": lambda mesh: mesh.bounds()[1][0],
    "world.westernmost": lambda mesh: -mesh.bounds()[0][0],
    "world.highest": lambda mesh: mesh.bounds()[1][1],
    "world.lowest": lambda mesh: -mesh.bounds()[0][1],
    "area.largest": lambda mesh: mesh.area(),
    "area.smallest": lambda mesh: -mesh.area(),
}

#: query name -> (its default, the number of arguments)
CONTEXT_QUERIES = {
    "contextCount": (0.0, 2),
    "contextCompare": (0.0, 3),
    "minimumDistance": (math.inf, 2),
}


def context_query(name: str, state, target: str, label: object, comparison: str = "") -> float:
    """The value of the query ``name`` for the shape of ``state``."""
    if target not in _TARGETS:
        raise GrammarError(f"{name}()'s target is intra, inter or all, got {target!r}")
    if not isinstance(label, str):
        raise GrammarError(f"{name}()'s label is a string, got {label!r}")
    default = CONTEXT_QUERIES[name][0]
    occlusion = getattr(state.run, "occlusion", None)
    if occlusion is None:
        raise GrammarError(f"{name}() needs a derivation that runs it in two passes")
    if occlusion.occluders is None:  # first pass: the reference's default
        occlusion.asked = True
        return default
    if target == "inter" or not label:
        return default  # one initial shape per derivation: no other shape trees
    shapes = [shape for text, _path, shape in occlusion.labelled if text == label]
    if not shapes:
        return default
    if name == "contextCount":
        return float(len(shapes))
    if name == "contextCompare":
        value = COMPARISONS[comparison]
        own = value(state.shape.world_mesh())
        return float(sum(1 for shape in shapes if value(shape.world_mesh()) > own + COINCIDENT_M))
    return min(_box_distance(state.shape.scope, shape.scope) for shape in shapes)


def _box_distance(first, second) -> float:
    """Least distance (m) between two scopes: points ``o + R u`` with ``0 <= u <= size``."""
    from scipy.optimize import lsq_linear  # loaded on first use: it costs the CLI's start-up

    matrix = np.hstack([first.rotation, -second.rotation])
    target = second.origin - first.origin
    upper = np.concatenate([first.size, second.size])
    free = upper > 0  # a flat scope (a face's sz = 0) has no extent along that axis
    if not free.any():
        return float(np.linalg.norm(target))
    result = lsq_linear(matrix[:, free], target, bounds=(0.0, upper[free]), method="bvls")
    return float(np.linalg.norm(matrix[:, free] @ result.x - target))

"""Small hand-built statics problems with known answers (interfaces built by hand, so these tests
do not depend on the contact search)."""

from __future__ import annotations

import math

import numpy as np

from shapegen.model import Block, Model
from shapegen.statics.interface import Interface, tangent_frame


def polygon_interface(first: int, second: int, normal, corners) -> Interface:
    """An interface with the given corners, sorted counter-clockwise about ``normal``."""
    normal = np.asarray(normal, float)
    normal = normal / np.linalg.norm(normal)
    corners = np.asarray(corners, float)
    t1, t2 = tangent_frame(normal)
    centre = corners.mean(axis=0)
    angles = np.arctan2((corners - centre) @ t2, (corners - centre) @ t1)
    return Interface(first, second, normal, t1, t2, corners[np.argsort(angles)])


def horizontal_interface(first: int, second: int, height, x, z, up: bool) -> Interface:
    """A rectangle ``x[0]..x[1]`` by ``z[0]..z[1]`` at y = ``height``; the normal is +y when
    ``up`` (``first`` below ``second``) and -y otherwise."""
    corners = [(x[i], height, z[j]) for i in (0, 1) for j in (0, 1)]
    return polygon_interface(first, second, (0, 1 if up else -1, 0), corners)


def running_bond_wall(
    courses=8, per_course=6, brick=(0.24, 0.07, 0.115), tilt_degrees=0.0, friction=None
) -> Model:
    """Courses of whole bricks alternating with courses offset by half a brick, on the ground;
    gravity tilted along +x by ``tilt_degrees``; ``friction`` None: the model's default."""
    length, height, depth = brick
    blocks = []
    for course in range(courses):
        edges = np.arange(per_course + 1) * length
        if course % 2:
            edges = np.concatenate([[0.0], edges[:-1] + 0.5 * length, [edges[-1]]])
        for x0, x1 in zip(edges[:-1], edges[1:], strict=True):
            y0 = course * height
            blocks.append(Block.box((x0, y0, 0.0), (x1, y0 + height, depth)))
    tilt = math.radians(tilt_degrees)
    settings = {"friction": friction} if friction is not None else {}
    gravity = 9.81 * np.array([math.sin(tilt), -math.cos(tilt), 0.0])
    return Model(blocks=blocks, ground=0.0, gravity=gravity, **settings)


def assert_solved_within(backend: str, problem, violations, limits) -> None:
    """``backend`` solves ``problem`` to OPTIMAL and each optimality-condition violation
    ``violations(problem, solution)`` returns (primal, dual, complementarity) is below its
    limit."""
    from shapegen.statics.solvers import SolveStatus, get_backend

    solution = get_backend(backend).solve(problem)
    assert solution.status is SolveStatus.OPTIMAL
    found = violations(problem, solution)
    assert all(v < limit for v, limit in zip(found, limits, strict=True)), (found, limits)

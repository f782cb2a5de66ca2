"""Block models for benchmarks: running-bond brick walls of a chosen size."""

from __future__ import annotations

__all__ = ["running_bond_wall"]

import math

import numpy as np

from shapegen.model.block import Block
from shapegen.model.model import Model

BRICK = (0.24, 0.07, 0.115)  # length, height, depth in metres (a common brick)


def running_bond_wall(n_blocks: int, brick: tuple[float, float, float] = BRICK) -> Model:
    """A free-standing running-bond wall of about ``n_blocks`` bricks on the ground plane y = 0.

    Courses alternate between ``m`` whole bricks and ``m + 1`` pieces (two half bricks at the
    ends), so each course is offset by half a brick from the one below. The wall is about
    twice as long as it is high; it stands in the xy plane with its depth along z.

    Parameters
    ----------
    n_blocks
        Target number of blocks; the result has between ``n_blocks`` and a course more.
    brick
        Brick length, height and depth, metres.
    """
    length, height, depth = brick
    # courses * m ~= n and m * length ~= 2 * courses * height
    per_course = max(2, round(math.sqrt(2.0 * n_blocks * height / length)))
    courses = max(1, math.ceil(n_blocks / (per_course + 0.5)))
    blocks = []
    for course in range(courses):
        y0, y1 = course * height, (course + 1) * height
        if course % 2 == 0:
            edges = np.arange(per_course + 1) * length
        else:
            inner = (np.arange(per_course) + 0.5) * length
            edges = np.concatenate([[0.0], inner, [per_course * length]])
        for x0, x1 in zip(edges[:-1], edges[1:], strict=True):
            blocks.append(Block.box((x0, y0, 0.0), (x1, y1, depth), id=f"c{course}x{len(blocks)}"))
    return Model(blocks=blocks, ground=0.0)

"""``wall``: courses of rectangular blocks filling the scope, optionally in running bond."""

from __future__ import annotations

__all__ = ["wall"]

import numpy as np

from shapegen.model.block import Block
from shapegen.model.scope import Scope
from shapegen.primitives.prism import prism_blocks
from shapegen.primitives.registry import primitive, require, require_blocks


@primitive("wall", scope_relative=True)
def wall(
    scope: Scope,
    *,
    block_length: float = 0.5,
    block_height: float = 0.25,
    running_bond: bool = True,
) -> list[Block]:
    """A wall of courses filling the scope (x = length, y = height, z = thickness).

    Parameters
    ----------
    block_length
        Nominal block length, m. The wall holds a whole number of blocks per course (at least
        one), so the actual length is the scope length divided by the nearest whole count.
    block_height
        Nominal course height, m; adjusted the same way to fill the scope height.
    running_bond
        Offset every second course (the second, fourth...) by half a block, with half blocks at
        both ends of those courses, so that vertical joints do not line up.

    Every block spans the full thickness. Blocks of neighbouring courses share their bed planes
    exactly, and blocks of one course their head joints.
    """
    name = "wall"
    length, height, thickness = scope.sx, scope.sy, scope.sz
    require(min(length, height, thickness) > 0, name, "scope",
            f"needs a positive size, got {scope.size_text}")  # fmt: skip
    require(block_length > 0, name, "block_length", f"must be positive, got {block_length:g} m")
    require(block_height > 0, name, "block_height", f"must be positive, got {block_height:g} m")
    # Counted as floats first: a tiny block size gives a huge (or infinite) count, not an overflow.
    require_blocks(
        name,
        max(1.0, length / block_length + 0.5) * max(1.0, height / block_height + 0.5) * 1.5,
        "blocks per course x courses, half blocks included",
    )
    per_course = max(1, round(length / block_length))
    courses = max(1, round(height / block_height))
    # All head joints lie on a grid of half blocks; every corner is taken from one pool of points.
    xs = length * np.arange(2 * per_course + 1) / (2 * per_course)
    ys = height * np.arange(courses + 1) / courses
    zs = np.array([0.0, thickness])
    grid = np.stack(np.meshgrid(xs, ys, zs, indexing="ij"), axis=-1).reshape(-1, 3)
    shape = (len(xs), len(ys), 2)

    def corner(ix: int, iy: int, iz: int) -> int:
        return int(np.ravel_multi_index((ix, iy, iz), shape))

    rings = []
    for course in range(courses):
        if running_bond and course % 2 == 1:
            joints = [0, *range(1, 2 * per_course, 2), 2 * per_course]
        else:
            joints = list(range(0, 2 * per_course + 1, 2))
        for left, right in zip(joints[:-1], joints[1:], strict=True):
            face = [(left, course), (right, course), (right, course + 1), (left, course + 1)]
            rings.append(
                ([corner(ix, iy, 0) for ix, iy in face], [corner(ix, iy, 1) for ix, iy in face])
            )
    return prism_blocks(scope, grid, rings, tags=("wall",))

"""``box``: a single block filling the scope."""

from __future__ import annotations

import numpy as np

from shapegen.model.block import Block
from shapegen.model.scope import Scope
from shapegen.primitives.registry import primitive, require

_UNIT_CUBE = np.array(
    [[0, 0, 0], [1, 0, 0], [1, 0, 1], [0, 0, 1], [0, 1, 0], [1, 1, 0], [1, 1, 1], [0, 1, 1]],
    dtype=float,
)


@primitive("box", scope_relative=True)
def box(scope: Scope) -> list[Block]:
    """One block filling the scope."""
    require(bool(np.all(scope.size > 0)), "box", "scope",
            f"needs a positive size on every axis, got {scope.size_text}")  # fmt: skip
    template = Block.box([0, 0, 0], [1, 1, 1])
    return [Block(scope.to_world(_UNIT_CUBE * scope.size), template.faces)]

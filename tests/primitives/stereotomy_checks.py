"""Checks shared by the vault, dome and buttress tests (independent of the primitives' code)."""

from __future__ import annotations

__all__ = ["ROTATED", "assert_convex", "interface_counts", "local_bounds"]

import numpy as np
from rotations import about_y
from scipy.spatial import ConvexHull

from shapegen.model.model import Model
from shapegen.model.scope import Scope
from shapegen.statics.interface import GROUND

# A scope turned about the vertical and moved off the origin, to catch local/world mix-ups.
ROTATED = Scope(np.array([3.0, 0.0, -2.0]), about_y(35.0), np.array([4.0, 5.0, 3.0]))


def assert_convex(blocks) -> None:
    """Each block's volume equals its vertices' convex hull volume, and no vertex lies outside a
    face plane: the block is a convex polyhedron with outward faces."""
    for block in blocks:
        hull = ConvexHull(block.vertices).volume
        assert block.volume > 0
        assert block.volume == np.float64(hull) or abs(block.volume - hull) <= 1e-9 * hull
        outside = block.vertices @ block.face_normals.T - block.face_offsets
        assert outside.max() <= 1e-9 * np.ptp(block.vertices, axis=0).max()


def interface_counts(blocks, ground: float | None = 0.0) -> tuple[int, int]:
    """(internal, ground) contact counts found by the statics' contact detection."""
    from shapegen.statics.contacts import find_interfaces

    interfaces = find_interfaces(Model(list(blocks), ground=ground))
    on_ground = sum(1 for i in interfaces if i.second == GROUND)
    return len(interfaces) - on_ground, on_ground


def local_bounds(blocks, scope: Scope) -> np.ndarray:
    """(2, 3) bounding box of all blocks in the scope's coordinates, metres."""
    local = scope.to_local(np.concatenate([b.vertices for b in blocks]))
    return np.array([local.min(axis=0), local.max(axis=0)])

"""Prismatic blocks on a shared pool of points.

Walls, columns and arches are made of prisms: a convex polygon swept along a straight direction.
Neighbouring blocks must share bit-identical vertex coordinates so that contact detection finds
their common faces; the primitives therefore compute every point once, transform the whole pool to
world coordinates in one call, and let each block index into it.
"""

from __future__ import annotations

__all__ = ["prism_faces", "prism_blocks", "extrusion_pool", "polygon_is_convex"]

from collections.abc import Sequence

import numpy as np

from shapegen.model.block import Block
from shapegen.model.scope import Scope


def prism_faces(k: int, flip: bool = False) -> tuple[tuple[int, ...], ...]:
    """Outward faces of a prism whose vertices are a base ring ``0..k-1`` and a top ring
    ``k..2k-1``, the base ring counter-clockwise about the base-to-top direction.

    ``flip`` reverses every face, for a scope whose axes form a mirror image.
    """
    base = tuple(range(k - 1, -1, -1))
    top = tuple(range(k, 2 * k))
    sides = tuple((i, (i + 1) % k, k + (i + 1) % k, k + i) for i in range(k))
    faces = (base, top) + sides
    if flip:
        faces = tuple(tuple(reversed(face)) for face in faces)
    return faces


def extrusion_pool(profile: np.ndarray, depth: float) -> np.ndarray:
    """Scope-local 3D points of a 2D ``profile`` ((m, 2), metres, in the scope's x-y plane) at
    z = 0 (rows ``0..m-1``) and at z = ``depth`` (rows ``m..2m-1``)."""
    profile = np.asarray(profile, dtype=float).reshape(-1, 2)
    m = len(profile)
    pool = np.zeros((2 * m, 3))
    pool[:m, :2] = profile
    pool[m:, :2] = profile
    pool[m:, 2] = depth
    return pool


def prism_blocks(
    scope: Scope,
    pool: np.ndarray,
    rings: Sequence[tuple[Sequence[int], Sequence[int]]],
    tags: tuple[str, ...] = (),
) -> list[Block]:
    """One block per ``(base, top)`` pair of index rings into ``pool`` (scope-local points, m).

    Each base ring is a convex polygon counter-clockwise about the direction from base to top;
    the top ring is the same polygon swept. The pool is moved to world coordinates in one call,
    so blocks that share a pool point share its world coordinates exactly.
    """
    world = scope.to_world(pool)
    flip = bool(np.linalg.det(scope.rotation) < 0)
    blocks = []
    for base, top in rings:
        index = np.concatenate([np.asarray(base, dtype=int), np.asarray(top, dtype=int)])
        blocks.append(Block(world[index], prism_faces(len(base), flip), tags=tags))
    return blocks


def polygon_is_convex(polygon: np.ndarray, tolerance: float) -> bool:
    """True when the 2D ``polygon`` ((k, 2), metres) is strictly convex and counter-clockwise.

    ``tolerance`` is a length (m): a turn whose signed area per edge length falls below it counts
    as a reflex or flat corner.
    """
    p = np.asarray(polygon, dtype=float)
    edges = np.roll(p, -1, axis=0) - p
    turn = (
        edges[:, 0] * np.roll(edges, -1, axis=0)[:, 1]
        - edges[:, 1] * np.roll(edges, -1, axis=0)[:, 0]
    )
    lengths = np.linalg.norm(edges, axis=1)
    scale = lengths * np.roll(lengths, -1)
    return bool(np.all(lengths > tolerance) and np.all(turn > tolerance * np.sqrt(scale)))

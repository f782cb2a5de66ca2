"""Voussoir geometry shared by the arched primitives (vaults, domes, flying buttresses).

Curved surfaces are approximated by planar facets: a voussoir between two radial joints is the
solid bounded by its two joint planes, the chord of its intrados and the chord of its extrados.
Neighbouring voussoirs are built from the same joint points, so they share their joint face
exactly and contact detection finds the interface between them.
"""

from __future__ import annotations

__all__ = [
    "arc_joints",
    "hexahedron",
    "hexahedra_in_scope",
]

import numpy as np

from shapegen.model.block import Block
from shapegen.model.scope import Scope
from shapegen.primitives.prism import prism_faces


def arc_joints(
    radius_in: float, radius_out: float, angles: np.ndarray, centre=(0.0, 0.0)
) -> np.ndarray:
    """The radial joints of a circular ring, as 2D segments.

    Parameters
    ----------
    radius_in, radius_out
        Intrados and extrados radii, metres.
    angles
        ``(n + 1,)`` polar angles of the joints, radians (0 along +x, pi/2 along +y).
    centre
        Centre of the ring, metres.

    Returns
    -------
    ``(n + 1, 2, 2)`` array: ``[k, 0]`` is the intrados point and ``[k, 1]`` the extrados point
    of joint ``k`` (metres).
    """
    angles = np.asarray(angles, float)
    direction = np.stack([np.cos(angles), np.sin(angles)], axis=-1)
    radii = np.array([radius_in, radius_out], float)
    return np.asarray(centre, float) + direction[:, None, :] * radii[None, :, None]


def hexahedron(corners: np.ndarray, **kwargs) -> Block:
    """A block from 8 corners whose six quads are planar (corners 0-3 one end, 4-7 the other).

    The faces are oriented outward whichever way the end quads wind.
    """
    block = Block(corners, prism_faces(4), **kwargs)
    if block.volume < 0:
        block = Block(corners, prism_faces(4, flip=True), **kwargs)
    return block


def hexahedra_in_scope(corners: np.ndarray, scope: Scope, **kwargs) -> list[Block]:
    """Blocks from ``(n, 8, 3)`` corner sets given in scope coordinates (metres)."""
    world = scope.to_world(corners.reshape(-1, 3)).reshape(corners.shape)
    return [hexahedron(c, **kwargs) for c in world]

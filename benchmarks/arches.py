"""Block models for benchmarks and checks: semicircular arches of voussoirs with radial joints."""

from __future__ import annotations

__all__ = ["semicircular_arch", "arch_row"]

import numpy as np

from shapegen.model.block import Block
from shapegen.model.model import Model


def _voussoirs(radius, thickness, n, depth, offset_x=0.0, offset_z=0.0, prefix="v"):
    inner, outer = radius - thickness / 2, radius + thickness / 2
    angles = np.linspace(np.pi, 0.0, n + 1)  # left springing to right springing
    blocks = []
    for k in range(n):
        a0, a1 = angles[k], angles[k + 1]
        ring = [(r * np.cos(a), r * np.sin(a)) for a in (a0, a1) for r in (inner, outer)]
        points = [(x + offset_x, y, z) for x, y in ring for z in (offset_z, offset_z + depth)]
        blocks.append(Block.from_hull(np.array(points), id=f"{prefix}{k}"))
    return blocks


def semicircular_arch(
    n_voussoirs: int = 100,
    thickness_ratio: float = 0.2,
    radius: float = 1.0,
    depth: float | None = None,
    friction: float = 0.7,
) -> Model:
    """A semicircular arch of ``n_voussoirs`` equal voussoirs with radial joints, springing from
    the ground plane y = 0.

    Parameters
    ----------
    n_voussoirs
        Number of voussoirs.
    thickness_ratio
        Ring thickness divided by the centreline radius (t / R, dimensionless).
    radius
        Centreline radius R, m.
    depth
        Extent along z, m (default: the ring thickness).
    friction
        Coulomb coefficient of the joints.
    """
    thickness = thickness_ratio * radius
    depth = thickness if depth is None else depth
    return Model(_voussoirs(radius, thickness, n_voussoirs, depth), friction=friction)


def arch_row(n_blocks: int, voussoirs: int = 20, thickness_ratio: float = 0.2) -> Model:
    """About ``n_blocks`` blocks as independent arches side by side along x (benchmark scaling)."""
    count = max(1, round(n_blocks / voussoirs))
    blocks = []
    for k in range(count):
        blocks += _voussoirs(
            1.0, thickness_ratio, voussoirs, 0.2, offset_x=2.6 * k, prefix=f"a{k}v"
        )
    return Model(blocks, friction=0.7)

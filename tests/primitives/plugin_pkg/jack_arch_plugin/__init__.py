"""A third-party primitive shipped in its own package: ``jack_arch``, a flat arch.

A jack (flat) arch spans an opening with a horizontal soffit and a horizontal top; its joints
radiate from one point below the soffit, so every voussoir is a wedge that the thrust locks in
place. The package registers the primitive on import; its ``pyproject.toml`` names this module in
the entry-point group ``shapegen.primitives`` so that shapegen imports it when it looks up
primitives.
"""

from __future__ import annotations

__all__ = ["jack_arch"]

import math

import numpy as np

from shapegen import Block, Scope
from shapegen.primitives import primitive, require


@primitive("jack_arch")
def jack_arch(scope: Scope, *, segments: int = 5, skewback: float = 20.0) -> list[Block]:
    """A flat arch filling the scope: soffit at y = 0, top at y = sy, joints radiating from a
    point below the middle of the soffit.

    Parameters
    ----------
    segments
        Voussoirs (>= 1).
    skewback
        Inclination of the two end joints from the vertical, degrees; the joints meet below the
        soffit, so ``tan(skewback)`` must be below ``sx / (2 sy)``.
    """
    width, height = scope.sx, scope.sy
    require(segments >= 1, "jack_arch", "segments", f"must be at least 1, got {segments}")
    slope = math.tan(math.radians(skewback))
    require(
        0 < slope < width / (2 * height),
        "jack_arch",
        "skewback",
        f"must be positive and below {math.degrees(math.atan(width / (2 * height))):.3g} degrees "
        f"for this scope, got {skewback:g} degrees",
    )
    # Every joint passes through the top at x_top and through the common centre below the soffit.
    centre_depth = width / (2 * slope) - height
    x_top = np.linspace(0.0, width, segments + 1)
    x_bottom = width / 2 + (x_top - width / 2) * centre_depth / (centre_depth + height)
    blocks = []
    for k in range(segments):
        section = [
            (x_bottom[k], 0),
            (x_bottom[k + 1], 0),
            (x_top[k + 1], height),
            (x_top[k], height),
        ]
        corners = [(x, y, z) for z in (0.0, scope.sz) for x, y in section]
        blocks.append(Block.from_hull(scope.to_world(np.array(corners, float))))
    return blocks

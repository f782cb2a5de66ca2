"""Small hand-built statics problems with known answers (interfaces built by hand, so these tests
do not depend on the contact search)."""

from __future__ import annotations

import numpy as np

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

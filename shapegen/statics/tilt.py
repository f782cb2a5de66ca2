"""The tilting table: every load turned by a tilt towards an azimuth, and the sideways load.

y is up. The azimuth is an angle in the ground plane x-z, in degrees from +x towards +z: azimuth
0 tilts gravity towards +x, 90 towards +z. Tilting a structure with its support by ``theta``
(the tilting-table test) is, for rigid-block statics, the same as keeping the structure put and
turning every load by ``theta`` about the horizontal axis ``k = d x y`` (``d`` the unit vector of
the azimuth): a weight ``-W y`` becomes ``W (-cos(theta) y + sin(theta) d)``. Point loads are
live loads (carried weights) and turn with gravity.

For a vertical load ``F`` the turned load is ``cos(theta) (F + tan(theta) k x F)`` with ``k x F``
horizontal along ``d`` and as large as ``F``. Equilibrium with compression-only, frictional
joints is unchanged when every load is scaled by a positive factor (the forces scale with it), so
the tilted structure stands exactly when it stands under its loads plus a horizontal load
``lambda = tan(theta)`` times each of them: the load multiplier of the equivalent static lateral
load. Tilt and multiplier are two names of one limit, ``theta = atan(lambda)``.

>>> import numpy as np
>>> np.round(rotation(30.0, 0.0) @ [0.0, -9.81, 0.0], 4)
array([ 4.905 , -8.4957,  0.    ])
"""

from __future__ import annotations

__all__ = [
    "direction",
    "lateral_map",
    "load_direction_problem",
    "normalized_azimuth",
    "rotation",
]

import math

import numpy as np

from shapegen.tolerances import ROUNDOFF_REL, is_positive

UP = np.array([0.0, 1.0, 0.0])


def normalized_azimuth(azimuth: float) -> float:
    """``azimuth`` in [0, 360) degrees."""
    value = math.fmod(float(azimuth), 360.0)
    value = value + 360.0 if value < 0 else value
    return 0.0 if value >= 360.0 else value


def direction(azimuth: float) -> np.ndarray:
    """Unit vector of ``azimuth`` (degrees from +x towards +z) in the ground plane."""
    a = math.radians(azimuth)
    return np.array([math.cos(a), 0.0, math.sin(a)])


def _axis(azimuth: float) -> np.ndarray:
    """The horizontal axis ``d x y`` about which a tilt towards ``azimuth`` turns the loads."""
    return np.cross(direction(azimuth), UP)


def _cross_matrix(k: np.ndarray) -> np.ndarray:
    return np.array([[0.0, -k[2], k[1]], [k[2], 0.0, -k[0]], [-k[1], k[0], 0.0]])


def rotation(tilt: float, azimuth: float) -> np.ndarray:
    """``(3, 3)`` rotation that turns every load by ``tilt`` (degrees) towards ``azimuth``."""
    theta = math.radians(tilt)
    k = _axis(azimuth)
    cross = _cross_matrix(k)
    return np.eye(3) + math.sin(theta) * cross + (1.0 - math.cos(theta)) * cross @ cross


def lateral_map(azimuth: float) -> np.ndarray:
    """``(3, 3)`` matrix taking a load ``F`` to ``k x F``: for a vertical load, the horizontal
    load of the same size towards ``azimuth`` (the derivative of the rotation at tilt 0)."""
    return _cross_matrix(_axis(azimuth))


def load_direction_problem(model) -> str | None:
    """Why the loads of ``model`` are not all vertical (gravity along -y, vertical point loads),
    or None when they are. Only then is a tilt the same as a horizontal load proportional to
    the vertical loads (module docstring), which the lateral capacity computes."""
    gravity = np.asarray(model.gravity, float)
    g = float(np.linalg.norm(gravity))
    if g > 0 and is_positive(float(np.hypot(gravity[0], gravity[2])), ROUNDOFF_REL * g):
        shown = ", ".join(f"{v:g}" for v in gravity)
        return f"the model's gravity ({shown}) is not along -y"
    for load in model.loads:
        force = np.asarray(load.force, float)
        size = float(np.linalg.norm(force))
        if size > 0 and is_positive(float(np.hypot(force[0], force[2])), ROUNDOFF_REL * size):
            return f"the point load on block {load.block!r} is not vertical"
    return None

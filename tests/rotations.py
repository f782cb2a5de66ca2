"""The rotations that tests turn blocks, meshes and scopes with."""

import numpy as np


def about_y(degrees: float) -> np.ndarray:
    """The 3 x 3 rotation by ``degrees`` about the vertical y axis (right-handed: x turns
    towards -z)."""
    angle = np.radians(degrees)
    cos, sin = np.cos(angle), np.sin(angle)
    return np.array([[cos, 0.0, sin], [0.0, 1.0, 0.0], [-sin, 0.0, cos]])

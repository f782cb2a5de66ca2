"""Skip the simulation tests when the optional pybullet extra is missing."""

import pytest

from shapegen.errors import ShapegenError
from shapegen.simulation.world import load_pybullet

try:
    load_pybullet()
except ShapegenError:
    pytest.skip("the simulation tests need the shapegen[sim] extra", allow_module_level=True)

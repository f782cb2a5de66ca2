"""Semicircular arches against the classical limit analysis results.

- Minimum thickness of a semicircular arch under self-weight with radial joints: t / R = 0.1075
  (Milankovitch 1907; Heyman; the seed paper finds 0.10746 with 100 voussoirs).
- Critical tilt of a semicircular arch tilted with its support (Ochsendorf 2002, friction high
  enough that no joint slides): 8.23 deg at t / R = 0.15, 15.84 deg at 0.20, 22.09 deg at 0.25.

Each arch has 100 voussoirs on the ground plane; the arch centreline radius R is 1 m.
"""

import math

import numpy as np
import pytest

from shapegen.model.block import Block
from shapegen.model.model import Model
from shapegen.primitives.arch import semicircular_arch
from shapegen.statics import analyze

RADIUS = 1.0  # m, centreline
SEGMENTS = 100
FRICTION = 5.0  # high enough that no joint slides


def arch_stands(ratio: float, tilt_degrees: float = 0.0, support: str = "ground") -> bool:
    """Verdict for an arch of thickness ``ratio * RADIUS`` on a support tilted by ``tilt``.

    ``support`` is "ground" (the plane y = 0) or "blocks" (a fixed block under each springing,
    no ground plane). Tilting the arch with its support is the same as turning gravity the other
    way: the support stays put and gravity leans towards +x.
    """
    thickness = ratio * RADIUS
    blocks = semicircular_arch(RADIUS, thickness, SEGMENTS, depth=0.5)
    ground = 0.0
    if support == "blocks":
        ground = None
        for side in (-1.0, 1.0):
            x0 = side * RADIUS - thickness
            blocks.append(Block.box([x0, -0.3, -0.1], [x0 + 2 * thickness, 0.0, 0.6], fixed=True))
    tilt = math.radians(tilt_degrees)
    gravity = 9.81 * np.array([math.sin(tilt), -math.cos(tilt), 0.0])
    model = Model(blocks, gravity=gravity, ground=ground, friction=FRICTION)
    return analyze(model).feasible


@pytest.mark.slow
@pytest.mark.parametrize("support", ["ground", "blocks"])
def test_minimum_thickness_of_the_semicircular_arch(bisect, support):
    stands = lambda ratio: arch_stands(ratio, support=support)  # noqa: E731
    assert not stands(0.100)
    assert stands(0.115)
    ratio = bisect(stands, 0.100, 0.115, tolerance=1e-4)
    assert ratio == pytest.approx(0.1075, rel=5e-3)


@pytest.mark.slow
@pytest.mark.parametrize(
    "ratio, critical_tilt",
    [(0.20, 15.84), (0.15, 8.23), (0.25, 22.09)],
)
def test_critical_tilt_of_the_semicircular_arch(bisect, ratio, critical_tilt):
    stands_at = lambda tilt: arch_stands(ratio, tilt)  # noqa: E731
    tilt = bisect(stands_at, critical_tilt - 1.5, critical_tilt + 1.5, tolerance=0.02)
    assert tilt == pytest.approx(critical_tilt, abs=0.15)

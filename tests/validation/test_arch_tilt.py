"""Lateral capacity of the semicircular arch: the tilting-table test against the literature.

A semicircular arch of 100 voussoirs with radial joints, centreline radius R = 1 m, on the
ground plane, friction high enough that no joint slides (mu = 5): its critical tilt, in the
plane of the arch, is the limit of a four-hinge mechanism.

- t / R = 0.20: 15.84 deg (Ochsendorf 2002; Whiting, Ochsendorf, Durand 2009);
- t / R = 0.15: about 8.2 deg (Shin 2016, Kao 2022; their 3D-printed model fell at 4.7 deg:
  the rigid-block figure is an upper bound, see docs/statics.md).

The arch is the one of ``test_arch_limits.py`` (``semicircular_arch`` of the primitives, depth
0.5 m). The quick tests run the capacity itself, which the verdict confirms half a resolution
either side; the curve over t / R and the block-count convergence of docs/statics.md are slow.
"""

import math

import pytest

from shapegen.model.model import Model
from shapegen.primitives.arch import semicircular_arch
from shapegen.statics import StaticsOptions, analyze
from shapegen.statics.capacity import lateral_capacity

RADIUS = 1.0
FRICTION = 5.0  # no joint slides: hinges govern
IN_PLANE = 0.0  # azimuth: the arch spans x


def arch(ratio: float, voussoirs: int = 100, depth: float = 0.5) -> Model:
    blocks = semicircular_arch(RADIUS, ratio * RADIUS, voussoirs, depth=depth)
    return Model(blocks, ground=0.0, friction=FRICTION)


@pytest.mark.parametrize("ratio, published", [(0.20, 15.84), (0.15, 8.23)])
def test_critical_tilt_of_the_semicircular_arch(ratio, published):
    model = arch(ratio)
    capacity = lateral_capacity(model, azimuths=[IN_PLANE, 180.0])
    towards, away = capacity.directions
    assert towards.checked and away.checked  # the verdict agrees within 0.025 deg
    assert towards.tilt == pytest.approx(published, abs=0.05)
    assert away.tilt == pytest.approx(towards.tilt, abs=1e-6)  # the arch is symmetric
    assert capacity.multiplier == pytest.approx(math.tan(math.radians(towards.tilt)))
    # and the tilted analysis itself, on either side of the published figure
    assert analyze(model, tilt=published - 0.1, azimuth=IN_PLANE).feasible
    assert not analyze(model, tilt=published + 0.1, azimuth=IN_PLANE).feasible


def test_the_thicker_arch_tilts_further_and_the_thinnest_hardly_at_all():
    tilts = [lateral_capacity(arch(r), azimuths=[IN_PLANE]).tilt for r in (0.11, 0.15, 0.25)]
    assert tilts == sorted(tilts)
    assert 0 < tilts[0] < 1.0  # t/R 0.11 is just above the minimum thickness 0.1075
    assert tilts[2] == pytest.approx(22.09, abs=0.05)  # Ochsendorf 2002


def test_with_default_friction_the_pyramids_joints_slide_first():
    # mu = 0.7 with the 4-sided pyramid allows mu / sqrt(2) = 0.49 along the arch's plane: at
    # t/R = 0.25 the springing joint slides (atan 0.49 = 26.3 deg is the table's angle for a
    # block on the ground, less where the thrust is inclined) before hinges form at 22.09 deg;
    # the default cone allows mu = 0.7 in every direction and the hinges govern
    model = Model(semicircular_arch(RADIUS, 0.25, 100, depth=0.5), ground=0.0, friction=0.7)
    pyramid = lateral_capacity(model, StaticsOptions(pyramid="4"), azimuths=[IN_PLANE]).tilt
    cone = lateral_capacity(model, azimuths=[IN_PLANE]).tilt
    assert pyramid < 22.09 - 1.0
    assert cone == pytest.approx(22.09, abs=0.05)  # mu = 0.7 in every direction: no sliding


def test_the_worst_direction_of_a_shallow_arch_is_out_of_its_plane():
    # 0.15 m deep, 0.2 m thick: tipping sideways over its 0.15 m depth comes before the in-plane
    # mechanism (15.84 deg); the sweep finds it across the arch, at azimuth 90 (or 270)
    model = arch(0.20, voussoirs=40, depth=0.15)
    capacity = lateral_capacity(model)
    assert capacity.swept and capacity.worst.checked
    assert min(abs(capacity.worst.azimuth - a) for a in (90.0, 270.0)) < 1.0
    in_plane = next(d for d in capacity.directions if d.azimuth == 0.0)
    assert capacity.tilt < in_plane.tilt


CURVE = [0.11, 0.12, 0.13, 0.14, 0.15, 0.16, 0.18, 0.20, 0.22, 0.25, 0.30]


@pytest.mark.slow
@pytest.mark.parametrize("voussoirs", [20, 50, 100, 200])
def test_the_curve_converges_with_the_number_of_voussoirs(voussoirs):
    # docs/statics.md: the critical tilt over t/R for 20, 50, 100 and 200 voussoirs. More
    # voussoirs put joints closer to the continuous arch's hinges: 100 and 200 agree within
    # 0.05 deg at every ratio, and every curve rises with the thickness.
    tilts = [lateral_capacity(arch(r, voussoirs), azimuths=[IN_PLANE]).tilt for r in CURVE]
    assert tilts == sorted(tilts)
    fine = [lateral_capacity(arch(r, 200), azimuths=[IN_PLANE]).tilt for r in (0.15, 0.20)]
    coarse = [tilts[CURVE.index(0.15)], tilts[CURVE.index(0.20)]]
    tolerance = {20: 0.35, 50: 0.05, 100: 0.02, 200: 1e-9}[voussoirs]
    assert coarse == pytest.approx(fine, abs=tolerance)

"""Single blocks and stacks at the limits of rigid-block statics.

- A block on a support tilted by alpha slides when tan(alpha) exceeds the friction limit along
  the slope: mu / sqrt(2) for the 4-sided pyramid whose sides face the slope (mu cos(pi / 8) for
  the octagon, mu for the square turned by 45 degrees, whose corner faces the slope).
- A tall block of base b and height h on a rough support tips at alpha = atan(b / h) first.
- A block overhanging the edge of a support stands iff its centroid is over the support; with the
  kern 1/3 iff its centroid is over the middle third of the contact.
- The harmonic stack: block k from the top overhangs the one below by L / (2k), which puts the
  centroid of the top k blocks exactly over the edge of block k + 1.

Tilting a support is the same as turning gravity the other way. The ground plane's normal is +y,
whose tangent frame (:func:`shapegen.statics.interface.tangent_frame`) has tangent2 along x, so
gravity turned in the x-y plane makes the slope lie along a tangent axis.
"""

import math

import numpy as np
import pytest

from shapegen.model.block import Block
from shapegen.model.model import Model
from shapegen.statics import analyze
from shapegen.statics.interface import tangent_frame


def tilted_gravity(degrees: float) -> np.ndarray:
    tilt = math.radians(degrees)
    return 9.81 * np.array([math.sin(tilt), -math.cos(tilt), 0.0])


def block_on_slope_stands(base: float, height: float, tilt: float, friction: float, pyramid: str):
    block = Block.box([0.0, 0.0, 0.0], [base, height, 0.5])
    model = Model([block], gravity=tilted_gravity(tilt), ground=0.0, friction=friction)
    return analyze(model, pyramid=pyramid).feasible


def test_the_slope_lies_along_a_tangent_of_the_ground():
    t1, t2 = tangent_frame(np.array([0.0, 1.0, 0.0]))
    assert abs(np.dot(t1, [1.0, 0.0, 0.0])) < 1e-12 or abs(np.dot(t2, [1.0, 0.0, 0.0])) < 1e-12
    assert max(abs(t1[0]), abs(t2[0])) == pytest.approx(1.0)


@pytest.mark.parametrize(
    "pyramid, friction_along_slope",
    [
        ("4", lambda mu: mu / math.sqrt(2)),
        ("8", lambda mu: mu * math.cos(math.pi / 8)),
        ("4r", lambda mu: mu),
    ],
)
@pytest.mark.parametrize("mu", [0.7, 0.4])
def test_a_block_slides_past_the_friction_angle(pyramid, friction_along_slope, mu):
    critical = math.degrees(math.atan(friction_along_slope(mu)))
    # A squat block: tipping needs atan(b / h) = 76 deg, far beyond sliding.
    assert block_on_slope_stands(1.0, 0.25, critical - 0.1, mu, pyramid)
    assert not block_on_slope_stands(1.0, 0.25, critical + 0.1, mu, pyramid)


@pytest.mark.parametrize("base, height", [(0.2, 1.0), (0.3, 0.8)])
def test_a_tall_block_tips_before_it_slides(base, height):
    mu = 0.7
    critical = math.degrees(math.atan(base / height))
    assert critical < math.degrees(math.atan(mu / math.sqrt(2)))
    assert block_on_slope_stands(base, height, critical - 0.1, mu, "4")
    assert not block_on_slope_stands(base, height, critical + 0.1, mu, "4")


def overhang_stands(overlap: float, kern: float) -> bool:
    """A 1 m block resting with ``overlap`` (m) of its length on a fixed support ending at x = 0."""
    support = Block.box([-2.0, -0.5, -0.5], [0.0, 0.0, 1.0], fixed=True)
    block = Block.box([-overlap, 0.0, 0.0], [1.0 - overlap, 0.4, 0.5])
    model = Model([support, block], ground=None, friction=0.7)
    return analyze(model, kern=kern).feasible


@pytest.mark.parametrize(
    "overlap, stands", [(0.52, True), (0.48, False), (0.9, True), (0.2, False)]
)
def test_an_overhanging_block_stands_iff_its_centroid_is_over_the_support(overlap, stands):
    assert overhang_stands(overlap, kern=1.0) is stands


# With the kern 1/3 the contact [-a, 0] shrinks to its middle third [-2a/3, -a/3]; the centroid
# of a 1 m block, at 0.5 - a, lies in it iff a >= 0.75 (for a <= 1).
@pytest.mark.parametrize(
    "overlap, stands", [(0.77, True), (0.73, False), (1.0, True), (0.52, False)]
)
def test_with_the_kern_a_third_the_centroid_must_be_over_the_middle_third(overlap, stands):
    assert overhang_stands(overlap, kern=1 / 3) is stands


def harmonic_stack(count: int, length: float, factor: float) -> Model:
    """``count`` blocks of ``length`` (m); block k from the top overhangs the one below by
    ``factor * length / (2 k)``; the bottom block lies on the ground."""
    height, depth = 0.2, 0.5
    left = 0.0
    blocks = []
    for k in range(count, 0, -1):  # from the bottom (k = count) to the top (k = 1)
        level = (count - k) * height
        blocks.append(Block.box([left, level, 0.0], [left + length, level + height, depth]))
        if k > 1:
            left += factor * length / (2 * (k - 1))
    return Model(blocks, ground=0.0, friction=0.7)


@pytest.mark.parametrize("count", [4, 6])
@pytest.mark.parametrize("factor, stands", [(0.98, True), (1.02, False)])
def test_harmonic_stack(count, factor, stands):
    assert analyze(harmonic_stack(count, 1.0, factor)).feasible is stands

"""Exact inertia tensors against closed forms."""

import math

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from shapegen.model.block import Block
from shapegen.simulation.inertia import inertia_tensor, principal_inertia


def test_box_matches_the_closed_form():
    a, b, c, density = 0.4, 0.2, 0.3, 2400.0
    block = Block.box([1.0, 2.0, 3.0], [1.0 + a, 2.0 + b, 3.0 + c], density=density)
    mass = density * a * b * c
    expected = mass / 12.0 * np.diag([b * b + c * c, a * a + c * c, a * a + b * b])
    assert inertia_tensor(block) == pytest.approx(expected, rel=1e-12, abs=1e-12)


def test_rotated_box_transforms_as_a_tensor():
    rotation = Rotation.from_euler("xyz", [0.3, -0.7, 1.1]).as_matrix()
    box = Block.box([0, 0, 0], [0.5, 0.2, 0.1])
    turned = box.transformed(rotation, [2.0, 1.0, -1.0])
    expected = rotation @ inertia_tensor(box) @ rotation.T
    assert inertia_tensor(turned) == pytest.approx(expected, rel=1e-10, abs=1e-12)


def test_regular_tetrahedron_is_isotropic_with_m_a2_over_20():
    edge = 0.5
    corners = np.array([[1, 1, 1], [1, -1, -1], [-1, 1, -1], [-1, -1, 1]], float)
    corners *= edge / (2.0 * math.sqrt(2.0))
    block = Block.from_hull(corners, density=1000.0)
    expected = block.mass * edge**2 / 20.0
    assert inertia_tensor(block) == pytest.approx(expected * np.eye(3), rel=1e-10, abs=1e-12)


def test_principal_frame_is_a_proper_rotation_that_diagonalises_the_tensor():
    rotation = Rotation.from_euler("zyx", [0.4, 0.2, -0.9]).as_matrix()
    block = Block.box([0, 0, 0], [0.6, 0.25, 0.1]).transformed(rotation, [0, 0, 0])
    frame = principal_inertia(block)
    assert np.linalg.det(frame.axes) == pytest.approx(1.0)
    body = frame.axes.T @ inertia_tensor(block) @ frame.axes
    assert body == pytest.approx(np.diag(frame.moments), abs=1e-10)
    mass = block.mass
    expected = sorted(mass / 12.0 * np.array([0.25**2 + 0.1**2, 0.6**2 + 0.1**2, 0.6**2 + 0.25**2]))
    assert frame.moments == pytest.approx(expected, rel=1e-10)

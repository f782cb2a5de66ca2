"""Convexity far from the origin: a block's vertices are stored as float64 coordinates, so a face
plane at x = 1e10 m cannot be checked closer than a few ulps of 1e10 (~2e-6 m). The test allows
that round-off (COORDINATE_ROUNDOFF_REL of the coordinates' magnitude) and nothing more: a real
dent is still found."""

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from shapegen.errors import GeometryError
from shapegen.model.block import Block
from shapegen.model.model import Model
from shapegen.tolerances import COORDINATE_ROUNDOFF_REL

TURN = Rotation.from_euler("xyz", [17, 29, 41], degrees=True).as_matrix()


def _turned_cube(offset: float) -> Block:
    cube = Block.box((0, 0, 0), (1, 1, 1))
    return Block(cube.vertices @ TURN.T + [offset, 0.5, offset / 3], cube.faces, id="a")


@pytest.mark.parametrize("offset", [0.0, 1e4, 1e8, 1e10, 1e12])
def test_a_turned_unit_cube_is_valid_wherever_it_is(offset):
    block = _turned_cube(offset)
    block.validate()
    Model([block]).validate()
    assert block.volume == pytest.approx(1.0, rel=1e-4)


def test_a_dent_well_above_the_round_off_is_still_found_far_away():
    block = _turned_cube(1e10)
    dented = block.vertices.copy()
    # Push one corner 4 mm out along its face's normal: the warped face's corners then lie
    # about 1 mm off its plane, 10 times the allowance at 1e10.
    normal = block.face_normals[0]
    corner = block.faces[0][0]
    dented[corner] += 4e-3 * normal
    assert 4e-3 / 4 >= 10 * COORDINATE_ROUNDOFF_REL * np.abs(dented).max() * 0.999
    with pytest.raises(GeometryError, match="not convex"):
        Block(dented, block.faces, id="a").validate()
    with pytest.raises(GeometryError, match="not convex"):
        Model([Block(dented, block.faces, id="a")]).validate()

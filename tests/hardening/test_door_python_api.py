"""The Python doors (shapegen.prt's PyPRT API) given values of the wrong kind: one line."""

from __future__ import annotations

import numpy as np
import pytest

import shapegen.prt as pyprt
from shapegen.errors import InputFormatError

SQUARE = [0, 0, 0, 0, 0, 10, 10, 0, 10, 10, 0, 0]


NUMBERS = "must be a list of numbers"
WHOLE = "must be a list of whole numbers"


@pytest.mark.parametrize(
    "kwargs, message",
    [
        ({"vertex_coordinates": ["0", "0", "0"] * 3}, "vertex_coordinates " + NUMBERS),
        ({"vertex_coordinates": "0 0 0 1 0 0 1 0 1"}, "vertex_coordinates " + NUMBERS),
        ({"vertex_coordinates": SQUARE, "indices": [0, 1.5, 2, 3]}, "indices " + WHOLE),
        ({"vertex_coordinates": SQUARE, "face_counts": [None]}, "face_counts " + WHOLE),
        ({"vertex_coordinates": SQUARE, "holes": [[0, "x"]]}, "holes " + WHOLE),
        ({"vertex_coordinates": 5}, "vertex_coordinates " + NUMBERS),
    ],
)
def test_an_initial_shape_of_the_wrong_kind_is_one_line(kwargs, message):
    # ValueError: could not convert string to float, and 1.5 read as index 1
    with pytest.raises(InputFormatError, match=message):
        pyprt.InitialShape(**kwargs)


def test_an_initial_shape_of_numpy_numbers_is_read():
    shape = pyprt.InitialShape(np.array(SQUARE, dtype=float), np.arange(4), np.array([4]))
    assert shape.get_vertex_count() == 12 and shape.get_index_count() == 4

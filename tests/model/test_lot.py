"""The one lot type (shapegen.model.lot): what it accepts, how it cleans a ring, and that each
front end (the command line, the design page, a city's rows, the library) says its one refusal
in the same line, behind its own name for the place."""

from __future__ import annotations

import math
import warnings

import numpy as np
import pytest

from shapegen import parse_grammar
from shapegen.city import city_from_polygons
from shapegen.cli import main
from shapegen.editor.attrs import RequestError
from shapegen.editor.inputs import checked_lot
from shapegen.errors import InputFormatError, LotError
from shapegen.model.lot import Lot
from shapegen.tolerances import LOT_MERGE_M


def test_a_rectangle_is_its_width_and_depth():
    lot = Lot.of((12, 8))
    assert lot == Lot.rectangle(12.0, 8.0) and lot.size == (12.0, 8.0) and lot.corners is None
    assert (lot.area, lot.to_json(), lot.is_polygon) == (96.0, [12.0, 8.0], False)
    assert Lot.of(np.array([12.0, 8.0])) == lot and Lot.of(lot) is lot


def test_a_polygon_keeps_its_corners_counter_clockwise_from_its_first():
    ccw = [(0, 8), (12, 8), (12, 0), (0, 0)]  # counter-clockwise seen from above (y up)
    lot = Lot.of(ccw)
    assert lot.corners == tuple(ccw) and lot.is_polygon and lot.area == 96.0
    clockwise = [ccw[0], *reversed(ccw[1:])]
    assert Lot.of(clockwise) == lot  # reversed, its first corner kept first
    assert Lot.of(lot.to_json()) == lot and Lot.of(np.array(ccw)) == lot
    assert hash(Lot.of(ccw)) == hash(lot)  # a key of the page's caches


@pytest.mark.parametrize("gap, corners", [(0.9 * LOT_MERGE_M, 4), (1.1 * LOT_MERGE_M, 5)])
def test_corners_closer_than_the_merge_distance_are_one(gap, corners):
    ring = [(0, 8), (12, 8), (12, 0), (0, 0), (0, gap)]
    assert len(Lot.polygon(ring).corners) == corners
    closed = [(0, 8), (12, 8), (12, 0), (0, 0), (-gap, 8)]  # a closing corner near the first
    assert len(Lot.polygon(closed).corners) == corners


@pytest.mark.parametrize(
    ("value", "message"),
    [
        ((0, 1), "lot width and depth must be finite numbers > 0 m, got 0 x 1"),
        ((1, math.nan), "lot width and depth must be finite numbers > 0 m, got 1 x nan"),
        ((10**400, 1), "lot width and depth must be finite numbers > 0 m, got inf x 1"),
        ((2e9, 1), "lot width and depth must be at most 1e+09 m, got 2e+09 x 1"),
        ((True, 2), "a lot is (width, depth) in metres or a polygon of 3 or more (x, z) corners"),
        ("12,8", "a lot is (width, depth) in metres or a polygon of 3 or more (x, z) corners"),
        (None, "a lot is (width, depth) in metres or a polygon of 3 or more (x, z) corners"),
        ([(0, 0), (1, 0), (1, 1), 2], "a lot is (width, depth) in metres or a polygon"),
        ([(0, 0), (1, 1)], "a lot needs at least 3 distinct corners, got 2"),
        ([(0, 0), (1, 0), (math.inf, 1)], "corner coordinates must be finite numbers"),
        ([(0, 0), (1, 0), (3, 0)], "the polygon has no area (its corners are in a line)"),
        ([(0, 0), (1, 1), (1, 0), (0, 1)],
         "the polygon crosses itself (self-intersection at x=0.5, z=0.5)"),
        ([(0, 0), (2e9, 0), (0, 1)], "corners must lie within 1e+09 m of the origin"),
        # corners 2e308 m apart: refused before their distances are taken (they overflow)
        ([(0, 0), (1e308, 0), (-1e308, 1e308)], "corners must lie within 1e+09 m of the origin"),
    ],
)  # fmt: skip
def test_what_cannot_be_a_lot_is_one_line(value, message):
    with pytest.raises(LotError) as caught, warnings.catch_warnings():
        warnings.simplefilter("error")  # one line, and not numpy's overflow warning before it
        Lot.of(value)
    assert str(caught.value).startswith(message) and "\n" not in str(caught.value)
    assert isinstance(caught.value, InputFormatError)


# A self-crossing bow tie, corners (x, z) in metres; it crosses itself at x=1, z=1.
BOW_TIE = [(0, 0), (2, 2), (2, 0), (0, 2)]
ONE_LINE = "the polygon crosses itself (self-intersection at x=1, z=1)"


def test_every_front_end_says_the_one_line(capsys, tmp_path):
    text = " ".join(f"{x},{z}" for x, z in BOW_TIE)
    # the command line: exit status 2, one line naming --lot
    written = tmp_path / "m.json"
    assert main(["build", "wall_windows.grammar", "--lot", text, "-o", str(written)]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert err[-1] == f"shapegen: error: argument --lot: {text!r}: {ONE_LINE}"
    assert not written.exists()
    # the design page: a 422 naming "lot"
    with pytest.raises(RequestError) as refused:
        checked_lot([list(p) for p in BOW_TIE])
    assert (refused.value.status, str(refused.value)) == (422, f'"lot": {ONE_LINE}')
    # a city: the lot is a failed row with the line, the city goes on
    east_north = [(x, -z) for x, z in BOW_TIE]  # the city's origin: (0, 0), the square's centre
    city = city_from_polygons([east_north, [(-4, -4), (4, -4), (4, 4), (-4, 4)]])
    assert (city.lots[0].problem, city.lots[1].problem) == (ONE_LINE, None)
    # the library: the LotError itself
    with pytest.raises(LotError) as caught:
        parse_grammar("@StartRule\nLot --> extrude(1) X.\n").build(lot=BOW_TIE)
    assert str(caught.value) == ONE_LINE

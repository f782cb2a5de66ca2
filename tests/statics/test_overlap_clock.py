"""The overlap check of blocks that all overlap (n^2 / 2 intersections of a millisecond or two
each) looks at the work clock: judging stops at its clock in one line rather than running on
(201 overlapping blocks of a numbers-fuzz rule took 39 s past a 6 s clock)."""

from __future__ import annotations

import numpy as np
import pytest

from shapegen import Block, Model
from shapegen.errors import WorkLimitError
from shapegen.limits import work_clock, work_limits
from shapegen.model.packed import pack_blocks
from shapegen.statics.checks import overlapping_pairs
from shapegen.tolerances import DEFAULT


def _overlapping_boxes(count: int) -> Model:
    blocks = [Block.box(np.array([0.01 * k, 0.0, 0.0]), (1.0, 1.0, 1.0)) for k in range(count)]
    return Model(blocks)


def test_overlapping_blocks_are_found_without_a_clock():
    model = _overlapping_boxes(4)
    pairs, volumes, _ = overlapping_pairs(model, pack_blocks(model.blocks), DEFAULT)
    assert len(pairs) == 6 and np.all(volumes > 0.9)


def test_the_overlap_check_stops_at_the_work_clock():
    model = _overlapping_boxes(4)
    with work_limits(max_seconds=1e-9), work_clock("judging the model"):
        with pytest.raises(WorkLimitError, match="judging the model ran for more than"):
            overlapping_pairs(model, pack_blocks(model.blocks), DEFAULT)

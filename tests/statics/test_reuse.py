"""What a search carries from one analysis to the next: the forces of a design that stands with a
reserve, moved to the full joints, report it without the reserve (no second solve)."""

from __future__ import annotations

import numpy as np
import pytest

from shapegen.model.block import Block
from shapegen.model.model import Model
from shapegen.statics import StaticsOptions, analyze, certify
from shapegen.statics.reserve import widened_forces
from shapegen.structures import Design
from shapegen.structures.blocks import BlockStatics


def stack(overhang: float = 0.0, middle_width: float = 1.0, corbel: float | None = 0.0) -> Model:
    """Four 1 m blocks on the ground (three in a column, one beside the column's foot), the
    top one shifted by ``overhang`` m along x, the middle one ``middle_width`` wide, and a
    small corbel hung on the top block's side ``corbel`` m below its top (None: none)."""
    blocks = [
        Block.box((0.0, 0.0, 0.0), (1.0, 1.0, 1.0)),
        Block.box((0.0, 1.0, 0.0), (middle_width, 2.0, 1.0)),
        Block.box((overhang, 2.0, 0.0), (overhang + 1.0, 3.0, 1.0)),
        Block.box((1.0, 0.0, 0.0), (2.0, 0.5, 1.0)),
    ]
    if corbel is not None:
        blocks.append(
            Block.box((overhang + 1.0, 2.5 - corbel, 0.2), (overhang + 1.6, 3.0 - corbel, 0.8))
        )
    return Model(blocks, friction=0.7)


def test_forces_with_a_reserve_keep_each_joints_resultant_and_moment():
    model = stack(overhang=0.2, corbel=None)
    narrow = analyze(model, StaticsOptions().shrunk(0.3))
    assert narrow.feasible
    wide = analyze(model, StaticsOptions(), stood=narrow)
    assert wide.feasible
    assert wide.timings["solve"] == 0.0 and wide.timings["interfaces"] < 0.01
    assert wide.problem.kern == 1.0 and narrow.problem.kern == pytest.approx(0.7)
    np.testing.assert_allclose(wide.resultant_forces, narrow.resultant_forces, atol=1e-9)
    # the moment of the normal forces about the joint (their centre) is the same
    np.testing.assert_allclose(wide.resultant_points, narrow.resultant_points, atol=1e-9)
    x = (wide.forces / wide.problem.weight).T.ravel()
    assert certify(wide.problem, x) <= 1e-7
    fresh = analyze(model, StaticsOptions())
    assert fresh.feasible == wide.feasible
    assert np.all(wide.forces[:, 0] >= -1e-12)


def test_forces_are_moved_only_from_narrower_joints_of_the_same_model():
    model = stack(overhang=0.2, corbel=None)
    narrow = analyze(model, StaticsOptions().shrunk(0.3))
    wide = analyze(model, StaticsOptions())
    x = (narrow.forces / narrow.problem.weight).T.ravel()
    assert widened_forces(wide.problem, narrow.problem, x) is None  # wider to narrower
    other = analyze(
        stack(overhang=0.25, corbel=None), StaticsOptions(), stood=narrow
    )  # another model
    assert other.timings["solve"] > 0.0


def test_a_design_judged_with_a_reserve_is_reported_without_one_by_moving_its_forces():
    structure = BlockStatics()
    design = Design(model=stack(overhang=0.2, corbel=None))
    with_margin = structure.assess(design, margin=0.1)
    assert with_margin.stands
    without = structure.assess(design, margin=0.0)
    assert without.stands and without.detail.timings["solve"] == 0.0
    assert analyze(design.model).feasible
    # a design that does not stand is solved as usual
    leaning = Design(model=stack(overhang=0.2))  # with its corbel
    assert not structure.assess(leaning, margin=0.1).stands
    assert structure.assess(leaning, margin=0.0).detail.timings["solve"] > 0.0

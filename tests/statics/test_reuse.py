"""What a search carries from one analysis to the next: the adjoint's local update (only the
joints a step moved are found again) and the forces of a design that stands with a reserve,
moved to the full joints (no second solve)."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from shapegen.model.block import Block
from shapegen.model.model import Model
from shapegen.statics import GROUND, StaticsOptions, analyze, certify
from shapegen.statics.contacts import find_interfaces
from shapegen.statics.reserve import widened_forces
from shapegen.statics.sensitivity import infeasibility_change
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


def central_difference(make, value: float, step: float, options: StaticsOptions) -> float:
    above = analyze(make(value + step), options).infeasibility_normalized
    below = analyze(make(value - step), options).infeasibility_normalized
    return (above - below) / (2 * step)


@pytest.mark.parametrize(
    ("make", "value"),
    [
        # the top block and its corbel shift: the joint under the top block slides, the
        # corbel's joint moves with both its blocks and keeps its terms
        (lambda v: stack(overhang=v, corbel=0.1), 0.75),
        (lambda v: stack(overhang=0.75, corbel=0.1, middle_width=v), 1.0),  # a shape changes
    ],
    ids=["shift", "shape"],
)
def test_the_local_adjoint_matches_the_full_one_and_central_differences(make, value):
    options = StaticsOptions().shrunk(0.1)
    step = 1e-6
    base = analyze(make(value), options)
    assert not base.feasible and base.infeasibility_normalized > 0.01
    assert base.model is not None
    moved = make(value + step)
    local = infeasibility_change(base, moved, options)
    full = infeasibility_change(dataclasses.replace(base, model=None), moved, options)
    assert local is not None and full is not None
    assert local == pytest.approx(full, rel=1e-6)
    assert abs(local / step) > 0.1
    assert local / step == pytest.approx(central_difference(make, value, 1e-4, options), rel=5e-3)


@pytest.mark.parametrize(
    ("corbel", "moved_corbel"),
    [
        ((1.75, 2.5, 0.2), (1.75, 0.5, 0.2)),  # it grows down onto block 3: a joint appears
        ((1.75, 0.5, 0.2), (1.75, 2.5, 0.2)),  # it shrinks off block 3: a joint vanishes
    ],
)
def test_the_local_adjoint_refuses_a_step_that_changes_the_joints(corbel, moved_corbel):
    # the caller then takes a difference of whole analyses
    def model(low):
        built = stack(overhang=0.75)  # the top block tips
        built.blocks[4] = Block.box(low, (2.35, 3.0, 0.8))  # the corbel, hung on block 2
        return built

    options = StaticsOptions()
    base = analyze(model(corbel), options)
    assert not base.feasible and base.model is not None
    assert infeasibility_change(base, model(moved_corbel), options) is None
    assert infeasibility_change(dataclasses.replace(base, model=None), model(moved_corbel),
                                options) is None  # fmt: skip


def test_contacts_among_chosen_blocks_are_those_of_the_whole_search():
    model = stack(overhang=0.3)
    everything = find_interfaces(model)
    chosen = {1, 2, 4}
    some = find_interfaces(model, blocks=np.array(sorted(chosen)))
    expected = [
        i for i in everything if i.first in chosen and (i.second in chosen or i.second == GROUND)
    ]
    assert [(i.first, i.second) for i in some] == [(i.first, i.second) for i in expected]
    for a, b in zip(some, expected, strict=True):
        np.testing.assert_array_equal(a.vertices, b.vertices)


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

"""Judging's clock reaches the solvers: a solve started on a clock that has run out stops with
the clock's one-line error, and Clarabel is given the time left as its own ``time_limit``
(its iterations cannot look at the clock), whose ``MaxTime`` becomes the same error."""

from __future__ import annotations

import pytest
from statics_cases import running_bond_wall

from shapegen.errors import WorkLimitError
from shapegen.limits import remaining_seconds, work_clock, work_limits
from shapegen.statics import assemble, find_interfaces
from shapegen.statics.multiplier import load_multiplier
from shapegen.statics.solvers import BACKENDS, get_backend
from shapegen.statics.solvers.base import limit_time


def _wall_problem():
    model = running_bond_wall(courses=4, per_course=4)
    return model, assemble(model, find_interfaces(model))


@pytest.mark.parametrize("name", list(BACKENDS))
def test_every_backend_solves_within_a_clock_and_stops_past_it(name):
    if not get_backend(name).available():
        pytest.skip(f"the {name} back-end is not installed")
    _, problem = _wall_problem()
    with work_limits(max_seconds=60), work_clock("judging the model"):
        assert get_backend(name).solve(problem).status.solved
    with work_limits(max_seconds=1e-9), work_clock("judging the model"):
        with pytest.raises(WorkLimitError, match="judging the model ran for more than 1e-09 s"):
            get_backend(name).solve(problem)


def test_the_load_multiplier_stops_past_the_clock():
    model, problem = _wall_problem()
    assert load_multiplier(model, problem, 0.0).status == "limit"
    with work_limits(max_seconds=1e-9), work_clock("judging the model"):
        with pytest.raises(WorkLimitError, match="max_seconds"):
            load_multiplier(model, problem, 0.0)


def test_clarabel_is_given_the_time_left():
    class Settings:
        time_limit = float("inf")

    free = Settings()
    limit_time(free)  # no clock: Clarabel's own default, no limit
    assert free.time_limit == float("inf")
    timed = Settings()
    with work_limits(max_seconds=30), work_clock("judging the model"):
        limit_time(timed)
        assert 0 < timed.time_limit <= 30
        assert remaining_seconds() <= 30


def test_an_outer_clock_that_ends_first_is_named_with_the_inner_work():
    with work_limits(max_seconds=1e-9), work_clock("the build"), work_clock("judging", 60):
        with pytest.raises(WorkLimitError, match=r"the build \(judging\) ran for more than 1e-09"):
            get_backend("reduced").solve(_wall_problem()[1])

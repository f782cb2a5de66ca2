"""A solver that ends without an answer gives no verdict: the design is taken not to stand, and
the printout and the design page say the solver ended so, never a plain "no"."""

from __future__ import annotations

import io

import pytest
from rich.console import Console

from shapegen.cli.display import analysis_table
from shapegen.statics.solvers import SolveStatus
from shapegen.structures import UNJUDGED_STATUSES, Assessment


def printed(analysis: dict) -> str:
    out = io.StringIO()
    Console(file=out, width=200, highlight=False).print(analysis_table("m", analysis))
    return out.getvalue()


def report(status: str, stands: bool = False) -> dict:
    return {"structure": "blocks", "stands": stands, "measure": None, "status": status,
            "solver": "reduced", "blocks": 2, "interfaces": 1, "free_bodies": 2}  # fmt: skip


def test_the_unjudged_statuses_are_the_solver_outcomes_without_an_answer():
    unsolved = {s.value for s in SolveStatus if not s.solved and s is not SolveStatus.INFEASIBLE}
    assert UNJUDGED_STATUSES == unsolved


@pytest.mark.parametrize("status", sorted(UNJUDGED_STATUSES))
def test_an_unjudged_design_prints_unknown_not_no(status):
    text = printed(report(status))
    line = next(line for line in text.splitlines() if line.startswith("stands"))
    assert f"unknown: the solver ended with {status} (solver reduced)" in line, line
    assert " no " not in f"{line} "
    assert not Assessment("blocks", False, float("nan"), status).judged


@pytest.mark.parametrize("status, word", [("optimal", "no"), ("infeasible", "no")])
def test_a_solved_design_prints_its_verdict(status, word):
    line = next(line for line in printed(report(status)).splitlines() if line.startswith("stands"))
    assert line.split()[1] == word, line
    assert Assessment("blocks", False, float("inf"), status).judged

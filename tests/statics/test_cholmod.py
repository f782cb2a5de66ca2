"""CHOLMOD (through cvxopt) factors the reduced solver's normal equations: its solves against
dense ones, one analysis for many numeric factorisations, SuperLU for a matrix it refuses, and
the same verdicts as SuperLU on the bundled rules."""

from __future__ import annotations

import subprocess
import sys

import numpy as np
import pytest
from statics_cases import running_bond_wall
from test_reduced_factorization import (
    explicit_normal_matrix,
    random_local_inverses,
    random_spd_matrix,
    small_wall_problem,
)

import shapegen
from shapegen.errors import OptionError
from shapegen.statics import analyze, find_interfaces
from shapegen.statics.solvers import cholmod, pardiso
from shapegen.statics.solvers.normal_equations import NormalEquations, build_pattern
from shapegen.statics.solvers.reduced import ReducedBackend

pytestmark = pytest.mark.skipif(not cholmod.available(), reason="cvxopt is not installed")

MKL_INSTALLED = pardiso.available()


@pytest.fixture(autouse=True)
def default_install(monkeypatch):
    """These tests run as the default install does (cvxopt, no MKL), whatever this one has."""
    monkeypatch.setattr(pardiso, "available", lambda: False)


QUICK_RULES = ["arch_columns", "bezier_arches", "wall_windows", "tower", "barrel_vault", "mosque"]


def random_values_on(pattern, seed):
    """Random values on the normal equations' upper-triangle pattern that make a symmetric
    positive definite matrix (diagonally dominant), and that matrix, dense."""
    rng = np.random.default_rng(seed)
    values = rng.uniform(-1.0, 1.0, len(pattern.indices))
    full = np.abs(pattern.full_matrix(values).toarray())
    values[pattern.diagonal] = full.sum(axis=1) + rng.uniform(0.1, 1.0, pattern.size)
    return values, pattern.full_matrix(values).toarray()


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_the_factor_solves_like_a_dense_solve_on_the_normal_equations_pattern(seed):
    _, problem = small_wall_problem(5 + seed)
    pattern = build_pattern(problem)
    values, dense = random_values_on(pattern, seed)
    factor = cholmod.CholmodFactor(pattern.indptr, pattern.indices)
    factor.factor(values)
    rng = np.random.default_rng(10 + seed)
    one = rng.standard_normal(pattern.size)
    np.testing.assert_allclose(
        factor.solve(one), np.linalg.solve(dense, one), rtol=1e-9, atol=1e-12
    )
    several = rng.standard_normal((pattern.size, 3))
    solved = factor.solve(several)
    assert solved.shape == several.shape
    np.testing.assert_allclose(solved, np.linalg.solve(dense, several), rtol=1e-9, atol=1e-12)
    factor.close()


def test_the_assembled_normal_equations_are_solved_by_cholmod():
    _, problem = small_wall_problem()
    local = random_local_inverses(problem.n_vertices, seed=4)
    normal = NormalEquations(problem, "cholmod")
    assert normal.method == "cholmod"
    normal.assemble(local, 0.0)
    dense = explicit_normal_matrix(problem, local)
    rhs = np.random.default_rng(5).standard_normal(dense.shape[0])
    np.testing.assert_allclose(dense @ normal.solve(rhs), rhs, atol=1e-8 * np.abs(rhs).max())
    assert normal.fallbacks == 0
    normal.release()


def test_one_analysis_serves_several_numeric_factorisations():
    _, problem = small_wall_problem(6)
    pattern = build_pattern(problem)
    factor = cholmod.CholmodFactor(pattern.indptr, pattern.indices)
    analysis = factor._symbolic
    for seed in (3, 4):
        values, dense = random_values_on(pattern, seed)
        factor.factor(values)
        rhs = np.ones(pattern.size)
        np.testing.assert_allclose(dense @ factor.solve(rhs), rhs, atol=1e-10)
        factor.release_factor()
    assert factor._symbolic is analysis  # a small pattern keeps its analysis
    # the normal equations borrow the pattern's kept analysis, solve after solve
    first = NormalEquations(problem, "cholmod")
    kept = first._cholesky
    first.release()
    second = NormalEquations(problem, "cholmod")
    assert second._cholesky is kept
    second.release()


def test_a_large_pattern_frees_its_factor_and_analyses_again(monkeypatch):
    monkeypatch.setattr(cholmod, "_KEEP_ENTRIES", 0)
    _, problem = small_wall_problem(4)
    pattern = build_pattern(problem)
    factor = cholmod.CholmodFactor(pattern.indptr, pattern.indices)
    values, dense = random_values_on(pattern, 7)
    factor.factor(values)
    factor.release_factor()
    assert factor._symbolic is None
    with pytest.raises(cholmod.CholmodError, match="no numeric factor"):
        factor.solve(np.ones(pattern.size))
    factor.factor(2.0 * values)
    rhs = np.ones(pattern.size)
    np.testing.assert_allclose(2.0 * dense @ factor.solve(rhs), rhs, atol=1e-10)


def test_a_matrix_that_is_not_positive_definite_is_refused_and_the_factor_recovers():
    rng, n = np.random.default_rng(2), 40
    matrix, upper = random_spd_matrix(n, rng)
    factor = cholmod.CholmodFactor(upper.indptr, upper.indices)
    indefinite = upper.data.copy()
    indefinite[upper.indptr[n // 2]] = -1.0  # a negative diagonal entry
    with pytest.raises(cholmod.CholmodError, match="not positive definite"):
        factor.factor(indefinite)
    with pytest.raises(cholmod.CholmodError, match="no numeric factor"):
        factor.solve(np.ones(n))
    factor.factor(upper.data)
    rhs = rng.standard_normal(n)
    np.testing.assert_allclose(matrix @ factor.solve(rhs), rhs, atol=1e-10)


def test_an_indefinite_normal_matrix_falls_back_to_superlu():
    _, problem = small_wall_problem(4)
    local = random_local_inverses(problem.n_vertices, seed=6)
    local[: problem.n_vertices // 2] *= -1.0  # negative definite blocks: M is not definite
    normal = NormalEquations(problem, "cholmod")
    normal.assemble(local, 0.0)
    assert normal.fallbacks == 1 and normal._lu is not None
    dense = explicit_normal_matrix(problem, local)
    rhs = np.ones(dense.shape[0])
    np.testing.assert_allclose(dense @ normal.solve(rhs), rhs, atol=1e-7)
    normal.release()


@pytest.mark.parametrize("tilt, friction", [(0.0, 0.7), (12.0, 0.2)], ids=["stands", "slides"])
def test_refused_factorisations_give_superlus_verdict(monkeypatch, tilt, friction):
    model = running_bond_wall(9, tilt_degrees=tilt, friction=friction)
    interfaces = find_interfaces(model)
    with monkeypatch.context() as without_cvxopt:
        without_cvxopt.setattr(cholmod, "available", lambda: False)
        superlu = analyze(model, interfaces=interfaces, solver="reduced")

    def refuse(self, data):
        raise cholmod.CholmodError("CHOLMOD: the matrix is not positive definite (column 0)")

    monkeypatch.setattr(cholmod.CholmodFactor, "factor", refuse)
    count = counting_factorisations(monkeypatch)
    refused = analyze(model, interfaces=interfaces, solver="reduced")
    assert count[0] > 0  # every factorisation was asked of CHOLMOD, and refused
    assert refused.feasible == superlu.feasible == (tilt == 0.0)
    assert refused.infeasibility_normalized == pytest.approx(
        superlu.infeasibility_normalized, rel=1e-6, abs=1e-9
    )
    _, problem = small_wall_problem(9, tilt, friction)
    solution = ReducedBackend().solve(problem)
    assert solution.info["factorization"] == "cholmod"
    assert solution.info["factorization_fallbacks"] == solution.info["factorizations"] > 0


def counting_factorisations(monkeypatch) -> list[int]:
    """Count CHOLMOD's numeric factorisations from here on (the count in a one-item list)."""
    count = [0]
    factor = cholmod.CholmodFactor.factor

    def counted(self, data):
        count[0] += 1
        return factor(self, data)

    monkeypatch.setattr(cholmod.CholmodFactor, "factor", counted)
    return count


@pytest.mark.parametrize("rule", QUICK_RULES)
def test_the_bundled_rules_get_superlus_verdicts_and_values(monkeypatch, rule):
    model = shapegen.load_grammar(f"{rule}.grammar").build()
    interfaces = find_interfaces(model)
    count = counting_factorisations(monkeypatch)
    with_cholmod = analyze(model, interfaces=interfaces, solver="reduced")
    factored = count[0]
    assert factored > 0
    monkeypatch.setattr(cholmod, "available", lambda: False)  # "auto" is SuperLU without cvxopt
    with_superlu = analyze(model, interfaces=interfaces, solver="reduced")
    assert count[0] == factored  # SuperLU did every factorisation of the second analysis
    assert with_cholmod.status.solved and with_superlu.status.solved
    assert with_cholmod.feasible == with_superlu.feasible
    assert with_cholmod.infeasibility_normalized == pytest.approx(
        with_superlu.infeasibility_normalized, rel=1e-6, abs=1e-9
    )


def test_auto_is_pardiso_where_mkl_is_installed_else_cholmod_else_superlu(monkeypatch):
    _, problem = small_wall_problem(3)
    if MKL_INSTALLED:  # shapegen[pardiso]: the faster one
        monkeypatch.setattr(pardiso, "available", lambda: True)
        normal = NormalEquations(problem)
        assert normal.method == "pardiso"
        normal.release()
        monkeypatch.setattr(pardiso, "available", lambda: False)  # the default install
    normal = NormalEquations(problem)
    assert normal.method == "cholmod"
    normal.release()
    monkeypatch.setattr(cholmod, "available", lambda: False)
    normal = NormalEquations(problem)
    assert normal.method == "superlu" and normal._cholesky is None
    with pytest.raises(OptionError, match="needs cvxopt"):
        ReducedBackend(factorization="cholmod")


@pytest.mark.parametrize(
    "name, message",
    [
        ("mumps", "factorization must be one of auto, cholmod, pardiso, superlu; got 'mumps'"),
        ("pardiso", "factorization 'pardiso' needs Intel MKL, which is not installed"),
    ],
)
def test_a_factorisation_that_cannot_be_honoured_is_refused_in_one_line(monkeypatch, name, message):
    monkeypatch.setattr(pardiso, "available", lambda: False)
    for make in (lambda: ReducedBackend(factorization=name), lambda: NormalEquations(None, name)):
        with pytest.raises(OptionError) as refused:
            make()
        assert str(refused.value).startswith(message)
        assert "\n" not in str(refused.value)


def test_a_plain_import_and_a_solver_import_load_no_cvxopt():
    code = (
        "import sys, shapegen; from shapegen.statics.statics_options import StaticsOptions;"
        " StaticsOptions(); import shapegen.statics.solvers.reduced;"
        " print('cvxopt' in sys.modules)"
    )
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert done.stdout.strip() == "False"


def test_the_blas_hint_is_given_for_the_import_only_and_never_over_a_users_choice(monkeypatch):
    code = (
        "import os; from shapegen.statics.solvers import cholmod; cholmod.available();"
        " print('OPENBLAS_CORETYPE' in os.environ)"
    )
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert done.stdout.strip() == "False"
    monkeypatch.setenv("OPENBLAS_CORETYPE", "Prescott")
    assert cholmod._kernels_hint() is None


@pytest.mark.parametrize("courses, per_course", [(3, 4), (12, 10)])
def test_block_order_from_cvxopt_is_qdldls(courses, per_course, monkeypatch):
    # the normal equations' ordering comes from cvxopt's AMD; without cvxopt, QDLDL's
    from shapegen.statics.assembly import assemble
    from shapegen.statics.solvers import normal_equations

    model = running_bond_wall(courses=courses, per_course=per_course)
    problem = assemble(model, find_interfaces(model))
    starts = np.flatnonzero(np.diff(np.concatenate([[-1], problem.vertex_interface])))
    blocks = problem.vertex_blocks[starts]
    both = (blocks >= 0).all(axis=1)
    nf = problem.n_free
    rows = np.concatenate([blocks[both, 0], np.arange(nf)])
    columns = np.concatenate([blocks[both, 1], np.arange(nf)])
    from_cvxopt = normal_equations._block_ordering(rows, columns, nf)
    monkeypatch.setattr(cholmod, "minimum_degree_order", lambda *args: None)
    from_qdldl = normal_equations._block_ordering(rows, columns, nf)
    assert sorted(from_cvxopt.tolist()) == list(range(nf))
    np.testing.assert_array_equal(from_cvxopt, from_qdldl)

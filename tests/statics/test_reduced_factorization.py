"""The reduced solver's normal equations: the assembled M, CHOLMOD and PARDISO against SuperLU."""

from __future__ import annotations

import numpy as np
import pytest
import scipy.sparse as sp
from statics_cases import running_bond_wall

from shapegen.errors import OptionError
from shapegen.statics import find_interfaces
from shapegen.statics.assembly import assemble
from shapegen.statics.solvers import cholmod, pardiso
from shapegen.statics.solvers.normal_equations import NormalEquations
from shapegen.statics.solvers.reduced import ReducedBackend

needs_mkl = pytest.mark.skipif(not pardiso.available(), reason="MKL PARDISO is not installed")
needs_cvxopt = pytest.mark.skipif(not cholmod.available(), reason="cvxopt is not installed")
CHOLESKY = [
    pytest.param("cholmod", marks=needs_cvxopt),
    pytest.param("pardiso", marks=needs_mkl),
]


def small_wall_problem(courses=6, tilt_degrees=0.0, friction=0.7):
    model = running_bond_wall(courses, tilt_degrees=tilt_degrees, friction=friction)
    return model, assemble(model, find_interfaces(model))


def random_local_inverses(m, seed=0):
    """``(m, 3, 3)`` symmetric positive definite per-vertex blocks."""
    rng = np.random.default_rng(seed)
    root = rng.standard_normal((m, 3, 3))
    return root @ np.transpose(root, (0, 2, 1)) + 0.1 * np.eye(3)


def random_spd_matrix(n, rng):
    """A random sparse symmetric positive definite ``n x n`` matrix (CSR) and its upper
    triangle (CSR, indices sorted), the form the Cholesky bindings take."""
    root = sp.random(n, n, density=0.1, random_state=rng) + sp.eye(n)
    matrix = (root @ root.T + sp.eye(n)).tocsr()
    upper = sp.triu(matrix).tocsr()
    upper.sort_indices()
    return matrix, upper


def explicit_normal_matrix(problem, local):
    """``A D A^T`` with ``A`` the (c, u, t) columns of the equality matrix, built directly."""
    m = problem.n_vertices
    a = problem.equality.tocsc()
    columns = sp.hstack([a[:, 0:m], a[:, 2 * m : 3 * m], a[:, 3 * m : 4 * m]]).tocsc()
    # column order (group, vertex): D is block diagonal in (vertex, group) order
    order = (np.arange(3)[None, :] * m + np.arange(m)[:, None]).ravel()
    d = sp.block_diag(list(local), format="csc")
    a_v = columns[:, order]
    return (a_v @ d @ a_v.T).toarray()


@pytest.mark.parametrize("factorization", ["superlu", *CHOLESKY])
def test_normal_equations_solve_the_explicit_system(factorization):
    _, problem = small_wall_problem()
    local = random_local_inverses(problem.n_vertices)
    normal = NormalEquations(problem, factorization)
    normal.assemble(local, 0.0)
    dense = explicit_normal_matrix(problem, local)
    assert normal.method == factorization
    permutation = normal.pattern.permutation
    # the stored upper triangle reproduces the whole matrix once symmetrised
    full = normal.pattern.full_matrix(normal.values).toarray()
    np.testing.assert_allclose(full, dense[np.ix_(permutation, permutation)], atol=1e-12)
    rhs = np.random.default_rng(1).standard_normal(dense.shape[0])
    solution = normal.solve(rhs)
    np.testing.assert_allclose(dense @ solution, rhs, atol=1e-8 * np.abs(rhs).max())
    normal.release()


@needs_mkl
def test_pardiso_refactors_after_a_release_and_closes_once():
    rng, n = np.random.default_rng(2), 50
    matrix, upper = random_spd_matrix(n, rng)
    factor = pardiso.PardisoFactor(upper.indptr, upper.indices)
    rhs = rng.standard_normal(n)
    for scale in (1.0, 3.0):
        factor.factor(scale * upper.data)
        np.testing.assert_allclose(scale * (matrix @ factor.solve(rhs)), rhs, atol=1e-10)
        factor.release_factor()
    assert factor.factor_nonzeros >= upper.nnz
    factor.close()
    factor.close()


@pytest.mark.parametrize("cholesky", CHOLESKY)
@pytest.mark.parametrize(
    "tilt, friction",
    [(0.0, 0.7), (12.0, 0.2)],
    ids=["stands", "slides"],
)
def test_cholesky_and_superlu_give_the_same_answer(cholesky, tilt, friction):
    _, problem = small_wall_problem(9, tilt, friction)
    results = {}
    for factorization in (cholesky, "superlu"):
        for objective in ("tension_sum", "tension_squared"):
            backend = ReducedBackend(factorization=factorization)
            solution = backend.solve(problem.with_objective(objective))
            assert solution.status.solved
            assert solution.info["factorization"] == factorization
            results[factorization, objective] = solution.objective
    for objective in ("tension_sum", "tension_squared"):
        assert results[cholesky, objective] == pytest.approx(
            results["superlu", objective], rel=1e-6, abs=1e-9
        )


def test_an_unknown_factorization_is_refused():
    _, problem = small_wall_problem(2)
    with pytest.raises(OptionError, match="factorization must be one of"):
        NormalEquations(problem, "mumps")


def test_a_new_problem_on_the_same_block_graph_reuses_the_symbolic_analysis():
    _, first = small_wall_problem(5)
    _, second = small_wall_problem(5, tilt_degrees=3.0)  # same blocks, another load
    one, two = NormalEquations(first), NormalEquations(second)
    assert two.pattern.indices is one.pattern.indices
    assert two.pattern.analysis is one.pattern.analysis
    if one.method != "superlu":
        # the analysis is lent to one solve at a time: the second got a private copy
        assert two._cholesky is not one._cholesky
    local = random_local_inverses(first.n_vertices)
    for normal, problem in ((one, first), (two, second)):
        normal.assemble(local, 0.0)
        dense = explicit_normal_matrix(problem, local)
        rhs = np.ones(dense.shape[0])
        np.testing.assert_allclose(dense @ normal.solve(rhs), rhs, atol=1e-8)
        normal.release()
    _, other = small_wall_problem(6)
    third = NormalEquations(other)
    assert third.pattern.indices is not one.pattern.indices
    third.release()


def test_the_normal_pattern_is_the_sorted_set_of_every_contribution():
    # a wall on a fixed block, and a block touching nothing (its diagonal alone)
    from shapegen.model.block import Block
    from shapegen.model.model import Model
    from shapegen.statics.solvers.normal_equations import build_pattern

    wall = running_bond_wall(courses=3, per_course=3)
    blocks = [*wall.blocks, Block.box((9, 9, 9), (10, 10, 10))]
    blocks[1] = Block.box(
        blocks[1].vertices.min(axis=0), blocks[1].vertices.max(axis=0), fixed=True
    )
    model = Model(blocks, ground=0.0)
    problem = assemble(model, find_interfaces(model))
    pattern = build_pattern(problem)
    size = pattern.size
    # every (row, column) that an interface's 12 x 12 contribution writes, by brute force
    position = np.empty(problem.n_free, dtype=np.int64)
    position[pattern.permutation[::6] // 6] = np.arange(problem.n_free)
    entries = {(r, r) for r in range(size)}
    for first, second in problem.vertex_blocks[pattern.interface_starts]:
        rows = [6 * position[b] + k for b in (first, second) if b >= 0 for k in range(6)]
        entries |= {(r, c) for r in rows for c in rows if c >= r}
    expected = sorted(entries)
    rows = np.repeat(np.arange(size), np.diff(pattern.indptr))
    assert list(zip(rows.tolist(), pattern.indices.tolist(), strict=True)) == expected
    # and each contribution lands on its own (row, column)
    ni = len(pattern.interface_starts)
    local = np.arange(12)
    block_rows = problem.vertex_blocks[pattern.interface_starts][:, local // 6]
    all_rows = np.where(block_rows >= 0, 6 * position[np.maximum(block_rows, 0)] + local % 6, -1)
    r = np.broadcast_to(all_rows[:, :, None], (ni, 12, 12)).ravel()[pattern.source]
    c = np.broadcast_to(all_rows[:, None, :], (ni, 12, 12)).ravel()[pattern.source]
    np.testing.assert_array_equal(rows[pattern.target], r)
    np.testing.assert_array_equal(pattern.indices[pattern.target], c)
    assert np.all(pattern.indices[pattern.diagonal] == np.arange(size))

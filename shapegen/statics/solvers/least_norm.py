"""The least-norm forces: a candidate for the feasibility certificate that costs one factorisation.

Of all the vertex forces ``f = (n, u, t)`` (normal and two friction components, any sign) that
hold the free blocks in equilibrium, ``A f + w = 0``, the one of least Euclidean norm is
``f = A^T lam`` with ``(A A^T) lam = -w``: the reduced interior point method's normal equations
(:mod:`~shapegen.statics.solvers.normal_equations`) with the identity for ``D``, the same
pattern, ordering and symbolic analysis, assembled and factored once.

In a wall that stands comfortably (every joint's resultant well inside its polygon, friction
well inside the cone) these forces are compressive and within the cone everywhere, and so they
are a certificate of the kind phase one looks for: the analysis checks them with its own test
(:func:`~shapegen.statics.certificate.certify`, to ``tolerances.feasible_rel``) and, when it
holds, no interior point iteration runs. When it does not hold (a resultant near a joint's
edge, an arch's thrust, anything that does not stand) the interior point method runs as
before: the candidate never decides on its own, and costs one iteration's linear algebra.
Measured on running-bond walls: 2 000 bricks certified in one factorisation, where phase one
takes nine iterations; Cluny's default design (which needs tension) is not certified (its
residual is 6e-3 against 1e-7).
"""

from __future__ import annotations

__all__ = ["least_norm_forces"]

import numpy as np

from shapegen.statics.solvers.base import trivial_solution

# The shift added to the diagonal of ``A A^T``, relative to its mean: keeps a rank-deficient
# matrix (a block held in some direction by nothing) factorable; the refinement below removes
# its effect where ``A A^T`` is regular, and the certificate catches it where it is not.
_SHIFT = 1e-13
# Passes of iterative refinement on the exact product ``A A^T``: the residual of the first
# solve is ~1e-14 of the load on walls of 10 000 bricks; two passes leave it at round-off, far
# below the certificate's 1e-7.
_REFINEMENTS = 2


def least_norm_forces(problem, factorization: str = "auto") -> np.ndarray | None:
    """The least-norm equilibrium forces of ``problem``, as the QP's ``[c, s, u, t]`` (scaled,
    N / W): positive normal forces as compressions, negative ones as tensions. None when there
    is nothing to solve (no vertices or no free blocks) or the factorisation fails.

    Without friction (``mu = 0``) the friction components are left out of the fit (they could
    only be shrunk away by the certificate).
    """
    from shapegen.statics.solvers.normal_equations import NormalEquations

    if trivial_solution(problem) is not None:
        return None
    m = problem.n_vertices
    friction_weight = 1.0 if problem.friction > 0 else 0.0
    weights = np.array([1.0, friction_weight, friction_weight])
    local = np.zeros((m, 3, 3))
    local[:, [0, 1, 2], [0, 1, 2]] = weights
    # D on the four variable groups [c, s, u, t]: the normal force is carried by the c column
    # alone (the s column is its negative)
    diagonal = np.repeat(np.array([1.0, 0.0, friction_weight, friction_weight]), m)
    normal = NormalEquations(problem, factorization)
    try:
        normal.assemble(local, _SHIFT)
        lam = np.zeros(6 * problem.n_free)
        residual = -problem.load
        for _ in range(_REFINEMENTS + 1):
            lam += normal.solve(residual)
            x = diagonal * problem.transposed_product(lam)
            residual = -problem.load - problem.product(x)
    except (np.linalg.LinAlgError, RuntimeError, ValueError, FloatingPointError):
        return None
    finally:
        normal.release()
    if not np.all(np.isfinite(x)):
        return None
    normal_force = x[:m].copy()
    x[:m] = np.maximum(normal_force, 0.0)
    x[m : 2 * m] = np.maximum(-normal_force, 0.0)
    return x

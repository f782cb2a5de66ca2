"""When the tension-penalty QP alone shows that a design needs tension.

Phase one (the least sum of tensions) decides whether a design stands; far from standing it may
stop early, once its optimal value is certainly above ``PHASE_ONE_STOP``. A search judges mostly
designs that need tension, and for those the QP (the least sum of squared tensions, ``y``) is
solved anyway, for the measure and its multipliers. Since ``(sum s)^2 >= sum s^2`` for any
forces, a lower bound of ``y / W^2`` of ``PHASE_ONE_STOP ** 2`` proves what phase one's early stop
proves, and phase one need not run (``analyze(expect_tension=True)``).
"""

from __future__ import annotations

__all__ = ["PHASE_ONE_STOP", "QP_PROOF_FACTOR", "proves_tension"]

import numpy as np

from shapegen.statics.solvers import Solution, SolveStatus

PHASE_ONE_STOP = 1e-3  # scaled sum of tensions (of W) above which phase one may stop early

QP_PROOF_FACTOR = 2.0
"""An optimal objective (``y / W^2``) this many times ``PHASE_ONE_STOP ** 2`` proves the tension
when the back-end reports no duality gap: an optimal point's gap is a small share of its
objective (1e-8 of it plus 1e-9 for the reduced back-end), so a factor of ten leaves room."""


def proves_tension(qp: Solution, below: float = np.inf) -> bool:
    """True when the QP's solution ``qp`` proves that phase one's least sum of tensions is at
    least ``PHASE_ONE_STOP`` (always when its ``y / W^2`` is ``below`` or more: the caller
    trusts a screened phase one there). The bound is the objective less twice the duality gap
    (the factor 2 of phase one's stop) when the back-end reports its gap (``info["gap"]``),
    otherwise ``QP_PROOF_FACTOR`` on an optimal objective."""
    if not qp.status.solved or qp.x is None:
        return False
    m = len(qp.x) // 4
    tensions = float(np.sum(qp.x[m : 2 * m] ** 2))
    if tensions > below:
        return True
    if qp.status is not SolveStatus.OPTIMAL:
        return False
    gap = qp.info.get("gap")
    if gap is None:
        return tensions >= QP_PROOF_FACTOR * PHASE_ONE_STOP**2
    # the objective holds the minute regularisation of the other forces too: leave it out,
    # ten times over
    regularization = max(qp.objective - tensions, 0.0)
    return qp.objective - 2.0 * gap - 10.0 * regularization >= PHASE_ONE_STOP**2

"""The numerical libraries' threads: one per process unless the user chose otherwise.

OpenBLAS (which numpy and scipy load) starts one thread per core and keeps them spinning between
calls. shapegen's matrices are small (3-vectors, 4x4 transforms, a contact's few rows) or sparse
(the statics factorise with CHOLMOD's own code), so those threads save nothing and cost CPU:
measured on the 2-core machine, a 2 001-brick wall's ``shapegen analyze`` takes 0.86 CPU s on
one thread and 0.97 on two (the imports alone 0.28 against 0.46 s), a 4 096-sided disk's
``innerRectangle`` 0.64 against 1.01 CPU s at the same wall time. A command-line run therefore
asks for one thread before numpy loads, unless the user set any of the libraries' variables
(then all of them are left as given). City workers always run on one thread: they are the
parallelism.
"""

from __future__ import annotations

__all__ = ["ONE_THREAD", "one_thread_unless_chosen"]

import os
from collections.abc import MutableMapping

# The variables the numerical libraries read for their thread counts, each set to one.
ONE_THREAD = {
    name: "1"
    for name in (
        "OMP_NUM_THREADS",
        "MKL_NUM_THREADS",
        "OPENBLAS_NUM_THREADS",
        "NUMEXPR_NUM_THREADS",
        "VECLIB_MAXIMUM_THREADS",
    )
}


def one_thread_unless_chosen(environ: MutableMapping[str, str] = os.environ) -> bool:
    """Set every thread-count variable to one in ``environ`` unless the user set any; whether
    it did. Effective only before numpy is first imported."""
    if any(name in environ for name in ONE_THREAD):
        return False
    environ.update(ONE_THREAD)
    return True

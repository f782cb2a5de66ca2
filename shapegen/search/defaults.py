"""The search's defaults, in a module of their own so the command line can show them in its
help without loading the search (numpy, scipy, the grammar machinery)."""

from __future__ import annotations

__all__ = ["DEFAULT_MARGIN"]

# A search that asks for a design that stands asks for one with a reserve: every joint of a block
# structure shrunk to 90% of its size (the cable diameter limit lowered to 90% for a bridge). The
# papers stop on the feasibility boundary (margin 0), where nothing is left for what the statics
# does not model: Cluny optimized with margin 0 stands for the QP with --kern 0.99, fails it with
# --kern 0.95, and the rigid-body simulator brings it down within its settling window. 0.1 is the
# margin every bundled rule is simulated with (shapegen.simulation.SIMULATION_MARGIN).
DEFAULT_MARGIN = 0.1

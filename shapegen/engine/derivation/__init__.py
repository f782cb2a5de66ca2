"""The state of a derivation: the shapes being derived and the run's limits and reports
(:mod:`~.state`), the boundary for numbers that are not finite, CGA errors carried past, and the
queries of a shape about the others (occlusion, context)."""

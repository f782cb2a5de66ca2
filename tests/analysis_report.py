"""What every statics report holds, written by the library (``Analysis.to_report``) and by the
command line (``analyze --report``, and ``build --analyze`` under ``"analysis"``)."""

ANALYSIS_REPORT_KEYS = frozenset(
    {
        "blocks",
        "interfaces",
        "feasible",
        "infeasibility",
        "infeasibility_normalized",
        "max_tension",
        "total_weight",
        "seconds",
        "status",
        "solver",
        "timings",
    }
)

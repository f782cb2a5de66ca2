"""Statics: contact interfaces, the tension-penalty QP (Whiting et al. 2009) and its verdict, and
the lateral capacity (the largest tilt at which an assembly stands)."""

import importlib

_HOMES = {
    "Analysis": "shapegen.statics.analysis",
    "analyze": "shapegen.statics.analysis",
    "certify": "shapegen.statics.analysis",
    "StaticsProblem": "shapegen.statics.assembly",
    "assemble": "shapegen.statics.assembly",
    "friction_cone": "shapegen.statics.assembly",
    "Capacity": "shapegen.statics.capacity",
    "lateral_capacity": "shapegen.statics.capacity",
    "check_model": "shapegen.statics.checks",
    "find_interfaces": "shapegen.statics.contacts",
    "GROUND": "shapegen.statics.interface",
    "Interface": "shapegen.statics.interface",
    "tangent_frame": "shapegen.statics.interface",
    "StaticsOptions": "shapegen.statics.options",
    "SolveStatus": "shapegen.statics.solvers",
    "get_backend": "shapegen.statics.solvers",
}

__all__ = [
    "Analysis",
    "StaticsOptions",
    "analyze",
    "certify",
    "Capacity",
    "lateral_capacity",
    "StaticsProblem",
    "assemble",
    "friction_cone",
    "check_model",
    "find_interfaces",
    "GROUND",
    "Interface",
    "tangent_frame",
    "SolveStatus",
    "get_backend",
]


def __getattr__(name: str):
    # The names load with their modules on first use: importing the package for one light
    # module (its options, say) does not load them all, nor scipy behind them.
    module = _HOMES.get(name)
    if module is None:
        raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
    value = getattr(importlib.import_module(module), name)
    globals()[name] = value
    return value


def __dir__() -> list[str]:
    return sorted(set(globals()) | set(__all__))

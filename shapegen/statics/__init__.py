"""Statics: contact interfaces, the tension-penalty QP (Whiting et al. 2009) and its verdict, and
the lateral capacity (the largest tilt at which an assembly stands)."""

from shapegen.lazy_names import lazy_names

_HOMES = {
    "Analysis": "shapegen.statics.analysis",
    "analyze": "shapegen.statics.analysis",
    "certify": "shapegen.statics.certificate",
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
    "StaticsOptions": "shapegen.statics.statics_options",
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


__getattr__, __dir__ = lazy_names(__name__, _HOMES, __all__)

"""Statics: contact interfaces, the tension-penalty QP (Whiting et al. 2009) and its verdict, and
the lateral capacity (the largest tilt at which an assembly stands)."""

from shapegen.statics.analysis import Analysis, analyze, certify
from shapegen.statics.assembly import StaticsProblem, assemble, friction_cone
from shapegen.statics.capacity import Capacity, lateral_capacity
from shapegen.statics.checks import check_model
from shapegen.statics.contacts import find_interfaces
from shapegen.statics.interface import GROUND, Interface, tangent_frame
from shapegen.statics.options import StaticsOptions
from shapegen.statics.solvers import SolveStatus, get_backend

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

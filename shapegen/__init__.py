"""shapegen: procedural modeling of structures that stand up."""

from shapegen.engine import Block, Model, PointLoad, Scope
from shapegen.errors import (
    GeometryError,
    GrammarError,
    InputFormatError,
    ShapegenError,
    StaticsError,
)

__version__ = "0.1.0"

__all__ = [
    "Block",
    "GeometryError",
    "GrammarError",
    "InputFormatError",
    "Model",
    "PointLoad",
    "Scope",
    "ShapegenError",
    "StaticsError",
    "__version__",
]

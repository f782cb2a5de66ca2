"""shapegen: procedural modeling of structures that stand up."""

from shapegen.errors import (
    GeometryError,
    GrammarError,
    InputFormatError,
    ShapegenError,
    StaticsError,
)
from shapegen.model import Block, Model, PointLoad, Scope

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
    "bundled_rules",
    "load_grammar",
]


def __getattr__(name: str):
    # The grammar machinery (lark, the interpreter) loads on first use, not on `import shapegen`.
    if name in ("load_grammar", "bundled_rules"):
        from shapegen.engine import grammar_api

        return getattr(grammar_api, name)
    raise AttributeError(f"module 'shapegen' has no attribute {name!r}")

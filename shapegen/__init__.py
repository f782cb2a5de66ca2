"""shapegen: procedural modeling of structures that stand up."""

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
    "bundled_rules",
    "load_grammar",
    "parse_grammar",
]


def __getattr__(name: str):
    # The model (numpy) and the grammar machinery (lark, the interpreter) load on first use, not
    # on `import shapegen`, so the command's --help and its errors come at once.
    if name in ("load_grammar", "parse_grammar", "bundled_rules"):
        from shapegen.engine import grammar_api

        return getattr(grammar_api, name)
    if name in ("Block", "Model", "PointLoad", "Scope"):
        from shapegen import model

        return getattr(model, name)
    raise AttributeError(f"module 'shapegen' has no attribute {name!r}")

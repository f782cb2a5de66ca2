"""shapegen: procedural modeling of structures that stand up."""

__version__ = "0.1.0"

__all__ = [
    "Block",
    "GeometryError",
    "GrammarError",
    "InputFormatError",
    "Model",
    "OptionError",
    "PluginError",
    "PointLoad",
    "Scope",
    "ShapegenError",
    "StaticsError",
    "__version__",
    "bundled_rules",
    "load_grammar",
    "parse_grammar",
]


_ERRORS = (
    "GeometryError",
    "GrammarError",
    "InputFormatError",
    "OptionError",
    "PluginError",
    "ShapegenError",
    "StaticsError",
)


def __getattr__(name: str):
    # Everything loads on first use, not on `import shapegen`: the command's --help and its
    # errors come at once, and the command's start, before it can catch a Ctrl-C, runs no code.
    if name in _ERRORS:
        from shapegen import errors

        return getattr(errors, name)
    if name in ("load_grammar", "parse_grammar", "bundled_rules"):
        from shapegen.engine import grammar_api

        return getattr(grammar_api, name)
    if name in ("Block", "Model", "PointLoad", "Scope"):
        from shapegen import model

        return getattr(model, name)
    raise AttributeError(f"module 'shapegen' has no attribute {name!r}")

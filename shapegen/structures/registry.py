"""The registry of structures: the built-in ones and plug-ins, found by name.

A plug-in registers a third structure the way primitives are registered, with a class decorator
in a module that an installed package names in its entry-point group ``shapegen.structures``::

    @register_structure
    class Truss(Structure):
        name = "truss"
        ...
"""

from __future__ import annotations

__all__ = [
    "DEFAULT_STRUCTURE",
    "available_structures",
    "make_structure",
    "register_structure",
    "structure_class",
]

import difflib
from importlib.metadata import entry_points

from shapegen.errors import GeometryError, OptionError
from shapegen.structures.base import Structure

DEFAULT_STRUCTURE = "blocks"
"""The structure of a grammar without ``@Structure(...)``: rigid-block statics."""

REGISTRY: dict[str, type[Structure]] = {}
_discovered = False


def register_structure(cls: type[Structure] | None = None, *, replace: bool = False):
    """Class decorator: register a :class:`Structure` subclass under its ``name``.

    A name already taken is refused, naming who holds it, unless ``replace=True``.
    """

    def register(structure: type[Structure]) -> type[Structure]:
        if not (isinstance(structure, type) and issubclass(structure, Structure)):
            raise TypeError("register_structure decorates a subclass of Structure")
        name = getattr(structure, "name", None)
        if not isinstance(name, str) or not name:
            raise TypeError(f"{structure.__qualname__} needs a class attribute 'name'")
        taken = REGISTRY.get(name)
        if taken is not None and taken is not structure and not replace:
            raise GeometryError(
                f"structure {name!r} is already registered by "
                f"{taken.__module__}.{taken.__qualname__}; choose another name or pass "
                "replace=True"
            )
        REGISTRY[name] = structure
        return structure

    return register(cls) if cls is not None else register


def _discover() -> None:
    global _discovered
    if _discovered:
        return
    _discovered = True
    from shapegen.structures import blocks, cable  # noqa: F401  (register the built-in ones)

    for entry in entry_points(group="shapegen.structures"):
        try:
            entry.load()
        except Exception as exc:  # a broken plug-in must not break the built-in structures
            raise GeometryError(
                f"cannot load structures from {entry.value!r} (entry point {entry.name!r}): {exc}"
            ) from None


def structure_class(name: str | None) -> type[Structure]:
    """The structure registered as ``name`` (None: the default); the error suggests names."""
    _discover()
    name = DEFAULT_STRUCTURE if name is None else name
    if name not in REGISTRY:
        close = difflib.get_close_matches(str(name), list(REGISTRY), n=1)
        hint = f" (did you mean {close[0]!r}?)" if close else ""
        raise GeometryError(
            f"unknown structure {name!r}{hint}; known: {', '.join(available_structures())}"
        )
    return REGISTRY[name]


def available_structures() -> list[str]:
    """Names of every registered structure, sorted."""
    _discover()
    return sorted(REGISTRY)


def make_structure(name: str | None, options: object | None = None) -> Structure:
    """A structure ready to judge designs, with ``options`` (None: its defaults).

    Raises
    ------
    OptionError
        When ``options`` mean nothing for that structure (for example block-statics options for
        a design judged by its cables): refused, never dropped.
    """
    cls = structure_class(name)
    if options is not None and (
        cls.options_type is None or not isinstance(options, cls.options_type)
    ):
        raise OptionError(
            f"{type(options).__name__} does not apply to the structure {cls.name!r}"
            f" ({cls.description})"
        )
    return cls(options)

"""The registry of structures: the built-in ones and plug-ins, found by name.

A plug-in registers a third structure the way primitives are registered, with a class decorator
in a module that an installed package names in its entry-point group ``shapegen.structures``::

    @register_structure
    class Truss(Structure):
        name = "truss"
        ...
"""

from __future__ import annotations

__all__ = ["DEFAULT_STRUCTURE", "REGISTRY", "register_structure"]

from shapegen.errors import PluginError
from shapegen.structures.base import Structure

DEFAULT_STRUCTURE = "blocks"
"""The structure of a grammar without ``@Structure(...)``: rigid-block statics."""

REGISTRY: dict[str, type[Structure]] = {}


def register_structure(cls: type[Structure] | None = None, *, replace: bool = False):
    """Class decorator: register a :class:`Structure` subclass under its ``name``.

    A name already taken is refused, naming who holds it, unless ``replace=True``.
    """

    def register(structure: type[Structure]) -> type[Structure]:
        if not (isinstance(structure, type) and issubclass(structure, Structure)):
            raise PluginError("register_structure decorates a subclass of Structure")
        name = getattr(structure, "name", None)
        if not isinstance(name, str) or not name:
            raise PluginError(f"{structure.__qualname__} needs a class attribute 'name'")
        taken = REGISTRY.get(name)
        if taken is not None and taken is not structure and not replace:
            raise PluginError(
                f"structure {name!r} is already registered by "
                f"{taken.__module__}.{taken.__qualname__}; choose another name or pass "
                "replace=True"
            )
        REGISTRY[name] = structure
        return structure

    return register(cls) if cls is not None else register

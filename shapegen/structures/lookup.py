"""Finding structures by name: the built-in ones, then the plug-ins of the entry-point group
``shapegen.structures``, loaded on first use."""

from __future__ import annotations

__all__ = ["available_structures", "make_structure", "structure_class"]


from shapegen.plugins import find_registered, load_plugins
from shapegen.structures import blocks, cable, registry  # noqa: F401  (register the built-in ones)
from shapegen.structures.base import Structure
from shapegen.structures.registry import DEFAULT_STRUCTURE


def structure_class(name: str | None) -> type[Structure]:
    """The structure registered as ``name`` (None: the default); the error suggests names."""
    name = DEFAULT_STRUCTURE if name is None else name
    if name not in registry.REGISTRY:  # the installed plug-ins, looked for when first needed
        load_plugins("shapegen.structures", "structures")
    return find_registered(registry.REGISTRY, name, "structure")


def available_structures() -> list[str]:
    """Names of every registered structure, sorted."""
    load_plugins("shapegen.structures", "structures")
    return sorted(registry.REGISTRY)


def make_structure(name: str | None, options: object | None = None) -> Structure:
    """A structure ready to judge designs, with ``options`` (None: its defaults).

    Raises
    ------
    OptionError
        When ``name`` is not registered, or ``options`` mean nothing for that structure (for
        example block-statics options for a design judged by its cables): refused, never
        dropped.
    """
    return structure_class(name)(options)

"""Packages whose public names load with their modules on first use.

Importing a package for one light module (its options, say) then loads neither the others nor
scipy behind them, and the command's ``--help`` stays quick. A package says where each name
lives and takes the two module hooks (PEP 562)::

    _HOMES = {"analyze": "shapegen.statics.analysis", ...}
    __getattr__, __dir__ = lazy_names(__name__, _HOMES, __all__)
"""

from __future__ import annotations

__all__ = ["lazy_names"]

import importlib
import sys
from collections.abc import Callable, Iterable, Mapping


def lazy_names(
    package: str, homes: Mapping[str, str], public: Iterable[str]
) -> tuple[Callable[[str], object], Callable[[], list[str]]]:
    """The ``__getattr__`` and ``__dir__`` of ``package``: a name of ``homes`` is imported from
    its module (a full name, or one relative to the package) when first read, then kept."""
    public = tuple(public)

    def __getattr__(name: str) -> object:
        home = homes.get(name)
        if home is None:
            raise AttributeError(f"module {package!r} has no attribute {name!r}")
        module = home if home.startswith("shapegen.") else f"{package}.{home}"
        value = getattr(importlib.import_module(module), name)
        setattr(sys.modules[package], name, value)
        return value

    def __dir__() -> list[str]:
        return sorted(set(vars(sys.modules[package])) | set(public))

    return __getattr__, __dir__

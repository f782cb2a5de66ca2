"""Plug-ins: installed packages that add primitives or structures through an entry-point group,
and the lookup by name both registries share."""

from __future__ import annotations

__all__ = ["LOADED_GROUPS", "find_registered", "load_plugins"]

import difflib
from collections.abc import Mapping

from shapegen.errors import OptionError, PluginError

#: The entry-point groups whose plug-ins have been looked for (each is looked for once).
LOADED_GROUPS: set[str] = set()


def load_plugins(group: str, what: str) -> None:
    """Import every module named in the entry-point ``group`` (each registers its ``what``),
    the first time the group is asked for.

    A broken plug-in is one clear error naming it, not a failure of the built-in ones.
    """
    if group in LOADED_GROUPS:
        return
    LOADED_GROUPS.add(group)
    from importlib.metadata import entry_points  # 0.03 s: only when plug-ins are looked for

    for entry in entry_points(group=group):
        try:
            entry.load()
        except Exception as exc:
            raise PluginError(
                f"cannot load {what} from {entry.value!r} (entry point {entry.name!r}): {exc}"
            ) from None


def find_registered(registry: Mapping[str, object], name: str, what: str):
    """``registry[name]``; an unknown name is one error suggesting the closest registered one
    and listing them all."""
    if name not in registry:
        close = difflib.get_close_matches(str(name), list(registry), n=1)
        hint = f" (did you mean {close[0]!r}?)" if close else ""
        raise OptionError(
            f"unknown {what} {name!r}{hint}; available: {', '.join(sorted(registry))}"
        )
    return registry[name]

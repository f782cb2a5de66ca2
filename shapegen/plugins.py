"""Plug-ins: installed packages that add primitives or structures through an entry-point group."""

from __future__ import annotations

__all__ = ["load_plugins"]

from importlib.metadata import entry_points

from shapegen.errors import GeometryError


def load_plugins(group: str, what: str) -> None:
    """Import every module named in the entry-point ``group`` (each registers its ``what``).

    A broken plug-in is one clear error naming it, not a failure of the built-in ones.
    """
    for entry in entry_points(group=group):
        try:
            entry.load()
        except Exception as exc:
            raise GeometryError(
                f"cannot load {what} from {entry.value!r} (entry point {entry.name!r}): {exc}"
            ) from None

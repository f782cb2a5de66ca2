"""Plug-ins: installed packages that add primitives or structures through an entry-point group,
modules named for one run (``--plugin``), and the lookup by name both registries share."""

from __future__ import annotations

__all__ = [
    "LOADED_GROUPS",
    "PLUGINS_VARIABLE",
    "find_registered",
    "load_module",
    "load_plugins",
    "use_modules",
]

import os
from collections.abc import Iterable, Mapping
from pathlib import Path

from shapegen.errors import OptionError, PluginError, did_you_mean

#: The entry-point groups whose plug-ins have been looked for (each is looked for once).
LOADED_GROUPS: set[str] = set()
#: The modules named for this run (``--plugin``), separated by the platform's path separator:
#: an environment variable, so that the processes a run starts (a city's workers) load them too.
PLUGINS_VARIABLE = "SHAPEGEN_PLUGINS"
#: The entry-point group of each kind of plug-in, by the name its errors use.
GROUPS = {"primitive": "shapegen.primitives", "structure": "shapegen.structures"}
# Each module named for this run, imported once per process (a second import would register
# its primitives twice): its spec -> the module.
_LOADED_MODULES: dict[str, object] = {}


def load_plugins(group: str, what: str) -> None:
    """Import every module named in the entry-point ``group`` (each registers its ``what``),
    the first time the group is asked for, after the modules named for this run.

    A broken plug-in is one clear error naming it, not a failure of the built-in ones.
    """
    _load_listed_modules()
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


def use_modules(specs: Iterable[str]) -> None:
    """Import each of ``specs`` now (a module name, ``package.module``, or a ``.py`` file) and
    list it in :data:`PLUGINS_VARIABLE` for the processes this one starts: what ``--plugin``
    does, so that a primitive or structure of one's own is used without packaging it.

    A name that cannot be imported, a file that does not exist or fails is one
    :class:`PluginError` naming it.
    """
    listed = [s for s in os.environ.get(PLUGINS_VARIABLE, "").split(os.pathsep) if s]
    for spec in specs:
        spec = _resolved(spec)
        load_module(spec)
        if spec not in listed:
            listed.append(spec)
    if listed:
        os.environ[PLUGINS_VARIABLE] = os.pathsep.join(listed)


def load_module(spec: str):
    """The module ``spec`` names (a module name or a ``.py`` file), imported once per process;
    its decorators register its primitives and structures as it is imported."""
    spec = _resolved(spec)
    if spec in _LOADED_MODULES:
        return _LOADED_MODULES[spec]
    import importlib
    import importlib.util
    import sys
    import zlib

    if spec.endswith(".py"):
        path = Path(spec)
        if not path.is_file():
            raise PluginError(f"plug-in {spec}: no such file")
        # a name of its own, so that two files called piers.py in two folders do not clash
        name = f"shapegen_plugin_{path.stem}_{zlib.crc32(spec.encode()):08x}"
        found = importlib.util.spec_from_file_location(name, path)
        module = importlib.util.module_from_spec(found)
        sys.modules[name] = module
        try:
            found.loader.exec_module(module)
        except PluginError:
            sys.modules.pop(name, None)
            raise
        except Exception as exc:
            sys.modules.pop(name, None)
            raise PluginError(f"plug-in {spec}: {type(exc).__name__}: {exc}") from None
    else:
        try:
            module = importlib.import_module(spec)
        except ModuleNotFoundError as exc:
            if exc.name is not None and spec.startswith(exc.name):
                raise PluginError(
                    f"plug-in {spec!r}: no module named {exc.name!r} (give an importable"
                    " module name, or the path of a .py file)"
                ) from None
            raise PluginError(f"plug-in {spec!r}: {exc}") from None
        except PluginError:
            raise
        except Exception as exc:
            raise PluginError(f"plug-in {spec!r}: {type(exc).__name__}: {exc}") from None
    _LOADED_MODULES[spec] = module
    return module


def _resolved(spec: str) -> str:
    """A ``.py`` file's absolute path (the processes a run starts may work elsewhere), or the
    module name as given."""
    spec = spec.strip()
    if spec.endswith(".py") or os.sep in spec or (os.altsep and os.altsep in spec):
        return str(Path(spec).expanduser().resolve())
    return spec


def _load_listed_modules() -> None:
    """The modules :data:`PLUGINS_VARIABLE` lists (set by ``--plugin`` in this process or the
    one that started it), each imported once."""
    listed = os.environ.get(PLUGINS_VARIABLE)
    if listed:
        for spec in listed.split(os.pathsep):
            if spec and spec not in _LOADED_MODULES:
                load_module(spec)


def find_registered(registry: Mapping[str, object], name: str, what: str):
    """``registry[name]``; an unknown name is one error suggesting the closest registered one,
    listing them all, and saying how one of one's own is made known."""
    if name not in registry:
        hint = did_you_mean(name, registry, parenthesised=True)
        own = ""
        if what in GROUPS:
            own = (
                f"; a {what} of your own is found once its module is imported: --plugin"
                f" MODULE_OR_FILE.py on the command line, or an installed package's entry point in"
                f" the group {GROUPS[what]!r}"
            )
        raise OptionError(
            f"unknown {what} {name!r}{hint}; available: {', '.join(sorted(registry))}{own}"
        )
    return registry[name]

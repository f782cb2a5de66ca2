"""CityEngine's shape operations, one module per area of the language (extrusion, comp and its
kin, splits, transforms, appearance, roofs, setbacks...).

Each module registers its operations in :mod:`shapegen.engine.operations.registry`, the one-shape
form and, where it has one, the batch form side by side; the modules import the registry, never
this package. :func:`register_all` imports them all: the compiler imports those of the parser's
own nodes when it loads and the others the first time a rule names one it has not found, so a
rule file that uses none of them does not pay for importing them (shapely among them).
"""

from __future__ import annotations

__all__ = ["register_all"]


def register_all() -> None:
    """Import every module of the package, so that each registers its operations."""
    from shapegen.engine.operations.cga import (  # noqa: F401
        appearance,
        assets,
        extrusion,
        inline,
        modify,
        offset,
        perimeter,
        polygons,
        rectify,
        roofs,
        scatter,
        scope_fit,
        scope_ops,
        setbacks,
        split_area,
        splitting,
        tags,
        topology,
        transforms,
        uv_insert,
    )

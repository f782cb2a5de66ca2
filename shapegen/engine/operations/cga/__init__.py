"""CityEngine's shape operations, one module per area of the language (extrusion, comp and its
kin, splits, transforms, appearance, roofs, setbacks...).

Each module registers its operations in :mod:`shapegen.engine.operations.registry`, the one-shape
form and, where it has one, the batch form side by side; importing this package imports them
all. The modules import the registry, never this package.
"""

from __future__ import annotations

from shapegen.engine.operations.cga import (  # noqa: F401  (each registers its operations)
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
    tags,
    topology,
    transforms,
    uv_insert,
)

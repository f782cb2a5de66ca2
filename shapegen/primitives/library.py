"""Imports every built-in primitive module so that each registers itself."""

from shapegen.primitives import (
    arch,  # noqa: F401
    box,  # noqa: F401
    bridge,  # noqa: F401
    buttress,  # noqa: F401
    column,  # noqa: F401
    dome,  # noqa: F401
    vault,  # noqa: F401
    wall,  # noqa: F401
)

"""Imports every built-in primitive module so that each registers itself."""

from shapegen.primitives import box  # noqa: F401

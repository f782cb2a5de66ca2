"""The plain data of the mass model: blocks, scopes, models, loads and their packed arrays.

This package is the bottom of shapegen: it imports nothing of shapegen but ``errors`` and
``tolerances``, so the grammar engine, the primitives, the statics and the exporters can all use
it without importing each other.
"""

from shapegen.model.block import DEFAULT_DENSITY, Block
from shapegen.model.model import GRAVITY, STANDARD_GRAVITY, Model, PointLoad
from shapegen.model.scope import Scope

__all__ = ["Block", "DEFAULT_DENSITY", "GRAVITY", "STANDARD_GRAVITY", "Model", "PointLoad", "Scope"]

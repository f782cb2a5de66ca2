"""Model, blocks and scopes; the interpreter and search live in submodules of this package.

Only the plain data types are imported here so that lower layers (statics, primitives) can use
them without pulling in the interpreter.
"""

from shapegen.engine.block import DEFAULT_DENSITY, Block
from shapegen.engine.model import GRAVITY, Model, PointLoad
from shapegen.engine.scope import Scope

__all__ = ["Block", "DEFAULT_DENSITY", "GRAVITY", "Model", "PointLoad", "Scope"]

"""Shape operations compiled into closures: the operations with an AST node of their own
(:mod:`~.compiler`: rule bodies, split, comp, insert, transforms, ``set``) and CityEngine's
others, registered by name in :mod:`~.cga`."""

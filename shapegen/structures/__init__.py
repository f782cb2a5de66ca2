"""Structures: how a built design is judged to stand (rigid-block statics, cable model, plug-ins).

>>> from shapegen.structures import make_structure, available_structures
>>> available_structures()
['blocks', 'cable']
"""

from shapegen.statics.statics_options import Reserve
from shapegen.structures.base import (
    UNJUDGED_STATUSES,
    Assessment,
    Design,
    Structure,
    StructureArgument,
)
from shapegen.structures.lookup import available_structures, make_structure, structure_class
from shapegen.structures.registry import DEFAULT_STRUCTURE, register_structure

__all__ = [
    "Assessment",
    "DEFAULT_STRUCTURE",
    "Design",
    "Reserve",
    "Structure",
    "StructureArgument",
    "UNJUDGED_STATUSES",
    "available_structures",
    "make_structure",
    "register_structure",
    "structure_class",
]

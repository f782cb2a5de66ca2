"""The fixed vocabulary of the .grammar language: operations, builtins, selectors, annotations.

The parser, the load-time checks and the interpreter all read these tables, so that a name is
valid in exactly one place.
"""

from __future__ import annotations

__all__ = [
    "ANNOTATIONS",
    "BUILTIN_FUNCTIONS",
    "CENTER_MODES",
    "COMP_KINDS",
    "COMP_SELECTORS",
    "OPERATIONS",
    "RESERVED_ATTRIBUTES",
    "ROTATE_PIVOTS",
    "SHAPE_ATTRIBUTES",
    "SPLIT_AXES",
    "UNSUPPORTED_OPERATIONS",
]

#: Builtin functions: name -> (minimum, maximum) number of arguments. Angles in degrees, as CGA.
BUILTIN_FUNCTIONS: dict[str, tuple[int, int]] = {
    "sin": (1, 1),
    "cos": (1, 1),
    "tan": (1, 1),
    "asin": (1, 1),
    "acos": (1, 1),
    "atan": (1, 1),
    "atan2": (2, 2),
    "sqrt": (1, 1),
    "abs": (1, 1),
    "min": (2, 2),
    "max": (2, 2),
    "floor": (1, 1),
    "ceil": (1, 1),
    "rint": (1, 1),
    "pow": (2, 2),
    "exp": (1, 1),
    "ln": (1, 1),
    "log10": (1, 1),
    "rand": (0, 2),
    "str": (1, 1),
    "float": (1, 1),
    "bool": (1, 1),
}

#: Shape attributes readable in expressions: object -> fields.
SHAPE_ATTRIBUTES: dict[str, tuple[str, ...]] = {
    "scope": ("sx", "sy", "sz", "tx", "ty", "tz", "rx", "ry", "rz"),
    "split": ("index", "total"),
    "comp": ("index", "total"),
}

#: Operations recognised in rule bodies: name -> (minimum, maximum) positional arguments.
OPERATIONS: dict[str, tuple[int, int]] = {
    "extrude": (1, 1),
    "split": (1, 1),
    "comp": (1, 1),
    "t": (3, 3),
    "r": (3, 4),
    "s": (3, 3),
    "center": (1, 1),
    "label": (1, 1),
    "set": (2, 2),
    "i": (1, 1),
    "print": (1, 1_000_000),
    "report": (2, 2),
}

#: CityEngine operations shapegen does not implement: an error, not a silent leaf.
UNSUPPORTED_OPERATIONS: frozenset[str] = frozenset(
    {
        "alignScopeToAxes",
        "alignScopeToGeometry",
        "color",
        "convexify",
        "envelope",
        "footprint",
        "innerRectangle",
        "insertAlongUV",
        "mirror",
        "mirrorScope",
        "offset",
        "primitiveCube",
        "primitiveCylinder",
        "primitiveSphere",
        "projectUV",
        "reverseNormals",
        "roofGable",
        "roofHip",
        "roofPyramid",
        "roofShed",
        "rotateScope",
        "setback",
        "setupProjection",
        "splitArea",
        "taper",
        "texture",
        "tileUV",
        "trim",
    }
)

SPLIT_AXES: tuple[str, ...] = ("x", "y", "z")
COMP_KINDS: tuple[str, ...] = ("f",)
#: ``comp(f)`` selectors by name; a face index (``0 : A``, CGA's numeric selector) is valid too.
COMP_SELECTORS: tuple[str, ...] = (
    "front",
    "back",
    "left",
    "right",
    "top",
    "bottom",
    "side",
    "vertical",
    "horizontal",
    "all",
)
CENTER_MODES: tuple[str, ...] = ("x", "y", "z", "xy", "xz", "yz", "xyz")
#: First argument of ``r(pivot, x, y, z)`` -> pivot name in :class:`~shapegen.grammar.ast.Rotate`.
ROTATE_PIVOTS: dict[str, str] = {"scopeOrigin": "origin", "scopeCenter": "center"}

#: In an annotation's keywords: any keyword (``@Structure``'s are checked against the
#: structure's own arguments when the grammar is compiled).
ANY_KEYWORD = "*"

#: Annotations: name -> (minimum, maximum) positional arguments, allowed keywords.
#: ``Order``, ``Group``, ``Enum``, ``Color``, ``Angle``, ``Percent`` and ``Distance`` are CGA's
#: user-interface hints; they are accepted so that CGA files load, and have no effect.
ANNOTATIONS: dict[str, tuple[int, int, tuple[str, ...]]] = {
    "StartRule": (0, 0, ()),
    "Range": (0, 2, ("min", "max", "stepsize", "restricted")),
    "Hidden": (0, 0, ()),
    "Description": (1, 1, ()),
    "Free": (0, 0, ()),
    "Lot": (2, 2, ()),
    "Structure": (1, 1, (ANY_KEYWORD,)),  # ours: how the model is judged (shapegen.structures)
    "Order": (1, 1, ()),
    "Group": (1, 3, ()),
    "Enum": (0, 1_000_000, ("restricted",)),
    "Color": (0, 0, ()),
    "Angle": (0, 0, ()),
    "Percent": (0, 0, ()),
    "Distance": (0, 0, ()),
}


#: Attributes read at each leaf to set its block's properties; usable without an ``attr`` line.
#: ``density`` in kg/m^3, ``structural`` and ``fixed`` booleans.
RESERVED_ATTRIBUTES: dict[str, object] = {
    "density": 2400.0,
    "structural": True,
    "fixed": False,
}

"""The fixed vocabulary of the .grammar language: operations, builtins, selectors, annotations.

The parser, the load-time checks and the interpreter all read these tables, so that a name is
valid in exactly one place.
"""

from __future__ import annotations

__all__ = [
    "ANNOTATIONS",
    "BLOCK_OPERATIONS",
    "BUILTIN_FUNCTIONS",
    "UNSUPPORTED_FUNCTIONS",
    "CENTER_MODES",
    "CGA_OPERATIONS",
    "COMP_KINDS",
    "COMP_SELECTORS",
    "FUNCTION_KEYWORDS",
    "FUNCTION_SELECTOR_POSITIONS",
    "GEOMETRY_FUNCTIONS",
    "GEOMETRY_KEYWORDS",
    "LIBRARY_FUNCTIONS",
    "OPERATIONS",
    "OPERATION_KEYWORDS",
    "RESERVED_ATTRIBUTES",
    "SETTABLE_SHAPE_ATTRIBUTES",
    "ROTATE_PIVOTS",
    "SHAPE_ATTRIBUTES",
    "SHAPE_VALUES",
    "SPLIT_AXES",
]

_MANY = 1_000_000

#: Builtin functions: name -> (minimum, maximum) number of arguments. Angles in degrees, as CGA.
#: CityEngine's builtins (func_*.html) and its utility library (celib: strings, string lists,
#: files, colours); the interpreter reports at load time any it does not evaluate.
UNSUPPORTED_FUNCTIONS: dict[str, str] = {
    # CGA functions of the reference that shapegen does not evaluate: said as such, not as a
    # name nobody defined
}

BUILTIN_FUNCTIONS: dict[str, tuple[int, int]] = {
    # maths
    **{name: (1, 1) for name in ("sin", "cos", "tan", "asin", "acos", "atan", "sqrt", "abs")},
    **{name: (1, 1) for name in ("floor", "ceil", "rint", "exp", "ln", "log10")},
    **{name: (1, 1) for name in ("isinf", "isnan", "isInf", "isNaN")},
    "atan2": (2, 2),
    "pow": (2, 2),
    "min": (2, 2),
    "max": (2, 2),
    "clamp": (3, 3),
    # probability
    "rand": (0, 2),
    "p": (1, 1),
    # component tags: op_comp's selector (also in modify)
    "isTagged": (1, 2),
    # conversion
    "str": (1, 1),
    "float": (1, 1),
    "bool": (1, 1),
    "isNull": (1, 1),
    "boolArray": (0, 1),
    "floatArray": (0, 1),
    "stringArray": (0, 1),
    "sel": (1, 1),
    # strings
    "count": (2, 2),
    "find": (3, 3),
    "len": (1, 1),
    "substring": (3, 3),
    "splitString": (2, 2),
    "findFirst": (2, 3),
    "findLast": (2, 2),
    "getPrefix": (2, 2),
    "getSuffix": (2, 2),
    "getRange": (3, 3),
    "replace": (3, 3),
    "toUpperCase": (1, 1),
    "toLowerCase": (1, 1),
    # string lists ("a;b;c;")
    **{name: (1, 1) for name in ("listClean", "listFirst", "listLast", "listRandom")},
    **{name: (1, 1) for name in ("listSize", "listTerminate", "listToArray", "listFromArray")},
    **{name: (2, 2) for name in ("listAdd", "listCount", "listIndex", "listItem", "listRemove")},
    **{name: (2, 2) for name in ("listRemoveAll", "listRetainAll")},
    "listRange": (3, 3),
    # arrays
    "size": (1, 1),
    "nRows": (1, 1),
    "nColumns": (1, 1),
    "sum": (1, 1),
    "transpose": (1, 1),
    "sortIndices": (1, 1),
    "sortRowIndices": (1, 1),
    "setElems": (3, 4),
    # colours
    **{f"colorHexTo{c}": (1, 1) for c in "RGBOHSV"},
    "colorRGBToHex": (3, 3),
    "colorRGBOToHex": (4, 4),
    "colorHSVToHex": (3, 3),
    "colorHSVOToHex": (4, 4),
    "colorRamp": (2, 2),
    # files and assets (answered from the rule file's project folder)
    **{name: (1, 1) for name in ("fileExists", "fileSearch", "filesSearch", "fileRandom")},
    **{name: (1, 1) for name in ("fileBasename", "fileDirectory", "fileExtension", "fileName")},
    **{name: (1, 1) for name in ("readTextFile", "readFloatTable", "readStringTable")},
    "readMaterial": (1, 1),
    "assetInfo": (2, 2),
    "imageInfo": (2, 2),
    "assetMetadata": (3, 3),
    "assetNamingInfo": (2, 2),
    "assetNamingInfos": (2, 2),
    "assetsSortRatio": (2, 2),
    "assetsSortSize": (3, 3),
    "imagesSortRatio": (2, 2),
    "assetApproxRatio": (3, 3),
    "assetApproxSize": (3, 3),
    "assetBestRatio": (2, 2),
    "assetBestSize": (2, 2),
    "assetFitSize": (3, 3),
    "imageApproxRatio": (3, 3),
    "imageBestRatio": (2, 2),
    # occlusion and context
    "inside": (0, 2),
    "overlaps": (0, 2),
    "touches": (0, 2),
    "minimumDistance": (2, 2),
    "contextCompare": (3, 3),
    "contextCount": (2, 2),
    # miscellaneous
    "print": (1, 1),
    "convert": (4, 7),
    "getGeoCoord": (1, 1),
    "getTreeKey": (0, 0),
    "uid": (0, 0),  # the shape attribute deprecated in 2015.0 (cga_changelog), read as a call
    "getMaterial": (2, 2),
    "edgeAttr.getFloat": (1, 1),
    "edgeAttr.getString": (1, 1),
    "edgeAttr.getBool": (1, 1),
}

#: CityEngine's utility library (celib): a rule file may define a function of the same name,
#: which then replaces it.
LIBRARY_FUNCTIONS: frozenset[str] = frozenset(
    "assetApproxRatio assetApproxSize assetBestRatio assetBestSize assetFitSize clamp "
    "colorHSVOToHex colorHSVToHex colorHexToB colorHexToG colorHexToH colorHexToO "
    "colorHexToR colorHexToS colorHexToV colorRGBOToHex colorRGBToHex colorRamp "
    "fileBasename fileDirectory fileExtension fileName fileRandom findFirst findLast "
    "getPrefix getRange getSuffix imageApproxRatio imageBestRatio listAdd listClean "
    "listCount listFirst listFromArray listIndex listItem listLast listRandom listRange "
    "listRemove listRemoveAll listRetainAll listSize listTerminate listToArray max min "
    "replace toUpperCase toLowerCase".split()
)

_TARGETS = frozenset({"intra", "inter", "all"})  # of the occlusion and context queries
_RANKS = ("northernmost", "southernmost", "easternmost", "westernmost", "highest", "lowest")
#: Words a builtin takes as arguments besides values (``inside(intra)``, ``assetInfo(f, sx)``).
FUNCTION_KEYWORDS: dict[str, frozenset[str]] = {
    **dict.fromkeys(("inside", "overlaps", "touches", "minimumDistance", "contextCount"), _TARGETS),
    "contextCompare": _TARGETS | {f"world.{r}" for r in _RANKS} | {"area.largest", "area.smallest"},
    "assetInfo": frozenset({"sx", "sy", "sz", "tx", "ty", "tz"}),
    "imageInfo": frozenset({"sx", "sy"}),
    # the axes of the asset choosers' sorting functions (func_assetsSortSize...)
    **dict.fromkeys(
        ("assetsSortSize", "assetsSortRatio", "imagesSortRatio"),
        frozenset({"x", "y", "z", "xy", "xz", "yz", "yx", "zx", "zy", "xyz"}),
    ),
    "getGeoCoord": frozenset({"X", "Y", "lat", "lon"}),
    "isTagged": frozenset({"e", "v"}),  # op_comp: match the tags of the edges or vertices
    "getMaterial": frozenset({"used", "shape", "geometry", "changed", "all"}),
}

#: The argument positions where a builtin of :data:`FUNCTION_KEYWORDS` takes only a selector,
#: for the builtins where a value may stand at other positions: convert(component, from, to,
#: type, x, y, z) (func_convert) has selectors first and values after, so ``x`` there may be an
#: attr. At a selector position (every position of a builtin not listed) the keyword wins over
#: a parameter, attr, const or function of the same name: CGA has no selector values.
FUNCTION_SELECTOR_POSITIONS: dict[str, range] = {"convert": range(4)}

#: ``geometry.<name>``: CityEngine's geometry functions, read as ``geometry.area`` or
#: ``geometry.area()`` (with arguments where they take them): name -> (minimum, maximum).
GEOMETRY_FUNCTIONS: dict[str, tuple[int, int]] = {
    "angle": (1, 1),
    "area": (0, 1),
    "boundaryLength": (0, 0),
    "du": (0, 2),
    "dv": (0, 2),
    "groups": (0, 0),
    "hasTags": (0, 2),
    "hasUVs": (0, 1),
    "height": (0, 0),
    "isClosedSurface": (0, 0),
    "isConcave": (0, 0),
    "isInstanced": (0, 0),
    "isOriented": (1, 1),
    "isPlanar": (0, 1),
    "isRectangular": (0, 1),
    "materials": (0, 0),
    "nEdges": (0, 0),
    "nFaces": (0, 0),
    "nHoles": (0, 0),
    "nVertices": (0, 0),
    "tags": (0, 2),
    "uMax": (0, 1),
    "uMin": (0, 1),
    "vMax": (0, 1),
    "vMin": (0, 1),
    "volume": (0, 1),
}

#: Shape attributes readable in expressions: object -> fields (``material`` fields are those
#: of CityEngine's material catalogue, checked by the appearance compiler).
SHAPE_ATTRIBUTES: dict[str, tuple[str, ...]] = {
    "scope": ("sx", "sy", "sz", "tx", "ty", "tz", "rx", "ry", "rz", "elevation"),
    "split": ("index", "total"),
    "comp": ("index", "total", "sel"),
    "initialShape": (
        "name",
        "startRule",
        "symbol",  # deprecated: startRule
        *(f"origin.{k}" for k in ("px", "py", "pz", "ox", "oy", "oz")),
    ),
    "pivot": ("px", "py", "pz", "ox", "oy", "oz"),
    "trim": ("horizontal", "vertical"),
    "geometry": tuple(GEOMETRY_FUNCTIONS),
}
#: Shape attributes without a field (``seedian``).
SHAPE_VALUES: tuple[str, ...] = ("seedian",)

#: Every CityEngine operation (the reference's op_*.html): name -> (minimum, maximum) positional
#: arguments. Those without a node of their own in :mod:`shapegen.grammar.rule_bodies` become a
#: generic :class:`~shapegen.grammar.ast.Operation`; the interpreter reports any it has no
#: compiler for. ``union``, ``subtract`` and ``intersect`` (op_boolOp) take only a block.
CGA_OPERATIONS: dict[str, tuple[int, int]] = {
    "alignScopeToAxes": (0, 1),
    "alignScopeToGeometry": (2, 3),
    "alignScopeToGeometryBBox": (1, 1),
    "center": (1, 1),
    "cleanupGeometry": (0, 2),
    "color": (1, 4),
    "comp": (1, 2),
    "convexify": (0, 1),
    "copyUV": (2, 2),
    "deleteHoles": (0, 0),
    "deleteTags": (0, 2),
    "deleteUV": (1, 1),
    "envelope": (3, 10),  # 3, 5, 7, 9: the deprecated forms without a direction
    "extrude": (1, 2),
    "footprint": (0, 0),
    "i": (1, 4),
    "inline": (0, 1),
    "innerRect": (0, 0),
    "innerRectangle": (0, 1),
    "insertAlongUV": (3, 5),
    "intersect": (0, 1),  # (swap): the deprecated form before a rule, 2024.1
    "label": (1, 1),
    "mirror": (3, 3),
    "mirrorScope": (3, 3),
    "modify": (1, 2),
    "normalizeUV": (3, 3),
    "offsetUV": (3, 3),  # deprecated: translateUV
    "offset": (1, 2),
    "primitiveCone": (0, 3),
    "primitiveCube": (0, 3),
    "primitiveCylinder": (0, 3),
    "primitiveDisk": (0, 2),
    "primitiveQuad": (0, 2),
    "primitiveSphere": (0, 3),
    "print": (1, 1_000_000),
    "projectUV": (1, 1),
    "r": (3, 4),
    "rectify": (1, 1),
    "reduceGeometry": (1, 1),
    "report": (2, 2),
    "resetGeometry": (0, 0),
    "resetMaterial": (0, 1),
    "reverseNormals": (0, 0),
    "roofGable": (1, 5),
    "roofHip": (1, 4),
    "roofPyramid": (1, 2),
    "roofRidge": (2, 2),
    "roofShed": (1, 3),
    "rotate": (5, 5),
    "rotateScope": (3, 3),
    "rotateUV": (2, 2),
    "s": (3, 3),
    "scaleUV": (3, 3),
    "scatter": (3, 5),
    "set": (2, 2),
    "setMaterial": (1, 1),
    "setNormals": (1, 1),
    "setPivot": (2, 2),
    "setTagsFromEdgeAttrs": (0, 0),
    "setback": (1, 2),
    "setbackPerEdge": (1, 2),
    "setbackToArea": (1, 4),
    "setupProjection": (4, 7),
    "shapeL": (2, 2),
    "shapeO": (4, 4),
    "shapeU": (3, 3),
    "softenNormals": (1, 1),
    "split": (1, 3),  # split(axis, adjustMode) and the UV split(u|v, space, uvSet)
    "splitAndSetbackPerimeter": (1, 3),
    "splitArea": (1, 2),
    "subtract": (0, 1),
    "t": (3, 3),
    "tag": (1, 2),
    "taper": (1, 1),
    "texture": (1, 1),
    "tileUV": (3, 3),
    "translate": (5, 5),
    "translateUV": (3, 3),
    "trim": (0, 0),
    "union": (0, 1),
}

#: Operations that take a ``{ ... }`` block of branches (``selector : body | ...``).
BLOCK_OPERATIONS: frozenset[str] = frozenset(
    {
        "comp",
        "innerRectangle",
        "intersect",
        "inline",
        "modify",
        "offset",
        "scatter",
        "setback",
        "setbackPerEdge",
        "setbackToArea",
        "shapeL",
        "shapeO",
        "shapeU",
        "split",
        "splitAndSetbackPerimeter",
        "splitArea",
        "subtract",
        "union",
        "roofGable",
        "roofHip",
        "roofPyramid",
        "roofShed",
        "envelope",
        "taper",
        "footprint",
    }
)

#: Words that CityEngine operations take as arguments (axes, modes, selectors, enum values): a
#: bare name among these in an operation's arguments or a branch key is not an undefined name.
OPERATION_KEYWORDS: frozenset[str] = frozenset(
    {
        *("x", "y", "z", "xy", "xz", "yx", "yz", "zx", "zy", "xyz", "yzx", "zxy"),
        *("xUp", "yUp", "zUp", "xDown", "yDown", "zDown"),
        *(
            f"{frame}.{axes}"
            for frame in ("scope", "world")
            for axes in ("xy", "xz", "yx", "yz", "zx", "zy")
        ),
        *("world", "object", "scope", "pivot", "abs", "rel", "worldUp"),
        *(f"{frame}.{axis}" for frame in ("world", "object") for axis in ("x", "y", "z", "xyz")),
        *("world.lowest", "world.highest", "object.lowest", "object.highest"),
        *("largest", "longest", "shortest", "lowest", "highest", "smallest", "any"),
        *("adjust", "noAdjust"),
        *("f", "e", "v", "u", "fe", "fv", "g", "h", "m", "zUp", "noAlign"),
        *("separatePerFace", "collectiveAllFaces"),  # normalizeUV's modes
        *("streetSide", "noStreetSide", "streetFront"),  # deprecated selectors, still compiled
        *("inside", "border", "remainder", "shape", "all", "none", "keep", "remove"),
        "geometry",  # resetMaterial(geometry): the inserted asset's materials
        "center",  # scatter's gaussian mean (op_scatter: center, front, back...)
        *("front", "back", "left", "right", "top", "bottom", "side", "vertical", "horizontal"),
        *("aslant", "nutant", "nonaside", "street", "eave", "hip", "valley", "ridge"),
        *("face.normal", "vertex.normal", "world.up", "world.up.flatTop", "world.down"),
        *("world.south", "world.north", "world.east", "world.west", "world.side"),
        *(
            f"{frame}.{name}"
            for frame in ("object", "street")
            for name in ("front", "back", "left", "right", "side", "top", "bottom")
        ),
        *("streetSide", "streetFront"),
        *("scopeOrigin", "scopeCenter", "uniform", "gaussian", "uniformDistribution"),
        *("byAngle", "byHeight", "angle", "height", "keepFaces", "noCleanup", "cleanup"),
        *("hard", "soft", "auto", "conform", "faces", "edges", "vertices", "holes"),
        *("intra", "inter"),
        *("uv", "uvSpace", "index", "total", "unitSpace", "uvUniform"),
        *("separatePerFace", "collectiveAllFaces"),  # normalizeUV
        *("stretch", "fitArea", "keepSizeAndPosition", "alignSizeAndPosition"),
        *("keepSizeAlignPosition", "numericalCleanup"),  # i(asset, upAxis, mode, cleanup)
        *("append", "recompose", "unify"),  # inline's merge strategies
        *("extend", "default", "pos", "orient", "dir"),
        *("edge", "normal"),  # innerRectangle(edge), envelope(normal, ...)
        *("surface", "volume"),  # scatter(surface, 10, uniform)
        *("scope.y", "alignPosition", "keepPosition"),  # insertAlongUV's height direction
    }
)
FUNCTION_KEYWORDS["convert"] = OPERATION_KEYWORDS

#: Selectors the ``geometry.*`` functions take (``geometry.angle(maxSlope)``,
#: ``geometry.area(top)``, ``geometry.nVertices(world.up)``): read as their names.
GEOMETRY_KEYWORDS: frozenset[str] = OPERATION_KEYWORDS | {
    *("maxSlope", "azimuth", "zenith"),
    *("all", "faces", "edges", "vertices"),  # geometry.tags and geometry.hasTags
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
    "i": (1, 4),  # i(asset[, upAxis[, insertMode[, cleanupMode]]]); a template takes key=value
    "print": (1, 1_000_000),
    "report": (2, 2),
}

SPLIT_AXES: tuple[str, ...] = ("x", "y", "z")
COMP_KINDS: tuple[str, ...] = ("f", "e", "v", "fe", "fv", "g", "m", "h")
#: comp selectors by name (op_comp's list); a face index (``0 : A``) is valid too, and so are
#: ``||``, ``&&``, ``!`` of selectors and boolean conditions (parsed as a generic comp).
COMP_SELECTORS: tuple[str, ...] = (
    *("front", "back", "left", "right", "top", "bottom"),
    *("vertical", "horizontal", "aslant", "nutant", "side", "all"),
    *("inside", "border", "eave", "hip", "valley", "ridge"),
    *(f"object.{name}" for name in ("front", "back", "left", "right", "top", "bottom", "side")),
    *(f"world.{name}" for name in ("up", "down", "north", "south", "east", "west", "side")),
    *(f"street.{name}" for name in ("front", "back", "left", "right", "side")),
    *("streetSide", "noStreetSide", "streetFront", "aside", "nonaside"),
)
CENTER_MODES: tuple[str, ...] = ("x", "y", "z", "xy", "xz", "yz", "xyz")
#: First argument of ``r(pivot, x, y, z)`` -> pivot name in :class:`~shapegen.grammar.ast.Rotate`.
ROTATE_PIVOTS: dict[str, str] = {"scopeOrigin": "origin", "scopeCenter": "center"}

#: In an annotation's keywords: any keyword (``@Structure``'s are checked against the
#: structure's own arguments when the grammar is compiled).
ANY_KEYWORD = "*"

#: Annotations: name -> (minimum, maximum) positional arguments, allowed keywords.
#: Besides shapegen's own (``Free``, ``Lot``, ``Structure``) these are CityEngine's
#: (cga_annotations.html): user-interface hints accepted so that CGA files load, with no effect
#: beyond ``@StartRule``, ``@Range``, ``@Hidden`` and ``@Description``. In a ``.cga`` file an
#: annotation CityEngine does not know is ignored, as CityEngine does; in a ``.grammar`` file it
#: is an error.
ANNOTATIONS: dict[str, tuple[int, int, tuple[str, ...]]] = {
    "StartRule": (0, 0, ()),
    "Range": (0, _MANY, ("min", "max", "stepsize", "restricted")),
    "Hidden": (0, _MANY, ()),
    "Description": (1, 1, ()),
    "Free": (0, 0, ()),
    "Lot": (2, 2, ()),
    "Structure": (1, 1, (ANY_KEYWORD,)),  # ours: how the model is judged (shapegen.structures)
    "Order": (0, 1, ()),
    "Group": (0, _MANY, ()),
    "Enum": (0, _MANY, ("restricted", "valuesAttr")),
    "Color": (0, 0, ()),
    "Angle": (0, 0, ()),
    "Percent": (0, 0, ()),
    "Distance": (0, 0, ()),
    "File": (0, _MANY, ()),
    "Directory": (0, _MANY, ()),
    "MaterialFile": (0, _MANY, ()),
    "Handle": (0, _MANY, (ANY_KEYWORD,)),
    "InPlace": (0, 0, ()),
    "Location": (0, _MANY, (ANY_KEYWORD,)),
    "DisplayName": (1, 1, ()),
    "RuleFileDescription": (1, 1, ()),
    "Out": (0, _MANY, (ANY_KEYWORD,)),
    "InMesh": (0, 0, ()),
    "InPolygon": (0, 0, ()),
    "InLine": (0, 0, ()),
    "InPoint": (0, 0, ()),
    "InPointCloud": (0, 0, ()),
    "Macro": (0, _MANY, (ANY_KEYWORD,)),
    "Label": (0, _MANY, ()),
}


#: Attributes read at each leaf to set its block's properties; usable without an ``attr`` line.
#: ``density`` in kg/m^3, ``structural`` and ``fixed`` booleans.
#: Shape attributes that ``set()`` changes like an attr, with their value before any set
#: (attr_trim: horizontal trim planes are off by default, vertical ones on).
SETTABLE_SHAPE_ATTRIBUTES: dict[str, object] = {"trim.horizontal": False, "trim.vertical": True}

RESERVED_ATTRIBUTES: dict[str, object] = {
    "density": 2400.0,
    "structural": True,
    "fixed": False,
}

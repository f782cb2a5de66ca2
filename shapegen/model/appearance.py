"""What a shape looks like, and the leaves that are drawn but not judged.

:class:`Appearance` is what CGA's ``color``, ``texture``, ``set(material.*)`` and the UV
operations leave on a shape; it is carried to the blocks and surfaces of the model and from
there to the export (glTF materials), and never changes the statics.

:class:`Surface` is a leaf of a derivation that is not a block: a face (a roof plane, a
``comp(f)`` face left as a leaf), an open mesh (an asset), or a closed solid that is not
convex (an L-shaped footprint extruded), kept as derived. Surfaces are kept for display and
export, and ``reason`` says why a surface is not a block. The statics judge blocks, and stand
in for some surfaces when they judge (``shapegen.statics.standins``): a solid's
:class:`SolidLeaf` says what it is made of and where it was derived, so its convex parts are
cut then, and only then.
"""

from __future__ import annotations

__all__ = [
    "Appearance",
    "DEFAULT_APPEARANCE",
    "MATERIAL_ATTRIBUTES",
    "SolidLeaf",
    "Surface",
    "changed",
    "with_uv",
    "material_value",
    "parse_hex_color",
    "with_material",
]

import re
from dataclasses import dataclass, field
from dataclasses import fields as dataclass_fields

import numpy as np

from shapegen.model.polygons import checked_faces


@dataclass(frozen=True)
class Appearance:
    """A shape's look.

    Attributes
    ----------
    color
        Base colour as sRGB ``(r, g, b)`` in [0, 1], or None for the default.
    opacity
        In [0, 1]; 1 is opaque.
    texture
        The colour map's file name (``texture("brick.jpg")``), or None.
    material
        Every other ``material.*`` attribute set on the shape: ``name -> value``.
    uv
        The UV set-up of the shape, as the operations left it: ``(operation, arguments)``
        pairs in the order they ran (``("setupProjection", (0, "scope.xy", 2.0, 1.0, 0.0,
        0.0, 0.0))``, ``("scaleUV", (0, 2.0, 2.0))``...), the first argument the uv-set;
        kept so that an export can use it.
    normals
        The shading of the geometry's normals: ``"hard"``, ``"soft"``, ``"auto"``,
        ``"conform"``, a crease angle in degrees (``softenNormals``), or None for the default.
    """

    color: tuple[float, float, float] | None = None
    opacity: float = 1.0
    texture: str | None = None
    material: tuple[tuple[str, object], ...] = ()
    uv: tuple[tuple[str, object], ...] = ()
    normals: str | float | None = None

    @property
    def is_default(self) -> bool:
        """True when nothing was set: the shape looks as if no appearance operation ran."""
        return self == DEFAULT_APPEARANCE

    def to_dict(self) -> dict:
        """The appearance as plain JSON types; only what differs from the default."""
        out: dict = {}
        if self.color is not None:
            out["color"] = [float(c) for c in self.color]
        if self.opacity != 1.0:
            out["opacity"] = float(self.opacity)
        if self.texture is not None:
            out["texture"] = self.texture
        if self.material:
            out["material"] = {name: value for name, value in self.material}
        if self.uv:
            out["uv"] = [[name, list(arguments)] for name, arguments in self.uv]
        if self.normals is not None:
            out["normals"] = self.normals
        return out

    @classmethod
    def from_dict(cls, document: dict) -> Appearance:
        """The inverse of :meth:`to_dict` (values are checked by the file readers)."""
        color = document.get("color")
        return cls(
            color=None if color is None else tuple(float(c) for c in color),
            opacity=float(document.get("opacity", 1.0)),
            texture=document.get("texture"),
            material=tuple((str(k), v) for k, v in (document.get("material") or {}).items()),
            uv=tuple((str(name), tuple(arguments)) for name, arguments in document.get("uv", [])),
            normals=document.get("normals"),
        )


DEFAULT_APPEARANCE = Appearance()


_MAPS = (
    "colormap",
    "bumpmap",
    "dirtmap",
    "specularmap",
    "opacitymap",
    "normalmap",
    "emissivemap",
    "occlusionmap",
    "roughnessmap",
    "metallicmap",
)


def _catalogue() -> dict[str, tuple[type, object]]:
    """``name -> (type, default)`` of every ``material.*`` attribute of CityEngine's reference
    (attr_material), without the ``material.`` prefix."""
    attributes: dict[str, tuple[type, object]] = {
        "name": (str, ""),
        "shader": (str, "CityEngineShader"),
        "color.rgb": (str, "#ffffff"),
        "opacity": (float, 1.0),
        "reflectivity": (float, 0.0),
        "shininess": (float, 1.0),
        "bumpValue": (float, 1.0),
        "metallic": (float, 0.0),
        "roughness": (float, 1.0),
        "doubleSided": (bool, True),
        "opacitymap.mode": (str, "blend"),
        "opacitymap.cutoff": (float, 0.5),
    }
    channels = (("color", 1.0), ("ambient", 0.0), ("specular", 0.0), ("emissive", 0.0))
    for channel, default in channels:
        for component in "rgb":
            attributes[f"{channel}.{component}"] = (float, default)
    for texture_map in _MAPS:
        attributes[texture_map] = (str, "")
        for key, default in (("su", 1.0), ("sv", 1.0), ("tu", 0.0), ("tv", 0.0), ("rw", 0.0)):
            attributes[f"{texture_map}.{key}"] = (float, default)
    return attributes


MATERIAL_ATTRIBUTES: dict[str, tuple[type, object]] = _catalogue()
"""``name -> (type, default)`` of the ``material.*`` attributes (names without the prefix)."""

_OPACITY_MODES = ("blend", "mask", "opaque")
_HEX = re.compile(r"#([0-9a-fA-F]{6})([0-9a-fA-F]{2})?")


def parse_hex_color(text: str) -> tuple[tuple[float, float, float], float | None]:
    """``"#rrggbb"`` or ``"#rrggbboo"`` as ``((r, g, b), opacity or None)`` in [0, 1].

    Raises ``ValueError`` with a message for the user on any other text.
    """
    match = _HEX.fullmatch(text.strip())
    if match is None:
        raise ValueError(f'a colour is "#rrggbb" or "#rrggbboo" in hexadecimal, got {text!r}')
    digits = match.group(1)
    rgb = tuple(int(digits[k : k + 2], 16) / 255.0 for k in (0, 2, 4))
    opacity = int(match.group(2), 16) / 255.0 if match.group(2) else None
    return rgb, opacity  # type: ignore[return-value]


def _hex(rgb: tuple[float, float, float]) -> str:
    return "#" + "".join(f"{round(255 * c):02x}" for c in rgb)


def _clamped(value: float) -> float:
    return min(max(value, 0.0), 1.0)


def material_value(appearance: Appearance | None, name: str) -> object:
    """The value of ``material.<name>`` on a shape whose appearance is ``appearance`` (None:
    the default), as CGA reads it: a float, a string or a boolean.

    Raises ``KeyError`` for a name that is not a material attribute.
    """
    kind, default = MATERIAL_ATTRIBUTES[name]
    look = appearance or DEFAULT_APPEARANCE
    if name.startswith("color."):
        rgb = look.color or (1.0, 1.0, 1.0)
        return _hex(rgb) if name == "color.rgb" else rgb["rgb".index(name[-1])]
    if name == "opacity":
        return look.opacity
    if name == "colormap":
        return look.texture or ""
    return dict(look.material).get(name, default)


# The appearances made from others: a rule's leaves run the same chain of colour, texture and
# material writes on the same looks, so each change is made once. Keyed by the look's id and
# the change (the look kept in the value, so an id is not reused while its entry lives).
_CHANGES: dict[tuple, tuple[Appearance, Appearance]] = {}
_CHANGES_KEPT = 4096
_FIELDS = frozenset(f.name for f in dataclass_fields(Appearance))


def _replaced(look: Appearance, fields: dict) -> Appearance:
    """``dataclasses.replace(look, **fields)`` for these fields of a frozen dataclass without
    ``__post_init__``: the same object, without replace()'s walk over the fields, which cost
    most of a new look (every setupProjection of a new scope size makes one)."""
    unknown = fields.keys() - _FIELDS
    if unknown:
        raise TypeError(f"Appearance has no field {sorted(unknown)[0]!r}")
    new = object.__new__(Appearance)
    state = new.__dict__
    state.update(look.__dict__)
    state.update(fields)
    return new


def _remembered(look: Appearance, change: tuple, make) -> Appearance:
    key = (id(look), *change)
    kept = _CHANGES.get(key)
    if kept is not None and kept[0] is look:
        return kept[1]
    new = make()
    if len(_CHANGES) >= _CHANGES_KEPT:
        _CHANGES.clear()
    _CHANGES[key] = (look, new)
    return new


def changed(appearance: Appearance | None, **fields) -> Appearance:
    """``appearance`` (None: the default) with ``fields`` replaced, as
    :func:`dataclasses.replace` gives it; the same change of the same look is made once."""
    look = appearance or DEFAULT_APPEARANCE
    # repr tells 0.0 from -0.0 and 1 from 1.0 and True, which a key of values would not
    change = tuple((name, repr(value)) for name, value in fields.items())
    return _remembered(look, change, lambda: _replaced(look, fields))


def with_uv(appearance: Appearance | None, entry: tuple) -> Appearance:
    """``appearance`` (None: the default) with ``entry`` added to its UV log."""
    look = appearance or DEFAULT_APPEARANCE
    return _remembered(
        look, ("uv", repr(entry)), lambda: _replaced(look, {"uv": look.uv + (entry,)})
    )


def with_material(appearance: Appearance | None, name: str, value: object) -> Appearance:
    """``appearance`` (None: the default) with ``material.<name>`` set to ``value``, whose type
    has been checked. Colour components and the opacity are clamped to [0, 1].

    Raises ``ValueError`` with a message for the user for a value CityEngine refuses (a
    malformed ``color.rgb``, an unknown ``opacitymap.mode``).
    """
    look = appearance or DEFAULT_APPEARANCE
    return _remembered(
        look, ("material", name, repr(value)), lambda: _with_material(look, name, value)
    )


def _with_material(look: Appearance, name: str, value: object) -> Appearance:
    if name.startswith("color."):
        rgb = list(look.color or (1.0, 1.0, 1.0))
        if name == "color.rgb":
            rgb, _ = parse_hex_color(value)  # type: ignore[arg-type]
        else:
            rgb["rgb".index(name[-1])] = _clamped(value)  # type: ignore[arg-type]
        return _replaced(look, {"color": tuple(rgb)})
    if name == "opacity":
        return _replaced(look, {"opacity": _clamped(value)})  # type: ignore[arg-type]
    if name == "colormap":
        return _replaced(look, {"texture": value or None})
    if name == "opacitymap.mode" and value not in _OPACITY_MODES:
        raise ValueError(
            f"material.opacitymap.mode is one of {', '.join(_OPACITY_MODES)}, got {value!r}"
        )
    material = tuple((key, old) for key, old in look.material if key != name)
    return _replaced(look, {"material": material + ((name, value),)})


@dataclass(frozen=True, eq=False)
class SolidLeaf:
    """What the statics need of a closed solid leaf the derivation kept as derived.

    Attributes
    ----------
    density
        kg/m^3, the leaf's ``density`` attr.
    structural, fixed
        The leaf's ``structural`` and ``fixed`` attrs.
    local, rotation, origin
        The leaf's mesh in its scope's coordinates and the scope's ``(3, 3)`` rotation and
        origin (m), where it is cut into convex parts (the same shape placed anywhere and at
        any size is cut once); None for a solid read from a file, which is cut where it is.
        Not written to files.
    """

    density: float
    structural: bool = True
    fixed: bool = False
    local: object = None
    rotation: np.ndarray | None = None
    origin: np.ndarray | None = None


@dataclass
class Surface:
    """A leaf drawn but not judged: a polygon mesh with its look and its origin.

    Attributes
    ----------
    vertices
        ``(k, 3)`` positions, metres (y up).
    faces
        Polygons as vertex-index tuples, counter-clockwise seen from their front.
    appearance
        Its look.
    tags
        Labels from ``label(...)``.
    rule_path
        The chain of rules that produced it.
    reason
        Why it is not a block, in words: ``"a face (no volume)"``, ``"not convex"``,
        ``"not closed"``...
    solid
        For a closed solid leaf kept as derived (``"not convex"``), its density, flags and
        scope (:class:`SolidLeaf`); None otherwise.
    polygons
        For a leaf whose faces have holes, its faces as CityEngine has them: each face's outer
        ring, then every face's holes, as vertex-index tuples over ``vertices`` (what PyPRT's
        encoder writes). ``faces`` are then polygons without holes covering the same surface,
        which the exports, pictures and statics take. None otherwise.
    """

    vertices: np.ndarray
    faces: tuple[tuple[int, ...], ...]
    appearance: Appearance = DEFAULT_APPEARANCE
    tags: tuple[str, ...] = ()
    rule_path: tuple[str, ...] = ()
    reason: str = ""
    id: str = ""
    extras: dict = field(default_factory=dict)
    solid: SolidLeaf | None = None
    polygons: tuple[tuple[int, ...], ...] | None = None

    def __post_init__(self) -> None:
        self.vertices = np.ascontiguousarray(self.vertices, dtype=float).reshape(-1, 3)
        self.faces = checked_faces(self.faces)
        self.tags = tuple(self.tags)
        self.rule_path = tuple(self.rule_path)

    def to_dict(self) -> dict:
        """The surface as a shapegen-blocks JSON object (see docs/formats.md)."""
        out: dict = {
            "id": self.id,
            "vertices": self.vertices.tolist(),
            "faces": [list(face) for face in self.faces],
            "reason": self.reason,
            "tags": list(self.tags),
        }
        if self.rule_path:
            out["rule_path"] = list(self.rule_path)
        if self.solid is not None:
            out["density"] = self.solid.density
            out["structural"] = self.solid.structural
            out["fixed"] = self.solid.fixed
        look = (self.appearance or DEFAULT_APPEARANCE).to_dict()
        if look:
            out["appearance"] = look
        return out

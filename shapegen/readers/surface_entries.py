"""The surface and appearance entries of a shapegen-blocks JSON document, read and checked.

A block model's surfaces (the leaves drawn but not judged) and every item's appearance are
written by :mod:`shapegen.export.blocks_json`; here they are read back, every value checked,
each mistake one :class:`~shapegen.errors.InputFormatError` line naming the entry.
"""

from __future__ import annotations

__all__ = ["SURFACE_GROUP", "SURFACE_ROLE", "appearance_from_entry", "surface_from_entry"]

from shapegen.errors import InputFormatError
from shapegen.model.appearance import Appearance, SolidLeaf, Surface
from shapegen.readers.json_fields import number, points, strings

SURFACE_ROLE = "surface"
"""The ``role`` in the glTF node extras of a surface (blocks have ``"block"``)."""
SURFACE_GROUP = "surface:"
"""Prefix of the OBJ group (or any mesh node) name of a surface: read back as a surface."""


def surface_from_entry(entry: object, k: int) -> Surface:
    """A :class:`Surface` from its shapegen-blocks JSON entry (``surfaces[k]``), every value
    checked."""
    where = f"surfaces[{k}]"
    if not isinstance(entry, dict):
        raise InputFormatError(f"{where} must be an object")
    surface_id = entry.get("id") or f"s{k}"
    if not isinstance(surface_id, str):
        raise InputFormatError(f'{where}: "id" must be a string')
    where = f"surface {surface_id!r}"
    vertices = points(entry.get("vertices"), f'{where}: "vertices"')
    faces = entry.get("faces", [])
    if not isinstance(faces, list) or not all(
        isinstance(f, list)
        and len(f) >= 3
        and all(
            isinstance(i, int) and not isinstance(i, bool) and 0 <= i < len(vertices) for i in f
        )
        for f in faces
    ):
        raise InputFormatError(
            f'{where}: "faces" must be lists of at least 3 vertex indices in 0..{len(vertices) - 1}'
        )
    reason = entry.get("reason", "")
    if not isinstance(reason, str):
        raise InputFormatError(f'{where}: "reason" must be a string')
    solid = None
    if "density" in entry:  # a solid kept as derived: what its convex parts are made of
        density = number(entry["density"], f'{where}: "density"')
        flags = [entry.get(name, default) for name, default in (("structural", True),
                                                                 ("fixed", False))]  # fmt: skip
        if density < 0 or not all(isinstance(flag, bool) for flag in flags):
            raise InputFormatError(
                f'{where}: "density" must be a number >= 0 and "structural", "fixed" true or false'
            )
        solid = SolidLeaf(density, *flags)
    return Surface(
        vertices,
        faces,
        appearance=appearance_from_entry(entry.get("appearance"), where),
        tags=strings(entry.get("tags", []), f'{where}: "tags"'),
        rule_path=strings(entry.get("rule_path", []), f'{where}: "rule_path"'),
        reason=reason,
        id=surface_id,
        solid=solid,
    )


def appearance_from_entry(value: object, where: str) -> Appearance | None:
    """An :class:`Appearance` from its JSON object (see :meth:`Appearance.to_dict`), checked;
    None when absent."""
    if value is None:
        return None
    where = f'{where}: "appearance"'
    if not isinstance(value, dict):
        raise InputFormatError(f"{where} must be an object")
    color = value.get("color")
    if color is not None:
        if not isinstance(color, list) or len(color) != 3:
            raise InputFormatError(f'{where}: "color" must be 3 numbers in [0, 1]')
        color = [number(c, f'{where}: "color"') for c in color]
    opacity = number(value.get("opacity", 1.0), f'{where}: "opacity"')
    for name, fraction in (("color", color or []), ("opacity", [opacity])):
        if any(not 0.0 <= c <= 1.0 for c in fraction):
            raise InputFormatError(f'{where}: "{name}" must be in [0, 1]')
    texture = value.get("texture")
    if texture is not None and not isinstance(texture, str):
        raise InputFormatError(f'{where}: "texture" must be a string')
    material = value.get("material", {})
    if not isinstance(material, dict) or not all(
        isinstance(v, str | bool | int | float) for v in material.values()
    ):
        raise InputFormatError(
            f'{where}: "material" must map names to numbers, strings or booleans'
        )
    uv = value.get("uv", [])
    if not isinstance(uv, list) or not all(
        isinstance(e, list) and len(e) == 2 and isinstance(e[0], str) and isinstance(e[1], list)
        for e in uv
    ):
        raise InputFormatError(f'{where}: "uv" must be a list of [operation, [arguments]]')
    normals = value.get("normals")
    if normals is not None and not isinstance(normals, str | int | float):
        raise InputFormatError(f'{where}: "normals" must be a string or a number')
    return Appearance.from_dict({**value, "color": color, "opacity": opacity})

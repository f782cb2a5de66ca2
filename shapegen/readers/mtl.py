"""OBJ material libraries (``.mtl``): each material's diffuse colour and diffuse texture.

What an initial shape read from an OBJ file carries of its materials, as CityEngine's runtime
reads them: ``newmtl`` names a material, ``Kd`` is its diffuse colour (0..1 each) and
``map_Kd`` its diffuse texture, a file name relative to the library's folder (the last field of
the line: the options that may come before it, ``-s 1 1 1``..., are skipped). The other
statements (``Ka``, ``Ks``, ``map_Ka``, ``illum``...) are not carried.

>>> library = mtl_materials("newmtl wall\\nKd 0.5 0.25 1\\nmap_Kd -bm 1 brick.png\\n", "a.mtl")
>>> library["wall"]
ObjMaterial(name='wall', diffuse=(0.5, 0.25, 1.0), texture='brick.png')
"""

from __future__ import annotations

__all__ = ["ObjMaterial", "mtl_materials"]

from dataclasses import dataclass

from shapegen.errors import InputFormatError

#: map_Kd's options and how many values each takes (the MTL format's description); what
#: follows them is the file name
_TEXTURE_OPTIONS = {"-blendu": 1, "-blendv": 1, "-bm": 1, "-boost": 1, "-cc": 1, "-clamp": 1,
                    "-imfchan": 1, "-mm": 2, "-o": 3, "-s": 3, "-t": 3, "-texres": 1}  # fmt: skip


@dataclass(frozen=True)
class ObjMaterial:
    """One ``newmtl`` material: its name, diffuse colour ``(r, g, b)`` (0..1; white when the
    library gives none) and diffuse texture file name as written (``""``: none)."""

    name: str
    diffuse: tuple[float, float, float] = (1.0, 1.0, 1.0)
    texture: str = ""


def mtl_materials(text: str, where: str) -> dict[str, ObjMaterial]:
    """The materials of the MTL ``text`` by name.

    Raises
    ------
    InputFormatError
        ``{where}:{line}: ...``: a ``Kd`` without three numbers, a statement before ``newmtl``
        that needs a material.
    """
    out: dict[str, ObjMaterial] = {}
    current: dict | None = None
    for number, line in enumerate(text.splitlines(), start=1):
        fields = line.split()
        if not fields or fields[0].startswith("#"):
            continue
        if fields[0] == "newmtl":
            name = line.split(None, 1)[1].strip() if len(fields) > 1 else ""
            current = {"name": name}
            out[name] = ObjMaterial(name)
            continue
        if fields[0] not in ("Kd", "map_Kd"):
            continue
        if current is None:
            raise InputFormatError(f"{where}:{number}: {fields[0]} before any newmtl")
        if fields[0] == "Kd":
            try:
                rgb = tuple(float(v) for v in fields[1:4])
            except ValueError:
                rgb = ()
            if len(rgb) != 3:
                raise InputFormatError(f"{where}:{number}: Kd needs r g b numbers")
            current["diffuse"] = rgb
        else:
            current["texture"] = _texture_name(fields[1:])
        out[current["name"]] = ObjMaterial(**current)
    return out


def _texture_name(fields: list[str]) -> str:
    """The file name of a ``map_Kd`` line's fields: what follows its options."""
    k = 0
    while k < len(fields) - 1 and fields[k] in _TEXTURE_OPTIONS:
        k += 1 + _TEXTURE_OPTIONS[fields[k]]
    return " ".join(fields[k:])

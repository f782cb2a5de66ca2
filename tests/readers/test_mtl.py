"""OBJ material libraries: each material's diffuse colour and diffuse texture, and a broken
line is one error naming the place."""

from __future__ import annotations

import pytest

from shapegen.errors import InputFormatError
from shapegen.readers.mtl import ObjMaterial, mtl_materials


def test_each_material_has_its_diffuse_colour_and_texture_and_white_without():
    text = (
        "# two\nnewmtl glass\nKa 0.2 0.2 0.2\nKd 0.1 0.2 0.3\nmap_Ka amb.png\n"
        "map_Kd -s 2 2 1 -clamp on my texture.png\n"
        "newmtl plain stone\nNs 10\n"
    )
    assert mtl_materials(text, "a.mtl") == {
        "glass": ObjMaterial("glass", (0.1, 0.2, 0.3), "my texture.png"),
        "plain stone": ObjMaterial("plain stone"),
    }


@pytest.mark.parametrize(
    ("text", "words"),
    [
        ("newmtl a\nKd 1 0\n", "a.mtl:2: Kd needs r g b numbers"),
        ("Kd 1 0 0\n", "a.mtl:1: Kd before any newmtl"),
    ],
)
def test_a_broken_line_is_one_error_naming_it(text, words):
    with pytest.raises(InputFormatError, match=words):
        mtl_materials(text, "a.mtl")

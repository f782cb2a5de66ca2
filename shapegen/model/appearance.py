"""What a shape looks like, and the leaves that are drawn but not judged.

:class:`Appearance` is what CGA's ``color``, ``texture``, ``set(material.*)`` and the UV
operations leave on a shape; it is carried to the blocks and surfaces of the model and from
there to the export (glTF materials), and never changes the statics.

:class:`Surface` is a leaf of a derivation that is not a block: a face (a roof plane, a
``comp(f)`` face left as a leaf), an open or non-convex mesh (an asset). Surfaces are kept for
display and export; the statics only use blocks, and ``reason`` says why a surface is not one.
"""

from __future__ import annotations

__all__ = ["Appearance", "Surface"]

from dataclasses import dataclass, field

import numpy as np


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
        The UV set-up of the shape (projections, tiling), as the operations left it; kept so
        that an export can use it.
    """

    color: tuple[float, float, float] | None = None
    opacity: float = 1.0
    texture: str | None = None
    material: tuple[tuple[str, object], ...] = ()
    uv: tuple[tuple[str, object], ...] = ()


DEFAULT_APPEARANCE = Appearance()


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
        Why the statics leave it out, in words: ``"a face (no volume)"``,
        ``"not convex"``, ``"not closed"``...
    """

    vertices: np.ndarray
    faces: tuple[tuple[int, ...], ...]
    appearance: Appearance = DEFAULT_APPEARANCE
    tags: tuple[str, ...] = ()
    rule_path: tuple[str, ...] = ()
    reason: str = ""
    id: str = ""
    extras: dict = field(default_factory=dict)

    def __post_init__(self) -> None:
        self.vertices = np.ascontiguousarray(self.vertices, dtype=float).reshape(-1, 3)
        self.faces = tuple(tuple(int(i) for i in face) for face in self.faces)
        self.tags = tuple(self.tags)
        self.rule_path = tuple(self.rule_path)

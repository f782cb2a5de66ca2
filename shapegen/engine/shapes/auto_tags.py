"""The auto-tags of the operations that make geometry (cga_componentTags, "Auto-Tags"):
extrude, and the Booleans. (The roofs, taper and envelope tag their faces as
:mod:`shapegen.geometry.roofs` builds them; the setbacks tag their edges:
:mod:`shapegen.engine.operations.cga.setback_tags`.)"""

from __future__ import annotations

__all__ = ["boolean_tags", "extruded", "extrusion_tags"]

import numpy as np

from shapegen.engine.shapes.tags import (
    _NONE,
    ComponentTags,
    Pending,
    Tags,
    _added,
    _coincident,
    merged_tags,
    resolved_tags,
)


def boolean_tags(result, operands) -> ComponentTags:
    """The tags of a Boolean's ``result`` (a world mesh) from its ``operands``, ``(world mesh,
    tags or None)`` of A and B (cga_componentTags, "Boolean operations"): each face the tags of
    the operand faces it lies on and ``bool.A`` or ``bool.B`` (both where both are), and
    ``bool.cut`` on the edges where a face of A meets a face of B. The operands' former
    ``bool.*`` tags are replaced."""
    items = []
    for (mesh, tags), name in zip(operands, ("bool.A", "bool.B"), strict=True):
        tags = tags.without_prefix("bool") if tags is not None else ComponentTags.empty(0)
        own = ComponentTags(
            tuple(_added(tags.face(k), (name,)) for k in range(mesh.n_faces)),
            tags.edges,
            tags.vertices,
        )
        items.append((mesh, own))
    merged = merged_tags(items, result, either_side=True)
    cut: dict[tuple[int, int], Tags] = dict(merged.edges)
    sides: dict[tuple[int, int], set[str]] = {}
    for f, face in enumerate(result.faces):
        for a, b in zip(face, face[1:] + face[:1], strict=True):
            if a != b:
                key = (a, b) if a < b else (b, a)
                sides.setdefault(key, set()).update(
                    t for t in merged.faces[f] if t in ("bool.A", "bool.B")
                )
    for key, names in sides.items():
        if len(names) == 2:
            cut[key] = _added(cut.get(key, _NONE), ("bool.cut",))
    return ComponentTags(merged.faces, cut, merged.vertices)


def extrusion_tags(source, result) -> ComponentTags | None:
    """The tags of ``result``, the extrusion of ``source``'s faces (each face a prism in face
    order: its bottom, its top, a side per edge; :func:`shapegen.geometry.extrude.prism`):
    ``extrude.bottom``, ``extrude.top``, ``extrude.side.outer`` and, on the walls of a face's
    holes, ``extrude.side.inner`` (cga_componentTags), after the tags of the source face ("New
    faces constructed on top of existing ones get the tags of their source face") and, on a
    side, of the edge it emanates from. The former ``extrude.*`` tags are replaced. None when
    the result's faces are not the prisms' (a degenerate face dropped)."""
    old = resolved_tags(source)
    if old is not None:
        old = old.without_prefix("extrude")
    if result.kind != "mass":
        return None
    mesh = source.mesh()
    faces: list[Tags] = []
    for k, face in enumerate(mesh.faces):
        if len(face) < 3 or not np.any(mesh.face_normal(k)):
            continue
        own = old.face(k) if old is not None else _NONE
        faces.append(_added(own, ("extrude.bottom",)))
        faces.append(_added(own, ("extrude.top",)))
        rings = [(face, "extrude.side.outer")]
        rings += [(ring, "extrude.side.inner") for ring in (mesh.holes[k] if mesh.holes else ())]
        for ring, name in rings:
            for a, b in zip(ring, ring[1:] + ring[:1], strict=True):
                edge = old.edge(a, b) if old is not None else _NONE
                faces.append(_added(_added(own, edge), (name,)))
    if len(faces) != result.mesh().n_faces:
        return None
    tags = ComponentTags(tuple(faces))
    if old is not None and (old.edges or old.vertices):
        kept = _coincident(source.world_mesh(), old, result.world_mesh())
        tags = ComponentTags(tags.faces, kept.edges, kept.vertices)
    return tags


def extruded(state, source, result):
    """``result``, the extrusion of ``source``, with its auto-tags to be worked out when read
    (:func:`extrusion_tags`), when the derivation of ``state`` keeps tags."""
    if not state.run.tags:
        return result
    return result.with_tags(Pending(source, extrusion_tags))

"""Component tags (cga_componentTags): strings stored on the faces, edges and vertices of a
shape's geometry.

A :class:`ComponentTags` belongs to one :class:`~shapegen.engine.shapes.shape.Shape` and
indexes the components of its :meth:`~shapegen.engine.shapes.shape.Shape.mesh`: a tuple of
tags per face, and the tagged edges (by their sorted vertex pair) and vertices (by index).

The reference's rules, as implemented here:

- a tag query matches a tag and every tag below it in the hierarchy of subtags ("Facade"
  matches "Facade.Front"); ``?`` stands for one subtag, ``*`` for one or more
  (:func:`query_matches`);
- an operation that keeps the components (t, r, s, center...) keeps the tags by index; one that
  remakes them (split, comp, setback, offset, trim, inline...) keeps the tags of the
  components that are still there: "When splitting geometry, tags on existing edge and face
  components that were cut are kept. New components, such as new faces to close cut volumes,
  have no initial tags." shapegen finds them by geometry (:func:`carried_tags`): a new face
  lying in an old face's plane and inside it has its tags, a new edge lying on an old tagged
  edge has its tags, a new vertex on an old tagged vertex has its tags;
- "Tags stored on a face also identify its edges and vertices, while tags stored on an edge also
  identify its two vertex endpoints" (op_comp's isTagged selector: :func:`identifying_tags`).
"""

from __future__ import annotations

__all__ = [
    "ComponentTags",
    "Pending",
    "carried_tags",
    "kept_tags",
    "resolved_tags",
    "TagIndex",
    "is_tagged",
    "merged_tags",
    "query_matches",
    "valid_tag",
]

from collections.abc import Iterable, Sequence
from dataclasses import dataclass, field

import numpy as np

from shapegen.tolerances import COSINE_SLACK, TAG_MATCH_REL

Tags = tuple[str, ...]
_NONE: Tags = ()


def _added(tags: Tags, names: Iterable[str]) -> Tags:
    out = list(tags)
    for name in names:
        if name not in out:
            out.append(name)
    return tuple(out)


@dataclass(frozen=True)
class ComponentTags:
    """The tags of one mesh's components: ``faces[k]`` the tags of face ``k``; ``edges`` the
    tagged edges, keyed by their sorted vertex pair; ``vertices`` the tagged vertices."""

    faces: tuple[Tags, ...]
    edges: dict[tuple[int, int], Tags] = field(default_factory=dict)
    vertices: dict[int, Tags] = field(default_factory=dict)

    @classmethod
    def empty(cls, n_faces: int) -> ComponentTags:
        return cls((_NONE,) * n_faces)

    def is_empty(self) -> bool:
        return not (any(self.faces) or self.edges or self.vertices)

    def face(self, k: int) -> Tags:
        return self.faces[k] if k < len(self.faces) else _NONE

    def edge(self, a: int, b: int) -> Tags:
        return self.edges.get((a, b) if a < b else (b, a), _NONE)

    def vertex(self, k: int) -> Tags:
        return self.vertices.get(k, _NONE)

    def tagged(self, mesh, name: str, components: str) -> ComponentTags:
        """These tags and ``name`` on every face, edge or vertex of ``mesh`` (op_tag; ``auto``
        is the highest-dimensional components there are)."""
        if components == "auto":
            components = "faces" if any(len(f) > 2 for f in mesh.faces) else "edges"
            if components == "edges" and not mesh.edges:
                components = "vertices"
        faces, edges, vertices = self.faces, dict(self.edges), dict(self.vertices)
        if components == "faces":
            faces = tuple(_added(self.face(k), (name,)) for k in range(mesh.n_faces))
        elif components == "edges":
            for key in mesh.edges:
                edges[key] = _added(edges.get(key, _NONE), (name,))
        else:
            for k in range(mesh.n_vertices):
                vertices[k] = _added(vertices.get(k, _NONE), (name,))
        return ComponentTags(faces, edges, vertices)

    def deleted(self, query: str | None, components: str) -> ComponentTags:
        """These tags without those ``query`` matches (all with None) on the ``components``
        (all, faces, edges or vertices), as op_deleteTags."""

        def kept(tags: Tags) -> Tags:
            return tuple(t for t in tags if query is not None and not query_matches(query, t))

        faces, edges, vertices = self.faces, self.edges, self.vertices
        if components in ("all", "faces"):
            faces = tuple(kept(t) for t in faces)
        if components in ("all", "edges"):
            edges = {k: t for k, t in ((k, kept(t)) for k, t in edges.items()) if t}
        if components in ("all", "vertices"):
            vertices = {k: t for k, t in ((k, kept(t)) for k, t in vertices.items()) if t}
        return ComponentTags(faces, edges, vertices)

    def listed(self, components: str) -> list[str]:
        """Every tag on the ``components`` (all, faces, edges or vertices), once each."""
        out: dict[str, None] = {}
        if components in ("all", "faces"):
            for tags in self.faces:
                out.update(dict.fromkeys(tags))
        if components in ("all", "edges"):
            for tags in self.edges.values():
                out.update(dict.fromkeys(tags))
        if components in ("all", "vertices"):
            for tags in self.vertices.values():
                out.update(dict.fromkeys(tags))
        return list(out)

    def without_prefix(self, prefix: str) -> ComponentTags:
        """These tags without the auto-tags of one operation (``extrude.*``): "Auto-tags
        applied by a certain operation remain accessible until the operation is called again,
        replacing them with new ones"."""
        return self.deleted(prefix, "all")


def valid_tag(name: str) -> str:
    """``name`` without the wildcard characters op_tag filters out (``?`` and ``*``)."""
    return name.replace("?", "").replace("*", "")


def query_matches(query: str, tag: str) -> bool:
    """Whether the tag query ``query`` matches ``tag``: subtag by subtag from the first, ``?``
    one subtag, ``*`` one or more, and the query may stop before the tag does."""
    if query == "":
        return True
    return _match(query.split("."), tag.split("."))


def _match(query: list[str], tag: list[str]) -> bool:
    if not query:
        return True  # the query is a prefix of the tag's hierarchy
    if not tag:
        return False
    head, rest = query[0], query[1:]
    if head == "*":
        return any(_match(rest, tag[k:]) for k in range(1, len(tag) + 1))
    if head == "?" or head == tag[0]:
        return _match(rest, tag[1:])
    return False


# ------------------------------------------------------------------ the components' tags
class TagIndex:
    """The tags that identify each component of one tagged mesh (op_comp's isTagged): a
    component's own, and those of the components of higher dimension holding it: "Tags stored
    on a face also identify its edges and vertices, while tags stored on an edge also identify
    its two vertex endpoints"."""

    def __init__(self, tags: ComponentTags, mesh):
        self.tags = tags
        self.mesh = mesh
        self.edge_faces: dict[tuple[int, int], list[int]] = {}
        self.vertex_faces: dict[int, list[int]] = {}
        for f, face in enumerate(mesh.faces):
            for a, b in zip(face, face[1:] + face[:1], strict=True):
                if a != b:
                    self.edge_faces.setdefault((a, b) if a < b else (b, a), []).append(f)
            for v in face:
                self.vertex_faces.setdefault(v, []).append(f)

    def face(self, f: int) -> set[str]:
        return set(self.tags.face(f))

    def edge(self, a: int, b: int) -> set[str]:
        key = (a, b) if a < b else (b, a)
        out = set(self.tags.edges.get(key, _NONE))
        for f in self.edge_faces.get(key, ()):
            out.update(self.tags.face(f))
        return out

    def vertex(self, v: int) -> set[str]:
        out = set(self.tags.vertex(v))
        for f in self.vertex_faces.get(v, ()):
            out.update(self.tags.face(f))
        for (a, b), tags in self.tags.edges.items():
            if v in (a, b):
                out.update(tags)
        return out

    def component(self, kind: str, faces: Sequence[int], vertices: Sequence[int], sub=None):
        """The tags identifying a component of ``kind`` (f, fe, e, v, fv) made of the mesh's
        ``faces`` (a face: itself; an edge: the faces along it) and ``vertices``; with ``sub``
        (``e`` or ``v``), those of its edges or vertices instead."""
        if sub == "v" or (sub is None and kind in ("v", "fv")):
            out: set[str] = set()
            for v in vertices:
                out |= self.vertex(v)
            return out
        if kind in ("e", "fe"):
            a, b = vertices
            return self.edge(a, b)
        if kind in ("f", "g", "m"):
            out = set()
            for f in faces:
                if sub == "e":
                    face = self.mesh.faces[f]
                    for a, b in zip(face, face[1:] + face[:1], strict=True):
                        out |= self.edge(a, b)
                else:
                    out |= self.face(f)
            return out
        out = set()
        for v in vertices:
            out |= self.vertex(v)
        return out


_COMPONENT_WORDS = ("all", "faces", "edges", "vertices")


def tags_value(shape, name: str, query=None, components="all"):
    """``geometry.tags([tagQuery[, components]])`` (an array of strings, sorted) or
    ``geometry.hasTags(...)`` (a bool) of ``shape``. Raises ``ValueError``."""
    from shapegen.engine.expressions.arrays import Array

    if query is not None and type(query) is not str:
        raise ValueError("the tag query must be a string")
    if components not in _COMPONENT_WORDS:
        raise ValueError(f"the components are one of {', '.join(_COMPONENT_WORDS)}")
    tags = resolved_tags(shape)
    listed = [] if tags is None else tags.listed(components)
    if query is not None:
        listed = [t for t in listed if query_matches(query, t)]
    if name == "hasTags":
        return bool(listed)
    listed.sort()
    return Array(tuple(listed), 1 if listed else 0, len(listed), str)


def is_tagged(state, query, sub=None) -> bool:
    """``isTagged(tagQuery[, e|v])``: whether a tag identifying the component that a comp()
    or modify() selector looks at matches ``query``. Raises ``ValueError`` elsewhere."""
    if type(query) is not str:
        raise ValueError("the tag query must be a string")
    if sub is not None and sub not in ("e", "v"):
        raise ValueError("the subcomponent is e or v")
    run = state.run
    selection = run.tag_selection
    if selection is None:
        raise ValueError("isTagged() is a selector of comp() and modify(); here there is no "
                         "component to look at")  # fmt: skip
    parent, kind, component = selection
    if resolved_tags(parent) is None:
        return False
    cached = run.tag_index
    if cached is None or cached[0] is not parent:
        cached = run.tag_index = (parent, TagIndex(parent.tags, parent.mesh()))
    tags = cached[1].component(kind, component.mesh_faces, component.vertices, sub)
    return any(query_matches(query, t) for t in tags)


def merged_tags(
    items: Sequence[tuple[object, ComponentTags | None]], mesh, either_side: bool = False
) -> ComponentTags:
    """The tags of ``mesh`` (world coordinates) carried from several tagged world meshes
    ``(mesh, tags)``: an inline's leaves joined, a Boolean's operands."""
    faces = [list() for _ in range(mesh.n_faces)]
    edges: dict = {}
    vertices: dict = {}
    for old, tags in items:
        if tags is None:
            continue
        one = _coincident(old, tags, mesh, either_side)
        for k, t in enumerate(one.faces):
            faces[k].extend(t)
        for key, t in one.edges.items():
            edges[key] = _added(edges.get(key, _NONE), t)
        for key, t in one.vertices.items():
            vertices[key] = _added(vertices.get(key, _NONE), t)
    return ComponentTags(tuple(tuple(dict.fromkeys(f)) for f in faces), edges, vertices)


class Pending:
    """The tags of a shape made from ``source`` by an operation that gives none of its own,
    worked out (:func:`carried_tags`) only when something reads them: most tagged shapes are
    never asked, and a derivation makes many. ``rule(source, shape)`` gives the tags (the
    source's already worked out); by default, those the components keep (:func:`carried_tags`).
    """

    __slots__ = ("source", "rule")

    def __init__(self, source, rule=None):
        self.source = source
        self.rule = rule


def resolved_tags(shape) -> ComponentTags | None:
    """The component tags of ``shape``, None when it has none (a pending carry is worked out
    here, from the first shape of the chain that has its tags, and kept)."""
    tags = shape.tags
    if tags is None or type(tags) is ComponentTags:
        return tags
    chain = [shape]
    while type(chain[-1].tags) is Pending:
        chain.append(chain[-1].tags.source)
    for later, earlier in zip(reversed(chain[:-1]), reversed(chain[1:]), strict=True):
        later.tags = (later.tags.rule or _carried)(earlier, later)
    return shape.tags


def kept_tags(shape):
    """What a shape made of ``shape``'s very components (moved, turned, scaled) holds as its
    tags."""
    tags = shape.tags
    return tags if tags is None or type(tags) is ComponentTags else Pending(shape, _by_index)


def _by_index(old, new) -> ComponentTags | None:
    return old.tags


def carried_tags(old, new) -> ComponentTags | None:
    """The tags of shape ``new`` carried from shape ``old`` (both
    :class:`~shapegen.engine.shapes.shape.Shape`) by geometry in world coordinates (a shape
    made of the very same components, moved or scaled, keeps them by index:
    :func:`kept_tags`)."""
    if old.tags is None:
        return None
    resolved_tags(old)
    return _carried(old, new)


def _carried(old, new) -> ComponentTags | None:
    tags = old.tags
    if tags is None:
        return None
    same = old.scope is new.scope or (
        np.array_equal(old.scope.origin, new.scope.origin)
        and np.array_equal(old.scope.rotation, new.scope.rotation)
        and np.array_equal(old.scope.size, new.scope.size)
    )
    if same and old.geometry is new.geometry and old.kind == new.kind:
        return tags  # the very same geometry where it was
    return _coincident(old.world_mesh(), tags, new.world_mesh())


def _slack(*meshes) -> float:
    size = max((float(m.size()) for m in meshes if m.n_vertices), default=1.0)
    return TAG_MATCH_REL * max(1.0, size)


def _coincident(old, tags: ComponentTags, new, either_side: bool = False) -> ComponentTags:
    """``tags`` of the world mesh ``old`` carried to the world mesh ``new`` by geometry
    (``either_side``: a new face facing the other way counts too, as a subtracted operand's
    faces do)."""
    slack = _slack(old, new)
    faces = [_NONE] * new.n_faces
    tagged_faces = [k for k, t in enumerate(tags.faces) if t and len(old.faces[k]) > 2]
    if tagged_faces and new.n_faces:
        planes = []
        for k in tagged_faces:
            points = old.face_points(k)
            normal = old.face_normal(k)
            length = float(np.linalg.norm(normal))
            if length == 0:
                continue
            normal = normal / length
            planes.append((k, normal, float(points.mean(axis=0) @ normal), points))
        for j, face in enumerate(new.faces):
            if len(face) < 3:
                continue
            points = new.face_points(j)
            normal = new.face_normal(j)
            length = float(np.linalg.norm(normal))
            if length == 0:
                continue
            normal = normal / length
            inner = _inner_point(points, normal)
            found: list[str] = []
            for k, n, offset, outline in planes:
                facing = float(n @ normal)
                if either_side:
                    facing = abs(facing)
                if facing < 1 - TAG_MATCH_REL - COSINE_SLACK:
                    continue
                if abs(float(inner @ n) - offset) > slack:
                    continue
                if _inside(inner, outline, n):
                    found.extend(tags.faces[k])
            faces[j] = tuple(dict.fromkeys(found))
    edges: dict[tuple[int, int], Tags] = {}
    if tags.edges and new.n_faces:
        segments = [(old.vertices[a], old.vertices[b], t) for (a, b), t in tags.edges.items()]
        for a, b in new.edges:
            p, q = new.vertices[a], new.vertices[b]
            found = []
            for s, e, t in segments:
                if _on_segment(p, s, e, slack) and _on_segment(q, s, e, slack):
                    found.extend(t)
            if found:
                edges[(a, b)] = tuple(dict.fromkeys(found))
    vertices: dict[int, Tags] = {}
    if tags.vertices:
        points = np.array([old.vertices[k] for k in tags.vertices])
        values = list(tags.vertices.values())
        for j, p in enumerate(new.vertices):
            near = np.flatnonzero(np.abs(points - p).max(axis=1) <= slack)
            if len(near):
                vertices[j] = tuple(dict.fromkeys(t for i in near for t in values[i]))
    return ComponentTags(tuple(faces), edges, vertices)


def _on_segment(p, s, e, slack: float) -> bool:
    d = e - s
    length2 = float(d @ d)
    if length2 == 0:
        return bool(np.abs(p - s).max() <= slack)
    u = float((p - s) @ d) / length2
    if u < -slack or u > 1 + slack:
        return False
    return bool(np.linalg.norm(s + u * d - p) <= slack)


def _frame2d(normal):
    helper = np.eye(3)[int(np.argmin(np.abs(normal)))]
    u = np.cross(helper, normal)
    u /= np.linalg.norm(u)
    return u, np.cross(normal, u)


def _inside(point, outline, normal) -> bool:
    """Whether ``point`` is inside the polygon ``outline`` (in its plane; even-odd rule)."""
    u, v = _frame2d(normal)
    x, y = float(point @ u), float(point @ v)
    xs, ys = outline @ u, outline @ v
    inside = False
    for k in range(len(xs)):
        x1, y1, x2, y2 = xs[k - 1], ys[k - 1], xs[k], ys[k]
        if (y1 > y) != (y2 > y):
            cross = x1 + (y - y1) * (x2 - x1) / (y2 - y1)
            if x < cross:
                inside = not inside
    return inside


def _inner_point(points: np.ndarray, normal) -> np.ndarray:
    """A point inside the polygon ``points``: its corner mean when that is inside (a convex
    face), else the centroid of the first fan triangle that is."""
    mean = points.mean(axis=0)
    if len(points) == 3 or _inside(mean, points, normal):
        return mean
    for k in range(1, len(points) - 1):
        centre = (points[0] + points[k] + points[k + 1]) / 3
        if _inside(centre, points, normal):
            return centre
    return mean

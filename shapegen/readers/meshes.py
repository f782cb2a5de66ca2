"""Mesh files in: OBJ, glTF, PLY and STL files as block models, through trimesh.

Every mesh node of the file (a glTF node, an OBJ group or object, the single mesh of a PLY or
STL file) is split into its connected components; each component becomes one block, the convex
hull of its vertices. Blocks must be convex, so a component that is clearly not (a vertex well
inside its hull, or a closed mesh whose volume is well below its hull's) is an error naming it.
See docs/formats.md for the rules. The bytes come through
:func:`shapegen.readers.files.read_model_bytes` (the size limit); :mod:`shapegen.export.meshes`
and :mod:`shapegen.export.gltf` write these formats.
"""

from __future__ import annotations

__all__ = ["read_mesh_model"]

import io
import re
from pathlib import Path

import numpy as np
import trimesh
from scipy.spatial import ConvexHull, QhullError

from shapegen.errors import GeometryError, InputFormatError
from shapegen.geometry.graphs import connected_components
from shapegen.limits import current_limits, limit_hint
from shapegen.model.model import Model
from shapegen.readers.blocks_json import FORMAT_NAME, FORMAT_VERSION, model_from_dict
from shapegen.readers.files import read_model_bytes
from shapegen.readers.surface_entries import SURFACE_GROUP, SURFACE_ROLE
from shapegen.tolerances import FLAT_REL

# A component is "clearly" non-convex past these margins; they are loose on purpose because mesh
# files store float32 coordinates and exporters leave slightly warped faces.
INTERIOR_DEPTH_REL = 1e-2  # a vertex deeper inside its hull than this fraction of its size
HULL_VOLUME_EXCESS = 0.02  # hull volume above the closed mesh's volume by this fraction

_GENERIC_NAME = re.compile(r"(geometry|mesh|node|object)?[_.]?\d*", re.IGNORECASE)


def read_mesh_model(path: str | Path) -> Model:
    """Read an OBJ, glTF (.gltf/.glb), PLY or STL file as a block model.

    Each connected component of each mesh node becomes one block (its convex hull). Block ids
    come from node or group names (``name.k`` when a node holds several components), tags from
    the same names, or, for files shapegen wrote, from the node ``extras`` (labels, density,
    fixed, structural, rule path) and the scene ``extras`` (gravity, ground, friction, loads).

    Raises
    ------
    InputFormatError
        The file is missing, unreadable or holds no mesh.
    GeometryError
        A component is degenerate (flat) or clearly non-convex; the message names it.
    """
    path = Path(path)
    if not path.exists():
        raise InputFormatError(f"{path}: no such file")
    data = read_model_bytes(path)
    suffix = path.suffix.lower()
    _check_text(data, suffix, path)
    try:
        scene = trimesh.load_scene(
            io.BytesIO(data),
            file_type=suffix.lstrip("."),
            resolver=trimesh.resolvers.FilePathResolver(str(path.resolve())),
            metadata={"file_name": path.name},
            process=False,
            split_objects=True,
            split_groups=True,
        )
    except Exception as exc:  # any parser failure on a user's file is bad input
        text = str(exc).strip()
        reason = text.splitlines()[0][:200] if text else type(exc).__name__
        raise InputFormatError(f"{path}: cannot read as a {path.suffix} mesh: {reason}") from None
    document = {
        "format": FORMAT_NAME,
        "version": FORMAT_VERSION,
        "blocks": [],
    }
    settings = scene.metadata if isinstance(scene.metadata, dict) else {}
    if settings.get("format") == FORMAT_NAME:
        for key in ("gravity", "ground", "friction", "loads", "structure"):
            if key in settings:
                document[key] = settings[key]
    try:
        document["surfaces"] = _surfaces_of_scene(scene)
        document["blocks"] = _blocks_of_scene(scene, path)
        if not document["blocks"] and not document["surfaces"]:
            raise InputFormatError("the file holds no mesh")
        return model_from_dict(document)
    except (InputFormatError, GeometryError) as exc:
        raise type(exc)(f"{path}: {exc}") from None


def _check_text(data: bytes, suffix: str, path: Path) -> None:
    """Refuse a text format that is not UTF-8 before trimesh guesses its encoding (with a
    module it may not have): OBJ and glTF are text; an STL that is not binary is ASCII."""
    if suffix not in (".obj", ".gltf", ".stl") or (suffix == ".stl" and _is_binary_stl(data)):
        return
    try:
        data.decode("utf-8")
    except UnicodeDecodeError as exc:
        kind = (
            "a binary STL (its size does not match its triangle count) nor an ASCII one"
            if suffix == ".stl"
            else f"{suffix} text"
        )
        raise InputFormatError(
            f"{path}: {'neither' if suffix == '.stl' else 'not'} {kind}: invalid UTF-8 at byte "
            f"{exc.start}"
        ) from None


def _is_binary_stl(data: bytes) -> bool:
    """A binary STL: an 80-byte header, a triangle count, 50 bytes per triangle."""
    if len(data) < 84:
        return False
    return len(data) == 84 + 50 * int.from_bytes(data[80:84], "little")


def _blocks_of_scene(scene: trimesh.Scene, path: Path) -> list[dict]:
    nodes = _mesh_nodes(scene)
    for name, _, vertices, _ in nodes:
        if not np.all(np.isfinite(vertices)):
            raise GeometryError(f"mesh {name!r}: vertex coordinates must be finite numbers")
    limit = current_limits().max_blocks
    if sum(len(faces) for _, _, _, faces in nodes) > 50 * limit:
        raise InputFormatError(
            f"the file has more than {50 * limit} triangles (50 per block of the limit) "
            + limit_hint("max_blocks")
        )
    pieces_of_node = _node_components(nodes)
    pieces = sum(len(node_pieces) for node_pieces in pieces_of_node)
    if pieces > limit:
        raise InputFormatError(
            f"the file holds {pieces} blocks (connected parts), more than {limit} "
            + limit_hint("max_blocks")
        )
    blocks: list[dict] = []
    used_ids: set[str] = set()
    for (name, extras, _, _), pieces in zip(nodes, pieces_of_node, strict=True):
        named = not _GENERIC_NAME.fullmatch(name) and name != path.name
        for k, (points, volume) in enumerate(pieces):
            if not named:
                block_id = f"b{len(blocks)}"
            else:
                block_id = name if len(pieces) == 1 else f"{name}.{k}"
            block_id = _unique(block_id, used_ids)
            hull_points = _convex_points(points, volume, block_id)
            blocks.append(_block_entry(block_id, name if named else None, hull_points, extras))
    return blocks


def _mesh_nodes(scene: trimesh.Scene) -> list[tuple[str, dict, np.ndarray, np.ndarray]]:
    """``(name, extras, world vertices, triangles)`` of each block node, in natural name order."""
    graph = scene.graph
    parents = graph.transforms.parents
    edge_data = graph.transforms.edge_data
    nodes = []
    for node in sorted(graph.nodes_geometry, key=_natural_key):
        matrix, geometry_name = graph[node]
        geometry = scene.geometry.get(geometry_name)
        if not isinstance(geometry, trimesh.Trimesh) or len(geometry.faces) == 0:
            continue
        extras = edge_data.get((parents.get(node), node), {}).get("metadata") or {}
        if not isinstance(extras, dict):
            extras = {}
        if extras.get("role", "block") != "block" or _is_surface(str(node), extras):
            continue  # surfaces, and drawings shapegen adds to its own files (arrows)
        vertices = np.asarray(geometry.vertices, dtype=float)
        faces = np.asarray(geometry.faces, dtype=np.int64)
        # trimesh does not check what it read (process=False): a malformed file may give
        # points of 1 or 2 coordinates, or triangles naming vertices the mesh lacks.
        if vertices.ndim != 2 or vertices.shape[1] != 3 or faces.ndim != 2 or faces.shape[1] != 3:
            raise InputFormatError(
                f"mesh {str(node)!r}: vertices must have 3 coordinates and faces 3 corners"
            )
        if faces.min() < 0 or faces.max() >= len(vertices):
            raise InputFormatError(
                f"mesh {str(node)!r}: a triangle refers to vertex {int(faces.max())}, but the mesh"
                f" has {len(vertices)} vertices"
            )
        matrix = np.asarray(matrix, dtype=float)
        if not np.allclose(matrix, np.eye(4)):
            vertices = vertices @ matrix[:3, :3].T + matrix[:3, 3]
        nodes.append((str(node), extras, vertices, faces))
    return nodes


def _is_surface(name: str, extras: dict) -> bool:
    return extras.get("role") == SURFACE_ROLE or name.startswith(SURFACE_GROUP)


def _surfaces_of_scene(scene: trimesh.Scene) -> list[dict]:
    """The shapegen-blocks entries of the scene's surface nodes: glTF nodes whose extras say
    ``role`` "surface", OBJ groups named ``surface:<id>`` (triangles, world coordinates)."""
    graph = scene.graph
    parents = graph.transforms.parents
    entries = []
    for node in sorted(graph.nodes_geometry, key=_natural_key):
        extras = graph.transforms.edge_data.get((parents.get(node), node), {}).get("metadata")
        extras = extras if isinstance(extras, dict) else {}
        if not _is_surface(str(node), extras):
            continue
        matrix, geometry_name = graph[node]
        geometry = scene.geometry.get(geometry_name)
        if not isinstance(geometry, trimesh.Trimesh) or len(geometry.faces) == 0:
            continue
        vertices = np.asarray(geometry.vertices, dtype=float)
        matrix = np.asarray(matrix, dtype=float)
        if not np.allclose(matrix, np.eye(4)):
            vertices = vertices @ matrix[:3, :3].T + matrix[:3, 3]
        entry = {
            "id": str(node).removeprefix(SURFACE_GROUP),
            "vertices": vertices.tolist(),
            "faces": np.asarray(geometry.faces, dtype=np.int64).tolist(),
            "reason": extras.get("reason", ""),
        }
        if "labels" in extras:
            entry["tags"] = extras["labels"]
        for key in ("rule_path", "appearance"):
            if key in extras:
                entry[key] = extras[key]
        entries.append(entry)
    return entries


def _node_components(nodes: list) -> list[list[tuple[np.ndarray, float | None]]]:
    """The connected components of every node: ``(points, volume)`` each, the volume (m^3) only
    for a closed component, else None.

    All nodes are split in one pass (their vertex indices are disjoint, so no component spans two
    nodes). Exporters that duplicate vertices per face (flat shading, STL) leave each face as its
    own piece; the vertices of such a node are then welded by position and it is split again.
    Welding is not the default because touching blocks share vertex positions and would fuse.
    """
    if not nodes:
        return []
    vertex_counts = np.array([len(vertices) for _, _, vertices, _ in nodes])
    face_counts = np.array([len(faces) for _, _, _, faces in nodes])
    offsets = np.concatenate([[0], np.cumsum(vertex_counts)[:-1]])
    vertices = np.concatenate([v for _, _, v, _ in nodes])
    faces = np.concatenate([f + o for (_, _, _, f), o in zip(nodes, offsets, strict=True)])
    face_node = np.repeat(np.arange(len(nodes)), face_counts)
    out: list[list] = [[] for _ in nodes]
    for points, volume, first_face in _split(vertices, faces):
        out[face_node[first_face]].append((points, volume))
    for k, (_, _, node_vertices, node_faces) in enumerate(nodes):
        if any(_is_flat(points) for points, _ in out[k]):
            welded = trimesh.Trimesh(node_vertices, node_faces, process=False)
            welded.merge_vertices(merge_tex=True, merge_norm=True)
            out[k] = [
                (points, volume)
                for points, volume, _ in _split(
                    np.asarray(welded.vertices, dtype=float), np.asarray(welded.faces)
                )
            ]
    return out


def _split(vertices: np.ndarray, faces: np.ndarray) -> list[tuple[np.ndarray, float | None, int]]:
    """The pieces of a triangle mesh whose triangles are linked through shared vertex indices:
    ``(points, volume or None when open, index of one of its triangles)`` each."""
    n = len(vertices)
    faces = faces.astype(np.int64)
    edges = np.concatenate([faces[:, [0, 1]], faces[:, [1, 2]], faces[:, [2, 0]]])
    count, label = connected_components(n, edges[:, 0], edges[:, 1])
    face_label = label[faces[:, 0]]
    # Closed: every edge of the piece is shared by exactly two of its triangles.
    _, inverse, uses = np.unique(
        np.sort(edges, axis=1), axis=0, return_inverse=True, return_counts=True
    )
    closed = np.ones(count, dtype=bool)
    closed[np.tile(face_label, 3)[uses[inverse.reshape(-1)] != 2]] = False
    # Signed volume of each piece (divergence theorem about the piece's vertex mean).
    used = np.unique(faces)
    used_label = label[used]
    sizes = np.bincount(used_label, minlength=count)
    reference = (
        np.stack(
            [np.bincount(used_label, vertices[used, axis], minlength=count) for axis in range(3)],
            axis=1,
        )
        / np.maximum(sizes, 1)[:, None]
    )
    corners = vertices[faces] - reference[face_label][:, None, :]
    six_volumes = np.einsum("ij,ij->i", corners[:, 0], np.cross(corners[:, 1], corners[:, 2]))
    volume = np.bincount(face_label, six_volumes, minlength=count) / 6.0
    first_face = np.full(count, -1)
    first_face[face_label] = np.arange(len(faces))  # any triangle of the piece will do
    order = np.argsort(used_label, kind="stable")
    groups = np.split(used[order], np.cumsum(sizes)[:-1])
    return [
        (vertices[group], abs(float(volume[k])) if closed[k] else None, int(first_face[k]))
        for k, group in enumerate(groups)
        if len(group)
    ]


def _is_flat(points: np.ndarray) -> bool:
    if len(points) < 4:
        return True
    centered = points - points.mean(axis=0)
    scale = float(np.abs(centered).max())
    if scale == 0:
        return True
    singular = np.linalg.svd(centered / scale, compute_uv=False)
    return bool(singular[-1] < FLAT_REL * singular[0])


def _convex_points(points: np.ndarray, mesh_volume: float | None, block_id: str) -> np.ndarray:
    """The component's hull vertices after checking that they bound a convex solid.

    ``mesh_volume`` is the volume of the closed component (m^3), or None when it is open.
    """
    if not np.all(np.isfinite(points)):
        raise GeometryError(f"block {block_id!r}: vertex coordinates must be finite numbers")
    if _is_flat(points):
        raise GeometryError(f"block {block_id!r}: its mesh is flat (zero volume)")
    try:
        hull = ConvexHull(points)
    except QhullError:
        raise GeometryError(f"block {block_id!r}: its mesh is flat (zero volume)") from None
    size = float(np.linalg.norm(np.ptp(points, axis=0)))
    # qhull planes: n . x + e <= 0 inside; a vertex on the hull's surface reaches 0 on some plane.
    signed = points @ hull.equations[:, :3].T + hull.equations[:, 3]
    depth = float(-signed.max(axis=1).min())
    if depth > INTERIOR_DEPTH_REL * size:
        raise GeometryError(
            f"block {block_id!r}: not convex (a vertex lies {depth:.3g} m inside its convex hull);"
            " blocks must be convex, split it into convex pieces"
        )
    if mesh_volume is not None and hull.volume > (1 + HULL_VOLUME_EXCESS) * mesh_volume:
        raise GeometryError(
            f"block {block_id!r}: not convex (its convex hull holds {hull.volume:.4g} m^3,"
            f" the mesh {mesh_volume:.4g} m^3); blocks must be convex"
        )
    return points[hull.vertices]


def _block_entry(block_id: str, name: str | None, points: np.ndarray, extras: dict) -> dict:
    """A shapegen-blocks block entry; the format reader then checks every value's type."""
    entry: dict = {"id": block_id, "vertices": points.tolist()}
    if "labels" in extras:
        entry["tags"] = extras["labels"]
    elif name is not None:
        entry["tags"] = [name]
    for key in ("density", "fixed", "structural", "rule_path", "appearance"):
        if key in extras:
            entry[key] = extras[key]
    return entry


def _unique(block_id: str, used: set[str]) -> str:
    candidate, n = block_id, 1
    while candidate in used:
        candidate = f"{block_id}.{n}"
        n += 1
    used.add(candidate)
    return candidate


def _natural_key(name: object) -> list:
    return [int(part) if part.isdigit() else part for part in re.split(r"(\d+)", str(name))]

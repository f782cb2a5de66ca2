"""The FBX encoder (``com.esri.prt.codecs.FBXEncoder``): the file read back by ufbx, a reader
independent of the writer, and the same checks passed by the FBX that CityEngine's runtime
(PyPRT 1.12) wrote of the same shapes (tests/data/fbx-pyprt/README.md)."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from prt_shapes import DATA, EXTRUSION, FIXED, SMALL, SQUARE

import shapegen.prt as pyprt
from shapegen.errors import OptionError

ufbx = pytest.importorskip("ufbx")

CITYENGINE_FILE = DATA / "fbx-pyprt" / "extrusion_pyprt112_0.fbx"
FBX = "com.esri.prt.codecs.FBXEncoder"


def read_fbx(path: Path) -> list[dict]:
    """Each mesh node of the file, in metres and y up: its name, vertices ``(n, 3)``, faces
    (vertex indices as the file has them), each face corner's normal, its materials' colours
    and each face's material; read by ufbx (plain data: nothing of ufbx outlives the scene)."""
    scene = ufbx.load_file(
        str(path), target_axes=ufbx.axes_right_handed_y_up, target_unit_meters=1.0
    )
    meshes = []
    try:
        version, ascii_form = scene.metadata.version, scene.metadata.ascii
        for node in scene.nodes:
            if node.mesh is not None:
                meshes.append({**_mesh_data(node), "version": version, "ascii": ascii_form})
            del node  # nothing may point into the scene when it is freed
    finally:
        scene.free()
    return meshes


def _mesh_data(node) -> dict:
    """A ufbx node's mesh as plain data (nothing of ufbx kept)."""
    mesh = node.mesh
    m = node.geometry_to_world
    affine = np.array([[m.c0.x, m.c1.x, m.c2.x, m.c3.x], [m.c0.y, m.c1.y, m.c2.y, m.c3.y],
                       [m.c0.z, m.c1.z, m.c2.z, m.c3.z]])  # fmt: skip
    points = np.array([[v.x, v.y, v.z] for v in mesh.vertices], dtype=float).reshape(-1, 3)
    corners = list(mesh.vertex_indices)
    spans = [(f.index_begin, f.num_indices) for f in mesh.faces]
    faces = [corners[start : start + n] for start, n in spans]
    normals = None
    if mesh.vertex_normal.exists:
        values = [(v.x, v.y, v.z) for v in mesh.vertex_normal.values]
        indices = list(mesh.vertex_normal.indices)
        normals = [np.array([values[indices[start + k]] for k in range(n)]) for start, n in spans]
    colors = []
    for material in mesh.materials:
        c = material.fbx.diffuse_color.value_vec4
        colors.append((c.x, c.y, c.z))
        del material
    out = {
        "name": str(node.name),
        "vertices": points @ affine[:, :3].T + affine[:, 3],
        "faces": faces,
        "normals": normals,
        "colors": colors,
        "face_materials": list(mesh.face_material) if colors else [],
    }
    del mesh, m
    return out


def polygons(meshes: list[dict]) -> list[tuple]:
    """Every face as its corners' coordinates (mm), starting at its least corner so that a
    face reads the same wherever its ring starts, sorted: the geometry, however it is split
    into meshes or its vertices numbered."""
    out = []
    for mesh in meshes:
        for face in mesh["faces"]:
            ring = [tuple(np.round(mesh["vertices"][i] * 1000).astype(int)) for i in face]
            first = ring.index(min(ring))
            out.append(tuple(ring[first:] + ring[:first]))
    return sorted(out)


def check_normals(meshes: list[dict], *, boxes: bool = True) -> None:
    """Each face corner's normal is a unit vector across the face's plane (at right angles to
    its edges) on the side the face's corners turn counter-clockwise, and (``boxes``) points out
    of the closed box the face belongs to (the centre of the faces
    joined to it by shared corners: a mesh may hold several boxes)."""
    for mesh in meshes:
        roots = corner_groups(len(mesh["vertices"]), mesh["faces"])
        for face, normals in zip(mesh["faces"], mesh["normals"], strict=True):
            centre = mesh["vertices"][roots == roots[face[0]]].mean(axis=0)
            ring = mesh["vertices"][face]
            edges = np.roll(ring, -1, axis=0) - ring
            for normal in normals:
                assert np.linalg.norm(normal) == pytest.approx(1.0)
                assert np.abs(edges @ normal).max() < 1e-9
                assert np.cross(ring, np.roll(ring, -1, axis=0)).sum(axis=0) @ normal > 0.0
                if boxes:
                    assert (ring.mean(axis=0) - centre) @ normal > 0.0


def corner_groups(count: int, faces: list[list[int]]) -> np.ndarray:
    """For each vertex, the root of the group of vertices joined by faces (union-find)."""
    part = list(range(count))

    def root(i: int) -> int:
        while part[i] != i:
            i = part[i]
        return i

    for face in faces:
        for i in face[1:]:
            part[root(i)] = root(face[0])
    return np.array([root(i) for i in range(count)])


def generate(tmp_path: Path, **options) -> list:
    generator = pyprt.ModelGenerator([pyprt.InitialShape(SQUARE), pyprt.InitialShape(SMALL)])
    generator.generate_model(
        [FIXED, FIXED], str(EXTRUSION), FBX, {"outputPath": str(tmp_path), **options}
    )
    return pyprt.ModelGenerator(
        [pyprt.InitialShape(SQUARE), pyprt.InitialShape(SMALL)]
    ).generate_model([FIXED, FIXED], str(EXTRUSION), "com.esri.pyprt.PyEncoder", {})


def test_each_shape_is_a_node_whose_mesh_is_the_model(tmp_path):
    models = generate(tmp_path, baseName="extrusion")
    meshes = read_fbx(tmp_path / "extrusion_0.fbx")
    assert not meshes[0]["ascii"] and meshes[0]["version"] == 7400
    assert [m["name"] for m in meshes] == ["shape_0", "shape_1"]
    for mesh, model in zip(meshes, models, strict=True):
        vertices = np.array(model.get_vertices()).reshape(-1, 3)
        np.testing.assert_allclose(mesh["vertices"], vertices, atol=1e-9)
        indices = iter(model.get_indices())
        assert mesh["faces"] == [[next(indices) for _ in range(n)] for n in model.get_faces()]
        assert [len(f) for f in mesh["faces"]] == [4] * 6  # the box's quads kept whole
    check_normals(meshes)
    # the rule's buildingColor, #FF00FF, on every face
    assert all(m["colors"] == [(1.0, 0.0, 1.0)] and set(m["face_materials"]) == {0}
               for m in meshes)  # fmt: skip
    for name in ("CGAReport.txt", "CGAPrint.txt", "CGAError.txt"):
        assert (tmp_path / name).is_file()


def test_cityengines_file_passes_the_same_checks_and_holds_the_same_faces(tmp_path):
    """The reader and checks read a file CityEngine's runtime wrote: its two boxes (one mesh)
    are shapegen's, face for face, in the same place and colour."""
    generate(tmp_path)
    ours = read_fbx(tmp_path / "base_name_0.fbx")
    theirs = read_fbx(CITYENGINE_FILE)
    assert not theirs[0]["ascii"] and theirs[0]["version"] == 7700
    check_normals(theirs)
    assert polygons(theirs) == polygons(ours)
    assert len(polygons(ours)) == 12
    assert theirs[0]["colors"] == ours[0]["colors"]


def test_options_change_what_is_written(tmp_path):
    generate(tmp_path, vertexNormals="NONE", includeMaterials=False)
    meshes = read_fbx(tmp_path / "base_name_0.fbx")
    assert all(m["normals"] is None and m["colors"] == [] for m in meshes)
    target = tmp_path / "base_name_0.fbx"
    target.write_bytes(b"kept")
    generate(tmp_path, existingFiles="SKIP")
    assert target.read_bytes() == b"kept"
    generate(tmp_path, existingFiles="OVERWRITE")
    assert len(read_fbx(target)) == 2


@pytest.mark.parametrize(
    ("options", "words"),
    [
        ({"fileType": "TEXT"}, "binary FBX only"),
        ({"triangulateMeshes": True}, "triangulateMeshes True"),
        ({"embedTextures": True}, "embedTextures True"),
        ({"globalOffset": [1, 0, 0]}, "globalOffset"),
        ({"localOffset": "SHAPE_CENTROID"}, "localOffset"),
        ({"fileGranularity": "START_SHAPE"}, "fileGranularity"),
        ({"facesWithHoles": "PASS"}, "facesWithHoles"),
        ({"vertexNormals": "SOME"}, "vertexNormals 'SOME'"),
        ({"includeMaterials": "yes"}, "includeMaterials is a boolean"),
        ({"author": "me"}, "'author'"),
        ({"colour": 1}, "not colour"),
    ],
)
def test_an_option_it_cannot_honour_is_refused_before_anything_is_written(tmp_path, options, words):
    with pytest.raises(OptionError, match=words) as caught:
        generate(tmp_path, **options)
    assert "\n" not in str(caught.value)
    assert list(tmp_path.iterdir()) == []


def records(data: bytes) -> list[tuple]:
    """The top-level records of a binary FBX file (versions below 7500: 32-bit offsets), each
    ``(name, [(type letter, value)], children)``, parsed from the format's description."""
    import struct

    sizes = {"Y": "<h", "C": "<?", "I": "<i", "F": "<f", "D": "<d", "L": "<q"}

    def record(offset: int):
        end, count, _, length = struct.unpack_from("<IIIB", data, offset)
        if end == 0:
            return None, offset + 13
        name = data[offset + 13 : offset + 13 + length].decode()
        offset += 13 + length
        values = []
        for _ in range(count):
            kind = chr(data[offset])
            offset += 1
            if kind in sizes:
                values.append((kind, struct.unpack_from(sizes[kind], data, offset)[0]))
                offset += struct.calcsize(sizes[kind])
            elif kind in "SR":
                (size,) = struct.unpack_from("<I", data, offset)
                values.append((kind, data[offset + 4 : offset + 4 + size]))
                offset += 4 + size
            else:
                _, _, size = struct.unpack_from("<III", data, offset)
                values.append((kind, None))
                offset += 12 + size
        children = []
        while offset < end:
            child, offset = record(offset)
            if child is None:
                break
            children.append(child)
        return (name, values, children), end

    out, offset = [], 27
    while True:
        top, offset = record(offset)
        if top is None:
            return out
        out.append(top)


def test_the_file_holds_what_autodesks_reader_asks(tmp_path):
    """What CityEngine's runtime (Autodesk's FBX SDK) needed to find the meshes, measured:
    int64 ids, every object type declared, the footer code with its FileId and CreationTime
    (the pair PyPRT's file shows: another time with the same code is not read), 16-byte end."""
    generate(tmp_path)
    data = (tmp_path / "base_name_0.fbx").read_bytes()
    assert data[:27] == b"Kaydara FBX Binary  \x00\x1a\x00" + (7400).to_bytes(4, "little")
    assert len(data) % 16 == 0 and data.endswith(bytes.fromhex("f85a8c6adef5d97eece90ce3758f290b"))
    top = {name: (values, children) for name, values, children in records(data)}
    assert top["FileId"][0] == [("R", bytes.fromhex("28b32aebb624ccc2bfc8b02aa92bfcf1"))]
    assert top["CreationTime"][0] == [("S", b"1970-01-01 10:00:00:000")]
    assert bytes.fromhex("fabcab09d0c8d466b176fb831cf7267e") in data[-176:]
    objects = top["Objects"][1]
    assert {name for name, _, _ in objects} == {"Geometry", "Model", "Material"}
    assert all(values[0][0] == "L" for _, values, _ in objects)
    links = [values for name, values, _ in top["Connections"][1] if name == "C"]
    assert links and all(v[1][0] == "L" and v[2][0] == "L" for v in links)
    declared = {
        values[0][1].decode(): next(c[1][0][1] for c in children if c[0] == "Count")
        for name, values, children in top["Definitions"][1]
        if name == "ObjectType"
    }
    assert declared == {"GlobalSettings": 1, "Model": 2, "Geometry": 2, "Material": 2}


def test_vertices_within_the_precision_are_merged_and_a_face_they_collapse_is_dropped():
    from shapegen.prt.fbx_encoder import merged_vertices

    # two unit quads side by side, each with its own corners; the second's shared edge 0.5 mm
    # off; a sliver triangle whose corners are all within 1 mm of one place
    vertices = np.array([[0, 0, 0], [1, 0, 0], [1, 0, 1], [0, 0, 1],
                         [1.0005, 0, 0], [2, 0, 0], [2, 0, 1], [1.0005, 0, 1],
                         [5, 0, 5], [5.0004, 0, 5], [5, 0, 5.0004]], dtype=float)  # fmt: skip
    faces = [[0, 1, 2, 3], [4, 5, 6, 7], [8, 9, 10]]
    points, merged, kept = merged_vertices(vertices, faces, 0.001)
    assert len(points) == 6 and kept == [0, 1]
    assert merged == [[0, 1, 2, 3], [1, 4, 5, 2]]
    np.testing.assert_allclose(points[merged[1][0]], [1, 0, 0])  # the first one's place
    points, merged, kept = merged_vertices(vertices, faces, 0.0001)
    assert len(points) == 11 and kept == [0, 1, 2]


@pytest.mark.parametrize(
    ("options", "words"),
    [({"vertexPrecision": 5.0}, "not between 0 and 1"), ({"mergeVertices": 1}, "a boolean")],
)
def test_a_merge_option_out_of_range_is_refused(tmp_path, options, words):
    with pytest.raises(OptionError, match=words):
        generate(tmp_path, **options)
    assert list(tmp_path.iterdir()) == []


COURTYARD_FILE = DATA / "fbx-pyprt" / "courtyard_pyprt112_0.fbx"
COURTYARD = [0, 0, 0, 0, 0, 10, 10, 0, 10, 10, 0, 0, 3, 0, 3, 7, 0, 3, 7, 0, 7, 3, 0, 7]


def surface(meshes: list[dict]) -> float:
    """The faces' total area (m²): each polygon's area vector (Newell) halved."""
    total = 0.0
    for mesh in meshes:
        for face in mesh["faces"]:
            ring = mesh["vertices"][face]
            total += np.linalg.norm(np.cross(ring, np.roll(ring, -1, axis=0)).sum(axis=0)) / 2
    return total


def volume(meshes: list[dict]) -> float:
    """The volume the faces enclose (m³), by the divergence theorem over fans of triangles:
    positive when every face turns counter-clockwise seen from outside."""
    total = 0.0
    for mesh in meshes:
        for face in mesh["faces"]:
            a, *rest = mesh["vertices"][face]
            for b, c in zip(rest, rest[1:], strict=False):
                total += np.dot(a, np.cross(b, c)) / 6
    return total


def test_a_face_with_a_hole_is_written_as_triangles_around_the_hole(tmp_path):
    """A 10 x 10 lot with a 4 x 4 courtyard, extruded 23 m: roof and floor with their hole as
    triangles (CityEngine's default facesWithHoles), the eight walls as quads; its surface in
    closed form, 2 (100 - 16) + 4 (10 x 23) + 4 (4 x 23) = 1456 m²; none of it over the
    courtyard; the triangle and quad counts of CityEngine's own file of it."""
    shape = pyprt.InitialShape(COURTYARD, [0, 1, 2, 3, 4, 5, 6, 7], [4, 4], [[0, 1]])
    pyprt.ModelGenerator([shape]).generate_model(
        [FIXED], str(EXTRUSION), FBX, {"outputPath": str(tmp_path)}
    )
    ours, theirs = read_fbx(tmp_path / "base_name_0.fbx"), read_fbx(COURTYARD_FILE)
    for meshes in (ours, theirs):
        assert surface(meshes) == pytest.approx(2 * (100 - 16) + 4 * 10 * 23 + 4 * 4 * 23)
        sizes = sorted(len(face) for mesh in meshes for face in mesh["faces"])
        assert sizes == [3] * 16 + [4] * 8
        check_normals(meshes, boxes=False)
        assert volume(meshes) == pytest.approx((100 - 16) * 23)  # the faces turn outwards
        for mesh in meshes:
            for face in mesh["faces"]:
                x, _, z = mesh["vertices"][face].mean(axis=0)
                assert not (3 < x < 7 and 3 < z < 7)  # no face over the courtyard


def test_a_colour_is_written_as_cityengines_runtime_writes_it(tmp_path):
    """PyPRT 1.12's FBX of this rule with buildingColor #808080 holds DiffuseColor
    0.2195197180748679 (measured): (128 / 255) ** 2.2."""
    generator = pyprt.ModelGenerator([pyprt.InitialShape(SQUARE)])
    generator.generate_model(
        [{**FIXED, "buildingColor": "#808080"}], str(EXTRUSION), FBX, {"outputPath": str(tmp_path)}
    )
    (mesh,) = read_fbx(tmp_path / "base_name_0.fbx")
    assert mesh["colors"] == [pytest.approx((0.2195197180748679,) * 3, abs=1e-12)]

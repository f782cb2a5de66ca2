"""An initial shape read from an OBJ file keeps its texture coordinates and material through
the derivation and into the FBX file, as CityEngine's runtime writes them: compared, corner by
corner, with the FBX PyPRT 1.12 wrote of the same file and rule
(tests/data/fbx-pyprt/README.md), read back by ufbx, a reader independent of the writer."""

from __future__ import annotations

import shutil
from pathlib import Path

import numpy as np
import pytest

import shapegen.prt as pyprt

ufbx = pytest.importorskip("ufbx")

DATA = Path(__file__).parent / "data"
CORPUS = Path(__file__).parents[1] / "data" / "cga-corpus"
IDENTITY_RULE = CORPUS / "tests_data_identity__c7aa1921" / "rules" / "identity.cga"
PYPRT_FILE = Path(__file__).parents[1] / "data" / "fbx-pyprt" / "bonnland_pyprt112_0.fbx"
PYPRT_OBJ = Path(__file__).parents[1] / "data" / "obj-pyprt" / "bonnland_pyprt112_0.obj"
FBX = "com.esri.prt.codecs.FBXEncoder"


def read_corners(path: Path) -> dict:
    """Every face of the file as its corners' (position mm, uv) pairs, starting at its least
    corner, sorted; and each material's name, diffuse colour and texture file (as the file
    names it, relative and absolute). Plain data: nothing of ufbx outlives the scene."""
    scene = ufbx.load_file(
        str(path), target_axes=ufbx.axes_right_handed_y_up, target_unit_meters=1.0
    )
    faces, materials = [], {}
    try:
        for node in scene.nodes:
            mesh = node.mesh
            if mesh is None:
                continue
            m = node.geometry_to_world
            affine = np.array([[m.c0.x, m.c1.x, m.c2.x, m.c3.x], [m.c0.y, m.c1.y, m.c2.y, m.c3.y],
                               [m.c0.z, m.c1.z, m.c2.z, m.c3.z]])  # fmt: skip
            points = np.array([[v.x, v.y, v.z] for v in mesh.vertices]).reshape(-1, 3)
            points = points @ affine[:, :3].T + affine[:, 3]
            corners = list(mesh.vertex_indices)
            uvs = uv_index = None
            if mesh.vertex_uv.exists:
                uvs = [(v.x, v.y) for v in mesh.vertex_uv.values]
                uv_index = list(mesh.vertex_uv.indices)
            for start, count in [(f.index_begin, f.num_indices) for f in mesh.faces]:
                ring = []
                for i in range(start, start + count):
                    key = tuple(int(v) for v in np.round(points[corners[i]] * 1000))
                    uv = None if uvs is None else tuple(np.round(uvs[uv_index[i]], 9).tolist())
                    ring.append((key, uv))
                first = ring.index(min(ring))
                faces.append(tuple(ring[first:] + ring[:first]))
            for material in mesh.materials:
                diffuse = material.fbx.diffuse_color
                texture = diffuse.texture
                c = diffuse.value_vec4
                materials[str(material.name)] = {
                    "diffuse": (c.x, c.y, c.z),
                    "texture": None if texture is None else str(texture.relative_filename),
                    "absolute": None if texture is None else str(texture.absolute_filename),
                }
                del material, diffuse, texture
            del mesh, m, node
    finally:
        scene.free()
    return {"faces": sorted(faces), "materials": materials}


def generate(tmp_path: Path, obj: Path, depth: int = 0, rule: Path = IDENTITY_RULE, **options):
    out = tmp_path / "out"
    out.mkdir(exist_ok=True)
    shape = pyprt.InitialShape(str(obj), depth)
    (model,) = pyprt.ModelGenerator([shape]).generate_model([{}], str(rule))
    pyprt.ModelGenerator([shape]).generate_model(
        [{}], str(rule), FBX, {"outputPath": str(out), **options}
    )
    return model, out


def test_an_obj_passed_through_is_written_with_its_uvs_and_texture_as_cityengine_writes_it(
    tmp_path,
):
    model, out = generate(tmp_path, DATA / "Bonnland_102.obj")
    ours, theirs = read_corners(out / "base_name_0.fbx"), read_corners(PYPRT_FILE)
    assert model.get_cga_errors() == []
    assert len(theirs["faces"]) == 14 and all(
        uv is not None for f in theirs["faces"] for _, uv in f
    )
    assert ours["faces"] == theirs["faces"]
    assert list(ours["materials"]) == list(theirs["materials"]) == ["Bonnland_102_mat"]
    mine, cityengine = (
        ours["materials"]["Bonnland_102_mat"],
        theirs["materials"]["Bonnland_102_mat"],
    )
    assert mine["diffuse"] == pytest.approx(cityengine["diffuse"], abs=1e-12)
    assert Path(mine["texture"]).name == Path(cityengine["texture"]).name == "Bonnland_102.png"
    # the texture is copied beside the FBX file, which names the copy
    assert (out / "Bonnland_102.png").read_bytes() == (DATA / "Bonnland_102.png").read_bytes()
    assert Path(mine["absolute"]) == (out / "Bonnland_102.png").resolve()


def test_without_collecting_the_texture_the_file_names_the_original(tmp_path):
    _, out = generate(tmp_path, DATA / "Bonnland_102.obj", collectTextures=False)
    (material,) = read_corners(out / "base_name_0.fbx")["materials"].values()
    assert not (out / "Bonnland_102.png").exists()
    assert Path(material["absolute"]).resolve() == (DATA / "Bonnland_102.png").resolve()


def test_texture_coordinates_none_writes_no_uv_layer_but_keeps_the_textured_material(tmp_path):
    """As PyPRT 1.12 writes with textureCoordinates NONE: no LayerElementUV, the material
    still tied to its texture, which is still copied."""
    _, out = generate(tmp_path, DATA / "Bonnland_102.obj", textureCoordinates="NONE")
    read = read_corners(out / "base_name_0.fbx")
    assert all(uv is None for face in read["faces"] for _, uv in face)
    assert read["materials"]["Bonnland_102_mat"]["texture"] == "Bonnland_102.png"
    assert (out / "Bonnland_102.png").exists()


@pytest.mark.parametrize(("depth", "found"), [(0, False), (1, False), (2, True)])
def test_files_the_obj_names_are_found_within_the_recursion_depth(tmp_path, depth, found):
    """PyPRT 1.12 on OBJ-Bonnland-nested (library two folders down, texture one): the
    material is found with depth 2 and "Could not resolve material" with 0 and 1."""
    model, out = generate(tmp_path, DATA / "OBJ-Bonnland-nested" / "Bonnland_102.obj", depth)
    read = read_corners(out / "base_name_0.fbx")
    assert (out / "Bonnland_102.png").exists() == found
    assert ("Bonnland_102_mat" in read["materials"]) == found
    errors = model.get_cga_errors()
    if found:
        assert errors == []
        assert read["faces"] == read_corners(PYPRT_FILE)["faces"]
    else:
        assert len(errors) == 1 and "could not resolve material library" in errors[0]
        assert "'a/b/Bonnland_102.mtl'" in errors[0] and f"within {depth} folder" in errors[0]


def test_a_library_or_texture_outside_the_files_folder_is_not_read(tmp_path):
    folder = tmp_path / "shape"
    folder.mkdir()
    shutil.copy(DATA / "Bonnland_102.png", tmp_path / "outside.png")
    text = (DATA / "Bonnland_102.obj").read_text()
    (folder / "b.obj").write_text(text.replace("mtllib Bonnland_102.mtl", "mtllib b.mtl"))
    (folder / "b.mtl").write_text("newmtl Bonnland_102\nKd 1 0 0\nmap_Kd ../outside.png\n")
    model, out = generate(tmp_path, folder / "b.obj", 5)
    read = read_corners(out / "base_name_0.fbx")
    (error,) = model.get_cga_errors()
    assert "could not resolve texture '../outside.png'" in error
    assert read["materials"]["Bonnland_102_mat"] == {
        "diffuse": (1.0, 0.0, 0.0), "texture": None, "absolute": None}  # fmt: skip


def square_obj(folder: Path) -> Path:
    """A 10 x 10 m level square whose texture coordinates are (x, z) / 10 at each corner, in
    two triangles, with a textured material."""
    shutil.copy(DATA / "Bonnland_102.png", folder / "tex.png")
    (folder / "square.mtl").write_text("newmtl stone\nKd 1 1 1\nmap_Kd tex.png\n")
    (folder / "square.obj").write_text(
        "mtllib square.mtl\n"
        "v 0 0 0\nv 0 0 10\nv 10 0 10\nv 10 0 0\n"
        "vt 0 0\nvt 0 1\nvt 1 1\nvt 1 0\n"
        "usemtl stone\nf 1/1 2/2 3/3 4/4\n"
    )
    return folder / "square.obj"


def write_rule(folder: Path, body: str) -> Path:
    path = folder / "rule.cga"
    path.write_text(f'version "2023.0"\n\n@StartRule\nLot -->\n    {body}\n')
    return path


def test_faces_cut_from_an_initial_face_take_its_coordinates_between_corners(tmp_path):
    """split cuts the square into strips; each strip's corners take the square's texture
    coordinates where they lie: (x, z) / 10 (the closed form of this square's layout)."""
    rule = write_rule(tmp_path, "split(x) { 2.5 : X. | ~1 : X. }")
    model, out = generate(tmp_path, square_obj(tmp_path), rule=rule)
    read = read_corners(out / "base_name_0.fbx")
    assert model.get_cga_errors() == []
    assert len(read["faces"]) == 2
    zs = set()
    for face in read["faces"]:
        for (x, _, z), uv in face:
            assert uv == pytest.approx((x / 10000, z / 10000), abs=1e-9)
            zs.add(z)
    assert zs == {0, 2500, 10000}  # the scope's x runs along the first edge, along z


def test_faces_moved_off_the_initial_faces_lose_their_coordinates_with_a_warning(tmp_path):
    rule = write_rule(tmp_path, "t(20, 0, 0) X.")
    model, out = generate(tmp_path, square_obj(tmp_path), rule=rule)
    read = read_corners(out / "base_name_0.fbx")
    warning, moves = model.get_cga_errors()
    assert warning.startswith(
        "texture coordinates: 1 of 1 faces are neither on nor over the initial shape"
    )
    assert moves.startswith("texture coordinates: the rule uses t; ")
    assert all(uv is None for face in read["faces"] for _, uv in face)
    # the shape keeps its one material's colour; its texture goes with the coordinates
    assert read["materials"]["stone_mat"]["texture"] is None


def _uv_corners(path: Path) -> list:
    """Every face of an OBJ file as its corners' (position mm, texture coordinates) from its
    least corner, sorted."""
    from shapegen.readers.obj import obj_surface

    surface = obj_surface(path.read_text(), str(path))
    faces = []
    for face, uv in zip(surface.faces, surface.face_uvs, strict=True):
        ring = [tuple(np.round(surface.vertices[i] * 1000).astype(int).tolist()) for i in face]
        first = ring.index(min(ring))
        order = [(first + n) % len(ring) for n in range(len(ring))]
        faces.append((tuple(ring[n] for n in order), np.asarray(uv)[order].tolist()))
    return sorted(faces, key=lambda face: face[0])


@pytest.mark.parametrize(("name", "height"), [("square", 4), ("l", 3), ("l_down", -3)])
def test_an_extrusion_s_faces_take_the_coordinates_of_the_corners_they_rise_from(
    tmp_path, name, height
):
    """PyPRT 1.12's OBJ files of the corpus's extrusion_rule on these initial shapes
    (tools/prt_extrusion_uvs.py): every corner of the top and the sides has the coordinates of
    the initial corner it was extruded from (a side's texture is its edge's, stretched up),
    both ways up; PyPRT writes them to 4 decimals."""
    source = PYPRT_OBJ.parent / f"uv_{name.removesuffix('_down')}.obj"
    rule = write_rule(tmp_path, f"extrude({height}) X.")
    shape = pyprt.InitialShape(str(source))
    (model,) = pyprt.ModelGenerator([shape]).generate_model([{}], str(rule))
    pyprt.ModelGenerator([shape]).generate_model(
        [{}], str(rule), "com.esri.prt.codecs.OBJEncoder", {"outputPath": str(tmp_path)}
    )
    assert model.get_cga_errors() == []
    ours = _uv_corners(tmp_path / "base_name_0.obj")
    theirs = _uv_corners(PYPRT_OBJ.parent / f"extruded_{name}_pyprt112_0.obj")
    assert [face for face, _ in ours] == [face for face, _ in theirs]
    for (_, mine), (_, cityengine) in zip(ours, theirs, strict=True):
        assert np.abs(np.subtract(mine, cityengine)).max() <= 1e-4


def test_a_split_of_an_extrusion_keeps_the_coordinates_of_the_corners_below(tmp_path):
    """Cut into floors, an extrusion's sides interpolate between corners of equal coordinates:
    each floor's corners have those of the square's corner below them, (x, z) / 10."""
    rule = write_rule(tmp_path, "extrude(6) split(y) { 2 : X. }*")
    model, out = generate(tmp_path, square_obj(tmp_path), rule=rule)
    read = read_corners(out / "base_name_0.fbx")
    assert model.get_cga_errors() == []
    assert {y for face in read["faces"] for (_, y, _), _ in face} == {0, 2000, 4000, 6000}
    for face in read["faces"]:
        for (x, _, z), uv in face:
            assert uv == pytest.approx((x / 10000, z / 10000), abs=1e-9)


def obj_corners(path: Path) -> list:
    """Every face of an OBJ file as its corners' positions (mm), from its least corner, with
    their texture coordinates, its material's diffuse colour and texture file name; sorted by
    the positions."""
    from shapegen.readers.mtl import mtl_materials
    from shapegen.readers.obj import obj_surface

    surface = obj_surface(path.read_text(), str(path))
    (library,) = surface.libraries
    materials = mtl_materials((path.parent / library).read_text(), library)
    faces = []
    for face, uv, name in zip(surface.faces, surface.face_uvs, surface.face_materials,
                              strict=True):  # fmt: skip
        ring = [tuple(np.round(surface.vertices[i] * 1000).astype(int).tolist()) for i in face]
        first = ring.index(min(ring))
        order = [(first + n) % len(ring) for n in range(len(ring))]
        look = materials[name]
        faces.append((tuple(ring[n] for n in order), uv[order].tolist(), look.diffuse,
                      Path(look.texture).name))  # fmt: skip
    return sorted(faces, key=lambda face: face[0])


def test_the_obj_encoder_writes_the_uvs_and_material_as_cityengine_writes_them(tmp_path):
    """PyPRT writes texture coordinates to 4 decimals, shapegen to 6: equal within 1e-4."""
    shape = pyprt.InitialShape(str(DATA / "Bonnland_102.obj"))
    pyprt.ModelGenerator([shape]).generate_model(
        [{}], str(IDENTITY_RULE), "com.esri.prt.codecs.OBJEncoder", {"outputPath": str(tmp_path)}
    )
    ours = obj_corners(tmp_path / "base_name_0.obj")
    theirs = obj_corners(PYPRT_OBJ)
    assert len(theirs) == 14
    assert [(f[0], f[2], f[3]) for f in ours] == [(f[0], f[2], f[3]) for f in theirs]
    for mine, cityengine in zip(ours, theirs, strict=True):
        assert np.abs(np.subtract(mine[1], cityengine[1])).max() <= 1e-4
    assert (tmp_path / "Bonnland_102.png").read_bytes() == (DATA / "Bonnland_102.png").read_bytes()


@pytest.mark.parametrize("encoder", ["GLTFEncoder", "I3SEncoder"])
def test_an_encoder_that_writes_no_texture_says_so(tmp_path, encoder):
    shape = pyprt.InitialShape(str(DATA / "Bonnland_102.obj"))
    pyprt.ModelGenerator([shape]).generate_model(
        [{}], str(IDENTITY_RULE), f"com.esri.prt.codecs.{encoder}", {"outputPath": str(tmp_path)}
    )
    (line,) = (tmp_path / "CGAError.txt").read_text().splitlines()
    assert line.startswith(f"com.esri.prt.codecs.{encoder}: shapegen's encoder writes no texture")


def test_a_broken_texture_coordinate_leaves_the_model_untextured_with_one_line(tmp_path):
    text = (DATA / "Bonnland_102.obj").read_text().replace("vt 0.0877396028586", "vt x", 1)
    shutil.copy(DATA / "Bonnland_102.mtl", tmp_path)
    (tmp_path / "Bonnland_102.obj").write_text(text)
    (model,) = pyprt.ModelGenerator([pyprt.InitialShape(str(tmp_path / "Bonnland_102.obj"))]
                                    ).generate_model([{}], str(IDENTITY_RULE))  # fmt: skip
    (error,) = model.get_cga_errors()
    assert "a texture coordinate needs u v numbers: no texture coordinates read" in error
    assert model.initial_texture is None and len(model.get_faces()) == 14


def test_a_rule_that_moves_faces_within_their_plane_is_named_in_a_warning(tmp_path):
    """t(2, 0, 0) moves the strip along the square: CityEngine's corners keep their own
    coordinates; shapegen's take those of where they lie, and one line says which operations
    make them differ."""
    rule = write_rule(tmp_path, "split(x) { 2.5 : t(0, 0, 2) X. | ~1 : r(0, 10, 0) X. }")
    model, _ = generate(tmp_path, square_obj(tmp_path), rule=rule)
    moves = [e for e in model.get_cga_errors() if "the rule uses" in e]
    assert moves == [
        "texture coordinates: the rule uses t, r; shapegen carries an initial shape's"
        " coordinates by where faces lie, so a face moved within an initial face's plane, or"
        " inserted on it, takes those of where it lies, which CityEngine's need not be"
    ]

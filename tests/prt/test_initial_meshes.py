"""Initial shapes of many faces read from files, as PyPRT makes them: every face of the file in
one start shape, read as CityEngine's runtime reads it. Counts measured with PyPRT 1.12
(``data/prt_initial_shape_counts.json`` says how)."""

import json
import os
import sys
from collections import Counter
from pathlib import Path

import numpy as np
import pytest

import shapegen.prt as pyprt
from shapegen.errors import InputFormatError
from shapegen.prt.initial_shapes import start_of
from shapegen.readers.fbx import MISSING

DATA = Path(__file__).parent / "data"
MEASURED = json.loads((DATA / "prt_initial_shape_counts.json").read_text())["shapes"]
IDENTITY = Path(__file__).parents[1] / "data" / "cga-corpus" / "tests_data_identity__c7aa1921"
IDENTITY_RULE = IDENTITY / "rules" / "identity.cga"
#: a checkout of Esri/pyprt, for its 2.6 MB FBX file (not copied here)
CHECKOUT = os.environ.get("SHAPEGEN_PYPRT_CHECKOUT", "")


def _file(tmp_path: Path, name: str) -> Path:
    if name == "box.glb":
        trimesh = pytest.importorskip("trimesh")
        box = trimesh.creation.box((2, 3, 4))
        box.apply_translation((5, 1.5, 0))
        box.export(tmp_path / name)
        return tmp_path / name
    if name.endswith(".fbx"):
        pytest.importorskip("ufbx", reason=MISSING)
        path = Path(CHECKOUT, "tests", "data", name)
        if not CHECKOUT or not path.is_file():
            pytest.skip(f"{name} is in Esri/pyprt's tests: set SHAPEGEN_PYPRT_CHECKOUT")
        return path
    return DATA / name


@pytest.mark.parametrize("name", sorted(MEASURED))
def test_a_file_is_one_initial_shape_of_all_its_faces_as_pyprt_reads_it(tmp_path, name):
    expected = MEASURED[name]
    (model,) = pyprt.ModelGenerator(
        [pyprt.InitialShape(str(_file(tmp_path, name)), 2)]
    ).generate_model([{}], str(IDENTITY_RULE))
    points = np.array(model.get_vertices()).reshape(-1, 3)
    sizes = Counter(model.get_faces())
    assert model.get_cga_errors() == []
    assert (len(points), len(model.get_faces())) == (expected["vertices"], expected["faces"])
    assert {str(k): v for k, v in sorted(sizes.items())} == expected["face_sizes"]
    if "bounds_m" in expected:
        assert points.min(axis=0) == pytest.approx(expected["bounds_m"][0], abs=1e-5)
        assert points.max(axis=0) == pytest.approx(expected["bounds_m"][1], abs=1e-5)


def test_a_file_of_one_level_face_is_still_a_polygon_lot():
    start = start_of(pyprt.InitialShape(str(DATA / "Bonnland_102.obj")))
    assert type(start).__name__ == "MeshLot" and len(start.faces) == 14
    square = pyprt.InitialShape([0, 0, 0, 0, 0, 10, 10, 0, 10, 10, 0, 0])
    assert type(start_of(square)).__name__ == "Footprint"


def _block_fbx(path: Path) -> None:
    """A 1 m cube of six quads and a level pentagon, written in centimetres (ASCII FBX 7.3)."""
    corners = [0, 0, 0, 100, 0, 0, 100, 100, 0, 0, 100, 0, 0, 0, 100, 100, 0, 100, 100, 100, 100,
               0, 100, 100, 300, 0, 0, 400, 0, 0, 450, 0, 80, 350, 0, 150, 250, 0, 80]  # fmt: skip
    faces = [[0, 3, 2, 1], [4, 5, 6, 7], [0, 1, 5, 4], [1, 2, 6, 5], [2, 3, 7, 6], [3, 0, 4, 7],
             [8, 12, 11, 10, 9]]  # fmt: skip
    index = [i for f in faces for i in [*f[:-1], -f[-1] - 1]]  # FBX ends a face with -(i + 1)
    settings = "".join(
        f'\t\tP: "{name}", "int", "Integer", "",{value}\n'
        for name, value in [("UpAxis", 1), ("UpAxisSign", 1), ("FrontAxis", 2),
                            ("FrontAxisSign", 1), ("CoordAxis", 0), ("CoordAxisSign", 1)]
    )  # fmt: skip
    path.write_text(
        "; FBX 7.3.0 project file\nFBXHeaderExtension:  {\n\tFBXVersion: 7300\n}\n"
        "GlobalSettings:  {\n\tVersion: 1000\n\tProperties70:  {\n" + settings
        + '\t\tP: "UnitScaleFactor", "double", "Number", "",1\n\t}\n}\n'
        'Objects:  {\n\tGeometry: 1000, "Geometry::block", "Mesh" {\n'
        f"\t\tVertices: *{len(corners)} {{\n\t\t\ta: {','.join(map(str, corners))}\n\t\t}}\n"
        f"\t\tPolygonVertexIndex: *{len(index)} {{\n\t\t\ta: {','.join(map(str, index))}\n\t\t}}\n"
        '\t}\n\tModel: 2000, "Model::block", "Mesh" {\n\t\tVersion: 232\n\t}\n}\n'
        'Connections:  {\n\tC: "OO",2000,0\n\tC: "OO",1000,2000\n}\n'
    )  # fmt: skip


def test_an_fbx_file_is_read_with_its_faces_whole_in_metres(tmp_path):
    pytest.importorskip("ufbx", reason=MISSING)
    from shapegen.readers.fbx import fbx_polygons

    _block_fbx(tmp_path / "block.fbx")
    vertices, faces = fbx_polygons(tmp_path / "block.fbx")
    assert [len(f) for f in faces] == [4] * 6 + [5]
    assert vertices.min(axis=0) == pytest.approx([0, 0, 0])
    assert vertices.max(axis=0) == pytest.approx([4.5, 1.0, 1.5])  # centimetres made metres
    cube = vertices[sorted({i for f in faces[:6] for i in f})]
    assert len(cube) == 8 and np.allclose(np.sort(np.abs(cube - 0.5), axis=0), 0.5)


def test_without_ufbx_an_fbx_shape_is_one_line_saying_what_to_install(
    tmp_path, monkeypatch, capsys
):
    path = tmp_path / "block.fbx"
    _block_fbx(path)
    monkeypatch.setitem(sys.modules, "ufbx", None)  # as if it were not installed
    with pytest.raises(InputFormatError, match=r"block\.fbx: reading FBX needs the ufbx package"):
        start_of(pyprt.InitialShape(str(path)))
    (model,) = pyprt.ModelGenerator([pyprt.InitialShape(str(path))]).generate_model(
        [{}], str(IDENTITY_RULE)
    )
    assert model.get_vertices() == [] and MISSING in model.get_cga_errors()[0]
    assert capsys.readouterr().err.strip().endswith(MISSING)

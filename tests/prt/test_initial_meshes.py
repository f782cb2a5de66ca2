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
from fbx_files import write_block_fbx

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


def test_an_fbx_file_is_read_with_its_faces_whole_in_metres(tmp_path):
    pytest.importorskip("ufbx", reason=MISSING)
    from shapegen.readers.fbx import fbx_polygons

    write_block_fbx(tmp_path / "block.fbx")
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
    write_block_fbx(path)
    monkeypatch.setitem(sys.modules, "ufbx", None)  # as if it were not installed
    with pytest.raises(InputFormatError, match=r"block\.fbx: reading FBX needs the ufbx package"):
        start_of(pyprt.InitialShape(str(path)))
    (model,) = pyprt.ModelGenerator([pyprt.InitialShape(str(path))]).generate_model(
        [{}], str(IDENTITY_RULE)
    )
    assert model.get_vertices() == [] and MISSING in model.get_cga_errors()[0]
    assert capsys.readouterr().err.strip().endswith(MISSING)

"""shapegen.prt, PyPRT's API on shapegen: each behaviour as PyPRT 1.12's reference documents it
(InitialShape, ModelGenerator.generate_model, GeneratedModel, get_rpk_attributes_info)."""

from __future__ import annotations

import math

import numpy as np
import pytest
from prt_shapes import CORPUS, EXTRUSION, FIXED, SQUARE

import shapegen.prt as pyprt
from shapegen.errors import OptionError

ARRAYS = CORPUS / "tests_data_arrayAttrs__507bccc9" / "rules" / "arrayAttrs.cga"


def generate(shapes, attrs, options=None, rule=EXTRUSION):
    generator = pyprt.ModelGenerator([pyprt.InitialShape(s) for s in shapes])
    return generator.generate_model(attrs, str(rule), "com.esri.pyprt.PyEncoder", options or {})


def test_an_initial_shape_counts_what_it_was_given():
    shape = pyprt.InitialShape(SQUARE + [5, 0, 5], [0, 1, 2, 3, 4], [5])
    assert (shape.get_vertex_count(), shape.get_index_count(), shape.get_face_counts_count()) == (
        15, 5, 1)  # fmt: skip
    assert shape.get_path() == ""
    assert pyprt.InitialShape("lot.obj").get_path() == "lot.obj"


def test_an_extruded_square_is_one_leaf_with_shared_vertices():
    (model,) = generate([SQUARE], [FIXED])
    vertices = model.get_vertices()
    assert len(vertices) == 8 * 3 and model.get_faces() == [4] * 6
    assert sum(model.get_faces()) == len(model.get_indices())
    heights = sorted(set(round(y, 9) for y in vertices[1::3]))
    assert heights == [0.0, 23.0]


def test_a_face_given_clockwise_faces_down_and_is_extruded_downwards():
    clockwise = [-10.0, 0.0, 10.0, -10.0, 0.0, 0.0, 10.0, 0.0, 0.0, 10.0, 0.0, 10.0]
    (model,) = generate([clockwise], [FIXED])
    xs, ys, zs = (model.get_vertices()[k::3] for k in range(3))
    assert sorted(set(round(y, 9) for y in ys)) == [-23.0, 0.0]
    assert (min(xs), max(xs), min(zs), max(zs)) == pytest.approx((-10, 10, 0, 10))


def test_a_raised_face_raises_the_model():
    raised = [v + 2.0 if k % 3 == 1 else v for k, v in enumerate(SQUARE)]
    (model,) = generate([raised], [FIXED])
    assert sorted(set(round(y, 9) for y in model.get_vertices()[1::3])) == [2.0, 25.0]


def test_one_dictionary_serves_every_shape_and_a_wrong_count_generates_nothing(capsys):
    models = generate([SQUARE, SQUARE], [FIXED])
    assert [m.get_initial_shape_index() for m in models] == [0, 1]
    assert generate([SQUARE, SQUARE, SQUARE], [{}, {}]) == []
    assert "2 shape attribute dictionaries for 3 initial shapes" in capsys.readouterr().err


def test_emit_options_leave_out_geometry_or_reports():
    (no_report,) = generate([SQUARE], [{}], {"emitReport": False})
    (no_geometry,) = generate([SQUARE], [{}], {"emitGeometry": False})
    assert no_report.get_report() == {} and no_report.get_vertices()
    assert no_geometry.get_vertices() == [] and no_geometry.get_faces() == []
    assert no_geometry.get_report()["Min Height.0_n"] == 1.0


def test_triangulate_gives_triangles_inside_their_faces():
    (model,) = generate([SQUARE], [FIXED], {"triangulate": True})
    assert model.get_faces() == [3] * 12
    notched = [0, 0, 0, 0, 0, 10, 10, 0, 10, 10, 0, 0, 5, 0, 5]  # not convex at (5, 5)
    (whole,) = generate([notched], [FIXED])
    (model,) = generate([notched], [FIXED], {"triangulate": True})
    assert set(model.get_faces()) == {3}
    # the triangles cover the faces' area exactly: none leaves its polygon, none overlaps
    assert _area(model) == pytest.approx(_area(whole), rel=1e-12)


def _area(model) -> float:
    xyz = np.array(model.get_vertices()).reshape(-1, 3)
    indices, total = iter(model.get_indices()), 0.0
    for count in model.get_faces():
        corners = xyz[[next(indices) for _ in range(count)]]
        total += 0.5 * np.linalg.norm(np.cross(corners, np.roll(corners, -1, axis=0)).sum(axis=0))
    return total


def test_reports_are_aggregated_per_key():
    (model,) = generate([SQUARE], [FIXED])
    report = model.get_report()
    assert report["Min Height.0_sum"] == 23.0 and report["Min Height.0_n"] == 1.0
    assert report["Parcel Area.0_avg"] == pytest.approx(100.0)
    assert report["Text_max"] == "salut" and report["Bool value_min"] is True


def test_the_attributes_used_leave_hidden_ones_out():
    (model,) = generate([SQUARE], [{"maxBuildingHeight": 35.0}])
    assert model.get_attributes() == {
        "maxBuildingHeight": 35.0, "OBJECTID": 0.0, "minBuildingHeight": 10.0,
        "buildingColor": "#FF00FF", "text": "salut"}  # fmt: skip


def test_array_attributes_are_lists_and_prints_are_kept():
    (model,) = generate([SQUARE], [{"arrayAttrFloat": [0.0, 1.0, 2.0]}], rule=ARRAYS)
    assert model.get_attributes()["arrayAttrFloat"] == [0.0, 1.0, 2.0]
    assert model.get_cga_prints().startswith("arrayAttrFloat = (3)[0,1,2]\n")


def test_an_attribute_the_rule_does_not_have_is_said_to_be_ignored():
    (model,) = generate([SQUARE], [{"noSuchAttr": 1.0}])
    assert any("'noSuchAttr'" in e and "ignored" in e for e in model.get_cga_errors())


@pytest.mark.parametrize(
    ("options", "message"),
    [({"emitGeometry": 1}, "is a boolean"), ({"bogus": True}, "not bogus")],
)
def test_py_encoder_options_are_checked(options, message):
    with pytest.raises(OptionError, match=message):
        generate([SQUARE], [{}], options)


def test_an_encoder_shapegen_does_not_have_is_refused(tmp_path):
    generator = pyprt.ModelGenerator([pyprt.InitialShape(SQUARE)])
    with pytest.raises(OptionError, match="is not supported by shapegen"):
        generator.generate_model([{}], str(EXTRUSION), "com.esri.prt.codecs.USDEncoder",
                                 {"outputPath": str(tmp_path)})  # fmt: skip
    assert list(tmp_path.iterdir()) == []


def test_an_output_folder_that_does_not_exist_is_refused_as_pyprt_refuses_it(tmp_path):
    # PyPRT (src/cpp/client/ModelGenerator.cpp) logs that the outputPath "is not valid or does
    # not exist" and writes nothing; its examples make the folder first
    generator = pyprt.ModelGenerator([pyprt.InitialShape(SQUARE)])
    missing = tmp_path / "out" / "models"
    with pytest.raises(OptionError, match="does not exist; make the folder first"):
        generator.generate_model([FIXED], str(EXTRUSION), "com.esri.prt.codecs.OBJEncoder",
                                 {"outputPath": str(missing)})  # fmt: skip
    assert list(tmp_path.iterdir()) == []


def test_without_an_output_folder_the_files_go_to_pyprts_fallback_folder(tmp_path, monkeypatch):
    import tempfile

    monkeypatch.setattr(tempfile, "tempdir", str(tmp_path))
    generator = pyprt.ModelGenerator([pyprt.InitialShape(SQUARE)])
    with pytest.warns(UserWarning, match="'outputPath' was not given; writing to .*pyprt_fallb"):
        assert generator.generate_model([FIXED], str(EXTRUSION),
                                        "com.esri.prt.codecs.OBJEncoder", {}) == []  # fmt: skip
    assert (tmp_path / "pyprt_fallback_output" / "base_name_0.obj").read_text().count("\nf ") > 0


def test_the_obj_encoder_writes_the_model_and_its_text_files(tmp_path):
    generator = pyprt.ModelGenerator([pyprt.InitialShape(SQUARE)])
    assert generator.generate_model([FIXED], str(EXTRUSION), "com.esri.prt.codecs.OBJEncoder",
                                    {"outputPath": str(tmp_path)}) == []  # fmt: skip
    lines = (tmp_path / "base_name_0.obj").read_text().splitlines()
    (model,) = generate([SQUARE], [FIXED])
    assert sum(line.startswith("v ") for line in lines) == len(model.get_vertices()) // 3
    assert sum(line.startswith("f ") for line in lines) == len(model.get_faces())
    assert "'Min Height.0'\t23.0" in (tmp_path / "CGAReport.txt").read_text()
    assert (tmp_path / "CGAPrint.txt").exists() and (tmp_path / "CGAError.txt").exists()


def test_a_shape_shapegen_cannot_start_on_is_a_model_with_its_error(capsys):
    # a hole named by a face index outside the shape's 2 faces (with holes=[[0, 1]] the
    # triangle is a hole of the square, and the shape is generated: tests/cga/test_cga_holes.py)
    holed = pyprt.InitialShape(SQUARE + [2, 0, 2, 8, 0, 8, 2, 0, 8], list(range(7)), [4, 3],
                               [[0, 5]])  # fmt: skip
    crossing = pyprt.InitialShape([0, 0, 0, 0, 0, -10, 10, 0, -10, 10, 0, 0, -5, 0, -5])
    shapes = [holed, pyprt.InitialShape("model.dwg"), crossing, pyprt.InitialShape(SQUARE)]
    models = pyprt.ModelGenerator(shapes).generate_model([{}], str(EXTRUSION))
    printed = capsys.readouterr().err.splitlines()
    errors = [model.get_cga_errors() for model in models]
    for k, expected in enumerate(["holes", "not supported", "crosses itself"]):
        assert models[k].get_vertices() == [] and expected in errors[k][0], errors[k]
        assert printed[k] == f"shapegen.prt: initial shape {k}: {errors[k][0]}"
    assert len(printed) == 3
    assert models[3].get_vertices() and not errors[3]  # the others are generated


def test_a_tilted_face_is_extruded_along_its_normal_as_pyprt_does():
    # PyPRT 1.12, the same shape and attrs: 8 vertices, 6 faces, from (-4.511, 0, 0) to
    # (10, 25.553, 10) (the square's y rises by 1 m per corner)
    tilted = pyprt.InitialShape([v + (k // 3) if k % 3 == 1 else v for k, v in enumerate(SQUARE)])
    (model,) = pyprt.ModelGenerator([tilted]).generate_model([FIXED], str(EXTRUSION))
    points = np.array(model.get_vertices()).reshape(-1, 3)
    assert (len(points), len(model.get_faces())) == (8, 6)
    assert points.min(axis=0) == pytest.approx([-4.511, 0.0, 0.0], abs=1e-3)
    assert points.max(axis=0) == pytest.approx([10.0, 25.553, 10.0], abs=1e-3)


def test_an_obj_footprint_is_read_with_its_polygon_whole(tmp_path):
    obj = tmp_path / "lot.obj"
    obj.write_text("v 0 0 0\nv 0 0 10\nv 10 0 10\nv 15 0 5\nv 10 0 0\nf 1 2 3 4 5\n")
    (model,) = pyprt.ModelGenerator([pyprt.InitialShape(str(obj))]).generate_model(
        [FIXED], str(EXTRUSION))  # fmt: skip
    assert model.get_report()["Parcel Area.0_sum"] == pytest.approx(125.0)


@pytest.mark.parametrize("suffix", [".obj", ".glb"])
def test_an_initial_shape_file_is_read_within_the_size_limit(tmp_path, suffix):
    from shapegen.limits import work_limits

    lot = tmp_path / f"lot{suffix}"
    if suffix == ".obj":
        lot.write_text("v 0 0 0\nv 0 0 10\nv 10 0 10\nv 10 0 0\nf 1 2 3 4\n")
    else:
        import trimesh

        square = trimesh.Trimesh([[0, 0, 0], [0, 0, 10], [10, 0, 10], [10, 0, 0]],
                                 [[0, 1, 2], [0, 2, 3]], process=False)  # fmt: skip
        lot.write_bytes(square.export(file_type="glb"))
    shape = pyprt.InitialShape(str(lot))
    (model,) = pyprt.ModelGenerator([shape]).generate_model([FIXED], str(EXTRUSION))
    assert model.get_report()["Parcel Area.0_sum"] == pytest.approx(100.0)
    with work_limits(max_file_bytes=lot.stat().st_size - 1):
        (refused,) = pyprt.ModelGenerator([shape]).generate_model([FIXED], str(EXTRUSION))
    assert refused.get_vertices() == []
    assert "more than" in refused.get_cga_errors()[0], refused.get_cga_errors()


def test_rule_package_attributes_carry_their_group():
    info = pyprt.get_rpk_attributes_info(str(EXTRUSION))
    assert "parcelArea" not in info  # @Hidden
    group = ["@Group", [pyprt.NO_KEY, "My Group"]]
    assert info["buildingColor"] == {"type": "string", "annotations": [["@Color"], group]}


def test_array_attrs_are_listed_with_their_items_type():
    # PyPRT 1.12's get_rpk_attributes_info of the same rules (Esri/pyprt's arrayAttrs.rpk)
    info = pyprt.get_rpk_attributes_info(str(ARRAYS))
    assert {name: entry["type"] for name, entry in info.items()} == {
        "arrayAttrFloat": "float[]",
        "arrayAttrBool": "bool[]",
        "arrayAttrString": "string[]",
    }


def test_the_statics_through_the_same_api():
    (model,) = generate([SQUARE], [FIXED])
    analysis = model.get_statics()
    assert analysis["stands"] is True and analysis["measure"] == pytest.approx(0.0, abs=1e-9)
    with pytest.raises(OptionError):
        model.get_statics(no_such_option=1)


def test_the_deprecated_life_cycle_calls_do_nothing():
    pyprt.initialize_prt()
    assert pyprt.is_prt_initialized() is True
    pyprt.shutdown_prt()
    assert len(pyprt.get_api_version()) == 3 and not math.isnan(pyprt.get_api_version()[0])

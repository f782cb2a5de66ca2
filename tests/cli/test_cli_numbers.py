"""The boundary for numbers, through the command line: a rule whose operations overflow (inf,
NaN, a size past ``max_coordinate``) or whose meshes ask for unbounded work ends in one line.

In a ``.cga`` file, where CityEngine's runtime carries on, it is a warning in the printout and
the report (a CGA error: the operation is skipped) and a model with finite coordinates; in a
``.grammar`` file, and for a mesh past a work limit in either, exit status 2 and no output file
at all.
"""

from __future__ import annotations

import json
import math
import sys
from pathlib import Path

import numpy as np
import pytest
import trimesh

from shapegen.cli import main
from shapegen.limits import DEFAULT_LIMITS

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "fuzz"))
from json_numbers import json_numbers  # noqa: E402

# (rule body after "Lot -->", words of the warning)
CGA_WARNINGS = [
    ("extrude(1e308) extrude(-1e308)", "extrude(): the shape it makes reaches 1e+308 m"),
    ("primitiveDisk(64) extrude(1e18)", "extrude(): the shape it makes reaches 1e+18 m"),
    ("extrude(10) s(1e308, 1, 1)", "s(): the shape it makes reaches 1e+308 m"),
    ("extrude(10) s('1e308, 1, 1)", "scope sizes must be finite numbers >= 0, got [inf, 1.0"),
    ("extrude(10) s('1e300, 1, 1) s('1e300, 1, 1)", "s(): the shape it makes reaches"),
    ("extrude(10) t(1e308, 0, 0) t(1e308, 0, 0)", "t(): the shape it makes reaches 1e+308 m"),
    ("extrude(10) t('1e308, 0, 0)", "t(): the shape it makes has a coordinate that is infinite"),
    ("roofHip(89.9999999999)", "roofHip(): the shape it makes reaches"),
    ("roofGable(89.99999999999)", "roofGable(): the shape it makes reaches"),
    ("roofPyramid(89.9999999999)", "roofPyramid(): the shape it makes reaches"),
    ("offset(1e308)", "offset(): the shape it makes reaches 1e+308 m"),
    ("primitiveCylinder(16, 1e308, 1e308)", "primitiveCylinder(): the shape it makes has"),
    ("primitiveSphere(16, 16, 1e308)", "primitiveSphere(): the shape it makes has"),
    ("primitiveCube(1e308, 1e308, 1e308)", "primitiveCube(): the shape it makes reaches"),
    ("extrude(10) comp(f) { side : extrude(1e308) A }", "extrude(): the shape it makes"),
    ('i("builtin:cube") s(1e308, 1e308, 1e308)', "s(): the shape it makes reaches 1e+308 m"),
    ("extrude(10) center(xyz) s(1e200, 1e200, 1e200)", "s(): the shape it makes reaches"),
    ("extrude(0/0)", "extrude height is nan: replaced by 0"),
    # reproducers of tests/fuzz/test_fuzz_numbers.py
    ("taper(1e308)", "taper(): a number it works out overflows"),
    # work bounded by the size of what the rule makes: a CGA error, as CityEngine's runtime
    ("primitiveDisk(4096) roofHip(30)", "(limit max_skeleton_corners = 1000;"),
    ("primitiveDisk(2000) offset(-1)", "(limit max_skeleton_corners = 1000;"),
    ("primitiveCylinder(1e9)", "sides is a whole number 3..4096"),
    # seed 3 of the fuzz: a GEOSException of the mitred corners of a roof face's offset
    ("trim() roofPyramid(10) offset(1e308)", "moves the polygon's corners past any finite"),
    # seed 2 of the fuzz: a cleanup that leaves no geometry, then a turn of the scope
    (
        "offset(1e-320) roofPyramid(-1e-320) primitiveSphere(0, 3) B\n"
        "B --> primitiveCylinder(300, (-1e308 * 10), 2) cleanupGeometry(all, -1e308) "
        "t(4096, -1e9, 4096) rotateScope(0, -90, 0)",
        "the shape has no geometry left to fit a scope to",
    ),
]

# (file name, rule text, words of the error)
ERRORS = [
    ("a.grammar", "Lot --> extrude(1e308) extrude(-1e308)", "limit max_coordinate"),
    ("a.grammar", "Lot --> extrude(10) t('1e308, 0, 0)", "has a coordinate that is infinite"),
    ("a.grammar", "Lot --> extrude(10) s('1e308, 1, 1)", "scope sizes must be finite numbers"),
    ("a.cga", "Lot --> primitiveSphere(4096, 4096)", "limit max_mesh_faces"),
    ("a.cga", "Lot --> extrude(5) primitiveSphere(100, 100)", "limit max_face_vertex_pairs"),
    ("a.cga", "Lot --> extrude(10) split(x) { ~1e-320 : A }*", "(max_shapes)"),
    ("a.cga", "Lot --> extrude(10) split(x) { 1e-320 : A }*", "(max_shapes)"),
]


@pytest.mark.parametrize(("body", "warning"), CGA_WARNINGS)
def test_a_cga_overflow_is_a_warning_and_a_finite_model(tmp_path, capsys, body, warning):
    rule = tmp_path / "lot.cga"
    rule.write_text(f"Lot --> {body}\n")
    model, scene, report = tmp_path / "x.json", tmp_path / "x.glb", tmp_path / "r.json"
    argv = ["build", str(rule), "-o", str(model), "--report", str(report), "--analyze"]
    assert main(argv) == 0
    assert main(["build", str(rule), "-o", str(scene), "-q"]) == 0
    printed = capsys.readouterr()
    assert warning in printed.out
    assert "Traceback" not in printed.err
    assert not [line for line in printed.err.splitlines() if "warning" in line]  # numpy's
    assert any(warning in w for w in json.loads(report.read_text())["warnings"])
    blocks = json.loads(model.read_text())["blocks"]
    coordinates = list(json_numbers([block["vertices"] for block in blocks]))
    bound = DEFAULT_LIMITS.max_coordinate
    assert all(math.isfinite(x) and abs(x) <= bound for x in coordinates)
    glb = trimesh.load(scene, force="scene")
    for geometry in glb.geometry.values():
        assert np.isfinite(geometry.vertices).all()


@pytest.mark.parametrize(("name", "text", "error"), ERRORS)
def test_an_overflow_or_unbounded_mesh_is_one_error_line(tmp_path, capsys, name, text, error):
    rule = tmp_path / name
    rule.write_text(text + "\n")
    outputs = [tmp_path / "x.json", tmp_path / "r.json", tmp_path / "p.png"]
    argv = ["build", str(rule), "-o", str(outputs[0]), "--report", str(outputs[1])]
    assert main([*argv, "--picture", str(outputs[2]), "--analyze"]) == 2
    printed = capsys.readouterr()
    first = printed.err.splitlines()[0]
    assert first.startswith("shapegen: error:") and error in first
    assert "Traceback" not in printed.err
    assert sorted(p.name for p in tmp_path.iterdir()) == [name]  # nothing written, no temp file


def test_the_grammar_error_names_the_operation_and_its_place(tmp_path, capsys):
    rule = tmp_path / "a.grammar"
    rule.write_text("Lot --> extrude(1e308) extrude(-1e308)\n")
    assert main(["build", str(rule)]) == 2
    first = capsys.readouterr().err.splitlines()[0]
    assert f"{rule}:1:9: extrude(): the shape it makes reaches 1e+308 m, beyond 1e+09 m" in first


def test_a_raised_coordinate_limit_lets_a_large_model_through(tmp_path):
    import shapegen
    from shapegen.limits import work_limits

    grammar = shapegen.parse_grammar("@StartRule @Lot(10, 10)\nLot --> extrude(2e9) A")
    with pytest.raises(shapegen.GrammarError, match="max_coordinate"):
        grammar.build()
    with work_limits(max_coordinate=10**10):
        assert grammar.build().blocks[0].vertices[:, 1].max() == pytest.approx(2e9)


# Reproducers of tests/fuzz/test_fuzz_numbers.py (seed 1): work that grew with what the rule
# made, not with the shapes it counted, under lowered limits so that they stay quick.
GROWING = [
    (
        # extrude() of a mass extrudes each of its faces: the faces double at every level
        "Lot --> split(x) { (1e308 * 10) : A | ~1e-320 : B } rotateScope(0, 1e300, 0)\n"
        "A --> s('(1e308 * 10), '1, '-1e-320)\n"
        "B --> extrude((1e308 * 10)) split(z) { '1e18 : B }* rotateScope(0, 5e-324, 0)\n",
        {"max_mesh_faces": 3000},
        "(limit max_mesh_faces = 3000;",
    ),
    (
        # 120 bisections a piece, all before the first child is counted
        "Lot --> offset(89.9999999999, inside) splitArea(x) { 1 : A | ~-90 : B }*\n",
        {"max_seconds": 0.3},
        "the build (the derivation) ran for more than 0.3 s",
    ),
]


@pytest.mark.parametrize(("text", "limits", "error"), GROWING)
def test_work_that_grows_with_the_model_stops_at_its_limit(tmp_path, capsys, text, limits, error):
    from shapegen.limits import work_limits

    rule = tmp_path / "fuzz.cga"
    rule.write_text(text)
    with work_limits(**limits):
        assert main(["build", str(rule), "-o", str(tmp_path / "x.json")]) == 2
    first = capsys.readouterr().err.splitlines()[0]
    assert first.startswith("shapegen: error:") and error in first
    assert [p.name for p in tmp_path.iterdir()] == ["fuzz.cga"]


def test_max_seconds_bounds_the_whole_build_and_names_its_option(tmp_path, capsys):
    # a wall of 1 600 bricks derives in well under a second here and judges in several: one
    # clock over deriving, judging and writing, stopped where it ran out
    rule = tmp_path / "wall.cga"
    rule.write_text("Lot --> extrude(10) split(y) { 0.25 : Row }*\nRow --> split(x) { 0.5 : B }*\n")
    out = tmp_path / "w.json"
    args = ["build", str(rule), "--lot", "20,1", "--analyze", "-o", str(out)]
    assert main([*args, "--max-seconds", "0.01"]) == 2
    first = capsys.readouterr().err.splitlines()[0]  # the rule's line below it when deriving
    assert first.startswith("shapegen: error:") and "the build (" in first
    assert (
        "ran for more than 0.01 s (limit max_seconds = 0.01; raise it with --max-seconds S)"
        in first
    )
    assert not out.exists()
    assert main([*args, "--max-seconds", "600", "-q"]) == 0 and out.exists()
    for bad in ("0", "-1", "nan", "inf", "soon"):
        assert main([*args, "--max-seconds", bad]) == 2
        assert "argument --max-seconds:" in capsys.readouterr().err


def test_a_face_welded_into_one_point_is_a_geometry_error():
    # seed 2 of the fuzz: innerRectangle of a face 1e-320 m wide made a mesh face of 1 corner
    from shapegen.engine.operations.cga.polygons import flat_shape
    from shapegen.engine.shapes.shape import FACE, Shape, lot_scope
    from shapegen.errors import GeometryError

    parent = Shape(lot_scope(1.0, 1.0), FACE, 1)
    with pytest.raises(GeometryError, match="a face it makes has no extent"):
        flat_shape(parent, [np.full((3, 3), 0.5)])


def test_a_block_too_large_to_check_names_the_limit():
    # seed 2 of the fuzz: a 4096-sided prism's face-vertex pairs filled 4.8 GB of packed arrays
    from shapegen.engine.operations.cga.assets import primitive_mesh
    from shapegen.errors import GeometryError
    from shapegen.limits import work_limits
    from shapegen.model.block import Block
    from shapegen.model.validation import validate_blocks

    prism = primitive_mesh("cylinder", 1200)  # 1202 faces x 2400 vertices: checked alone
    block = Block(prism.vertices * 10, prism.faces, id="b0")
    validate_blocks([block])  # sound
    with work_limits(max_face_vertex_pairs=2_000_000), pytest.raises(GeometryError) as caught:
        validate_blocks([block])
    assert "block 'b0': 1202 faces and 2400 vertices" in str(caught.value)
    assert "(limit max_face_vertex_pairs = 2000000;" in str(caught.value)

"""CGA errors of the runtime: in a .cga file an operation's bad argument or degenerate geometry is
a warning at its place, the operation is skipped, the shape carries on and the count is
reported; a .grammar file stops there, as before.

What CityEngine's runtime does was checked with PyPRT on the corpus packages with attrs that
reach these cases (envelope2002's shapeL with a negative lot coverage, simpleRuleDataset's
setback with a negative front setback): negative widths and distances are taken as 0 and no
CGA error is recorded; the geometry counts then match PyPRT's (24 vertices, 6 faces; 28, 7).
"""

from __future__ import annotations

import json

import numpy as np
import pytest

from shapegen import load_grammar
from shapegen.cli import main
from shapegen.errors import GrammarError, OperationError
from shapegen.geometry.mesh import Mesh

LOT = (12.0, 8.0)

COVERS = {
    "test_bad_argument_or_degenerate_geometry_is_a_located_warning": ("op:envelope",),
}

# (rule text, the message of its CGA error)
CASES = [
    ("Lot --> envelope(normal, 0, 2, 45, 2, 45) X.", "envelope's maximum height must be > 0"),
    ("Lot --> roofGable(30, -10) X.", "the roof's negative overhang is larger than the face"),
    ("Lot --> roofHip(30, -10) X.", "the roof's negative overhang is larger than the face"),
    ("Lot --> roofHip(30) s('1, '1, 0) comp(f) { all : extrude(1) X. }",
     "extrude() of a face with no area"),
    ("Lot --> extrude(3) reduceGeometry(2) X.", "the tolerance is 0..1, got 2"),
]  # fmt: skip


def _area(model) -> float:
    return sum(Mesh(s.vertices, s.faces).area() for s in model.surfaces)


def _write(tmp_path, text: str, suffix: str = ".cga"):
    path = tmp_path / f"rule{suffix}"
    path.write_text(text + "\n")
    return path


@pytest.mark.parametrize(("text", "message"), CASES)
def test_bad_argument_or_degenerate_geometry_is_a_located_warning(tmp_path, text, message):
    model = load_grammar(_write(tmp_path, text)).build(lot=LOT)
    errors = [w for w in model.metadata["warnings"] if message in w]
    assert errors, model.metadata["warnings"]
    assert errors[0].startswith(f"{tmp_path / 'rule.cga'}:1:")  # file:line:column
    assert "the operation is skipped" in errors[0]
    assert model.metadata["cga_errors"] >= 1
    assert model.blocks or model.surfaces  # the shape carried on to a leaf


@pytest.mark.parametrize(("text", "message"), CASES)
def test_a_grammar_file_stays_strict(tmp_path, text, message):
    with pytest.raises(GrammarError, match=message.replace("(", r"\(").replace(")", r"\)")):
        load_grammar(_write(tmp_path, text, ".grammar")).build(lot=LOT)


def test_a_setback_to_more_than_the_face_leaves_the_face_in_cga_and_stops_a_grammar(tmp_path):
    # PyPRT (tests/data/prt_setback_holes.json, 12x8): setbackToArea(500) of a 96 m^2 lot sets
    # nothing back and records no error; the remainder is the whole lot
    text = 'Lot --> setbackToArea(500) { front : X. | remainder : report("r", geometry.area) Y. }'
    model = load_grammar(_write(tmp_path, text)).build(lot=LOT)
    assert model.metadata["cga_errors"] == 0 and model.metadata["reports"]["r"] == 96.0
    with pytest.raises(GrammarError, match="less than 500"):
        load_grammar(_write(tmp_path, text, ".grammar")).build(lot=LOT)


def test_the_shape_carries_on_unchanged_to_the_next_operation(tmp_path):
    # the roof is skipped: the lot is extruded by the next operation as if it were not there
    model = load_grammar(_write(tmp_path, "Lot --> roofHip(30, -10) extrude(2) X.")).build(lot=LOT)
    assert model.metadata["cga_errors"] == 1
    assert model.volume == pytest.approx(12 * 8 * 2)


def test_each_shape_counts_its_error_and_the_warning_is_listed_once(tmp_path):
    text = "Lot --> split(x) { ~3 : roofHip(30, -10) X. }*"
    model = load_grammar(_write(tmp_path, text)).build(lot=LOT)
    assert model.metadata["cga_errors"] == 4  # four pieces of 3 m
    assert sum("negative overhang" in w for w in model.metadata["warnings"]) == 1
    assert len(model.surfaces) == 4


def test_the_limits_still_stop_a_cga_derivation(tmp_path):
    path = _write(tmp_path, "Lot --> split(x) { 0.001 : roofHip(30, -10) X. }*")
    with pytest.raises(GrammarError, match="max_shapes") as raised:
        load_grammar(path).build(lot=LOT, max_shapes=100)
    assert not isinstance(raised.value, OperationError)


def test_negative_setback_and_shape_widths_are_zero_as_in_cityengine(tmp_path):
    text = "Lot --> setback(-2) { front : NIL | remainder : X. }"
    model = load_grammar(_write(tmp_path, text)).build(lot=LOT)
    assert model.metadata["cga_errors"] == 0
    assert _area(model) == pytest.approx(96.0)
    text = "Lot --> shapeL(-1, 3) { shape : A. | remainder : B. }"
    model = load_grammar(_write(tmp_path, text)).build(lot=LOT)
    assert any("a negative width is taken as 0" in w for w in model.metadata["warnings"])
    assert _area(model) == pytest.approx(96.0)


def test_the_printout_and_the_report_count_the_errors(tmp_path, capsys):
    path = _write(tmp_path, "Lot --> split(x) { ~6 : roofHip(30, -10) X. }*")
    report = tmp_path / "report.json"
    assert main(["build", str(path), "--lot", "12x8", "--report", str(report)]) == 0
    out = capsys.readouterr().out
    assert "CGA errors: 2 operations skipped" in out
    assert f"{path}:1:" in out
    data = json.loads(report.read_text())
    assert data["cga_errors"] == 2
    assert any("negative overhang" in w for w in data["warnings"])


def test_an_edge_is_extruded_along_its_normal_into_a_face(tmp_path):
    # op_extrude's edge examples: comp(e) edges along the mean of their faces' normals (up,
    # a wall on each edge of the lot); comp(fe) edges out of the face, in its plane
    text = "Start --> comp(e) { all = Edges }\nEdges --> extrude(10)"
    model = load_grammar(_write(tmp_path, text)).build(lot=LOT)
    assert len(model.surfaces) == 4 and _area(model) == pytest.approx(2 * (12 + 8) * 10)
    low, high = _bounds(model)
    assert low == pytest.approx([0, 0, 0]) and high == pytest.approx([12, 10, 8])
    text = "Start --> comp(fe) { all = Edges }\nEdges --> extrude(10)"
    model = load_grammar(_write(tmp_path, text)).build(lot=LOT)
    low, high = _bounds(model)
    assert low == pytest.approx([-10, 0, -10]) and high == pytest.approx([22, 0, 18])


def _bounds(model):
    points = np.vstack([s.vertices for s in model.surfaces])
    return points.min(axis=0).tolist(), points.max(axis=0).tolist()


@pytest.mark.parametrize(
    "operation", ["roofHip(30)", "offset(-1)", "taper(2)", "scatter(surface, 3, uniform) { A. }",
                  "alignScopeToGeometry(yUp, 0)", "setback(1) { front : A. }"],
)  # fmt: skip
def test_an_operation_on_faces_of_an_edge_is_a_cga_error(tmp_path, operation):
    text = f"Lot --> comp(e) {{ 0 : X }}\nX --> {operation} E."
    model = load_grammar(_write(tmp_path, text)).build(lot=LOT)
    assert model.metadata["cga_errors"] == 1
    assert "the operation is skipped" in model.metadata["warnings"][0]


def test_face_operations_on_a_mass_work_on_each_face(tmp_path):
    # op_envelope: "above each face of the current shape's geometry"; op_setback: "also applies
    # to shapes with more than one face"; op_splitArea "does not apply to 3D geometry"
    text = "Lot --> extrude(4) envelope(normal, 10, 2, 45, 2, 45) X."
    model = load_grammar(_write(tmp_path, text)).build(lot=LOT)
    assert model.metadata["cga_errors"] == 0
    (solid,) = [Mesh(s.vertices, s.faces) for s in model.surfaces] or [
        Mesh(b.vertices, b.faces) for b in model.blocks
    ]
    assert solid.is_closed and solid.signed_volume() > 12 * 8 * 4  # six envelopes over a box
    text = "Lot --> extrude(4) setback(1) { all : NIL | remainder : R. }"
    model = load_grammar(_write(tmp_path, text)).build(lot=LOT)
    assert len(model.surfaces) == 6  # one remainder per face
    assert _area(model) < 2 * (12 * 8 + 12 * 4 + 8 * 4)
    text = "Lot --> extrude(4) splitArea(x) { 10 : A. }*"
    model = load_grammar(_write(tmp_path, text)).build(lot=LOT)
    assert model.metadata["cga_errors"] == 1 and model.volume == pytest.approx(384.0)

"""Operations real rule files use that change no geometry shapegen derives, accepted with a
warning (the texture and tag operations, the deprecated names of the changelog), and the
insert of an empty asset name, envelope's forms without a direction and rectify."""

from __future__ import annotations

import math

import numpy as np
import pytest

from shapegen import parse_grammar
from shapegen.errors import GrammarError

#: The reference entries each test shows (tools/cga_coverage.py reads this table).
COVERS = {
    "test_offset_uv_is_translate_uv_by_its_old_name": ("op:offsetUV", "op:translateUV"),
    "test_normalize_uv_takes_its_modes": ("op:normalizeUV",),
    "test_tags_change_no_geometry": ("op:setTagsFromEdgeAttrs",),
    "test_material_color_a_is_the_opacity": ("attr:material.color.a", "attr:material.opacity"),
    "test_envelope_without_a_direction": ("op:envelope",),
    "test_rectify_squares_a_nearly_rectangular_lot": ("op:rectify",),
}


def _model(text: str, lot=(12.0, 8.0)):
    return parse_grammar("@StartRule\n" + text, "accepted.cga").build(lot=lot)


def _geometry(model) -> list:
    return [np.round(b.vertices, 9).tolist() for b in model.blocks] + [
        np.round(s.vertices, 9).tolist() for s in model.surfaces
    ]


def test_offset_uv_is_translate_uv_by_its_old_name():
    # cga_changelog 2009.3: "translateUV operation (was offsetUV)"
    old = _model("Lot --> extrude(3) offsetUV(0, 0.5, 0.25) X.")
    new = _model("Lot --> extrude(3) translateUV(0, 0.5, 0.25) X.")
    assert _geometry(old) == _geometry(new)
    assert old.blocks[0].appearance.uv == new.blocks[0].appearance.uv
    assert old.blocks[0].appearance.uv == (("translateUV", (0, 0.5, 0.25)),)
    (warning,) = old.metadata["warnings"]
    assert warning.startswith("accepted.cga:2:20: offsetUV() is deprecated")


@pytest.mark.parametrize("mode", ["uv", "uvUniform", "u", "v"])
@pytest.mark.parametrize("kind", ["separatePerFace", "collectiveAllFaces"])
def test_normalize_uv_takes_its_modes(mode, kind):
    model = _model(f"Lot --> extrude(3) normalizeUV(0, {mode}, {kind}) X.")
    assert model.blocks[0].appearance.uv == (("normalizeUV", (0, mode, kind)),)
    assert _geometry(model) == _geometry(_model("Lot --> extrude(3) X."))


@pytest.mark.parametrize(
    "operation",
    [
        'tag("roof")',
        'tag("roof.edge", edges)',
        "deleteTags()",
        'deleteTags("bool.*", faces)',
        "setTagsFromEdgeAttrs()",
    ],
)
def test_tags_change_no_geometry(operation):
    """Tags label components; the geometry stays as it is. setTagsFromEdgeAttrs() reads edge
    attributes, which shapegen's lots do not have: a warning, and nothing is tagged."""
    model = _model(f"Lot --> extrude(3) {operation} X.")
    assert _geometry(model) == _geometry(_model("Lot --> extrude(3) X."))
    warnings = model.metadata["warnings"]
    if operation.startswith("setTagsFromEdgeAttrs"):
        (warning,) = warnings
        assert "no edge attributes" in warning and warning.startswith("accepted.cga:2:20: ")
    else:
        assert warnings == []


@pytest.mark.parametrize(
    ("operation", "message"),
    [('tag("a", all)', "components are one of auto, faces"), ("tag()", "takes 1 to 2")],
)
def test_bad_tag_calls_are_refused_when_loaded(operation, message):
    with pytest.raises(GrammarError, match=message):
        _model(f"Lot --> extrude(3) {operation} X.")


def test_material_color_a_is_the_opacity():
    # cga_changelog 2011.1: "deprecated material.color.a (replaced by material.opacity)"
    model = _model(
        'Lot --> extrude(3) set(material.color.a, 0.25) report("a", material.color.a) '
        'report("opacity", material.opacity) X.'
    )
    assert model.metadata["reports"] == {"a": 0.25, "opacity": 0.25}
    assert model.blocks[0].appearance.opacity == 0.25
    assert sum("material.color.a is deprecated" in w for w in model.metadata["warnings"]) == 2


@pytest.mark.parametrize("name", ['""', '"builin:cube"'])
def test_an_empty_asset_name_inserts_a_box_with_a_warning(name):
    # an asset that cannot be found: a box fills the scope, as for a missing file
    model = _model(f"Lot --> extrude(3) s('0.5, '1, '1) i({name}) X.")
    assert np.allclose(model.blocks[0].vertices.min(axis=0), 0)
    assert np.allclose(model.blocks[0].vertices.max(axis=0), [6, 3, 8])
    (warning,) = model.metadata["warnings"]
    assert "a box fills" in warning


@pytest.mark.parametrize(
    ("deprecated", "current"),
    [("8, 3, 45", "normal, 8, 3, 45"), ("8, 3, 45, 3, 60", "normal, 8, 3, 45, 3, 60")],
)
def test_envelope_without_a_direction(deprecated, current):
    # cga_changelog: "envelope operation: deprecated signatures without direction parameter"
    old, new = (
        _model(f"Lot --> envelope({deprecated}) X."),
        _model(f"Lot --> envelope({current}) X."),
    )
    assert _geometry(old) == _geometry(new)
    (warning,) = old.metadata["warnings"]
    assert "without a direction is deprecated" in warning


def _angles(points: np.ndarray) -> list[float]:
    out = []
    for k in range(len(points)):
        a, b = points[k - 1] - points[k], points[(k + 1) % len(points)] - points[k]
        out.append(math.degrees(math.acos(a @ b / np.linalg.norm(a) / np.linalg.norm(b))))
    return out


@pytest.mark.parametrize(("angle", "square"), [(15, True), (2, False)])
def test_rectify_squares_a_nearly_rectangular_lot(angle, square):
    # op_rectify: edges within `angle` of a scope axis are made parallel to it; the second and
    # last edges are 3.1 and 5.7 degrees off a right angle to the first (the scope's x)
    lot = [(0, 0), (10, 0), (10.3, -5.5), (-0.5, -5)]
    model = _model("Lot --> rectify(" + str(angle) + ") X.", lot=lot)
    (surface,) = model.surfaces
    angles = _angles(surface.vertices)
    assert np.allclose(angles, 90) is square
    assert any("rectify()" in w for w in model.metadata["warnings"])

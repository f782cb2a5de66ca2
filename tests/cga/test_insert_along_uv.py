"""insertAlongUV (op_insertAlongUV), approximated: shapegen keeps no texture coordinates, so
the uv space is taken as 0..1 over the face's scope (over each triangle and quad of a mass); the
asset's x-span runs along u, its z-span along -v and its y-span is the height given. Every use
is a warning."""

from __future__ import annotations

import numpy as np
import pytest

from shapegen import load_grammar
from shapegen.errors import GrammarError

COVERS = {"test_an_asset_is_laid_over_the_face_and_the_warning_says_how": ("op:insertAlongUV",)}

LOT = (10.0, 3.0)
# a wedge 1 m long (x), 1 m high at z = 0 and 0 m at z = 2: which way -v runs shows
WEDGE = "v 0 0 0\nv 1 0 0\nv 1 0 2\nv 0 0 2\nv 0 1 0\nv 1 1 0\nf 1 2 3 4\nf 5 6 2 1\n"
WEDGE += "f 4 3 6 5\nf 1 4 5\nf 2 6 3\n"


def _build(tmp_path, body: str):
    (tmp_path / "assets").mkdir(exist_ok=True)
    (tmp_path / "assets" / "wedge.obj").write_text(WEDGE)
    path = tmp_path / "street.cga"
    path.write_text(f'version "2023.0"\n@StartRule\nStreet --> {body}\n')
    return load_grammar(path).build(lot=LOT)


def test_an_asset_is_laid_over_the_face_and_the_warning_says_how(tmp_path):
    model = _build(tmp_path, 'insertAlongUV(0, "assets/wedge.obj", 2) Barrier.')
    (block,) = model.blocks
    points = block.vertices
    # stretched over the 10 x 3 lot, 2 m high: half the box
    assert np.allclose(points.min(axis=0), 0) and np.allclose(points.max(axis=0), (10, 2, 3))
    assert block.volume == pytest.approx(10 * 2 * 3 / 2)
    # the asset's z runs along -v: its high end (z = 0) lies at the far side of the face
    assert np.allclose(points[np.isclose(points[:, 1], 2)][:, 2], 3)
    (warning,) = model.metadata["warnings"]
    assert "insertAlongUV(): shapegen keeps no texture coordinates" in warning


def test_keep_position_measures_the_height_from_the_asset_origin(tmp_path):
    body = 'insertAlongUV(0, "assets/wedge.obj", 2, scope.y, keepPosition) B.'
    (block,) = _build(tmp_path, body).blocks
    assert block.vertices[:, 1].max() == pytest.approx(2.0)


def test_an_asset_not_found_gives_a_box_and_a_warning(tmp_path):
    model = _build(tmp_path, 'insertAlongUV(0, "assets/gone.obj", 1.5) B.')
    assert [b.volume for b in model.blocks] == pytest.approx([10 * 1.5 * 3])
    assert any("'assets/gone.obj' not found" in w for w in model.metadata["warnings"])


@pytest.mark.parametrize(
    ("call", "message"),
    [
        ('insertAlongUV(0, "a.obj")', "takes"),
        ('insertAlongUV(0, "a.obj", 1, world.up, alignPosition)', "heightDirection is one of"),
        ('insertAlongUV(0, "a.obj", 1, scope.y, top)', "heightAlignment is one of"),
    ],
)
def test_malformed_calls_are_refused_when_the_file_loads(tmp_path, call, message):
    path = tmp_path / "r.cga"
    path.write_text(f"@StartRule\nLot --> {call}\n")
    with pytest.raises(GrammarError, match=message):
        load_grammar(path)


def test_on_a_mass_the_asset_is_laid_on_each_face_along_the_vertex_normals(tmp_path):
    # a box asset (not found) 0.5 m high on each face of a 4 m cube, raised along the vertex
    # normals: at a corner of the cube the three faces' mean normal is (+-1, +-1, +-1) / sqrt(3)
    body = (
        'primitiveCube(4, 4, 4) insertAlongUV(0, "gone.obj", 0.5, vertex.normal, alignPosition) B.'
    )
    model = _build(tmp_path, body)
    points = np.vstack([b.vertices for b in model.blocks] + [s.vertices for s in model.surfaces])
    reach = 0.5 / np.sqrt(3)
    low, high = points.min(axis=0), points.max(axis=0)
    assert np.allclose(high - low, 4 + 2 * reach)
    assert any("laid once on each triangle and quad" in w for w in model.metadata["warnings"])


def test_on_a_mass_faces_of_more_than_four_corners_get_nothing(tmp_path):
    # a cylinder of 8 sides: 8 side quads get a box each, the two octagonal caps none
    model = _build(tmp_path, 'primitiveCylinder(8, 1, 2) insertAlongUV(0, "gone.obj", 0.2) B.')
    faces = sum(len(b.faces) for b in model.blocks) + sum(len(s.faces) for s in model.surfaces)
    assert faces == 8 * 6

"""Assets read as CityEngine's runtime reads them: counts measured with PyPRT 1.12
(``prt_asset_counts.json`` says how) on every OBJ asset of the corpus packages."""

import json
from collections import Counter
from pathlib import Path

import numpy as np
import pytest

from shapegen.engine.project.asset_files import load_asset
from shapegen.geometry.asset_cleanup import cleaned_polygons
from shapegen.readers.archives import unpack_7z

HERE = Path(__file__).parent
MEASURED = json.loads((HERE / "prt_asset_counts.json").read_text())
CORPUS = HERE.parent / "data" / "cga-corpus"
#: the packages themselves (glass_door.obj is only there): shared/ beside the checkout
PACKAGES = next(
    (p / "shared" / "cga-corpus" / "packages" for p in Path(__file__).resolve().parents
     if (p / "shared" / "cga-corpus" / "packages").is_dir()),
    Path("shared/cga-corpus/packages"),
)  # fmt: skip


def _asset(tmp_path: Path, name: str) -> Path:
    path = CORPUS / name
    if path.is_file():
        return path
    package, inside = name.split("/", 1)
    archive = PACKAGES / f"Esri+pyprt__{package}.rpk"
    if not archive.is_file():
        pytest.skip(f"{name} is only in the package {archive.name}, not found")
    unpack_7z(archive, tmp_path)
    return tmp_path / inside


@pytest.mark.parametrize("name", sorted(MEASURED["assets"]))
def test_every_corpus_asset_reads_as_cityengines_runtime_reads_it(tmp_path, name):
    expected = MEASURED["assets"][name]
    mesh = load_asset(_asset(tmp_path, name))
    sizes = Counter(len(face) for face in mesh.faces)
    assert (mesh.n_vertices, mesh.n_faces) == (expected["vertices"], expected["faces"])
    assert {str(k): v for k, v in sorted(sizes.items())} == expected["face_sizes"]


def test_a_short_edge_goes_into_the_vertex_more_faces_use():
    # vertex 1 is used by both squares, vertex 2 (0.5 mm from it) by the first only
    points = np.array([[0, 0, 0], [1, 0, 0], [1, 0.0005, 0], [1, 1, 0], [0, 1, 0], [2, 0, 0],
                       [2, 1, 0]], dtype=float)  # fmt: skip
    vertices, faces = cleaned_polygons(points, [[0, 2, 1, 3, 4], [1, 5, 6, 3]])
    assert faces == [[0, 1, 2, 3], [1, 4, 5, 2]]
    assert np.array_equal(vertices[1], [1, 0, 0])
    assert len(vertices) == 6  # vertex 2 is no longer used


def test_a_sliver_face_is_merged_into_the_face_across_its_spanning_edge():
    # two squares meeting along x = 1, and a face of no area along that seam through (1, 0.5),
    # run as the first square's neighbour: its corner joins the first square's edge only
    points = np.array([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0], [2, 0, 0], [2, 1, 0],
                       [1, 0.5, 0]], dtype=float)  # fmt: skip
    vertices, faces = cleaned_polygons(points, [[0, 1, 2, 3], [1, 6, 2], [1, 4, 5, 2]])
    assert len(faces) == 2 and len(vertices) == 7
    first = [tuple(vertices[i]) for i in faces[0]]
    assert first == [(0, 0, 0), (1, 0, 0), (1, 0.5, 0), (1, 1, 0), (0, 1, 0)]
    assert len(faces[1]) == 4


def test_a_sliver_meeting_no_face_goes():
    points = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [5, 0, 0], [6, 0, 0], [7, 0, 0.0]])
    vertices, faces = cleaned_polygons(points, [[0, 1, 2], [3, 4, 5]])
    assert faces == [[0, 1, 2]] and len(vertices) == 3


def test_vertices_at_one_position_stay_two_and_unused_ones_go():
    points = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [1, 0, 0], [1, 1, 0], [5, 5, 5.0]])
    vertices, faces = cleaned_polygons(points, [[0, 1, 2], [3, 4, 2]])
    assert len(vertices) == 5 and faces == [[0, 1, 2], [3, 4, 2]]


def test_a_repeated_corner_is_one_and_a_face_given_twice_stays_twice():
    # PyPRT 1.12 reads "f 1 2 2 3 4" as a quad, and keeps both copies of a face given twice
    points = np.array([[0, 0, 0], [1, 0, 0], [1, 0, -1], [0, 0, -1.0]])
    assert cleaned_polygons(points, [[0, 1, 1, 2, 3]])[1] == [[0, 1, 2, 3]]
    assert cleaned_polygons(points, [[0, 1, 2, 3], [0, 1, 2, 3]])[1] == [[0, 1, 2, 3]] * 2


def test_each_cleaned_corner_is_named_by_the_input_corner_it_is():
    """What a corner carries follows it: the corner that stays of a collapsed edge, the
    corners of a sliver spliced into a face (numbered in the input's faces, one after
    another), the same faces and vertices as cleaned_polygons gives."""
    from shapegen.geometry.asset_cleanup import cleaned_polygons_and_corners

    # the short edge: corners 0..4 of the pentagon, 5..8 of the square; vertex 1 stays
    points = np.array([[0, 0, 0], [1, 0, 0], [1, 0.0005, 0], [1, 1, 0], [0, 1, 0], [2, 0, 0],
                       [2, 1, 0]], dtype=float)  # fmt: skip
    faces = [[0, 2, 1, 3, 4], [1, 5, 6, 3]]
    vertices, cleaned, corners = cleaned_polygons_and_corners(points, faces)
    expected_vertices, expected_faces = cleaned_polygons(points, faces)
    assert np.array_equal(vertices, expected_vertices) and cleaned == expected_faces
    assert corners == [[0, 2, 3, 4], [5, 6, 7, 8]]
    # the sliver [1, 6, 2] (corners 4, 5, 6) spliced into the first square (corners 0..3)
    points = np.array([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0], [2, 0, 0], [2, 1, 0],
                       [1, 0.5, 0]], dtype=float)  # fmt: skip
    _, cleaned, corners = cleaned_polygons_and_corners(
        points, [[0, 1, 2, 3], [1, 6, 2], [1, 4, 5, 2]]
    )
    assert corners == [[0, 1, 5, 2, 3], [7, 8, 9, 10]]

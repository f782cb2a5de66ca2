"""Extruding several faces: along one direction no internal lamina faces (op_extrude), checked
on unit cases and against CityEngine's runtime (``prt_lamina.json`` says how it was measured)."""

import json
from collections import Counter
from pathlib import Path

import numpy as np
import pytest

import shapegen.prt as prt
from shapegen.geometry.extrude import extrude_faces
from shapegen.geometry.mesh import Mesh

HERE = Path(__file__).resolve().parent
MEASURED = json.loads((HERE / "prt_lamina.json").read_text())
BUILDING = (
    HERE.parent / "data" / "cga-corpus" / "data_Building_From_FootprintSMALL__fc6ce924" / "rules"
    / "Building_From_FootprintSMALL.cga"
)  # fmt: skip


def two_squares(lift: float = 0.0) -> Mesh:
    # two unit squares side by side in the xz-plane, sharing the edge x = 1 (seen from +y);
    # ``lift`` raises the second's far edge, so the two lie in different planes
    points = [(0, 0, 1), (1, 0, 1), (1, 0, 0), (0, 0, 0), (2, lift, 1), (2, lift, 0)]
    return Mesh(np.array(points, float), ((0, 1, 2, 3), (1, 4, 5, 2)))


def edge_uses(mesh: Mesh) -> Counter:
    uses = Counter()
    keys = [tuple(np.round(p, 9)) for p in mesh.vertices]
    for face in mesh.faces:
        for e in range(len(face)):
            uses[frozenset((keys[face[e]], keys[face[(e + 1) % len(face)]]))] += 1
    return uses


def test_faces_in_one_plane_make_one_solid_without_the_shared_side():
    solid = extrude_faces(two_squares(), 2.0)
    assert len(solid.faces) == 2 + 2 + 6  # two bottoms, two tops, the six outer sides
    assert set(edge_uses(solid).values()) == {2}  # closed: every edge between two faces
    assert solid.volume() == pytest.approx(4.0)


def test_faces_in_different_planes_keep_their_internal_faces():
    solid = extrude_faces(two_squares(lift=0.5), 2.0)
    assert len(solid.faces) == 2 * 6  # op_extrude: "internal faces are created"


def test_along_a_direction_the_shared_side_goes_whatever_the_planes():
    solid = extrude_faces(two_squares(lift=0.5), 2.0, np.array([0.0, 1.0, 0.0]))
    assert len(solid.faces) == 2 + 2 + 6  # world.up: "no internal lamina faces"


def test_flat_roof_parapet_counts_as_cityengine():
    (model,) = prt.ModelGenerator([prt.InitialShape(MEASURED["lot"])]).generate_model(
        [dict(MEASURED["attrs"], seed=0)], str(BUILDING)
    )
    assert len(model.get_faces()) == MEASURED["faces"]
    assert len(model.get_vertices()) // 3 == MEASURED["vertices"]

"""Surfaces (leaves drawn but left out of the statics) and rule colours in the written files:
JSON, glTF and OBJ keep them and read them back; triangles cover non-convex faces exactly."""

from __future__ import annotations

import json

import numpy as np
import pytest
import trimesh

from shapegen.errors import InputFormatError
from shapegen.export.blocks_json import model_to_dict
from shapegen.export.model_io import encode_model, write_model
from shapegen.export.surfaces import face_triangles, left_out_summary
from shapegen.model import Model
from shapegen.model.appearance import Appearance, Surface
from shapegen.model.block import Block
from shapegen.readers.blocks_json import model_from_dict
from shapegen.readers.models import read_model

# An L-shaped face at y = 2 (area 3 m^2), counter-clockwise seen from above (+y).
L_SHAPE = np.array([[0, 2, 0], [0, 2, 2], [1, 2, 2], [1, 2, 1], [2, 2, 1], [2, 2, 0]], float)
RED = Appearance(color=(1.0, 0.0, 0.0))
GREEN_GLASS = Appearance(color=(0.0, 1.0, 0.0), opacity=0.5)


def _model() -> Model:
    model = Model(
        [Block.box((0, 0, 0), (2, 1, 2), appearance=RED), Block.box((0, 1, 0), (1, 2, 1))]
    )
    model.surfaces = [
        Surface(L_SHAPE, [tuple(range(6))], GREEN_GLASS, ("roof",), ("Lot", "Roof"),
                "a face (no volume)"),
        Surface(L_SHAPE + [0, 1, 0], [tuple(range(6))], reason="not convex"),
    ]  # fmt: skip
    return model


def _triangle_areas(vertices, triangles, normal=None):
    a, b, c = (vertices[triangles[:, k]] for k in range(3))
    cross = np.cross(b - a, c - a)
    if normal is not None:
        return cross @ np.asarray(normal, float) / 2
    return np.linalg.norm(cross, axis=1) / 2


def test_non_convex_face_is_covered_exactly():
    triangles = face_triangles(L_SHAPE, [tuple(range(6))])
    assert len(triangles) == 4  # a hexagon: n - 2
    signed = _triangle_areas(L_SHAPE, triangles, normal=(0, 1, 0))
    assert (signed > 0).all()  # every triangle turned as the polygon
    assert signed.sum() == pytest.approx(3.0)  # no triangle outside the L, none missing


def test_convex_faces_are_fanned_and_flat_ones_dropped():
    square = np.array([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0], [2, 0, 0]], float)
    assert face_triangles(square, [(0, 1, 2, 3)]).tolist() == [[0, 1, 2], [0, 2, 3]]
    assert face_triangles(square, [(0, 1, 4, 0)]).shape == (0, 3)  # collinear: no area


def test_left_out_summary_counts_by_reason():
    assert left_out_summary(_model()) == {
        "leaves": 2,
        "by_reason": {"a face (no volume)": 1, "not convex": 1},
    }
    assert left_out_summary(Model([])) == {"leaves": 0, "by_reason": {}}


def test_json_keeps_surfaces_and_colours(tmp_path):
    path = tmp_path / "model.json"
    write_model(_model(), path)
    document = json.loads(path.read_text())
    assert document["blocks"][0]["appearance"] == {"color": [1.0, 0.0, 0.0]}
    assert "appearance" not in document["blocks"][1]
    back = read_model(path)
    assert back.blocks[0].appearance == RED
    first, second = back.surfaces
    assert (first.id, first.reason, first.tags, first.rule_path) == (
        "s0", "a face (no volume)", ("roof",), ("Lot", "Roof")
    )  # fmt: skip
    assert first.appearance == GREEN_GLASS
    assert np.array_equal(first.vertices, L_SHAPE) and first.faces == (tuple(range(6)),)
    assert second.reason == "not convex"


def test_json_without_surfaces_is_unchanged():
    document = model_to_dict(Model([Block.box((0, 0, 0), (1, 1, 1))]))
    assert "surfaces" not in document and "appearance" not in document["blocks"][0]


@pytest.mark.parametrize("suffix", [".glb", ".gltf"])
def test_gltf_materials_and_surface_nodes(tmp_path, suffix):
    path = tmp_path / f"model{suffix}"
    write_model(_model(), path)
    scene = trimesh.load_scene(str(path))
    extras = {
        node: scene.graph.transforms.edge_data[(scene.graph.base_frame, node)].get("metadata")
        for node in scene.graph.nodes_geometry
    }
    assert extras["s0"]["role"] == "surface" and extras["s0"]["structural"] is False
    assert extras["s0"]["reason"] == "a face (no volume)"
    assert extras["b0"]["appearance"] == {"color": [1.0, 0.0, 0.0]}

    def material(node):
        return scene.geometry[scene.graph[node][1]].visual.material

    assert material("b0").baseColorFactor.tolist() == [255, 0, 0, 255]
    assert material("s0").baseColorFactor.tolist() == [0, 255, 0, 128]
    assert material("s0").doubleSided and material("s0").alphaMode == "BLEND"
    back = read_model(path)
    assert len(back.blocks) == 2 and back.blocks[0].appearance == RED
    assert [s.id for s in back.surfaces] == ["s0", "s1"]
    assert back.surfaces[0].appearance == GREEN_GLASS and back.surfaces[0].tags == ("roof",)
    areas = _triangle_areas(back.surfaces[0].vertices, np.array(back.surfaces[0].faces))
    assert areas.sum() == pytest.approx(3.0, rel=1e-6)


def test_gltf_with_an_analysis_keeps_the_surfaces_colour():
    from shapegen.statics import analyze

    model = _model()
    content = encode_model(model, "x.glb", analyze(model))
    scene = trimesh.load(trimesh.util.wrap_as_stream(content), file_type="glb")
    colors = {n: scene.geometry[scene.graph[n][1]].visual.material.baseColorFactor.tolist()
              for n in scene.graph.nodes_geometry}  # fmt: skip
    assert colors["s0"] == [0, 255, 0, 128]
    assert colors["b0"] != [255, 0, 0, 255]  # blocks take the tension ramp


def test_obj_vertex_colours_and_surface_groups(tmp_path):
    path = tmp_path / "model.obj"
    write_model(_model(), path)
    text = path.read_text()
    assert "g surface:s0" in text
    assert "v 0 0 0 1 0 0" in text  # the red block's first corner, with its colour
    back = read_model(path)
    assert len(back.blocks) == 2
    assert [s.id for s in back.surfaces] == ["s0", "s1"]
    areas = _triangle_areas(back.surfaces[0].vertices, np.array(back.surfaces[0].faces))
    assert areas.sum() == pytest.approx(3.0)


@pytest.mark.parametrize(
    "entry, message",
    [
        ([], r"surfaces\[0\] must be an object"),
        ({"vertices": [[0, 0, 0]], "faces": [[0, 0, 5]]}, r'"faces" must be lists of at least 3'),
        ({"vertices": [[0, 0, "x"]]}, r'surface .s0.: "vertices" must be a finite number'),
        ({"vertices": [[0, 0, 0]], "reason": 3}, r'"reason" must be a string'),
        ({"vertices": [[0, 0, 0]], "appearance": {"color": [2, 0, 0]}}, r'"color" must be in'),
        ({"vertices": [[0, 0, 0]], "appearance": {"uv": [1]}}, r'"uv" must be a list of'),
    ],
)
def test_bad_surface_entries_are_one_clear_error(entry, message):
    document = model_to_dict(Model([Block.box((0, 0, 0), (1, 1, 1))]))
    document["surfaces"] = [entry]
    with pytest.raises(InputFormatError, match=message):
        model_from_dict(document)


def test_picture_draws_surfaces_from_both_sides():
    from shapegen.export.render import render_blocks

    model = Model([])
    green = Appearance(color=(0.0, 1.0, 0.0))
    model.surfaces = [Surface(L_SHAPE, [tuple(range(6))], green)]
    reversed_face = Model([])
    reversed_face.surfaces = [Surface(L_SHAPE, [tuple(reversed(range(6)))], green)]
    seen = []
    for case in (model, reversed_face):
        colors = np.array([[0, 255, 0, 255]])
        rendering = render_blocks(case, np.empty((0, 4)), size_px=(80, 60), surface_colors=colors)
        rgb = rendering.rgb.reshape(-1, 3).astype(int)
        seen.append(int(((rgb[:, 1] > 150) & (rgb[:, 0] < 100) & (rgb[:, 2] < 100)).sum()))
    assert seen[0] > 200 and seen[0] == seen[1]  # the same pixels whichever way it faces


def test_picture_of_a_model_with_surfaces_has_their_legend_row():
    from shapegen.export.picture import _surface_entries

    assert [name for name, _ in _surface_entries(_model().surfaces)] == ["not judged"]

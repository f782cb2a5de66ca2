"""Stand-ins: leaves the model keeps as drawn (open shells, solids that do not cut into convex
pieces) judged as solids by the statics alone, counted by reason, the model left as derived."""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np
import pytest

from shapegen.errors import StaticsError
from shapegen.geometry.mesh import Mesh
from shapegen.geometry.solids import HULL_CORNERS, hull_corners
from shapegen.model import Block, Model
from shapegen.model.appearance import Surface
from shapegen.statics import analyze, lateral_capacity
from shapegen.statics.standins import CAPPED, HULL, TURNED, StaticsModel, statics_model

WIDTH, HEIGHT = 1.0, 3.0  # m: a column tips at atan(WIDTH / HEIGHT) on a tilting table


def tube(low, size, reason="not closed", **kwargs) -> Surface:
    """A box's four sides without its bottom and top: an open shell, as a leaf left out."""
    box = Mesh.box(size)
    return Surface(box.vertices + np.asarray(low, float), box.faces[2:], reason=reason, **kwargs)


def post_and_lintel(reason_column=None) -> Model:
    """Two open-tube columns under a lintel block: the lintel rests on nothing unless the
    columns stand in."""
    columns = [
        tube((x, 0.0, 0.0), (WIDTH, HEIGHT, WIDTH), id=f"s{k}", tags=("Shaft",))
        for k, x in enumerate((0.0, 3.0))
    ]
    lintel = Block.box((0.0, HEIGHT, 0.0), (4.0, HEIGHT + 0.5, WIDTH), id="lintel")
    return Model([lintel], surfaces=columns)


def test_open_columns_stand_in_and_carry_the_lintel_the_model_left_as_derived():
    model = post_and_lintel()
    judged = statics_model(model)
    assert isinstance(judged, StaticsModel)
    assert [b.id for b in judged.blocks] == ["lintel", "s0", "s1"]
    assert judged.stand_ins.by_reason == {CAPPED: 2}
    assert judged.stand_ins.left_out == {}
    # the model itself keeps its one block and its two surfaces
    assert len(model.blocks) == 1 and len(model.surfaces) == 2
    analysis = analyze(model)
    assert analysis.feasible
    # the weight is the lintel's and the two capped columns'
    volume = 4.0 * 0.5 * WIDTH + 2 * WIDTH * HEIGHT * WIDTH
    assert analysis.total_weight == pytest.approx(volume * 2400.0 * 9.81, rel=1e-12)
    # the figures per block are the model's own blocks'
    assert analysis.n_blocks == 1 and len(analysis.block_tension) == 1
    report = analysis.to_report()
    assert report["blocks"] == 1
    assert report["stand_ins"] == {
        "leaves": 2,
        "blocks": 2,
        "by_reason": {CAPPED: 2},
        "left_out": {"leaves": 0, "by_reason": {}},
    }


def test_the_model_is_written_as_derived_with_the_analysis_of_its_stand_ins():
    import json

    from shapegen.export.model_io import encode_model

    model = post_and_lintel()
    analysis = analyze(model)
    written = json.loads(encode_model(model, "temple.json", analysis))
    assert [b["id"] for b in written["blocks"]] == ["lintel"]
    assert len(written["surfaces"]) == 2
    assert encode_model(model, "temple.glb", analysis)  # one tension per block of the model


def test_the_same_model_gives_the_same_statics_model_and_a_statics_model_is_its_own():
    model = post_and_lintel()
    judged = statics_model(model)
    assert statics_model(model) is judged
    assert statics_model(judged) is judged
    plain = Model([Block.box((0, 0, 0), (1, 1, 1))])
    assert statics_model(plain) is plain


def test_a_capped_column_tips_at_the_closed_form_tilt():
    column = Model([], surfaces=[tube((0.0, 0.0, 0.0), (WIDTH, HEIGHT, WIDTH))])
    capacity = lateral_capacity(column, azimuths=[0])
    assert capacity.tilt == pytest.approx(math.degrees(math.atan(WIDTH / HEIGHT)), abs=0.05)


def test_a_solid_that_does_not_cut_stands_on_its_hull_with_its_own_weight():
    # an L-shaped prism as its true (non-convex) mesh, left out as "not convex"
    outline = [(0, 0), (2, 0), (2, 1), (1, 1), (1, 3), (0, 3)]
    bottom = [(x, 0.0, z) for x, z in outline]
    top = [(x, 0.5, z) for x, z in outline]
    n = len(outline)
    faces = [tuple(range(n)), tuple(range(2 * n - 1, n - 1, -1))]
    faces += [(k, (k + 1) % n + 0, (k + 1) % n + n, k + n)[::-1] for k in range(n)]
    mesh = Mesh(np.array(bottom + top), faces)
    if mesh.signed_volume() < 0:
        mesh = mesh.reversed()
    assert mesh.is_closed and not mesh.is_convex()
    leaf = Surface(mesh.vertices, mesh.faces, reason="not convex", id="s0")
    model = Model([], surfaces=[leaf])
    judged = statics_model(model)
    assert judged.stand_ins.by_reason == {HULL: 1}
    (hull,) = judged.blocks
    assert hull.volume == pytest.approx(2.5, rel=1e-12)  # the hull of the L: 5 m^2 x 0.5 m
    assert hull.mass == pytest.approx(4 * 0.5 * 2400.0, rel=1e-12)  # the L's own weight
    assert analyze(model).feasible


def test_inward_faces_are_turned_out():
    box = Mesh.box((1.0, 1.0, 1.0)).reversed()
    model = Model([], surfaces=[Surface(box.vertices, box.faces, reason="faces turned inwards")])
    judged = statics_model(model)
    assert judged.stand_ins.by_reason == {TURNED: 1}
    assert judged.blocks[0].volume == pytest.approx(1.0)


def test_what_cannot_stand_in_stays_out_counted_by_reason():
    box = Mesh.box((1.0, 1.0, 1.0))
    # a mesh that runs an edge twice the same way (a face repeated) is not one surface
    doubled = Surface(box.vertices, box.faces[1:] + box.faces[1:2], reason="not closed")
    face = Surface(box.vertices, box.faces[:1], reason="a face (no volume)")
    model = post_and_lintel()
    model.surfaces += [doubled, face]
    judged = statics_model(model)
    assert judged.stand_ins.by_reason == {CAPPED: 2}
    assert judged.stand_ins.left_out == {"not closed": 1, "a face (no volume)": 1}
    assert len(judged.surfaces) == 2


def test_a_stand_in_is_structure_by_its_labels():
    model = post_and_lintel()
    with pytest.raises(StaticsError, match="'lintel' touches no support"):
        analyze(model, ignore="Shaft")  # the columns ride as ornaments: the lintel floats


def test_a_thinned_hull_keeps_its_flat_ends_and_lies_inside_the_hull():
    sides = 400  # a cylinder of 400 sides: 1 596 hull triangles
    angles = np.linspace(0.0, 2 * np.pi, sides, endpoint=False)
    ring = np.column_stack([np.cos(angles), np.zeros(sides), np.sin(angles)])
    points = np.vstack([ring, ring + [0.0, 2.0, 0.0]])
    corners = hull_corners(points)
    assert len(corners) <= HULL_CORNERS
    block = Block.from_hull(corners)
    low, high = block.vertices[:, 1].min(), block.vertices[:, 1].max()
    assert (low, high) == (0.0, 2.0)
    ends = [k for k, n in enumerate(block.face_normals) if abs(abs(n[1]) - 1.0) < 1e-12]
    assert len(ends) == 2
    # each end an inscribed polygon of the unit disc: no corner outside it, most of its area
    for k in ends:
        assert block.face_area(k) == pytest.approx(np.pi, rel=0.01)
        assert block.face_area(k) <= np.pi
    assert np.all(np.hypot(corners[:, 0], corners[:, 2]) <= 1.0 + 1e-12)
    few = hull_corners(points[::25])  # a hull of few triangles keeps every corner
    assert len(few) == len(points[::25])


def test_the_editor_reads_joints_with_stand_ins_as_neighbours():
    from types import SimpleNamespace

    from shapegen.editor.blocks import block_details
    from shapegen.editor.scene import scene_data
    from shapegen.pipeline import load
    from shapegen.structures import Design, make_structure

    model = post_and_lintel()
    assessment = make_structure("blocks").assess(Design.of_model(model))
    scene = scene_data(model, assessment)
    assert [b["id"] for b in scene["blocks"]] == ["lintel"]
    assert len(scene["forces"]["joints"]) == 2  # the lintel on each column
    grammar = load("arch_columns.grammar")  # any grammar: the lintel names no rule
    outcome = SimpleNamespace(model=model, assessment=assessment, grammar=grammar)
    details = block_details(outcome, "lintel", {})
    assert sorted(j["other"] for j in details["joints"]) == ["s0", "s1"]


def test_a_solid_kept_as_derived_is_cut_when_judged_from_the_model_or_its_file():
    # an L-shaped mass stays one solid in the model and in its file; the statics cut it into
    # two convex parts of one body with the rule's density, before and after a round trip
    import shapegen
    from shapegen.export.blocks_json import model_to_dict
    from shapegen.readers.blocks_json import model_from_dict
    from shapegen.statics.standins import CUT

    grammar = shapegen.parse_grammar("attr density = 1500\n@StartRule\nLot --> extrude(3) Mass\n")
    model = grammar.build(lot=[(0, 0), (4, 0), (4, -2), (2, -2), (2, -4), (0, -4)])
    assert not model.blocks and [s.reason for s in model.surfaces] == ["not convex"]
    again = model_from_dict(model_to_dict(model))
    assert again.surfaces[0].solid.density == 1500.0
    for judged in (statics_model(model), statics_model(again)):
        assert judged.stand_ins.by_reason == {CUT: 1} and judged.stand_ins.left_out == {}
        assert sorted(b.volume for b in judged.blocks) == pytest.approx([12.0, 24.0])
        assert sum(b.mass for b in judged.blocks) == pytest.approx(36.0 * 1500.0)
        assert len({b.body for b in judged.blocks}) == 1
    assert analyze(model).feasible
    # a model moved after its derivation (as a PyPRT initial shape's): cut where it now is
    solid = model.surfaces[0]
    moved = Model([], surfaces=[replace(solid, vertices=solid.vertices + 100.0)])
    pieces = statics_model(moved).blocks
    assert sorted(b.volume for b in pieces) == pytest.approx([12.0, 24.0])
    low = np.concatenate([b.vertices for b in pieces]).min(axis=0)
    assert low == pytest.approx([100.0, 100.0, 96.0])

"""set() of the shape attributes CityEngine lets a rule write: the scope (attr_scope: "can be
both read and written") and the pivot (attr_pivot), each read back as scope.* / pivot.*; and
two operations of geometry upkeep: cleanupGeometry on the edges of comp(e), reduceGeometry
(kept whole, with a warning)."""

from __future__ import annotations

import numpy as np
import pytest

from shapegen import parse_grammar
from shapegen.errors import GrammarError

COVERS = {
    "test_writing_the_scope_moves_turns_and_sizes_the_shape": (
        "op:set",
        "attr:scope.tx",
        "attr:scope.ry",
        "attr:scope.sy",
    ),
    "test_writing_the_pivot_keeps_the_shape_in_place": ("attr:pivot.px", "attr:pivot.oy"),
    "test_reduce_geometry_keeps_the_geometry_and_says_so": ("op:reduceGeometry",),
}

LOT = (4.0, 6.0)


def _model(body: str, name: str = "r.cga"):
    return parse_grammar(f"@StartRule\nLot --> extrude(2) {body}", name).build(lot=LOT)


def _reports(body: str) -> dict:
    return _model(body).metadata["reports"]


def test_writing_the_scope_moves_turns_and_sizes_the_shape():
    moved = _model("set(scope.tx, 3) set(scope.ty, 1) X.")
    plain = _model("X.")
    shift = moved.blocks[0].vertices.min(axis=0) - plain.blocks[0].vertices.min(axis=0)
    assert np.allclose(shift, (3, 1, 0))
    reports = _reports('set(scope.tx, 3) report("tx", scope.tx) X.')
    assert reports["tx"] == pytest.approx(3.0)
    turned = _model("set(scope.ry, 90) X.")
    size = np.ptp(turned.blocks[0].vertices, axis=0)
    assert np.allclose(size, (6, 2, 4))  # the 4 x 2 x 6 mass turned a quarter about y
    assert _reports('set(scope.ry, 90) report("ry", scope.ry) X.')["ry"] == pytest.approx(90)
    tall = _model("set(scope.sy, 5) X.")
    assert tall.blocks[0].volume == pytest.approx(4 * 5 * 6)


def test_writing_the_pivot_keeps_the_shape_in_place():
    # the scope stays; only what scope.t* reads (relative to the pivot) changes
    body = 'set(scope.tx, 3) set(pivot.px, 1) report("tx", scope.tx) report("px", pivot.px) X.'
    model = _model(body)
    assert model.metadata["reports"]["tx"] == pytest.approx(2.0)
    assert model.metadata["reports"]["px"] == pytest.approx(1.0)
    assert np.allclose(model.blocks[0].vertices.min(axis=0), (3, 0, 0))
    reports = _reports('set(pivot.oy, 90) report("oy", pivot.oy) report("ry", scope.ry) X.')
    assert reports["oy"] == pytest.approx(90) and reports["ry"] == pytest.approx(-90)


def test_scope_elevation_and_grammar_files_refuse_the_writes():
    with pytest.raises(GrammarError, match="unknown attribute 'scope.elevation'"):
        _model("set(scope.elevation, 3) X.")
    with pytest.raises(GrammarError, match="unknown attribute 'scope.tx'"):
        _model("set(scope.tx, 3) X.", "r.grammar")


def test_cleanup_geometry_of_edges_leaves_them_as_they_are():
    model = _model('comp(e) { all : cleanupGeometry(all, 0.01) report("edge", 1) E. }')
    assert len(model.metadata["reports"]["edge"]) == 12 and not model.metadata["warnings"]


def test_reduce_geometry_keeps_the_geometry_and_says_so():
    model = _model("reduceGeometry(0.5) X.")
    assert model.blocks[0].volume == pytest.approx(48.0)
    (warning,) = model.metadata["warnings"]
    assert "reduceGeometry(0.5): the geometry is kept whole" in warning
    # a tolerance out of range is a CGA error of the runtime: skipped, the mass carries on
    model = _model("reduceGeometry(2) X.")
    assert model.metadata["cga_errors"] == 1
    assert model.blocks[0].volume == pytest.approx(48.0)
    assert any("the tolerance is 0..1, got 2; the operation is skipped" in w
               for w in model.metadata["warnings"])  # fmt: skip


def test_insert_options_may_be_strings_chosen_when_derived(tmp_path):
    (tmp_path / "slab.obj").write_text(
        "v 0 0 0\nv 1 0 0\nv 1 0 3\nv 0 0 3\nv 0 2 0\nv 1 2 0\nv 1 2 3\nv 0 2 3\n"
        "f 1 2 3 4\nf 8 7 6 5\nf 1 5 6 2\nf 2 6 7 3\nf 3 7 8 4\nf 4 8 5 1\n"
    )
    path = tmp_path / "r.cga"
    path.write_text('attr up = "zUp"\nmode = "keepSizeAndPosition"\n@StartRule\n'
                    'Lot --> i("slab.obj", up, mode) X.\n')  # fmt: skip
    from shapegen import load_grammar

    (block,) = load_grammar(path).build(lot=LOT).blocks
    assert np.allclose(np.ptp(block.vertices, axis=0), (1, 3, 2))  # z up turned to y
    path.write_text('attr up = "sideways"\n@StartRule\nLot --> i("slab.obj", up) X.\n')
    model = load_grammar(path).build(lot=LOT)  # a CGA error: i() is skipped, the lot stays
    assert model.metadata["cga_errors"] == 1 and not model.blocks and len(model.surfaces) == 1
    assert "argument 2 is one of yUp, zUp; got sideways" in model.metadata["warnings"][0]

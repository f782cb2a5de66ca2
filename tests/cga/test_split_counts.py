"""Repeat groups nested in a sequence, as CityEngine's runtime lays them out (.cga files).

op_split: "the number of repetitions and floating dimensions are adapted to the best solution
(best number of repetitions and least stretching)". PyPRT's model of the candler package gives
the figures (its windows, ``Windows(n)`` on a 1.93 m sub-tile): one window for n = 1, two of
0.84 m for n = 2, three of 0.48 m for n = 3. Files in shapegen's ``.grammar`` dialect keep their
documented rule (the group is a floating part of its nominal length, repeated at least once).
"""

from __future__ import annotations

import pytest

import shapegen
from shapegen.engine.shapes.split import ABSOLUTE, FLOATING, SplitPart, SplitRepeat, resolve_split
from shapegen.statics.standins import statics_model

TILE = 1.93  # candler's sub-tile: TileWidth 3.55 - 2 x 0.7, on a 12 m facade of three tiles


def _windows(n: int, best_counts: bool) -> list[tuple[str, float]]:
    """candler's ``split(x){ { ~w/n : Window | 0.25 : Wall }* | ~w/n : Window }``."""
    window = SplitPart(TILE / n, FLOATING, "window")
    pattern = [SplitRepeat((window, SplitPart(0.25, ABSOLUTE, "wall"))), window]
    pieces = resolve_split(TILE, pattern, best_counts=best_counts)
    return [(p.key, round(p.size, 2)) for p in pieces]


@pytest.mark.parametrize(
    "n, windows, width",
    [(1, 1, 1.93), (2, 2, 0.84), (3, 3, 0.48)],  # PyPRT's candler model
)
def test_nested_repeats_take_the_count_that_stretches_least(n, windows, width):
    pieces = _windows(n, best_counts=True)
    assert [size for key, size in pieces if key == "window"] == [width] * windows
    assert [key for key, _ in pieces].count("wall") == windows - 1
    assert sum(size for _, size in pieces) == pytest.approx(TILE, abs=0.02)


def test_the_grammar_dialect_keeps_at_least_one_repetition():
    # shapegen's own rule: the group is a floating part, laid out at least once
    assert [key for key, _ in _windows(1, best_counts=False)] == ["window", "wall", "window"]


def test_top_level_repeats_are_unchanged():
    pattern = SplitRepeat((SplitPart(2.1, FLOATING, "g"),))
    for flag in (False, True):
        assert len(resolve_split(10, pattern, best_counts=flag)) == 5


def test_a_cga_file_lays_its_windows_out_as_cityengine(tmp_path):
    path = tmp_path / "windows.cga"
    path.write_text(
        "@StartRule\n"
        "Lot --> extrude(3) comp(f) { 2 : Tile }\n"  # the 12 m side
        "Tile --> split(x) { { ~4 : Window | 0.25 : Wall }* | ~4 : Window }\n"
        'Window --> report("w", scope.sx) X.\n'
    )
    reports = shapegen.load_grammar(path).build(lot=(12, 8)).metadata["reports"]
    # two repetitions: three windows of (12 - 0.5) / 3 m; one (two windows of 5.875 m) stretches
    # them by 1.47, three (four of 2.81 m) by 0.70, two by 0.96
    assert reports["w"] == pytest.approx([11.5 / 3] * 3)


def test_envelope_keeps_the_faces_axes_and_resizes_its_scope(tmp_path):
    path = tmp_path / "envelope.cga"
    path.write_text(
        "@StartRule\n"
        "Lot --> extrude(10) comp(f) { top : Top }\n"
        "Top --> envelope(normal, 0.6, 0.45, 45, 0.45, 45) "
        'report("sx", scope.sx) report("sy", scope.sy) report("sz", scope.sz) X.\n'
    )
    reports = shapegen.load_grammar(path).build(lot=(12, 8)).metadata["reports"]
    # the top face's scope: x and y in the roof plane, z along its normal (up), sized to fit
    assert reports["sx"] == pytest.approx(12.0)
    assert reports["sy"] == pytest.approx(8.0)
    assert reports["sz"] == pytest.approx(0.6)


def test_leaves_count_leaf_shapes_and_extrude_zero_is_a_face(tmp_path):
    path = tmp_path / "leaves.cga"
    # an L-shaped mass is one leaf, kept as derived (cut into two convex blocks when judged);
    # extrude(0) leaves the lot's face
    path.write_text("@StartRule\nLot --> shapeL(4, 4) { shape : extrude(3) A | remainder : B }\n"
                    "B --> extrude(0)\n")  # fmt: skip
    model = shapegen.load_grammar(path).build(lot=(12, 8))
    assert not model.blocks and model.metadata["leaves"] == 2
    solid, face = model.surfaces
    assert solid.reason == "not convex" and face.reason == "a face (no volume)"
    assert len(statics_model(model).blocks) == 2


def test_an_offset_that_leaves_nothing_is_ignored_with_a_warning(tmp_path):
    # PyPRT's candler: "offset(): no face selected, ignoring operation" on its roof's narrowest
    # pipe ring; the ring is then laid on the face as it was
    path = tmp_path / "offset.cga"
    path.write_text('@StartRule\nLot --> offset(-5, inside) report("area", geometry.area()) X.\n')
    model = shapegen.load_grammar(path).build(lot=(12, 8))
    assert model.metadata["reports"]["area"] == pytest.approx(96.0)
    (warning,) = model.metadata["warnings"]
    assert "offset(-5, inside) left no face" in warning and "Lot" in warning
    path.write_text('@StartRule\nLot --> offset(-3, inside) report("area", geometry.area()) X.\n')
    model = shapegen.load_grammar(path).build(lot=(12, 8))
    assert model.metadata["reports"]["area"] == pytest.approx(6 * 2)
    assert not model.metadata["warnings"]


def test_the_old_string_range_is_not_a_numeric_parameter(tmp_path):
    # candler: @Range("Visualization", "3DPrint") on a string attr (CityEngine's old form)
    path = tmp_path / "mode.cga"
    path.write_text(
        '@Range("Visualization", "3DPrint")\nattr Mode = "Visualization"\n'
        "@Range(28, 150)\nattr H = 62\n@StartRule\nLot --> extrude(H) X.\n"
    )
    grammar = shapegen.load_grammar(path)
    assert set(grammar.parameter_ranges()) == {"H"}

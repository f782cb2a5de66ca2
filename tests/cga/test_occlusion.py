"""Occlusion queries (inside, overlaps, touches) on closed-form arrangements of boxes.

The lot is 12 x 8 m; ``split(x) { 6 : A | ~1 : B }`` puts A on x in [0, 6] and B on [6, 12]. A is
a 10 m high box; B is moved and sized with s()/t() so that the answers follow from the boxes'
coordinates alone.
"""

from __future__ import annotations

import pytest

from shapegen import load_grammar

PROBE = """
Lot --> split(x) { 6 : A | ~1 : B }
A --> extrude(10) label("blk") Big.
Probe --> report("inside", case inside(intra) : 1 else : 0)
          report("overlaps", case overlaps(intra) : 1 else : 0)
          report("touches", case touches(intra) : 1 else : 0)
          report("touches_blk", case touches(intra, "blk") : 1 else : 0)
          report("touches_other", case touches(intra, "other") : 1 else : 0)
          report("touches_inter", case touches(inter) : 1 else : 0)
          P.
"""


def _reports(tmp_path, text: str) -> dict:
    path = tmp_path / "occlusion.cga"
    path.write_text(text)
    return load_grammar(path).build(lot=(12.0, 8.0)).metadata["reports"]


def _probe(tmp_path, b_rule: str) -> dict:
    reports = _reports(tmp_path, PROBE + "B --> " + b_rule + "\n")
    return {k: reports[k] for k in reports}


@pytest.mark.parametrize(
    ("b_rule", "expected"),
    [
        # x 2..4, y 0..2, z 2..4: inside A (x 0..6, y 0..10, z 0..8)
        ("extrude(2) s(2, 2, 2) t(-4, 0, 2) Probe", (1, 1, 1)),
        # x 4..8: half in A
        ("extrude(2) s(4, 2, 2) t(-2, 0, 2) Probe", (0, 1, 1)),
        # x 6..12, y 0..2: against A's right face (a 2 x 8 m contact)
        ("extrude(2) Probe", (0, 0, 1)),
        # x 8..10: a 2 m gap
        ("extrude(2) s(2, 2, 2) t(2, 0, 2) Probe", (0, 0, 0)),
        # y 10..12, x 6..12: only A's top edge at x = 6 is shared (no planar contact)
        ("extrude(2) t(0, 10, 0) Probe", (0, 0, 0)),
        # a face (no volume) lying on A's right face: inside (on its surface) and touching
        ("extrude(2) comp(f) { left : Probe | all : X. }", (1, 0, 1)),
    ],
)
def test_boxes_closed_form(tmp_path, b_rule, expected):
    reports = _probe(tmp_path, b_rule)
    assert (reports["inside"], reports["overlaps"], reports["touches"]) == expected
    assert reports["touches_blk"] == expected[2]  # A carries the label
    assert reports["touches_other"] == 0  # no occluder has that label
    assert reports["touches_inter"] == 0  # one lot: no other shape trees


def test_ancestors_are_not_occluders_and_neighbours_are(tmp_path):
    # A: 6 x 10 x 8 box cut into faces, each face into 2 m high tiles (5 per side, 20 tiles);
    # B: x 6..12, 5 m high. Tiles of A's right side with y in [0, 5] touch B: 0-2, 2-4, 4-6.
    # A's own volume (their ancestor) does not count, so no other tile touches anything.
    reports = _reports(
        tmp_path,
        """
Lot --> extrude(10) split(x) { 6 : A | ~1 : B }
A --> comp(f) { side : Facade | top : X. | bottom : X. }
B --> s('1, '0.5, '1) X.
Facade --> split(y) { 2 : Tile }*
Tile --> case touches(intra) : report("touch", 1) T.
         else : report("free", 1) T.
""",
    )
    assert len(reports["touch"]) == 3
    assert len(reports["free"]) == 17


def test_two_passes_as_the_reference_example(tmp_path):
    # cga_context's example: the default (false) case enlarges each volume so that in the first
    # pass both enlarged volumes overlap; in the second each query sees the other's enlarged
    # volume and answers true, so both stay unenlarged and red.
    reports = _reports(
        tmp_path,
        """
Lot --> split(x) { 6 : E | ~1 : E }
E --> extrude(10) Test
Test --> case overlaps(intra) : report("red", 1) Red.
         else : s('2, '1, '2) center(xyz) report("green", 1) Green.
""",
    )
    assert reports.get("red") == [1.0, 1.0]
    assert "green" not in reports


def test_a_rule_derived_in_two_passes_prints_once(tmp_path, capsys):
    # CityEngine prints in the pass that makes the model; the first pass only answers queries
    rule = tmp_path / "twice.cga"
    rule.write_text(
        'Lot --> print("start") split(x) { 6 : E | ~1 : E }\n'
        "E --> extrude(10) Test\n"
        'Test --> case overlaps(intra) : print("inside") Red.\n'
        "         else : Green.\n"
    )
    load_grammar(rule).build(lot=(12.0, 8.0))
    assert capsys.readouterr().out.splitlines() == ["start"]

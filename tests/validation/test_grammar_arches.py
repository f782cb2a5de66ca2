"""Statics through the primitives inserted from a grammar (issue 4, section 2).

- A semicircular arch of 100 voussoirs written as a rule reproduces Milankovitch's minimum
  thickness t / R = 0.1075 (R: centreline radius).
- An arch on two columns (the seed paper's Figure 8): a thin arch or narrow columns fall, a thick
  enough arch on wide enough columns stands (see test_arch_on_columns.py for the hand analysis
  that decides each case).
"""

import pytest

try:
    from shapegen import parse_grammar
except (ImportError, AttributeError):  # the grammar is built by another part of the package
    parse_grammar = None
pytestmark = pytest.mark.skipif(parse_grammar is None, reason="shapegen.parse_grammar is missing")

from shapegen.statics import analyze  # noqa: E402

ARCH = """
attr R = 1.0
attr t = 0.12

@StartRule
@Lot(2, 0.5)
Lot --> extrude(1) s(2 * R + t, R + t, 0.5) Arch

Arch --> i("arch", thickness = t, segments = 100)
"""

ARCH_ON_COLUMNS = """
attr t = 0.25
attr c = 1.5
attr h = 3

@StartRule
@Lot(4, 1)
Lot --> extrude(h + 2) split(y) { h : Piers | ~1 : Arch }

Piers --> split(x) { c : Pier | ~1 : NIL | c : Pier }

Pier --> i("column", courses = 3)

Arch --> i("arch", thickness = t, segments = 60)
"""


@pytest.mark.slow
def test_grammar_arch_has_the_minimum_thickness(bisect):
    grammar = parse_grammar(ARCH)

    def stands(ratio: float) -> bool:
        model = grammar.build(attrs={"t": ratio})
        model.friction = 5.0  # no joint slides
        assert len(model.blocks) == 100
        return analyze(model).feasible

    ratio = bisect(stands, 0.100, 0.115, tolerance=1e-4)
    assert ratio == pytest.approx(0.1075, rel=5e-3)


@pytest.mark.parametrize(
    "thickness, column_width, stands",
    [(0.18, 1.5, False), (0.25, 0.25, False), (0.25, 1.5, True)],
)
def test_grammar_arch_on_two_columns(thickness, column_width, stands):
    model = parse_grammar(ARCH_ON_COLUMNS).build(attrs={"t": thickness, "c": column_width})
    model.friction = 1.0
    assert len(model.blocks) == 60 + 2 * 3
    assert analyze(model).feasible is stands

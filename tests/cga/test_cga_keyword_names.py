"""A keyword where an operation or builtin takes a selector wins over a name the rule defines.

CityEngine's reference types those parameters as selectors (op_alignScopeToAxes: "alignAxes
(selector) x, y, z, world.x..."), and CGA has no selector values: no attr, const, parameter or
function can stand there, so ``alignScopeToAxes(y)`` aligns to the y axis in a file that also
defines ``y(i) = R * sin(a(i))`` (issue 45: it stopped with "function 'y' takes 1 argument").
Each rule below must derive the same with and without a function, a const and an attr named as
its keyword (a builtin's name, such as ``inside``, cannot be defined at all). Where a value may
stand, a bare function name is still refused, with the name.
"""

from __future__ import annotations

import numpy as np
import pytest

import shapegen
from shapegen.errors import GrammarError

#: (keyword, rule using it where its operation or builtin takes a selector)
KEYWORD_RULES = [
    ("y", "Lot --> extrude(4) r(0, 30, 0) alignScopeToAxes(y) X."),
    ("x", "Lot --> extrude(4) split(x) { 2 : A. | ~1 : B. }"),
    ("y", "Lot --> extrude(4) split(y) { 1 : A. | ~1 : B. }"),
    ("z", "Lot --> extrude(4) split(z) { 2 : A. | ~1 : B. }"),
    ("xz", "Lot --> extrude(4) s(2, 2, 2) center(xz) X."),
    ("xz", "Lot --> extrude(4) r(0, 20, 0) alignScopeToGeometryBBox(xz) X."),
    ("top", "Lot --> extrude(4) comp(f) { top : T. | side : S. }"),
    ("side", "Lot --> extrude(4) comp(f) { top : T. | side : S. }"),
    ("bottom", "Lot --> extrude(4) comp(f) { bottom : T. | all : S. }"),
    ("all", "Lot --> extrude(4) comp(f) { bottom : T. | all : S. }"),
    ("vertical", "Lot --> extrude(4) comp(f) { vertical : V. | horizontal : H. }"),
    ("e", "Lot --> comp(e) { all : s('1, 1, 1) primitiveCube() E. }"),
    ("front", "Lot --> setback(2) { front : A. | remainder : B. }"),
    ("remainder", "Lot --> setback(2) { front : A. | remainder : B. }"),
    ("byHeight", "Lot --> extrude(4) comp(f) { top : roofGable(byHeight, 2) R. }"),
    ("yUp", "Lot --> extrude(4) alignScopeToGeometry(yUp, largest) X."),
    ("largest", "Lot --> extrude(4) alignScopeToGeometry(yUp, largest) X."),
    ("xyz", "Lot --> extrude(4) setPivot(xyz, 2) X."),
    ("all", "Lot --> extrude(4) cleanupGeometry(all, 0.1) X."),
    ("surface", "Lot --> scatter(surface, 5, uniform) { s(1, 1, 1) primitiveCube() X. }"),
    ("uniform", "Lot --> scatter(surface, 5, uniform) { s(1, 1, 1) primitiveCube() X. }"),
    ("border", "Lot --> offset(-1) comp(f) { border : B. | inside : I. }"),
    ("scope", "Lot --> innerRectangle(scope) { shape : I. | remainder : R. }"),
    ("edge", "Lot --> innerRectangle(edge) { shape : I. | remainder : R. }"),
    ("keepSizeAndPosition", 'Lot --> i("builtin:cube", yUp, keepSizeAndPosition) X.'),
    ("inter", "Lot --> extrude(4) X.\nX --> case inside(inter) : A. else : B."),
    ("top", 'Lot --> extrude(4) report("a", geometry.area(top)) X.'),
    ("x", 'Lot --> extrude(4) report("c", convert(x, scope, world, pos, 1, 2, 3)) X.'),
    ("pos", 'Lot --> extrude(4) report("c", convert(x, scope, world, pos, 1, 2, 3)) X.'),
]

DEFINITIONS = {
    "function": "{word}(i) = R * sin(i)\nconst R = 2\n",
    "const": "const {word} = 3\n",
    "attr": "attr {word} = 0.5\n",
}


def _derived(text: str):
    model = shapegen.parse_grammar("@StartRule\n" + text, "keywords.cga").build(lot=(12.0, 8.0))
    points = [b.vertices for b in model.blocks] + [s.vertices for s in model.surfaces]
    return (
        model.metadata["reports"],
        [b.rule_path for b in model.blocks],
        [s.rule_path for s in model.surfaces],
        np.vstack(points).round(9),
    )


@pytest.mark.parametrize("definition", DEFINITIONS)
@pytest.mark.parametrize(("word", "rule"), KEYWORD_RULES, ids=[r for _, r in KEYWORD_RULES])
def test_a_keyword_wins_over_a_name_the_rule_defines(word, rule, definition):
    plain = _derived(rule)
    clashing = _derived(DEFINITIONS[definition].format(word=word) + rule)
    assert clashing[:3] == plain[:3]
    assert np.array_equal(clashing[3], plain[3])


def test_the_issue_rule_aligns_to_the_y_axis():
    text = (
        "const R = 5\na(i) = i * 10\ny(i) = R * sin(a(i))\n"
        "@StartRule\nLot --> extrude(4) r(0, 30, 0) alignScopeToAxes(y) "
        'report("ry", scope.ry) X.\n'
    )
    model = shapegen.parse_grammar(text, "issue45.cga").build(lot=(12.0, 8.0))
    assert model.metadata["reports"]["ry"] == pytest.approx(0.0, abs=1e-9)


@pytest.mark.parametrize(
    "rule",
    [
        "Lot --> offset(x) X.",
        "Lot --> t(0, x, 0) X.",
        "Lot --> extrude(x + 1) X.",
        'Lot --> report("c", convert(x, scope, world, pos, x, 0, 0)) X.',
    ],
)
def test_a_function_written_bare_where_a_value_stands_is_refused(rule):
    with pytest.raises(GrammarError, match=r"function 'x' takes 1 argument: write x\(\.\.\.\)"):
        shapegen.parse_grammar("x(i) = i\n@StartRule\n" + rule, "bare.cga").build(lot=(12, 8))


def test_an_attr_stays_a_value_where_convert_takes_values():
    # func_convert(component, from, to, type, x, y, z): the first four are selectors, x a value
    def converted(x_text: str, attr: str = "") -> float:
        call = f"convert(x, scope, world, pos, {x_text}, 0, 0)"
        text = f'{attr}@StartRule\nLot --> report("c", {call}) X.\n'
        return shapegen.parse_grammar(text, "c.cga").build(lot=(12, 8)).metadata["reports"]["c"]

    assert converted("x", "attr x = 2\n") == pytest.approx(converted("2"))
    assert converted("x", "attr x = 2\n") != pytest.approx(converted("0"))

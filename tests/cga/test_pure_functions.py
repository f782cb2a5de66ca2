"""A user function that reads only its arguments keeps its values (engine/expressions'
``_remembered``): the reports are the same as a derivation that evaluates every call, and a
function that reads an attr, a const, the shape or a random stream is evaluated every time."""

from __future__ import annotations

import shapegen.engine.expressions.compiler as compiler
from shapegen import parse_grammar

RULES = """
attr height = 2
tiles(name) = float(getRange(name, "_t", "_"))
scaled(name, k) = tiles(name) * k
withAttr(x) = x * height
withShape(x) = x + scope.sx
withRandom(x) = x + rand(0, 1)
countDown(n, acc) = case n <= 0: acc else: countDown(n - 1, acc + 1)
inverse(x) = 1 / x

Lot --> A(1) A(2) A(2) A(1)
A(k) -->
    report("tiles", tiles("u_f3_t4_x.jpg"))
    report("scaled", scaled("u_f3_t4_x.jpg", k))
    report("attr", withAttr(k))
    set(height, height + 1)
    report("attr after set", withAttr(k))
    report("shape", withShape(k))
    s('0.5, '1, '1)
    report("shape after s", withShape(k))
    report("random", withRandom(k))
    report("count", countDown(k * 3, 0))
    report("deep", countDown(k * 20000, 0))
    report("inverse of 0", inverse(0))
    report("inverse of -0", inverse(-0))
    X.
"""


def _reports(remember: bool, monkeypatch) -> dict:
    if not remember:  # every call evaluated: the reference
        monkeypatch.setattr(compiler, "_remembered", lambda body: body)
    return parse_grammar(RULES, "pure.cga").build(lot=(12, 8)).metadata["reports"]


def test_remembered_values_are_the_evaluated_ones(monkeypatch):
    remembered = _reports(True, monkeypatch)
    evaluated = _reports(False, monkeypatch)
    assert repr(sorted(remembered.items())) == repr(sorted(evaluated.items()))


def test_only_functions_of_their_arguments_are_remembered(monkeypatch):
    wrapped = []
    original = compiler._remembered

    def spy(body):
        wrapped.append(body)
        return original(body)

    monkeypatch.setattr(compiler, "_remembered", spy)
    parse_grammar(RULES, "pure.cga").build(lot=(12, 8))
    # tiles, scaled, countDown and inverse read only their arguments; withAttr, withShape
    # and withRandom do not
    assert len(wrapped) == 4


def test_a_zero_argument_is_not_taken_for_the_other():
    grammar = parse_grammar(
        'inverse(x) = 1 / x\nLot --> A(0) A(-0)\nA(z) --> report("v", inverse(z)) X.',
        "zero.cga",
    )
    reports = grammar.build(lot=(12, 8)).metadata["reports"]
    assert sorted(reports["v"]) == [float("-inf"), float("inf")]

"""OperationCalls: each operation with a node of its own is built by its own builder."""

import pytest

from shapegen.grammar import ast
from shapegen.grammar.names import OPERATIONS
from shapegen.grammar.operation_calls import _DEDICATED
from shapegen.grammar.parser import parse_with_problems

CALLS = {
    "extrude": ("extrude(2)", ast.Extrude),
    "split": ("split(x) { 1 : A }", ast.Split),
    "comp": ("comp(f) { top : A }", ast.Comp),
    "t": ("t(0, 1, 0)", ast.Translate),
    "s": ("s(1, 1, 1)", ast.Scale),
    "r": ("r(0, 90, 0)", ast.Rotate),
    "center": ("center(xz)", ast.Center),
    "label": ('label("a")', ast.Label),
    "set": ("set(h, 2)", ast.Set),
    "i": ('i("box")', ast.Insert),
    "print": ("print(1)", ast.Print),
    "report": ('report("k", 1)', ast.Report),
}


def test_every_operation_with_a_node_of_its_own_has_a_builder():
    assert set(_DEDICATED) == set(OPERATIONS) == set(CALLS)


@pytest.mark.parametrize("name", sorted(CALLS))
def test_a_call_becomes_its_operations_node(name):
    call, node_class = CALLS[name]
    grammar, problems = parse_with_problems(f"attr h = 1\nLot --> {call}")
    assert problems == []
    (item,) = grammar.rule("Lot").body.items
    assert type(item) is node_class

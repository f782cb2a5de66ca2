"""Hand-made CGA operations for the engine's tests: AST nodes built in code, compiled on a real
program and run on one shape, so a test does not depend on how the parser spells a call.
"""

from __future__ import annotations

from pathlib import Path

import shapegen
from shapegen.engine.derivation.state import Derivation, root_state
from shapegen.engine.operations.cga import register_all
from shapegen.engine.shapes.shape import FACE, Shape, lot_scope
from shapegen.grammar import ast

# Operations register when a rule first names them; the nodes here are made in code, so every
# operation is registered, whether a rule named it yet or not.
register_all()

SIMPLE_RULE_DATASET = (
    Path(__file__).resolve().parent
    / "data"
    / "cga-corpus"
    / "caseStudy_Tensorflow_simpleRuleDataset__de221ff8"
    / "rules"
    / "simpleRuleDataset.cga"
)
"""A corpus rule with setbacks, innerRectangle and comp selectors, as its package ships it."""


def operations_program():
    """The operation compiler of a small real program (a module fixture's value)."""
    return shapegen.parse_grammar("@StartRule\nLot --> extrude(1) A").program.operations


def lot_state(program, width: float, depth: float):
    """The start state of a derivation on a flat ``width`` x ``depth`` lot."""
    run = Derivation(program, seed=0)
    return root_state(run, Shape(lot_scope(width, depth), FACE, 1), {}, ())


def shape_state(program, shape: Shape):
    """The start state of a derivation whose start shape is ``shape``."""
    run = Derivation(program, seed=0)
    run.start_shape = shape
    return root_state(run, shape, {}, ())


def node(value, text=ast.Name):
    """``value`` as an expression node: a bool, a number, ``"@name"`` (a bare name),
    ``"scope.sx"`` (a shape attribute, where plain text is a name) or plain text as ``text``
    (``ast.Name`` or ``ast.String``); a node is kept as it is."""
    if isinstance(value, bool):
        return ast.Boolean(value)
    if isinstance(value, int | float):
        return ast.Number(float(value))
    if not isinstance(value, str):
        return value
    if value.startswith("@"):
        return ast.Name(value[1:])
    if text is ast.Name and "." in value:
        obj, field = value.split(".")
        return ast.ShapeAttribute(obj, field)
    return text(value)


def operation(name, *values, kinds=None, branches=(), text=ast.Name):
    """The operation ``name(values...)`` with each argument of its kind (``"plain"`` unless
    said) and a block of empty branches ``(key, merge)``."""
    kinds = kinds or ["plain"] * len(values)
    arguments = tuple(
        ast.OperationArgument(kind, node(v, text)) for kind, v in zip(kinds, values, strict=True)
    )
    block = tuple(
        ast.OperationBranch(node(key, text), "absolute", ast.Sequence(()), merge)
        for key, merge in branches
    )
    return ast.Operation(name, arguments, block)

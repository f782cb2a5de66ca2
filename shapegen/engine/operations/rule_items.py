"""The items of a rule body that make the tree and its records: a successor (``A``), ``NIL``,
``[ ... ]``, ``set``, ``label``, ``print`` and ``report``.

Each is registered in :mod:`~shapegen.engine.operations.registry` by its one-shape form and,
for a successor without arguments, ``set`` of an attr and ``report``, its batch form beside it
(a city's lots standing at one rule: :class:`~shapegen.engine.batch.lots.ShapeBatch`).
"""

from __future__ import annotations

__all__ = ["compile_report", "compile_set", "compile_successor"]

from shapegen.engine.expressions.compiler import format_value
from shapegen.engine.operations.registry import (
    Unsupported,
    batch_form,
    is_column,
    operation,
    value_kind,
)
from shapegen.engine.operations.shape_writes import WRITABLE, compile_shape_write
from shapegen.errors import did_you_mean
from shapegen.grammar import ast
from shapegen.grammar.names import RESERVED_ATTRIBUTES, SETTABLE_SHAPE_ATTRIBUTES


@operation("successor", nodes=(ast.Successor,))
def compile_successor(program, node: ast.Successor, params):
    """``A`` or ``A(args)``: a new shape below this one, derived by rule ``A`` (a leaf for
    ``A.``); its arguments are evaluated, and draw, before its stream is begun."""
    rule = None if node.leaf else program.rules.get((node.name, len(node.args)))
    # CityEngine's compiler warns of a rule of no such arity and leaves the shape a leaf (the
    # load check's warning); shapegen's .grammar files refuse it
    if rule is None and not node.leaf and node.name in program.arities and not program.cga_dialect:
        counts = " or ".join(str(n) for n in sorted(program.arities[node.name]))
        raise program.error(
            node, f"rule {node.name!r} takes {counts} parameters, got {len(node.args)}"
        )
    arguments = tuple(program.expressions.compile(a, params) for a in node.args)
    name = node.name

    def successor(state, args, out):
        values = tuple(a(args, state) for a in arguments)
        child = state.run.child(state, state.shape, node, name)
        out.append((child, rule, values))
        return True

    return successor


@batch_form("successor")
def batch_successor(program, node: ast.Successor, params):
    """A successor without arguments of every shape of the batch: one new shape per lot, its
    stream begun from its parent's as the one-shape derivation begins it."""
    if node.args:
        raise Unsupported("a successor with arguments")
    rule = None if node.leaf else program.rules.get((node.name, 0))
    if rule is None and not node.leaf and node.name in program.arities:
        raise Unsupported("a successor of another arity")

    def successor_batch(batch, out):
        out.append((batch.successor(), rule))
        return True

    return successor_batch


@operation("NIL", nodes=(ast.Nil,))
def compile_nil(program, node: ast.Nil, params):
    """``NIL`` (op_nil): the current shape is deleted, so it leaves no leaf. The operations
    after it still run: CityEngine's runtime counts a ``report`` written after ``NIL``
    (envelope2002's "total report for optimisation"). Inside ``[ ]`` it deletes the pushed
    copy only (op_pushpop: ``]`` deletes that copy anyway)."""

    def delete(state, args, out):
        state.deleted = True
        return True

    return delete


@operation("push", nodes=(ast.Push,))
def compile_push(program, node: ast.Push, params):
    """``[ ... ]`` (op_pushpop): the body on a copy of the shape; the shape goes on as it was."""
    body = program.body(node.body, params)

    def push(state, args, out):
        body(state.copy(), args, out)
        return True

    return push


@operation(
    "set",
    nodes=(ast.Set,),
    partial="seedian and scope.elevation cannot be set (refused when the file loads); scope.* "
    "and pivot.* are set in .cga rules",
)
def compile_set(program, node: ast.Set, params):
    """``set(name, value)`` of an attr (or a reserved one), a ``material.*`` attribute or, in
    ``.cga``, a writable shape attribute (``scope.*``, ``pivot.*``)."""
    attribute = node.attribute
    if attribute.startswith("material."):
        from shapegen.engine.operations.cga.appearance import compile_material_set

        return compile_material_set(program, node, params)
    if attribute in program.const_names:
        raise program.error(node, f"set() changes attrs; {attribute!r} is a const")
    if program.cga_dialect and attribute in WRITABLE and attribute not in program.attr_names:
        return compile_shape_write(program, node, params)
    if (
        attribute not in program.attr_names
        and attribute not in RESERVED_ATTRIBUTES
        and attribute not in SETTABLE_SHAPE_ATTRIBUTES
    ):
        known = sorted(set(program.attr_names) | set(RESERVED_ATTRIBUTES))
        hint = did_you_mean(attribute, known, parenthesised=True)
        raise program.error(node, f"set() of unknown attribute {attribute!r}{hint}")
    value = program.expressions.compile(node.value, params)

    def set_op(state, args, out):
        state.attrs = {**state.attrs, attribute: value(args, state)}
        return True

    return set_op


@batch_form("set")
def batch_set(program, node: ast.Set, params):
    """``set`` of an attr on every shape of the batch: one value shared, or a column; of the
    attr's own type."""
    attribute = node.attribute
    if attribute not in program.attr_names:
        raise Unsupported(f"set() of {attribute}")

    def set_batch(batch, out):
        value = batch.value(node.value)
        if value_kind(value) is not value_kind(batch.attrs[attribute]):
            raise Unsupported("set() of a value of another type")
        batch.attrs = {**batch.attrs, attribute: value}
        return True

    return set_batch


@operation("label", nodes=(ast.Label,))
def compile_label(program, node: ast.Label, params):
    """``label(name)``: the shape's label, read by the occlusion queries."""
    name = program.expressions.compile(node.name, params)

    def label_op(state, args, out):
        text = format_value(name(args, state))
        if text not in state.labels:
            state.labels = state.labels + (text,)
        if state.run.occlusion is not None:  # None while attrs are evaluated
            state.run.occlusion.label(state, text)
        return True

    return label_op


@operation("print", nodes=(ast.Print,))
def compile_print(program, node: ast.Print, params):
    """``print(values)``: the values written on one line."""
    values = [program.expressions.compile(v, params) for v in node.values]

    def print_op(state, args, out):
        print(" ".join(format_value(v(args, state)) for v in values))
        return True

    return print_op


@operation("report", nodes=(ast.Report,))
def compile_report(program, node: ast.Report, params):
    """``report(key, value)``: the value added to the derivation's reports under ``key``."""
    key_of = program.expressions.compile(node.key, params)
    value_of = program.expressions.compile(node.value, params)

    def report_op(state, args, out):
        key = format_value(key_of(args, state))
        state.run.reports.setdefault(key, []).append(value_of(args, state))
        return True

    return report_op


@batch_form("report")
def batch_report(program, node: ast.Report, params):
    """``report`` of every shape of the batch: one key, a value shared or a column."""

    def report_batch(batch, out):
        key = batch.value(node.key)
        if is_column(key):
            raise Unsupported("a report key that differs between shapes")
        batch.report(format_value(key), batch.value(node.value))
        return True

    return report_batch

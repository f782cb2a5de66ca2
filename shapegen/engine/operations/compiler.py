"""Compilers of rule bodies and shape operations: each turns an AST node into a closure.

A compiled operation is called as ``op(state, args, out)``
(:data:`~shapegen.engine.derivation.state.Operation`): it changes the shape ``state``, appends
the successors it creates to ``out`` and returns False when the shape was replaced by others (a
split, a comp...). :class:`OperationCompiler` compiles them for one grammar; the compiler of an
AST node type ``T`` is its method ``_op_T``, and those of CityEngine's operations without a node
of their own (:mod:`shapegen.engine.operations.cga`) are handed the compiler itself.
"""

from __future__ import annotations

__all__ = ["OperationCompiler"]

from collections.abc import Callable, Mapping

from shapegen.engine.derivation.cga_errors import carrying_on
from shapegen.engine.derivation.finite import checked_operation, finite_parameter
from shapegen.engine.derivation.random_streams import choice
from shapegen.engine.derivation.state import Operation, format_chain
from shapegen.engine.expressions.compiler import ExpressionCompiler, format_value, type_name
from shapegen.engine.operations.hole_guard import keeps_holes, refusing_holes
from shapegen.engine.operations.shape_writes import WRITABLE, compile_shape_write
from shapegen.engine.operations.template_primitives import INSERT, compile_insert
from shapegen.engine.shapes.auto_tags import extruded
from shapegen.engine.shapes.shape import (
    FACE,
    MASS,
    axis_index,
    center,
    extrude_shape,
    rotate,
    split_pieces,
    translate,
)
from shapegen.engine.shapes.split import (
    PieceLimitError,
    SplitPart,
    SplitRepeat,
    resolve_split,
)
from shapegen.errors import GrammarError, OperationError, did_you_mean
from shapegen.grammar import ast
from shapegen.grammar.names import RESERVED_ATTRIBUTES, SETTABLE_SHAPE_ATTRIBUTES


class OperationCompiler:
    """The compilers of rule bodies, their items and the operations' arguments, for one grammar.

    Parameters
    ----------
    grammar
        The parsed file: its dialect and its file name (where assets are searched from).
    expressions
        The grammar's expression compiler (arguments, conditions, values).
    rules
        ``(name, arity) -> rule`` of the grammar, read when a successor is compiled; a rule's
        ``body`` is read only while deriving, so the rules' bodies may be compiled after.
    """

    def __init__(
        self,
        grammar: ast.RuleFile,
        expressions: ExpressionCompiler,
        rules: Mapping[tuple[str, int], object],
    ):
        self.grammar = grammar
        self.expressions = expressions
        self.rules = rules
        self.arities: dict[str, list[int]] = {}
        for name, arity in rules:
            self.arities.setdefault(name, []).append(arity)
        self.attr_names = frozenset(a.name for a in grammar.attrs)
        self.const_names = frozenset(c.name for c in grammar.consts)
        # CityEngine rule files (.cga) get CityEngine's semantics: its scope after extruding a
        # comp face, its repeat counts, and its leniency (CGA errors carried on past).
        self.cga_dialect = grammar.dialect == "cga"

    def error(self, node, message: str) -> GrammarError:
        """The error at ``node`` of the grammar (file, line, column and caret)."""
        return self.expressions.error(node, message)

    def body(self, node: ast.Body, params: dict[str, int]) -> Operation:
        """The operation of a rule body (a sequence, a case or a stochastic choice) whose
        parameters are ``params`` (name -> index in the arguments)."""
        if isinstance(node, ast.Sequence):
            items = tuple(self._item(item, params) for item in node.items)

            def sequence(state, args, out):
                for item in items:
                    if not item(state, args, out):
                        return False
                return True

            return sequence
        if isinstance(node, ast.ConditionalBody):
            branches = [
                (self.expressions.compile(b.condition, params), self.body(b.body, params), b)
                for b in node.branches
            ]
            otherwise = self.body(node.otherwise, params)
            error = self.error

            def conditional(state, args, out):
                for condition, body, branch in branches:
                    test = condition(args, state)
                    if type(test) is not bool:
                        raise error(
                            branch, f"a case condition must be a boolean, got a {type_name(test)}"
                        )
                    if test:
                        return body(state, args, out)
                return otherwise(state, args, out)

            return conditional
        if isinstance(node, ast.StochasticBody):
            fractions = tuple(float(b.percent) / 100.0 for b in node.branches)
            bodies = (*(self.body(b.body, params) for b in node.branches),
                      self.body(node.otherwise, params))  # fmt: skip

            def stochastic(state, args, out):
                return bodies[choice(state.random, fractions)](state, args, out)

            return stochastic
        raise self.error(node, f"unsupported rule body {type(node).__name__}")

    def _item(self, node, params: dict[str, int]) -> Operation:
        method = getattr(self, "_op_" + type(node).__name__, None)
        if method is None:
            raise self.error(node, f"unsupported operation {type(node).__name__}")
        operation = checked_operation(
            self, node, method(node, params)
        )  # engine/derivation/finite.py
        if not keeps_holes(node):
            operation = refusing_holes(operation, node, self)
        if self.cga_dialect and not isinstance(node, _CANNOT_FAIL):
            return carrying_on(operation, node, self)  # CityEngine records a CGA error
        return operation

    def operation_error(self, node, message: str) -> OperationError:
        """The error of an operation's bad argument or degenerate geometry met while deriving:
        a CGA error that the shape carries on past in a ``.cga`` file
        (engine/derivation/cga_errors.py), an error in a ``.grammar`` file."""
        error = self.error(node, message)
        return OperationError(message, error.location, error.source)

    def number(self, node, expression, params, what: str):
        """A compiled expression that must give a finite number (``what`` names it in the
        error: ``"extrude height"``)."""
        compiled = self.expressions.compile(expression, params)
        error = self.error

        def number(args, state):
            value = compiled(args, state)
            if type(value) is not float:
                raise error(node, f"{what} must be a number, got a {type_name(value)}")
            return finite_parameter(self, node, state, value, what)

        return number

    def _op_Successor(self, node: ast.Successor, params) -> Operation:
        rule = None if node.leaf else self.rules.get((node.name, len(node.args)))
        # CityEngine's compiler warns of a rule of no such arity and leaves the shape a leaf
        # (the load check's warning); shapegen's .grammar files refuse it
        if rule is None and not node.leaf and node.name in self.arities and not self.cga_dialect:
            counts = " or ".join(str(n) for n in sorted(self.arities[node.name]))
            raise self.error(
                node, f"rule {node.name!r} takes {counts} parameters, got {len(node.args)}"
            )
        arguments = tuple(self.expressions.compile(a, params) for a in node.args)
        name = node.name

        def successor(state, args, out):
            values = tuple(a(args, state) for a in arguments)
            child = state.run.child(state, state.shape, node, name)
            out.append((child, rule, values))
            return True

        return successor

    def _op_Nil(self, node, params) -> Operation:
        """``NIL`` (op_nil): the current shape is deleted, so it leaves no leaf. The operations
        after it still run: CityEngine's runtime counts a ``report`` written after ``NIL``
        (envelope2002's "total report for optimisation"). Inside ``[ ]`` it deletes the pushed
        copy only (op_pushpop: ``]`` deletes that copy anyway)."""

        def delete(state, args, out):
            state.deleted = True
            return True

        return delete

    def _op_Push(self, node: ast.Push, params) -> Operation:
        body = self.body(node.body, params)

        def push(state, args, out):
            body(state.copy(), args, out)
            return True

        return push

    def _op_Extrude(self, node: ast.Extrude, params) -> Operation:
        height = self.number(node, node.height, params, "extrude height")
        error, operation_error = self.error, self.operation_error
        cityengine = self.cga_dialect

        def extrude_op(state, args, out):
            shape = state.shape
            if cityengine and shape.kind == "edge":  # an edge of comp(e|fe): a face
                from shapegen.engine.operations.cga.extrusion import edge_extrusion

                state.shape = extruded(state, shape, edge_extrusion(shape, height(args, state)))
                return True
            if shape.kind != FACE and not (cityengine and shape.kind == MASS):
                raise error(
                    node,
                    "extrude() needs a flat shape (the lot or a comp(f) face); "
                    "this shape is already 3D",
                )
            try:
                state.shape = extruded(
                    state, shape, extrude_shape(shape, height(args, state), cityengine)
                )
            except ValueError as exc:
                raise operation_error(node, str(exc)) from None
            return True

        return extrude_op

    def _split_items(self, group: ast.SplitGroup, params) -> Callable:
        """A closure giving the evaluated split items of ``group`` (nested groups inline)."""
        builders = []
        for part in group.parts:
            if isinstance(part, ast.SplitGroup):
                inner = self._split_items(part, params)
                if part.repeat:
                    builders.append(
                        lambda args, state, inner=inner: [SplitRepeat(tuple(inner(args, state)))]
                    )
                else:
                    builders.append(inner)
                continue
            size = self.number(part, part.size, params, "a split size")
            key = (self.body(part.body, params), part)
            mode = part.mode
            builders.append(
                lambda args, state, size=size, key=key, mode=mode: [
                    SplitPart(size(args, state), mode, key)
                ]
            )

        def items(args, state):
            out = []
            for build in builders:
                out.extend(build(args, state))
            return out

        return items

    def _op_Split(self, node: ast.Split, params) -> Operation:
        axis = axis_index(node.axis)
        items = self._split_items(node.group, params)
        repeat = node.group.repeat
        error, operation_error = self.error, self.operation_error
        best_counts = self.cga_dialect  # CityEngine's repeat counts in .cga files
        where = node.location
        adjust = node.adjust  # noAdjust: the pieces keep the scope slices (op_split)

        def split_op(state, args, out):
            shape = state.shape
            if shape.kind == INSERT:
                raise error(
                    node,
                    "split() cannot cut an inserted primitive; split first, then "
                    "insert into the pieces",
                )
            pattern = items(args, state)
            if repeat:
                pattern = SplitRepeat(tuple(pattern))
            run = state.run
            extent = shape.scope.d[axis]
            scale = 1.0
            if node.texture is not None:
                run.warn(
                    f"{where}: split({'u' if axis == 0 else 'v'}, {node.texture}) runs along "
                    f"the scope's {'x' if axis == 0 else 'y'} axis: shapegen keeps no texture "
                    "coordinates"
                    + (" (uv taken as 0..1 over the scope)" if node.texture == "uvSpace" else "")
                )
                if node.texture == "uvSpace":
                    extent, scale = 1.0, extent
            try:
                pieces = resolve_split(
                    extent,
                    pattern,
                    max_pieces=max(run.max_shapes - run.shape_count, 0) + 1,
                    best_counts=best_counts,
                )
            except PieceLimitError:
                raise error(
                    node,
                    f"the split creates more than {run.max_shapes} shapes "
                    f"(max_shapes). Chain of rules: "
                    f"{format_chain(state.rule_path)} "
                    f"(raise it with Grammar.build(max_shapes=...) or "
                    f"shapegen.limits.work_limits(max_shapes=...))",
                ) from None
            except ValueError as exc:
                raise operation_error(node, str(exc)) from None
            spans = [(piece.start * scale, piece.size * scale) for piece in pieces]
            cuts, within = split_pieces(shape, axis, spans, run.limits.max_coordinate, adjust)
            made = [  # CityEngine drops pieces with no geometry
                (piece.key, cut) for piece, cut in zip(pieces, cuts, strict=True) if cut is not None
            ]
            total = len(made)
            for index, ((body, part), cut) in enumerate(made):
                child = run.child(state, cut, part, within_bounds=within)
                child.split_index = index
                child.split_total = total
                if body(child, args, out) and child.is_leaf():
                    out.append((child, None, ()))
            return True

        return split_op

    def _op_Comp(self, node: ast.Comp, params) -> Operation:
        from shapegen.engine.operations.cga.topology import comp_operation

        for branch in node.branches:
            if branch.connected and node.kind != "f":
                raise self.error(
                    branch,
                    f"comp's '=:' operator (a shape per connected set of components) is "
                    f"supported by shapegen for faces, not comp({node.kind})",
                )
        branches = [
            (branch.selector, branch.merge, self.body(branch.body, params), branch)
            for branch in node.branches
        ]
        return comp_operation(self, node, node.kind, branches, params)

    def _coordinates(self, node, coordinates, params, what: str):
        compiled = [
            (self.number(node, c.value, params, what), c.relative, k)
            for k, c in enumerate(coordinates)
        ]

        def values(args, state):
            size = state.shape.scope.d  # floats: an overflow is inf, not a warning
            return [
                value(args, state) * size[k] if relative else value(args, state)
                for value, relative, k in compiled
            ]

        return values

    def _op_Translate(self, node: ast.Translate, params) -> Operation:
        values = self._coordinates(node, (node.x, node.y, node.z), params, "a t() offset")

        def translate_op(state, args, out):
            state.shape = state.shape.with_scope(translate(state.shape.scope, values(args, state)))
            return True

        return translate_op

    def _op_Scale(self, node: ast.Scale, params) -> Operation:
        values = self._coordinates(node, (node.x, node.y, node.z), params, "an s() size")
        operation_error = self.operation_error

        def scale_op(state, args, out):
            try:
                state.shape = state.shape.resized(values(args, state))
            except ValueError as exc:
                raise operation_error(node, str(exc)) from None
            return True

        return scale_op

    def _op_Rotate(self, node: ast.Rotate, params) -> Operation:
        angles = [self.number(node, e, params, "an r() angle") for e in (node.x, node.y, node.z)]
        about_center = node.pivot == "center"

        def rotate_op(state, args, out):
            values = [angle(args, state) for angle in angles]
            state.shape = state.shape.with_scope(rotate(state.shape.scope, values, about_center))
            return True

        return rotate_op

    def _op_Center(self, node: ast.Center, params) -> Operation:
        axes = node.axes
        if not axes or any(a not in "xyz" for a in axes):
            raise self.error(node, f"center() takes x, y, z, xy, xz, yz or xyz, got {axes!r}")

        def center_op(state, args, out):
            scope = center(state.shape.scope, state.initial_scope, axes)
            state.shape = state.shape.with_scope(scope)
            return True

        return center_op

    def _op_Label(self, node: ast.Label, params) -> Operation:
        name = self.expressions.compile(node.name, params)

        def label_op(state, args, out):
            text = format_value(name(args, state))
            if text not in state.labels:
                state.labels = state.labels + (text,)
            if state.run.occlusion is not None:  # None while attrs are evaluated
                state.run.occlusion.label(state, text)
            return True

        return label_op

    def _op_Set(self, node: ast.Set, params) -> Operation:
        attribute = node.attribute
        if attribute.startswith("material."):
            from shapegen.engine.operations.cga import appearance

            compile_material_set = getattr(appearance, "compile_material_set", None)
            if compile_material_set is not None:
                return compile_material_set(self, node, params)
        if attribute in self.const_names:
            raise self.error(node, f"set() changes attrs; {attribute!r} is a const")
        if self.cga_dialect and attribute in WRITABLE and attribute not in self.attr_names:
            return compile_shape_write(self, node, params)
        if (
            attribute not in self.attr_names
            and attribute not in RESERVED_ATTRIBUTES
            and attribute not in SETTABLE_SHAPE_ATTRIBUTES
        ):
            known = sorted(set(self.attr_names) | set(RESERVED_ATTRIBUTES))
            hint = did_you_mean(attribute, known, parenthesised=True)
            raise self.error(node, f"set() of unknown attribute {attribute!r}{hint}")
        value = self.expressions.compile(node.value, params)

        def set_op(state, args, out):
            state.attrs = {**state.attrs, attribute: value(args, state)}
            return True

        return set_op

    def _op_Insert(self, node: ast.Insert, params) -> Operation:
        return compile_insert(self, node, params)

    def _op_Operation(self, node: ast.Operation, params) -> Operation:
        from shapegen.engine.operations.cga import compiler_for

        compiler = compiler_for(node.name)
        if compiler is None:
            raise self.error(node, f"the CGA operation {node.name!r} is not supported by shapegen")
        return compiler(self, node, params)

    def _op_Print(self, node: ast.Print, params) -> Operation:
        values = [self.expressions.compile(v, params) for v in node.values]

        def print_op(state, args, out):
            print(" ".join(format_value(v(args, state)) for v in values))
            return True

        return print_op

    def _op_Report(self, node: ast.Report, params) -> Operation:
        key_of = self.expressions.compile(node.key, params)
        value_of = self.expressions.compile(node.value, params)

        def report_op(state, args, out):
            key = format_value(key_of(args, state))
            state.run.reports.setdefault(key, []).append(value_of(args, state))
            return True

        return report_op


# Items that call no operation of their own: nothing to carry on past.
_CANNOT_FAIL = (ast.Successor, ast.Nil, ast.Push)


def _selector(name: str) -> str | int:
    return int(name) if name.isdigit() else name

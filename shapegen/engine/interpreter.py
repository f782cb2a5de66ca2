"""The interpreter: derives a block :class:`~shapegen.model.model.Model` from a grammar's AST.

:class:`Program` compiles a parsed grammar once (expressions and rule bodies become closures);
:meth:`Program.derive` runs the derivation for given attribute values, seed and lot.

The derivation is depth first, in the order successors appear in the rules, and uses an explicit
stack rather than recursion, so deep grammars need no Python recursion. Each 3D leaf shape (not
``NIL``, positive volume) becomes one block (a box filling its scope) or the blocks of its
inserted primitive, numbered ``b0``, ``b1``... in derivation order. Randomness (``rand``,
stochastic rules) comes from a generator seeded by the seed and the shape's position in the shape
tree, so a shape's draws do not depend on how many shapes were derived before it.
"""

from __future__ import annotations

__all__ = [
    "DEFAULT_LOT",
    "DEFAULT_MAX_DEPTH",
    "DEFAULT_MAX_SHAPES",
    "Program",
    "format_chain",
]

import difflib
import math
import random
from collections.abc import Callable, Mapping

import numpy as np

from shapegen.engine.expressions import ExpressionCompiler, format_value, type_name
from shapegen.engine.shape import (
    FACE,
    MASS,
    Shape,
    axis_index,
    center,
    extrude,
    face_scopes,
    flat_face,
    lot_scope,
    resize,
    rotate,
    select_faces,
    split_scope,
    translate,
)
from shapegen.engine.split import (
    PieceLimitError,
    SplitPart,
    SplitRepeat,
    resolve_split,
)
from shapegen.errors import GeometryError, GrammarError
from shapegen.grammar import ast
from shapegen.grammar.names import RESERVED_ATTRIBUTES
from shapegen.model.block import Block
from shapegen.model.model import Model
from shapegen.model.scope import Scope

DEFAULT_LOT = (10.0, 10.0)
"""Lot width and depth (m) when neither ``@Lot`` nor the caller gives one."""

DEFAULT_MAX_DEPTH = 500
"""Longest chain of rules from the start rule to a shape."""

DEFAULT_MAX_SHAPES = 1_000_000
"""Most shapes one derivation may create."""

INSERT = "insert"
_TOO_DEEP = "a user function calls itself too deeply (endless recursion?)"
_MIN_SIZE = 1e-9  # m; a leaf thinner than this along any axis has no volume and makes no block

# Vertices of the unit box in scope coordinates and its outward faces (see Block.box).
_UNIT_BOX = np.array(
    [[0, 0, 0], [1, 0, 0], [1, 0, 1], [0, 0, 1], [0, 1, 0], [1, 1, 0], [1, 1, 1], [0, 1, 1]],
    dtype=float,
)
_BOX_FACES = ((0, 1, 2, 3), (4, 7, 6, 5), (0, 4, 5, 1), (3, 2, 6, 7), (0, 3, 7, 4), (1, 5, 6, 2))


class _State:
    """One shape being derived, with everything the grammar can read or change on it."""

    __slots__ = (
        "run",
        "shape",
        "attrs",
        "labels",
        "split_index",
        "split_total",
        "comp_index",
        "comp_total",
        "path",
        "children",
        "rng",
        "rule_path",
        "depth",
        "initial_scope",
    )

    def random(self) -> float:
        """A uniform draw in [0, 1) from this shape's own generator."""
        rng = self.rng[0]
        if rng is None:
            key = f"{self.run.seed}/" + "/".join(str(k) for k in self.path)
            rng = self.rng[0] = random.Random(key)
        return rng.random()

    def copy(self) -> _State:
        """A copy for ``[ ... ]``: same place in the tree (children and draws are shared)."""
        other = _State.__new__(_State)
        for name in _State.__slots__:
            setattr(other, name, getattr(self, name))
        other.initial_scope = self.shape.scope
        return other


class _Derivation:
    """The mutable part of one derivation: seed, limits, the shape count and the reports."""

    def __init__(self, program: Program, seed: int, max_depth: int, max_shapes: int):
        self.program = program
        self.seed = int(seed)
        self.max_depth = max_depth
        self.max_shapes = max_shapes
        self.shape_count = 0
        self.reports: dict[str, list] = {}

    def child(self, parent: _State, shape: Shape, node, name: str | None = None) -> _State:
        """A new shape below ``parent``; ``name`` is the successor's name for a successor."""
        self.shape_count += 1
        if self.shape_count > self.max_shapes:
            chain = parent.rule_path + ((name,) if name else ())
            raise self.program.error(
                node,
                f"the derivation creates more than {self.max_shapes} shapes (max_shapes); "
                f"the grammar may be running away. Chain of rules: {format_chain(chain)}",
            )
        state = _State.__new__(_State)
        state.run = self
        state.shape = shape
        state.attrs = parent.attrs
        state.labels = parent.labels
        state.split_index = parent.split_index
        state.split_total = parent.split_total
        state.comp_index = parent.comp_index
        state.comp_total = parent.comp_total
        state.path = parent.path + (parent.children[0],)
        parent.children[0] += 1
        state.children = [0]
        state.rng = [None]
        state.initial_scope = shape.scope
        if name is None:
            state.rule_path = parent.rule_path
            state.depth = parent.depth
        else:
            state.rule_path = parent.rule_path + (name,)
            state.depth = parent.depth + 1
            if state.depth > self.max_depth:
                raise self.program.error(
                    node,
                    f"the derivation is deeper than {self.max_depth} rules (max_depth); the "
                    f"grammar may recurse without end. Chain of rules: "
                    f"{format_chain(state.rule_path)}",
                )
        return state


def format_chain(chain: tuple[str, ...], keep: int = 12) -> str:
    """``A -> B -> C x 40 -> D``: a rule chain with repeats folded and the middle elided."""
    runs: list[list] = []
    for name in chain:
        if runs and runs[-1][0] == name:
            runs[-1][1] += 1
        else:
            runs.append([name, 1])
    parts = [name if count == 1 else f"{name} x {count}" for name, count in runs]
    if len(parts) > keep:
        half = keep // 2
        parts = parts[:half] + [f"... ({len(parts) - keep} more) ..."] + parts[-half:]
    return " -> ".join(parts)


class _Rule:
    __slots__ = ("name", "arity", "body", "node")

    def __init__(self, node: ast.Rule):
        self.name = node.name
        self.arity = len(node.params)
        self.body = None
        self.node = node


# An operation: op(state, args, out) -> False when the shape was deleted (NIL), else True.
Operation = Callable[[_State, tuple, list], bool]


class Program:
    """A compiled grammar, ready to derive models.

    Parameters
    ----------
    grammar
        The parsed file (:func:`shapegen.grammar.parse`).
    """

    def __init__(self, grammar: ast.Grammar):
        self.grammar = grammar
        self.attr_nodes = {a.name: a for a in grammar.attrs}
        self.const_nodes = {c.name: c for c in grammar.consts}
        global_names = set(self.attr_nodes) | set(self.const_nodes) | set(RESERVED_ATTRIBUTES)
        self.expressions = ExpressionCompiler(grammar, global_names)
        self.expressions.compile_functions()
        self.definitions = {
            name: self.expressions.compile(node.value, {})
            for name, node in {**self.attr_nodes, **self.const_nodes}.items()
        }
        # Rules by (name, arity): CGA overloads a rule name by its number of parameters.
        self.rules = {(rule.name, len(rule.params)): _Rule(rule) for rule in grammar.rules}
        self.arities: dict[str, list[int]] = {}
        for name, arity in self.rules:
            self.arities.setdefault(name, []).append(arity)
        for rule in self.rules.values():
            params = {p.name: k for k, p in enumerate(rule.node.params)}
            rule.body = self._body(rule.node.body, params)
        self.start = grammar.start_rule
        if self.start is None:
            raise GrammarError(f"{grammar.filename}: the grammar has no rules")
        if self.start.params:
            raise self.error(
                self.start, f"the start rule {self.start.name!r} cannot take parameters"
            )
        self.structure = _checked_structure(self.start, self.error)

    def error(self, node, message: str) -> GrammarError:
        return self.expressions.error(node, message)

    # ------------------------------------------------------------------ attributes
    def initial_values(
        self, overrides: Mapping[str, object] | None, seed: int, lot: Scope
    ) -> dict[str, object]:
        """Values of every attr and const (with ``overrides``) and of the reserved attrs."""
        overrides = dict(overrides or {})
        for name in overrides:
            if name in self.attr_nodes or name in RESERVED_ATTRIBUTES:
                continue
            if name in self.const_nodes:
                raise GrammarError(f"{name!r} is a const and cannot be set; only attrs can")
            known = sorted(self.attr_nodes)
            close = difflib.get_close_matches(name, known, n=1)
            hint = f" (did you mean {close[0]!r}?)" if close else ""
            listing = ", ".join(known) if known else "none"
            raise GrammarError(f"unknown attribute {name!r}{hint}; attributes: {listing}")
        run = _Derivation(self, seed, DEFAULT_MAX_DEPTH, DEFAULT_MAX_SHAPES)
        values: dict[str, object] = {}
        resolving: list[str] = []

        def resolve(name: str) -> object:
            if name in values:
                return values[name]
            if name in resolving:
                cycle = " -> ".join(resolving[resolving.index(name) :] + [name])
                node = self.attr_nodes.get(name) or self.const_nodes.get(name)
                raise self.error(
                    node, f"attributes and constants refer to each other in a cycle: {cycle}"
                )
            resolving.append(name)
            state = _root_state(run, Shape(lot, FACE, 1), lazy, ("attr", name))
            if name in self.definitions:
                value = self.definitions[name]((), state)
            else:
                value = RESERVED_ATTRIBUTES[name]
                value = float(value) if type(value) in (int, float) else value
            if name in overrides:
                value = _coerce(name, overrides[name], value)
            resolving.pop()
            values[name] = value
            return value

        lazy = _LazyValues(resolve)
        try:
            for name in (*self.attr_nodes, *self.const_nodes, *RESERVED_ATTRIBUTES):
                resolve(name)
        except RecursionError:
            raise GrammarError(_TOO_DEEP) from None
        return values

    def free_parameters(
        self, values: Mapping[str, object], lot: Scope, *, only_free: bool = True
    ) -> dict[str, dict]:
        """``name -> {value, min, max}`` for the ``@Free`` attrs (bounds from ``@Range``), or,
        with ``only_free=False``, for every attr that has a ``@Range``."""
        run = _Derivation(self, 0, DEFAULT_MAX_DEPTH, DEFAULT_MAX_SHAPES)
        state = _root_state(run, Shape(lot, FACE, 1), dict(values), ("free",))
        out = {}
        for name, node in self.attr_nodes.items():
            if only_free and not node.free:
                continue
            bounds = node.range
            if bounds is None and not only_free:
                continue
            if bounds is None:
                raise self.error(node, f"@Free attr {name!r} needs a @Range(min, max)")
            low, high = (self.expressions.compile(b, {})((), state) for b in bounds)
            for bound in (low, high):
                if type(bound) is not float:
                    raise self.error(
                        node, f"@Range of {name!r} needs numbers, got a {type_name(bound)}"
                    )
            out[name] = {"value": values[name], "min": low, "max": high}
        return out

    def lot_size(self, values: Mapping[str, object]) -> tuple[float, float]:
        """The start rule's ``@Lot(width, depth)`` (m), else :data:`DEFAULT_LOT`."""
        annotation = self.start.annotation("Lot")
        if annotation is None:
            return DEFAULT_LOT
        run = _Derivation(self, 0, DEFAULT_MAX_DEPTH, DEFAULT_MAX_SHAPES)
        state = _root_state(run, Shape(lot_scope(*DEFAULT_LOT), FACE, 1), dict(values), ("lot",))
        size = []
        for k, keyword in enumerate(("width", "depth")):
            node = annotation.argument(keyword, k)
            value = self.expressions.compile(node, {})((), state) if node is not None else None
            if type(value) is not float or not math.isfinite(value) or value <= 0:
                raise self.error(
                    annotation, f"@Lot needs a positive width and depth in metres, got {value!r}"
                )
            size.append(value)
        return size[0], size[1]

    def structure_arguments(self, values: Mapping[str, object], lot: Scope) -> dict[str, object]:
        """The keyword arguments of the start rule's ``@Structure(...)``, evaluated with the attr
        ``values`` (empty without one): what the structure reads of this design."""
        annotation = self.start.annotation("Structure")
        if annotation is None or not annotation.keywords:
            return {}
        run = _Derivation(self, 0, DEFAULT_MAX_DEPTH, DEFAULT_MAX_SHAPES)
        state = _root_state(run, Shape(lot, FACE, 1), dict(values), ("structure",))
        return {
            keyword.name: self.expressions.compile(keyword.value, {})((), state)
            for keyword in annotation.keywords
        }

    # ------------------------------------------------------------------ derivation
    def derive(
        self,
        attrs: Mapping[str, object] | None = None,
        seed: int = 0,
        lot: tuple[float, float] | None = None,
        max_depth: int = DEFAULT_MAX_DEPTH,
        max_shapes: int = DEFAULT_MAX_SHAPES,
    ) -> Model:
        """Derive the block model; see :meth:`shapegen.engine.grammar_api.Grammar.build`."""
        if lot is None:
            defaults = self.initial_values(attrs, seed, lot_scope(*DEFAULT_LOT))
            lot = self.lot_size(defaults)
        try:
            width, depth = (float(v) for v in lot)
            start_scope = lot_scope(width, depth)
        except (TypeError, ValueError) as exc:
            raise GrammarError(f"lot: {exc}") from None
        values = self.initial_values(attrs, seed, start_scope)
        run = _Derivation(self, seed, max_depth, max_shapes)
        root = _root_state(run, Shape(start_scope, FACE, 1), values, ())
        root.rule_path = (self.start.name,)
        leaves: list[_State] = []
        stack: list[tuple] = [(root, self.rules[(self.start.name, 0)], ())]
        try:
            while stack:
                state, rule, args = stack.pop()
                if rule is None:
                    leaves.append(state)
                    continue
                out: list[tuple] = []
                if rule.body(state, args, out) and state.children[0] == 0:
                    out.append((state, None, ()))
                stack.extend(reversed(out))
        except RecursionError:
            raise GrammarError(_TOO_DEEP) from None
        blocks = self._blocks(leaves)
        metadata = {
            "grammar": self.grammar.filename,
            "seed": int(seed),
            "lot": [width, depth],
            "attrs": {name: values[name] for name in self.attr_nodes},
            "free_parameters": self.free_parameters(values, start_scope),
            "reports": {k: v[0] if len(v) == 1 else v for k, v in run.reports.items()},
            "structure": {
                "name": self.structure,
                "arguments": self.structure_arguments(values, start_scope),
            },
        }
        return Model(blocks, metadata=metadata)

    def _blocks(self, leaves: list[_State]) -> list[Block]:
        boxes = [s for s in leaves if s.shape.kind == MASS and s.shape.scope.size.min() > _MIN_SIZE]
        corners = {}
        if boxes:
            origins = np.array([s.shape.scope.origin for s in boxes])
            rotations = np.array([s.shape.scope.rotation for s in boxes])
            sizes = np.array([s.shape.scope.size for s in boxes])
            local = _UNIT_BOX[None, :, :] * sizes[:, None, :]
            world = origins[:, None, :] + np.einsum("nij,nkj->nki", rotations, local)
            corners = {id(s): world[k] for k, s in enumerate(boxes)}
        blocks: list[Block] = []
        for state in leaves:
            kind = state.shape.kind
            if kind == MASS:
                vertices = corners.get(id(state))
                if vertices is None:
                    continue
                density, structural, fixed = self._properties(state)
                blocks.append(
                    Block(
                        vertices,
                        _BOX_FACES,
                        density=density,
                        id=f"b{len(blocks)}",
                        tags=state.labels,
                        structural=structural,
                        fixed=fixed,
                        rule_path=state.rule_path,
                    )
                )
            elif kind == INSERT:
                name, params, node = state.shape.insert
                scope = state.shape.scope
                try:
                    pieces = _insert(name, scope, params)
                except GeometryError as exc:
                    raise self.error(node, f"i({name!r}): {exc}") from None
                density, structural, fixed = self._properties(state)
                for piece in pieces:
                    piece.density = density
                    piece.structural = structural
                    piece.fixed = fixed
                    piece.id = f"b{len(blocks)}"
                    piece.tags = state.labels + tuple(
                        t for t in piece.tags if t not in state.labels
                    )
                    piece.rule_path = state.rule_path
                    blocks.append(piece)
        return blocks

    def _properties(self, state: _State) -> tuple[float, bool, bool]:
        attrs = state.attrs
        density, structural, fixed = attrs["density"], attrs["structural"], attrs["fixed"]
        if type(density) is not float or not math.isfinite(density) or density < 0:
            raise GrammarError(
                f"attr 'density' must be a number >= 0 (kg/m^3), got "
                f"{format_value(density)!r} (rules: {format_chain(state.rule_path)})"
            )
        for name, value in (("structural", structural), ("fixed", fixed)):
            if type(value) is not bool:
                raise GrammarError(
                    f"attr {name!r} must be true or false, got "
                    f"{format_value(value)!r} (rules: "
                    f"{format_chain(state.rule_path)})"
                )
        return density, structural, fixed

    # ------------------------------------------------------------------ compiling bodies
    def _body(self, node: ast.Body, params: dict[str, int]) -> Operation:
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
                (self.expressions.compile(b.condition, params), self._body(b.body, params), b)
                for b in node.branches
            ]
            otherwise = self._body(node.otherwise, params)
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
            branches = [(float(b.percent), self._body(b.body, params)) for b in node.branches]
            otherwise = self._body(node.otherwise, params)

            def stochastic(state, args, out):
                draw = 100.0 * state.random()
                for percent, body in branches:
                    if draw < percent:
                        return body(state, args, out)
                    draw -= percent
                return otherwise(state, args, out)

            return stochastic
        raise self.error(node, f"unsupported rule body {type(node).__name__}")

    def _item(self, node, params: dict[str, int]) -> Operation:
        method = getattr(self, "_op_" + type(node).__name__, None)
        if method is None:
            raise self.error(node, f"unsupported operation {type(node).__name__}")
        return method(node, params)

    def _number(self, node, expression, params, what: str):
        """A compiled expression that must give a finite number."""
        compiled = self.expressions.compile(expression, params)
        error = self.error

        def number(args, state):
            value = compiled(args, state)
            if type(value) is not float:
                raise error(node, f"{what} must be a number, got a {type_name(value)}")
            if not math.isfinite(value):
                raise error(node, f"{what} must be a finite number, got {value}")
            return value

        return number

    def _op_Successor(self, node: ast.Successor, params) -> Operation:
        rule = None if node.leaf else self.rules.get((node.name, len(node.args)))
        if rule is None and not node.leaf and node.name in self.arities:
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
        return lambda state, args, out: False

    def _op_Push(self, node: ast.Push, params) -> Operation:
        body = self._body(node.body, params)

        def push(state, args, out):
            body(state.copy(), args, out)
            return True

        return push

    def _op_Extrude(self, node: ast.Extrude, params) -> Operation:
        height = self._number(node, node.height, params, "extrude height")
        error = self.error

        def extrude_op(state, args, out):
            shape = state.shape
            if shape.kind != FACE:
                raise error(
                    node,
                    "extrude() needs a flat shape (the lot or a comp(f) face); "
                    "this shape is already 3D",
                )
            scope = extrude(shape.scope, shape.normal_axis, height(args, state))
            state.shape = Shape(scope, MASS)
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
            size = self._number(part, part.size, params, "a split size")
            key = (self._body(part.body, params), part)
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
        error = self.error

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
            try:
                pieces = resolve_split(
                    float(shape.scope.size[axis]),
                    pattern,
                    max_pieces=max(run.max_shapes - run.shape_count, 0) + 1,
                )
            except PieceLimitError:
                raise error(
                    node,
                    f"the split creates more than {run.max_shapes} shapes "
                    f"(max_shapes). Chain of rules: "
                    f"{format_chain(state.rule_path)}",
                ) from None
            except ValueError as exc:
                raise error(node, str(exc)) from None
            total = len(pieces)
            for index, piece in enumerate(pieces):
                body, part = piece.key
                scope = split_scope(shape.scope, axis, piece.start, piece.size)
                child = run.child(state, Shape(scope, shape.kind, shape.normal_axis), part)
                child.split_index = index
                child.split_total = total
                if body(child, args, out) and child.children[0] == 0:
                    out.append((child, None, ()))
            return True

        return split_op

    def _op_Comp(self, node: ast.Comp, params) -> Operation:
        if node.kind != "f":
            raise self.error(node, f"comp({node.kind}) is not supported; only comp(f)")
        branches = []
        for branch in node.branches:
            if branch.merge:
                raise self.error(
                    branch,
                    f"'{branch.selector} =' (all selected faces as one "
                    f"shape) is not supported; write "
                    f"'{branch.selector} :'",
                )
            branches.append((branch.selector, self._body(branch.body, params), branch))
        selectors = [_selector(s) for s, _, _ in branches]
        error = self.error

        def comp_op(state, args, out):
            shape = state.shape
            if shape.kind == MASS:
                faces = face_scopes(shape.scope)
            elif shape.kind == FACE:
                faces = [flat_face(shape.scope, shape.normal_axis)]
            else:
                raise error(node, "comp(f) cannot take apart an inserted primitive")
            run = state.run
            for (_, body, branch), chosen in zip(
                branches, select_faces(faces, selectors), strict=True
            ):
                total = len(chosen)
                for index, (_, scope) in enumerate(chosen):
                    child = run.child(state, Shape(scope, FACE, 2), branch)
                    child.comp_index = index
                    child.comp_total = total
                    if body(child, args, out) and child.children[0] == 0:
                        out.append((child, None, ()))
            return True

        return comp_op

    def _coordinates(self, node, coordinates, params, what: str):
        compiled = [
            (self._number(node, c.value, params, what), c.relative, k)
            for k, c in enumerate(coordinates)
        ]

        def values(args, state):
            size = state.shape.scope.size
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
        error = self.error

        def scale_op(state, args, out):
            try:
                scope = resize(state.shape.scope, values(args, state))
            except ValueError as exc:
                raise error(node, str(exc)) from None
            state.shape = state.shape.with_scope(scope)
            return True

        return scale_op

    def _op_Rotate(self, node: ast.Rotate, params) -> Operation:
        angles = [self._number(node, e, params, "an r() angle") for e in (node.x, node.y, node.z)]
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
            return True

        return label_op

    def _op_Set(self, node: ast.Set, params) -> Operation:
        attribute = node.attribute
        if attribute in self.const_nodes:
            raise self.error(node, f"set() changes attrs; {attribute!r} is a const")
        if attribute not in self.attr_nodes and attribute not in RESERVED_ATTRIBUTES:
            known = sorted(set(self.attr_nodes) | set(RESERVED_ATTRIBUTES))
            close = difflib.get_close_matches(attribute, known, n=1)
            hint = f" (did you mean {close[0]!r}?)" if close else ""
            raise self.error(node, f"set() of unknown attribute {attribute!r}{hint}")
        value = self.expressions.compile(node.value, params)

        def set_op(state, args, out):
            state.attrs = {**state.attrs, attribute: value(args, state)}
            return True

        return set_op

    def _op_Insert(self, node: ast.Insert, params) -> Operation:
        if isinstance(node.primitive, ast.String):
            _check_primitive_call(node, self.error)
        name_of = self.expressions.compile(node.primitive, params)
        keywords = [(k.name, self.expressions.compile(k.value, params)) for k in node.parameters]
        error = self.error

        def insert_op(state, args, out):
            name = name_of(args, state)
            if type(name) is not str:
                raise error(node, f"i() needs a primitive name (a string), got a {type_name(name)}")
            values = {key: value(args, state) for key, value in keywords}
            scope = state.shape.scope
            if name == "box" and not values:
                # The box primitive is exactly the block a 3D leaf makes: skip the registry.
                state.shape = Shape(scope, MASS)
                return True
            try:
                resolved = _resolve_primitive(name, values)
            except GeometryError as exc:
                raise error(node, str(exc)) from None
            state.shape = Shape(scope, INSERT, insert=(name, resolved, node))
            return True

        return insert_op

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


def _selector(name: str) -> str | int:
    return int(name) if name.isdigit() else name


def _check_primitive_call(node: ast.Insert, error: Callable) -> None:
    """At load time: ``i("name", key=...)`` with a literal name must name a registered
    primitive and only its parameters (values are checked when the shape is derived)."""
    from shapegen.primitives import get

    name = node.primitive.value
    if name == "box" and not node.parameters:
        return
    try:
        primitive = get(name)
    except GeometryError as exc:
        raise error(node, str(exc)) from None
    for keyword in node.parameters:
        if keyword.name not in primitive.parameters:
            known = ", ".join(sorted(primitive.parameters)) or "none"
            close = difflib.get_close_matches(keyword.name, list(primitive.parameters), n=1)
            hint = f" (did you mean {close[0]!r}?)" if close else ""
            raise error(
                keyword if getattr(keyword, "location", None) else node,
                f"primitive {name!r} has no parameter {keyword.name!r}{hint}; "
                f"its parameters: {known}",
            )


def _checked_structure(start: ast.Rule, error: Callable) -> str:
    """At load time: the structure named by the start rule's ``@Structure`` (the default without
    one), which must be registered and given only its own keyword arguments."""
    from shapegen.structures import DEFAULT_STRUCTURE, structure_class

    annotation = start.annotation("Structure")
    if annotation is None:
        return DEFAULT_STRUCTURE
    name = annotation.args[0].value if annotation.args else None
    if not isinstance(name, str):
        raise error(annotation, "@Structure names a structure: a string")
    try:
        structure = structure_class(name)
    except GeometryError as exc:
        raise error(annotation, str(exc)) from None
    given = {keyword.name for keyword in annotation.keywords}
    for keyword in annotation.keywords:
        if keyword.name not in structure.arguments:
            known = ", ".join(structure.arguments) or "none"
            close = difflib.get_close_matches(keyword.name, list(structure.arguments), n=1)
            hint = f" (did you mean {close[0]!r}?)" if close else ""
            raise error(
                keyword if getattr(keyword, "location", None) else annotation,
                f"structure {name!r} has no argument {keyword.name!r}{hint}; its arguments: "
                f"{known}",
            )
    missing = [n for n, a in structure.arguments.items() if a.required and n not in given]
    if missing:
        raise error(
            annotation, f"@Structure({name!r}) needs the argument(s) {', '.join(missing)}"
        )
    return name


def _resolve_primitive(name: str, values: dict) -> dict:
    from shapegen.primitives import get

    return get(name).resolve(values)


def _insert(name: str, scope: Scope, params: dict) -> list[Block]:
    from shapegen.primitives import insert

    return insert(name, scope, **params)


class _LazyValues(dict):
    """Attribute values computed on first read (attrs and consts may refer to each other)."""

    def __init__(self, resolve: Callable[[str], object]):
        super().__init__()
        self._resolve = resolve

    def __missing__(self, name: str) -> object:
        return self._resolve(name)


def _root_state(run: _Derivation, shape: Shape, attrs, path: tuple) -> _State:
    state = _State.__new__(_State)
    state.run = run
    state.shape = shape
    state.attrs = attrs
    state.labels = ()
    state.split_index = 0
    state.split_total = 0
    state.comp_index = 0
    state.comp_total = 0
    state.path = path
    state.children = [0]
    state.rng = [None]
    state.rule_path = ()
    state.depth = 0
    state.initial_scope = shape.scope
    return state


def _coerce(name: str, value: object, default: object) -> object:
    """An overriding value converted to the type of the attr's default."""
    if isinstance(value, np.generic):
        value = value.item()
    if isinstance(default, bool):
        if isinstance(value, bool):
            return value
        if isinstance(value, str) and value.strip().lower() in ("true", "false"):
            return value.strip().lower() == "true"
        raise GrammarError(f"attr {name!r} is true or false, got {value!r}")
    if isinstance(default, float):
        if isinstance(value, bool):
            raise GrammarError(f"attr {name!r} is a number, got {value!r}")
        try:
            number = float(value)
        except (TypeError, ValueError):
            raise GrammarError(f"attr {name!r} is a number, got {value!r}") from None
        if not math.isfinite(number):
            raise GrammarError(f"attr {name!r} must be a finite number, got {value!r}")
        return number
    if isinstance(default, str):
        return (
            value
            if isinstance(value, str)
            else format_value(
                float(value) if isinstance(value, int) and not isinstance(value, bool) else value
            )
        )
    return value

"""Parse tree -> AST: :class:`AstBuilder`, the lark Transformer that builds
:mod:`shapegen.grammar.ast` nodes.

It has one callback per rule of ``cga.lark``, named as the rule is (lark calls ``comp_value``
for the rule ``comp_value``), in the grammar's order: the file and its definitions, function
and rule bodies, operation calls, expressions, imports. What an operation call means is decided
by the :class:`~shapegen.grammar.operation_calls.OperationCalls` it owns (``comp(f) { ... }``:
:meth:`AstBuilder.operation` -> :meth:`OperationCalls.node
<shapegen.grammar.operation_calls.OperationCalls.node>` -> ``OperationCalls._comp``). Problems
that the syntax lets through (an unknown split axis, a ``'`` where it means nothing) are
collected in :attr:`AstBuilder.problems`, not raised, so that they are reported together with
the load-time checks; merging imported files is :mod:`shapegen.grammar.imports`' work.
"""

from __future__ import annotations

import dataclasses

from lark import Token, Transformer, v_args

from shapegen.errors import SourceLocation
from shapegen.grammar import ast
from shapegen.grammar.ast import BlockEntry, CallArgument, EntryGroup
from shapegen.grammar.definitions import dialect_of
from shapegen.grammar.names import CGA_OPERATIONS, OPERATIONS, SHAPE_ATTRIBUTES, SHAPE_VALUES
from shapegen.grammar.operation_calls import OperationCalls
from shapegen.grammar.problems import Problem
from shapegen.grammar.rewrites import BOOLEAN_OPERATIONS, generic_start_rules, two_operands

__all__ = ["AstBuilder"]


@dataclasses.dataclass(frozen=True)
class _Version:
    text: str


@dataclasses.dataclass(frozen=True)
class _Style:
    name: str


class _FileAnnotations:
    """Annotations after the last definition (``@RuleFileDescription("...")``)."""


class _WithClause:
    """A definition's ``with ( ... )``: its local variables."""

    def __init__(self, variables: tuple):
        self.variables = variables


def _locals(children) -> tuple:
    """The local variables of the ``with`` clause among a definition's ``children``."""
    return next((c.variables for c in children if isinstance(c, _WithClause)), ())


class _Repeat:
    """Marker for a ``*`` after a block."""


_REPEAT = _Repeat()
#: Annotations of the whole rule file, which may stand after its last definition.
FILE_ANNOTATIONS = frozenset({"RuleFileDescription"})
_EXTENSION_MARK = object()  # ``extension`` before a rule
_START_MARK = object()  # ``start`` before a rule


@v_args(meta=True)
class AstBuilder(Transformer):
    """Builds AST nodes; problems that the syntax lets through are collected, not raised."""

    def __init__(self, filename: str):
        super().__init__()
        self.filename = filename
        self.problems: list[Problem] = []
        self.start_keyword_rules: set[SourceLocation] = set()  # rules written `start Name`
        #: What each operation call means; it reports into ``problems``.
        self.operation_calls = OperationCalls(self.problems)

    def _problem(self, location: SourceLocation, message: str) -> None:
        self.problems.append((location, message))

    # Locations -------------------------------------------------------------------------------

    def _at(self, where) -> SourceLocation:
        if isinstance(where, Token):
            return SourceLocation(self.filename, where.line or 0, where.column or 0)
        line = getattr(where, "line", None)
        column = getattr(where, "column", None)
        return SourceLocation(self.filename, line or 0, column or 0)

    # File and definitions ----------------------------------------------------------------------

    def start(self, meta, children):
        version = None
        definitions = []
        imports = []
        styles = []
        for child in children:
            if isinstance(child, _Version):
                version = child.text
            elif isinstance(child, _Style):
                styles.append(child.name)
            elif isinstance(child, ast.Import):
                imports.append(child)
            elif isinstance(child, _FileAnnotations):
                continue  # only CityEngine's editors read them
            elif not styles:  # only the default style is derived
                definitions.append(child)
        definitions += generic_start_rules(definitions, self.start_keyword_rules)
        rules = {(d.name, len(d.params)) for d in definitions if isinstance(d, ast.Rule)}
        self.operation_calls.settle(rules, cga=dialect_of(self.filename) == "cga")
        return ast.RuleFile(
            definitions=tuple(definitions),
            version=version,
            filename=self.filename,
            imports=tuple(imports),
            styles=tuple(styles),
            location=SourceLocation(self.filename, 1, 1),
        )

    def file_annotations(self, meta, children):
        for annotation in children:
            if annotation.name not in FILE_ANNOTATIONS:
                self._problem(
                    annotation.location, f"@{annotation.name} stands before no definition"
                )
        return _FileAnnotations()

    def style_def(self, meta, children):
        name = next(c for c in children if isinstance(c, Token))
        return _Style(str(name))

    def version(self, meta, children):
        return _Version(unescape(children[0]))

    def definition(self, meta, children):
        *annotations, definition = children
        written = {a.name for a in annotations}  # `@StartRule start A -->` says it once
        marks = tuple(a for a in definition.annotations if a.name not in written)
        return dataclasses.replace(definition, annotations=(*annotations, *marks))

    def annotation(self, meta, children):
        name, *arguments = children
        args = tuple(a for a in arguments if not isinstance(a, ast.Keyword))
        keywords = tuple(a for a in arguments if isinstance(a, ast.Keyword))
        if args and keywords and arguments.index(keywords[0]) < arguments.index(args[-1]):
            self._problem(self._at(meta), "positional arguments must come before keyword ones")
        return ast.Annotation(str(name), args, keywords, location=self._at(name))

    def keyword(self, meta, children):
        name, value = children
        return ast.Keyword(str(name), value, location=self._at(name))

    def attr_def(self, meta, children):
        name, *local_variables, value = children
        if any(type(c) is tuple for c in local_variables):  # attr f(x) = ..., before CGA 2016
            return self._parameterised("attr", meta, children)
        return ast.Attribute(
            str(name), value, local_variables=_locals(local_variables), location=self._at(name)
        )

    def const_def(self, meta, children):
        name, *local_variables, value = children
        if any(type(c) is tuple for c in local_variables):  # a const function, const f(x) = ...
            return self._parameterised("const", meta, children)
        return ast.Constant(
            str(name), value, local_variables=_locals(local_variables), location=self._at(name)
        )

    def _parameterised(self, keyword: str, meta, children):
        """``const f(x) = ...`` (with.html's const functions) and ``attr f(x) = ...`` (CGA before
        2016): a function in a .cga file; the .grammar language keeps them apart."""
        if dialect_of(self.filename) != "cga":
            self._problem(
                self._at(children[0]),
                f"{keyword} '{children[0]}' takes no parameters (write a function: "
                f"{children[0]}(...) = ...)",
            )
        return self.function_def(meta, children)

    def function_def(self, meta, children):
        name, *rest = children
        params = next((r for r in rest[:-1] if type(r) is tuple), ())
        return ast.Function(
            str(name),
            params,
            rest[-1],
            local_variables=_locals(rest[:-1]),
            location=self._at(name),
        )

    def with_clause(self, meta, children):
        return _WithClause(tuple(children))

    def local_variable(self, meta, children):
        name, value = children
        return ast.LocalVariable(str(name), value, location=self._at(name))

    def rule_def(self, meta, children):
        marks = [c for c in children if c is _EXTENSION_MARK or c is _START_MARK]
        extension = _EXTENSION_MARK in marks
        start = _START_MARK in marks
        name, *rest = children[len(marks) :]
        rest = [child for child in rest if not (isinstance(child, Token) and child.type == "ARROW")]
        params = next((r for r in rest[:-1] if type(r) is tuple), ())
        local_variables = _locals(rest[:-1])
        # the start keyword means what @StartRule means, and lets start(...) call the rule
        annotations = (ast.Annotation("StartRule", location=self._at(name)),) if start else ()
        if start:
            self.start_keyword_rules.add(self._at(name))
        return ast.Rule(
            str(name),
            params,
            rest[-1],
            annotations=annotations,
            local_variables=local_variables,
            extension=extension,
            location=self._at(name),
        )

    def extension_mark(self, meta, children):
        return _EXTENSION_MARK

    def start_mark(self, meta, children):
        return _START_MARK

    def params(self, meta, children):
        return tuple(ast.Parameter(str(name), location=self._at(name)) for name in children)

    # Function and rule bodies: ``case ... else`` and ``30% : ... else``, each of an expression
    # (a function's body) or of a rule body, with the ``else`` last

    def _choice(self, node_class, meta, children):
        *branches, otherwise = children
        return node_class(tuple(branches), otherwise, location=self._at(meta))

    def _case_branch(self, branch_class, meta, children):
        condition, then = children
        return branch_class(condition, then, location=self._at(meta))

    def _stochastic_branch(self, branch_class, meta, children):
        probability, then = children
        return branch_class(_percent(probability), then, location=self._at(meta))

    def function_case(self, meta, children):
        return self._choice(ast.CaseExpression, meta, children)

    def case_value(self, meta, children):
        return self._case_branch(ast.CaseBranch, meta, children)

    def function_stochastic(self, meta, children):
        return self._choice(ast.StochasticExpression, meta, children)

    def stochastic_value(self, meta, children):
        return self._stochastic_branch(ast.StochasticValue, meta, children)

    def rule_case(self, meta, children):
        return self._choice(ast.ConditionalBody, meta, children)

    def case_body(self, meta, children):
        return self._case_branch(ast.ConditionalBranch, meta, children)

    def rule_stochastic(self, meta, children):
        return self._choice(ast.StochasticBody, meta, children)

    def stochastic_body(self, meta, children):
        return self._stochastic_branch(ast.StochasticBranch, meta, children)

    # Rule bodies -------------------------------------------------------------------------------

    def sequence(self, meta, children):
        items = []
        for item in children:
            previous = items[-1] if items else None
            if (  # subtract Rule, subtract(swap) Rule: CGA 2024.1's form, deprecated in 2025.0
                isinstance(previous, ast.Operation)
                and previous.name in BOOLEAN_OPERATIONS
                and not previous.branches
            ):
                items[-1] = two_operands(previous, item)
                continue
            if (  # inline(strategy) Rule: the operation takes the item after it (op_inline)
                isinstance(previous, ast.Operation)
                and previous.name == "inline"
                and previous.arguments
                and not previous.branches
            ):
                body = ast.Sequence((item,), location=item.location)
                branch = ast.OperationBranch(None, "absolute", body, location=item.location)
                items[-1] = dataclasses.replace(previous, branches=(branch,))
                continue
            items.append(item)
        return ast.Sequence(tuple(items), location=self._at(meta))

    def successor(self, meta, children):
        (name,) = children
        if name == "NIL":
            return ast.Nil(location=self._at(name))
        if name in CGA_OPERATIONS and CGA_OPERATIONS[name][0] == 0 and name not in OPERATIONS:
            # CGA lets an operation without arguments drop its parentheses (``innerRect``)
            return self.operation_calls.generic(str(name), [], None, self._at(name))
        return ast.Successor(str(name), location=self._at(name))

    def leaf(self, meta, children):
        (name,) = children
        if name == "NIL":
            return ast.Nil(location=self._at(name))
        return ast.Successor(str(name), leaf=True, location=self._at(name))

    def boolean_operation(self, meta, children):
        name, _brace, *bodies = children
        return self._alternatives(str(name), bodies, self._at(name))

    def inline_keyword(self, meta, children):
        (item,) = children
        body = ast.Sequence((item,), location=item.location)
        return self._alternatives("inline", [body], self._at(meta))

    def inline_block(self, meta, children):
        body = children[-1]
        return self._alternatives("inline", [body], self._at(meta))

    @staticmethod
    def _alternatives(name: str, bodies, location) -> ast.Operation:
        """A generic operation whose branches are bodies without keys (op_boolOp's operands,
        op_inline's operations)."""
        branches = tuple(
            ast.OperationBranch(None, "absolute", body, location=body.location) for body in bodies
        )
        return ast.Operation(name, (), branches, location=location)

    def push(self, meta, children):
        (body,) = children
        return ast.Push(body, location=self._at(meta))

    # Operation calls ---------------------------------------------------------------------------

    def plain_arg(self, meta, children):
        return CallArgument("plain", children[0], self._at(meta))

    def case_arg(self, meta, children):
        return CallArgument("plain", self.function_case(meta, children), self._at(meta))

    def stochastic_arg(self, meta, children):
        return CallArgument("plain", self.function_stochastic(meta, children), self._at(meta))

    def relative_arg(self, meta, children):
        return CallArgument("relative", children[0], self._at(meta))

    def floating_arg(self, meta, children):
        return CallArgument("floating", children[0], self._at(meta))

    def keyword_arg(self, meta, children):
        name, value = children
        return CallArgument("keyword", value, self._at(name), name=str(name))

    def repeat(self, meta, children):
        return _REPEAT

    def block(self, meta, children):
        return EntryGroup(tuple(children), False, self._at(meta))

    def bare_block(self, meta, children):
        body = children[-1]
        return EntryGroup(
            (BlockEntry("absolute", None, body, False, self._at(meta)),), False, self._at(meta)
        )

    def block_part(self, meta, children):
        (mode, key), body = children
        return BlockEntry(mode, key, body, False, self._at(meta))

    def block_merge(self, meta, children):
        (mode, key), body = children
        return BlockEntry(mode, key, body, True, self._at(meta))

    def block_connected(self, meta, children):
        (mode, key), body = children
        return BlockEntry(mode, key, body, True, self._at(meta), connected=True)

    def block_setback(self, meta, children):
        (mode, key), _colon, depth, body = children
        return BlockEntry(mode, key, body, False, self._at(meta), depth=depth)

    def block_group(self, meta, children):
        block = children[0]
        return dataclasses.replace(block, repeat=len(children) > 1)

    def absolute_size(self, meta, children):
        return ("absolute", children[0])

    def relative_size(self, meta, children):
        return ("relative", children[0])

    def floating_size(self, meta, children):
        return ("floating", children[0])

    def operation(self, meta, children):
        """``name(args) { block }*``: the call as written (its arguments, one block), handed to
        :meth:`OperationCalls.node <shapegen.grammar.operation_calls.OperationCalls.node>`."""
        name_token = children[0]
        name = str(name_token)
        location = self._at(name_token)
        arguments = [c for c in children[1:] if isinstance(c, CallArgument)]
        blocks = [c for c in children[1:] if isinstance(c, EntryGroup)]
        block = blocks[0] if blocks else None
        if block is not None and any(c is _REPEAT for c in children[1:]):
            block = dataclasses.replace(block, repeat=True)
        if len(blocks) > 1:  # splitAndSetbackPerimeter(...) { pattern }* { remainder : ops }
            if name == "splitAndSetbackPerimeter":
                block = dataclasses.replace(block, entries=block.entries + blocks[1].entries)
            else:
                self._problem(blocks[1].location, f"{name}() takes one {{ ... }} block")
        return self.operation_calls.node(name, arguments, block, location)

    # Expressions -------------------------------------------------------------------------------

    def binary(self, meta, children):
        left, operator, right = children
        return ast.Binary(str(operator), left, right, location=self._at(operator))

    def add_op(self, meta, children):
        return children[0]

    mul_op = add_op
    unary_op = add_op

    def unary(self, meta, children):
        operator, operand = children
        return ast.Unary(str(operator), operand, location=self._at(operator))

    def number(self, meta, children):
        (token,) = children
        return ast.Number(float(token), location=self._at(token))

    def string(self, meta, children):
        (token,) = children
        return ast.String(unescape(token), location=self._at(token))

    def name(self, meta, children):
        (token,) = children
        if token in ("true", "false"):
            return ast.Boolean(token == "true", location=self._at(token))
        return _dotted_name(str(token), (), self._at(token), call=False)

    def call(self, meta, children):
        name, *args = children
        return _dotted_name(str(name), tuple(args), self._at(name), call=True)

    def component_values(self, meta, children):
        name, *rest = children
        args = tuple(c for c in rest if not isinstance(c, ast.ComponentValue))
        branches = tuple(c for c in rest if isinstance(c, ast.ComponentValue))
        if name != "comp":
            self._problem(self._at(name), "only comp() takes a { ... } block in an expression")
        return ast.ComponentValues(args, branches, location=self._at(name))

    def comp_value(self, meta, children):
        return ast.ComponentValue(children[0], children[1], location=self._at(meta))

    def comp_value_merged(self, meta, children):
        return ast.ComponentValue(children[0], children[1], merge=True, location=self._at(meta))

    def comp_value_connected(self, meta, children):
        return ast.ComponentValue(
            children[0], children[1], merge=True, connected=True, location=self._at(meta)
        )

    def array(self, meta, children):
        return ast.ArrayLiteral(tuple(children), location=self._at(meta))

    def array_row(self, meta, children):
        return tuple(children)

    def index(self, meta, children):
        target, *indices = children
        return ast.Index(target, tuple(indices), location=self._at(meta))

    def colon(self, meta, children):
        if len(children) == 2:
            return ast.Colon(children[0], None, children[1], location=self._at(meta))
        start, step, stop = children
        return ast.Colon(start, step, stop, location=self._at(meta))

    def colon_all(self, meta, children):
        return ast.Colon(None, None, None, location=self._at(meta))

    # Imports ---------------------------------------------------------------------------------

    def import_prefixed(self, meta, children):
        annotations = [c for c in children if isinstance(c, ast.Annotation)]
        rest = [c for c in children if not isinstance(c, ast.Annotation)]
        prefix = rest[0]
        path = next(c for c in rest[1:] if isinstance(c, Token) and c.type == "STRING")
        arguments = rest[-1] if isinstance(rest[-1], list) else None
        styles = next((c for c in rest[1:] if isinstance(c, tuple)), ())
        item = self._import(str(prefix), path, arguments, annotations, self._at(prefix))
        return dataclasses.replace(item, styles=styles)

    def import_plain(self, meta, children):
        annotations = [c for c in children if isinstance(c, ast.Annotation)]
        rest = [c for c in children if not isinstance(c, ast.Annotation)]
        arguments = rest[-1] if isinstance(rest[-1], list) else None
        return self._import(None, rest[0], arguments, annotations, self._at(rest[0]))

    def _import(self, prefix, path, arguments, annotations, location):
        protected, overrides, rules = [], [], []
        for argument in arguments or ():
            if isinstance(argument, ast.Keyword):
                overrides.append(argument)
            elif isinstance(argument, ast.Rule):
                rules.append(argument)
            else:
                protected.append(str(argument))
        return ast.Import(
            prefix,
            unescape(path),
            tuple(protected),
            protect_all=arguments is not None and not arguments,
            overrides=tuple(overrides),
            annotations=tuple(annotations),
            rules=tuple(rules),
            location=location,
        )

    def import_styles(self, meta, children):
        return tuple(str(c) for c in children)

    def import_args(self, meta, children):
        return list(children)

    def import_protect(self, meta, children):
        return children[0]

    def import_override(self, meta, children):
        name, value = children
        return ast.Keyword(str(name), value, location=self._at(name))

    def import_rule(self, meta, children):
        name = children[0]
        params = next((c for c in children[1:-1] if isinstance(c, tuple)), ())
        return ast.Rule(str(name), params, children[-1], location=self._at(name))

    def dynamic_import(self, meta, children):
        name = children[0]
        arguments = [c for c in children[1:] if isinstance(c, CallArgument)]
        rest = [c for c in children[1:] if not isinstance(c, CallArgument)]
        rule, args = rest[0], tuple(rest[1:])
        overrides = []
        for argument in arguments:
            if argument.kind != "keyword":
                self._problem(
                    argument.location,
                    f"a dynamic import {name}(...) takes attr = value overrides only",
                )
                continue
            overrides.append(ast.Keyword(argument.name, argument.value, location=argument.location))
        return ast.DynamicImport(
            str(name), tuple(overrides), str(rule), args, location=self._at(name)
        )


def _percent(token: Token) -> float:
    return float(str(token).rstrip().rstrip("%").rstrip())


def unescape(literal: str) -> str:
    """The value of a double-quoted string literal (``\\n``, ``\\t``, ``\\"``, ``\\\\``)."""
    escapes = {"n": "\n", "t": "\t", '"': '"', "\\": "\\"}
    out = []
    chars = iter(literal[1:-1])
    for char in chars:
        if char == "\\":
            escaped = next(chars, "")
            if escaped == "u":  # \uXXXX, as CGA writes its NULL string "\ue000"
                digits = "".join(next(chars, "") for _ in range(4))
                try:
                    out.append(chr(int(digits, 16)))
                except ValueError:
                    out.append("\\u" + digits)
                continue
            out.append(escapes.get(escaped, "\\" + escaped))
        else:
            out.append(char)
    return "".join(out)


#: Objects whose dotted names are shape attributes (``scope.sx``, ``geometry.area``...).
_SHAPE_OBJECTS = frozenset({*SHAPE_ATTRIBUTES, "material"})


def _dotted_name(name: str, args: tuple, location: SourceLocation, *, call: bool):
    """A name as written: a shape attribute (``scope.sx``, ``geometry.area()``, ``seedian``), a
    call, or a plain (possibly dotted: ``prefix.attr``, ``world.up``) name."""
    head, _, rest = name.partition(".")
    if rest and head in _SHAPE_OBJECTS:
        return ast.ShapeAttribute(head, rest, args, location=location)
    if name in SHAPE_VALUES and not call:
        return ast.ShapeAttribute(name, "", location=location)
    if call:
        return ast.Call(name, args, location=location)
    return ast.Name(name, location=location)

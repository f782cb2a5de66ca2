"""Parse tree -> AST: the lark Transformer that builds :mod:`shapegen.grammar.ast` nodes.

Operation calls share one syntax (``name(args) { block }*``); which operation a call is, and
whether its arguments fit, is decided here and in the builders of
:mod:`shapegen.grammar.operation_calls`. Problems that the syntax lets through (an unknown split
axis, a ``'`` where it means nothing) are collected in :attr:`AstBuilder.problems`, not raised, so
that they are reported together with the load-time checks.
"""

from __future__ import annotations

import dataclasses

from lark import Token, Transformer, v_args

from shapegen.errors import SourceLocation
from shapegen.grammar import ast
from shapegen.grammar.definitions import dialect_of
from shapegen.grammar.expression_builders import ExpressionBuilders, unescape
from shapegen.grammar.import_syntax import ImportBuilders
from shapegen.grammar.names import (
    BLOCK_OPERATIONS,
    CGA_OPERATIONS,
    OPERATIONS,
)
from shapegen.grammar.operation_calls import (
    Argument,
    BlockEntry,
    EntryGroup,
    OperationBuilders,
    prefix_in_words,
)
from shapegen.grammar.rewrites import BOOLEAN_OPERATIONS, generic_start_rules, two_operands

__all__ = ["AstBuilder", "Problem"]

Problem = tuple[SourceLocation | None, str]


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


def _plural(count: int, word: str) -> str:
    return f"{count} {word}" if count == 1 else f"{count} {word}s"


@v_args(meta=True)
class AstBuilder(ImportBuilders, OperationBuilders, ExpressionBuilders, Transformer):
    """Builds AST nodes; problems that the syntax lets through are collected, not raised."""

    _string_value = staticmethod(unescape)

    def __init__(self, filename: str):
        super().__init__()
        self.filename = filename
        self.problems: list[Problem] = []
        self.start_keyword_rules: set[SourceLocation] = set()  # rules written `start Name`
        # operation calls whose arity fits no signature: (location, message, name, count)
        self.operation_named_calls: list[tuple[SourceLocation, str, str, int]] = []

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
        for location, message, name, count in self.operation_named_calls:
            if (name, count) not in rules or dialect_of(self.filename) != "cga":
                self._problem(location, message)
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

    # Function bodies ---------------------------------------------------------------------------

    def function_case(self, meta, children):
        *branches, otherwise = children
        return ast.CaseExpression(tuple(branches), otherwise, location=self._at(meta))

    def case_value(self, meta, children):
        condition, value = children
        return ast.CaseBranch(condition, value, location=self._at(meta))

    def function_stochastic(self, meta, children):
        *branches, otherwise = children
        return ast.StochasticExpression(tuple(branches), otherwise, location=self._at(meta))

    def stochastic_value(self, meta, children):
        probability, value = children
        return ast.StochasticValue(_percent(probability), value, location=self._at(meta))

    # Rule bodies -------------------------------------------------------------------------------

    def rule_case(self, meta, children):
        *branches, otherwise = children
        return ast.ConditionalBody(tuple(branches), otherwise, location=self._at(meta))

    def case_body(self, meta, children):
        condition, body = children
        return ast.ConditionalBranch(condition, body, location=self._at(meta))

    def rule_stochastic(self, meta, children):
        *branches, otherwise = children
        return ast.StochasticBody(tuple(branches), otherwise, location=self._at(meta))

    def stochastic_body(self, meta, children):
        probability, body = children
        return ast.StochasticBranch(_percent(probability), body, location=self._at(meta))

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
            return self._generic(str(name), [], None, self._at(name))
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
        return Argument("plain", children[0], self._at(meta))

    def case_arg(self, meta, children):
        return Argument("plain", self.function_case(meta, children), self._at(meta))

    def stochastic_arg(self, meta, children):
        return Argument("plain", self.function_stochastic(meta, children), self._at(meta))

    def relative_arg(self, meta, children):
        return Argument("relative", children[0], self._at(meta))

    def floating_arg(self, meta, children):
        return Argument("floating", children[0], self._at(meta))

    def keyword_arg(self, meta, children):
        name, value = children
        return Argument("keyword", value, self._at(name), name=str(name))

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
        name_token = children[0]
        name = str(name_token)
        location = self._at(name_token)
        arguments = [c for c in children[1:] if isinstance(c, Argument)]
        blocks = [c for c in children[1:] if isinstance(c, EntryGroup)]
        block = blocks[0] if blocks else None
        if block is not None and any(c is _REPEAT for c in children[1:]):
            block = dataclasses.replace(block, repeat=True)
        if len(blocks) > 1:  # splitAndSetbackPerimeter(...) { pattern }* { remainder : ops }
            if name == "splitAndSetbackPerimeter":
                block = dataclasses.replace(block, entries=block.entries + blocks[1].entries)
            else:
                self._problem(blocks[1].location, f"{name}() takes one {{ ... }} block")

        positional = [a for a in arguments if a.kind != "keyword"]
        if name in CGA_OPERATIONS:
            low, high = CGA_OPERATIONS[name]
            if not low <= len(positional) <= high:
                message = _count_message(name, low, high, len(positional))
                if block is None and all(a.kind == "plain" for a in arguments):
                    # a rule of the operation's name and this arity is called (a .cga file may
                    # define one: 'start' decides once every rule is known)
                    self.operation_named_calls.append((location, message, name, len(arguments)))
                    args = tuple(a.value for a in arguments)
                    return ast.Successor(name, args, called=True, location=location)
                self._problem(location, message)
                return ast.Nil(location=location)
            if name in ("split", "comp") and block is None:
                self._problem(location, f"{name}() needs a {{ ... }} block of branches after it")
                return ast.Nil(location=location)
            if block is not None and name not in BLOCK_OPERATIONS:
                self._problem(block.location, f"{name}() takes no {{ ... }} block")
                block = None
            bare = block is not None and any(
                isinstance(e, BlockEntry) and e.key is None for e in block.entries
            )
            if bare and name not in ("scatter", "inline"):  # inline(unify) { operations }
                self._problem(block.location, f"{name}() needs 'key : operations' in its block")
                return ast.Nil(location=location)
            if self._dedicated(name, arguments, block):
                builder = getattr(self, f"_op_{name}")
                if name != "i":
                    for argument in arguments:
                        if argument.kind == "keyword":
                            self._problem(
                                argument.location,
                                f"{name}() takes no keyword arguments (got '{argument.name}=')",
                            )
                return builder(arguments, block, location)
            return self._generic(name, arguments, block, location)
        if block is not None:
            self._problem(
                block.location,
                f"'{name}' is not a CGA operation, and only operations take a {{ ... }} block",
            )
        args = []
        for argument in arguments:
            if argument.kind != "plain":
                self._problem(
                    argument.location,
                    f"arguments of the successor '{name}' are plain expressions "
                    f"({prefix_in_words(argument)} is not allowed here)",
                )
            args.append(argument.value)
        return ast.Successor(name, tuple(args), called=True, location=location)


def _percent(token: Token) -> float:
    return float(str(token).rstrip().rstrip("%").rstrip())


def _count_message(name: str, low: int, high: int, got: int) -> str:
    if low == high:
        wanted = _plural(low, "argument")
    elif high >= 1_000_000:
        wanted = f"at least {_plural(low, 'argument')}"
    else:
        wanted = f"{low} to {high} arguments"
    return f"{name}() takes {wanted}, got {got}"

"""Load-time checks of a parsed .grammar: every problem found in one pass.

What is checked (each message names the place, and suggests a near name where one exists):

- duplicate attr/const/function names and duplicate rule names; a function named like a builtin;
  a rule named like an operation; repeated parameter names;
- names in expressions that are no parameter, attr, const or function; calls of unknown functions
  and calls with the wrong number of arguments (builtins and user functions); successor calls
  whose argument count does not match their rule (a successor without a rule is a leaf, not an
  error); ``set`` of something that is not an attr; unknown shape attributes (``scope.sw``);
- attrs and consts that depend on themselves;
- stochastic branches whose percentages add up to more than 100;
- annotations: unknown names, wrong arguments, misplaced ones (``@StartRule`` and ``@Lot`` on
  rules, ``@Range`` and ``@Free`` on attrs), ``@Free`` without ``@Range``, a ``@Range`` whose min
  exceeds its max or that excludes the attr's default, more than one ``@StartRule``, a start rule
  with parameters, a ``@Lot`` with non-positive sizes or not on the start rule.
"""

from __future__ import annotations

from shapegen.errors import GrammarError, SourceLocation, did_you_mean
from shapegen.grammar import ast
from shapegen.grammar.checks_annotations import AnnotationChecker
from shapegen.grammar.checks_definitions import DefinitionTable
from shapegen.grammar.checks_keywords import KeywordNames
from shapegen.grammar.constant_folding import constant_value
from shapegen.grammar.names import (
    BUILTIN_FUNCTIONS,
    CGA_OPERATIONS,
    GEOMETRY_FUNCTIONS,
    OPERATIONS,
    RESERVED_ATTRIBUTES,
    SHAPE_ATTRIBUTES,
    UNSUPPORTED_FUNCTIONS,
)
from shapegen.grammar.problems import Findings, Problem, arity, plural, show_number
from shapegen.tolerances import PERCENT_SLACK

__all__ = ["Checker", "check", "examine", "find_problems", "constant_value"]


class Checker:
    """Walks a RuleFile once and collects its problems and warnings in ``findings``.

    It owns the parts of the check: the file's :class:`DefinitionTable` (built first, reporting
    duplicates), its :class:`KeywordNames` (names CityEngine reads as keywords where they stand)
    and an :class:`AnnotationChecker`; it checks the names, calls and successors of every body
    and expression itself (:meth:`visit`).
    """

    def __init__(self, grammar: ast.RuleFile):
        self.grammar = grammar
        self.cga = grammar.dialect == "cga"
        self.findings = Findings(self.cga)
        self.definitions = DefinitionTable(grammar, self.findings)
        self.keywords = KeywordNames(grammar, self.definitions, self.findings)
        self.annotations = AnnotationChecker(grammar, self.definitions, self.findings, self.visit)

    def run(self) -> list[Problem]:
        """Check every definition; the problems found (the warnings are in ``findings``)."""
        annotations = self.annotations
        for definition in self.grammar.definitions:
            annotations.check(definition)
            scope = self._params(getattr(definition, "params", ()))
            for variable in definition.local_variables:  # each reads those before it
                self.visit(variable.value, scope)
                scope = {**scope, variable.name: variable}
            if isinstance(definition, ast.Attribute | ast.Constant):
                self.visit(definition.value, scope)
            elif isinstance(definition, ast.Function | ast.Rule):
                self.visit(definition.body, scope)
        annotations.check_start_rule()
        if not self.cga:  # CityEngine evaluates lazily: a cycle is an error only when reached
            self._check_cycles()
        return self.findings.problems

    def _params(self, params: tuple[ast.Parameter, ...]) -> dict[str, ast.Parameter]:
        seen: dict[str, ast.Parameter] = {}
        for param in params:
            if param.name in seen:
                self.findings.report(param.location, f"parameter '{param.name}' is listed twice")
            seen[param.name] = param
        return seen

    def _check_cycles(self) -> None:
        """Report attrs/consts whose value depends on itself through other attrs/consts."""
        graph: dict[str, list[str]] = {}
        for name, definition in self.definitions.values.items():
            if isinstance(definition, ast.Attribute | ast.Constant):
                graph[name] = [
                    ref
                    for ref in _referenced_names(definition.value)
                    if isinstance(self.definitions.values.get(ref), ast.Attribute | ast.Constant)
                ]
        state: dict[str, int] = {}
        reported: set[str] = set()

        def visit(name: str, path: list[str]) -> None:
            state[name] = 1
            path.append(name)
            for ref in graph.get(name, ()):
                if state.get(ref) == 1:
                    cycle = path[path.index(ref) :] + [ref]
                    if ref not in reported:
                        reported.add(ref)
                        self.findings.report(
                            self.definitions.values[ref].location,
                            f"'{ref}' depends on itself: {' -> '.join(cycle)}",
                        )
                elif ref not in state:
                    visit(ref, path)
            path.pop()
            state[name] = 2

        for name in graph:
            if name not in state:
                visit(name, [])

    # Rule bodies and expressions -------------------------------------------------------------

    def visit(self, tree, params: dict) -> None:
        """Check every node of a rule body, an expression or an annotation's arguments."""
        for node in ast.walk(tree):
            if isinstance(node, ast.Name):
                self._name(node, params)
            elif isinstance(node, ast.Call):
                self._call(node, params)
            elif isinstance(node, ast.ShapeAttribute):
                self._shape_attribute(node)
            elif isinstance(node, ast.Successor):
                self._successor(node)
            elif isinstance(node, ast.Set):
                self._set_target(node)
            elif isinstance(node, ast.StochasticBody | ast.StochasticExpression):
                self._percentages(node.branches, node.location)

    def _percentages(self, branches, location: SourceLocation) -> None:
        total = sum(branch.percent for branch in branches)
        if total > 100.0 + PERCENT_SLACK:
            self.findings.report(
                location,
                f"the stochastic percentages add up to {show_number(total)}% (at most 100%)",
            )

    def _successor(self, successor: ast.Successor) -> None:
        if successor.leaf:
            return  # ``Name.`` is a leaf named Name, whatever rules or operations are called so
        if (successor.name, len(successor.args)) in self.definitions.rules and (
            successor.called or (self.cga and _needs_arguments(successor.name))
        ):
            pass  # a rule with an operation's name and another arity (operation_overload),
            # written with its arguments or, taking none, bare (``i --> ...`` then ``A --> i``)
        elif successor.name in OPERATIONS or successor.name in CGA_OPERATIONS:
            self.findings.report(
                successor.location,
                f"'{successor.name}' is an operation: write {successor.name}(...)",
            )
            return
        arities = self.definitions.arities.get(successor.name)
        if arities is None and successor.called and _looks_like_call(successor.name):
            known = [*CGA_OPERATIONS, *(name for name, _ in self.definitions.rules)]
            self.findings.warn(
                successor.location,
                f"'{successor.name}(...)' is neither a CGA operation nor a rule of this file"
                + (" (the shape stays a leaf)" if self.cga else "")
                + did_you_mean(successor.name, known),
            )
            return
        if arities is None:
            return  # a leaf shape, as in CGA
        if len(successor.args) not in arities:
            counts = " or ".join(str(n) for n in sorted(arities))
            noun = "argument" if sorted(arities) == [1] else "arguments"
            self.findings.warn(
                successor.location,
                f"rule '{successor.name}' takes {counts} {noun}, got {len(successor.args)}"
                + (": an undefined rule, the shape stays a leaf" if self.cga else ""),
            )

    def _set_target(self, item: ast.Set) -> None:
        name = item.attribute
        if not name:
            return  # already reported by the parser
        target = self.definitions.values.get(name)
        if isinstance(target, ast.Attribute) or (target is None and name in RESERVED_ATTRIBUTES):
            return
        if target is None and name.partition(".")[0] in _SETTABLE_OBJECTS:
            return  # a shape attribute: the interpreter says which it can set
        if target is not None:
            kind = "a const" if isinstance(target, ast.Constant) else "a function"
            self.findings.report(item.location, f"set() needs an attr, and '{name}' is {kind}")
            return
        candidates = [n for n, d in self.definitions.values.items() if isinstance(d, ast.Attribute)]
        self.findings.report(
            item.location,
            f"set() of undefined attr '{name}'"
            + did_you_mean(name, [*candidates, *RESERVED_ATTRIBUTES]),
        )

    def _name(self, node: ast.Name, params: dict) -> None:
        name = node.name
        if name in params:
            return
        target = self.definitions.values.get(name)
        if target is None and name in RESERVED_ATTRIBUTES:
            return
        if name in self.keywords.words_at(node):
            return
        if isinstance(target, ast.Function) and 0 not in self.definitions.function_arities[name]:
            self.findings.report(
                node.location,
                f"function '{name}' takes {plural(len(target.params), 'argument')}: "
                f"write {name}(...)",
            )
            return
        if target is not None:
            return
        if name in self.keywords.words_at(node):
            return
        if name in BUILTIN_FUNCTIONS:
            if not (self.cga and BUILTIN_FUNCTIONS[name][0] == 0):  # CityEngine calls rand
                self.findings.report(
                    node.location, f"'{name}' is a builtin function: write {name}(...)"
                )
            return
        candidates = [*params, *self.definitions.values, *RESERVED_ATTRIBUTES]
        self.findings.report(
            node.location, f"undefined name '{name}'" + did_you_mean(name, candidates)
        )

    def _call(self, node: ast.Call, params: dict) -> None:
        name = node.name
        count = len(node.args)
        if name in params or isinstance(
            self.definitions.values.get(name), ast.Attribute | ast.Constant
        ):
            self.findings.report(node.location, f"'{name}' is not a function")
            return
        target = self.definitions.values.get(name)
        if (
            isinstance(target, ast.Function)
            and name in BUILTIN_FUNCTIONS
            and count not in self.definitions.function_arities[name]
        ):
            target = None  # the builtin of that name (user functions overload by arity)
        if isinstance(target, ast.Function):
            expected = len(target.params)
            if count not in self.definitions.function_arities[name]:
                self.findings.report(
                    node.location,
                    f"function '{name}' takes {plural(expected, 'argument')}, got {count}",
                )
            return
        if name in BUILTIN_FUNCTIONS:
            low, high = BUILTIN_FUNCTIONS[name]
            if not low <= count <= high:
                self.findings.report(
                    node.location, f"{name}() takes {arity(low, high)}, got {count}"
                )
            return
        if name in UNSUPPORTED_FUNCTIONS:
            self.findings.report(node.location, f"{name}() {UNSUPPORTED_FUNCTIONS[name]}")
            return
        functions = [n for n, d in self.definitions.values.items() if isinstance(d, ast.Function)]
        self.findings.report(
            node.location,
            f"undefined function '{name}'" + did_you_mean(name, [*BUILTIN_FUNCTIONS, *functions]),
        )

    def _shape_attribute(self, node: ast.ShapeAttribute) -> None:
        written = f"{node.obj}.{node.field}" if node.field else node.obj
        if written in self.keywords.words_at(node):
            return
        if node.obj == "material" or (node.obj == "seedian" and not node.field):
            return  # material fields are checked against the catalogue when compiled
        fields = SHAPE_ATTRIBUTES.get(node.obj)
        if node.obj == "geometry" and node.field in GEOMETRY_FUNCTIONS:
            low, high = GEOMETRY_FUNCTIONS[node.field]
            if not low <= len(node.args) <= high:
                self.findings.report(
                    node.location, f"{written}() takes {arity(low, high)}, got {len(node.args)}"
                )
            return
        if fields is not None and node.field in fields:
            if node.args:
                self.findings.report(
                    node.location, f"'{written}' is a shape attribute, not a function"
                )
            return
        valid = [f"{obj}.{field}" for obj, names in SHAPE_ATTRIBUTES.items() for field in names]
        self.findings.report(
            node.location,
            f"unknown shape attribute '{written}'"
            + (did_you_mean(written, valid) or f"; valid: {', '.join(valid)}"),
        )


#: Objects whose attributes ``set()`` may name (``set(material.color.r, 1)``, ``set(trim.vertical,
#: false)``); the interpreter reports the ones it does not honour.
_SETTABLE_OBJECTS = frozenset({"material", "scope", "trim", "pivot", "comp", "initialShape"})


def _looks_like_call(name: str) -> bool:
    """A call ``name(...)`` with no rule: an error when it reads as a misspelt operation or
    function (lower-case, as CGA writes them); ``Window(2)`` stays a leaf, as CGA leaves
    successors without a rule."""
    return name.rpartition(".")[2][:1].islower()


def _referenced_names(expression: ast.Expression) -> list[str]:
    """Names and called functions in ``expression``, in source order."""
    return [node.name for node in ast.walk(expression) if isinstance(node, ast.Name | ast.Call)]


# --------------------------------------------------------------------------------------------
# Entry points


def _order(problem: Problem) -> tuple[int, int]:
    location = problem[0]
    return (location.line, location.column) if location is not None else (0, 0)


def examine(grammar: ast.RuleFile) -> tuple[list[Problem], list[Problem]]:
    """The load-time problems and warnings of ``grammar``, each as ``(location, message)``
    pairs in file order. Warnings come only from ``.cga`` files: what CityEngine's compiler
    warns about and derives anyway (see :meth:`~shapegen.grammar.problems.Findings.warn`)."""
    try:
        checker = Checker(grammar)
        problems = checker.run()
    except RecursionError:
        location = SourceLocation(grammar.filename, 1, 1)
        return [(location, "the file nests too deeply to process")], []
    return (
        sorted(dict.fromkeys(problems), key=_order),
        sorted(dict.fromkeys(checker.findings.warnings), key=_order),
    )


def find_problems(grammar: ast.RuleFile) -> list[Problem]:
    """Every load-time problem of ``grammar`` as ``(location, message)`` pairs, in file order."""
    return examine(grammar)[0]


def check(grammar: ast.RuleFile) -> ast.RuleFile:
    """Check ``grammar``; return it unchanged, or raise one GrammarError listing every problem.

    Raises
    ------
    GrammarError
        With ``problems`` holding each ``(location, message)``, in file order.
    """
    problems = find_problems(grammar)
    if problems:
        location, message = problems[0]
        raise GrammarError(message, location, source=grammar.source, problems=problems)
    return grammar


def _needs_arguments(name: str) -> bool:
    """Whether every signature of the CGA operation ``name`` takes arguments: then a bare
    ``name`` can only be a rule of that name taking none."""
    low, _ = CGA_OPERATIONS.get(name, (0, 0))
    return low > 0

"""Load-time checks of annotations: unknown names (ignored in ``.cga`` files, as CityEngine only
warns), argument counts and keywords, misplaced ones, ``@Range`` bounds and the start rule's
``@StartRule``, ``@Lot`` and ``@Structure``: :class:`AnnotationChecker`.

The checker of :mod:`shapegen.grammar.checks` owns one, and hands it the function that checks
the names in an expression (an annotation's arguments are expressions).
"""

from __future__ import annotations

from collections.abc import Callable

from shapegen.errors import did_you_mean
from shapegen.grammar import ast
from shapegen.grammar.checks_definitions import DefinitionTable
from shapegen.grammar.constant_folding import UNKNOWN, constant_value, is_number
from shapegen.grammar.definitions import dialect_of
from shapegen.grammar.names import ANNOTATIONS, ANY_KEYWORD
from shapegen.grammar.problems import Findings, arity, show_number
from shapegen.limits import LOT_EXTENT_LIMIT_M

__all__ = ["AnnotationChecker"]

_RULE_ONLY_ANNOTATIONS = ("StartRule", "Lot", "Structure")
#: shapegen's own annotations, which decide how a model is built, searched and judged.
_SHAPEGEN_ANNOTATIONS = frozenset({"Free", "Lot", "Structure"})
#: Annotations whose arguments are evaluated in a .cga file (their names must exist).
_EVALUATED_IN_CGA = _SHAPEGEN_ANNOTATIONS | {"Range"}
_ATTR_ONLY_ANNOTATIONS = ("Range", "Free")
_KIND_NAMES = {
    ast.Attribute: "an attr",
    ast.Constant: "a const",
    ast.Function: "a function",
    ast.Rule: "a rule",
}


#: CityEngine's annotations for its inspector and viewport whose arguments are CityEngine's own
#: words (``@Handle(shape=Lot, axis=y)``, ``@Out(granularity=separate)``): never evaluated here,
#: so their names are not looked up.
_UNEVALUATED = frozenset(
    {"Handle", "Location", "Out", "Macro", "File", "Directory", "MaterialFile", "Label"}
)


class AnnotationChecker:
    """Checks the annotations of each definition (:meth:`check`) and the start rule's
    (:meth:`check_start_rule`), reporting into ``findings``; ``visit(tree, params)`` checks the
    names of an annotation's arguments."""

    def __init__(
        self,
        grammar: ast.RuleFile,
        definitions: DefinitionTable,
        findings: Findings,
        visit: Callable[[object, dict], None],
    ):
        self._grammar = grammar
        self._definitions = definitions
        self._findings = findings
        self._visit = visit
        self._cga = findings.cga

    def _annotation_problem(self, name: str, location, message: str) -> None:
        """A problem with annotation ``@name``: CityEngine's compiler only warns about its own
        annotations (the inspector ignores what it cannot read), so in a ``.cga`` file it is a
        warning; shapegen's own (``@Free``, ``@Lot``, ``@Structure``) decide how a model is
        built and judged, so they stay errors."""
        if name in _SHAPEGEN_ANNOTATIONS:
            self._findings.report(location, message)
        else:
            self._findings.warn(location, message + (" (ignored)" if self._cga else ""))

    def check(self, definition: ast.Definition) -> None:
        kind = _KIND_NAMES[type(definition)]
        seen: set[str] = set()
        for annotation in definition.annotations:
            name = annotation.name
            if name not in ANNOTATIONS and (
                self._cga or dialect_of(annotation.location.file or "") == "cga"
            ):
                continue  # CityEngine takes any annotation (it only warns)
            if name not in ANNOTATIONS:
                self._findings.report(
                    annotation.location,
                    f"unknown annotation '@{name}'" + did_you_mean(name, ANNOTATIONS),
                )
                continue
            if name in seen:
                self._annotation_problem(name, annotation.location, f"'@{name}' is given twice")
            seen.add(name)
            low, high, keywords = ANNOTATIONS[name]
            count = len(annotation.args)
            if not (low <= count <= high) and not (name == "Range" and annotation.keywords):
                self._annotation_problem(
                    name,
                    annotation.location,
                    f"@{name} takes {arity(low, high)}, got {count}",
                )
            for keyword in annotation.keywords:
                if ANY_KEYWORD not in keywords and keyword.name not in keywords:
                    valid = ", ".join(keywords) if keywords else "none"
                    self._annotation_problem(
                        name,
                        keyword.location,
                        f"@{name} has no argument '{keyword.name}' (valid: {valid})"
                        + did_you_mean(keyword.name, keywords),
                    )
            if name not in _UNEVALUATED and (not self._cga or name in _EVALUATED_IN_CGA):
                # CityEngine reads the other inspector hints' unquoted words as words
                self._visit_annotation(name, definition, annotation)
            if name in _RULE_ONLY_ANNOTATIONS and not isinstance(definition, ast.Rule):
                self._annotation_problem(
                    name, annotation.location, f"@{name} belongs on a rule, not on {kind}"
                )
            if name in _ATTR_ONLY_ANNOTATIONS and not isinstance(definition, ast.Attribute):
                self._annotation_problem(
                    name, annotation.location, f"@{name} belongs on an attr, not on {kind}"
                )
        if isinstance(definition, ast.Attribute):
            self._check_range(definition)

    def _visit_annotation(self, name: str, definition, annotation: ast.Annotation) -> None:
        """Check the names in the annotation's arguments. A ``@Range`` that is only an
        inspector hint (not ``@Free``) in a ``.cga`` file turns its problems into warnings: the
        range is ignored, as the inspector can do nothing with it."""
        hint = name == "Range" and not (isinstance(definition, ast.Attribute) and definition.free)
        before = len(self._findings.problems)
        self._visit(annotation, {})
        if hint and self._cga:
            self._findings.demote_since(before, " (the @Range is ignored)")

    def _check_range(self, attribute: ast.Attribute) -> None:
        annotation = attribute.annotation("Range")
        if annotation is None:
            if attribute.free:
                self._findings.report(
                    attribute.annotation("Free").location,
                    f"@Free attr '{attribute.name}' needs a @Range(min=..., max=...) "
                    "for its bounds",
                )
            return
        # a @Free attr's bounds are the search's; any other @Range is an inspector hint, which
        # CityEngine only warns about
        problem = (
            self._findings.report
            if attribute.free
            else lambda location, message: self._annotation_problem("Range", location, message)
        )
        bounds = attribute.range
        if bounds is None:
            problem(annotation.location, "@Range needs both a min and a max")
            return
        low, high = (constant_value(bound, self._definitions.values) for bound in bounds)
        for bound, value in zip(bounds, (low, high), strict=True):
            if value is UNKNOWN and attribute.free:
                self._findings.report(
                    bound.location,
                    f"the @Range bounds of @Free attr '{attribute.name}' must be constants",
                )
            elif value is not UNKNOWN and not is_number(value) and attribute.free:
                self._findings.report(bound.location, "a @Range bound must be a number")
            elif value is not UNKNOWN and not is_number(value) and not isinstance(value, str):
                # CityEngine's older string form @Range("a", "b") lists choices, like @Enum
                problem(bound.location, "a @Range bound must be a number")
        if not (is_number(low) and is_number(high)):
            return
        if low > high:
            problem(
                annotation.location,
                f"@Range min {show_number(low)} is greater than its max {show_number(high)}",
            )
            return
        default = constant_value(attribute.value, self._definitions.values)
        if is_number(default) and not (low <= default <= high):
            self._findings.warn(
                attribute.value.location,
                f"the value {show_number(default)} of '{attribute.name}' is outside its "
                f"@Range [{show_number(low)}, {show_number(high)}]",
            )
        elif attribute.free and default is not UNKNOWN and not is_number(default):
            self._findings.report(
                attribute.value.location,
                f"@Free attr '{attribute.name}' must have a numeric value",
            )

    def check_start_rule(self) -> None:
        starts = list({id(r): r for r in self._definitions.rules.values() if r.start}.values())
        for extra in [rule for rule in starts if rule.name != starts[0].name]:
            # CityEngine lets a file offer several start rules and the user pick one
            self._findings.warn(
                extra.annotation("StartRule").location,
                f"more than one @StartRule (the first is '{starts[0].name}' at "
                f"{starts[0].location})"
                + (f": '{starts[0].name}' is derived" if self._cga else ""),
            )
        start = self._grammar.start_rule
        if start is not None and start.start and start.params:
            self._findings.report(
                start.location, f"the start rule '{start.name}' cannot take parameters"
            )
        if self._cga and starts and start is not None and start not in starts:
            # start.html: a start rule with parameters is called as rule.start(...)
            self._findings.warn(
                starts[0].location,
                f"the start rule '{starts[0].name}' takes parameters, so it cannot start a "
                f"derivation on a lot: '{start.name}' is derived",
            )
        for rule in self._definitions.rules.values():
            for name in ("Lot", "Structure"):  # annotations of the start rule only
                annotation = rule.annotation(name)
                if annotation is None:
                    continue
                if rule is not start:
                    self._findings.report(annotation.location, f"@{name} belongs on the start rule")
                for argument in annotation.args:
                    self._start_annotation_value(name, argument)

    def _start_annotation_value(self, name: str, argument: ast.Expression) -> None:
        value = constant_value(argument, self._definitions.values)
        if value is UNKNOWN:
            return
        if name == "Lot" and not (is_number(value) and value > 0):
            self._findings.report(argument.location, "@Lot sizes must be positive numbers (metres)")
        elif name == "Lot" and not value <= LOT_EXTENT_LIMIT_M:
            self._findings.report(
                argument.location, f"@Lot sizes must be at most {LOT_EXTENT_LIMIT_M:g} m"
            )  # fmt: skip
        if name == "Structure" and not isinstance(value, str):
            self._findings.report(argument.location, "@Structure names a structure: a string")

"""Definition nodes of the .grammar AST: annotations, attrs, consts, functions, rules and the
whole file.

The whole tree is described in :mod:`shapegen.grammar.ast`, which re-exports these classes.
"""

from __future__ import annotations

from dataclasses import field

from shapegen.errors import SourceLocation
from shapegen.grammar.expressions import Expression, Keyword
from shapegen.grammar.rule_bodies import Body
from shapegen.grammar.tree import location_field, node

__all__ = [
    "Annotation",
    "Attribute",
    "Constant",
    "Definition",
    "Function",
    "Import",
    "LocalVariable",
    "Parameter",
    "Rule",
    "RuleFile",
    "dialect_of",
]


@node
class Annotation:
    """``@Name`` or ``@Name(args, key=value)``."""

    name: str
    args: tuple[Expression, ...] = ()
    keywords: tuple[Keyword, ...] = ()
    location: SourceLocation = location_field()

    def argument(self, keyword: str, position: int) -> Expression | None:
        """The argument given as ``keyword=...`` or else at ``position``, or None."""
        for kw in self.keywords:
            if kw.name == keyword:
                return kw.value
        if 0 <= position < len(self.args):
            return self.args[position]
        return None


class _Annotated:
    """Lookup of annotations on a definition."""

    annotations: tuple[Annotation, ...]

    def annotation(self, name: str) -> Annotation | None:
        """The first annotation called ``name`` (without ``@``), or None."""
        for annotation in self.annotations:
            if annotation.name == name:
                return annotation
        return None

    def has_annotation(self, name: str) -> bool:
        return self.annotation(name) is not None


@node
class Parameter:
    """A formal parameter of a function or rule."""

    name: str
    location: SourceLocation = location_field()


@node
class LocalVariable:
    """``name := value`` in a definition's ``with ( ... )`` (with.html): evaluated once, in
    order, when the definition is called; later ones and the body may read it."""

    name: str
    value: Expression
    location: SourceLocation = location_field()


@node
class Attribute(_Annotated):
    """``attr name = value``."""

    name: str
    value: Expression
    annotations: tuple[Annotation, ...] = ()
    local_variables: tuple[LocalVariable, ...] = ()
    location: SourceLocation = location_field()

    @property
    def range(self) -> tuple[Expression, Expression] | None:
        """The ``(min, max)`` expressions of its ``@Range``, or None without one."""
        annotation = self.annotation("Range")
        if annotation is None:
            return None
        low = annotation.argument("min", 0)
        high = annotation.argument("max", 1)
        if low is None or high is None:
            return None
        return low, high

    @property
    def free(self) -> bool:
        """True for an ``@Free`` attribute (a parameter the optimizer may change)."""
        return self.has_annotation("Free")


@node
class Constant(_Annotated):
    """``const name = value``."""

    name: str
    value: Expression
    annotations: tuple[Annotation, ...] = ()
    local_variables: tuple[LocalVariable, ...] = ()
    location: SourceLocation = location_field()


@node
class Function(_Annotated):
    """``name(params) = body`` (``params`` may be empty)."""

    name: str
    params: tuple[Parameter, ...]
    body: Expression
    annotations: tuple[Annotation, ...] = ()
    local_variables: tuple[LocalVariable, ...] = ()
    location: SourceLocation = location_field()


@node
class Rule(_Annotated):
    """``Name(params) --> body``."""

    name: str
    params: tuple[Parameter, ...]
    body: Body
    annotations: tuple[Annotation, ...] = ()
    local_variables: tuple[LocalVariable, ...] = ()
    #: Written ``extension Name --> ...``: an import may redefine it (extension.html).
    extension: bool = field(default=False, compare=False)
    location: SourceLocation = location_field()

    @property
    def start(self) -> bool:
        """True for an ``@StartRule`` rule."""
        return self.has_annotation("StartRule")


Definition = Attribute | Constant | Function | Rule


@node
class Import:
    """``import prefix : "file.cga" (args)`` or ``import "file.cga"`` (``prefix`` None).

    ``protected`` lists the attrs named bare in the argument list (not propagated from the
    importing file); ``protect_all`` is True for empty parentheses; ``overrides`` gives the attrs
    set to an expression of the importing file (``(height = 20)``); ``rules`` the extension rules
    redefined there (``(Roof --> roofHip(30))``); ``styles`` the styles named after the prefix
    (``import p (mystyle) : "x.cga"``). ``path`` is as written.
    """

    prefix: str | None
    path: str
    protected: tuple[str, ...] = ()
    protect_all: bool = False
    overrides: tuple[Keyword, ...] = ()
    annotations: tuple[Annotation, ...] = ()
    rules: tuple[Rule, ...] = ()
    styles: tuple[str, ...] = ()
    location: SourceLocation = location_field()


def dialect_of(filename: str) -> str:
    """The dialect of a rule file by its name, the one place it is decided: ``"cga"`` for a
    CityEngine rule file (``.cga``, any case: lenient where CityEngine is), ``"grammar"`` for
    shapegen's own ``.grammar`` files and texts (strict). The parser asks it before the
    :class:`RuleFile` exists; everything after asks ``RuleFile.dialect`` (the public
    ``Grammar.dialect``, a model's ``metadata["dialect"]``).

    >>> dialect_of("building.CGA"), dialect_of("vault.grammar"), dialect_of("<string>")
    ('cga', 'grammar', 'grammar')
    """
    return "cga" if filename.lower().endswith(".cga") else "grammar"


@node
class RuleFile:
    """A whole .grammar file.

    Attributes
    ----------
    definitions : tuple
        Every attr, const, function and rule, in source order.
    version : str or None
        The text of the ``version "..."`` line.
    filename : str
        Name used in error messages.
    imports : tuple
        The file's ``import`` lines (their definitions are merged into ``definitions`` under
        their prefix by :func:`shapegen.grammar.imports.resolve_imports`).
    styles : tuple
        Names of the ``style`` sections; only the default style is derived, so the definitions
        after a ``style`` line are parsed and left out of ``definitions``.
    source : str
        The file's text (for error carets); excluded from equality.
    sources : dict
        ``file name -> text`` of every file merged into this one by its imports (for the carets
        of problems found in them); excluded from equality.
    warnings : tuple
        What the load found and let through in a ``.cga`` file, where CityEngine's compiler only
        warns (an unknown annotation, an undefined rule, a default outside its ``@Range``), one
        ``file:line:col: message`` line each; the derivation carries them into the model's
        ``metadata["warnings"]``. Excluded from equality.
    """

    definitions: tuple[Definition, ...]
    version: str | None = None
    filename: str = "<string>"
    imports: tuple[Import, ...] = ()
    styles: tuple[str, ...] = ()
    source: str = field(default="", compare=False, repr=False)
    sources: dict[str, str] = field(default_factory=dict, compare=False, repr=False)
    warnings: tuple[str, ...] = field(default=(), compare=False, repr=False)
    location: SourceLocation = location_field()

    @property
    def dialect(self) -> str:
        """``"cga"`` or ``"grammar"``: :func:`dialect_of` the file's name."""
        return dialect_of(self.filename)

    def source_of(self, file: str | None) -> str:
        """The text of ``file`` (this file's or an imported one's), for an error's caret."""
        if file is None or file == self.filename:
            return self.source
        return self.sources.get(file, "")

    @property
    def attrs(self) -> tuple[Attribute, ...]:
        return tuple(d for d in self.definitions if isinstance(d, Attribute))

    @property
    def consts(self) -> tuple[Constant, ...]:
        return tuple(d for d in self.definitions if isinstance(d, Constant))

    @property
    def functions(self) -> tuple[Function, ...]:
        return tuple(d for d in self.definitions if isinstance(d, Function))

    @property
    def rules(self) -> tuple[Rule, ...]:
        return tuple(d for d in self.definitions if isinstance(d, Rule))

    def rule(self, name: str) -> Rule | None:
        """The rule called ``name``, or None (a successor without a rule is a leaf)."""
        for definition in self.definitions:
            if isinstance(definition, Rule) and definition.name == name:
                return definition
        return None

    @property
    def start_rule(self) -> Rule | None:
        """The first ``@StartRule`` (or ``start``) rule without parameters, else the first
        rule without parameters (else the first rule), else None."""
        rules = self.rules
        starts = [rule for rule in rules if rule.start]
        for rule in starts:
            if not rule.params:
                return rule
        if starts and self.dialect != "cga":
            return starts[0]  # refused by the checks: a start rule cannot take parameters
        for rule in rules:  # a rule with parameters cannot start a derivation
            if not rule.params:
                return rule
        return rules[0] if rules else None

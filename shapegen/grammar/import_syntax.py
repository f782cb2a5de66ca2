"""Parse tree -> AST for CityEngine's ``import`` lines and dynamic imports (``p(a = 1).Rule``).

:class:`ImportBuilders` is mixed into :class:`~shapegen.grammar.transformer.AstBuilder`, which
provides ``_at`` (a token's location), ``_problem`` and ``_string_value`` (a string literal's
value); merging the imported files is :mod:`shapegen.grammar.imports`' work.
"""

from __future__ import annotations

import dataclasses

from lark import Token, v_args

from shapegen.grammar import ast
from shapegen.grammar.operation_calls import Argument

__all__ = ["ImportBuilders"]


class ImportBuilders:
    """The builders of :class:`~shapegen.grammar.ast.Import` and
    :class:`~shapegen.grammar.ast.DynamicImport` nodes."""

    @v_args(meta=True)
    def import_prefixed(self, meta, children):
        annotations = [c for c in children if isinstance(c, ast.Annotation)]
        rest = [c for c in children if not isinstance(c, ast.Annotation)]
        prefix = rest[0]
        path = next(c for c in rest[1:] if isinstance(c, Token) and c.type == "STRING")
        arguments = rest[-1] if isinstance(rest[-1], list) else None
        styles = next((c for c in rest[1:] if isinstance(c, tuple)), ())
        item = self._import(str(prefix), path, arguments, annotations, self._at(prefix))
        return dataclasses.replace(item, styles=styles)

    @v_args(meta=True)
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
            self._string_value(path),
            tuple(protected),
            protect_all=arguments is not None and not arguments,
            overrides=tuple(overrides),
            annotations=tuple(annotations),
            rules=tuple(rules),
            location=location,
        )

    @v_args(meta=True)
    def import_styles(self, meta, children):
        return tuple(str(c) for c in children)

    @v_args(meta=True)
    def import_args(self, meta, children):
        return list(children)

    @v_args(meta=True)
    def import_protect(self, meta, children):
        return children[0]

    @v_args(meta=True)
    def import_override(self, meta, children):
        name, value = children
        return ast.Keyword(str(name), value, location=self._at(name))

    @v_args(meta=True)
    def import_rule(self, meta, children):
        name = children[0]
        params = next((c for c in children[1:-1] if isinstance(c, tuple)), ())
        return ast.Rule(str(name), params, children[-1], location=self._at(name))

    @v_args(meta=True)
    def dynamic_import(self, meta, children):
        name = children[0]
        arguments = [c for c in children[1:] if isinstance(c, Argument)]
        rest = [c for c in children[1:] if not isinstance(c, Argument)]
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

"""AST -> CGA text: the inverse of :func:`shapegen.grammar.parse`, up to source locations.

:func:`print_grammar` writes a :class:`~shapegen.grammar.ast.RuleFile` back as rule-file text
that parses to an equal tree (nodes compare without their ``location``): one definition a line,
its annotations on the lines before it, operators with the fewest parentheses that keep their
grouping. Comments and the original layout are not kept. :func:`print_expression` and
:func:`print_body` write one expression or rule body.

>>> from shapegen.grammar import parse
>>> print(print_grammar(parse("Lot-->extrude(3)split(y){~1:Floor|'0.2:Roof}*")).strip())
Lot --> extrude(3) split(y) { ~1 : Floor | '0.2 : Roof }*
"""

from __future__ import annotations

import math

from shapegen.grammar import ast
from shapegen.grammar.names import ROTATE_PIVOTS

__all__ = ["print_body", "print_expression", "print_grammar"]

# Binding strength of the binary operators, loosest first (cga.lark's expression levels).
_LEVELS: dict[str, int] = {
    **dict.fromkeys(("||", ".||"), 1),
    **dict.fromkeys(("&&", ".&&"), 2),
    **dict.fromkeys(("==", "!=", ".==", ".!="), 3),
    **dict.fromkeys(("<", "<=", ">", ">=", ".<", ".<=", ".>", ".>="), 4),
    **dict.fromkeys(("+", "-", ".+", ".-"), 5),
    **dict.fromkeys(("*", "/", "%", ".*", "./", ".%"), 6),
}
_UNARY_LEVEL = 7
_PRIMARY_LEVEL = 8

_PIVOT_NAMES = {pivot: name for name, pivot in ROTATE_PIVOTS.items()}
_UV_DIRECTIONS = {"x": "u", "y": "v"}
_MODE_PREFIX = {"absolute": "", "relative": "'", "floating": "~"}
_ARGUMENT_PREFIX = {"plain": "", "relative": "'", "floating": "~"}
# Generic operations whose keyless branches are alternatives: union { A | B } (op_boolOp).
_ALTERNATIVES = frozenset({"union", "subtract", "intersect"})


# ------------------------------------------------------------------------------- expressions
def print_expression(expression: ast.Expression) -> str:
    """``expression`` as CGA text; a conditional or stochastic value is put in parentheses."""
    return _expression(expression)[0]


def _level(expression) -> int:
    if isinstance(expression, ast.Binary):
        return _LEVELS.get(expression.op, 0)
    if isinstance(expression, ast.Unary):
        return _UNARY_LEVEL
    return _PRIMARY_LEVEL


def _expression(expression) -> tuple[str, int]:
    """The text of ``expression`` and how tightly it binds (:data:`_LEVELS`)."""
    kind = type(expression)
    if kind is ast.Binary:
        level = _LEVELS.get(expression.op, 0)
        left = _operand(expression.left, level, strict=False)
        right = _operand(expression.right, level, strict=True)
        return f"{left} {expression.op} {right}", level
    if kind is ast.Unary:
        operand = _operand(expression.operand, _UNARY_LEVEL, strict=False)
        space = " " if operand[:1] in "-+!." else ""
        return f"{expression.op}{space}{operand}", _UNARY_LEVEL
    return _primary(expression), _PRIMARY_LEVEL


def _operand(expression, level: int, strict: bool) -> str:
    text, own = _expression(expression)
    if own < level or (strict and own == level):
        return f"({text})"
    return text


def _primary(expression) -> str:
    kind = type(expression)
    if kind is ast.Number:
        return _number(expression.value)
    if kind is ast.String:
        return _string(expression.value)
    if kind is ast.Boolean:
        return "true" if expression.value else "false"
    if kind is ast.Name:
        return expression.name
    if kind is ast.ShapeAttribute:
        text = f"{expression.obj}.{expression.field}" if expression.field else expression.obj
        if expression.args:
            text += f"({_values(expression.args)})"
        return text
    if kind is ast.Call:
        return f"{expression.name}({_values(expression.args)})"
    if kind is ast.ArrayLiteral:
        rows = "; ".join(", ".join(_array_item(item) for item in row) for row in expression.rows)
        return f"[{rows}]"
    if kind is ast.Colon:
        return _colon(expression)
    if kind is ast.Index:
        target, level = _expression(expression.target)
        if level < _PRIMARY_LEVEL:
            target = f"({target})"
        indices = ", ".join(_array_item(index) for index in expression.indices)
        return f"{target}[{indices}]"
    if kind is ast.ComponentValues:
        branches = " | ".join(
            f"{print_expression(b.selector)} {_operator(b)} {print_expression(b.value)}"
            for b in expression.branches
        )
        return f"comp({_values(expression.arguments)}) {{ {branches} }}"
    if kind in (ast.CaseExpression, ast.StochasticExpression):
        return f"({_choice(expression)})"
    raise TypeError(f"not an expression node: {kind.__name__}")


def _array_item(item) -> str:
    return _colon(item) if isinstance(item, ast.Colon) else print_expression(item)


def _colon(colon: ast.Colon) -> str:
    parts = [colon.start, colon.step, colon.stop]
    if all(part is None for part in parts):
        return ":"
    return " : ".join(print_expression(part) for part in parts if part is not None)


def _values(values) -> str:
    return ", ".join(print_expression(value) for value in values)


def _number(value: float) -> str:
    if math.isinf(value):
        return "1e999" if value > 0 else "-1e999"
    if value == int(value) and abs(value) < 1e16:
        return str(int(value))
    return repr(value)


def _string(value: str) -> str:
    return '"' + value.replace("\\", "\\\\").replace('"', '\\"') + '"'


def _percent(value: float) -> str:
    text = _number(value)
    if "e" in text:  # a probability is written without an exponent
        text = f"{value:.20f}".rstrip("0").rstrip(".")
    return f"{text}%"


def _choice(expression) -> str:
    """A conditional or stochastic value without parentheses (a definition's whole body)."""
    if isinstance(expression, ast.CaseExpression):
        parts = [
            f"case {print_expression(b.condition)} : {_definition_value(b.value)}"
            for b in expression.branches
        ]
    else:
        parts = [
            f"{_percent(b.percent)} : {_definition_value(b.value)}" for b in expression.branches
        ]
    return " ".join([*parts, f"else : {_definition_value(expression.otherwise)}"])


def _definition_value(expression) -> str:
    if isinstance(expression, ast.CaseExpression | ast.StochasticExpression):
        return _choice(expression)
    return print_expression(expression)


# ---------------------------------------------------------------------------------- rule bodies
def print_body(body: ast.Body) -> str:
    """A rule body as CGA text (a sequence, or ``case``/percent branches with ``else``)."""
    if isinstance(body, ast.Sequence):
        return " ".join(_item(item) for item in body.items) if body.items else "NIL"
    if isinstance(body, ast.ConditionalBody):
        parts = [
            f"case {print_expression(b.condition)} : {print_body(b.body)}" for b in body.branches
        ]
    else:
        parts = [f"{_percent(b.percent)} : {print_body(b.body)}" for b in body.branches]
    return " ".join([*parts, f"else : {print_body(body.otherwise)}"])


def _item(item) -> str:
    kind = type(item)
    if kind is ast.Successor:
        text = item.name
        if item.args or item.called:
            text += f"({_values(item.args)})"
        return text + "." if item.leaf else text
    if kind is ast.Nil:
        return "NIL"
    if kind is ast.Push:
        return f"[ {print_body(item.body)} ]"
    if kind is ast.Extrude:
        return f"extrude({print_expression(item.height)})"
    if kind is ast.Split:
        if item.texture is not None:
            head = f"split({_UV_DIRECTIONS[item.axis]}, {item.texture})"
        else:
            head = f"split({item.axis}{'' if item.adjust else ', noAdjust'})"
        return f"{head} {_split_group(item.group)}"
    if kind is ast.Comp:
        branches = " | ".join(
            f"{b.selector} {_operator(b)} {print_body(b.body)}" for b in item.branches
        )
        return f"comp({item.kind}) {{ {branches} }}"
    if kind in (ast.Translate, ast.Scale):
        name = "t" if kind is ast.Translate else "s"
        return f"{name}({', '.join(_coordinate(c) for c in (item.x, item.y, item.z))})"
    if kind is ast.Rotate:
        angles = _values((item.x, item.y, item.z))
        if item.pivot != "origin":
            return f"r({_PIVOT_NAMES[item.pivot]}, {angles})"
        return f"r({angles})"
    if kind is ast.Center:
        return f"center({item.axes})"
    if kind is ast.Label:
        return f"label({print_expression(item.name)})"
    if kind is ast.Set:
        return f"set({item.attribute}, {print_expression(item.value)})"
    if kind is ast.Insert:
        arguments = [print_expression(item.primitive), *map(print_expression, item.options)]
        arguments += [_keyword(k) for k in item.parameters]
        return f"i({', '.join(arguments)})"
    if kind is ast.Print:
        return f"print({_values(item.values)})"
    if kind is ast.Report:
        return f"report({_values((item.key, item.value))})"
    if kind is ast.Operation:
        return _operation(item)
    if kind is ast.DynamicImport:
        overrides = ", ".join(_keyword(k) for k in item.overrides)
        call = f"({_values(item.args)})" if item.args else ""
        return f"{item.prefix}({overrides}).{item.rule}{call}"
    raise TypeError(f"not a rule body item: {kind.__name__}")


def _coordinate(coordinate: ast.Coordinate) -> str:
    return ("'" if coordinate.relative else "") + print_expression(coordinate.value)


def _keyword(keyword: ast.Keyword) -> str:
    return f"{keyword.name} = {print_expression(keyword.value)}"


def _split_group(group: ast.SplitGroup) -> str:
    parts = []
    for part in group.parts:
        if isinstance(part, ast.SplitGroup):
            parts.append(_split_group(part))
        else:
            size = _MODE_PREFIX[part.mode] + print_expression(part.size)
            parts.append(f"{size} : {print_body(part.body)}")
    return "{ " + " | ".join(parts) + " }" + ("*" if group.repeat else "")


def _operation(operation: ast.Operation) -> str:
    name = operation.name
    keyless = bool(operation.branches) and all(b.key is None for b in operation.branches)
    if keyless and name in _ALTERNATIVES and not operation.arguments:
        return f"{name} {{ {' | '.join(print_body(b.body) for b in operation.branches)} }}"
    if keyless and name == "inline":
        (branch,) = operation.branches
        if not operation.arguments:
            return f"inline {{ {print_body(branch.body)} }}"
        # inline(strategy) Rule: the operation takes the one item after it (op_inline), or a
        # block of operations; an inline taking an inline is written with its block, or the
        # outer one would take the inner one alone
        body = print_body(branch.body)
        one = (
            isinstance(branch.body, ast.Sequence)
            and len(branch.body.items) == 1
            and isinstance(branch.body.items[0], ast.Successor)
        )
        return f"inline({_arguments(operation.arguments)}) " + (body if one else f"{{ {body} }}")
    text = f"{name}({_arguments(operation.arguments)})"
    if keyless:
        return text + f" {{ {' | '.join(print_body(b.body) for b in operation.branches)} }}"
    if operation.branches or operation.repeat:
        # splitAndSetbackPerimeter's remainder stands in a block of its own after the pattern
        pattern = [b for b in operation.branches if not _perimeter_remainder(name, b)]
        rest = [b for b in operation.branches if _perimeter_remainder(name, b)]
        text += f" {{ {' | '.join(map(_branch, pattern))} }}" + ("*" if operation.repeat else "")
        if rest:
            text += f" {{ {' | '.join(map(_branch, rest))} }}"
    return text


def _operator(branch) -> str:
    """``:``, ``=`` (merged) or ``=:`` (connected sets) of a comp-like branch."""
    return "=:" if branch.connected else "=" if branch.merge else ":"


def _perimeter_remainder(name: str, branch: ast.OperationBranch) -> bool:
    return (
        name == "splitAndSetbackPerimeter"
        and branch.depth is None
        and isinstance(branch.key, ast.Name)
        and branch.key.name == "remainder"
    )


def _branch(branch: ast.OperationBranch) -> str:
    operator = _operator(branch)
    key = _MODE_PREFIX[branch.mode] + print_expression(branch.key)
    if branch.depth is not None:
        key += f" : {print_expression(branch.depth)}"  # a choice in parentheses
    return f"{key} {operator} {print_body(branch.body)}"


def _arguments(arguments) -> str:
    texts = []
    for argument in arguments:
        if argument.kind == "keyword":
            texts.append(f"{argument.name} = {print_expression(argument.value)}")
        else:
            texts.append(_ARGUMENT_PREFIX[argument.kind] + print_expression(argument.value))
    return ", ".join(texts)


# ---------------------------------------------------------------------------------- definitions
def _annotation(annotation: ast.Annotation) -> str:
    if not annotation.args and not annotation.keywords:
        return f"@{annotation.name}"
    arguments = [*map(print_expression, annotation.args), *map(_keyword, annotation.keywords)]
    return f"@{annotation.name}({', '.join(arguments)})"


def _with_clause(definition) -> str:
    if not definition.local_variables:
        return ""
    variables = " ".join(
        f"{v.name} := {_definition_value(v.value)}" for v in definition.local_variables
    )
    return f" with ({variables})"


def _parameters(parameters) -> str:
    return f"({', '.join(p.name for p in parameters)})" if parameters else ""


def _definition(definition) -> str:
    lines = [_annotation(a) for a in definition.annotations]
    kind = type(definition)
    if kind is ast.Rule:
        head = ("extension " if definition.extension else "") + definition.name
        head += _parameters(definition.params) + _with_clause(definition)
        lines.append(f"{head} --> {print_body(definition.body)}")
        return "\n".join(lines)
    if kind is ast.Attribute:
        head = f"attr {definition.name}"
    elif kind is ast.Constant:
        head = f"const {definition.name}"
    else:
        head = definition.name + _parameters(definition.params)
    lines.append(f"{head}{_with_clause(definition)} = {_definition_value(_value(definition))}")
    return "\n".join(lines)


def _value(definition):
    return definition.body if isinstance(definition, ast.Function) else definition.value


def _import(item: ast.Import) -> str:
    lines = [_annotation(a) for a in item.annotations]
    text = "import "
    if item.prefix is not None:
        text += item.prefix
        if item.styles:
            text += f" ({', '.join(item.styles)})"
        text += " : "
    text += _string(item.path)
    arguments = [*item.protected, *map(_keyword, item.overrides)]
    arguments += [f"{r.name}{_parameters(r.params)} --> {print_body(r.body)}" for r in item.rules]
    if arguments or item.protect_all:
        text += f" ({', '.join(arguments)})"
    lines.append(text)
    return "\n".join(lines)


def print_grammar(grammar: ast.RuleFile) -> str:
    """The whole file as CGA text: version, imports, definitions, then the style names."""
    parts = []
    if grammar.version is not None:
        parts.append(f"version {_string(grammar.version)}")
    parts += [_import(item) for item in grammar.imports]
    parts += [_definition(definition) for definition in grammar.definitions]
    parts += [f"style {name}" for name in grammar.styles]
    return "\n\n".join(parts) + "\n"

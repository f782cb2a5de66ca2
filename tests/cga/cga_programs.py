"""Random well-formed CGA programs, from the language's definition rather than from examples.

:func:`generate` makes one program from a seed: attrs with annotations, consts, functions (with
parameters, ``with`` locals, conditional and stochastic bodies), rules with parameters, with
conditional and stochastic bodies, and operations drawn from the signatures of CityEngine's CGA
reference (op_*.html, func_*.html: each operation with arguments of the kinds its page lists:
axes, selectors, extrusion types, roof value types, file paths, colours, booleans), nested
blocks, push/pop, arrays, string and boolean expressions, and now and then an import of a second
generated file (resolvable: both files are written to the same folder).

The programs are well-formed as CityEngine's compiler sees them: every name is defined before it
is used or is a rule defined in the file, every call has the number and types of arguments its
signature takes, values keep their types (float, string, bool, float array), and ``set`` gives
an attr a value of its own type. Rules call only rules made after them, so a derivation ends;
split sizes are positive sizes of a metre or more, so that repeats stay small on a 12 x 8 m lot.
Nothing else is promised: a value may be NaN or out of an operation's range at run time, which
CityEngine's runtime warns about, and which is what the property looks for.
"""

from __future__ import annotations

import contextlib
import io
import random
import re
import traceback
from dataclasses import dataclass, field
from pathlib import Path

from shapegen.grammar.names import BUILTIN_FUNCTIONS

__all__ = ["KNOWN_REFUSALS", "LOT", "GeneratedProgram", "Outcome", "check", "generate"]

LOT = (12.0, 8.0)  # metres, the lot every program is derived on
MAX_SHAPES = 20_000

#: Refusals of well-formed forms the parser does not take yet: (message fragment, the form of
#: :attr:`GeneratedProgram.forms` that brings it) -> a description of the gap and the reference
#: page that allows the form. Remove an entry when the parser takes
#: the form (tests/cga/test_generated_programs.py's strict xfails show when).
KNOWN_REFUSALS: dict[tuple[str, str], str] = {}

FLOAT, STRING, BOOL, FLOATS = "float", "string", "bool", "float[]"
# the geometry a rule is written for: a lot's face, a volume, or edges, vertices and points
# (comp(e), comp(v), scatter), on which only operations that need no faces are written
FACE, MASS, OTHER = "face", "mass", "other"

# func_*.html: name -> (argument types, result type)
BUILTINS: dict[str, tuple[tuple[str, ...], str]] = {
    **{name: ((FLOAT,), FLOAT) for name in ("sin", "cos", "tan", "abs", "floor", "ceil", "rint")},
    "sqrt": ((FLOAT,), FLOAT),
    "exp": ((FLOAT,), FLOAT),
    "min": ((FLOAT, FLOAT), FLOAT),
    "max": ((FLOAT, FLOAT), FLOAT),
    "pow": ((FLOAT, FLOAT), FLOAT),
    "atan2": ((FLOAT, FLOAT), FLOAT),
    "clamp": ((FLOAT, FLOAT, FLOAT), FLOAT),
    "rand": ((FLOAT, FLOAT), FLOAT),
    "len": ((STRING,), FLOAT),
    "count": ((STRING, STRING), FLOAT),
    "find": ((STRING, STRING, FLOAT), FLOAT),
    "float": ((STRING,), FLOAT),
    "size": ((FLOATS,), FLOAT),
    "sum": ((FLOATS,), FLOAT),
    "str": ((FLOAT,), STRING),
    "toUpperCase": ((STRING,), STRING),
    "toLowerCase": ((STRING,), STRING),
    "substring": ((STRING, FLOAT, FLOAT), STRING),
    "replace": ((STRING, STRING, STRING), STRING),
    "colorRGBToHex": ((FLOAT, FLOAT, FLOAT), STRING),
    "p": ((FLOAT,), BOOL),
    "isnan": ((FLOAT,), BOOL),
    "bool": ((FLOAT,), BOOL),
}
# attr_scope, attr_split, attr_comp, func_geometry*, attr_seedian
SHAPE_FLOATS = (
    *("scope.sx", "scope.sy", "scope.sz", "scope.tx", "scope.ty", "scope.tz", "scope.ry"),
    *("split.index", "split.total", "comp.index", "comp.total", "seedian"),
    *("geometry.area", "geometry.area()", "geometry.nVertices", "geometry.height"),
)
WORDS = ("brick", "glass", "roof", "a;b;c;", "", "façade", 'say \\"hi\\"', "#ff8800", "a\\nb")
COLOURS = ("#ff0000", "#ffffff", "#336699", "#a0a0a0")
COMP_FACE_SELECTORS = (
    "front",
    "back",
    "left",
    "right",
    "top",
    "bottom",
    "side",
    "vertical",
    "horizontal",
    "all",
    "object.top",
    "world.up",
    "street.front",
)
SETBACK_SELECTORS = ("front", "back", "left", "right", "side", "all", "streetSide")
EXTRUSION_TYPES = ("world.y", "world.up", "face.normal", "vertex.normal", "world.up.flatTop")
ANNOTATIONS_FLOAT = (
    "@Angle",
    "@Distance",
    "@Percent",
    "@Hidden",
    '@Group("Sizes", 1)',
    "@Order(2)",
)


#: Operations as the Syntax sections of their reference pages list them (op_*.html), which keep
#: the kind of geometry they are given.
VARIANTS = (
    "alignScopeToGeometry(zUp, 0, world.lowest)",
    "alignScopeToGeometryBBox(xz)",
    "rotate(rel, scope, 0, 45, 0)",
    "translate(abs, world, 1, 0, 1)",
    "setupProjection(0, scope.xz, 1, 1, 0, 0, 1)",
    "setupProjection(0, world.xy, '1, '1)",
    "normalizeUV(0, uv, separatePerFace)",
    'deleteTags("a")',
    'deleteTags("a", faces)',
    "cleanupGeometry(vertices, 0.1)",
    'tag("x", edges)',
    "copyUV(0, 1)",
    "rotateUV(0, 45)",
    "scaleUV(0, 2, 2)",
    "translateUV(0, 1, 1)",
    "resetMaterial(all)",
    "convexify(2)",
    "setNormals(soft)",
    "setPivot(yzx, 3)",
    "rectify(5)",
    "mirrorScope(true, false, false)",
    "modify(f) { top : s('1, '1, '1) }",
    "trim",
    "r(scopeOrigin, 0, 45, 0)",
    'insertAlongUV(0, "x.obj", 1)',
)

#: Decorations (operations that keep the geometry) written as one of a list, by form; the other
#: forms are built from expressions (``_Writer.decoration``).
DECORATIONS = {
    "set shape attribute": (
        "set(material.opacity, 0.5)",
        "set(material.color.r, 0.3)",
        'set(material.colormap, "wall.jpg")',
        "set(trim.vertical, false)",
        "set(trim.horizontal, true)",
        'set(material.name, "stone")',
    ),
    "label": ('label("wall")', 'label("roof")'),
    "tag": ('tag("a")', 'tag("b")'),
    "center": tuple(f"center({axes})" for axes in ("x", "y", "z", "xy", "xz", "yz", "xyz")),
    "align": (
        "alignScopeToAxes()",
        "alignScopeToAxes(y)",
        "alignScopeToGeometry(yUp, 0, 0)",
        "alignScopeToGeometry(zUp, any, longest)",
        "setPivot(xyz, 0)",
        "mirror(true, false, false)",
        "mirrorScope(false, false, true)",
    ),
    "texture": (
        "setupProjection(0, scope.xy, 1.5, 1) projectUV(0)",
        'texture("facade.jpg")',
        "tileUV(0, 2, 2)",
        "deleteUV(0)",
        'setMaterial(["color.r", "1.0", "color.g", "0.5"])',
    ),
    "variant": VARIANTS,
    "misc": (
        "reverseNormals()",
        "reverseNormals",
        "resetMaterial()",
        "deleteHoles()",
        "deleteHoles",
        "cleanupGeometry(all, 0.01)",
        "convexify()",
        "reduceGeometry(0.05)",
        "softenNormals(30)",
        "setNormals(hard)",
    ),
}

#: Forms drawn less often than the others, with the share of their draws kept: each would
#: otherwise be in a third of the programs, and a program the parser refuses is not derived.
RARE = {"perimeter": 0.3, "inline": 0.3, "degenerate": 0.5, "splitArea": 0.5}


def low_high(name: str) -> tuple[int, int]:
    """The numbers of arguments CityEngine's builtin ``name`` takes (all its forms)."""
    return BUILTIN_FUNCTIONS.get(name, (len(BUILTINS[name][0]),) * 2)


@dataclass
class GeneratedProgram:
    """A generated program: ``files`` maps file names to texts, ``main`` names the one to load."""

    seed: int
    files: dict[str, str]
    main: str = "generated.cga"
    forms: set[str] = field(default_factory=set)  # which kinds of form it holds

    @property
    def text(self) -> str:
        return self.files[self.main]


@dataclass
class _Callable:
    name: str
    params: tuple[str, ...]
    result: str = ""
    geometry: str = FACE


class _Writer:
    def __init__(self, rng: random.Random, prefix: str = "", library: _Writer | None = None):
        self.rng = rng
        self.values: dict[str, str] = {}  # attr and const names -> type
        self.attrs: dict[str, str] = {}
        self.functions: list[_Callable] = []
        self.comp_functions: list[str] = []  # parameterless functions giving one value an edge
        self.rules: list[_Callable] = []
        self.library = library  # an imported file's writer, read under its prefix
        self.prefix = prefix
        self.forms: set[str] = set()
        self.counter = 0

    # names ----------------------------------------------------------------------------------
    def fresh(self, stem: str) -> str:
        self.counter += 1
        return f"{self.prefix}{stem}{self.counter}"

    def chance(self, p: float) -> bool:
        return self.rng.random() < p

    # expressions ----------------------------------------------------------------------------
    def number(self, low: float = -5, high: float = 20) -> str:
        if self.chance(0.05):
            self.forms.add("number forms")
            return self.rng.choice([".5", "1e1", "2.5E-1", "0.0"])
        value = self.rng.choice(
            [
                self.rng.randint(int(low), int(high)),
                round(self.rng.uniform(low, high), self.rng.randint(1, 3)),
            ]
        )
        return str(value) if value >= 0 else f"({value})"

    def expression(self, kind: str, env: dict[str, str], depth: int = 0) -> str:
        rng = self.rng
        leaf = depth >= 2 or self.chance(0.4)
        names = [n for n, t in env.items() if t == kind]
        names += [n for n, t in self.values.items() if t == kind]
        if self.library is not None:
            names += [f"lib.{n}" for n, t in self.library.attrs.items() if t == kind]
        if leaf:
            if names and self.chance(0.5):
                return rng.choice(names)
            return self.literal(kind)
        if kind == FLOAT:
            return self.float_expression(env, depth)
        if kind == STRING:
            return self.string_expression(env, depth)
        if kind == BOOL:
            return self.bool_expression(env, depth)
        return self.array_expression(env, depth)

    def literal(self, kind: str) -> str:
        if kind == FLOAT:
            return self.rng.choice([self.number(), self.rng.choice(SHAPE_FLOATS)])
        if kind == STRING:
            return f'"{self.rng.choice(WORDS)}"'
        if kind == BOOL:
            return self.rng.choice(["true", "false"])
        return self.array_literal()

    def array_literal(self) -> str:
        self.forms.add("array")
        items = [self.number(0, 9) for _ in range(self.rng.randint(1, 4))]
        if self.chance(0.2):
            return f"[{', '.join((items * 2)[:2])}; {', '.join((items * 2)[-2:])}]"
        return f"[{', '.join(items)}]"

    def call(self, result: str, env, depth) -> str | None:
        options = [(n, s) for n, s in BUILTINS.items() if s[1] == result]
        options += [(f.name, (f.params, f.result)) for f in self.functions if f.result == result]
        if not options:
            return None
        name, (params, _) = self.rng.choice(options)
        args = ", ".join(self.expression(p, env, depth + 1) for p in params)
        return f"{name}({args})"

    def float_expression(self, env, depth) -> str:
        rng = self.rng
        form = rng.choice(["binary", "binary", "unary", "call", "call", "case", "index", "paren"])
        if form == "binary":
            op = rng.choice(["+", "-", "*", "/", "%"])
            return f"{self.expression(FLOAT, env, depth + 1)} {op} {self.operand(env, depth)}"
        if form == "unary":
            return f"-{self.operand(env, depth)}"
        if form == "case":
            self.forms.add("case expression")
            return f"({self.choice_value(FLOAT, env, depth)})"
        if form == "index":
            self.forms.add("array index")
            return f"({self.expression(FLOATS, env, depth + 1)})[0]"
        if form == "paren":
            return f"({self.expression(FLOAT, env, depth + 1)})"
        return self.call(FLOAT, env, depth) or self.literal(FLOAT)

    def operand(self, env, depth) -> str:
        text = self.expression(FLOAT, env, depth + 1)
        return text if text.replace(".", "").replace("_", "").isalnum() else f"({text})"

    def string_expression(self, env, depth) -> str:
        form = self.rng.choice(["concat", "call", "number", "case", "array"])
        if form == "array":  # arrayTypes.html: a string joined to an array is a string
            self.forms.add("array string")
            return f'"values: " + ({self.expression(FLOATS, env, depth + 1)})'

        if form == "concat":
            self.forms.add("string concatenation")
            other = self.expression(self.rng.choice([STRING, FLOAT]), env, depth + 1)
            return f"{self.expression(STRING, env, depth + 1)} + {other}"
        if form == "number":
            return f'"n" + {self.operand(env, depth)}'
        if form == "case":
            return f"({self.choice_value(STRING, env, depth)})"
        return self.call(STRING, env, depth) or self.literal(STRING)

    def bool_expression(self, env, depth) -> str:
        form = self.rng.choice(["compare", "compare", "logic", "not", "call", "equal", "arrays"])
        if form == "arrays":  # arrayTypes.html: arrays compare as wholes
            self.forms.add("array comparison")
            op = self.rng.choice(["==", "!=", ">", ">="])
            left, right = (self.expression(FLOATS, env, depth + 1) for _ in range(2))
            return f"({left}) {op} ({right})"
        if form == "compare":
            op = self.rng.choice(["<", "<=", ">", ">=", "==", "!="])
            return f"{self.expression(FLOAT, env, depth + 1)} {op} {self.operand(env, depth)}"
        if form == "equal":
            op = self.rng.choice(["==", "!="])
            kind = self.rng.choice([STRING, BOOL])
            left, right = (self.expression(kind, env, depth + 1) for _ in range(2))
            return f"{left} {op} ({right})"
        if form == "logic":
            op = self.rng.choice(["&&", "||"])
            left, right = (self.expression(BOOL, env, depth + 1) for _ in range(2))
            return f"({left}) {op} ({right})"
        if form == "not":
            return f"!({self.expression(BOOL, env, depth + 1)})"
        return self.call(BOOL, env, depth) or self.literal(BOOL)

    def array_expression(self, env, depth) -> str:
        """A float[] (arrayTypes.html): items, a range, a column, element-wise operators."""
        rng = self.rng
        form = rng.choice(["items", "items", "range", "column", "elementwise", "unary"])
        if form == "range":
            self.forms.add("array range")
            return rng.choice(["[1:5]", "[1:2:5]", f"[1:{rng.randint(1, 4)}]"])
        if form == "column":
            return f"[{'; '.join(self.number(0, 9) for _ in range(rng.randint(1, 3)))}]"
        if form == "elementwise":
            self.forms.add("array element-wise")
            op = rng.choice([".+", ".-", ".*", "./", ".%"])
            array = self.array_literal()  # two arrays of equal dimensions, or an array and a value
            other = self.operand(env, depth) if self.chance(0.5) else array
            return f"{array} {op} {other}"
        if form == "unary":
            return f"{rng.choice(['.-', '.+'])}{self.array_literal()}"
        items = [self.expression(FLOAT, env, depth + 1) for _ in range(rng.randint(1, 3))]
        return f"[{', '.join(items)}]"

    def choice_value(self, kind: str, env, depth) -> str:
        """``case c : v ... else : v`` or ``30% : v ... else : v`` (func bodies, case_value)."""
        parts = []
        if self.chance(0.6):
            for _ in range(self.rng.randint(1, 3)):
                condition = self.expression(BOOL, env, depth + 1)
                parts.append(f"case {condition} : {self.expression(kind, env, depth + 1)}")
        else:
            self.forms.add("stochastic value")
            left = 100
            for _ in range(self.rng.randint(1, 3)):
                share = self.rng.randint(0, left)
                left -= share
                percent = share if self.chance(0.7) else share * 0.5
                parts.append(f"{percent}% : {self.expression(kind, env, depth + 1)}")
        return " ".join([*parts, f"else : {self.expression(kind, env, depth + 1)}"])

    def size(self, env) -> str:
        """A positive split size of a metre or more."""
        rng = self.rng
        form = rng.choice(["number", "number", "max", "attr", "rand"])
        if form == "max":
            return f"max(1, {self.expression(FLOAT, env, 2)})"
        if form == "attr" and (sizes := [n for n in self.attrs if n.startswith("size")]):
            return rng.choice(sizes)
        if form == "rand":
            return f"rand(1, {rng.randint(2, 4)})"
        return str(rng.choice([1, 1.5, 2, 2.5, 3, 4]))

    # definitions ----------------------------------------------------------------------------
    def attribute(self) -> str:
        rng = self.rng
        kind = rng.choice([FLOAT, FLOAT, STRING, BOOL, FLOATS])
        annotations = []
        if kind == FLOAT and self.chance(0.5):
            name = self.fresh("size")
            low = rng.randint(1, 3)
            annotations.append(
                rng.choice([f"@Range(min={low}, max={low + 4})", f"@Range({low}, {low + 4})"])
            )
            value = str(rng.randint(low, low + 4))
        else:
            name = self.fresh("a")
            if "start" not in self.values and not self.prefix and self.chance(0.1):
                self.forms.add("keyword as name")
                name = "start"
            value = self.expression(kind, {}, 1)
            if kind == FLOAT and self.chance(0.4):
                annotations.append(rng.choice(ANNOTATIONS_FLOAT))
            if kind == STRING and self.chance(0.5):
                words = ", ".join(f'"{w}"' for w in ("brick", "glass", "roof"))
                annotations.append(rng.choice([f"@Enum({words})", "@Color", "@File", "@Hidden"]))
                if annotations[-1] == "@Color":
                    value = f'"{rng.choice(COLOURS)}"'
        if self.chance(0.3):
            annotations.append(f'@Description("{name} of the building")')
        if self.chance(0.15):
            self.forms.add("with")
            local = self.fresh("w")
            value = f"{value}"  # an attr's with-clause: evaluated once when it is read
            head = f"attr {name} with ({local} := {self.expression(kind, {}, 2)}) = {local}"
        else:
            head = f"attr {name} = {value}"
        self.values[name] = kind
        self.attrs[name] = kind
        self.forms.add("attr")
        return "\n".join([*annotations, head])

    def constant(self) -> str:
        kind = self.rng.choice([FLOAT, STRING, BOOL])
        name = self.fresh("k")
        text = f"const {name} = {self.expression(kind, {}, 1)}"
        if self.chance(0.15):
            self.forms.add("with")
            text = f"const {name} with (x := {self.array_literal()}) = x[0] > 1"
            kind = BOOL
        self.values[name] = kind
        self.forms.add("const")
        return text

    def function(self) -> str:
        rng = self.rng
        if self.chance(0.15):
            return self.comp_function()
        result = rng.choice([FLOAT, FLOAT, STRING, BOOL])
        params = tuple(rng.choice([FLOAT, STRING, BOOL]) for _ in range(rng.randint(0, 3)))
        name = self.fresh("f")
        if self.chance(0.1):
            # a builtin's name with another number of parameters: an overload of its own
            builtins = [n for n in BUILTINS if not low_high(n)[0] <= len(params) <= low_high(n)[1]]
            name = rng.choice(builtins)
            if any(f.name == name and len(f.params) == len(params) for f in self.functions):
                name = self.fresh("f")
            else:
                self.forms.add("builtin name overloaded")
        env = {f"p{i}": t for i, t in enumerate(params)}
        head = name + (f"({', '.join(env)})" if params else "")
        if self.chance(0.2):
            self.forms.add("with")
            local = f"v{self.counter}"
            head += f" with ({local} := {self.expression(result, env, 1)})"
            env[local] = result
        if self.chance(0.4):
            self.forms.add("function case")
            body = self.choice_value(result, env, 1)
        else:
            body = self.expression(result, env, 0)
        self.functions.append(_Callable(name, params, result))  # after: no recursion
        self.forms.add("function")
        return f"{head} = {body}"

    def comp_function(self) -> str:
        """func_comp: ``name = comp(fe) { selector : value | ... }``, a float array with one value
        per edge, which setback() takes as its distances."""
        self.forms.add("comp function")
        name = self.fresh("edges")
        branches = []
        for _ in range(self.rng.randint(1, 3)):
            selector = self.rng.choice(
                [
                    "front",
                    "back",
                    "left",
                    "right",
                    "side",
                    "all",
                    "street.front",
                    "street.side",
                    "object.front",
                ]
            )
            if self.chance(0.15):
                self.forms.add("comp function case")
                value = f"case scope.sx > {self.rng.randint(2, 9)} : 2 else : 1"
            else:
                value = self.rng.choice(["1", "2", "0.5", "comp.index % 2 + 1"])
            branches.append(f"{selector} {self.rng.choice([':', ':', '='])} {value}")
        self.comp_functions.append(name)
        return f"{name} = comp(fe) {{ {' | '.join(branches)} }}"

    # rules ----------------------------------------------------------------------------------
    def rule_call(self, geometry: str, env, after: int) -> str:
        """A successor: a rule made after rule ``after`` (a new one now and then), or NIL."""
        candidates = [r for r in self.rules[after + 1 :] if r.geometry == geometry]
        if self.library is not None and self.chance(0.1):
            library_rules = [r for r in self.library.rules if r.geometry == geometry]
            if library_rules:
                self.forms.add("import")
                floats = [n for n, t in self.library.attrs.items() if t == FLOAT]
                if floats and self.chance(0.3):
                    self.forms.add("dynamic import")
                    rule = self.rng.choice(library_rules)
                    call = self.call_text(rule, env, "")
                    return f"lib({self.rng.choice(floats)} = {self.size(env)}).{call}"
                return self.call_text(self.rng.choice(library_rules), env, "lib.")
        if not candidates or (len(self.rules) < 6 and self.chance(0.35)):
            if len(self.rules) >= 8:
                return "NIL"
            params = tuple(
                self.rng.choice([FLOAT, STRING, BOOL])
                for _ in range(self.rng.choice([0, 0, 0, 1, 2]))
            )
            rule = _Callable(self.fresh("R"), params, geometry=geometry)
            self.rules.append(rule)
            candidates = [rule]
        return self.call_text(self.rng.choice(candidates), env, "")

    def call_text(self, rule: _Callable, env, prefix: str) -> str:
        if not rule.params:
            return prefix + rule.name + ("()" if self.chance(0.05) else "")
        self.forms.add("rule parameters")
        return f"{prefix}{rule.name}({', '.join(self.expression(t, env, 1) for t in rule.params)})"

    def body(self, geometry: str, env, index: int, depth: int = 0) -> str:
        """A rule body: a sequence, or (at the top) case or percent branches."""
        if depth == 0 and self.chance(0.25):
            self.forms.add("conditional rule")
            branches = [
                f"case {self.expression(BOOL, env, 1)} : {self.sequence(geometry, env, index, 1)}"
                for _ in range(self.rng.randint(1, 2))
            ]
            return " ".join([*branches, f"else : {self.sequence(geometry, env, index, 1)}"])
        if depth == 0 and self.chance(0.15):
            self.forms.add("stochastic rule")
            share = self.rng.randint(1, 99)
            return (
                f"{share}% : {self.sequence(geometry, env, index, 1)} "
                f"else : {self.sequence(geometry, env, index, 1)}"
            )
        return self.sequence(geometry, env, index, depth)

    def sequence(self, geometry: str, env, index: int, depth: int) -> str:
        items = [self.decoration(env, geometry) for _ in range(self.rng.choice([0, 0, 1]))]
        if depth < 2:
            item, geometry = self.structural(geometry, env, index, depth)
            if item:
                items.append(item)
        if not items or not items[-1].endswith("}"):
            items.append(self.rule_call(geometry, env, index))
        text = items[0]
        for item in items[1:]:
            text += self.separator() + item
        return text

    def separator(self) -> str:
        """Between two items: a space, a new line, or a comment (cgaindex: // and /* */)."""
        roll = self.rng.random()
        if roll < 0.8:
            return " "
        self.forms.add("layout")
        if roll < 0.9:
            return "\n\t"
        if roll < 0.95:
            return " /* then */ "
        return " // then\n\t\t"

    def decoration(self, env, geometry: str = FACE) -> str:
        """An operation that keeps the geometry (appearance, attributes, reports, transforms)."""
        rng = self.rng
        forms = ["color", "set", "report", "print", "t", "r", "s", "label", "center", "push"]
        if geometry != OTHER:  # these need faces (op_alignScopeToGeometry, op_tag...)
            forms += ["align", "misc", "texture", "tag", "variant"]
        form = rng.choice(forms)
        self.forms.add(form)
        if form == "color":
            if self.chance(0.5):
                return f'color("{rng.choice(COLOURS)}")'
            channels = (str(round(rng.random(), 2)) for _ in range(rng.choice([3, 4])))
            return f"color({', '.join(channels)})"
        if form == "set" and not self.attrs:
            form = "label"
        if form == "set" and self.chance(0.25):
            self.forms.add("set shape attribute")
            return rng.choice(DECORATIONS["set shape attribute"])
        if form == "set":
            name = rng.choice(list(self.attrs))
            return f"set({name}, {self.expression(self.attrs[name], env, 1)})"
        if form == "report":
            kind = rng.choice([FLOAT, STRING, BOOL])
            key = rng.choice(["area", "floors", "kind"])
            return f'report("{key}", {self.expression(kind, env, 1)})'
        if form == "print":
            return f"print({self.expression(rng.choice([FLOAT, STRING, BOOL]), env, 1)})"
        if form == "t":
            return f"t({self.coordinate(env)}, {self.coordinate(env)}, {self.coordinate(env)})"
        if form == "s":
            return f"s({', '.join(self.coordinate(env, scale=True) for _ in range(3))})"
        if form == "r":
            angles = ", ".join(str(rng.choice([0, 0, 15, 45, 90, -30])) for _ in range(3))
            return rng.choice(
                [f"r({angles})", f"r(scopeCenter, {angles})", f"rotateScope({angles})"]
            )
        if form == "push":
            return f"[ {self.decoration(env, geometry)} ]"
        return rng.choice(DECORATIONS[form])

    def coordinate(self, env, scale: bool = False) -> str:
        if self.chance(0.3):
            self.forms.add("relative coordinate")
            return f"'{self.rng.choice([0.5, 1, 0.25])}"
        if scale:
            return self.size(env)
        return self.expression(FLOAT, env, 2)

    def structural(self, geometry: str, env, index: int, depth: int) -> tuple[str, str]:
        """An operation that makes new shapes or changes the geometry; the geometry after it."""
        rng = self.rng
        sub = lambda g: self.body(g, env, index, depth + 1)  # noqa: E731
        if geometry == OTHER:
            form = rng.choice(["insert", "push", "case", "none"])
        elif geometry == FACE:
            form = rng.choice(
                [
                    "extrude",
                    "extrude",
                    "roof",
                    "split",
                    "offset",
                    "setback",
                    "shape",
                    "inner",
                    "comp_e",
                    "scatter",
                    "envelope",
                    "taper",
                    "splitArea",
                    "perimeter",
                    "degenerate",
                    "case",
                    "push",
                    "bool",
                    "inline",
                    "insert",
                    "none",
                ]
            )
        else:
            form = rng.choice(
                [
                    "comp",
                    "comp",
                    "split",
                    "split",
                    "insert",
                    "push",
                    "footprint",
                    "case",
                    "primitive",
                    "none",
                ]
            )
        if form in RARE and not self.chance(RARE[form]):
            form = "push"
        self.forms.add(form)
        if form == "extrude":
            height = self.size(env)
            if self.chance(0.3):
                return f"extrude({rng.choice(EXTRUSION_TYPES)}, {height})", MASS
            return f"extrude({height})", MASS
        if form == "roof":
            angle = rng.choice([20, 30, 45])
            text = rng.choice(
                [
                    f"roofHip({angle})",
                    f"roofHip({angle}, 0.5)",
                    f"roofHip({angle}, 0.5, true)",
                    f"roofGable({angle})",
                    f"roofGable({angle}, 0.5, 0.5)",
                    f"roofGable({angle}, 0, 0, false, 1)",
                    "roofGable(byHeight, 2)",
                    f"roofHip(byAngle, {angle}, 0.3)",
                    f"roofPyramid({angle})",
                    "roofPyramid(byHeight, 3)",
                    f"roofShed({angle})",
                    f"roofShed({angle}, 1)",
                    "roofShed(byHeight, 2, 0)",
                ]
            )
            return text, MASS
        if form == "split":
            axis = rng.choice(["x", "z", "x"] if geometry == FACE else ["x", "y", "z", "y"])
            head = f"split({axis})" if self.chance(0.8) else f"split({axis}, noAdjust)"
            parts = []
            for _ in range(rng.randint(1, 3)):
                prefix = rng.choice(["", "~", "~", "'"])
                size = "0.5" if prefix == "'" else self.size(env)
                parts.append(f"{prefix}{size} : {sub(geometry)}")
            if self.chance(0.15):
                self.forms.add("nested split group")
                parts.insert(
                    rng.randint(0, len(parts)), f"{{ ~{self.size(env)} : {sub(geometry)} }}*"
                )
            star = "*" if self.chance(0.5) else ""
            return f"{head} {{ {' | '.join(parts)} }}{star}", geometry
        if form == "splitArea":
            if depth > 0:  # once a program: splitArea's bisections are slow to derive
                return "", geometry
            return (
                f"splitArea({rng.choice(['x', 'z'])}) {{ ~{rng.randint(30, 60)} : {sub(FACE)} }}*",
                FACE,
            )
        if form == "offset":
            distance = f"-{rng.choice([0.5, 1, 2])}"
            keep = rng.choice(["", "", ", all", ", inside", ", border"])
            if keep or self.chance(0.3):
                return f"offset({distance}{keep})", FACE
            branches = f"inside : {sub(FACE)} | border : {sub(FACE)}"
            return f"offset({distance}) comp(f) {{ {branches} }}", FACE
        if form == "setback":
            selector = rng.choice(SETBACK_SELECTORS)
            op = rng.choice([":", "="])
            distances = ["1", "2", "[1, 2, 1, 2]", self.size(env), *self.comp_functions]
            distance = rng.choice(distances)
            name = (
                rng.choice(["setback", "setback", "setbackPerEdge"])
                if "[" not in distance and distance not in self.comp_functions
                else "setback"
            )
            return (
                f"{name}({distance}) {{ {selector} {op} {sub(FACE)} | remainder : {sub(FACE)} }}",
                FACE,
            )
        if form == "perimeter":
            parts = " | ".join(
                f"~{self.rng.choice([2, 3, 4])} : {self.rng.choice([1, 1.5, 2])} : {sub(FACE)}"
                for _ in range(rng.randint(1, 3))
            )
            star = "*" if self.chance(0.6) else ""
            return (
                f"splitAndSetbackPerimeter({rng.choice([0, 1])}) {{ {parts} }}{star} "
                f"{{ remainder : {sub(FACE)} }}",
                FACE,
            )
        if form == "degenerate":
            self.forms.add("degenerate")  # runtime values CityEngine warns about and goes on
            return rng.choice(
                [
                    "extrude(0)",
                    "s(0, 0, 0) extrude(3)",
                    "roofHip(30, -20)",
                    "offset(-20)",
                    "envelope(normal, 0, 3, 45)",
                    "setback(20) { all : NIL | remainder : X }",
                    "extrude(-2)",
                    "roofGable(89.9)",
                    "taper(0)",
                    "innerRectangle(edge) { shape : NIL | remainder : NIL }",
                ]
            ), MASS
        if form == "shape":
            text = rng.choice(["shapeL(3, 2)", "shapeU(2, 2, 2)", "shapeO(2, 2, 2, 2)"])
            return f"{text} {{ shape : {sub(FACE)} | remainder : {sub(FACE)} }}", FACE
        if form == "inner":
            if self.chance(0.4):
                return "innerRect", FACE
            return (
                f"innerRectangle({rng.choice(['edge', 'scope'])}) "
                f"{{ shape : {sub(FACE)} | remainder : {sub(FACE)} }}",
                FACE,
            )
        if form == "comp_e":
            return f"comp({rng.choice(['e', 'v'])}) {{ all : {sub(OTHER)} }}", FACE
        if form == "scatter":
            kind = rng.choice(["uniform", "gaussian"])
            return f"scatter(surface, {rng.randint(1, 5)}, {kind}) {{ {sub(OTHER)} }}", FACE
        if form == "envelope":
            return "envelope(normal, 10, 3, 45)", MASS
        if form == "taper":
            return f"taper({self.size(env)})", MASS
        if form == "comp":
            # op_comp: selectors by name, index, isTagged(), or any logical expression
            branches = []
            for _ in range(rng.randint(1, 3)):
                selector = rng.choice([*COMP_FACE_SELECTORS, "0", "1"])
                if self.chance(0.15):
                    self.forms.add("comp selector expression")
                    selector = rng.choice(
                        [
                            "front || back",
                            "comp.index > 2 && side",
                            "!(top)",
                            'isTagged("extrude.side")',
                            f"({self.expression(BOOL, env, 1)})",
                        ]
                    )
                op = ":" if self.chance(0.8) else "="
                if self.chance(0.04):
                    self.forms.add("comp connected operator")
                    op = "=:"
                branches.append(f"{selector} {op} {sub(FACE)}")
            kind = rng.choice(["f", "f", "f", "f, noAlign", "f, zUp"])
            return f"comp({kind}) {{ {' | '.join(branches)} }}", FACE
        if form == "footprint":
            return rng.choice(["footprint()", "trim()"]), OTHER
        if form == "primitive":
            return rng.choice(
                [
                    "primitiveCube()",
                    "primitiveCylinder(8)",
                    "primitiveSphere(8, 8)",
                    "primitiveCone(8)",
                ]
            ), MASS
        if form == "insert":
            self.forms.add("insert")
            asset = rng.choice(['"builtin:cube"', '"builtin:cube:notex"', '"assets/window.obj"'])
            options = rng.choice(["", ", yUp", ", yUp, keepSizeAndPosition", ", zUp, fitScope"])
            if options.endswith("fitScope"):
                options = ", zUp, keepSizeAlignPosition"
            return f"i({asset}{options})", MASS
        if form == "case":
            self.forms.add("case body")
            return (
                f"[ case {self.expression(BOOL, env, 1)} : {sub(geometry)} else : {sub(geometry)} ]"
            ), geometry
        if form == "push":
            return f"[ {sub(geometry)} ]", geometry
        if form == "bool":
            op = rng.choice(["union", "subtract", "intersect"])
            return f"{op} {{ extrude(2) | extrude(1) t(1, 0, 1) }}", MASS
        if form == "inline":
            operations = sub(geometry)
            return rng.choice(
                [f"inline {{ {operations} }}", f"inline(unify) {{ {operations} }}"]
            ), OTHER
        return "", geometry

    def rule(self, index: int) -> str:
        rule = self.rules[index]
        env = {f"q{i}": t for i, t in enumerate(rule.params)}
        if env and "start" not in self.values and self.chance(0.15):  # not hiding the attr
            # start.html's keyword is a name elsewhere
            self.forms.add("keyword as name")
            first = next(iter(env))
            env = {("start" if n == first else n): t for n, t in env.items()}
        head = rule.name + (f"({', '.join(env)})" if rule.params else "")
        if self.chance(0.15):
            self.forms.add("with")
            kinds = [self.rng.choice([FLOAT, STRING, BOOL]) for _ in range(self.rng.randint(1, 2))]
            variables = []
            for kind in kinds:  # each may read the ones before it (with.html)
                local = f"v{len(env)}"
                variables.append(f"{local} := {self.expression(kind, env, 1)}")
                env[local] = kind
            head += f" with ({' '.join(variables)})"
        if index == 0 and not self.prefix:
            head = "@StartRule\n" + head
        self.forms.add("rule")
        return f"{head} --> {self.body(rule.geometry, env, index)}"


def _file(writer: _Writer, start: str, imports: str = "") -> str:
    rng = writer.rng
    parts = ['version "2023.0"'] if rng.random() < 0.3 else []
    parts += [imports] if imports else []
    for _ in range(rng.randint(0, 3)):
        parts.append(writer.attribute())
    for _ in range(rng.randint(0, 2)):
        parts.append(writer.constant())
    for _ in range(rng.randint(0, 2)):
        parts.append(writer.function())
    writer.rules.append(_Callable(start, (), geometry=FACE))
    rules = []
    index = 0
    while index < len(writer.rules):
        rules.append(writer.rule(index))
        index += 1
    if writer.attrs and rng.random() < 0.1:
        writer.forms.add("style")
        name, kind = rng.choice(list(writer.attrs.items()))
        rules.append(f"style Winter\n\nattr {name} = {writer.expression(kind, {}, 1)}")
    return "\n\n".join([*parts, *rules]) + "\n"


def generate(seed: int) -> GeneratedProgram:
    """The program of ``seed`` (the same seed gives the same files)."""
    rng = random.Random(seed)
    files = {}
    library = None
    if rng.random() < 0.1:
        library = _Writer(random.Random(seed + 1_000_003))
        library.prefix = "L"
        files["library.cga"] = _file(library, "LStart")
    writer = _Writer(rng, library=library)
    imports = ""
    if library is not None:
        overrides = [n for n, t in library.attrs.items() if t == FLOAT]
        arguments = f" ({overrides[0]} = 3)" if overrides and rng.random() < 0.5 else ""
        imports = f'import lib : "library.cga"{arguments}'
    text = _file(writer, "Lot", imports)
    files = {"generated.cga": text, **files}
    forms = writer.forms | (library.forms if library is not None else set())
    return GeneratedProgram(seed, files, forms=forms)


@dataclass
class Outcome:
    """What became of one generated program: ``stage`` is ``derives``, ``refused`` (the parser
    refused a file), ``known refusal`` (a refusal of :data:`KNOWN_REFUSALS`), ``round trip``
    (the printed text parses to another tree or not at all), ``error`` (a ShapegenError while
    loading or deriving) or ``crash`` (any other exception: a traceback)."""

    seed: int
    stage: str
    message: str = ""
    where: str = ""

    @property
    def kind(self) -> str:
        """The message without its variable parts (place, quoted names, numbers)."""
        text = re.sub(r"^\S*\.cga:\d+:\d+: ", "", self.message)
        text = re.sub(r"'[^']*'|\"[^\"]*\"", "'_'", text)
        return re.sub(r"(?<![\w.])[-+]?\d+(\.\d+)?(e[-+]?\d+)?", "N", text)[:160]


def check(
    program: GeneratedProgram, folder: Path, max_shapes: int = MAX_SHAPES, derive: bool = True
) -> Outcome:
    """Parse every file of ``program``, print and parse it again, then (with ``derive``) load the
    main file from ``folder`` (where the files are written) and derive it on :data:`LOT`; a
    program that is not derived ends ``parses``."""
    from shapegen import load_grammar
    from shapegen.errors import GrammarError, ShapegenError
    from shapegen.grammar import parse
    from shapegen.grammar.printer import print_grammar

    folder.mkdir(parents=True, exist_ok=True)
    for name, text in program.files.items():
        (folder / name).write_text(text, encoding="utf-8")
    try:
        for name, text in program.files.items():
            try:
                first = parse(text, name)
            except GrammarError as error:
                message = str(error).splitlines()[0]
                known = any(
                    fragment in message and form in program.forms
                    for fragment, form in KNOWN_REFUSALS
                )
                return Outcome(program.seed, "known refusal" if known else "refused", message)
            try:
                second = parse(print_grammar(first), name)
            except GrammarError as error:
                return Outcome(program.seed, "round trip", str(error).splitlines()[0])
            if second != first:
                return Outcome(
                    program.seed,
                    "round trip",
                    f"{name}: the printed text reads back as another tree",
                )
        if not derive:
            return Outcome(program.seed, "parses")
        grammar = load_grammar(folder / program.main)
        with contextlib.redirect_stdout(io.StringIO()):  # the programs' print() output
            grammar.build(lot=LOT, max_shapes=max_shapes)
    except ShapegenError as error:
        return Outcome(program.seed, "error", str(error).splitlines()[0])
    except Exception as error:  # noqa: BLE001 - a traceback is what the property looks for
        cause = getattr(error, "orig_exc", None)
        raised = cause if isinstance(cause, BaseException) else error
        frames = traceback.extract_tb(raised.__traceback__)
        where = f"{frames[-1].filename}:{frames[-1].lineno} in {frames[-1].name}" if frames else ""
        return Outcome(
            program.seed, "crash", f"{type(raised).__name__}: {raised}".splitlines()[0], where
        )
    return Outcome(program.seed, "derives")

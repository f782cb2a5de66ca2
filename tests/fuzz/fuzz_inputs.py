"""Fuzz inputs, all from a seed number (the same number gives the same input on every run).

- :func:`mutated_rule`: a bundled rule file, a docs example or a test example with a few edits:
  tokens deleted, duplicated, swapped or inserted, characters dropped, and numbers replaced by
  extreme values (0, -1, 1e-9, 5e-324, 1e16, 1e308, 1e999...), which drive splits, primitives
  and expressions to their limits;
- :func:`random_rule`: a grammar written from scratch by a small random generator (attrs,
  recursive functions, string building, splits, comps, transforms, inserts of every registered
  primitive with extreme parameters);
- :func:`mutated_model`: a shapegen-blocks JSON document or a mesh file (OBJ, STL, PLY, glTF)
  with bytes, numbers or structure changed.

:func:`run_rule` and :func:`run_model` are what a child process does with one input.
"""

from __future__ import annotations

import json
import random
import re
import tempfile
from functools import cache
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]

EXTREMES = [
    "0", "-1", "1e-9", "-1e-9", "5e-324", "1e-300", "0.001", "1e6", "1e16", "1e308", "-1e308",
    "1e999", "10000000", "2000", "3", "0.5", "(0 - 1e308 * 10)", "(1 / 3)",
]  # fmt: skip

TOKENS = [
    "-->", "=", "(", ")", "{", "}", "}*", "[", "]", "|", ":", ",", "'", "~", "%", "*", "/", "+",
    "-", "!", "&&", "||", "<", "==", "@Range(0, 1)", "@Free", "@StartRule", "attr", "const",
    "case", "else", "NIL", "true", "x", "y", "z", "split(x)", "split(y)", "comp(f)",
    "extrude(1)", "t('1, 0, 0)", "r(0, 45, 0)", "s('0.5, '1, '1)", "scope.sx", "split.index",
    "A", "B(1)", "0", "1e999", "5e-324", '"s"', '"', "#", "\n", " ", "sin(", "rand(1, 2)",
    "i(\"arch\")", "report(\"k\", 1)", "label(\"a\")", "set(density, 1e308)",
]  # fmt: skip

_TOKEN = re.compile(r"-->|[A-Za-z_][A-Za-z0-9_.]*|\d+(\.\d*)?([eE][-+]?\d+)?|\S")
_NUMBER = re.compile(r"(?<![A-Za-z_\d.])\d+(\.\d*)?([eE][-+]?\d+)?")


@cache
def seed_rules(small_only: bool = False) -> tuple[str, ...]:
    """The texts mutated: bundled rules, tests/grammar/examples, docs' ```grammar blocks."""
    texts = []
    for path in sorted((ROOT / "rules").glob("*.grammar")):
        texts.append(path.read_text())
    for path in sorted((ROOT / "tests" / "grammar" / "examples").glob("*.grammar")):
        texts.append(path.read_text())
    for page in sorted((ROOT / "docs").glob("*.md")) + [ROOT / "README.md"]:
        texts += re.findall(r"```grammar\n(.*?)```", page.read_text(), re.S)
    if small_only:  # parsing costs ~50 us a character: the quick lane keeps to small seeds
        texts = [t for t in texts if len(t) <= 5000]
    return tuple(texts)


def mutated_rule(number: int, small_only: bool = False) -> str:
    rng = random.Random(f"rule/{number}")
    text = rng.choice(seed_rules(small_only))
    for _ in range(rng.randint(1, 4)):
        kind = rng.choice(
            ["number", "number", "number", "delete", "duplicate", "swap", "insert", "chars"]
        )
        spans = [m.span() for m in _TOKEN.finditer(text)]
        if kind == "number":
            numbers = [m.span() for m in _NUMBER.finditer(text)]
            if numbers:
                a, b = rng.choice(numbers)
                text = text[:a] + rng.choice(EXTREMES) + text[b:]
            continue
        if not spans:
            text += rng.choice(TOKENS)
            continue
        a, b = rng.choice(spans)
        if kind == "delete":
            text = text[:a] + text[b:]
        elif kind == "duplicate":
            text = text[:b] + " " + text[a:b] + text[b:]
        elif kind == "swap":
            (a, b), (c, d) = sorted([(a, b), rng.choice(spans)])
            if b <= c:
                text = text[:a] + text[c:d] + text[b:c] + text[a:b] + text[d:]
        elif kind == "insert":
            text = text[:a] + rng.choice(TOKENS) + " " + text[a:]
        else:
            k = rng.randrange(len(text))
            text = text[:k] + text[k + rng.randint(1, 6) :]
    return text


# ------------------------------------------------------------------------------ random grammars
class _Writer:
    def __init__(self, rng: random.Random):
        self.rng = rng
        self.functions: list[tuple[str, int]] = []
        self.attrs: list[str] = []

    def number(self) -> str:
        rng = self.rng
        return rng.choice(EXTREMES) if rng.random() < 0.3 else f"{rng.uniform(0, 6):.3g}"

    def expression(self, depth: int = 0, names: tuple[str, ...] = ()) -> str:
        rng = self.rng
        if depth >= 3 or rng.random() < 0.35:
            choices = [self.number(), "scope.sx", "scope.sy", "split.index", "comp.index"]
            choices += list(names) + self.attrs + ['"s"']
            return rng.choice(choices)
        kind = rng.choice(["binary", "binary", "call", "user", "unary", "paren", "compare"])
        if kind == "binary":
            op = rng.choice(["+", "-", "*", "/", "%"])
            return f"{self.expression(depth + 1, names)} {op} {self.expression(depth + 1, names)}"
        if kind == "compare":
            return f"{self.expression(depth + 1, names)} > {self.expression(depth + 1, names)}"
        if kind == "call":
            name = rng.choice(["sin", "sqrt", "abs", "floor", "rint", "pow", "exp", "ln", "min"])
            count = 2 if name in ("pow", "min") else 1
            args = ", ".join(self.expression(depth + 1, names) for _ in range(count))
            return f"{name}({args})"
        if kind == "user" and self.functions:
            name, arity = rng.choice(self.functions)
            args = ", ".join(self.expression(depth + 1, names) for _ in range(arity))
            return f"{name}({args})"
        if kind == "unary":
            return f"-{self.expression(depth + 1, names)}"
        return f"({self.expression(depth + 1, names)})"

    def function(self, index: int) -> str:
        rng = self.rng
        name = f"f{index}"
        self.functions.append((name, 1))
        body = rng.choice(
            [
                f"case n > 0 : {name}(n - 1) + {name}(n - 1) else : 1",
                f'case n > 0 : {name}(n - 1) + {name}(n - 1) else : "x"',
                f"case n > 0 : {name}(n + 1) else : 0",
                f"case n < {self.number()} : {name}(n + 1) * 2 else : n",
                self.expression(1, ("n",)),
            ]
        )
        return f"{name}(n) = {body}\n"

    def insert(self) -> str:
        from shapegen.primitives import available, get

        rng = self.rng
        name = rng.choice(available())
        parameters = list(get(name).parameters)
        chosen = rng.sample(parameters, k=min(len(parameters), rng.randint(0, 3)))
        values = []
        for parameter in chosen:
            value = rng.choice([self.number(), self.expression(1), '"gothic"', "true"])
            values.append(f"{parameter} = {value}")
        return f'i("{name}"' + "".join(", " + v for v in values) + ")"

    def body(self, rules: list[str], depth: int = 0) -> str:
        rng = self.rng
        items = []
        for _ in range(rng.randint(1, 4)):
            kind = rng.choice(["split", "comp", "t", "s", "r", "insert", "succ", "report", "push"])
            if kind == "split" and depth < 2:
                axis = rng.choice("xyz")
                parts = " | ".join(
                    f"{rng.choice(['', '~', chr(39)])}{self.expression(2)} : {rng.choice(rules)}"
                    for _ in range(rng.randint(1, 3))
                )
                items.append(f"split({axis}) {{ {parts} }}{rng.choice(['', '*'])}")
            elif kind == "comp" and depth < 2:
                items.append(
                    f"comp(f) {{ top : {rng.choice(rules)} | side : {rng.choice(rules)} }}"
                )
            elif kind in "tsr":
                values = ", ".join(self.expression(2) for _ in range(3))
                items.append(f"{kind}({values})")
            elif kind == "insert":
                items.append(self.insert())
            elif kind == "report":
                items.append(f'report("k", {self.expression(1)})')
            elif kind == "push" and depth < 2:
                items.append(f"[ {self.body(rules, depth + 1)} ]")
            else:
                items.append(rng.choice(rules + ["NIL"]))
        return " ".join(items)


def random_rule(number: int) -> str:
    rng = random.Random(f"random/{number}")
    writer = _Writer(rng)
    lines = []
    for k in range(rng.randint(0, 3)):
        name = f"a{k}"
        lines.append(f"attr {name} = {writer.expression(1)}\n")
        writer.attrs.append(name)
    for k in range(rng.randint(0, 2)):
        lines.append(writer.function(k))
    rules = [f"R{k}" for k in range(rng.randint(1, 4))]
    lot = f"@Lot({writer.number()}, {writer.number()})" if rng.random() < 0.5 else ""
    lines.append(
        f"@StartRule {lot}\nLot --> extrude({writer.expression(1)}) {writer.body(rules)}\n"
    )
    for rule in rules:
        lines.append(f"{rule} --> {writer.body(rules)}\n")
    return "".join(lines)


def warm_up() -> None:
    """Load in the parent what every child needs (the LALR parser, the primitives, the mesh
    readers), so that forked children share it instead of building it each time."""
    import shapegen
    from shapegen.primitives import available

    inserts = " ".join(f'[ i("{name}") ]' for name in available())
    try:
        shapegen.parse_grammar(f"@StartRule\nLot --> extrude(1) {inserts}").build()
    except shapegen.errors.ShapegenError:
        pass  # some primitives need other scopes; loading them is what counts
    for item in _model_seeds():
        try:
            run_model(item)
        except shapegen.errors.ShapegenError:
            pass


def run_rule(text: str) -> None:
    """What one child does with a grammar: parse, then build (the project's errors are fine)."""
    import shapegen

    grammar = shapegen.parse_grammar(text, "fuzz.grammar")
    grammar.build(seed=1)


# ------------------------------------------------------------------------------ model files
@cache
def _model_seeds() -> tuple[tuple[str, bytes], ...]:
    import shapegen
    from shapegen.export.model_io import encode_model

    model = shapegen.load_grammar("arch_columns.grammar").build()
    seeds = [(".json", (ROOT / "docs" / "examples" / "arch.json").read_bytes())]
    for suffix in (".json", ".obj", ".stl", ".ply", ".gltf", ".glb"):
        seeds.append((suffix, encode_model(model, f"model{suffix}")))
    return tuple(seeds)


def mutated_model(number: int) -> tuple[str, bytes]:
    """``(suffix, bytes)`` of a mutated model file."""
    rng = random.Random(f"model/{number}")
    suffix, data = rng.choice(_model_seeds())
    kind = rng.choice(["numbers", "numbers", "bytes", "truncate", "structure", "suffix"])
    if kind == "numbers" and suffix in (".json", ".obj", ".gltf"):
        text = data.decode()
        spans = [m.span() for m in _NUMBER.finditer(text)]
        for _ in range(rng.randint(1, 5)):
            a, b = rng.choice(spans)
            value = rng.choice(["nan", "1e999", "1" + "0" * 400, "9" * 5000, "-0", "1e-320", "7"])
            text = text[:a] + value + text[b:]
            spans = [m.span() for m in _NUMBER.finditer(text)]
        data = text.encode()
    elif kind == "structure" and suffix == ".json":
        document = json.loads(data)
        block = rng.choice(document["blocks"])
        key = rng.choice(["vertices", "faces", "id", "density", "tags", "structure"])
        block[key] = rng.choice([[], [[0, 0, 0]] * 3, "x", None, [[1, 2]], 1e308, {"a": [[[]]]}])
        if rng.random() < 0.3:
            document["structure"] = {"name": "blocks", "arguments": {"deep": [[[[[[[[1]]]]]]]]}}
        data = json.dumps(document).encode()
    elif kind == "truncate":
        data = data[: rng.randrange(len(data))]
    elif kind == "suffix":
        suffix = rng.choice([".json", ".obj", ".stl", ".ply", ".gltf", ".glb"])
    else:
        data = bytearray(data)
        for _ in range(rng.randint(1, 20)):
            data[rng.randrange(len(data))] = rng.randrange(256)
        data = bytes(data)
    return suffix, data


def run_model(item: tuple[str, bytes]) -> None:
    """What one child does with a model file: write it, read it back."""
    from shapegen.readers.models import read_model

    suffix, data = item
    with tempfile.TemporaryDirectory() as folder:
        path = Path(folder) / f"fuzz{suffix}"
        path.write_bytes(data)
        read_model(path)

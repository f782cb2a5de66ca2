"""The coverage of CityEngine's CGA reference: one row per reference entry, with its status
taken from the code, written into docs/cga-compatibility.md.

The entries (names only) are ``tools/cga_reference_entries.json``: every operation, builtin
function (with the utility library), shape attribute field, annotation and keyword of the
reference, and the deprecated names real rule files still use. Each entry's status comes from
shapegen itself, never from this file:

- an operation is *supported* when the interpreter compiles it (a compiler registered in
  :mod:`shapegen.engine.operations.registry`), *partial* when its compiler was registered with
  what it does not honour (``@operation(name, partial=...)``), and *not supported* otherwise;
  the text a rule file gets when it loads is shown;
- a function, a shape attribute or an annotation is probed: a rule file using it is loaded
  (an expression in an ``attr``, compiled when the file loads) and is supported when it loads,
  partial when the code keeps a note of what differs (``PARTIAL_FUNCTIONS``,
  ``PARTIAL_ATTRIBUTES``, ``PARTIAL_GEOMETRY``), not supported when loading refuses it;
- a keyword is probed with a small rule file whose result is known.

The test column names a test that shows the entry: the tests in ``tests/cga/test_*.py`` declare
what they show in a module-level ``COVERS`` table (``{"test_name": ("op:translate", ...)}``, or
``{"tests/x.py::test_name": (...)}`` for a test elsewhere); the first declared is shown.

    .venv/bin/python tools/cga_coverage.py            # print the table
    .venv/bin/python tools/cga_coverage.py --write    # rewrite the docs between the markers
    .venv/bin/python tools/cga_coverage.py --check    # exit 1 when the docs are out of date
"""

from __future__ import annotations

import argparse
import ast
import importlib.util
import json
import re
import sys
import tempfile
from dataclasses import dataclass
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
ENTRIES = ROOT / "tools" / "cga_reference_entries.json"
DOC = ROOT / "docs" / "cga-compatibility.md"
TESTS = ROOT / "tests" / "cga"
START, END = "<!-- coverage:start -->", "<!-- coverage:end -->"
KINDS = {
    "operations": "op",
    "functions": "func",
    "attributes": "attr",
    "annotations": "annotation",
    "keywords": "keyword",
}
SUPPORTED, PARTIAL, NOT_SUPPORTED = "supported", "partial", "not supported"


@dataclass(frozen=True)
class Row:
    """One reference entry and what shapegen does with it."""

    key: str  # "op:extrude"
    name: str
    page: str
    deprecated: bool
    status: str
    note: str
    test: str


# ------------------------------------------------------------------------------- entries
def entries() -> list[tuple[str, dict]]:
    """``(kind prefix, entry)`` for every entry of the data file, in its order."""
    data = json.loads(ENTRIES.read_text(encoding="utf-8"))
    return [(KINDS[kind], item) for kind in KINDS for item in data[kind]]


# ------------------------------------------------------------------------------- probes
def _load(text: str, files: dict[str, str] | None = None):
    """Load ``text`` as a .cga file (and ``files`` beside it); the grammar or the error."""
    import shapegen
    from shapegen.errors import ShapegenError

    with tempfile.TemporaryDirectory() as folder:
        for name, content in (files or {}).items():
            (Path(folder) / name).write_text(content, encoding="utf-8")
        path = Path(folder) / "probe.cga"
        path.write_text(text, encoding="utf-8")
        try:
            return shapegen.load_grammar(path), None
        except ShapegenError as exc:
            return None, exc


def _refusal(error) -> str:
    """The first line of a load error, without its file:line:col."""
    line = str(error).splitlines()[0]
    return re.sub(r"^\S*?probe\.cga(:\d+:\d+)?: ", "", line)


_OPERATION_PROBES = {
    "union": "Lot --> extrude(3) union { A | B }\n",
    "subtract": "Lot --> extrude(3) subtract { A | B }\n",
    "intersect": "Lot --> extrude(3) intersect { A | B }\n",
    "inline": "Lot --> extrude(3) inline A\nA --> X.\n",
    "modify": "Lot --> extrude(3) modify(f) { top : X. }\n",
    "splitAndSetbackPerimeter": (
        "Lot --> splitAndSetbackPerimeter(0) { 4 : 1 : A | ~1 : 0 : B } { remainder : C }\n"
    ),
}


def _operation_refusal(name: str, low: int) -> str:
    default = f"Lot --> extrude(3) {name}({', '.join(['1'] * low)}) X.\n"
    grammar, error = _load("@StartRule\n" + _OPERATION_PROBES.get(name, default))
    if error is None:
        return "loads (no compiler: refused when derived)"
    return _refusal(error)


def operation_status(name: str) -> tuple[str, str]:
    from shapegen.engine.operations import registry
    from shapegen.engine.operations.cga import register_all

    register_all()  # every operation registered
    from shapegen.grammar.names import CGA_OPERATIONS, OPERATIONS

    dedicated = set(OPERATIONS) | {"NIL", "push", "pop"}
    notes = registry.partial_notes()
    if name in dedicated or registry.compiler_for(name) is not None:
        return (PARTIAL, notes[name]) if name in notes else (SUPPORTED, "")
    low = CGA_OPERATIONS.get(name, (0, 0))[0]
    return NOT_SUPPORTED, "refused when the file loads: " + _operation_refusal(name, low)


_FUNCTION_PROBES = {
    "array": "[1, 2; 3, 4]",
    "colon": "[0 : 2 : 10]",
    "index": "[1, 2, 3][1]",
    "comp": "comp(f) { all : 1 }",
    "simpleTypes": '1 + 2 * 3 % 2 == 1 && !false || "a" + 1 < "b"',
    "arrayTypes": "[1, 2] .+ [3, 4] .< [5, 5]",
    "inside": "inside(intra)",
    "overlaps": "overlaps(all)",
    "touches": "touches(inter)",
    "minimumDistance": 'minimumDistance(intra, "a")',
    "contextCount": 'contextCount(intra, "a")',
    "contextCompare": 'contextCompare(intra, "a", world.highest)',
    "convert": "convert(x, scope, world, pos, 0, 0, 0)",
    "getGeoCoord": "getGeoCoord(X)",
    "assetInfo": 'assetInfo("a.obj", sx)',
    "imageInfo": 'imageInfo("a.png", sx)',
    "geometry.angle": "geometry.angle(maxSlope)",
    "geometry.isOriented": "geometry.isOriented(top)",
    "geometry.du": "geometry.du(0, unitSpace)",
    "geometry.dv": "geometry.dv(0, unitSpace)",
}


def _call(name: str) -> str:
    from shapegen.grammar.names import BUILTIN_FUNCTIONS, GEOMETRY_FUNCTIONS

    if name in _FUNCTION_PROBES:
        return _FUNCTION_PROBES[name]
    if name.startswith("geometry."):
        low = GEOMETRY_FUNCTIONS.get(name.removeprefix("geometry."), (0, 0))[0]
    else:
        low = BUILTIN_FUNCTIONS.get(name, (0, 0))[0]
    return f"{name}({', '.join(['1'] * low)})"


def _function_notes() -> dict[str, str]:
    from shapegen.engine.expressions import calls as functions_calls
    from shapegen.engine.expressions import file_reading as functions_files
    from shapegen.engine.expressions import pure_functions as functions
    from shapegen.engine.expressions import shape_attributes as functions_shape
    from shapegen.geometry import queries

    return {
        **functions.PARTIAL_FUNCTIONS,
        **functions_calls.PARTIAL_FUNCTIONS,
        **functions_files.PARTIAL_FUNCTIONS,
        **functions_shape.PARTIAL_FUNCTIONS,
        **{f"geometry.{k}": v for k, v in queries.PARTIAL_GEOMETRY.items()},
    }


def _probed(expression: str, notes: dict[str, str], name: str) -> tuple[str, str]:
    grammar, error = _load(f"attr probe = {expression}\n@StartRule\nLot --> X.\n")
    if error is not None:
        return NOT_SUPPORTED, "refused when the file loads: " + _refusal(error)
    return (PARTIAL, notes[name]) if name in notes else (SUPPORTED, "")


def function_status(name: str) -> tuple[str, str]:
    return _probed(_call(name), _function_notes(), name)


def attribute_status(name: str) -> tuple[str, str]:
    from shapegen.engine.expressions.shape_attributes import PARTIAL_ATTRIBUTES
    from shapegen.model.appearance import MATERIAL_ATTRIBUTES

    if "{map}" in name:  # one row for the field of every texture map
        field = name.split(".")[-1]
        maps = [n for n in MATERIAL_ATTRIBUTES if n.endswith("map")]
        missing = [m for m in maps if f"{m}.{field}" not in MATERIAL_ATTRIBUTES]
        if missing or not maps:
            return NOT_SUPPORTED, f"no {field} for {', '.join(missing)}"
        name = f"material.{maps[0]}.{field}"
    return _probed(name, PARTIAL_ATTRIBUTES, name)


_ANNOTATION_ARGUMENTS = {
    "Range": "(min=0, max=10)",
    "Enum": '("a", "b")',
    "Description": '("d")',
    "DisplayName": '("d")',
    "RuleFileDescription": '("d")',
    "Order": "(1)",
    "Group": '("g")',
    "Handle": "(shape=Lot, axis=y)",
    "Out": "(granularity=separatedShapes)",
}
_ON_RULES = ("StartRule", "InLine", "InMesh", "InPoint", "InPointCloud", "InPolygon", "Out")


def annotation_status(name: str) -> tuple[str, str]:
    from shapegen.grammar.names import ANNOTATIONS

    mark = f"@{name}{_ANNOTATION_ARGUMENTS.get(name, '')}"
    text = (
        f"attr h = 1\n{mark}\nLot --> X.\n"
        if name in _ON_RULES
        else f"{mark}\nattr h = 1\n@StartRule\nLot --> X.\n"
    )
    grammar, error = _load(text)
    if error is not None:
        return NOT_SUPPORTED, "refused when the file loads: " + _refusal(error)
    if name not in ANNOTATIONS or grammar.ast.warnings:
        return PARTIAL, "ignored with a warning"
    return SUPPORTED, ""


def _reports(text: str, files=None) -> dict | None:
    grammar, error = _load(text, files)
    if error is not None:
        return {"error": _refusal(error)}
    return grammar.build(lot=(12.0, 8.0)).metadata["reports"]


#: Keywords: a rule file using it and the reports it must give.
_KEYWORD_PROBES = {
    "attr": ('attr h = 3\n@StartRule\nLot --> report("h", h) X.\n', None, {"h": 3.0}),
    "const": ('const h = 3\n@StartRule\nLot --> report("h", h) X.\n', None, {"h": 3.0}),
    "import": (
        'import lib : "lib.cga"\n@StartRule\nLot --> report("h", lib.h) lib.Mark\n',
        {"lib.cga": 'attr h = 4\nMark --> report("m", 1) X.\n'},
        {"h": 4.0, "m": 1.0},
    ),
    "extension": (
        'extension Roof --> report("r", 1) X.\n@StartRule\nLot --> Roof\n',
        None,
        {"r": 1.0},
    ),
    "start": ('start Lot --> report("s", 1) X.\n', None, {"s": 1.0}),
    "style": (
        'attr h = 2\n@StartRule\nLot --> report("h", h) X.\nstyle Tall\nattr h = 5\n',
        None,
        {"h": 2.0},  # the Default style's value
    ),
    "version": ('version "2024.0"\n@StartRule\nLot --> report("v", 1) X.\n', None, {"v": 1.0}),
    "with": (
        '@StartRule\nLot with (h := 3) --> report("h", h) X.\n',
        None,
        {"h": 3.0},
    ),
    "case": (
        '@StartRule\nLot --> case 1 > 2 : report("c", 1) X.\n      else : report("c", 2) X.\n',
        None,
        {"c": 2.0},
    ),
    "else": (
        "c = case 2 > 1 : 5 else : 6\n@StartRule\n"
        'Lot --> 30% : report("c", c) X.\n      else : report("c", c) X.\n',
        None,
        {"c": 5.0},
    ),
}


def keyword_status(name: str) -> tuple[str, str]:
    text, files, expected = _KEYWORD_PROBES[name]
    reports = _reports(text, files)
    if "error" in reports:
        return NOT_SUPPORTED, "refused when the file loads: " + reports["error"]
    if reports != expected:
        return PARTIAL, f"the probe reports {reports}, not {expected}"
    return SUPPORTED, ""


_STATUS = {
    "op": operation_status,
    "func": function_status,
    "attr": attribute_status,
    "annotation": annotation_status,
    "keyword": keyword_status,
}


# ------------------------------------------------------------------------------- tests
def declared_tests() -> dict[str, list[str]]:
    """``entry key -> ["tests/cga/file.py::test", ...]`` from the ``COVERS`` tables of the
    test modules (imported: a table may be built from the module's own cases)."""
    out: dict[str, list[str]] = {}
    # the tests import their shared helpers (tests/*.py) as pytest lets them: from its root
    if str(ROOT / "tests") not in sys.path:
        sys.path.insert(0, str(ROOT / "tests"))
    for path in sorted(TESTS.glob("test_*.py")):
        if "COVERS" not in path.read_text(encoding="utf-8"):
            continue
        spec = importlib.util.spec_from_file_location(f"_covers_{path.stem}", path)
        module = importlib.util.module_from_spec(spec)
        spec.loader.exec_module(module)
        for test, keys in getattr(module, "COVERS", {}).items():
            where = test if "::" in test else f"{path.relative_to(ROOT).as_posix()}::{test}"
            for key in keys:
                out.setdefault(key, []).append(where)
    return out


def test_exists(where: str) -> bool:
    """Whether ``file::name`` is a test function defined at the top of that file."""
    file, _, name = where.partition("::")
    path = ROOT / file
    if not path.is_file():
        return False
    tree = ast.parse(path.read_text(encoding="utf-8"))
    return any(isinstance(n, ast.FunctionDef) and n.name == name for n in tree.body)


# ------------------------------------------------------------------------------- the table
def rows() -> list[Row]:
    tests = declared_tests()
    out = []
    for prefix, item in entries():
        key = f"{prefix}:{item['name']}"
        status, note = _STATUS[prefix](item["name"])
        shown = tests.get(key, [""])[0]
        out.append(
            Row(
                key,
                item["name"],
                item.get("page", ""),
                bool(item.get("deprecated")),
                status,
                note,
                shown,
            )  # fmt: skip
        )
    return out


_KIND_WORDS = {
    "op": "operation",
    "func": "function",
    "attr": "shape attribute",
    "annotation": "annotation",
    "keyword": "keyword",
}


def _cell(text: str) -> str:
    return text.replace("|", "\\|").replace("\n", " ")


def markdown(table: list[Row]) -> str:
    counts = {s: sum(r.status == s for r in table) for s in (SUPPORTED, PARTIAL, NOT_SUPPORTED)}
    lines = [
        "<!-- generated by tools/cga_coverage.py from tools/cga_reference_entries.json and the "
        "code; do not edit by hand -->",
        "",
        f"{len(table)} reference entries: {counts[SUPPORTED]} supported, {counts[PARTIAL]} "
        f"partial, {counts[NOT_SUPPORTED]} not supported.",
        "",
        "| entry | kind | status | what differs, or how it is refused | test |",
        "|---|---|---|---|---|",
    ]
    for r in table:
        name = f"`{r.name}`" + (" (deprecated)" if r.deprecated else "")
        if r.key.startswith("annotation:"):
            name = f"`@{r.name}`"
        test = f"`{r.test}`" if r.test else ""
        lines.append(
            f"| {name} | {_KIND_WORDS[r.key.split(':')[0]]} | {r.status} | {_cell(r.note)} "
            f"| {test} |"
        )
    return "\n".join(lines) + "\n"


def updated_doc(text: str, table: str) -> str:
    """The document ``text`` with ``table`` between the markers (added at the end if absent)."""
    if START in text and END in text:
        head, rest = text.split(START, 1)
        _, tail = rest.split(END, 1)
        return f"{head}{START}\n{table}{END}{tail}"
    return f"{text.rstrip()}\n\n{START}\n{table}{END}\n"


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--write", action="store_true", help="rewrite the docs' table")
    parser.add_argument("--check", action="store_true", help="exit 1 when the docs differ")
    options = parser.parse_args(argv)
    table = markdown(rows())
    current = DOC.read_text(encoding="utf-8")
    wanted = updated_doc(current, table)
    if options.write:
        if wanted != current:
            DOC.write_text(wanted, encoding="utf-8")
        return 0
    if options.check:
        if wanted != current:
            print(f"{DOC.relative_to(ROOT)} is out of date: run tools/cga_coverage.py --write")
            return 1
        return 0
    sys.stdout.write(table)
    return 0


if __name__ == "__main__":
    sys.exit(main())

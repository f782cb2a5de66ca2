"""The package's layers import only downward, and no modules import each other in a cycle.

Read from the source (every ``import`` and ``from ... import``, at module level or inside a
function), so a lazy import counts as much as a top-level one.
"""

import ast
import functools
from pathlib import Path

import pytest

PACKAGE = Path(__file__).resolve().parents[1] / "shapegen"

# Bottom to top. A module may import its own layer and the layers below it.
LAYERS = [
    ["errors", "tolerances", "json_values", "plugins", "limits", "lazy_names", "threads"],
    ["model"],
    ["geometry"],  # polygon meshes and their CGA operations (cut, extrude, offset, roofs)
    ["readers"],  # input files (lots, GeoJSON, OSM): export writes, city and cli read
    ["grammar", "statics", "export"],
    ["primitives"],  # the cable primitive sizes its section with statics.cables
    ["structures"],
    ["engine"],  # checks @Structure and i("...") names against their registries at load time
    ["search"],
    ["simulation"],
    ["pipeline"],
    ["cli", "editor", "city", "prt", "demo", "__main__", "__init__"],  # prt: PyPRT's API
]
LEVEL = {name: level for level, names in enumerate(LAYERS) for name in names}
# A module is as long as its concept. Past this length one is usually two concepts; the ones
# that are one concept all the same are listed with the reason, rather than cut to fit.
MAX_LINES = 500
LONG_BY_CONCEPT = {
    "grammar/transformer.py": "the one lark Transformer of cga.lark: a short callback per rule of "
    "the grammar, named as the rule (lark's contract), in one class; what an operation call means "
    "is grammar/operation_calls.py's OperationCalls",
    "engine/expressions/compiler.py": "one compiler from expression AST to closures: each node "
    "kind and each builtin's dispatch belong to the one walk",
    "engine/shapes/shape.py": "the shape a rule works on: its scope, geometry, holes, tags and "
    "the values CGA reads of it are one object",
    "engine/program/interpreter.py": "one walk of the rule tree: the derivation loop and how its "
    "leaves become blocks and surfaces",
    "engine/operations/cga/topology.py": "comp and its kin: taking a shape apart into components "
    "and their scopes (boxes' closed forms in engine/shapes/boxes.py)",
    "geometry/mesh.py": "one immutable polygon mesh: its faces and their holes, counts, measures, "
    "predicates and the meshes made from it are one class (the ring work on holes is "
    "geometry/hole_rings.py)",
}


def _modules() -> dict[str, Path]:
    out = {}
    for path in PACKAGE.rglob("*.py"):
        parts = path.relative_to(PACKAGE).with_suffix("").parts
        if parts[-1] == "__init__" and len(parts) > 1:
            parts = parts[:-1]
        out["shapegen." + ".".join(parts) if parts != ("__init__",) else "shapegen"] = path
    return out


MODULE_NAMES: list[str] = []


@functools.cache
def _tree(path: Path) -> ast.Module:
    """The module's syntax tree, parsed once per process and only when a test asks (not while
    the tests are collected: each worker collects them)."""
    return ast.parse(path.read_text(encoding="utf-8"))


def _imports(module: str, path: Path) -> set[str]:
    tree = _tree(path)
    package = module if path.name == "__init__.py" else module.rsplit(".", 1)[0]
    found = set()
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            found.update(alias.name for alias in node.names)
        elif isinstance(node, ast.ImportFrom):
            base = node.module or ""
            if node.level:
                anchor = package.split(".")
                anchor = anchor[: len(anchor) - (node.level - 1)]
                base = ".".join([*anchor, base]) if base else ".".join(anchor)
            submodules = {f"{base}.{alias.name}" for alias in node.names}
            named = submodules & set(MODULE_NAMES)
            found.update(named if named else {base})
    return {name for name in found if name == "shapegen" or name.startswith("shapegen.")}


MODULES = _modules()
MODULE_NAMES.extend(MODULES)


@functools.cache
def _graph() -> dict[str, set[str]]:
    """Each module's imports of the package's modules."""
    return {
        module: {name for name in _imports(module, path) if name in MODULES and name != module}
        for module, path in MODULES.items()
    }


def _layer(module: str) -> int:
    top = module.split(".")[1] if "." in module else "__init__"
    return LEVEL[top]


def test_every_top_level_module_has_a_layer():
    tops = {m.split(".")[1] for m in MODULES if "." in m}
    assert tops <= set(LEVEL), f"give these a layer: {sorted(tops - set(LEVEL))}"


@pytest.mark.parametrize("module", sorted(MODULES))
def test_imports_only_downward(module):
    upward = sorted(i for i in _graph()[module] if _layer(i) > _layer(module))
    assert not upward, f"{module} imports from a higher layer: {upward}"


def test_no_import_cycles():
    # Packages' __init__ modules re-export their own submodules; the edge from a submodule up to
    # its package's face is not a dependency, so both directions inside one package are ignored
    # for the package module itself.
    def edges(module):
        return {i for i in _graph()[module] if not module.startswith(i + ".")}

    state: dict[str, int] = {}
    cycles = []

    def visit(module, path):
        state[module] = 1
        for other in edges(module):
            if state.get(other) == 1:
                cycles.append(path[path.index(other) :] + [other] if other in path else [other])
            elif other not in state:
                visit(other, [*path, other])
        state[module] = 2

    for module in sorted(MODULES):
        if module not in state:
            visit(module, [module])
    assert not cycles, f"import cycles: {cycles[:3]}"


def test_no_module_is_too_long():
    long = {
        str(path.relative_to(PACKAGE)): n
        for path in PACKAGE.rglob("*.py")
        if (n := len(path.read_text(encoding="utf-8").splitlines())) > MAX_LINES
        and str(path.relative_to(PACKAGE)) not in LONG_BY_CONCEPT
    }
    assert not long, f"modules over {MAX_LINES} lines: {long}"


def test_lower_layers_know_nothing_of_the_engine_or_the_search():
    for module, imports in _graph().items():
        if _layer(module) <= LEVEL["primitives"]:
            bad = [i for i in imports if i.startswith(("shapegen.engine", "shapegen.search"))]
            assert not bad, f"{module} imports {bad}"


def test_only_structures_compare_a_structure_name():
    # What a structure can do is asked of the structure (Assessment.block_analysis,
    # Structure.judges_blocks, measure_name...), so a new structure needs no front-end change.
    from shapegen.structures import available_structures

    names = set(available_structures())
    found = []
    for path in PACKAGE.rglob("*.py"):
        if "structures" in path.relative_to(PACKAGE).parts:
            continue
        for node in ast.walk(_tree(path)):
            if isinstance(node, ast.Compare) and any(
                isinstance(c, ast.Constant) and c.value in names
                for side in (node.left, *node.comparators)
                for c in ast.walk(side)
            ):
                found.append(f"{path.relative_to(PACKAGE)}:{node.lineno} {ast.unparse(node)}")
    assert not found, "structure names compared outside structures/:\n" + "\n".join(found)

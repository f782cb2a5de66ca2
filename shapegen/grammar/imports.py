"""CityEngine's ``import``: the rule files a file imports, merged into one :class:`ast.RuleFile`.

Semantics (CityEngine's import.html, extension.html and the changelog's notes on imports):

- ``import p : "x.cga"`` makes every rule, attr, const and function of ``x.cga`` available as
  ``p.Name``; references inside ``x.cga`` are renamed with it, so the merged grammar is one flat
  namespace (``p.Lot``, ``p.height``, ``p.f(1)``, ``set(p.height, 2)``). A successor of ``x.cga``
  without a rule there becomes ``p.Name`` too, which the importing file may define
  (``p.Slab --> ...``): a definition of the importing file wins over the imported one of the
  same name. An imported file's ``@StartRule`` (and ``@Lot``, ``@Structure``) is ignored.
- Attr propagation: an attr of ``x.cga`` that the importing file also defines takes the
  importing file's value (``p.height = height``), unless it is protected (``(height)``, or ``()``
  for all) or overridden (``(height = 20)``, evaluated in the importing file). Propagation goes
  one level down at a time: a second-level attr follows the first-level file's attr of its name,
  if that file defines one. An importing attr that reads the imported one (``attr x = p.x + 1``)
  reads the imported file's own value, as CityEngine's "special case" allows.
- ``(Roof --> ops)`` redefines the imported ``extension`` rule ``Roof``; its operations are
  those of the importing file.
- ``import "x.cga"`` (no prefix; not in today's reference) merges the names as written; the
  importing file's definition wins where both define a name.
- Paths: relative to the importing file's folder, then to its project (the nearest folder above
  holding ``rules/``); ``/Project/rest`` is the project itself when named so, else a project
  beside it in the workspace, else ``.ws/Project/rest`` (a ``.rpk`` package) or the project's
  ``.resolvemap.xml``. A text without a file resolves against the working directory.

Cycles, missing files, unknown protected or overridden attrs and rules are problems located at
the import line; problems inside an imported file are located in that file.
"""

from __future__ import annotations

__all__ = ["resolve_imports", "project_folder", "import_candidates", "used_definitions"]

import dataclasses
from pathlib import Path

from shapegen.errors import SourceLocation
from shapegen.grammar import ast
from shapegen.grammar.dynamic_imports import reinitialised
from shapegen.grammar.import_paths import import_candidates, project_folder
from shapegen.grammar.names import BUILTIN_FUNCTIONS, OPERATION_KEYWORDS
from shapegen.grammar.parser import parse_with_problems
from shapegen.grammar.problems import Problem
from shapegen.grammar.source_files import read_rule_file
from shapegen.grammar.tree import rebuilt as _rebuilt
from shapegen.limits import current_limits, limit_hint
from shapegen.readers.archives import unpacked_package, within

#: Annotations of a start rule, ignored on an imported file's rules.
_START_ANNOTATIONS = frozenset({"StartRule", "Lot", "Structure"})
#: Suffix of the hidden const that keeps an imported attr's own value (CGA names have no ``$``).
_OWN_VALUE = "$default"


@dataclasses.dataclass(frozen=True)
class _Merged:
    """A file with its imports merged: the grammar and the names of its own attrs."""

    grammar: ast.RuleFile
    own_attrs: frozenset[str]


class _Merger:
    """Merges the imports of one file and, recursively, of the files it imports."""

    def __init__(self, search_folders: tuple[Path, ...] = ()) -> None:
        self.search_folders = search_folders  # the user's rules path, looked in last
        self.problems: list[Problem] = []
        self.sources: dict[str, str] = {}
        self.cache: dict[Path, _Merged | None] = {}
        self.failed: set[str] = set()  # prefixes whose file could not be merged
        self.warnings: list[str] = []  # an imported file read in another encoding than UTF-8
        self.exhausted = False  # past max_definitions: nothing more is merged

    def merge(self, grammar: ast.RuleFile, folder: Path, stack: tuple[Path, ...]) -> _Merged:
        own = list(grammar.definitions)
        own_attrs = frozenset(d.name for d in own if isinstance(d, ast.Attribute))
        importer_attrs = {d.name: d for d in own if isinstance(d, ast.Attribute)}
        imported: list[ast.Definition] = []
        prefixes: dict[str, ast.Import] = {}
        redirects: dict[str, dict[str, str]] = {}
        for item in grammar.imports:
            if item.prefix is not None:
                first = prefixes.setdefault(item.prefix, item)
                if first is not item:
                    self.problems.append(
                        (
                            item.location,
                            f"the import prefix '{item.prefix}' is used twice (first at "
                            f"{first.location})",
                        )
                    )
                    continue
            sub = self._imported(item, folder, stack)
            if sub is not None and not self.exhausted:
                imported += self._prefixed(sub, item, importer_attrs, redirects)
                if len(imported) > current_limits().max_definitions and not self.exhausted:
                    self._too_many(item)
            if self.exhausted:
                break
            elif item.prefix is not None:
                self.failed.add(item.prefix)
        if redirects:
            own = [_redirected(d, redirects.get(d.name)) for d in own]
        imported_attrs = [d for d in imported if isinstance(d, ast.Attribute)]
        own = [self._dynamic_imports(d, set(prefixes), imported_attrs) for d in own]
        # rules and functions are told apart by name and arity, attrs and consts by name
        taken = {_key(d) for d in own}
        merged = list(own)
        for definition in imported:  # the importing file's definitions win
            if _key(definition) in taken:
                continue
            taken.add(_key(definition))
            merged.append(definition)
        result = dataclasses.replace(grammar, definitions=tuple(merged), sources=self.sources)
        return _Merged(result, own_attrs)

    def _dynamic_imports(
        self, definition: ast.Definition, prefixes: set[str], attrs: list[ast.Attribute]
    ) -> ast.Definition:
        """``p(a = v).Rule`` becomes ``[ set(p.x, ...) ... p.Rule ]``: every attr of the import
        set again in dependency order, to ``v`` where overridden, else to its definition (with
        the static import's propagation and overrides), for this invocation only."""
        if not isinstance(definition, ast.Rule | ast.Function):
            return definition

        def change(tree, params):
            if not isinstance(tree, ast.DynamicImport):
                return None
            if tree.prefix not in prefixes:
                self.problems.append(
                    (tree.location, f"dynamic import of '{tree.prefix}', which is not imported")
                )
                return ast.Nil(location=tree.location)
            return reinitialised(
                tree, [a for a in attrs if a.name.startswith(tree.prefix + ".")], self.problems
            )

        return _rebuilt(definition, change)

    # Files -------------------------------------------------------------------------------------

    def _imported(self, item: ast.Import, folder: Path, stack: tuple[Path, ...]) -> _Merged | None:
        candidates = import_candidates(item.path, folder, self.search_folders)
        package = unpacked_package(folder)
        if package is not None:  # a package's imports stay in it, or in the rules path
            candidates = [c for c in candidates if within(c, [package, *self.search_folders])]
        path = next((c.resolve() for c in candidates if c.is_file()), None)
        if path is None and not candidates:
            self.problems.append(
                (
                    item.location,
                    f'import of "{item.path}": it lies outside the rule package (a package '
                    "imports its own files, or those of the --rules-path folders)",
                )
            )
            return None
        if path is None:
            tried = ", ".join(str(c) for c in candidates)
            self.problems.append(
                (
                    item.location,
                    f'import of "{item.path}": no such file (tried {tried}; name the folder '
                    "that holds it with --rules-path or SHAPEGEN_RULES_PATH)",
                )
            )
            return None
        if len(stack) > current_limits().max_import_depth:
            depth = current_limits().max_import_depth
            self.problems.append(
                (
                    item.location,
                    f'import of "{item.path}": the imports nest more than {depth} files deep '
                    + limit_hint("max_import_depth"),
                )
            )
            return None
        if path in stack:
            chain = " -> ".join(p.name for p in (*stack[stack.index(path) :], path))
            self.problems.append((item.location, f'import of "{item.path}" makes a cycle: {chain}'))
            return None
        if item.styles and set(item.styles) != {"Default"}:
            self.problems.append(
                (
                    item.location,
                    f'importing the style(s) {", ".join(item.styles)} of "{item.path}" is not '
                    "supported by shapegen (it derives the Default style only)",
                )
            )
        if path not in self.cache:
            self.cache[path] = None  # a file met again below itself is a cycle, caught above
            self.cache[path] = self._load(path, stack + (path,))
        return self.cache[path]

    def _load(self, path: Path, stack: tuple[Path, ...]) -> _Merged:
        filename = str(path)
        text, encoding = read_rule_file(path, "the imported file")
        if encoding is not None:
            self.warnings.append(f"{filename}: {encoding}")
        grammar, problems = parse_with_problems(text, filename)
        self.sources[filename] = grammar.source
        self.problems += problems
        return self.merge(grammar, path.parent, stack)

    def _too_many(self, item: ast.Import) -> None:
        self.exhausted = True
        limit = current_limits().max_definitions
        self.problems.append(
            (
                item.location,
                f'import of "{item.path}": with it the imports make more than {limit} '
                "definitions (each prefix copies the imported file's) "
                + limit_hint("max_definitions"),
            )
        )

    # Prefixes, propagation and overrides -------------------------------------------------------

    def _prefixed(
        self,
        sub: _Merged,
        item: ast.Import,
        importer_attrs: dict[str, ast.Attribute],
        redirects: dict[str, dict[str, str]],
    ) -> list[ast.Definition]:
        prefix = item.prefix
        grammar = sub.grammar

        def rename(name: str) -> str:
            return f"{prefix}.{name}" if prefix else name

        renamer = _Renamer(grammar, rename)
        definitions = [renamer.definition(d) for d in grammar.definitions]
        overrides = {keyword.name: keyword for keyword in item.overrides}
        for name, where in [
            *((n, item.location) for n in item.protected),
            *((k.name, k.location) for k in item.overrides),
        ]:
            if name not in sub.own_attrs:
                deeper = any(a.name.endswith("." + name) for a in grammar.attrs)
                self.problems.append(
                    (
                        where if where.line else item.location,
                        f"\"{item.path}\" has no attr '{name}'"
                        + (
                            " of its own (an attr of a file it imports cannot be set here)"
                            if deeper
                            else ""
                        ),
                    )
                )
        for name in set(item.protected) & set(overrides):
            self.problems.append(
                (item.location, f"the attr '{name}' is both protected and overridden")
            )
        extra: list[ast.Definition] = []
        for k, definition in enumerate(definitions):
            name = grammar.definitions[k].name
            if not isinstance(definition, ast.Attribute) or name not in sub.own_attrs:
                continue
            own_value = definition.name + _OWN_VALUE
            keeps_own = False
            if name in overrides:
                value = overrides[name].value
                if _reads(value, definition.name):  # (h = p.h * 2): the imported file's own h
                    value = _with_names(value, {definition.name: own_value})
                    keeps_own = True
            elif item.protect_all or name in item.protected or prefix is None:
                continue
            elif name in importer_attrs:
                value = ast.Name(name, location=importer_attrs[name].location)
                if _reads(importer_attrs[name].value, definition.name):  # attr x = p.x + 1
                    redirects.setdefault(name, {})[definition.name] = own_value
                    keeps_own = True
            else:
                continue
            if keeps_own:
                extra.append(
                    ast.Constant(own_value, definition.value, location=definition.location)
                )
            definitions[k] = dataclasses.replace(definition, value=value)
        for rule in item.rules:
            definitions = self._rule_override(definitions, grammar, rule, item, rename)
        return definitions + extra

    def _rule_override(self, definitions, grammar, rule, item, rename):
        target = rename(rule.name)
        found = [
            k
            for k, d in enumerate(definitions)
            if isinstance(d, ast.Rule)
            and d.name == target
            and grammar.definitions[k].name == rule.name
        ]
        if not found:
            self.problems.append((rule.location, f"\"{item.path}\" has no rule '{rule.name}'"))
            return definitions
        k = found[0]
        original = definitions[k]
        if not original.extension:
            self.problems.append(
                (
                    rule.location,
                    f"'{rule.name}' of \"{item.path}\" is not an extension rule; only rules "
                    "written 'extension Name --> ...' can be redefined in an import",
                )
            )
        elif len(original.params) != len(rule.params):
            self.problems.append(
                (
                    rule.location,
                    f"'{rule.name}' of \"{item.path}\" takes {len(original.params)} "
                    f"parameter(s), the redefinition {len(rule.params)}",
                )
            )
        else:
            definitions = list(definitions)
            definitions[k] = dataclasses.replace(original, params=rule.params, body=rule.body)
        return definitions


class _Renamer:
    """Renames the definitions of one imported file and every reference to them."""

    def __init__(self, grammar: ast.RuleFile, rename):
        self.rename = rename
        self.values = frozenset(d.name for d in grammar.definitions if not isinstance(d, ast.Rule))
        self.functions = frozenset(d.name for d in grammar.functions)
        #: arities of the functions that share a builtin's name: a call of another arity is the
        #: builtin's (CGA resolves a call by its signature)
        self.overloads: dict[str, set[int]] = {}
        for function in grammar.functions:
            if function.name in BUILTIN_FUNCTIONS:
                self.overloads.setdefault(function.name, set()).add(len(function.params))
        self.attrs = frozenset(d.name for d in grammar.attrs)
        #: renamed values that are also selector words: a branch key keeps the word
        self.selectors = {rename(v): v for v in self.values if v in OPERATION_KEYWORDS}

    def definition(self, definition: ast.Definition) -> ast.Definition:
        params = frozenset(p.name for p in getattr(definition, "params", ())) | frozenset(
            v.name for v in definition.local_variables
        )
        annotations = tuple(
            _rebuilt(a, self.change)
            for a in definition.annotations
            if not (isinstance(definition, ast.Rule) and a.name in _START_ANNOTATIONS)
        )
        changes = {"name": self.rename(definition.name), "annotations": annotations}
        if definition.local_variables:
            changes["local_variables"] = _rebuilt(definition.local_variables, self.change, params)
        if isinstance(definition, ast.Function | ast.Rule):
            changes["body"] = _rebuilt(definition.body, self.change, params)
        else:
            changes["value"] = _rebuilt(definition.value, self.change)
        return dataclasses.replace(definition, **changes)

    def change(self, tree, params: frozenset[str]) -> dict | None:
        if isinstance(tree, ast.Name) and tree.name in self.values and tree.name not in params:
            return {"name": self.rename(tree.name)}
        if isinstance(tree, ast.Call) and tree.name in self.functions:
            arities = self.overloads.get(tree.name)
            if arities is not None and len(tree.args) not in arities:
                return None  # the builtin of that name: max(1, 2) beside a file's max(a)
            return {"name": self.rename(tree.name)}
        if isinstance(tree, ast.Successor):
            return {"name": self.rename(tree.name)}
        if isinstance(tree, ast.Set) and tree.attribute in self.attrs:
            return {"attribute": self.rename(tree.attribute)}
        key = getattr(tree, "key", None) if isinstance(tree, ast.OperationBranch) else None
        if isinstance(key, ast.Name) and key.name in self.selectors:
            # shapeL(...) { shape : A } beside an ``attr shape``: the selector, as in the file
            return {"key": dataclasses.replace(key, name=self.selectors[key.name])}
        return None


def _key(definition: ast.Definition) -> tuple[str, int]:
    params = getattr(definition, "params", None)
    return (definition.name, -1 if params is None else len(params))


def _reads(expression, name: str) -> bool:
    return any(isinstance(n, ast.Name) and n.name == name for n in ast.walk(expression))


def _with_names(expression, mapping: dict[str, str]):
    """``expression`` with the names in ``mapping`` replaced (nothing else renamed)."""

    def change(tree, params):
        if isinstance(tree, ast.Name) and tree.name in mapping:
            return {"name": mapping[tree.name]}
        return None

    return _rebuilt(expression, change)


def _redirected(definition: ast.Definition, mapping: dict[str, str] | None) -> ast.Definition:
    """An importing attr that reads the imported attr it propagates to reads its own value."""
    if not mapping or not isinstance(definition, ast.Attribute):
        return definition
    return dataclasses.replace(definition, value=_with_names(definition.value, mapping))


def resolve_imports(
    grammar: ast.RuleFile, origin: str | Path | None = None, search_folders: tuple[Path, ...] = ()
) -> tuple[ast.RuleFile, list[Problem], set[str]]:
    """Merge the files ``grammar`` imports (and theirs) into it.

    Parameters
    ----------
    grammar
        The parsed importing file.
    origin
        The file it was read from: import paths are relative to its folder. None (a text)
        resolves them against the working directory.
    search_folders
        Where imports are looked up after the file's own project (the user's rules path,
        checked by :class:`~shapegen.engine.project.rule_packages.RulesPath`).

    Returns
    -------
    (ast.RuleFile, list, set)
        The merged grammar (``sources`` holds the imported files' texts), the problems found
        (missing files, cycles, unknown protected or overridden names, and the problems the
        imported files' parse let through) and the prefixes whose file could not be merged
        (references to ``prefix.*`` are not worth reporting after that); a syntax error in an
        imported file raises its :class:`GrammarError`.
    """
    merger = _Merger(tuple(search_folders))
    if origin is not None:
        path = Path(origin).resolve()
        folder, stack = path.parent, (path,)
    else:
        folder, stack = Path.cwd(), ()
    try:
        merged = merger.merge(grammar, folder, stack)
    except RecursionError:
        location = SourceLocation(grammar.filename, 1, 1)
        return grammar, [(location, "the imported files nest too deeply to process")], set()
    merged_grammar = dataclasses.replace(
        merged.grammar, warnings=(*merged.grammar.warnings, *merger.warnings)
    )
    return merged_grammar, merger.problems, merger.failed


def used_definitions(grammar: ast.RuleFile) -> ast.RuleFile:
    """``grammar`` without the imported rules, functions and consts that nothing uses.

    The importing file's own definitions and every attr (the Inspector's, which a caller may
    set) are kept, with all they reach through successors, calls and names. CityEngine compiles
    an imported library whole, but what no rule reaches changes no model; leaving it out spares
    compiling it and refusing an operation that would never run. Load-time checks run before,
    on the whole merge, so a mistake in an unused part is still reported.
    """
    if not grammar.sources:
        return grammar
    by_name: dict[str, list[ast.Definition]] = {}
    for definition in grammar.definitions:
        by_name.setdefault(definition.name, []).append(definition)
    kept: set[int] = set()
    pending = [
        d
        for d in grammar.definitions
        if d.location.file == grammar.filename or isinstance(d, ast.Attribute)
    ]
    while pending:
        definition = pending.pop()
        if id(definition) in kept:
            continue
        kept.add(id(definition))
        for node in ast.walk(definition):
            if isinstance(node, ast.Name | ast.Call | ast.Successor):
                pending.extend(by_name.get(node.name, ()))
            elif isinstance(node, ast.Set):
                pending.extend(by_name.get(node.attribute, ()))
    definitions = tuple(d for d in grammar.definitions if id(d) in kept)
    return dataclasses.replace(grammar, definitions=definitions)

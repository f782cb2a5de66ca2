"""The public entry points to grammars: :func:`load_grammar` reads a rule file,
:func:`parse_grammar` takes source text; both return a :class:`Grammar`.

>>> import shapegen
>>> grammar = shapegen.parse_grammar('''
... attr height = 3
... @StartRule @Lot(4, 1)
... Lot --> extrude(height) split(x) { ~1 : Stone }*
... ''')
>>> model = grammar.build(attrs={"height": 2.0}, seed=1)
>>> len(model.blocks), model.metadata["attrs"]
(4, {'height': 2.0})
"""

from __future__ import annotations

__all__ = ["Grammar", "load_grammar", "parse_grammar", "bundled_rules"]

import functools
import os
import re
from collections.abc import Mapping
from pathlib import Path

import numpy as np

from shapegen.engine.attr_catalogue import AttrCatalogue
from shapegen.engine.program.interpreter import Program
from shapegen.engine.project.rule_packages import PACKAGE_SUFFIX, RulesPath, start_rule_of_package
from shapegen.engine.project.rules_path import bundled_rules, find_bundled_rule
from shapegen.engine.shapes.shape import lot_scope, lot_shape
from shapegen.errors import GrammarError, did_you_mean
from shapegen.grammar import ast
from shapegen.grammar.source_files import read_rule_file
from shapegen.limits import work_clock
from shapegen.model.model import Model


class Grammar:
    """A loaded, checked and compiled grammar.

    Attributes
    ----------
    ast
        The parsed file.
    path
        The file it was read from, or None for a text.
    """

    def __init__(self, tree: ast.RuleFile, path: Path | None = None):
        self.ast = tree
        self.path = path
        self.program = Program(tree)
        self._defaults: dict | None = None

    @property
    def name(self) -> str:
        """The file name, or ``<string>``."""
        return self.ast.filename

    @property
    def dialect(self) -> str:
        """``"cga"`` (lenient where CityEngine is) or ``"grammar"`` (strict): the rule
        file's, decided once when it was read (:func:`shapegen.grammar.definitions.dialect_of`)."""
        return self.ast.dialect

    @property
    def attrs(self) -> dict[str, object]:
        """``name -> default value`` of every ``attr`` (number, boolean or string)."""
        values = self._default_values()
        return {name: values[name] for name in self.program.attr_nodes}

    @property
    def free_parameters(self) -> dict[str, dict]:
        """``name -> {"value", "min", "max"}`` of the ``@Free`` attrs, at their defaults."""
        values = self._default_values()
        return self.program.attributes.free_parameters(values, lot_scope(*self.lot))

    def parameter_ranges(self, attrs: Mapping[str, object] | None = None) -> dict[str, dict]:
        """``name -> {"value", "min", "max"}`` of every attr with a ``@Range`` (free or not),
        with ``attrs`` overriding defaults; the parameters a search may be asked to vary."""
        if not attrs:
            values = self._default_values()
        else:
            from shapegen.engine.program.interpreter import DEFAULT_LOT

            values = self.program.attributes.initial_values(attrs, 0, lot_scope(*DEFAULT_LOT))
        attributes = self.program.attributes
        return attributes.free_parameters(values, lot_scope(*self.lot), only_free=False)

    @functools.cached_property
    def catalogue(self) -> AttrCatalogue:
        """Every fact of the attrs (kind, default, ``@Free``, ``@Range``, group, hidden, ...)
        and the one line for a name no attr has: :mod:`shapegen.engine.attr_catalogue`."""
        return AttrCatalogue(self)

    @property
    def lot(self) -> tuple[float, float]:
        """The default lot (width, depth) in metres: the start rule's ``@Lot`` or 10 x 10."""
        return self.program.attributes.lot_size(self.program.start, self._default_values())

    @property
    def structure(self) -> str:
        """The name of the structure that judges this grammar's models: the start rule's
        ``@Structure(...)``, or ``"blocks"`` (rigid-block statics) without one."""
        return self.program.structure

    def structure_arguments(
        self,
        attrs: Mapping[str, object] | None = None,
        seed: int = 0,
        lot=None,
    ) -> dict[str, object]:
        """The ``@Structure(...)`` keyword arguments for these attrs, without deriving a model:
        what a structure that judges from its arguments alone reads of the design."""
        from shapegen.engine.program.interpreter import DEFAULT_LOT

        attributes, start = self.program.attributes, self.program.start
        values = attributes.initial_values(attrs, seed, lot_scope(*DEFAULT_LOT))
        if lot is None:
            lot = attributes.lot_size(start, values)
        scope = lot_shape(lot)[0].scope
        values = attributes.initial_values(attrs, seed, scope)
        return attributes.structure_arguments(start, values, scope)

    def _default_values(self) -> dict:
        if self._defaults is None:
            from shapegen.engine.program.interpreter import DEFAULT_LOT

            self._defaults = self.program.attributes.initial_values(
                None, 0, lot_scope(*DEFAULT_LOT)
            )
        return self._defaults

    def build(
        self,
        attrs: Mapping[str, object] | None = None,
        seed: int = 0,
        lot=None,
        *,
        max_depth: int | None = None,
        max_shapes: int | None = None,
    ) -> Model:
        """Derive the block model.

        Parameters
        ----------
        attrs
            ``name -> value`` overriding attr defaults (strings are converted to the attr's type,
            so ``{"height": "3.5"}`` works as well as ``{"height": 3.5}``).
        seed
            Seed of ``rand()`` and stochastic rules; the same seed gives the same model.
        lot
            ``(width, depth)`` of the start lot in metres, overriding ``@Lot``, or a polygon:
            three or more ``(x, z)`` points in metres, counter-clockwise seen from above; the
            start shape's scope then has x along the first edge and y up (CityEngine's), and
            ``metadata["lot_polygon"]`` records the points.
        max_depth, max_shapes
            Derivation limits: the longest chain of rules and the most shapes (default: the
            current :class:`~shapegen.limits.WorkLimits`, which bound the rest of the work too);
            exceeding either raises :class:`~shapegen.errors.GrammarError` showing the chain of
            rules.

        Returns
        -------
        Model
            Blocks ``b0``, ``b1``... in derivation order; ``metadata`` holds ``attrs`` (final
            values), ``reports`` (``report()`` values: one value per key, or a list when a key
            was reported several times), ``free_parameters``, ``seed``, ``lot`` and ``grammar``.
        """
        # an overflow on the way is no news: the boundary for numbers (engine/derivation/finite.py)
        # judges every shape an operation makes
        with (
            np.errstate(over="ignore", invalid="ignore", divide="ignore"),
            work_clock("the derivation"),
        ):
            return self.program.derive(
                attrs, seed=seed, lot=lot, max_depth=max_depth, max_shapes=max_shapes
            )

    def __repr__(self) -> str:
        return f"Grammar({self.name!r}, {len(self.ast.rules)} rules)"


def load_grammar(path: str | os.PathLike, rules_path=()) -> Grammar:
    """Load a grammar from a rule file.

    ``path`` names a file (a ``str`` or any ``PathLike``); a bare file name that is not in the
    working directory is looked up among the bundled rules (``load_grammar("wall_windows.grammar")``
    works anywhere, so does ``load_grammar("wall_windows")``). Grammar text is never guessed from
    a string: pass it to :func:`parse_grammar`.

    ``rules_path`` names folders (or rule packages, ``.rpk``) where the file's imports are
    looked up after its own project, such as the one holding ``ESRI.lib``; the folders listed
    in ``SHAPEGEN_RULES_PATH`` come after them. A source not in UTF-8 is read as Windows-1252,
    as CityEngine reads it, with a warning in the model's metadata.

    Raises
    ------
    GrammarError
        For a missing or unreadable file, a string that is grammar text rather than a path (with
        a pointer to :func:`parse_grammar`), syntax errors and load-time problems (all of them
        at once, with file, line, column and caret).
    """
    folders = RulesPath.of(rules_path).folders  # checked once, where it is made
    path = _rule_file(path)
    text, encoding = read_rule_file(path)
    warnings = (f"{path}: {encoding}",) if encoding is not None else ()
    return Grammar(_parse(text, str(path), path, warnings, folders), path)


def parse_grammar(text: str, name: str = "<string>") -> Grammar:
    """Parse and check grammar source ``text``; ``name`` is how errors and reports call it.
    Its ``import`` lines (if any) name files relative to the working directory.

    >>> parse_grammar("@StartRule @Lot(2, 1)\\nLot --> extrude(1) Stone").lot
    (2.0, 1.0)

    Raises
    ------
    GrammarError
        For a ``text`` that is not a string (a path: use :func:`load_grammar`), syntax errors and
        load-time problems.
    """
    if not isinstance(text, str):
        raise GrammarError(
            f"parse_grammar takes the grammar's text as a str, got {type(text).__name__};"
            " to read a rule file use load_grammar(path)"
        )
    if not isinstance(name, str):
        raise GrammarError(f"parse_grammar: name must be a str, got {type(name).__name__}")
    return Grammar(_parse(text, name))


# What a one-line rule file name never contains but grammar text often does.
_RULE_SYNTAX = re.compile(r"-->|^\s*(attr|const|version|import)\s|^\s*@[A-Za-z]")


def _rule_file(path: str | os.PathLike) -> Path:
    """The rule file meant by ``path`` (a bundled one for a bare name not found here)."""
    if isinstance(path, bytes | bytearray) or not isinstance(path, str | os.PathLike):
        raise GrammarError(
            f"load_grammar takes the path of a rule file (str or PathLike), got"
            f" {type(path).__name__}; for grammar text use parse_grammar(text)"
        )
    name = os.fspath(path)
    if isinstance(name, bytes):
        name = os.fsdecode(name)
    if "\0" in name:
        raise GrammarError(f"no grammar file {name!r}: a path cannot contain a NUL character")
    if not name.strip() or "\n" in name or _RULE_SYNTAX.search(name):
        shown = name.strip().splitlines()[0][:40] if name.strip() else ""
        raise GrammarError(
            f"load_grammar takes the path of a rule file, and {shown!r}"
            + ("..." if len(name.strip()) > len(shown) else "")
            + " looks like grammar text"
            + ("" if name.strip() else " (it is empty)")
            + ": use parse_grammar(text) for text"
        )
    candidate = Path(name)
    try:
        if candidate.is_file():
            if candidate.suffix.lower() == PACKAGE_SUFFIX:
                return start_rule_of_package(candidate)
            return candidate
        exists = candidate.exists()
    except OSError as exc:  # a name too long for the file system, a bad character...
        raise GrammarError(f"cannot read {name[:80]!r}: {exc.strerror or exc}") from None
    if exists:
        raise GrammarError(f"cannot read {name!r}: it is not a file")
    if _is_bare_name(name):
        bundled = find_bundled_rule(name)
        if bundled is not None:
            if bundled.suffix.lower() == PACKAGE_SUFFIX:
                return start_rule_of_package(bundled)
            return bundled
    names = bundled_rules()
    # compare the stems: every bundled name ends in .grammar or .rpk, which would make any two
    # look alike
    stems = {Path(bundled).stem: bundled for bundled in names}
    hint = did_you_mean(Path(candidate.name).stem, stems, cutoff=0.75, shown=stems)
    raise GrammarError(
        f"no grammar file {name!r} (not in the working directory nor among the bundled "
        f"rules: {', '.join(names) or 'none'}){hint}"
    )


def _is_bare_name(text: str) -> bool:
    """A file name with no directory part and no spaces (``cluny.grammar``, ``cluny``)."""
    return (
        bool(text)
        and not any(c.isspace() for c in text)
        and os.sep not in text
        and "/" not in text
        and Path(text).name == text
    )


def _parse(
    text: str,
    filename: str,
    origin: Path | None = None,
    warnings: tuple[str, ...] = (),
    search_folders: tuple[Path, ...] = (),
) -> ast.RuleFile:
    """Parse and check ``text`` with the grammar package's loader; imports are resolved from
    ``origin``'s folder (the working directory without one), then ``search_folders``."""
    from shapegen import grammar as language

    return language.load(text, filename, origin, warnings, search_folders)

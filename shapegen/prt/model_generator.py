"""PyPRT's ``ModelGenerator``: rule packages applied to initial shapes, on shapegen's engine.

``ModelGenerator(initial_shapes).generate_model(shape_attributes, rule_package_path,
geometry_encoder, encoder_options)`` as PyPRT documents it: one attribute dictionary per
initial shape, or one for all (any other count is an error: nothing is generated and an empty
list returned, as PyPRT does, with the reason on standard error). A shape that cannot be
generated (a shape shapegen cannot start on, a derivation error) gives a model without geometry
whose ``get_cga_errors()`` says why, and the same line on standard error; the other shapes are
generated. A dictionary holds the rule's
attrs, and ``seed`` (int, default 0), ``shapeName``, ``ruleFile`` and ``startRule``
(``"Default$Lot"``: the style, then the rule). The encoders:

``com.esri.pyprt.PyEncoder``
    returns one :class:`~shapegen.prt.generated_models.GeneratedModel` per initial shape;
    options ``emitGeometry``, ``emitReport``, ``triangulate`` (booleans).
``com.esri.prt.codecs.OBJEncoder``, ``com.esri.prt.codecs.GLTFEncoder``
    write the models to ``outputPath`` (``baseName``, default ``base_name``) with
    ``CGAReport.txt``, ``CGAPrint.txt`` and ``CGAError.txt`` beside them; return ``[]``.

Any other encoder is refused with one line (:class:`~shapegen.errors.OptionError`), and so is
an option an encoder does not take.
"""

from __future__ import annotations

__all__ = ["ModelGenerator", "PY_ENCODER"]

import contextlib
import io
import sys
from collections.abc import Mapping, Sequence
from dataclasses import replace
from pathlib import Path

from shapegen.errors import GeometryError, GrammarError, InputFormatError, OptionError
from shapegen.model.model import Model
from shapegen.prt.generated_models import GeneratedModel
from shapegen.prt.initial_shapes import Footprint, InitialShape, start_of

PY_ENCODER = "com.esri.pyprt.PyEncoder"
PY_ENCODER_OPTIONS = {"emitGeometry": True, "emitReport": True, "triangulate": False}
SHAPE_KEYS = ("seed", "shapeName", "ruleFile", "startRule")
"""Keys of a shape attribute dictionary that are not the rule's attrs."""


class ModelGenerator:
    """Generates models on a list of :class:`InitialShape` (PyPRT's ``pyprt.ModelGenerator``)."""

    def __init__(self, initial_shapes: Sequence[InitialShape]):
        shapes = list(initial_shapes)
        if not all(isinstance(shape, InitialShape) for shape in shapes):
            raise TypeError("ModelGenerator takes a list of InitialShape")
        self._shapes = shapes
        self._grammars: dict[str, object] = {}

    def generate_model(
        self,
        shape_attributes: Sequence[Mapping[str, object]],
        rule_package_path: str = "",
        geometry_encoder: str = PY_ENCODER,
        encoder_options: Mapping[str, object] | None = None,
    ) -> list[GeneratedModel]:
        """Generate a model on every initial shape; see the module's documentation."""
        from shapegen.prt import encoders

        attributes = list(shape_attributes)
        if len(attributes) == 1:
            attributes = attributes * len(self._shapes)
        if len(attributes) != len(self._shapes):
            print(
                f"shapegen.prt: {len(shape_attributes)} shape attribute dictionaries for"
                f" {len(self._shapes)} initial shapes (give one, or one per shape):"
                " nothing generated",
                file=sys.stderr,
            )
            return []
        options = dict(encoder_options or {})
        if geometry_encoder == PY_ENCODER:
            flags = _py_encoder_options(options)
            return [
                self._generate(k, shape, attributes[k], rule_package_path, **flags)
                for k, shape in enumerate(self._shapes)
            ]
        write = encoders.file_encoder(geometry_encoder, options)
        models = [
            self._generate(k, shape, attributes[k], rule_package_path)
            for k, shape in enumerate(self._shapes)
        ]
        write(models)
        return []

    def _generate(
        self,
        index: int,
        shape: InitialShape,
        attributes: Mapping[str, object],
        package: str,
        **flags,
    ) -> GeneratedModel:
        grammar = self._grammar(package, attributes)
        seed = attributes.get("seed", 0)
        if isinstance(seed, bool) or not isinstance(seed, int):
            raise OptionError(f"shape attribute 'seed' must be an int, got {seed!r}")
        known = grammar.catalogue
        overrides = {k: v for k, v in attributes.items() if k not in SHAPE_KEYS and k in known}
        ignored = sorted(k for k in attributes if k not in SHAPE_KEYS and k not in known)
        printed = io.StringIO()
        try:
            base = start_of(shape)
            lot = base.lot() if isinstance(base, Footprint) else base
            with contextlib.redirect_stdout(printed):
                model = grammar.build(attrs=overrides, seed=seed, lot=lot)
        except (InputFormatError, GrammarError, GeometryError) as exc:
            # CityEngine's runtime logs a shape it cannot generate and goes on with the others
            problem = str(exc).splitlines()[0]
            print(f"shapegen.prt: initial shape {index}: {problem}", file=sys.stderr)
            empty = Model([], metadata={"warnings": [problem], "reports": {}, "attrs": {}})
            return GeneratedModel(empty, index, {}, printed.getvalue(), **flags)
        if ignored:
            model.metadata.setdefault("warnings", []).extend(
                f"shape attribute {name!r} is not an attr of the rule: ignored" for name in ignored
            )
        used = _attributes(grammar, model)
        placed = _placed(model, base)
        texture = _texture(shape, placed, grammar)
        return GeneratedModel(placed, index, used, printed.getvalue(), texture=texture, **flags)

    def _grammar(self, package: str, attributes: Mapping[str, object]):
        from shapegen.engine.grammar_api import load_grammar

        if not package:
            raise OptionError("generate_model needs the path of a rule package (.rpk)")
        grammar = self._grammars.get(package)
        if grammar is None:
            grammar = self._grammars[package] = load_grammar(package)
        _check_rule_file(grammar, attributes.get("ruleFile"))
        _set_start_rule(grammar, attributes.get("startRule"))
        return grammar


def _placed(model, base):
    """``model`` moved where CityEngine derives it on the initial shape (raised to its height,
    turned back if it faces down); its ground is the shape's height. A start of several faces
    is derived where it is."""
    if not isinstance(base, Footprint) or (not base.faces_down and base.height == 0.0):
        return model
    blocks = [replace(b, vertices=base.place(b.vertices)) for b in model.blocks]
    surfaces = [replace(s, vertices=base.place(s.vertices)) for s in model.surfaces]
    return replace(model, blocks=blocks, surfaces=surfaces, ground=base.height)


def _texture(shape: InitialShape, model, grammar):
    """The initial shape's texturing (read from its OBJ file); its warnings, the count of faces
    left without its texture coordinates, and the rule's operations after which the carried
    coordinates may differ from CityEngine's, added to ``model``'s warnings."""
    from shapegen.prt.initial_textures import initial_texture, moving_operations, texture_warning

    if not shape.get_path():
        return None
    try:
        texture, warnings = initial_texture(Path(shape.get_path()), shape._depth)
    except InputFormatError as exc:  # the geometry was read: the model goes on untextured
        texture, warnings = None, [f"{str(exc).splitlines()[0]}: no texture coordinates read"]
    lost = texture_warning(model, texture)
    notes = [*warnings, *([lost] if lost else [])]
    moves = moving_operations(grammar.ast) if texture is not None and texture.has_uvs else []
    if moves:
        notes.append(
            f"texture coordinates: the rule uses {', '.join(moves)}; shapegen carries an initial"
            " shape's coordinates by where faces lie, so a face moved within an initial face's"
            " plane, or inserted on it, takes those of where it lies, which CityEngine's need"
            " not be"
        )
    if notes:
        model.metadata.setdefault("warnings", []).extend(notes)
    return texture


def _py_encoder_options(options: dict) -> dict:
    unknown = sorted(set(options) - set(PY_ENCODER_OPTIONS))
    if unknown:
        raise OptionError(
            f"the PyEncoder takes {', '.join(PY_ENCODER_OPTIONS)}; not {', '.join(unknown)}"
        )
    values = {**PY_ENCODER_OPTIONS, **options}
    for name, value in values.items():
        if not isinstance(value, bool):
            raise OptionError(f"the PyEncoder's {name!r} is a boolean, got {value!r}")
    return {
        "emit_geometry": values["emitGeometry"],
        "emit_report": values["emitReport"],
        "triangulate": values["triangulate"],
    }


def _check_rule_file(grammar, rule_file: object) -> None:
    """A ``ruleFile`` (``bin/name.cgb``) must name the package's start rule file, the one
    shapegen derives."""
    if rule_file is None:
        return
    if Path(str(rule_file)).stem != Path(grammar.path).stem:
        raise OptionError(
            f"ruleFile {rule_file!r}: shapegen derives the package's start rule file"
            f" {Path(grammar.path).name!r} only"
        )


def _set_start_rule(grammar, start: object) -> None:
    """``startRule`` is ``"Style$Rule"``; shapegen derives the default style."""
    if start is None:
        return
    style, _, name = str(start).rpartition("$")
    if style not in ("", "Default"):
        raise OptionError(f"startRule {start!r}: shapegen derives the Default style only")
    for rule in grammar.ast.rules:
        if rule.name == name and not rule.params:
            grammar.program.start = rule
            return
    raise OptionError(f"startRule {start!r}: the rule file has no rule {name!r} without parameters")


def _plain(value: object) -> object:
    """A CGA array as PyPRT gives it: a list, or a list of rows for more than one row."""
    from shapegen.engine.expressions.arrays import Array

    if isinstance(value, Array):
        items = list(value.values)
        if value.rows <= 1:
            return items
        return [items[r * value.columns : (r + 1) * value.columns] for r in range(value.rows)]
    return list(value) if isinstance(value, tuple) else value


def _attributes(grammar, model) -> dict:
    """The attrs a model was generated with, as PyPRT lists them: hidden ones left out."""
    final = model.metadata.get("attrs", {})
    out = {}
    for name, entry in grammar.catalogue.items():
        if not entry.hidden and name in final:
            out[name] = _plain(final[name])
    return out

"""The interpreter: derives a block :class:`~shapegen.model.model.Model` from a grammar's AST.

:class:`Program` compiles a parsed grammar once (expressions and rule bodies become closures);
:meth:`Program.derive` runs the derivation for given attribute values, seed and lot.

The derivation is depth first, in the order successors appear in the rules, and uses an explicit
stack rather than recursion, so deep grammars need no Python recursion. Each 3D leaf shape (not
``NIL``, positive volume) becomes one block (a box filling its scope, a closed convex mesh) or
the blocks of its inserted primitive, numbered ``b0``, ``b1``... in derivation order; any other
leaf (a face, an open mesh, a closed solid that is not convex, kept as derived) is a
:class:`~shapegen.model.appearance.Surface` of the model, with the reason it is not a block.
Randomness (``rand``, stochastic rules) comes from CityEngine's streams: one per shape, begun from
its parent's when the shape is made (:mod:`~shapegen.engine.derivation.random_streams`), so a
shape's draws do not depend on how many shapes were derived before it elsewhere in the tree.

The work is shared with :mod:`~shapegen.engine.derivation.state` (the state of a derivation),
:mod:`~shapegen.engine.operations.compiler` (compiling rule bodies and operations,
:class:`~shapegen.engine.operations.compiler.OperationCompiler`) and
:mod:`~shapegen.engine.program.attributes` (attr and const values, ``@Range``, ``@Lot``,
``@Structure``).
"""

from __future__ import annotations

__all__ = [
    "DEFAULT_LOT",
    "DEFAULT_MAX_DEPTH",
    "DEFAULT_MAX_SHAPES",
    "Program",
    "format_chain",
]

import contextlib
import io
import numbers
import sys
from collections.abc import Mapping

from shapegen.engine.derivation.occlusion import Occlusion
from shapegen.engine.derivation.state import (
    DEFAULT_MAX_DEPTH,
    DEFAULT_MAX_SHAPES,
    TOO_DEEP,
    Derivation,
    ShapeState,
    format_chain,
    root_state,
)
from shapegen.engine.expressions.compiler import ExpressionCompiler, format_value
from shapegen.engine.expressions.local_variables import local_scope, with_locals
from shapegen.engine.operations.compiler import OperationCompiler
from shapegen.engine.operations.template_primitives import INSERT
from shapegen.engine.program.attributes import (
    DEFAULT_LOT,
    AttributeValues,
    checked_structure,
    shown,
)
from shapegen.engine.program.held import derivation_held
from shapegen.engine.program.leaf_batches import (
    BOX_LEAF_FACES,
    box_corners,
    geometry_leaves,
    rectangle_corners,
)
from shapegen.engine.shapes.shape import FACE, MASS, lot_scope, lot_shape
from shapegen.errors import GeometryError, GrammarError
from shapegen.geometry.convex import hole_free
from shapegen.geometry.cut import NEEDS_CUT, placed_convex_decomposition
from shapegen.geometry.mesh import Mesh
from shapegen.geometry.trim import trimmed_solid
from shapegen.grammar import ast
from shapegen.grammar.names import RESERVED_ATTRIBUTES
from shapegen.limits import limit_hint
from shapegen.model.appearance import DEFAULT_APPEARANCE, SolidLeaf, Surface
from shapegen.model.block import MAX_DENSITY, Block, density_is_valid
from shapegen.model.model import Model
from shapegen.model.scope import Scope
from shapegen.tolerances import MIN_LEAF_SIZE

_MIN_SIZE = MIN_LEAF_SIZE  # m; see shapegen.tolerances


class _Rule:
    __slots__ = ("name", "arity", "body", "node")

    def __init__(self, node: ast.Rule):
        self.name = node.name
        self.arity = len(node.params)
        self.body = None
        self.node = node


class Program:
    """A compiled grammar, ready to derive models.

    Parameters
    ----------
    grammar
        The parsed file (:func:`shapegen.grammar.parse`).
    """

    def __init__(self, grammar: ast.RuleFile):
        self.grammar = grammar
        # CityEngine rule files (.cga) get CityEngine's semantics: its scope after extruding a
        # comp face (y along the extrusion; .grammar files keep shapegen's, the face's z grows),
        # its repeat counts, and its leniency: where its runtime warns and carries on, so does
        # the derivation (the model's metadata lists the warnings); .grammar files stay strict.
        self.cga_dialect = grammar.dialect == "cga"
        # component tags are kept only where the file can read them (isTagged, geometry.tags,
        # geometry.hasTags): elsewhere nothing could tell them, and keeping them costs
        self.reads_tags = reads_tags(grammar)
        self.attr_nodes = {a.name: a for a in grammar.attrs}
        self.const_nodes = {c.name: c for c in grammar.consts}
        global_names = set(self.attr_nodes) | set(self.const_nodes) | set(RESERVED_ATTRIBUTES)
        self.expressions = ExpressionCompiler(grammar, global_names, _component_values)
        self.expressions.compile_functions()
        definitions = {
            name: self._value(node)
            for name, node in {**self.attr_nodes, **self.const_nodes}.items()
        }
        self.attributes = AttributeValues(
            self.attr_nodes, self.const_nodes, definitions, self.expressions
        )
        # Rules by (name, arity): CGA overloads a rule name by its number of parameters.
        self.rules = {(rule.name, len(rule.params)): _Rule(rule) for rule in grammar.rules}
        self.operations = OperationCompiler(grammar, self.expressions, self.rules)
        for rule in self.rules.values():
            params = {p.name: k for k, p in enumerate(rule.node.params)}
            scope, extend = local_scope(self.expressions, rule.node, params)
            rule.body = self.operations.body(rule.node.body, scope)
            if extend is not None:  # with ( ... ): the values follow the rule's arguments
                rule.body = _rule_with_locals(rule.body, extend)
        self.start = grammar.start_rule
        if self.start is None:
            raise GrammarError(
                f"{grammar.filename}: the grammar has no rules"
                + (
                    " (a library of attrs and functions, for rule files that import it)"
                    if self.cga_dialect and grammar.definitions
                    else ""
                )
            )
        if self.start.params:
            raise self.error(
                self.start, f"the start rule {self.start.name!r} cannot take parameters"
            )
        self.structure = checked_structure(self.start, self.error)

    def _value(self, node):
        """An attr's or const's compiled value, its ``with`` variables evaluated first."""
        scope, extend = local_scope(self.expressions, node, {})
        value = self.expressions.compile(node.value, scope)
        return value if extend is None else with_locals(value, extend)

    def error(self, node, message: str) -> GrammarError:
        return self.expressions.error(node, message)

    # ------------------------------------------------------------------ derivation
    def derive(
        self,
        attrs: Mapping[str, object] | None = None,
        seed: int = 0,
        lot=None,
        max_depth: int | None = None,
        max_shapes: int | None = None,
        _first_pass: Occlusion | None = None,
    ) -> Model:
        """Derive the block model; see :meth:`shapegen.engine.grammar_api.Grammar.build`.

        ``max_depth`` and ``max_shapes`` default to the current
        :class:`~shapegen.limits.WorkLimits`, which bound the rest of the work too.
        """
        with derivation_held():
            return self._derive(attrs, seed, lot, max_depth, max_shapes, _first_pass)

    def _derive(self, attrs, seed, lot, max_depth, max_shapes, _first_pass) -> Model:
        if isinstance(seed, bool) or not isinstance(seed, numbers.Integral):
            raise GrammarError(f"seed must be a whole number, got {shown(seed)}")
        if lot is None:
            defaults = self.attributes.initial_values(attrs, seed, lot_scope(*DEFAULT_LOT))
            lot = self.attributes.lot_size(self.start, defaults)
        start, lot_metadata = lot_shape(lot)  # a Lot, or what Lot.of takes (its one check)
        start_scope = start.scope
        run = Derivation(self, seed, max_depth, max_shapes)
        run.warnings.extend(self.grammar.warnings)  # what the load let through (.cga only)
        # the object frame (initialShape.origin) is known before attrs read it
        run.object_rotation = start_scope.rotation
        run.start_shape = start
        values = self.attributes.initial_values(attrs, seed, start_scope, run)
        run.occlusion = Occlusion() if _first_pass is None else _first_pass
        root = root_state(run, start, values, ())
        root.rule_path = (self.start.name,)
        leaves: list[ShapeState] = []
        stack: list[tuple] = [(root, self.rules[(self.start.name, 0)], ())]
        # What print() writes in a pass that turns out to be the first of two is not shown:
        # CityEngine prints once, in the pass that makes the model.
        printed = io.StringIO()
        capture = contextlib.redirect_stdout(printed) if _first_pass is None else None
        try:
            with capture or contextlib.nullcontext():
                while stack:
                    state, rule, args = stack.pop()
                    if rule is None:
                        leaves.append(state)
                        continue
                    out: list[tuple] = []
                    if rule.body(state, args, out) and state.is_leaf():
                        out.append((state, None, ()))
                    stack.extend(reversed(out))
        except RecursionError:
            sys.stdout.write(printed.getvalue())
            raise GrammarError(TOO_DEEP) from None
        except BaseException:  # what was printed before the error is shown, as it was
            sys.stdout.write(printed.getvalue())
            raise
        if run.occlusion.asked and _first_pass is None:  # CityEngine's second pass
            first_pass = run.occlusion.second_pass(leaves)
            return self._derive(attrs, seed, lot, max_depth, max_shapes, first_pass)
        sys.stdout.write(printed.getvalue())
        blocks, surfaces = self._blocks(leaves, run)
        metadata = {
            "grammar": self.grammar.filename,
            "dialect": self.grammar.dialect,  # what the statics ask (statics.bodies)
            "seed": int(seed),
            **lot_metadata,
            "attrs": {name: values[name] for name in self.attr_nodes},
            "free_parameters": self.attributes.free_parameters(values, start_scope),
            "reports": {k: v[0] if len(v) == 1 else v for k, v in run.reports.items()},
            "warnings": list(run.warnings),  # assets not found, operations ignored
            "cga_errors": run.cga_errors,  # operations skipped (engine/derivation/cga_errors.py)
            "leaves": run.leaf_count,  # leaf shapes that gave a block or a surface
            "structure": {
                "name": self.structure,
                "arguments": self.attributes.structure_arguments(self.start, values, start_scope),
            },
        }
        return Model(blocks, metadata=metadata, surfaces=surfaces)

    def _blocks(
        self, leaves: list[ShapeState], run: Derivation
    ) -> tuple[list[Block], list[Surface]]:
        """The blocks and surfaces of the leaves, in derivation order: a box filling its scope
        or a closed convex mesh with volume is a block, an inserted primitive gives its blocks,
        any other geometry (a face, an open or non-convex mesh) a surface."""
        boxes = [
            s
            for s in leaves
            if s.shape.kind == MASS
            and s.shape.geometry is None
            and min(s.shape.scope.d) > _MIN_SIZE
        ]
        limit = run.limits.max_blocks
        if len(boxes) > limit:
            raise self._too_many_blocks(len(boxes), run, boxes[limit].rule_path)
        corners = {}
        if boxes:
            world = box_corners([s.shape.scope for s in boxes])
            corners = {id(s): world[k] for k, s in enumerate(boxes)}
        rectangles = _rectangle_leaves(leaves)
        placed = geometry_leaves(leaves)
        blocks: list[Block] = []
        surfaces: list[Surface] = []
        seen = produced = 0  # leaves that gave geometry: CityEngine's generated meshes
        for state in leaves:
            count = len(blocks) + len(surfaces)
            produced += count > seen  # the previous leaf gave something
            seen = count
            kind = state.shape.kind
            if state.shape.geometry is not None and kind in (MASS, FACE):
                made = self._geometry_leaf(state, *placed[id(state)], len(blocks), surfaces)
                if len(blocks) + len(made) > limit:
                    raise self._too_many_blocks(len(blocks) + len(made), run, state.rule_path)
                blocks.extend(made)
                continue
            if kind == FACE:
                vertices, faces, area = rectangles[id(state)]
                if area > _MIN_SIZE**2:
                    face = Mesh.of_valid_faces(vertices, faces)
                    surfaces.append(_surface(state, face, "a face (no volume)", len(surfaces)))
                continue
            if kind == MASS:
                vertices = corners.get(id(state))
                if vertices is None:
                    if self.cga_dialect:  # extrude(0): CityEngine draws the face
                        self._flat_box(state, surfaces)
                    continue
                density, structural, fixed = self._properties(state)
                blocks.append(
                    Block(
                        vertices,
                        BOX_LEAF_FACES,
                        density=density,
                        id=f"b{len(blocks)}",
                        tags=state.labels,
                        structural=structural,
                        fixed=fixed,
                        rule_path=state.rule_path,
                        appearance=state.appearance,
                    )
                )
            elif kind == INSERT:
                name, params, node = state.shape.insert
                scope = state.shape.scope
                run.check_clock(node)
                try:
                    pieces = _insert(name, scope, params)
                except GeometryError as exc:
                    raise self.error(node, f"i({name!r}): {exc}") from None
                if len(blocks) + len(pieces) > limit:
                    raise self._too_many_blocks(len(blocks) + len(pieces), run, state.rule_path)
                density, structural, fixed = self._properties(state)
                for piece in pieces:
                    piece.density = density
                    piece.structural = structural
                    piece.fixed = fixed
                    piece.id = f"b{len(blocks)}"
                    piece.tags = state.labels + tuple(
                        t for t in piece.tags if t not in state.labels
                    )
                    piece.rule_path = state.rule_path
                    if state.appearance is not None:
                        piece.appearance = state.appearance
                    blocks.append(piece)
        run.leaf_count = produced + (len(blocks) + len(surfaces) > seen)
        return blocks, surfaces

    @staticmethod
    def _flat_box(state: ShapeState, surfaces: list) -> None:
        """A box leaf flat along one scope axis (``extrude(0)``) as the face it is."""
        size = state.shape.scope.size
        flat = [k for k in range(3) if size[k] <= _MIN_SIZE]
        if len(flat) == 1:
            face = Mesh.rectangle(size, flat[0])
            world = face.transformed(state.shape.scope.rotation, state.shape.scope.origin)
            surfaces.append(_surface(state, world, "a face (no volume)", len(surfaces)))

    @staticmethod
    def _flat_solid(state: ShapeState, mesh: Mesh, surfaces: list) -> None:
        """A closed mesh with no volume (a face extruded by 0) as the faces it has that face
        along the scope's y, the side it was extruded towards; the rest are the same faces
        turned, or edges."""
        areas, normals = mesh.face_areas(), mesh.face_normals()
        up = state.shape.scope.rotation[:, 1]
        keep = [k for k in range(mesh.n_faces) if areas[k] > _MIN_SIZE**2 and normals[k] @ up > 0]
        if keep:
            surfaces.append(_surface(state, mesh.subset(keep), "a face (no volume)", len(surfaces)))

    def _geometry_leaf(
        self, state: ShapeState, mesh: Mesh, area: float, number: int, surfaces: list
    ) -> list[Block]:
        """The blocks of a leaf with geometry: one for a closed convex mesh. Otherwise none,
        and the leaf is added to ``surfaces`` with the reason: a closed solid that is not
        convex stays as derived (``"not convex"``, with its :class:`SolidLeaf`), and the
        statics cut it into convex parts of one body when they judge
        (:mod:`shapegen.statics.standins`), so a model nobody judges never pays for the cut.
        The model keeps the leaf's own geometry: an open shell is not capped and a solid is not
        replaced by its hull here, so the model is the one CityEngine's runtime derives (its
        volume and bounding box). ``mesh`` is the leaf's geometry in world coordinates, ``area``
        its faces' total (m^2)."""
        # the leaf's geometry is made of polygons without holes covering the same surface (what
        # blocks and the statics' cut take); its faces and holes as rings are what PyPRT writes
        holed = state.shape.geometry is not None and state.shape.geometry.holes
        polygons = tuple(state.shape.world_mesh().rings()) if holed else None
        solid = self._trimmed_solid(state, mesh)
        if solid is not None:
            # an insert cut at its trim planes is drawn open, as CityEngine draws it: an open
            # shell, which the statics cap when they judge, with the leaf's own density and
            # flags (the SolidLeaf, which keeps the closed cut for the volume)
            density, structural, fixed = self._properties(state)
            scope = state.shape.scope
            leaf = SolidLeaf(density, structural, fixed, solid, scope.rotation, scope.origin)
            surfaces.append(_surface(state, mesh, "not closed", len(surfaces), leaf, polygons))
            return []
        if state.shape.kind == FACE or not mesh.is_closed:
            if area > _MIN_SIZE**2:
                reason = "a face (no volume)" if state.shape.kind == FACE else "not closed"
                surfaces.append(_surface(state, mesh, reason, len(surfaces), None, polygons))
            return []
        volume = mesh.signed_volume()
        if abs(volume) <= _MIN_SIZE**3:
            if self.cga_dialect:  # extrude(0) of any face: CityEngine draws the face
                self._flat_solid(state, mesh, surfaces)
            return []
        if volume < 0:
            surfaces.append(
                _surface(state, mesh, "faces turned inwards", len(surfaces), None, polygons)
            )
            return []
        # judged and cut in scope coordinates, where the same asset gives the same mesh
        scope = state.shape.scope
        local = hole_free(state.shape.mesh())
        pieces = placed_convex_decomposition(local, scope.rotation, scope.origin, cut=False)
        density, structural, fixed = self._properties(state)
        if pieces is None or pieces is NEEDS_CUT:
            solid = SolidLeaf(density, structural, fixed, local, scope.rotation, scope.origin)
            surfaces.append(_surface(state, mesh, "not convex", len(surfaces), solid, polygons))
            return []
        blocks = []
        for piece in pieces:
            clean = piece.cleaned()
            blocks.append(
                Block(
                    clean.vertices,
                    clean.faces,
                    density=density,
                    id=f"b{number + len(blocks)}",
                    tags=state.labels,
                    structural=structural,
                    fixed=fixed,
                    rule_path=state.rule_path,
                    appearance=state.appearance,
                    body=f"b{number}" if len(pieces) > 1 else "",
                )
            )
        return blocks

    @staticmethod
    def _trimmed_solid(state: ShapeState, mesh: Mesh) -> Mesh | None:
        """The closed solid (scope coordinates) of a leaf that an insert's cut at its trim
        planes left open (``mesh``, world coordinates); None for any other leaf, and for a cut
        changed since (``primitiveCube() s(...)`` scales it), which is an open shell as any."""
        geometry = state.shape.geometry
        if state.shape.kind == FACE or geometry is None or mesh.is_closed:
            return None
        solid = trimmed_solid(geometry)
        if solid is None or solid.signed_volume() <= _MIN_SIZE**3:
            return None
        return solid

    def _too_many_blocks(self, count: int, run: Derivation, chain: tuple) -> GrammarError:
        return GrammarError(
            f"the model has at least {count} blocks, more than {run.limits.max_blocks} "
            f"(rules: {format_chain(chain)}) {limit_hint('max_blocks', run.limits)}"
        )

    def _properties(self, state: ShapeState) -> tuple[float, bool, bool]:
        attrs = state.attrs
        density, structural, fixed = attrs["density"], attrs["structural"], attrs["fixed"]
        if type(density) is not float or not density_is_valid(density):
            raise GrammarError(
                f"attr 'density' must be a number in [0, {MAX_DENSITY:g}] (kg/m^3), got "
                f"{format_value(density)!r} (rules: {format_chain(state.rule_path)})"
            )
        for name, value in (("structural", structural), ("fixed", fixed)):
            if type(value) is not bool:
                raise GrammarError(
                    f"attr {name!r} must be true or false, got "
                    f"{format_value(value)!r} (rules: "
                    f"{format_chain(state.rule_path)})"
                )
        return density, structural, fixed


def _rectangle_leaves(leaves: list[ShapeState]) -> dict[int, tuple]:
    """``id(leaf) -> (world corners, faces, area)`` of the face leaves that fill their scopes,
    placed together per flat axis (:mod:`shapegen.engine.program.leaf_batches`)."""
    by_axis: dict[int, list[ShapeState]] = {}
    for state in leaves:
        shape = state.shape
        if shape.kind == FACE and shape.geometry is None:
            by_axis.setdefault(shape.normal_axis, []).append(state)
    out = {}
    for axis, states in by_axis.items():
        corners, areas, mirrored = rectangle_corners([s.shape.scope for s in states], axis)
        for k, state in enumerate(states):
            out[id(state)] = (corners[k], _TURNED if mirrored[k] else _RECTANGLE, areas[k])
    return out


_RECTANGLE = ((0, 1, 2, 3),)
_TURNED = ((0, 3, 2, 1),)  # a mirrored scope's rectangle, turned to face out (Mesh.transformed)


def _surface(
    state: ShapeState,
    mesh,
    reason: str,
    number: int,
    solid: SolidLeaf | None = None,
    polygons: tuple | None = None,
) -> Surface:
    return Surface(
        mesh.vertices,
        mesh.faces,
        appearance=state.appearance or DEFAULT_APPEARANCE,
        tags=state.labels,
        rule_path=state.rule_path,
        reason=reason,
        id=f"s{number}",
        solid=solid,
        polygons=polygons,
    )


def _insert(name: str, scope: Scope, params: dict) -> list[Block]:
    from shapegen.primitives import insert

    return insert(name, scope, **params)


def _component_values(compiler, node, params):
    """The comp function, compiled by the operations' module of it: the CGA operations are
    loaded when a rule file uses one, not with the engine."""
    from shapegen.engine.operations.cga.comp_values import compile_component_values

    return compile_component_values(compiler, node, params)


def reads_tags(grammar: ast.RuleFile) -> bool:
    """Whether the rule file reads component tags: isTagged(), geometry.tags, geometry.hasTags."""
    from shapegen.grammar.tree import walk

    for item in walk(grammar):
        if type(item) is ast.Call and item.name == "isTagged":
            return True
        if type(item) is ast.ShapeAttribute and item.obj == "geometry":
            if item.field in ("tags", "hasTags"):
                return True
    return False


def _rule_with_locals(body, extend):
    def with_locals(state, args, out):
        return body(state, extend(args, state), out)

    return with_locals

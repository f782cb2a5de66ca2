"""Stand-ins: the solids the statics judge in place of leaves the model keeps as drawn.

A solid leaf that is not convex (an extruded L-shaped footprint, a column's moulding) is
kept as derived, a surface with its :class:`~shapegen.model.appearance.SolidLeaf`; here, when
the statics judge, it is cut into convex parts of one body by the planes of its faces
(:func:`~shapegen.geometry.cut.placed_convex_decomposition`, in its scope, so one shape is cut
once however often and at whatever size it is placed): ``"not convex, cut into convex
parts"``, with the leaf's own density, ``structural`` and ``fixed``. One that does not cut
stands on its hull, as below.

A real CityEngine rule models what is seen. A column shaft is a fluted tube without its end
discs, an echinus a flared bowl open at both ends, a moulding a closed solid that does not cut
into convex pieces: none is a convex block, so the derivation leaves them out of the blocks, as
surfaces with the reason (the derived model stays exactly the one CityEngine's runtime makes).
What they carry would then rest on nothing. For the statics alone, each such leaf gets a
*stand-in*, a block (or the parts of one body) appended after the model's own blocks in a
:class:`StaticsModel`:

- a shell left open only where loops of edges can be capped (the shaft) is closed by one face
  per loop (:func:`~shapegen.geometry.solids.capped`): ``"open shell, capped"`` when the closed
  solid is convex or cuts into convex parts of one body, ``"open shell, capped, on its convex
  hull"`` when it does not;
- a closed solid that does not cut into convex pieces stands on its convex hull:
  ``"not convex, on its convex hull"``;
- a closed mesh whose faces look inwards is turned out: ``"faces turned inwards, turned out"``
  (``", on its convex hull"`` added when it does not cut into convex parts).

A hull carries the leaf's own weight (its density scaled by the leaf's volume over the hull's);
its centroid is the hull's. Contacts act over the convex hull of the touching region anyway,
so a hull is exact where the leaf touches its neighbours on its flat ends. What cannot stand in
(a mesh that runs an edge twice, a face) stays out, counted by reason. The stand-ins are
reported (``analysis.stand_ins``) and never change the model that is written or shown: an
analysis of a :class:`StaticsModel` gives its per-block figures for the model's own blocks.

>>> from shapegen.geometry.mesh import Mesh
>>> from shapegen.model import Block, Model
>>> from shapegen.model.appearance import Surface
>>> tube = Mesh.box((1.0, 2.0, 1.0))
>>> tube = Mesh(tube.vertices + [0.0, 1.0, 0.0], tube.faces[2:])  # no bottom nor top
>>> lintel = Block.box((-0.5, 3.0, 0.0), (1.5, 3.5, 1.0))
>>> model = Model([lintel], surfaces=[Surface(tube.vertices, tube.faces, reason="not closed")])
>>> judged = statics_model(model)
>>> len(judged.blocks), judged.stand_ins.by_reason
(2, {'open shell, capped': 1})
"""

from __future__ import annotations

__all__ = [
    "StandIns",
    "StaticsModel",
    "design_blocks",
    "design_figures",
    "from_cityengine",
    "statics_model",
]

from collections import Counter
from dataclasses import dataclass, field, replace

import numpy as np

from shapegen.errors import GeometryError
from shapegen.geometry.cut import convex_decomposition, placed_convex_decomposition
from shapegen.geometry.mesh import Mesh
from shapegen.geometry.solids import capped, hull_corners
from shapegen.model.block import DEFAULT_DENSITY, Block, compute_mass_properties
from shapegen.model.model import Model, PointLoad
from shapegen.tolerances import COINCIDENT_M, COINCIDENT_REL, MIN_LEAF_SIZE

CUT = "not convex, cut into convex parts"
CAPPED = "open shell, capped"
CAPPED_HULL = "open shell, capped, on its convex hull"
HULL = "not convex, on its convex hull"
TURNED = "faces turned inwards, turned out"
TURNED_HULL = "faces turned inwards, turned out, on its convex hull"

# what became of a block too small to judge (:func:`statics_model`, a real CityEngine model's)
MERGED = "merged into its leaf's body"
CARRIED = "carried as load by the block it touches"
TOUCHING_NOTHING = "left out, touching no block"
NOT_STRUCTURAL = "left out, not structural"

# the surfaces' reasons (the interpreter's, kept in the JSON format) a stand-in is tried for
_OPEN, _NOT_CONVEX, _INWARDS = "not closed", "not convex", "faces turned inwards"
_CANDIDATES = (_OPEN, _NOT_CONVEX, _INWARDS)


@dataclass(frozen=True)
class StandIns:
    """What the statics judge in place of the model's surfaces.

    Attributes
    ----------
    design_blocks
        Number of the model's own blocks; the stand-ins follow them in the statics model.
    blocks
        Number of stand-in blocks (a stand-in cut into convex parts has several).
    by_reason
        Leaves stood in for, by what was done: ``"not convex, cut into convex parts"``,
        ``"open shell, capped"``, ``"open shell,
        capped, on its convex hull"``, ``"not convex, on its convex hull"``, ``"faces turned
        inwards, turned out"``; in decreasing count.
    left_out
        Leaves the statics still leave out, by the surface's reason (a mesh whose boundary is
        not loops of edges stays ``"not closed"``).
    too_small
        Blocks too small to judge (volume at most ``volume_floor``), by what became of them:
        ``"merged into its leaf's body"`` (a sliver of a leaf's cut, its weight a load on a
        part it touches), ``"carried as load by the block it touches"``, ``"left out,
        touching no block"``, ``"left out, not structural"``; in decreasing count.
    volume_floor
        The model's volume tolerance, m^3 (:attr:`~shapegen.tolerances.Tolerances.volume`:
        ``volume_rel`` times the cube of the model's size).
    judged_design
        Positions among the model's own blocks of those the statics judge (all of them but
        the blocks too small to judge), in order: they are the statics model's first blocks;
        None when every one is.
    """

    design_blocks: int
    blocks: int
    by_reason: dict = field(default_factory=dict)
    left_out: dict = field(default_factory=dict)
    too_small: dict = field(default_factory=dict)
    volume_floor: float = 0.0
    judged_design: tuple | None = None

    @property
    def leaves(self) -> int:
        """Number of leaves stood in for."""
        return int(sum(self.by_reason.values()))

    def to_report(self) -> dict:
        """Plain JSON values (see docs/formats.md, ``analysis.stand_ins``)."""
        return {
            "leaves": self.leaves,
            "blocks": int(self.blocks),
            "by_reason": dict(self.by_reason),
            "left_out": {"leaves": int(sum(self.left_out.values())), "by_reason": self.left_out},
            **({"too_small": self.too_small_report()} if self.too_small else {}),
        }

    def too_small_report(self) -> dict:
        """``{"blocks": n, "volume_floor_m3": v, "by_reason": {...}}``: the blocks too small
        to judge (see docs/formats.md, ``analysis.stand_ins.too_small``)."""
        return {
            "blocks": int(sum(self.too_small.values())),
            "volume_floor_m3": float(self.volume_floor),
            "by_reason": dict(self.too_small),
        }


@dataclass
class StaticsModel(Model):
    """A model with stand-in blocks appended after its own, for the statics alone
    (:func:`statics_model`); ``stand_ins`` says what they are."""

    stand_ins: StandIns | None = None


def design_blocks(model) -> int:
    """Number of blocks of the model as derived: all of them, but for a :class:`StaticsModel`,
    whose stand-ins follow its own blocks."""
    stand_ins = getattr(model, "stand_ins", None)
    return len(model.blocks) if stand_ins is None else stand_ins.design_blocks


def design_figures(values: np.ndarray, model) -> np.ndarray:
    """``values`` per block of the statics model ``model`` as figures per block of the model as
    derived: the stand-ins' dropped, 0 for a block too small to judge."""
    stand_ins = getattr(model, "stand_ins", None)
    if stand_ins is None:
        return values
    if stand_ins.judged_design is None:
        return values[: stand_ins.design_blocks]
    out = np.zeros(stand_ins.design_blocks, dtype=np.asarray(values).dtype)
    judged = np.asarray(stand_ins.judged_design, dtype=int)
    out[judged] = values[: len(judged)]
    return out


def statics_model(model: Model) -> Model:
    """The model the statics judge: ``model`` itself when no surface can stand in and no
    block is too small to judge, else a :class:`StaticsModel` with the model's blocks
    followed by the stand-ins (see the module docstring) and the surfaces still left out.
    In a model derived from a ``.cga`` rule, the blocks too small to judge are taken out and
    their weight carried (:func:`_without_too_small`); a ``.grammar`` design keeps them, and
    its validation refuses them. The same model gives the same object (the last few are
    kept), so an analysis, its contacts and its capacity agree on the blocks; a statics
    model is its own."""
    if isinstance(model, StaticsModel):
        return model
    surfaces = list(getattr(model, "surfaces", None) or [])
    standing_in = any(s.reason in _CANDIDATES for s in surfaces)
    cityengine = from_cityengine(model)
    if not standing_in and not cityengine:
        return model
    kept = _MODELS.get(id(model))
    if kept is not None and kept[0] is model:
        return kept[1]
    judged = _with_stand_ins(model, surfaces)
    if cityengine:
        judged = _without_too_small(judged)
    if not standing_in and not judged.stand_ins.too_small:
        judged = model  # nothing to stand in, nothing too small: the model as derived
    if len(_MODELS) >= _MODELS_LIMIT:
        del _MODELS[next(iter(_MODELS))]  # the oldest entry
    _MODELS[id(model)] = (model, judged)
    return judged


def _with_stand_ins(model: Model, surfaces: list) -> StaticsModel:
    properties = _Properties(model.blocks)
    taken = {b.id for b in model.blocks}
    blocks: list[Block] = []
    by_reason: Counter = Counter()
    left_out: Counter = Counter()
    remaining = []
    for number, surface in enumerate(surfaces):
        made = None
        if surface.reason in _CANDIDATES:
            made = _stand_in(surface)
        if made is None:
            left_out[surface.reason or "not a block"] += 1
            remaining.append(surface)
            continue
        what, pieces, density_scale = made
        solid = surface.solid
        if solid is not None:  # the leaf's own
            density, structural, fixed = solid.density, solid.structural, solid.fixed
        else:
            density, structural, fixed = properties.of(surface.rule_path)
        name = surface.id or f"s{number}"
        while name in taken or any(f"{name}.{k}" in taken for k in range(len(pieces))):
            name += "'"
        for k, (vertices, faces) in enumerate(pieces):
            block_id = name if len(pieces) == 1 else f"{name}.{k}"
            taken.add(block_id)
            blocks.append(
                Block(
                    vertices,
                    faces,
                    density=density * density_scale,
                    id=block_id,
                    tags=surface.tags,
                    structural=structural,
                    fixed=fixed,
                    rule_path=surface.rule_path,
                    extras={"stand_in": what, "surface": name},
                    body=name if len(pieces) > 1 else "",
                )
            )
        by_reason[what] += 1
    stand_ins = StandIns(
        design_blocks=len(model.blocks),
        blocks=len(blocks),
        by_reason=dict(by_reason.most_common()),
        left_out=dict(left_out.most_common()),
    )
    return StaticsModel(
        blocks=[*model.blocks, *blocks],
        loads=model.loads,
        gravity=model.gravity,
        ground=model.ground,
        friction=model.friction,
        metadata=model.metadata,
        surfaces=remaining,
        stand_ins=stand_ins,
    )


def from_cityengine(model) -> bool:
    """True for a model derived from a CityEngine rule (``.cga``, or a rule package): the
    derivation records its grammar's dialect in ``metadata["dialect"]``. Its ornaments are
    often fixed to surfaces the statics leave out (a triglyph's open mesh), so a body that
    touches no support rides as load on the body below rather than being an error, as it is
    in a ``.grammar`` design; and a block too small to judge is merged or carried as load
    (:func:`statics_model`) rather than refused, as it is in a ``.grammar`` design."""
    return (getattr(model, "metadata", None) or {}).get("dialect") == "cga"


def _without_too_small(judged: StaticsModel) -> StaticsModel:
    """``judged`` without its blocks too small to judge (volume within the model's volume
    tolerance of zero), each counted by what became of it (:attr:`StandIns.too_small`).

    A block that cannot be judged (its six equilibrium rows would rest on contacts of no
    area) is not the whole model's failure: a sliver of a leaf's cut gives its weight, as a
    point load at its centroid, to the part of its own leaf nearest it (merged into its
    body); any other block to the block it touches (the one its bounding box overlaps most,
    the nearest of those it touches); a block touching none is left out with its weight.
    Point loads turn with gravity on a tilted table, so the weight is carried as a
    block's own would be. The floor is the model's: ``volume_rel`` times the cube of its
    size (:attr:`~shapegen.tolerances.Tolerances.volume`)."""
    blocks = judged.blocks
    if not blocks:
        return judged
    compute_mass_properties(blocks)
    floor = judged.tolerances().volume
    volumes = np.array([b.volume for b in blocks])
    small = np.abs(volumes) <= floor
    if not small.any():
        return replace(judged, stand_ins=replace(judged.stand_ins, volume_floor=floor))
    low = np.array([b.vertices.min(axis=0) for b in blocks])
    high = np.array([b.vertices.max(axis=0) for b in blocks])
    reach = judged.tolerances().planar  # bounding boxes this close touch, m
    loads = list(judged.loads)
    outcome: Counter = Counter()
    gravity = np.asarray(judged.gravity, float)
    for k in np.flatnonzero(small).tolist():
        block = blocks[k]
        host = None
        if block.structural:
            host = _host(k, blocks, small, low, high, reach)
        if host is None:
            outcome[TOUCHING_NOTHING if block.structural else NOT_STRUCTURAL] += 1
        else:
            merged = bool(block.body) and blocks[host].body == block.body
            outcome[MERGED if merged else CARRIED] += 1
            if not block.fixed and block.mass > 0:
                loads.append(PointLoad(blocks[host].id, block.mass * gravity, block.centroid))
        # the loads on it go where its weight goes, or with it
        moved = []
        for load in loads:
            if load.block != block.id:
                moved.append(load)
            elif host is not None:
                moved.append(PointLoad(blocks[host].id, load.force, load.point))
        loads = moved
    stand_ins = judged.stand_ins
    design = stand_ins.design_blocks
    judged_design = tuple(k for k in range(design) if not small[k])
    kept = [b for b, tiny in zip(blocks, small.tolist(), strict=True) if not tiny]
    return replace(
        judged,
        blocks=kept,
        loads=loads,
        stand_ins=replace(
            stand_ins,
            blocks=stand_ins.blocks - int(small[design:].sum()),
            too_small=dict(outcome.most_common()),
            volume_floor=floor,
            judged_design=judged_design if len(judged_design) < design else None,
        ),
    )


def _host(k, blocks, small, low, high, reach) -> int | None:
    """The block that takes block ``k``'s weight: a part of its own leaf's body it touches,
    else a block it touches; of several, the one whose bounding box overlaps its own most,
    then the nearest. None when it touches none (bounding boxes ``reach`` m apart or more)."""
    gap = np.maximum(low - high[k], low[k] - high).max(axis=1)  # > 0: apart along some axis
    touching = (gap <= reach) & ~small
    if not touching.any():
        return None
    body = blocks[k].body
    if body:
        same = touching & np.array([b.body == body for b in blocks])
        if same.any():
            touching = same
    candidates = np.flatnonzero(touching)
    overlap = np.clip(
        np.minimum(high[candidates], high[k]) - np.maximum(low[candidates], low[k]), 0.0, None
    ).prod(axis=1)
    centre = 0.5 * (low[k] + high[k])
    distance = np.linalg.norm(0.5 * (low[candidates] + high[candidates]) - centre, axis=1)
    return int(candidates[np.lexsort((distance, -overlap))[0]])


class _Properties:
    """A stand-in's density, ``structural`` and ``fixed``: those of the model's blocks made by
    the same chain of rules, else the density most of its blocks have (2 400 kg/m^3 when it has
    none), structural and free."""

    def __init__(self, blocks: list[Block]):
        self.by_chain: dict[tuple, tuple[float, bool, bool]] = {}
        for block in blocks:
            if block.rule_path:
                self.by_chain.setdefault(
                    block.rule_path, (block.density, block.structural, block.fixed)
                )
        densities = Counter(b.density for b in blocks)
        density = densities.most_common(1)[0][0] if densities else DEFAULT_DENSITY
        self.default = (density, True, False)

    def of(self, rule_path: tuple) -> tuple[float, bool, bool]:
        return self.by_chain.get(tuple(rule_path), self.default) if rule_path else self.default


def _stand_in(surface) -> tuple[str, list, float] | None:
    """``(what was done, [(vertices, faces), ...] of the convex parts in world coordinates,
    density scale)`` for one surface, or None when it cannot stand in. Worked out once per
    shape up to a translation (a temple's columns are one asset placed many times)."""
    vertices = np.asarray(surface.vertices, dtype=float)
    if len(vertices) < 4:
        return None
    if surface.reason == _NOT_CONVEX:
        pieces = _solid_parts(surface)
        if pieces is not None:
            return CUT, pieces, 1.0
    anchor = vertices.min(axis=0)
    local = vertices - anchor
    key = (surface.reason, np.round(local / COINCIDENT_M).astype(np.int64).tobytes(),
           tuple(surface.faces))  # fmt: skip
    found = _SHAPES.get(key, _MISSING)
    if found is _MISSING:
        found = _local_stand_in(Mesh(local, surface.faces), surface.reason)
        if len(_SHAPES) >= _SHAPES_LIMIT:
            del _SHAPES[next(iter(_SHAPES))]  # the oldest entry
        _SHAPES[key] = found
    if found is None:
        return None
    what, pieces, scale = found
    return what, [(piece_vertices + anchor, faces) for piece_vertices, faces in pieces], scale


def _solid_parts(surface) -> list | None:
    """The convex parts of a closed solid leaf kept as derived (one with a
    :class:`~shapegen.model.appearance.SolidLeaf`), in world coordinates: cut in its scope
    where the derivation recorded it, else where it is; None when it does not cut (it then
    stands on its hull)."""
    solid = surface.solid
    if solid is None:  # a file's surface that was not cut when derived: it did not cut
        return None
    if solid.local is not None and _still_placed(surface.vertices, solid):
        local, rotation, origin = solid.local, solid.rotation, solid.origin
    else:  # read from a file, or moved since it was derived: cut where it is
        local = Mesh(surface.vertices, surface.faces)
        if not local.is_closed or local.signed_volume() <= MIN_LEAF_SIZE**3:
            return None
        rotation, origin = np.eye(3), np.zeros(3)
    pieces = placed_convex_decomposition(local, rotation, origin)
    if pieces is None:
        return None
    cleaned = [piece.cleaned() for piece in pieces]
    return [(piece.vertices, piece.faces) for piece in cleaned]


def _still_placed(vertices: np.ndarray, solid) -> bool:
    """Whether the leaf's vertices are still its scope's mesh placed by its scope (a model
    moved after its derivation, as a PyPRT initial shape's, has moved its vertices only)."""
    local = np.asarray(solid.local.vertices)
    if local.shape != vertices.shape:
        return False
    placed = local @ np.asarray(solid.rotation).T + solid.origin
    return bool(
        np.allclose(
            placed, vertices, rtol=0.0, atol=COINCIDENT_REL * (1.0 + np.abs(vertices).max())
        )
    )


def _local_stand_in(mesh: Mesh, reason: str) -> tuple[str, list, float] | None:
    if reason == _OPEN:
        mesh = capped(mesh)
        if mesh is None:
            return None
        what, whole = CAPPED, CAPPED_HULL
    elif reason == _INWARDS:
        mesh, what, whole = mesh.reversed(), TURNED, TURNED_HULL
    else:  # the derivation found no convex pieces: the hull at once
        what = whole = HULL
    if not mesh.is_closed:
        return None
    volume = mesh.signed_volume()
    if volume <= MIN_LEAF_SIZE**3:
        return None
    if reason != _NOT_CONVEX and mesh.n_faces <= _MAX_CUT_FACES:
        pieces = convex_decomposition(mesh, _MAX_PIECES)
        if pieces is not None:
            cleaned = [piece.cleaned() for piece in pieces]
            return what, [(p.vertices, p.faces) for p in cleaned], 1.0
    try:
        hull = Block.from_hull(hull_corners(mesh.vertices))
    except GeometryError:
        return None
    return whole, [(hull.vertices, hull.faces)], volume / hull.volume


_MAX_PIECES = 64  # convex parts of one stand-in, as the derivation's own decompositions
# a solid of more faces is not cut (a fluted shaft, a curved capital: the cuts would fail after
# many pieces, or give slivers) but stands on its hull
_MAX_CUT_FACES = 200
_SHAPES: dict = {}
_SHAPES_LIMIT = 512
_MODELS: dict = {}
_MODELS_LIMIT = 4
_MISSING = object()

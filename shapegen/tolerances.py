"""Every numerical tolerance of shapegen, in one place.

Geometric tolerances are relative to the model's size ``L`` (the diagonal of its bounding box, in
metres) so that a 10 cm model and a 100 m cathedral behave the same. ``Tolerances.for_size(L)``
turns the relative values into absolute ones.

The module-level constants below the class are the tolerances that do not scale with a model:
round-off slack of sums and ratios, and the force below which a statics result is noise.

A comparison with a tolerance is written with one of the predicates at the end, each naming the
tolerance it uses (in the unit of the values compared)::

    >>> is_zero(1e-16, ZERO_LENGTH) and is_positive(1e-3, ZERO_LENGTH)
    True
    >>> is_close(0.1 + 0.2, 0.3, ROUNDOFF_REL) and at_least(0.99999999999999, 1.0, ROUNDOFF_REL)
    True
    >>> are_zero(np.array([0.0, 1e-16, 1e-3]), ZERO_LENGTH).tolist()
    [True, True, False]
"""

from __future__ import annotations

__all__ = [
    "Tolerances",
    "DEFAULT",
    "ROUNDOFF_REL",
    "PERCENT_SLACK",
    "SPLIT_SLACK_REL",
    "REPEAT_SLACK",
    "FLAT_REL",
    "COPLANAR_REL",
    "MIN_LEAF_SIZE",
    "FORCE_NOISE_REL",
    "SIMULATION_FALL_REL",
    "SIMULATION_MOVING_REL",
    "SIMULATION_DECAY_RATIO",
    "COORDINATE_ROUNDOFF_REL",
    "TILT_RESOLUTION_DEG",
    "ZERO_LENGTH",
    "SIZE_FLOOR_M",
    "LOT_MERGE_M",
    "ASSET_EDGE_M",
    "TEXTURE_FACE_M",
    "COINCIDENT_REL",
    "COINCIDENT_M",
    "COSINE_SLACK",
    "COLLINEAR_REL",
    "EXTRUDE_JOIN_REL",
    "LEVEL_REL",
    "LEVEL_M",
    "TRIG_ROUNDOFF",
    "DIVISION_FLOOR",
    "RAY_PARALLEL_DET",
    "BATCH_DOUBT_REL",
    "GRID_SLACK",
    "TIE_REL",
    "HORIZON_SIN",
    "GROUND_FLOOR_M",
    "PIXEL_AREA_FLOOR",
    "PIXEL_EDGE_SLACK_REL",
    "is_zero",
    "is_close",
    "is_positive",
    "is_negative",
    "at_least",
    "at_most",
    "are_zero",
    "are_close",
    "are_positive",
]

from dataclasses import dataclass, replace

import numpy as np


@dataclass(frozen=True)
class Tolerances:
    """Relative and absolute tolerances.

    Attributes
    ----------
    planar_rel
        Two faces are coplanar when their plane offsets differ by at most ``planar_rel * L``
        (dimensionless).
    normal_cos
        Two faces are opposite-facing when the cosine between their outward normals is below
        ``-normal_cos`` (dimensionless, close to 1).
    area_rel
        A contact polygon smaller than ``area_rel * L**2`` is ignored (dimensionless).
    merge_rel
        Vertices closer than ``merge_rel * L`` are the same point (dimensionless).
    convex_rel
        A block is convex when no vertex lies outside any face plane by more than
        ``convex_rel * L`` (dimensionless). The convex cut of a non-convex leaf
        (:mod:`shapegen.geometry.cut`, :mod:`shapegen.geometry.prism_cut`) splits a piece
        until none of its corners lies farther than ``convex_rel`` times the piece's size
        outside a face plane, so the pieces it makes pass this check.
    volume_rel
        A block with volume below ``volume_rel * L**3`` (m^3, :attr:`volume`) is degenerate,
        too small to judge (dimensionless): a ``.grammar`` design refuses it, naming this
        tolerance and the block's rules; in a model derived from a ``.cga`` rule it is merged
        into its leaf's body or carried as load by the block it touches, counted
        (:func:`shapegen.statics.standins.statics_model`). The cut of a leaf into convex
        pieces drops the slivers it makes (thinner than ``convex_rel`` times the leaf's size).
    penetration_rel
        Two blocks interpenetrate when their intersection volume exceeds
        ``penetration_rel * min(volume_a, volume_b)`` (dimensionless).
    feasible_rel
        Statics: an assembly is certified feasible when a compression-only equilibrium exists
        with residual below ``feasible_rel * total_weight`` (dimensionless).
    screen_rel
        Statics: an infeasibility normalised by the squared total weight above ``screen_rel``
        is clearly infeasible and needs no certificate (dimensionless).
    size
        The model size ``L`` in metres that the absolute values below are computed for.
    """

    planar_rel: float = 1e-6
    normal_cos: float = 1.0 - 1e-6
    area_rel: float = 1e-10
    merge_rel: float = 1e-9
    convex_rel: float = 1e-7
    volume_rel: float = 1e-12
    penetration_rel: float = 1e-4
    feasible_rel: float = 1e-7
    screen_rel: float = 1e-4
    size: float = 1.0

    def for_size(self, size: float) -> Tolerances:
        """The same tolerances for a model of size ``size`` metres (bounding-box diagonal)."""
        return replace(self, size=max(float(size), 1e-9))

    @property
    def planar(self) -> float:
        """Coplanarity distance, metres."""
        return self.planar_rel * self.size

    @property
    def merge(self) -> float:
        """Vertex merge distance, metres."""
        return self.merge_rel * self.size

    @property
    def area(self) -> float:
        """Smallest contact area, square metres."""
        return self.area_rel * self.size**2

    @property
    def convex(self) -> float:
        """Convexity slack, metres."""
        return self.convex_rel * self.size

    @property
    def volume(self) -> float:
        """Smallest block volume, cubic metres."""
        return self.volume_rel * self.size**3


DEFAULT = Tolerances()


#: Floating-point round-off of a computed coordinate, relative to the length it was computed
#: from (dimensionless). Far below every tolerance above: a value that should lie on a bound
#: (a Bezier arch line on its springing line) may miss it by this much and still count as on it.
ROUNDOFF_REL = 1e-12

#: Stochastic rules and functions: branch percentages may add up to ``100 + PERCENT_SLACK``
#: (percent): ``32.2% + 45.1% + 22.7%`` sums to 100.00000000000001 in floating point.
PERCENT_SLACK = 1e-9

#: Splits: running sums of part sizes may miss the split's length by round-off; a cut closer to
#: a span's end than ``SPLIT_SLACK_REL`` times the split's length is at that end (dimensionless),
#: so that rounding neither leaves a sliver nor drops a last full part.
SPLIT_SLACK_REL = 1e-10

#: Splits: a repeated pattern of fixed sizes fits ``n`` whole times when ``length / period`` is
#: within ``REPEAT_SLACK`` below ``n`` (dimensionless, a fraction of one repetition).
REPEAT_SLACK = 1e-9

#: Mesh import: points are flat (no solid to take the hull of) when the smallest singular value
#: of the centred points is below ``FLAT_REL`` times the largest (dimensionless).
FLAT_REL = 1e-9

#: Convex hulls: a hull vertex lies on a facet's plane when within ``COPLANAR_REL`` times the
#: block's size (dimensionless); qhull's triangles of one face are merged on this test.
COPLANAR_REL = 1e-10

#: Derivation: a leaf shape thinner than ``MIN_LEAF_SIZE`` metres along any axis has no volume
#: and makes no block.
MIN_LEAF_SIZE = 1e-9

#: Statics output: a force or tension below ``FORCE_NOISE_REL`` times its scale (the total weight,
#: or the largest force drawn) is solver round-off, not a force (dimensionless).
FORCE_NOISE_REL = 1e-6

#: Simulation verdict: a block *fell* when one of its vertices ended farther from where it
#: started than ``SIMULATION_FALL_REL`` times the block's smallest width (dimensionless). Measured
#: over 5 s (docs/simulation.md, "Verdict"): no block of a standing model of the agreement study
#: moved more than 1.6 % of its width (2.8 % in the bundled buildings), and the most-moved block of
#: every collapse at least 925 % (one slow slide, 8 %, is caught as still moving).
SIMULATION_FALL_REL = 0.1

#: Simulation verdict: a block is *still moving* when, over the last quarter of the judged window,
#: one of its vertices moved more than ``SIMULATION_MOVING_REL`` times the block's smallest width
#: (dimensionless) and that motion is not dying out (see ``SIMULATION_DECAY_RATIO``). Standing
#: models of the agreement study moved at most 0.32 % of a block's width over that quarter.
SIMULATION_MOVING_REL = 0.01

#: Simulation verdict: motion is dying out when a block moved less than ``SIMULATION_DECAY_RATIO``
#: times as far over the last quarter of the judged window as over the quarter before it
#: (dimensionless): settling decays, a fall speeds up.
SIMULATION_DECAY_RATIO = 0.5

#: Blocks: a vertex stored as a float64 coordinate is off its exact place by up to half an ulp of
#: the coordinate, so a face plane far from the origin (x = 1e10 m) cannot be checked closer
#: than a few ulps of the coordinates' magnitude. The convexity test allows
#: ``COORDINATE_ROUNDOFF_REL`` times the block's largest |coordinate| on top of ``convex``
#: (dimensionless, about 45 float64 epsilons).
COORDINATE_ROUNDOFF_REL = 1e-14

#: Lateral capacity: the critical tilt is reported to ``TILT_RESOLUTION_DEG`` degrees. The
#: load-multiplier program finds it far closer; the statics verdict confirms that the assembly
#: stands half this below the figure and does not stand half this above it
#: (:mod:`shapegen.statics.capacity`).
TILT_RESOLUTION_DEG = 0.05

#: Geometry: a vector shorter than ``ZERO_LENGTH`` (metres for an edge, dimensionless for a
#: normal) has no direction; no frame is built on it.
ZERO_LENGTH = 1e-15

#: Geometry: a relative tolerance is scaled by a size of at least ``SIZE_FLOOR_M`` metres, so a
#: mesh shrunk to a point still gets a positive slack.
SIZE_FLOOR_M = 1e-12

#: Lots: consecutive corners of a polygon lot closer than ``LOT_MERGE_M`` metres are one corner
#: (a repeated closing corner, a survey's doubled point, a ring projected from degrees), on
#: every front end alike (:class:`shapegen.model.lot.Lot`).
LOT_MERGE_M = 1e-3

#: Assets: an edge of an asset's mesh no longer than ``ASSET_EDGE_M`` (the file's units, metres
#: for CityEngine) has no length, and a face no thicker than it (twice its area over its longest
#: edge) has no area: both are removed when the asset is read, as CityEngine's runtime does
#: (:mod:`shapegen.geometry.asset_cleanup`). Measured with PyPRT 1.12 on the corpus assets: an
#: edge of 0.00066 is removed (candler's ledgeLarge.obj), one of 0.00102 is kept (ledgeSmall.obj).
ASSET_EDGE_M = 1e-3

#: Trim planes: a corner of an insert within ``TRIM_PLANE_M`` (m) of a trim plane is on it, kept
#: where it is, and no edge is cut there, as CityEngine's runtime cuts. Measured with PyPRT 1.12
#: on the parthenon: its corner capitals, set 1 mm off their face's end, are cut by the corner's
#: plane from one corner of the abacus to the opposite one, both 0.71 mm off the plane, with no
#: sliver beside them; its raking geisons keep corners 0.24 and 0.47 mm beyond the ridge's
#: plane. The value is CityEngine's length of an asset's edge that has no length (above).
TRIM_PLANE_M = 1e-3

#: Texture coordinates: a derived face whose corners lie within ``TEXTURE_FACE_M`` metres of an
#: initial shape's face (its plane, and inside its outline) lies on it and takes its texture
#: coordinates (:mod:`shapegen.geometry.texture_transfer`); a tenth of a millimetre, ten times
#: the derivation's own drift on a 100 m model and far below a face a modeller draws.
TEXTURE_FACE_M = 1e-4

#: Geometry: points, lines and planes closer than ``COINCIDENT_REL`` times the size of the shape
#: they belong to (its largest extent, metres) coincide (dimensionless): a corner on a cutting
#: plane, a vertex on a face, a face's plane among a hull's, a solid on its placed scope.
COINCIDENT_REL = 1e-9

#: Geometry: a length below ``COINCIDENT_M`` metres in a derived shape (an edge, an offset, a
#: tile's extent) is nought, and a shape's size is taken as at least this much when a relative
#: tolerance is scaled by it; a shape's coordinates are keyed to it when shapes are compared.
COINCIDENT_M = 1e-9

#: Geometry: the cosine (or sine) of the angle between two unit vectors is compared with
#: ``COSINE_SLACK`` of slack (dimensionless): two directions within it of opposite are opposite,
#: a face within it of edge-on is edge-on.
COSINE_SLACK = 1e-9

#: Component tags: a face or edge of an operation's result carries the tags of one before it
#: when it lies within ``TAG_MATCH_REL`` times the shape's size (its largest extent, metres) of
#: it (dimensionless), and a face faces the same way when the cosine between their normals is
#: within ``TAG_MATCH_REL`` of one. Coarser than ``COINCIDENT_REL``: a remade face (a split
#: cap's neighbour, a setback's strip) is recomputed, not copied, and drifts by round-off.
TAG_MATCH_REL = 1e-6

#: Extrusion: faces extruded together (op_extrude: "no internal lamina faces") share a corner
#: within ``EXTRUDE_JOIN_REL`` times the faces' size (their largest extent, metres), and lie in
#: one plane facing one way within it (dimensionless). Coarser than ``COINCIDENT_REL``: an
#: offset's or a setback's faces meet at corners computed once per face.
EXTRUDE_JOIN_REL = 1e-6

#: Convex hulls: three vertices are collinear when the cross product of their edges is below
#: ``COLLINEAR_REL`` times the squared size of the block (dimensionless).
COLLINEAR_REL = 1e-8

#: Roofs: an edge whose ends differ in height by less than ``LEVEL_REL`` times the mesh's size is
#: level (dimensionless); a probe stepped off an edge is in front of a face beyond this share of
#: the step.
LEVEL_REL = 1e-6

#: PyPRT initial shapes: the corners of a starting face lie at one height when within
#: ``LEVEL_M`` metres of each other.
LEVEL_M = 1e-6

#: Trigonometry: a sine or cosine of an exact angle below ``TRIG_ROUNDOFF`` is zero
#: (``cos(pi/2)`` is 6e-17 in float64), dimensionless.
TRIG_ROUNDOFF = 1e-15

#: Arithmetic: a non-negative quantity that divides, or whose logarithm is taken, is taken as at
#: least ``DIVISION_FLOOR`` (in its own unit): far below any real one, it only keeps a degenerate
#: zero (a shape of no extent) from dividing by zero.
DIVISION_FLOOR = 1e-300

#: Ray casting (CGA's scatter on a mesh): a ray is parallel to a triangle when the determinant
#: of the Moller-Trumbore system is below ``RAY_PARALLEL_DET`` (square metres).
RAY_PARALLEL_DET = 1e-14

#: Batch derivation: a footprint corner turning by a sine below ``BATCH_DOUBT_REL``, an edge
#: shorter than it times the footprint's span, an extrusion lower than it times that span, a
#: footprint of less area than it times that span squared, is in doubt, and its lot is derived
#: one shape at a time (dimensionless).
BATCH_DOUBT_REL = 1e-6

#: A value lies on a ``@Range`` stepsize's grid ``low + k * step`` when within ``GRID_SLACK``
#: of a step of it (dimensionless, a fraction of one step).
GRID_SLACK = 1e-6

#: Lateral capacity: directions whose figures differ by at most ``TIE_REL`` are tied and the
#: least azimuth is reported (degrees for a tilt; times ``max(1, |multiplier|)`` for a load
#: multiplier).
TIE_REL = 1e-9

#: Pictures: the ground is drawn when the eye is above the horizon by a sine of more than
#: ``HORIZON_SIN`` (dimensionless).
HORIZON_SIN = 1e-6

#: Pictures: the ground patch is sized from a footprint of at least ``GROUND_FLOOR_M`` metres.
GROUND_FLOOR_M = 1e-6

#: Pictures: a projected triangle of area ``PIXEL_AREA_FLOOR`` square pixels or less covers no
#: sample.
PIXEL_AREA_FLOOR = 1e-12

#: Pictures: a sample on a triangle's edge is inside it within ``PIXEL_EDGE_SLACK_REL`` times the
#: size of the edge functions (dimensionless), so an edge two triangles share covers it once.
PIXEL_EDGE_SLACK_REL = 1e-7


# Predicates. Each takes the tolerance by name (one of the constants above, or one scaled to a
# size), in the unit of the values it compares; the comparisons are inclusive of the tolerance
# (``is_zero``, ``is_close``, ``at_least``, ``at_most``) or strictly beyond it (``is_positive``,
# ``is_negative``), so that ``is_positive(x, tol)`` is exactly ``not at_most(x, 0, tol)``.


def is_zero(value: float, tol: float) -> bool:
    """``|value| <= tol``: zero within ``tol`` (``tol`` in the unit of ``value``)."""
    return abs(value) <= tol


def is_close(a: float, b: float, tol: float) -> bool:
    """``|a - b| <= tol``: equal within ``tol`` (``tol`` in the unit of ``a`` and ``b``)."""
    return abs(a - b) <= tol


def is_positive(value: float, tol: float) -> bool:
    """``value > tol``: positive beyond ``tol`` (``tol`` in the unit of ``value``)."""
    return value > tol


def is_negative(value: float, tol: float) -> bool:
    """``value < -tol``: negative beyond ``tol`` (``tol`` in the unit of ``value``)."""
    return value < -tol


def at_least(value: float, bound: float, tol: float) -> bool:
    """``value >= bound - tol``: not below ``bound`` by more than ``tol``."""
    return value >= bound - tol


def at_most(value: float, bound: float, tol: float) -> bool:
    """``value <= bound + tol``: not above ``bound`` by more than ``tol``."""
    return value <= bound + tol


def are_zero(values: np.ndarray, tol: float | np.ndarray) -> np.ndarray:
    """``is_zero`` for every element of ``values`` (a boolean array of the same shape)."""
    return np.abs(values) <= tol


def are_close(a: np.ndarray, b: np.ndarray, tol: float | np.ndarray) -> np.ndarray:
    """``is_close`` element by element (a boolean array of the broadcast shape)."""
    return np.abs(np.subtract(a, b)) <= tol


def are_positive(values: np.ndarray, tol: float | np.ndarray) -> np.ndarray:
    """``is_positive`` for every element of ``values`` (a boolean array of the same shape)."""
    return np.asarray(values) > tol

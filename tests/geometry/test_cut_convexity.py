"""The convex pieces the cut makes of a non-convex leaf pass the blocks' convexity check.

The cut (cut.py, prism_cut.py) splits a piece until none of its corners lies farther outside a
face plane than the blocks' convexity tolerance (``Tolerances.convex_rel``); the check
(``Block.validate``, ``validate_blocks``) allows that tolerance of the whole model. When the cut
allowed ten times more, a footprint with corners nearly in line (surveyed points on a straight
wall) made pieces 3e-6 to 3e-5 m out of convex, and the lot failed to be judged on its own cut.
Footprints are extruded and judged as a city lot is (``pipeline.design``): the leaf is kept
as derived and the statics cut it (``statics_model``) and check the pieces (``validate``).
"""

from __future__ import annotations

import json
import sys
from pathlib import Path

import numpy as np
import pytest
import shapely
from polygon_cases import footprint

from shapegen.engine.grammar_api import parse_grammar
from shapegen.geometry.cut import convex_decomposition
from shapegen.geometry.mesh import Mesh
from shapegen.model.block import Block
from shapegen.pipeline import design
from shapegen.statics.standins import CUT, HULL, statics_model
from shapegen.tolerances import DEFAULT

# Lots that failed "block 'b0': not convex (a vertex lies 7.9e-06 m outside a face plane)" and
# the like, and a notch whose first cut leaves a sliver (cut_footprints.json): (x, z) corners,
# m, counter-clockwise seen from above
_FOOTPRINTS = json.loads((Path(__file__).parent / "cut_footprints.json").read_text())
FAILED = _FOOTPRINTS["failed"]["lots"]
NOTCH = _FOOTPRINTS["notch"]["corners"]


def _grammar():
    return parse_grammar("Lot --> extrude(10)\n", "lot.cga")


def _lots(seed: int, count: int) -> list[list[tuple[float, float]]]:
    """``count`` simple non-convex footprints drawn from ``seed``, as (x, z) lots."""
    rng = np.random.default_rng(seed)
    lots = []
    while len(lots) < count:
        ring = footprint(rng)
        polygon = shapely.Polygon(ring)
        if not polygon.exterior.is_simple or polygon.convex_hull.area - polygon.area < 1e-3:
            continue  # crossing itself, or convex: nothing to cut
        if not polygon.exterior.is_ccw:
            ring = ring[::-1]
        lots.append([(float(x), -float(y)) for x, y in ring])  # north is -z
    return lots


def _failures(lots, *, judge: bool, hulls: list | None = None) -> list[str]:
    """Why each lot failed on its own geometry (an error, or no verdict); the lots whose
    footprint the cut gave up on, judged on its convex hull, are added to ``hulls``."""
    grammar = _grammar()
    failures = []
    for k, lot in enumerate(lots):
        try:
            if judge:
                outcome = design(grammar, lot=lot, assess=True)
                if outcome.assessment is None or not outcome.assessment.judged:
                    failures.append(f"lot {k}: no verdict: {lot!r}")
                stood_in = outcome.report["analysis"].get("stand_ins") or {}
                if HULL in stood_in.get("by_reason", {}) and hulls is not None:
                    hulls.append(k)
            else:  # the statics' cut and the first thing they check
                statics_model(grammar.build(lot=lot)).validate()
        except Exception as exc:  # noqa: BLE001 - every failure is listed
            failures.append(f"lot {k}: {type(exc).__name__}: {exc}: {lot!r}")
    return failures


@pytest.mark.parametrize("index", range(len(FAILED)))
def test_a_lot_with_corners_nearly_in_line_is_judged_on_its_own_cut(index):
    outcome = design(_grammar(), lot=FAILED[index], assess=True)
    stood_in = outcome.report["analysis"]["stand_ins"]
    assert stood_in["by_reason"] == {CUT: 1} and stood_in["blocks"] > 1  # cut into pieces
    assert not outcome.report["left_out"]["leaves"]
    assert outcome.assessment is not None and outcome.assessment.judged


def test_a_cut_that_leaves_a_sliver_gives_way_to_the_next_plane():
    outcome = design(_grammar(), lot=NOTCH, assess=True)
    assert outcome.report["analysis"]["stand_ins"]["by_reason"] == {CUT: 1}  # not its hull
    statics_model(_grammar().build(lot=NOTCH)).validate()


def test_the_pieces_of_random_footprints_pass_the_blocks_check():
    failures = _failures(_lots(7, 300), judge=False)
    assert failures == []


@pytest.mark.slow
def test_no_judged_lot_of_10000_footprints_fails_on_its_own_cut():
    seed = 20261128
    print(f"footprints from seed {seed}", file=sys.stderr)
    hulls: list[int] = []
    failures = _failures(_lots(seed, 10_000), judge=True, hulls=hulls)
    print(f"{len(hulls)} footprints the cut gave up on, judged on their hulls", file=sys.stderr)
    shown = "\n".join(failures[:10])
    assert not failures, f"{len(failures)} of 10 000 lots failed:\n{shown}"


def _door_window() -> Mesh:
    """The parthenon's door window (leaf s670 of parthenon.cga on a 30 x 70 m lot), in its
    scope: a frame whose diamond opening bends by a few 1e-6 of its size at each side's
    middle, with two crossing bars through it."""
    data = json.loads((Path(__file__).parent / "door_window.json").read_text())
    return Mesh(np.array(data["vertices"], float), tuple(tuple(f) for f in data["faces"]))


def test_a_cut_between_corners_nearly_in_line_leaves_no_sliver():
    # the cut along one of two sides nearly in line left a wedge 1.1e-8 m^3 between its
    # plane and the other side: above the leaf's own volume floor, below the 82 m temple's
    # (5.6e-7 m^3), and the analysis stopped at "block 's670.1': zero or negative volume"
    mesh = _door_window()
    pieces = convex_decomposition(mesh)
    assert pieces is not None and len(pieces) > 1  # cut into parts, not on its hull
    thickness = min(piece.signed_volume() / piece.size() ** 2 for piece in pieces)
    assert thickness > DEFAULT.convex_rel * mesh.size()
    temple = DEFAULT.for_size(82.35)  # the parthenon's size on 30 x 70 m
    for piece in pieces:
        Block(piece.vertices, piece.faces).validate(temple)
    # the slivers left out weigh nothing the model can tell
    kept = sum(piece.signed_volume() for piece in pieces)
    assert kept == pytest.approx(mesh.signed_volume(), rel=1e-6)

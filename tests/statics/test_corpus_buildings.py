"""Real CityEngine buildings of the rule corpus (tests/data/cga-corpus) judged as stone: a
verdict and a lateral capacity, or, for a rule that models no solids, nothing to judge.

The figures are closed forms where the building is one block or a few: a mass of the lot's
10 x 10 m extruded 16.85 m tips at atan(10 / 16.85) = 30.68 deg with the exact friction cone
(the default: it would slide at atan(mu) = 34.99 deg), and slides before it tips with the
four-sided pyramid, at atan(mu cos 45 deg) = 26.33 deg across one of its sides; candler's
walls are faces, so what stands on the ground is its two door frames, 0.15 m deep and 4.3 m
tall, which tip at atan(0.15 / 4.3).
"""

from __future__ import annotations

import functools
import importlib.util
import math
import sys
from pathlib import Path

import numpy as np
import pytest

from shapegen.limits import work_limits
from shapegen.pipeline import design, load
from shapegen.statics import StaticsOptions

CORPUS = Path(__file__).resolve().parents[1] / "data" / "cga-corpus"
FRICTION = 0.7  # the model's default
RESOLUTION = 0.05  # degrees: the capacity's


def judged(package: str, rule: str, lot=(10.0, 10.0), pyramid: str | None = None):
    grammar = load(str(CORPUS / package / "rules" / rule))
    statics = StaticsOptions(pyramid=pyramid) if pyramid else None
    # a result, not a time: the parthenon's 12 CPU s ran past the default 60 s clock at load 12
    with work_limits(max_seconds=900):
        return design(grammar, lot=lot, assess=True, capacity=[], statics=statics)


@pytest.mark.parametrize(
    ("package", "rule"),
    [
        ("caseStudy_simple_rule2019__3f9666e3", "simple_rule2019.cga"),
        ("examples_data_extrusion_rule__1c38c522", "extrusion_rule.cga"),
    ],
)
@pytest.mark.parametrize("pyramid", ["cone", "4"])
def test_an_extruded_mass_tips_or_slides_at_its_closed_form(package, rule, pyramid):
    outcome = judged(package, rule, pyramid=pyramid)
    analysis = outcome.report["analysis"]
    assert outcome.report["blocks"] == 1 and analysis["stands"]
    (block,) = outcome.model.blocks
    width, height = np.ptp(block.vertices[:, 0]), np.ptp(block.vertices[:, 1])
    tipping = math.degrees(math.atan(width / height))
    # the cone holds mu c in every direction; the pyramid's side mu cos(45 deg) c across a side
    capacity = {"cone": FRICTION, "4": FRICTION * math.cos(math.pi / 4)}[pyramid]
    sliding = math.degrees(math.atan(capacity))
    assert (sliding < tipping) == (pyramid == "4")  # the pyramid slides first, the cone tips
    assert analysis["capacity"]["tilt_deg"] == pytest.approx(min(sliding, tipping), abs=RESOLUTION)


def test_a_rule_of_faces_has_nothing_to_judge():
    outcome = judged(
        "data_Building_From_FootprintSMALL__fc6ce924", "Building_From_FootprintSMALL.cga"
    )
    report = outcome.report
    assert report["blocks"] == 0
    assert report["left_out"]["by_reason"] == {"a face (no volume)": report["left_out"]["leaves"]}
    assert report["analysis"]["free_bodies"] == 0


@pytest.mark.slow
def test_candlers_walls_are_faces_and_its_door_frames_tip_at_their_slenderness():
    outcome = judged("examples_data_candler__f6a47f94", "candler.cga")
    analysis = outcome.report["analysis"]
    assert outcome.report["left_out"]["by_reason"]["a face (no volume)"] > 800  # the walls
    assert analysis["stands"] and analysis["free_bodies"] == 2
    detail = outcome.assessment.detail
    frames = [outcome.model.blocks[k] for k in np.flatnonzero(detail.bodies.body >= 0)]
    assert {b.rule_path[-1] for b in frames} == {"Frame"}
    depth = min(np.ptp(frames[0].vertices[:, 0]), np.ptp(frames[0].vertices[:, 2]))
    height = np.ptp(frames[0].vertices[:, 1])
    tipping = math.degrees(math.atan(depth / height))
    assert analysis["capacity"]["tilt_deg"] == pytest.approx(tipping, abs=RESOLUTION)


@pytest.mark.slow
def test_envelope_is_faces_and_a_block_touching_nothing():
    outcome = judged("tests_data_envelope2002__3bb69433", "typology/envelope2002.cga")
    analysis = outcome.report["analysis"]
    assert analysis["free_bodies"] == 0
    # its few solid tiles of interior wall (1, then 2 since its facades are cut as PyPRT cuts
    # them) touch nothing that holds them: each rides as load, none is a free body
    assert analysis["bodies"]["unsupported_riding"] == outcome.report["blocks"] >= 1


@pytest.mark.slow
def test_the_parthenon_stands_on_its_stand_ins_with_a_lateral_capacity():
    outcome = judged("caseStudy_NumPy_parthenon__2b00aac9", "parthenon.cga", lot=(12.0, 8.0))
    report = outcome.report
    analysis = report["analysis"]
    stand_ins = analysis["stand_ins"]
    # the model is CityEngine's: the shafts and echini stay open shells in it (some cut open at
    # trim planes, which carry their solid and are not left out)
    open_shells = sum(1 for s in outcome.model.surfaces if s.reason == "not closed")
    assert open_shells >= stand_ins["by_reason"]["open shell, capped, on its convex hull"]
    assert stand_ins["leaves"] > 0 and analysis["stands"]
    # measured when the stand-ins came in: 9.80 deg with the 4-sided pyramid, the default then;
    # with the exact cone, the default now, 10.08 deg (a joint that slid at the pyramid's
    # mu / sqrt 2 holds more: a capacity limited by sliding can only rise). The worst of 16
    # directions; the derivation may move it a little, not a degree
    capacity = analysis["capacity"]
    assert capacity["tilt_deg"] == pytest.approx(10.08, abs=0.25)


@pytest.mark.slow
def test_the_parthenon_on_30_by_70_stands_with_its_documented_capacity():
    # README and docs/statics.md: 9.60 deg across the temple (towards 0 deg, along the lot's
    # 30 m first edge) and 10.36 deg along it, with the exact cone. After 6f5ed9e the cut of
    # its door windows left slivers below the model's volume floor and the analysis stopped
    # at "block 's670.1': zero or negative volume"
    grammar = load(str(CORPUS / "caseStudy_NumPy_parthenon__2b00aac9" / "rules" / "parthenon.cga"))
    with work_limits(max_seconds=1800):  # 61 s of CPU, 155 s on a loaded 2-core machine
        outcome = design(grammar, lot=(30.0, 70.0), assess=True, capacity=[0.0, 90.0])
    analysis = outcome.report["analysis"]
    assert analysis["stands"]
    assert not analysis["stand_ins"].get("too_small")  # the cut leaves no sliver to count
    across, along = analysis["capacity"]["directions"]
    assert across["azimuth_deg"] == 0.0 and along["azimuth_deg"] == 90.0
    assert across["tilt_deg"] == pytest.approx(9.60, abs=2 * RESOLUTION)
    assert along["tilt_deg"] == pytest.approx(10.36, abs=2 * RESOLUTION)


@functools.cache
def _cga_compare():
    """tools/cga_compare.py, which knows each package's main rule (as tests/cga loads it)."""
    if "cga_compare" not in sys.modules:
        tool = Path(__file__).resolve().parents[2] / "tools" / "cga_compare.py"
        spec = importlib.util.spec_from_file_location("cga_compare", tool)
        sys.modules["cga_compare"] = importlib.util.module_from_spec(spec)
        spec.loader.exec_module(sys.modules["cga_compare"])
    return sys.modules["cga_compare"]


def _main_rule(package: Path) -> Path:
    """The rule file PyPRT runs for a corpus package."""
    rules = sorted((package / "rules").rglob("*.cga"))
    return next(p for p in rules if _cga_compare().is_main_rule(p))


PACKAGES = sorted(p.name for p in CORPUS.iterdir() if p.is_dir())
# the lots the docs and tests name: the rules' default lot (10 x 10 m, docs/statics.md's table),
# the 12 x 8 m lot of the references (tests/cga/test_corpus.py), and the parthenon's 30 x 70 m
LOTS = {"caseStudy_NumPy_parthenon__2b00aac9": [None, (12.0, 8.0), (30.0, 70.0)]}


def _lot_name(lot) -> str:
    width, depth = lot
    return f"{width:g}x{depth:g}"


@pytest.mark.slow
@pytest.mark.parametrize(
    ("package", "lot"),
    [
        pytest.param(p, lot, id=f"{p}-{'default lot' if lot is None else _lot_name(lot)}")
        for p in PACKAGES
        for lot in LOTS.get(p, [None, (12.0, 8.0)])
    ],
)
def test_every_corpus_package_is_judged_to_a_verdict(package, lot):
    outcome = design(load(str(_main_rule(CORPUS / package))), lot=lot, assess=True)
    analysis = outcome.report["analysis"]
    assert outcome.assessment is not None and outcome.assessment.judged
    # a verdict: stands, or not, or nothing to judge (a rule of faces: no free body)
    assert analysis["stands"] in (True, False) and analysis["free_bodies"] >= 0

"""The rule and initial shapes the shapegen.prt tests share: Esri/pyprt's extrusion rule (as
CityEngine's runtime derives it in the reference files under tests/data) on a 10 x 10 m square
and an 8 x 8 m one beside it."""

from pathlib import Path

DATA = Path(__file__).resolve().parents[1] / "data"
CORPUS = DATA / "cga-corpus"
EXTRUSION = CORPUS / "tests_data_extrusion_rule__e4df6667" / "rules" / "extrusion_rule.cga"
SQUARE = [0, 0, 0, 0, 0, 10, 10, 0, 10, 10, 0, 0]  # counter-clockwise seen from above (+y)
SMALL = [30, 0, 0, 30, 0, 8, 38, 0, 8, 38, 0, 0]
FIXED = {"minBuildingHeight": 23.0, "maxBuildingHeight": 23.0}  # the rule's random height pinned

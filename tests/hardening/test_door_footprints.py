"""Generated non-convex footprints that still fail on their own cut: the slow generators of
footprints other than the lot files' own (thin slivers, corners nearly in line, scales from
1e-2 to 1e2, combs, far from the origin) found these; each is judged as a city lot is."""

from __future__ import annotations

import pytest

from shapegen.engine.grammar_api import parse_grammar
from shapegen.pipeline import design

# a footprint scaled by about 3 (scaled generator, seed 4242): the cut leaves a piece of
# 1.3e-5 m^3 (a sliver 1.3e-6 m^2 across, 10 m high), below the blocks' volume tolerance
SCALED = [
    (147.90298175132705, -26.40641660202041),
    (142.69146630483743, -27.825761125706986),
    (91.84205557487635, -46.66375291239001),
    (45.358430415736116, -67.56610795584287),
    (-1.1252252229285222, -88.46845844318084),
    (-47.608855145779955, -109.37080542477858),
    (-48.817247140335525, -110.5667211084205),
    (-50.02565989072835, -111.7626506777022),
    (-51.234065371125354, -112.95857525427894),
    (-61.971119999850366, -84.18724518621096),
    (-72.70817284555817, -55.41590820743606),
    (-83.4452286314289, -26.64456766693436),
    (-79.4138220490449, -0.57291130406038),
    (-75.38240584141425, 25.4987546842811),
    (-71.35099856356496, 51.570415213569134),
    (-46.752114633983595, 66.28011105661636),
    (-22.153204029694265, 80.9898136430362),
    (2.4456980849407493, 95.69951903881866),
    (14.418313745883413, 77.40002325069585),
    (26.390895167442608, 59.10051886518874),
    (36.5040952562424, 89.25119362843803),
    (46.617322867764884, 119.40185928341506),
    (49.611453134499456, 93.5705497821596),
    (52.60562535194411, 67.73921779129938),
    (55.59978170994257, 41.90790563144509),
]

# one of 10 000 footprints of the lot files' own generator (polygon_cases.footprint, seed
# 31337), 1.6 km from the origin: a piece of its cut lies 3.2e-6 m out of convex
NEAR_IN_LINE = [
    (1616.3701494655274, 1540.2178646309665),
    (1609.2074576033144, 1532.4449195703255),
    (1595.79805944167, 1532.096933368806),
    (1598.3789535505512, 1537.400537857736),
    (1600.959843014011, 1542.7041426533222),
    (1603.540737781452, 1548.0077462653092),
    (1608.5133792799486, 1548.9079957725437),
    (1613.4860197788705, 1549.8082420923497),
    (1618.4586589595062, 1550.7084882887168),
    (1618.1635685858532, 1549.1010087537911),
    (1617.8684784445065, 1547.4935306547898),
    (1617.5733888457062, 1545.8860464414213),
]


@pytest.mark.xfail(
    strict=True, reason="the cut keeps a sliver below the blocks' volume tolerance (open)"
)
def test_a_scaled_footprint_is_judged_on_its_own_cut():
    outcome = design(parse_grammar("Lot --> extrude(10)\n", "lot.cga"), lot=SCALED, assess=True)
    assert outcome.assessment is not None and outcome.assessment.judged


@pytest.mark.xfail(
    strict=True, reason="a piece of the cut is 3.2e-6 m out of convex past the check (open)"
)
def test_a_footprint_of_the_lot_generator_is_judged_on_its_own_cut():
    grammar = parse_grammar("Lot --> extrude(10)\n", "lot.cga")
    outcome = design(grammar, lot=NEAR_IN_LINE, assess=True)
    assert outcome.assessment is not None and outcome.assessment.judged

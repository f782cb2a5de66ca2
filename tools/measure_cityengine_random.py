"""Measure CityEngine's random numbers with PyPRT 1.12 into tests/data/cityengine_random.json.

A development tool, run with the python of an environment with PyPRT (never a dependency)::

    python3 -m venv /tmp/prt && /tmp/prt/bin/pip install pyprt
    /tmp/prt/bin/python tools/measure_cityengine_random.py [PACKAGES_FOLDER]
"""

import json
import sys
from pathlib import Path

import pyprt

# the corpus's packages: ../shared/cga-corpus/packages of the checkout, or the folder named
P = (
    sys.argv[1]
    if len(sys.argv) > 1
    else str(Path(__file__).resolve().parents[2] / "shared" / "cga-corpus" / "packages")
) + "/"
EXT = P + "Esri+pyprt__tests_data_extrusion_rule__3d9b5297.rpk"
BFF = P + "Esri+pyprt__data_Building_From_FootprintSMALL__fc6ce924.rpk"
ENV = P + "Esri+pyprt__tests_data_envelope2002__3bb69433.rpk"
LOT = [0.0, 0.0, 8.0, 12.0, 0.0, 8.0, 12.0, 0.0, 0.0, 0.0, 0.0, 0.0]
TRAPEZOID = [0.0, 0.0, 20.0, 32.0, 0.0, 20.0, 30.0, 0.0, 0.0, 0.0, 0.0, 0.0]
L_LOT = [0, 0, 0, 0, 0, 12, 6, 0, 12, 6, 0, 5, 14, 0, 5, 14, 0, 0]  # tools/prt_geometry.py's L


def generate(package, lot, attrs_list, report=True, geometry=False):
    g = pyprt.ModelGenerator([pyprt.InitialShape(lot) for _ in attrs_list])
    return g.generate_model(
        attrs_list,
        package,
        "com.esri.pyprt.PyEncoder",
        {"emitReport": report, "emitGeometry": geometry},
    )


out = {
    "measured_with": "PyPRT 1.12.0.12 (pip install pyprt), the rule packages of "
    "../shared/cga-corpus/packages (Esri/pyprt test data), PyEncoder; lots as PyPRT's flat "
    "[x, y, z] lists",
    "lots": {"12x8": LOT, "trapezoid": TRAPEZOID, "L": L_LOT},
}
seeds = [0, 1, 666, -1, 12345, 2147483647, -2147483648]
models = generate(EXT, LOT, [{"seed": s} for s in seeds])
out["extrusion_rule"] = {
    "package": "tests_data_extrusion_rule__3d9b5297",
    "lot": "12x8",
    "what": "report 'Building Height.0' = geometry.volume() / parcelArea of extrude(rand(10, "
    "30)): the first draw of BuildingCreation, the start shape's first successor (to round-off "
    "of the volume)",
    "values": {
        str(s): m.get_report()["Building Height.0_sum"] for s, m in zip(seeds, models, strict=True)
    },
}
seeds = [0, 1, 2, -1, 12345, 2147483647]
models = generate(BFF, LOT, [{"seed": s} for s in seeds], report=False)
out["attr_streams"] = {
    "package": "data_Building_From_FootprintSMALL__fc6ce924",
    "lot": "12x8 (area 96 m2)",
    "what": "get_attributes(): Eave_Ht = 96 / rand(5, 10) and Ridge_Ht = Eave_Ht + rand(3, 6) "
    "(one draw each, from the attr's own stream (uint32(seed) mod 714025 + k) mod 714025; "
    "k solved from the values: the same for every seed)",
    "k": {"Eave_Ht": 442175, "Ridge_Ht": 643046},
    "values": {
        str(s): {k: m.get_attributes()[k] for k in ("Eave_Ht", "Ridge_Ht", "Roof_Form")}
        for s, m in zip(seeds, models, strict=True)
    },
}
seeds = list(range(0, 400, 7))
models = generate(BFF, LOT, [{"seed": s} for s in seeds], report=False)
out["three_way_choice"] = {
    "package": "data_Building_From_FootprintSMALL__fc6ce924",
    "lot": "12x8",
    "what": "get_attributes()['Roof_Form'] = 40%: hip 50%: gable else: gambrel, in the attr's "
    "own stream; the offsets k consistent with 700 seeds (0..299 and 400 drawn from the "
    "int32 range) under 'one draw per branch, u < share / share left' (no k fits one draw "
    "against running sums)",
    "k_candidates": [381130, 384442],
    "values": {str(s): m.get_attributes()["Roof_Form"] for s, m in zip(seeds, models, strict=True)},
}
fixed = {"Roof_Form": "flat", "Eave_Ht": 20.0, "Ridge_Ht": 20.0, "Representation": "solid color"}
splits = {}
for form in ("setback top", "setback everywhere"):
    seeds = list(range(6))
    models = generate(
        BFF,
        TRAPEZOID,
        [{"seed": s, "Building_Form": form, **fixed} for s in seeds],
        report=False,
        geometry=True,
    )
    splits[form] = {}
    for s, m in zip(seeds, models, strict=True):
        v = m.get_vertices()
        splits[form][str(s)] = {
            "vertices": len(v) // 3,
            "x": sorted({round(x, 3) for x in v[0::3]}),
            "y": sorted({round(y, 3) for y in v[1::3]}),
        }
out["splits"] = {
    "package": "data_Building_From_FootprintSMALL__fc6ce924",
    "lot": "trapezoid",
    "attrs": fixed,
    "what": "split(x) sizes 'rand(0.1, 0.3) and pieces' successors Extrusion(Eave_Ht - "
    "rint(rand(3)) * Floor_Ht, ...), nested splits (setback everywhere): the distinct x "
    "and y of the model's vertices (m, rounded to 1 mm)",
    "values": splits,
}
seeds = [0, 1]
models = generate(ENV, LOT, [{"seed": s} for s in seeds])
out["comp_pieces"] = {
    "package": "tests_data_envelope2002__3bb69433",
    "lot": "12x8",
    "what": "reports of envelope2002 (comp, offset, setback and split pieces, stochastic "
    "choices of up to 7 branches in landscape.cga)",
    "values": {
        str(s): {
            k: v for k, v in m.get_report().items() if k.startswith(("green area", "Greenery Area"))
        }
        for s, m in zip(seeds, models, strict=True)
    },
}
seeds = [0, 1, 2]
models = generate(ENV, L_LOT, [{"seed": s} for s in seeds])
out["repeat_split_pieces"] = {
    "package": "tests_data_envelope2002__3bb69433",
    "lot": "L",
    "what": "green-area reports of envelope2002 on the L lot: the vertical greenery's repeat "
    "split(y){~size : Tile_y}* (size = rand(1.5, 3) drawn once, 12.5%: NIL per tile) on the "
    "walls of split(x){{1.8: Skalosia_pos | ~4: NIL}* | 1.8: Skalosia_pos} of the floors' "
    "comp(f){side} (the floors, split pieces of an extruded L-lot volume, list their sides in "
    "the volume's order)",
    "values": {
        str(s): {k: v for k, v in m.get_report().items() if k.startswith("green area")}
        for s, m in zip(seeds, models, strict=True)
    },
}
fixture = Path(__file__).resolve().parents[1] / "tests" / "data" / "cityengine_random.json"
# what other tools add to the fixture (tools/measure_attr_offsets.py: attr_offsets) is kept
kept = json.loads(fixture.read_text()) if fixture.exists() else {}
fixture.write_text(json.dumps({**kept, **out}, indent=1) + "\n")

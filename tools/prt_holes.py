"""Measure CityEngine's faces with holes with its runtime: writes ``tests/data/prt_holes.json``.

As tools/prt_primitives.py does (whose rewriter this tool reuses), the corpus's
``extrusion_rule`` package has its call of ``extrude`` replaced by one case's operations, and
the case is generated through PyPRT's PyEncoder, here on initial shapes with a hole given as
PyPRT takes them (``InitialShape(coordinates, indices, face_counts, holes)``). Per case the JSON
gives the reports ``geometry.nVertices``, ``nFaces``, ``nHoles``, ``area``, ``volume`` and the
scope after the operations, and the vertex and face counts PyPRT's encoder returns. Run with
PyPRT's Python (a development tool; shapegen never imports it)::

    /tmp/prt/bin/python tools/prt_holes.py tests/data/prt_holes.json
"""

from __future__ import annotations

import argparse
import os
import shutil
import subprocess
import sys
import tempfile
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
from prt_primitives import (  # noqa: E402
    ASM_JAR,
    CORPUS,
    SCOPE,
    measured_cases,
    rewritable_package,
    write_fixture,
)

GEOMETRY = ("nVertices", "nFaces", "nHoles", "area", "volume")
LOTS = {
    # PyPRT's own test shape: a 10 x 10 m square with a triangular hole (its pyGeometry_test)
    "square_triangle": {
        "coordinates": [0, 0, 0, 0, 0, 10, 10, 0, 10, 10, 0, 0, 2, 0, 2, 8, 0, 8, 2, 0, 8],
        "indices": [0, 1, 2, 3, 4, 5, 6],
        "face_counts": [4, 3],
        "holes": [[0, 1]],
    },
    # a courtyard lot: 12 x 8 m with a 4 x 2 m hole from (4, 3) to (8, 5)
    "courtyard": {
        "coordinates": [0, 0, 8, 12, 0, 8, 12, 0, 0, 0, 0, 0]  # the 12 x 8 m outline
        + [4, 0, 3, 8, 0, 3, 8, 0, 5, 4, 0, 5],  # the hole
        "indices": [0, 1, 2, 3, 4, 5, 6, 7],
        "face_counts": [4, 4],
        "holes": [[0, 1]],
    },
}
CASES = [
    "",
    "extrude(10)",
    "extrude(-4)",
    "deleteHoles()",
    "extrude(10) deleteHoles()",
    "offset(-1)",
    "offset(1)",
    "roofHip(30)",
    "roofGable(30)",
    "roofPyramid(30)",
    "roofShed(30)",
]


def calls(operations: str) -> str:
    import re

    found = [c.replace(" ", "") for c in re.findall(r"\w+\([^)]*\)", operations)]
    found += [f"report:geometry${k}" for k in GEOMETRY]
    found += [f"report:scope${k}" for k in SCOPE]
    return ";".join(found)


def measure(pyprt, work: Path, source: Path, patcher: Path, lot: dict, operations: str) -> dict:
    case = Path(tempfile.mkdtemp(dir=work))
    package = case / "package"
    shutil.copytree(source, package)
    cgb = package / "bin" / "extrusion_rule.cgb"
    java = ["java", "-cp", f"{ASM_JAR}{os.pathsep}{patcher}", "Patch", str(cgb), str(cgb)]
    subprocess.run([*java, calls(operations)], check=True)
    rpk = case / "case.rpk"
    subprocess.run(
        ["7z", "a", "-t7z", "-m0=LZMA", "-ms=off", "-mhc=off", str(rpk), ".resolvemap.xml",
         "bin", "rules"],
        cwd=package, check=True, stdout=subprocess.DEVNULL,
    )  # fmt: skip
    shape = pyprt.InitialShape(lot["coordinates"], lot["indices"], lot["face_counts"], lot["holes"])
    options = {"emitReport": True, "emitGeometry": True}
    (model,) = pyprt.ModelGenerator([shape]).generate_model(
        [{}], str(rpk), "com.esri.pyprt.PyEncoder", options
    )
    report = model.get_report()
    row = {"rule": operations}
    for key in GEOMETRY:
        value = report.get(f"geometry${key}_avg")
        row[key] = None if value is None else round(value, 6) + 0.0
    row["scope"] = [round(report[f"scope${k}_avg"], 4) + 0.0 for k in SCOPE]
    row["encoder_vertices"] = len(model.get_vertices()) // 3
    row["encoder_faces"] = list(model.get_faces())
    row["errors"] = list(model.get_cga_errors())
    return row


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("output", type=Path, help="the JSON file to write")
    parser.add_argument("--corpus", type=Path, default=CORPUS, help="the shared CGA corpus")
    args = parser.parse_args(argv)
    with rewritable_package(args.corpus, "prt_holes") as (pyprt, work, source, patcher):
        rows = measured_cases(
            "prt_holes",
            LOTS,
            CASES,
            lambda lot, case: measure(pyprt, work, source, patcher, lot, case),
        )
    from importlib.metadata import version as installed

    head = {
        "source": f"CityEngine's runtime, PyPRT {installed('pyprt')}, by tools/prt_holes.py: each "
        "rule's operations run on the named initial shape (PyPRT's InitialShape with holes) "
        "through PyPRT's PyEncoder; nVertices ... volume are geometry.* reported after the "
        "operations, scope is scope.sx, sy, sz, tx, ty, tz, encoder_vertices and encoder_faces "
        "what the PyEncoder returns (its faces as vertex counts)",
        "lots": LOTS,
    }
    write_fixture(args.output, head, "cases", rows)
    print(f"prt_holes: {len(rows)} cases written to {args.output}")
    return 0


if __name__ == "__main__":
    sys.exit(main())

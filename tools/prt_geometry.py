"""Compare shapegen.prt's PyEncoder output with PyPRT's on every package of the shared corpus.

For each rule package (``../shared/cga-corpus/packages/*.rpk``) and each lot (the 12 x 8 m lot
of tools/cga_reference.py and an L-shaped polygon lot), both runtimes generate the package's
start rule with its default attrs and seed 0 through the same API (``generate_model`` with the
PyEncoder); the table gives, per package and lot: vertex and face counts of each, the
Hausdorff distance between the two vertex sets both ways (metres), and whether the report
dictionaries are equal to 1e-6 relative. PyPRT runs in its own environment (a development
tool: ``python3 -m venv /tmp/prt && /tmp/prt/bin/pip install pyprt``); shapegen never imports
it::

    .venv/bin/python tools/prt_geometry.py --prt /tmp/prt/bin/python
    .venv/bin/python tools/prt_geometry.py --prt /tmp/prt/bin/python --markdown /tmp/table.md

A package that fails on either side is a row with the first line of its error.

``--fixture tests/data/prt_geometry.npz.xz`` also writes what PyPRT gave for every pair (vertex
and face counts, report, and its vertex set rounded to 0.1 mm), so that the slow lane checks the
table without PyPRT (tests/prt/test_geometry_table.py)::

    .venv/bin/python tools/prt_geometry.py --prt /tmp/prt/bin/python \
        --fixture tests/data/prt_geometry.npz.xz
"""

from __future__ import annotations

import argparse
import io
import json
import lzma
import math
import subprocess
import sys
from pathlib import Path

import numpy as np
from scipy.spatial import cKDTree

# ../shared/cga-corpus of the checkout; a worktree's checkout lies one folder further down
CORPUS = next(
    (p / "shared" / "cga-corpus" for p in Path(__file__).resolve().parents[2:4]
     if (p / "shared" / "cga-corpus").is_dir()),
    Path(__file__).resolve().parents[2] / "shared" / "cga-corpus",
)  # fmt: skip
LOTS = {
    "12x8": [0.0, 0.0, 8.0, 12.0, 0.0, 8.0, 12.0, 0.0, 0.0, 0.0, 0.0, 0.0],
    "L": [0, 0, 0, 0, 0, 12, 6, 0, 12, 6, 0, 5, 14, 0, 5, 14, 0, 0],
}
"""Initial shapes as PyPRT's flat coordinate lists, counter-clockwise seen from above."""
TOLERANCE_M = 1e-3
REPORT_REL = 1e-6
# A fixture's vertices are rounded to this (m): within half of it of PyPRT's on each axis
FIXTURE_STEP_M = 1e-4

PRT_SCRIPT = r"""
import json, sys, pyprt
package, coordinates = sys.argv[1], json.loads(sys.argv[2])
generator = pyprt.ModelGenerator([pyprt.InitialShape(coordinates)])
models = generator.generate_model([{}], package, "com.esri.pyprt.PyEncoder",
                                  {"emitReport": True, "emitGeometry": True})
if not models:
    print(json.dumps({"error": "PyPRT generated nothing"}))
else:
    m = models[0]
    report = {k: v for k, v in m.get_report().items()}
    print(json.dumps({"vertices": list(m.get_vertices()), "faces": list(m.get_faces()),
                      "report": report}))
"""


def prt_model(python: str, package: Path, coordinates: list) -> dict:
    run = subprocess.run(
        [python, "-c", PRT_SCRIPT, str(package), json.dumps(coordinates)],
        capture_output=True, text=True, timeout=600,
    )  # fmt: skip
    lines = [line for line in run.stdout.splitlines() if line.startswith("{")]
    if not lines:
        return {"error": (run.stderr.strip().splitlines() or ["PyPRT failed"])[-1]}
    return json.loads(lines[-1])


def shapegen_model(package: Path, coordinates: list) -> dict:
    import shapegen.prt as pyprt
    from shapegen.errors import ShapegenError

    try:
        generator = pyprt.ModelGenerator([pyprt.InitialShape(coordinates)])
        (model,) = generator.generate_model([{}], str(package))
    except ShapegenError as exc:
        return {"error": str(exc).splitlines()[0]}
    if not model.get_vertices() and model.get_cga_errors():
        return {"error": model.get_cga_errors()[0]}
    return {"vertices": model.get_vertices(), "faces": model.get_faces(),
            "report": model.get_report()}  # fmt: skip


def hausdorff(a: np.ndarray, b: np.ndarray) -> tuple[float, float]:
    """The largest distance from a vertex of ``a`` to ``b``'s vertices, and the other way."""
    if not len(a) or not len(b):
        return (math.inf, math.inf) if len(a) or len(b) else (0.0, 0.0)
    return float(cKDTree(b).query(a)[0].max()), float(cKDTree(a).query(b)[0].max())


def reports_equal(ours: dict, theirs: dict) -> bool:
    if set(ours) != set(theirs):
        return False
    for key, value in theirs.items():
        mine = ours[key]
        if isinstance(value, bool) or isinstance(value, str):
            if mine != value:
                return False
        elif not math.isclose(float(mine), float(value), rel_tol=REPORT_REL, abs_tol=1e-9):
            return False
    return True


def compare(python: str, package: Path, lot: str, theirs: dict | None = None) -> dict:
    """One row of the table: ``package`` on ``lot`` by shapegen and by PyPRT (run by
    ``python``, or its model ``theirs`` given: a fixture's)."""
    if theirs is None:
        theirs = prt_model(python, package, LOTS[lot])
    ours = shapegen_model(package, LOTS[lot])
    row = {"package": package.name.removeprefix("Esri+pyprt__").removesuffix(".rpk"), "lot": lot}
    if "error" in theirs or "error" in ours:
        row["error"] = ("PyPRT: " + theirs["error"]) if "error" in theirs else ours["error"]
        return row
    a = np.asarray(ours["vertices"], float).reshape(-1, 3)
    b = np.asarray(theirs["vertices"], float).reshape(-1, 3)
    row["vertices"] = (len(a), theirs.get("vertex_count", len(b)))
    row["faces"] = (len(ours["faces"]), len(theirs["faces"]))
    row["hausdorff"] = hausdorff(a, b)
    row["reports"] = reports_equal(ours["report"], theirs["report"])
    row["same"] = (
        row["vertices"][0] == row["vertices"][1]
        and row["faces"][0] == row["faces"][1]
        and max(row["hausdorff"]) <= TOLERANCE_M
    )
    return row


def pair_key(package: Path, lot: str) -> str:
    return package.name.removeprefix("Esri+pyprt__").removesuffix(".rpk") + "/" + lot


def write_fixture(path: Path, models: dict[str, dict]) -> None:
    """PyPRT's ``models`` (by :func:`pair_key`) into ``path``: one xz-compressed ``.npz`` whose
    ``meta`` is a JSON text (counts, report or error per pair) and whose array ``<k>`` is pair
    k's vertex set, rounded to ``FIXTURE_STEP_M`` (unique rows, int32 steps)."""
    meta, arrays = {}, {}
    for k, (key, model) in enumerate(sorted(models.items())):
        if "error" in model:
            meta[key] = {"error": model["error"]}
            continue
        vertices = np.asarray(model["vertices"], float).reshape(-1, 3)
        steps = np.unique(np.round(vertices / FIXTURE_STEP_M).astype(np.int64), axis=0)
        arrays[f"v{k}"] = steps.astype(np.int32)
        meta[key] = {"array": f"v{k}", "vertex_count": len(vertices),
                     "faces": list(model["faces"]), "report": model["report"]}  # fmt: skip
    buffer = io.BytesIO()
    np.savez(buffer, meta=np.array(json.dumps(meta, sort_keys=True)), **arrays)
    path.write_bytes(lzma.compress(buffer.getvalue()))


def read_fixture(path: Path) -> dict[str, dict]:
    """The models :func:`write_fixture` wrote, by pair key: ``vertices`` (the rounded set,
    metres), ``vertex_count``, ``faces`` (as PyPRT's ``get_faces()``: each face's corner
    count), ``report``; or ``error``."""
    with np.load(io.BytesIO(lzma.decompress(path.read_bytes()))) as data:
        meta = json.loads(str(data["meta"]))
        for model in meta.values():
            if "array" in model:
                model["vertices"] = (data[model.pop("array")] * FIXTURE_STEP_M).ravel().tolist()
    return meta


def markdown(rows: list[dict]) -> str:
    lines = [
        "| package | lot | vertices (shapegen / PyPRT) | faces | Hausdorff (m, both ways) |"
        " reports | same |",
        "|---|---|---:|---:|---:|---|---|",
    ]
    for r in rows:
        if "error" in r:
            lines.append(f"| {r['package']} | {r['lot']} | | | | | error: {r['error'][:80]} |")
            continue
        h = " / ".join(f"{d:.3g}" for d in r["hausdorff"])
        lines.append(
            f"| {r['package']} | {r['lot']} | {r['vertices'][0]} / {r['vertices'][1]} |"
            f" {r['faces'][0]} / {r['faces'][1]} | {h} | {'equal' if r['reports'] else 'differ'}"
            f" | {'yes' if r['same'] else 'no'} |"
        )
    same = sum(1 for r in rows if r.get("same"))
    lines.append("")
    lines.append(f"{same} of {len(rows)} package-lot pairs: equal counts and within 1 mm.")
    return "\n".join(lines) + "\n"


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--prt", required=True, help="the python of an environment with PyPRT")
    parser.add_argument("--only", default="", help="a substring of the package names to run")
    parser.add_argument("--markdown", type=Path, help="write the table as markdown here")
    parser.add_argument("--fixture", type=Path, help="write PyPRT's models here (see above)")
    args = parser.parse_args(argv)
    rows, models = [], {}
    for package in sorted((CORPUS / "packages").glob("*.rpk")):
        if args.only not in package.name:
            continue
        for lot in LOTS:
            theirs = prt_model(args.prt, package.resolve(), LOTS[lot])
            models[pair_key(package, lot)] = theirs
            row = compare(args.prt, package.resolve(), lot, theirs)
            rows.append(row)
            print(json.dumps(row), flush=True)
    table = markdown(rows)
    print(table)
    if args.markdown:
        args.markdown.write_text(table)
    if args.fixture:
        write_fixture(args.fixture, models)
    return 0


if __name__ == "__main__":
    sys.exit(main())

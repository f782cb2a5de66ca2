"""``shapegen city`` on a real district: CPU per lot of every process, against PyPRT.

Run: ``.venv/bin/python benchmarks/bench_city_osm.py [--lots N] [--packages extrusion,building]
[--runs local1,local2,dask2] [--analyze]``.

The lots are the 10 000 building footprints of Neubrandenburg in
``tests/data/osm/neubrandenburg.geojson.gz`` (OpenStreetMap, ODbL; the first N with ``--lots``),
or with ``--rectangles`` N rectangles of 12 x 8 m (the footprints are mostly not convex, and a
rule's leaf on one is cut into convex blocks: the rectangles show the cost without that).
The packages are two CityEngine rule packages of the shared corpus: ``extrusion`` (one extrusion
of the footprint, ``examples_data_extrusion_rule``) and ``building`` (a building from its
footprint, ``data_Building_From_FootprintSMALL``). Each run is a fresh process that does what
``shapegen city LOTS RULE -o OUT`` does (imports, reads the lots, runs, writes the tables and
``city.glb``) on 1 local worker (``local1``), 2 local workers (``local2``) or a new two-worker
Dask ``LocalCluster`` (``dask2``, ``--scheduler local:2``), without judging the buildings unless
``--analyze`` (PyPRT only generates). It prints per run: wall seconds and lots per second, CPU
milliseconds per lot of all processes (parent and workers: user + system), of the parent alone
(and of its part before the run: imports, the package and the lots read), and of the workers;
how many workers one parent can keep busy: the workers' CPU per lot over the parent's while it
runs the lots (scheduling, merging, the tables and city.glb), and over all of the parent's; and
the peak memory of the parent and of the largest worker process.

PyPRT (CityEngine's runtime; the venv ``~/.cache/shapegen/prt-venv`` that
benchmarks/bench_cga.py makes) generates the same footprints with the same package in one
``generate_model`` call for all of them, twice: writing every model into one glTF
(``GLTFEncoder``, as a city run writes city.glb: the reference the ratio is taken against) and
into memory (``PyEncoder``); its CPU seconds for each call (and for its whole process: import
and package read included) are printed beside shapegen's. The machine is shared:
CPU seconds, not wall seconds, are the figures to compare; the load is printed.
"""

from __future__ import annotations

import argparse
import datetime
import gzip
import json
import os
import subprocess
import sys
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from benchmarks.processes import user_environment  # noqa: E402

LOTS = ROOT / "tests" / "data" / "osm" / "neubrandenburg.geojson.gz"
# ../shared/cga-corpus of the checkout (a worktree's checkout lies one folder further down)
CORPUS = next(
    (p / "shared" / "cga-corpus" / "packages" for p in ROOT.parents[:2]
     if (p / "shared" / "cga-corpus").is_dir()),
    ROOT.parent / "shared" / "cga-corpus" / "packages",
)  # fmt: skip
PACKAGES = {
    "extrusion": CORPUS / "Esri+pyprt__examples_data_extrusion_rule__1c38c522.rpk",
    "building": CORPUS / "Esri+pyprt__data_Building_From_FootprintSMALL__fc6ce924.rpk",
}
RUNS = {"local1": {"workers": 1}, "local2": {"workers": 2}, "dask2": {"scheduler": "local:2"}}
PRT_VENV = Path.home() / ".cache" / "shapegen" / "prt-venv"

# One city run in a fresh process, as the command runs it; prints its CPU seconds as JSON.
_RUNNER = r"""
import json, resource, sys, time

def cpu(who):
    usage = resource.getrusage(who)
    return usage.ru_utime + usage.ru_stime

wall = time.perf_counter()
job = json.loads(sys.argv[1])
import shapegen
from shapegen.city import read_lots, run_city
from dataclasses import replace

grammar = shapegen.load_grammar(job["package"])
city = read_lots(job["lots"])
city = replace(city, lots=city.lots[: job["count"]])
before = cpu(resource.RUSAGE_SELF)
run = run_city(city, grammar, job["out"], analyze=job["analyze"], **job["executor"])
print(json.dumps({
    "parent": cpu(resource.RUSAGE_SELF), "before": before,
    "workers": cpu(resource.RUSAGE_CHILDREN), "wall": time.perf_counter() - wall,
    "run_wall": run.seconds, "built": run.built, "failed": run.failed,
    "parent_mib": resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024,
    "worker_mib": resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss / 1024,
    "errors": sorted({(r["error"] or "")[:70] for r in run.records if r["status"] != "ok"})[:3],
}))
"""

# PyPRT: every footprint as an initial shape, one generate_model call for all.
_PRT_DRIVER = r"""
import json, resource, sys, tempfile, time
import pyprt

job = json.loads(sys.stdin.read())
shapes = []
for ring in job["rings"]:
    vertices = []
    for east, north in ring:
        vertices += [east, 0.0, -north]  # y up, north -z: the face's normal is +y
    shapes.append(pyprt.InitialShape(vertices))
generator = pyprt.ModelGenerator(shapes)
options = {"emitReport": False, "emitGeometry": True}
start = time.process_time()
models = generator.generate_model([{}] * len(shapes), job["package"], "com.esri.pyprt.PyEncoder",
                                  options)
call = time.process_time() - start
# the issue's reference: every model written into one glTF, as a city run writes city.glb
with tempfile.TemporaryDirectory() as folder:
    start = time.process_time()
    pyprt.ModelGenerator(shapes).generate_model(
        [{}] * len(shapes), job["package"], "com.esri.prt.codecs.GLTFEncoder",
        {"outputPath": folder, "baseName": "city", "emitReport": False})
    written = time.process_time() - start
usage = resource.getrusage(resource.RUSAGE_SELF)
print(json.dumps({"call": call, "gltf": written, "process": usage.ru_utime + usage.ru_stime,
                  "models": len(models)}))
"""


def shapegen_run(
    package: Path, lots: Path, count: int, executor: dict, analyze: bool, folder: Path
):
    job = {
        "package": str(package),
        "lots": str(lots),
        "count": count,
        "out": str(folder),
        "executor": executor,
        "analyze": analyze,
    }
    result = subprocess.run(
        [sys.executable, "-c", _RUNNER, json.dumps(job)],
        capture_output=True,
        text=True,
        env=user_environment(),
    )
    if result.returncode != 0:
        return f"failed: {result.stderr.strip().splitlines()[-1:]}"
    return json.loads(result.stdout.strip().splitlines()[-1])


def prt_run(package: Path, lots: Path, count: int):
    python = PRT_VENV / "bin" / "python"
    if not python.exists():
        return "no PyPRT venv (run benchmarks/bench_cga.py once to make it)"
    from shapegen.city import read_lots

    city = read_lots(lots)
    rings = [lot.ring.tolist() for lot in city.lots[:count] if lot.problem is None]
    result = subprocess.run(
        [str(python), "-W", "ignore", "-c", _PRT_DRIVER],
        input=json.dumps({"package": str(package), "rings": rings}),
        capture_output=True,
        text=True,
    )
    if result.returncode != 0:
        return f"PyPRT failed: {result.stderr.strip().splitlines()[-1:]}"
    return json.loads(result.stdout.strip().splitlines()[-1])


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--lots", type=int, default=10_000)
    parser.add_argument("--packages", default="extrusion,building")
    parser.add_argument("--runs", default="local1,local2,dask2")
    parser.add_argument("--analyze", action="store_true", help="judge every building too")
    parser.add_argument(
        "--rectangles",
        action="store_true",
        help="12 x 8 m rectangles on a 20 m grid (local metres) instead of the district",
    )
    args = parser.parse_args()
    scratch = tempfile.TemporaryDirectory()
    if args.rectangles:
        count = args.lots
        lots = Path(scratch.name) / "rectangles.geojson"
        lots.write_text(json.dumps(_rectangles(count)))
    else:
        lots = LOTS
        with gzip.open(LOTS) as handle:
            count = min(args.lots, len(json.load(handle)["features"]))
    when = datetime.datetime.now(datetime.timezone.utc).strftime("%Y-%m-%d %H:%M UTC")
    print(
        f"{count} lots of {lots.name}; {os.cpu_count()} cores; {when};"
        f" load {os.getloadavg()[0]:.1f}; buildings"
        + (" judged" if args.analyze else " derived, not judged")
    )
    for name in args.packages.split(","):
        package = PACKAGES[name]
        if not package.is_file():
            raise SystemExit(f"bench_city_osm: no rule package {package}")
        prt = prt_run(package, lots, count)
        if isinstance(prt, dict):
            prt_ms = 1000 * prt["gltf"] / count
            print(
                f"{name}: PyPRT {prt['gltf']:.2f} s CPU for one call over {prt['models']} shapes"
                f" writing one glTF ({prt_ms:.3f} ms a lot, the reference; into memory with its"
                f" PyEncoder {1000 * prt['call'] / count:.3f} ms a lot; its whole process"
                f" {prt['process']:.2f} s)"
            )
        else:
            prt_ms = None
            print(f"{name}: {prt}")
        for run_name in args.runs.split(","):
            with tempfile.TemporaryDirectory() as folder:
                figures = shapegen_run(
                    package, lots, count, RUNS[run_name], args.analyze, Path(folder)
                )
            if isinstance(figures, str):
                print(f"  {run_name}: {figures}")
                continue
            parent, workers = figures["parent"], figures["workers"]
            each = 1000 * (parent + workers) / count
            versus = f", {each / prt_ms:.0f}x PyPRT's" if prt_ms else ""
            busy = workers / parent if parent > 0 else float("inf")
            running = parent - figures["before"]
            busy_running = workers / running if running > 0 else float("inf")
            print(
                f"  {run_name}: {figures['wall']:.1f} s wall ({count / figures['run_wall']:.0f}"
                f" lots/s in the run), {figures['built']} built, {figures['failed']} failed;"
                f" CPU a lot: all {each:.2f} ms{versus}; parent {1000 * parent / count:.3f} ms"
                f" ({1000 * figures['before'] / count:.3f} before the run: imports, package,"
                f" lots), workers {1000 * workers / count:.2f} ms; one parent keeps"
                f" {busy_running:.0f} workers busy ({busy:.0f} counting its start and the lots'"
                f" reading); peak memory: parent {figures['parent_mib']:.0f} MiB, largest worker"
                f" {figures['worker_mib']:.0f} MiB"
            )
            if figures["errors"]:
                print(f"    errors: {figures['errors']}")


def _rectangles(count: int) -> dict:
    """``count`` 12 x 8 m lots, 20 m apart on a square grid, as GeoJSON in local metres."""
    side = max(1, round(count**0.5))
    features = []
    for k in range(count):
        x, y = 20.0 * (k % side), 20.0 * (k // side)
        ring = [[x, y], [x + 12, y], [x + 12, y + 8], [x, y + 8], [x, y]]
        geometry = {"type": "Polygon", "coordinates": [ring]}
        features.append({"type": "Feature", "properties": {}, "geometry": geometry})
    return {"type": "FeatureCollection", "features": features}


if __name__ == "__main__":
    main()

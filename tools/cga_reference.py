"""Reference models of the CGA corpus from CityEngine's own runtime (PyPRT), for comparison.

A development tool, not part of shapegen: it needs PyPRT and py7zr, installed in a separate
environment (PyPRT is CityEngine's procedural runtime; it runs the corpus's ``.rpk`` packages
offline)::

    python3 -m venv /tmp/prt && /tmp/prt/bin/pip install pyprt py7zr
    /tmp/prt/bin/python tools/cga_reference.py --out tools/cga_reference

For every package in ``../shared/cga-corpus/packages`` it generates the start rule on a
12 x 8 m lot (CityEngine's initial shape in the x-z plane, first edge along +x) with the rule's
default attrs, and writes one JSON file per package: the rule files it contains (matched to the
corpus by the SHA-1 prefix in their names), the generated mesh's vertex and face counts, its
bounding box, its enclosed volume (divergence theorem over the triangulated faces), the
``report()`` values, and the number of leaves: PyPRT's own encoder merges the leaves into one
mesh, so they are counted in a second generation with CityEngine's OBJ encoder and
``meshGranularity=AS_GENERATED``, which writes one OBJ group per generated leaf mesh.
shapegen's tests read these files; nothing in shapegen imports PyPRT.
"""

from __future__ import annotations

import argparse
import hashlib
import json
import sys
import tempfile
from pathlib import Path

import numpy as np

CORPUS = Path(__file__).resolve().parents[2] / "shared" / "cga-corpus"
LOT = [0.0, 0.0, 8.0, 12.0, 0.0, 8.0, 12.0, 0.0, 0.0, 0.0, 0.0, 0.0]
"""The 12 x 8 m lot as PyPRT's flat coordinate list: (0,0,8) (12,0,8) (12,0,0) (0,0,0).

Counter-clockwise seen from above (+y), first edge along +x: CityEngine puts the scope's x along
the first edge, so the scope is x along +x (12 m), z along +z (8 m), y up -- shapegen's
``lot=(12, 8)``.
"""


def package_rules(package: Path) -> dict[str, str]:
    """``path inside the package -> corpus file name`` for every ``.cga`` in ``package``."""
    import py7zr

    corpus = {p.stem.rsplit("_", 1)[1]: p.name for p in (CORPUS / "rules").glob("*.cga")}
    out = {}
    with tempfile.TemporaryDirectory() as tmp:
        with py7zr.SevenZipFile(package) as archive:
            archive.extractall(tmp)
        for cga in sorted(Path(tmp).rglob("*.cga")):
            digest = hashlib.sha1(cga.read_bytes()).hexdigest()[:8]
            out[str(cga.relative_to(tmp))] = corpus.get(digest, "")
    return out


def mesh_figures(vertices: np.ndarray, indices: np.ndarray, faces: np.ndarray) -> dict:
    """Counts, bounding box and enclosed volume of PyPRT's indexed polygon mesh."""
    points = vertices.reshape(-1, 3)
    volume = 0.0
    start = 0
    for count in faces:
        polygon = points[indices[start : start + count]]
        start += count
        for k in range(1, count - 1):  # fan triangulation; the faces are planar
            volume += np.dot(polygon[0], np.cross(polygon[k], polygon[k + 1])) / 6.0
    figures = {"vertices": int(len(points)), "faces": int(len(faces)), "volume": float(volume)}
    if len(points):
        figures["bbox_min"] = points.min(axis=0).tolist()
        figures["bbox_max"] = points.max(axis=0).tolist()
    return figures


def reference(package: Path) -> dict:
    import pyprt

    generator = pyprt.ModelGenerator([pyprt.InitialShape(LOT)])
    options = {"emitReport": True, "emitGeometry": True}
    models = generator.generate_model([{}], str(package), "com.esri.pyprt.PyEncoder", options)
    out = {"package": package.name, "lot": LOT, "rules": package_rules(package)}
    if not models:
        out["generated"] = False
        return out
    model = models[0]
    out["generated"] = True
    out.update(
        mesh_figures(
            np.asarray(model.get_vertices(), float),
            np.asarray(model.get_indices(), int),
            np.asarray(model.get_faces(), int),
        )
    )
    out["reports"] = {k: v for k, v in sorted(model.get_report().items()) if k.endswith("_sum")}
    out["leaves"] = leaf_count(package)
    return out


def leaf_count(package: Path) -> int:
    """The generated leaf meshes: OBJ groups written with ``meshGranularity=AS_GENERATED``."""
    import pyprt

    with tempfile.TemporaryDirectory() as folder:
        generator = pyprt.ModelGenerator([pyprt.InitialShape(LOT)])
        options = {"outputPath": folder, "meshGranularity": "AS_GENERATED"}
        generator.generate_model([{}], str(package), "com.esri.prt.codecs.OBJEncoder", options)
        count = 0
        for obj in Path(folder).glob("*.obj"):
            with open(obj, encoding="utf-8", errors="replace") as handle:
                count += sum(1 for line in handle if line.startswith("g "))
        return count


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--out", type=Path, required=True, help="directory for the JSON files")
    parser.add_argument("--only", default="", help="a substring of the package names to run")
    args = parser.parse_args(argv)
    args.out.mkdir(parents=True, exist_ok=True)
    for package in sorted((CORPUS / "packages").glob("*.rpk")):
        if args.only not in package.name:
            continue
        data = reference(package)
        name = package.name.removeprefix("Esri+pyprt__").removesuffix(".rpk")
        (args.out / f"{name}.json").write_text(json.dumps(data, indent=1) + "\n")
        print(f"{name}: {data.get('faces', 0)} faces, volume {data.get('volume', 0):.2f} m3")
    return 0


if __name__ == "__main__":
    sys.exit(main())

"""Measure the texture coordinates CityEngine's runtime gives an extruded face: writes the OBJ
files of ``tests/data/obj-pyprt/`` named ``extruded_*``.

Each initial shape is an OBJ file with texture coordinates (``tests/data/obj-pyprt/uv_*.obj``:
a 10 x 10 m square whose coordinates are (x, z) / 10, and an L-shaped lot whose coordinates are
a turned and sheared map of its corners), generated with the corpus's ``extrusion_rule``
package as it is, its height fixed by ``minBuildingHeight = maxBuildingHeight``, through
PyPRT's OBJ encoder; the written OBJ is kept as ``extruded_<name>_pyprt112_0.obj``. Run with
PyPRT's Python (a development tool; shapegen never imports it)::

    /tmp/prt-venv/bin/python tools/prt_extrusion_uvs.py --corpus /work/shared/cga-corpus
"""

from __future__ import annotations

import argparse
import shutil
import sys
import tempfile
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
from prt_measure import CORPUS, corpus_package  # noqa: E402
from prt_primitives import PACKAGE  # noqa: E402

DATA = Path(__file__).resolve().parents[1] / "tests" / "data" / "obj-pyprt"
# initial shape -> the extrusion's height (m)
SHAPES = {"square": 4.0, "l": 3.0, "l_down": -3.0}


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--corpus", type=Path, default=CORPUS, help="the shared CGA corpus")
    args = parser.parse_args(argv)
    package = corpus_package(args.corpus, "prt_extrusion_uvs", PACKAGE)
    import pyprt  # PyPRT's environment only

    for name, height in SHAPES.items():
        source = DATA / f"uv_{name.removesuffix('_down')}.obj"
        with tempfile.TemporaryDirectory() as out:
            shape = pyprt.InitialShape(str(source))
            attrs = {"minBuildingHeight": height, "maxBuildingHeight": height}
            pyprt.ModelGenerator([shape]).generate_model(
                [attrs], str(package), "com.esri.prt.codecs.OBJEncoder", {"outputPath": out}
            )
            target = DATA / f"extruded_{name}_pyprt112_0.obj"
            shutil.copy(Path(out) / "base_name_0.obj", target)
            print(f"prt_extrusion_uvs: {target}")
    return 0


if __name__ == "__main__":
    sys.exit(main())

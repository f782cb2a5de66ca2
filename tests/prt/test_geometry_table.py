"""The geometry table of docs/cga-compatibility.md in the slow lane: every package of the shared
corpus on both lots, derived by shapegen.prt and held against what PyPRT 1.12 gave
(tests/data/prt_geometry.npz.xz, written by ``tools/prt_geometry.py --fixture``: its vertex and
face counts and its vertices to 0.1 mm). A pair is equal with the same counts and every vertex
within 1 mm of the other's both ways (plus the fixture's rounding); every pair that differs is
listed with its cause in tests/data/prt_geometry_expected.json, and a pair listed there must
still differ, so the list says what is true."""

import importlib.util
import json
import math
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
DATA = ROOT / "tests" / "data"
PACKAGES = next(
    (p / "shared" / "cga-corpus" / "packages" for p in ROOT.parents
     if (p / "shared" / "cga-corpus" / "packages").is_dir()),
    None,
)  # fmt: skip


def _tool():
    spec = importlib.util.spec_from_file_location(
        "prt_geometry", ROOT / "tools" / "prt_geometry.py"
    )
    tool = importlib.util.module_from_spec(spec)
    sys.modules.setdefault("prt_geometry", tool)
    spec.loader.exec_module(tool)
    return tool


@pytest.mark.slow
@pytest.mark.skipif(PACKAGES is None, reason="no shared corpus (../shared/cga-corpus/packages)")
def test_the_geometry_table_holds_and_each_difference_is_explained():
    tool = _tool()
    theirs = tool.read_fixture(DATA / "prt_geometry.npz.xz")
    explained = json.loads((DATA / "prt_geometry_expected.json").read_text())["differ"]
    # the fixture's rounding moves a vertex by at most half a step on each axis
    tolerance = tool.TOLERANCE_M + math.sqrt(3) * tool.FIXTURE_STEP_M / 2
    differ, errors, missing = {}, [], []
    for key, model in sorted(theirs.items()):
        name, lot = key.rsplit("/", 1)
        package = PACKAGES / f"Esri+pyprt__{name}.rpk"
        if not package.is_file():
            missing.append(key)
            continue
        row = tool.compare(None, package, lot, model)
        if "error" in row:
            errors.append(f"{key}: {row['error']}")
            continue
        same = (
            row["vertices"][0] == row["vertices"][1]
            and row["faces"][0] == row["faces"][1]
            and max(row["hausdorff"]) <= tolerance
        )
        if not same:
            differ[key] = row
    equal = len(theirs) - len(differ) - len(errors) - len(missing)
    print(f"{equal} of {len(theirs)} package-lot pairs equal to PyPRT's within 1 mm")
    assert not missing, f"packages of the fixture not in the corpus: {missing}"
    assert not errors, "\n".join(errors)
    unexplained = sorted(set(differ) - set(explained))
    assert not unexplained, "differ from PyPRT without a cause listed: " + "; ".join(
        f"{k} vertices {differ[k]['vertices']} faces {differ[k]['faces']} "
        f"Hausdorff {max(differ[k]['hausdorff']):.3g} m"
        for k in unexplained
    )
    stale = sorted(set(explained) - set(differ))
    assert not stale, f"listed as differing but now equal to PyPRT's: {stale}"

"""CityEngine rule files in the editor: a .cga start rule with its imports, and a .rpk rule
package, open as a .grammar file does; their warnings are in the state, and the stable range of
a free attr is scanned from the file (whose folder resolves the imports)."""

import json
import shlex

import pytest
from editor_http import request, serving
from editor_stack import (
    CGA_BUILDING,
    CGA_WARNING,
    WAIT_BOUND_S,
    cga_package,
    cga_project,
    scanned,
)

from shapegen.cli import main
from shapegen.editor import EditorSession

pytestmark = pytest.mark.usefixtures("package_cache")


def values(state) -> dict:
    return {a["name"]: a["value"] for a in state["attrs"]}


def test_a_cga_file_opens_with_its_imports_and_warnings(tmp_path):
    with serving(cga_project(tmp_path)) as server:
        state = json.loads(request(server, "GET", "/api/state")[2])
        assert state["grammar"]["name"] == "building.cga" and state["grammar"]["dialect"] == "cga"
        assert any(CGA_WARNING in w for w in state["warnings"]), state["warnings"]
        assert values(state) == {"floor_height": 1, "lib.height": 6}  # the import's attr too
        # an import's attrs are in a section of their own; a @Group holds within its file
        assert state["sections"] == [
            {"group": ["Mass"], "attrs": ["floor_height"]},
            {"group": ["lib"], "attrs": ["lib.height"]},
        ]
        assert state["grammar"]["blocks"] == 6 and state["verdict"]["stands"]
        status, _, content = request(server, "POST", "/api/attrs", {"lib.height": 9})
        assert status == 200 and json.loads(content)["grammar"]["blocks"] == 9
        exported = json.loads(request(server, "GET", "/api/attrs.json")[2])
        assert exported["command"].endswith("--set lib.height=9")


def test_a_rule_package_opens_as_its_start_rule(tmp_path):
    package = cga_package(tmp_path)
    with serving(package) as server:
        state = json.loads(request(server, "GET", "/api/state")[2])
        assert state["grammar"]["name"] == "building.cga"
        assert state["grammar"]["package"] == str(package.resolve())
        assert any(CGA_WARNING in w for w in state["warnings"])
        assert state["grammar"]["blocks"] == 6
        request(server, "POST", "/api/attrs", {"lib.height": 9})
        exported = json.loads(request(server, "GET", "/api/attrs.json")[2])
    # the line names the package the designer opened, not its start rule unpacked in a cache,
    # and builds the same design as it stands
    assert exported["grammar"] == str(package.resolve())
    for key in ("command", "command_every_attr"):
        words = shlex.split(exported[key])
        assert words[:3] == ["shapegen", "build", str(package.resolve())], exported[key]
        report = tmp_path / f"{key}.json"
        assert main([*words[1:], "--report", str(report), "-q"]) == 0
        built = json.loads(report.read_text(encoding="utf-8"))
        assert built["blocks"] == 9 and built["attrs"]["lib.height"] == 9


def test_a_rule_package_exported_anew_is_read_anew(tmp_path):
    package = cga_package(tmp_path)
    with serving(package) as server:
        before = json.loads(request(server, "GET", "/api/state")[2])["grammar"]
        # CityEngine exports the package again: one more floor
        cga_package(
            tmp_path, CGA_BUILDING.replace("extrude(lib.height)", "extrude(lib.height + 1)")
        )
        status, _, content = request(server, "POST", "/api/reload", {})
        after = json.loads(content)["grammar"]
    assert status == 200 and (before["blocks"], after["blocks"]) == (6, 7)
    assert after["package"] == before["package"] and after["path"] != before["path"]


def test_the_stable_range_of_a_cga_files_free_attr_is_scanned(tmp_path):
    session = EditorSession(str(cga_project(tmp_path)))
    try:
        state = session.wait_for(scanned("floor_height"), timeout=WAIT_BOUND_S)
        stability = state["stability"]["floor_height"]
        # the scanning process read the file, so its import was found: every design was judged
        assert all(stands is not None for _, stands in stability["samples"])
        assert stability["intervals"] == [[0.5, 3.0]]
    finally:
        session.close()

"""GET /api/blocks/ID: one block's labels, rule path, the attrs its rules read, its joints'
forces (in equilibrium with its weight) and the tension it needs."""

import json

import numpy as np
import pytest
from editor_http import request, serving
from editor_stack import STACK_WEIGHT

from shapegen import pipeline
from shapegen.editor.blocks import rule_attrs

BLOCK_WEIGHT = STACK_WEIGHT / 2  # N: one unit cube


@pytest.fixture(scope="module")
def server(tmp_path_factory):
    from editor_stack import STACK

    path = tmp_path_factory.mktemp("blocks") / "stack.grammar"
    path.write_text(STACK, encoding="utf-8")
    with serving(path, attrs={"offset": 0.7}) as server:  # the upper block needs tension
        yield server


def block(server, block_id):
    status, _, content = request(server, "GET", f"/api/blocks/{block_id}")
    return status, json.loads(content)


def test_a_block_says_where_it_came_from(server):
    status, upper = block(server, "b1")
    assert status == 200
    assert upper["labels"] == ["upper"] and upper["rule_path"] == ["Lot", "Upper"]
    assert upper["attrs"] == [{"name": "offset", "value": 0.7, "user": True}]
    assert block(server, "b0")[1]["attrs"] == []  # the lower block's rules read no attr
    assert upper["weight"] == pytest.approx(BLOCK_WEIGHT)
    assert upper["volume"] == pytest.approx(1.0)


def test_its_joints_hold_its_weight_and_say_the_tension_they_need(server):
    _, upper = block(server, "b1")
    (joint,) = upper["joints"]
    assert joint["other"] == "b0" and not joint["support"]
    assert joint["compression"] == pytest.approx(BLOCK_WEIGHT, rel=1e-6)
    assert joint["shear"] == 0  # a level joint under its own weight: the noise reads 0
    assert joint["tension"] > 0 and upper["tension"] == joint["tension"]
    assert joint["area"] == pytest.approx(0.3)  # the overlap of the two faces: 0.3 x 1 m
    _, lower = block(server, "b0")
    by_other = {j["other"]: j for j in lower["joints"]}
    assert set(by_other) == {"ground", "b1"} and by_other["ground"]["support"]
    # each block in equilibrium: the forces of its joints carry its weight
    for details in (upper, lower):
        total = np.sum([j["force"] for j in details["joints"]], axis=0)
        np.testing.assert_allclose(total, [0, details["weight"], 0], atol=1e-6 * STACK_WEIGHT)


def test_a_standing_design_needs_no_tension(stack_file):
    with serving(stack_file) as server:
        _, upper = block(server, "b1")
        assert upper["tension"] == 0 and upper["joints"][0]["tension"] == 0


@pytest.mark.parametrize(
    ("method", "path", "status", "message"),
    [
        ("GET", "/api/blocks/b9", 404, "the current model has no block 'b9'"),
        ("GET", "/api/blocks/", 404, "no such address"),
        ("GET", "/api/blocks/b1/joints", 404, "no such address"),
        ("POST", "/api/blocks/b1", 405, "/api/blocks/b1 takes GET, not POST"),
    ],
)
def test_bad_block_requests(server, method, path, status, message):
    got, _, content = request(server, method, path, {} if method == "POST" else None)
    assert got == status and message in json.loads(content)["error"]


READING = """\
attr width = 2
attr height = width * 2
attr unused = 1
const half = width / 2
attr depth = 1
attr hidden_by_param = 3
thickness(k) = k * depth

@StartRule @Lot(2, 1)
Lot --> extrude(height) Wall(hidden_by_param)
Wall(hidden_by_param) --> s(half, '1, thickness(hidden_by_param)) label("wall") i("box")
"""


def test_the_attrs_a_rule_reads_are_followed_through_consts_functions_and_defaults(tmp_path):
    path = tmp_path / "reading.grammar"
    path.write_text(READING, encoding="utf-8")
    grammar = pipeline.load(str(path))
    assert rule_attrs(grammar, ["Lot"]) == ["width", "height", "hidden_by_param"]
    # Wall's parameter hides the attr of its name; half is width / 2, thickness reads depth
    assert rule_attrs(grammar, ["Wall"]) == ["width", "depth"]
    assert rule_attrs(grammar, ["Nothing"]) == []

"""POST /api/settings: which attrs the search varies, its margin, the seed and the lot."""

import json

import pytest
from editor_http import request, serving


def post(server, path, body=None):
    status, _, content = request(server, "POST", path, {} if body is None else body)
    return status, json.loads(content)


def block_volume(server, block_id="b1") -> float:
    return json.loads(request(server, "GET", f"/api/blocks/{block_id}")[2])["volume"]


def test_the_margin_of_the_search(stack_file):
    # The upper block stands on the lower one shrunk to 1 - m of its size while its offset is
    # at most (1 - m) / (2 - m): 1/3 for a margin of 0.5 (0.5 without a margin).
    with serving(stack_file) as server:
        _, state = post(server, "/api/settings", {"margin": 0.5})
        assert state["settings"]["margin"] == 0.5
        post(server, "/api/attrs", {"offset": 0.8})
        status, state = post(server, "/api/optimize", {"objective": "closest"})
        offset = {a["name"]: a["value"] for a in state["attrs"]}["offset"]
        assert status == 200 and offset <= 1 / 3 + 1e-3, offset
        assert offset > 0.25, offset  # the closest: near the boundary, not anywhere


def test_free_and_fixed_attrs(stack_file):
    with serving(stack_file) as server:
        state = json.loads(request(server, "GET", "/api/state")[2])
        assert state["settings"]["free"] == ["offset"] and state["settings"]["free_from_file"]
        _, state = post(server, "/api/settings", {"free": []})  # offset fixed
        assert state["settings"]["free"] == [] and not state["settings"]["free_from_file"]
        assert not {a["name"]: a for a in state["attrs"]}["offset"]["free"]
        status, answer = post(server, "/api/optimize", {})
        assert status == 422 and "no attr is free to search" in answer["error"]
        _, state = post(server, "/api/settings", {"free": None})  # the file's @Free again
        assert state["settings"]["free"] == ["offset"]


def test_seed_and_lot_rebuild_the_design_and_can_be_undone(stack_file):
    with serving(stack_file) as server:
        _, state = post(server, "/api/settings", {"lot": [2, 1], "seed": 7})
        assert state["settings"]["lot"] == [2, 1] and state["settings"]["seed"] == 7
        assert state["settings"]["file_lot"] == [1, 1]
        assert block_volume(server) == pytest.approx(2.0)  # a unit-high block on a 2 x 1 lot
        # a polygon, counter-clockwise seen from above
        _, state = post(server, "/api/settings", {"lot": [[0, 0], [0, 2], [2, 2], [2, 0]]})
        assert block_volume(server) == pytest.approx(4.0)
        exported = json.loads(request(server, "GET", "/api/attrs.json")[2])
        command = exported["command"]
        assert "--seed 7" in command and "--lot '0,0 0,2 2,2 2,0'" in command
        _, state = post(server, "/api/undo")
        assert state["settings"]["lot"] == [2, 1] and block_volume(server) == pytest.approx(2.0)
        _, state = post(server, "/api/settings", {"lot": None})
        assert state["settings"]["lot"] is None and block_volume(server) == pytest.approx(1.0)


def test_every_change_of_the_settings_is_a_step_of_the_history(stack_file):
    with serving(stack_file) as server:
        start = json.loads(request(server, "GET", "/api/state")[2])
        _, state = post(server, "/api/attrs", {"offset": 0.3})
        _, state = post(server, "/api/settings", {"free": []})
        # fixing an attr neither rebuilds the design nor leaves it out of the history
        assert state["model_version"] == start["model_version"] + 1
        _, state = post(server, "/api/settings", {"margin": 0.4})
        _, state = post(server, "/api/settings", {"seed": 5})
        assert state["history"] == {"undo": 4, "redo": 0}
        steps = [(5, 0.4, []), (0, 0.4, []), (0, 0.1, []), (0, 0.1, ["offset"])]
        for seed, margin, free in steps[1:]:
            _, state = post(server, "/api/undo")
            settings = state["settings"]
            assert (settings["seed"], settings["margin"], settings["free"]) == (seed, margin, free)
        assert state["settings"]["free_from_file"] and state["history"]["redo"] == 3
        offset = {a["name"]: a for a in state["attrs"]}["offset"]
        assert offset["value"] == 0.3 and offset["free"]  # the attr's change is the next undo
        _, state = post(server, "/api/undo")
        assert {a["name"]: a["value"] for a in state["attrs"]}["offset"] == 0.2
        for seed, margin, free in [(0, 0.1, ["offset"]), *reversed(steps)]:
            settings = state["settings"]
            assert (settings["seed"], settings["margin"], settings["free"]) == (seed, margin, free)
            if seed == 5:
                break
            _, state = post(server, "/api/redo")
        assert state["history"] == {"undo": 4, "redo": 0}
        # the same settings again change nothing and are no step
        _, state = post(server, "/api/settings", {"margin": 0.4, "seed": 5})
        assert state["history"] == {"undo": 4, "redo": 0}


@pytest.mark.parametrize(
    ("body", "status", "message"),
    [
        ({}, 400, 'send a JSON object with any of "free", "margin", "seed", "lot"'),
        ([1], 400, "send a JSON object"),
        ({"margins": 0.1}, 400, "the settings are free, margin, seed and lot; got 'margins'"),
        ({"margin": 1}, 400, '"margin": margin must be at least 0 and below 1; got 1'),
        ({"margin": -0.1}, 400, '"margin": margin must be at least 0 and below 1'),
        ({"margin": True}, 400, '"margin": margin must be a number'),
        ({"seed": 1.5}, 400, '"seed" is a whole number'),
        ({"seed": -1}, 400, '"seed" is a whole number'),
        ({"free": "offset"}, 400, '"free" is a list of attr names'),
        ({"free": ["ofset"]}, 400, "the grammar has no attr 'ofset'"),
        ({"free": ["stone"]}, 400, "attr 'stone' cannot be free: the search varies numbers"),
        ({"free": ["courses"]}, 400, "attr 'courses' cannot be free"),  # no @Range
        # every lot refusal is the one lot check's line behind "lot": (model/lot.py), a 422
        ({"lot": [0, 1]}, 422, '"lot": lot width and depth must be finite numbers > 0 m, got 0'),
        ({"lot": [1]}, 422, '"lot": a lot is (width, depth) in metres or a polygon of 3 or more'),
        ({"lot": "12,8"}, 422, '"lot": a lot is (width, depth) in metres'),
        ({"lot": [[0, 0], [1, 0]]}, 422, '"lot": a lot needs at least 3 distinct corners, got 2'),
        ({"lot": [[0, 0], [2, 2], [2, 0], [0, 2]]}, 422, '"lot": the polygon crosses itself'),
        # numbers whose squares overflow, and a lot too small for its corners to stay apart
        ({"lot": [[0, 0], [1e308, 0], [1e308, 1e308], [0, 1e308]]}, 422, "within 1e+09 m"),
        ({"lot": [[0, 0], [0, 1e10], [1e10, 1e10], [1e10, 0]]}, 422, "within 1e+09 m"),
        ({"lot": [1e308, 1e308]}, 422, "width and depth must be at most 1e+09 m"),
        (
            {"lot": [[1, 0], [1, 2e-9], [1 + 2e-9, 2e-9], [1 + 2e-9, 0]]},
            422,
            '"lot": a lot needs at least 3 distinct corners, got 1',
        ),
    ],
)
def test_bad_settings_are_refused_and_change_nothing(stack_file, capfd, body, status, message):
    with serving(stack_file) as server:
        before = json.loads(request(server, "GET", "/api/state")[2])
        got, answer = post(server, "/api/settings", body)
        assert got == status and message in answer["error"], answer
        after = json.loads(request(server, "GET", "/api/state")[2])
        assert after["settings"] == before["settings"]
        assert after["model_version"] == before["model_version"]
    assert "Traceback" not in capfd.readouterr().err


def test_settings_are_closed_to_other_sites(stack_file):
    with serving(stack_file) as server:
        got = request(server, "POST", "/api/settings", {"seed": 3}, {"Origin": "null"})[0]
        assert got == 403
        got = request(server, "POST", "/api/settings", b'{"seed": 3}', {"Content-Type": None})[0]
        assert got == 415
        assert json.loads(request(server, "GET", "/api/state")[2])["settings"]["seed"] == 0

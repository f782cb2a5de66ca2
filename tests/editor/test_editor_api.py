"""The JSON API over HTTP, without a browser: answers, and a 4xx for every bad request."""

import json
import struct
import threading

import pytest
from editor_http import request, serving, serving_stack
from editor_stack import WAIT_BOUND_S

from shapegen.editor.server import MAX_BODY


@pytest.fixture(scope="module")
def server(tmp_path_factory):
    with serving_stack(tmp_path_factory.mktemp("api")) as server:
        yield server


def test_state_then_a_change_then_the_new_state(server):
    status, kind, content = request(server, "GET", "/api/state")
    state = json.loads(content)
    assert status == 200 and kind == "application/json"
    assert state["verdict"]["stands"] and state["grammar"]["name"] == "stack.grammar"
    names = [a["name"] for a in state["attrs"]]
    assert names == ["offset", "stone", "mortar", "courses"]
    assert set(state["timings"]) >= {"update_s", "analysis_s"}
    status, _, content = request(server, "POST", "/api/attrs", {"offset": 0.75})
    changed = json.loads(content)
    assert status == 200 and not changed["verdict"]["stands"]
    assert changed["model_version"] == state["model_version"] + 1
    assert json.loads(request(server, "GET", "/api/state")[2])["verdict"]["stands"] is False
    request(server, "POST", "/api/attrs", {"offset": 0.2})


def test_the_model_and_the_scene(server):
    status, kind, content = request(server, "GET", "/api/model.glb")
    assert status == 200 and kind == "model/gltf-binary"
    magic, version, length = struct.unpack("<4sII", content[:12])
    assert magic == b"glTF" and version == 2 and length == len(content)
    scene = json.loads(request(server, "GET", "/api/scene")[2])
    assert [b["id"] for b in scene["blocks"]] == ["b0", "b1"]


def test_optimize_over_http(server):
    request(server, "POST", "/api/attrs", {"offset": 0.8})
    status, _, content = request(server, "POST", "/api/optimize", {"objective": "energy"})
    state = json.loads(content)
    assert status == 200 and state["verdict"]["stands"]
    assert request(server, "POST", "/api/cancel")[0] == 200
    request(server, "POST", "/api/attrs", {"offset": 0.2})


@pytest.mark.parametrize(
    ("method", "path", "body", "status", "message"),
    [
        ("POST", "/api/attrs", {"ofset": 1}, 400, "no attr 'ofset'; did you mean 'offset'?"),
        ("POST", "/api/attrs", {"offset": "abc"}, 400, "takes a number; got 'abc'"),
        ("POST", "/api/attrs", b'{"offset": 0.1', 400, "the body is not valid JSON"),
        ("POST", "/api/attrs", b'{"offset": NaN}', 400, "NaN is not a JSON number"),
        ("POST", "/api/attrs", b"\xff\xfe", 400, "the body is not UTF-8 text (byte 0 is 0xff)"),
        ("POST", "/api/attrs", None, 400, "send a JSON object"),
        ("POST", "/api/attrs", [1, 2], 400, "send a JSON object"),
        ("GET", "/api/attrs", None, 405, "/api/attrs takes POST, not GET"),
        ("POST", "/api/state", {}, 405, "/api/state takes GET, not POST"),
        ("DELETE", "/api/state", None, 405, "takes GET, not DELETE"),
        ("PUT", "/api/attrs", {"offset": 0.1}, 405, "takes POST, not PUT"),
        ("OPTIONS", "/api/state", None, 405, "takes GET, not OPTIONS"),
        ("BREW", "/api/state", None, 405, "no address takes BREW"),
        ("POST", "/", None, 405, "takes GET, not POST"),
        ("GET", "/api/nothing", None, 404, "no such address: /api/nothing"),
        ("GET", "/static/../session.py", None, 404, "no such file"),
        ("GET", "/static/vendor/../../session.py", None, 404, "no such file"),
        ("GET", "/static/missing.js", None, 404, "no such file"),
        ("POST", "/api/optimize", {"objective": "fast"}, 400, "objective must be one of"),
    ],
)
def test_bad_requests_get_a_4xx_with_a_message(server, method, path, body, status, message):
    got, kind, content = request(server, method, path, body)
    assert got == status and kind == "application/json"
    assert message in json.loads(content)["error"]


def test_a_huge_body_is_refused_unread(server):
    got, _, content = request(server, "POST", "/api/attrs", b" " * (MAX_BODY + 1))
    assert got == 413 and "at most" in json.loads(content)["error"]


def test_a_foreign_host_is_refused(server):
    got, _, content = request(server, "GET", "/api/state", headers={"Host": "evil.example"})
    assert got == 403


def test_the_server_still_answers_after_the_bad_requests(server):
    assert request(server, "GET", "/api/state")[0] == 200


def test_the_page_and_every_script_it_needs_are_served_by_the_package(server):
    status, kind, page = request(server, "GET", "/")
    assert status == 200 and kind.startswith("text/html")
    text = page.decode()
    assert "http://" not in text.replace("http://www.w3.org", "") and "https://" not in text
    scripts = [
        "/static/editor.js",
        "/static/editor.css",
        "/static/vendor/three/three.module.js",
        "/static/vendor/three/three.core.js",
        "/static/vendor/three/addons/controls/OrbitControls.js",
        "/static/vendor/three/addons/loaders/GLTFLoader.js",
        "/static/vendor/three/addons/utils/BufferGeometryUtils.js",
        "/static/vendor/three/addons/utils/SkeletonUtils.js",
        "/static/vendor/three/LICENSE",
    ]
    for path in scripts:
        status, kind, content = request(server, "GET", path)
        assert status == 200 and content, path
    assert request(server, "GET", "/static/editor.js")[1].startswith("text/javascript")
    editor = request(server, "GET", "/static/editor.js")[2].decode()
    assert "http://" not in editor and "https://" not in editor


def test_a_reload_during_a_search_answers_at_once_and_happens_when_it_ends(stack_file):
    # The search is held in its first iteration until the reload has been answered: a reload
    # that waited for the search would wait forever (the request's 60 s timeout fails the test).
    with serving(stack_file) as server:
        session = server.session
        request(server, "POST", "/api/attrs", {"offset": 0.8})
        searching, held = threading.Event(), threading.Event()
        progress = session._progress

        def held_progress(record):
            searching.set()
            held.wait(300)
            progress(record)

        session._progress = held_progress
        answers = []
        search = threading.Thread(
            target=lambda: answers.append(request(server, "POST", "/api/optimize", {}))
        )
        search.start()
        try:
            assert searching.wait(WAIT_BOUND_S), "the search did not start"
            good = stack_file.read_text()
            stack_file.write_text(good.replace("attr courses = 2", "attr courses = 3"))
            status, _, content = request(server, "POST", "/api/reload")
            state = json.loads(content)
            assert status == 202 and state["reload_pending"] is True
            assert state["optimization"]["running"] is True
            assert {a["name"]: a["value"] for a in state["attrs"]}["courses"] == 2  # not yet
            status, _, content = request(server, "POST", "/api/attrs", {"offset": 0.1})
            assert status == 409 and "a search is running" in json.loads(content)["error"]
        finally:
            held.set()
            search.join(WAIT_BOUND_S)
        ((status, _, content),) = answers
        state = json.loads(content)
        values = {a["name"]: a["value"] for a in state["attrs"]}
        assert status == 200 and state["reload_pending"] is False and state["error"] is None
        assert values["courses"] == 3  # re-read once the search ended
        assert state["verdict"]["stands"] and values["offset"] <= 0.5 + 1e-6  # what it found


COUNTED = """\
@Description("Drums of the column")
@Range(1, 6)
attr drums = 3

@StartRule @Lot(1, 1)
Lot --> extrude(3) label("column") i("column", courses = drums)
"""


def test_a_count_steps_by_one_and_a_fraction_of_it_is_refused(tmp_path):
    path = tmp_path / "column.grammar"
    path.write_text(COUNTED, encoding="utf-8")
    with serving(path) as server:
        before = json.loads(request(server, "GET", "/api/state")[2])
        (drums,) = before["attrs"]
        assert drums["whole"] is True and drums["step"] == 1
        status, _, content = request(server, "POST", "/api/attrs", {"drums": 2.5})
        assert status == 422
        assert json.loads(content)["error"] == (
            "attr 'drums' is a count: it takes a whole number; got 2.5"
        )
        after = json.loads(request(server, "GET", "/api/state")[2])
        assert after["model_version"] == before["model_version"]
        assert after["grammar"]["blocks"] == before["grammar"]["blocks"]
        status, _, content = request(server, "POST", "/api/attrs", {"drums": 5})
        assert status == 200 and json.loads(content)["grammar"]["blocks"] == 5

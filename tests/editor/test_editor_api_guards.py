"""The API closed to other sites, and every malformed body refused: a 4xx, the design unchanged.

A web page elsewhere can make the browser send a request to 127.0.0.1 (a form, or ``fetch`` with
``mode: "no-cors"``) although it cannot read the answer; the browser then names that page in
``Origin`` and ``Sec-Fetch-Site``, and can send only a "simple" ``Content-Type`` (text/plain,
a form) without asking first.
"""

import json
import time
from pathlib import Path

import pytest
from editor_http import request, serving, serving_stack, state
from editor_stack import WAIT_BOUND_S

from shapegen.editor.server import MAX_BODY

PAGE = Path(__file__).resolve().parents[2] / "shapegen" / "editor" / "static" / "editor.js"
# the requests that change something, with a body each would be obeyed with
CHANGES = [
    ("/api/attrs", b'{"offset": 0.7}'),
    ("/api/optimize", b'{"objective": "energy"}'),
    ("/api/reload", b""),
    ("/api/cancel", b""),
]


@pytest.fixture(scope="module")
def server(tmp_path_factory):
    with serving_stack(tmp_path_factory.mktemp("guards")) as server:
        yield server


def own(server, host="127.0.0.1") -> str:
    return f"http://{host}:{server.server_address[1]}"


def unchanged(before: dict, after: dict) -> bool:
    keys = ("version", "model_version", "attrs", "verdict", "optimization", "reload_pending")
    return all(before.get(key) == after.get(key) for key in keys)


@pytest.mark.parametrize(("path", "body"), CHANGES)
@pytest.mark.parametrize(
    "headers",
    [
        # the attack as a page elsewhere writes it: fetch(url, {method: "POST", mode: "no-cors",
        # body: '{"angle": 88.8}'}) sends text/plain with the page's origin
        {"Origin": "http://evil.example", "Content-Type": "text/plain;charset=UTF-8"},
        {"Origin": "http://evil.example", "Sec-Fetch-Site": "cross-site"},
        {"Origin": "null"},  # a file:// page or a sandboxed frame
        {"Origin": "http://127.0.0.1:1"},  # another program's page on this machine
        {"Origin": "http://127.0.0.1.evil.example"},
        {"Sec-Fetch-Site": "cross-site"},  # a browser that names the site but not the origin
        {"Sec-Fetch-Site": "same-site"},  # another port of 127.0.0.1
    ],
)
def test_a_page_elsewhere_cannot_change_the_design(server, path, body, headers):
    before = state(server)
    status, kind, content = request(server, "POST", path, body, headers)
    assert status == 403 and kind == "application/json"
    assert "may not change the design" in json.loads(content)["error"]
    assert unchanged(before, state(server))


@pytest.mark.parametrize(("path", "body"), CHANGES)
@pytest.mark.parametrize(
    "kind",
    [
        "text/plain",
        "text/plain;charset=UTF-8",
        "application/x-www-form-urlencoded",
        "multipart/form-data; boundary=x",
        None,
        "application/json; charset=latin-1",
        "application/jsonp",
    ],
)
def test_only_a_json_request_changes_the_design(server, path, body, kind):
    before = state(server)
    headers = {"Origin": own(server), "Content-Type": kind}
    status, _, content = request(server, "POST", path, body, headers)
    assert status == 415
    assert "Content-Type: application/json" in json.loads(content)["error"]
    assert unchanged(before, state(server))


@pytest.mark.parametrize(
    "headers",
    [
        {"Origin": "{own}", "Sec-Fetch-Site": "same-origin"},  # the page, as a browser sends it
        {"Origin": "{localhost}", "Sec-Fetch-Site": "same-origin"},  # opened as localhost
        {"Content-Type": "application/json; charset=utf-8"},
        {},  # a script: no Origin, no Sec-Fetch-Site
    ],
)
def test_the_page_itself_and_scripts_may_change_it(server, headers):
    mine = {"{own}": own(server), "{localhost}": own(server, "localhost")}
    headers = {key: mine.get(value, value) for key, value in headers.items()}
    status, _, content = request(server, "POST", "/api/attrs", {"offset": 0.3}, headers)
    assert status == 200, content
    assert {a["name"]: a["value"] for a in json.loads(content)["attrs"]}["offset"] == 0.3
    request(server, "POST", "/api/attrs", {"offset": 0.2})


def test_reading_stays_open_but_gives_other_sites_nothing_to_read(server):
    status, _, _, headers = request(
        server, "GET", "/api/state", headers={"Origin": "http://evil.example"}, answer_headers=True
    )
    assert status == 200
    assert not any(name.lower().startswith("access-control-") for name in headers)


def test_the_page_sends_its_changes_as_json():
    # every change the page makes goes through one post(), which says it sends JSON (a page
    # that sent text/plain would be refused with 415: the browser tests drive it)
    script = PAGE.read_text(encoding="utf-8")
    assert script.count("method: 'POST'") == 1
    start = script.index("function post(")
    post = script[start : script.index("\n}\n", start)]
    assert "method: 'POST'" in post and "'Content-Type': 'application/json'" in post
    assert "fetch(" not in script.replace("await fetch(url, options)", "")


DEEP = 30_000
MALFORMED = [
    (b'{"offset": 1' + b"0" * 400 + b"}", "(401 digits) is too large"),
    (b'{"offset": 1e400}', "the number '1e400' is too large"),
    (b'{"offset": -1e400}', "is too large"),
    (b"[" * DEEP + b"]" * DEEP, "nests too deeply"),
    (b'{"a":' * 10_000 + b"1" + b"}" * 10_000, "nests too deeply"),
    (b'{"offset": NaN}', "NaN is not a JSON number"),
    (b'{"offset": Infinity}', "Infinity is not a JSON number"),
    (b'{"offset": -Infinity}', "-Infinity is not a JSON number"),
    (b"\xff\xfe{}", "the body is not UTF-8 text (byte 0 is 0xff)"),
    (b'{"stone": "\xed\xa0\x80"}', "the body is not UTF-8 text"),
    (b'{"offset": 0.1', "the body is not valid JSON"),
    (b'{"offset": 0.1}{"offset": 0.7}', "the body is not valid JSON: Extra data"),
    (b'{"offset": 0.1,}', "the body is not valid JSON"),
    (b"[0.7]", "send a JSON object"),
    (b'"offset=0.7"', "send a JSON object"),
    (b"0.7", "send a JSON object"),
    (b"null", "send a JSON object"),
    (b"", "send a JSON object"),
    (b"{}", "no attr values given"),
    (b'{"offset": "0.7"}', "takes a number"),
    (b" " * (MAX_BODY + 1), "at most 65536 are accepted"),
]


@pytest.mark.parametrize(("body", "message"), MALFORMED, ids=range(len(MALFORMED)))
def test_a_malformed_body_is_a_4xx_in_one_line_and_changes_nothing(server, capfd, body, message):
    before = state(server)
    status, kind, content = request(server, "POST", "/api/attrs", body)
    error = json.loads(content)["error"]
    assert 400 <= status < 500 and kind == "application/json"
    assert message in error and "\n" not in error and len(error) < 200
    assert unchanged(before, state(server))
    assert "Traceback" not in capfd.readouterr().err


@pytest.mark.parametrize(
    ("path", "body", "message"),
    [
        ("/api/optimize", b"[" * DEEP + b"]" * DEEP, "nests too deeply"),
        ("/api/optimize", b'{"objective": NaN}', "NaN is not a JSON number"),
        ("/api/optimize", b"[1]", "send a JSON object"),
        ("/api/reload", b'{"a":' * 10_000 + b"1" + b"}" * 10_000, "nests too deeply"),
    ],
)
def test_other_changes_refuse_a_malformed_body_too(server, capfd, path, body, message):
    before = state(server)
    status, _, content = request(server, "POST", path, body)
    assert 400 <= status < 500 and message in json.loads(content)["error"]
    assert unchanged(before, state(server))
    assert "Traceback" not in capfd.readouterr().err


@pytest.mark.parametrize("length", ["abc", "-1", "1e3"])
def test_a_bad_content_length_is_a_400(server, length):
    before = state(server)
    headers = {"Content-Length": length}
    status, _, content = request(server, "POST", "/api/attrs", b'{"offset": 0.7}', headers)
    assert status == 400 and "bad Content-Length" in json.loads(content)["error"]
    assert unchanged(before, state(server))


def _idle_connections(server, count: int) -> list:
    import socket

    return [
        socket.create_connection(("127.0.0.1", server.server_address[1]), timeout=30)
        for _ in range(count)
    ]


def test_an_idle_connection_is_closed(stack_file, monkeypatch):
    from shapegen.editor import server as editor_server

    monkeypatch.setattr(editor_server._ApiHandler, "timeout", 0.3)
    with serving(stack_file) as server:
        (idle,) = _idle_connections(server, 1)
        idle.sendall(b"GET /api/state HTTP/1.1\r\n")  # half a request, then nothing
        assert idle.recv(1024) == b""  # the server hung up, without a word, well before 30 s
        idle.close()
        assert request(server, "GET", "/api/state")[0] == 200


def test_connections_over_the_cap_are_a_503_and_the_page_answers_when_they_close(
    stack_file, monkeypatch, capfd
):
    from shapegen.editor import server as editor_server

    monkeypatch.setattr(editor_server, "MAX_CONNECTIONS", 4)
    with serving(stack_file) as server:
        held = _idle_connections(server, 4)
        held[0].sendall(b"GET /api/state HTTP/1.1\r\nHost: 127.0.0.1\r\n\r\n")
        assert held[0].recv(16).startswith(b"HTTP/1.1 200")  # served: one of the 4
        status, _, content = request(server, "GET", "/api/state")
        assert status == 503 and "serving 4 connections" in json.loads(content)["error"]
        for connection in held:
            connection.close()
        # their threads notice the closed connections and end (the bound times nothing)
        deadline = time.monotonic() + WAIT_BOUND_S
        while server.connections and time.monotonic() < deadline:
            time.sleep(0.01)
        assert request(server, "GET", "/api/state")[0] == 200
    assert "Traceback" not in capfd.readouterr().err

"""Undo, redo and reset over the API, and the mark on the attrs the designer set: a value set on
the page never hides a new default saved in the file."""

import json

import pytest
from editor_http import request, serving


def values(state) -> dict:
    return {a["name"]: a["value"] for a in state["attrs"]}


def marked(state) -> set:
    return {a["name"] for a in state["attrs"] if a["user"]}


def post(server, path, body=None, query=""):
    status, _, content = request(server, "POST", path + query, {} if body is None else body)
    return status, json.loads(content)


def test_undo_and_redo_step_through_every_change(stack_file):
    with serving(stack_file) as server:
        _, state = post(server, "/api/attrs", {"offset": 0.3})
        _, state = post(server, "/api/attrs", {"stone": "granite", "courses": 3})
        assert state["history"] == {"undo": 2, "redo": 0}
        assert marked(state) == {"offset", "stone", "courses"}
        status, state = post(server, "/api/undo")
        assert status == 200 and state["history"] == {"undo": 1, "redo": 1}
        assert values(state)["stone"] == "limestone" and values(state)["offset"] == 0.3
        assert marked(state) == {"offset"}
        _, state = post(server, "/api/undo")
        assert values(state)["offset"] == 0.2 and marked(state) == set()
        status, state = post(server, "/api/undo")
        assert status == 409 and state["error"] == "nothing to undo"
        _, state = post(server, "/api/redo")
        _, state = post(server, "/api/redo")
        assert values(state)["stone"] == "granite" and values(state)["courses"] == 3
        assert state["history"] == {"undo": 2, "redo": 0}
        assert post(server, "/api/redo")[0] == 409
        # a new change after an undo drops the changes undone
        post(server, "/api/undo")
        _, state = post(server, "/api/attrs", {"mortar": True})
        assert state["history"] == {"undo": 2, "redo": 0}


def test_a_drag_is_one_step_of_the_history(stack_file):
    with serving(stack_file) as server:
        for offset in (0.25, 0.3, 0.35, 0.4):  # one drag: the page names it
            post(server, "/api/attrs", {"offset": offset}, "?gesture=drag-1")
        _, state = post(server, "/api/attrs", {"offset": 0.45}, "?gesture=drag-2")
        assert state["history"]["undo"] == 2
        _, state = post(server, "/api/undo")
        assert values(state)["offset"] == 0.4
        _, state = post(server, "/api/undo")
        assert values(state)["offset"] == 0.2


def test_reset_gives_back_the_rule_default_and_can_be_undone(stack_file):
    with serving(stack_file) as server:
        post(server, "/api/attrs", {"offset": 0.3, "stone": "granite"})
        _, state = post(server, "/api/reset", {"attrs": ["offset"]})
        assert values(state)["offset"] == 0.2 and marked(state) == {"stone"}
        _, state = post(server, "/api/reset", {})
        assert values(state)["stone"] == "limestone" and marked(state) == set()
        _, state = post(server, "/api/undo")
        assert marked(state) == {"stone"}
        _, state = post(server, "/api/undo")
        assert values(state)["offset"] == 0.3


def test_after_a_reload_an_untouched_attr_takes_the_new_default_and_a_set_one_stays(stack_file):
    with serving(stack_file) as server:
        post(server, "/api/attrs", {"stone": "granite"})
        text = stack_file.read_text()
        text = text.replace("attr offset = 0.2", "attr offset = 0.1")
        stack_file.write_text(text.replace('attr stone = "limestone"', 'attr stone = "marble"'))
        _, state = post(server, "/api/reload")
        attrs = {a["name"]: a for a in state["attrs"]}
        assert attrs["offset"]["value"] == 0.1 and not attrs["offset"]["user"]  # new default
        assert attrs["stone"]["value"] == "granite" and attrs["stone"]["user"]  # the designer's
        assert attrs["stone"]["default"] == "marble"  # and the page can say what it hides
        _, state = post(server, "/api/reset", {"attrs": ["stone"]})
        assert values(state)["stone"] == "marble"


@pytest.mark.parametrize(
    ("path", "body", "message"),
    [
        ("/api/reset", {"attrs": ["ofset"]}, "the grammar has no attr 'ofset'"),
        ("/api/reset", {"attrs": "offset"}, '"attrs" is a list of attr names'),
        ("/api/reset", {"names": []}, 'send {"attrs": ["name", ...]}'),
        ("/api/reset", [1], 'send {"attrs": ["name", ...]}'),
        ("/api/undo", {"offset": 1}, "/api/undo takes no values"),
        ("/api/redo", [], "/api/redo takes no values"),
    ],
)
def test_bad_history_requests_are_refused(stack_file, path, body, message):
    with serving(stack_file) as server:
        status, answer = post(server, path, body)
        assert status == 400 and message in answer["error"]


@pytest.mark.parametrize("path", ["/api/undo", "/api/redo", "/api/reset"])
def test_the_history_is_closed_to_other_sites_and_takes_only_json(stack_file, path):
    with serving(stack_file) as server:
        post(server, "/api/attrs", {"offset": 0.3})
        post(server, "/api/undo")  # one step each way, so that undo and redo could act
        foreign = {"Origin": "http://evil.example"}
        assert request(server, "POST", path, {}, foreign)[0] == 403
        assert request(server, "POST", path, {}, {"Sec-Fetch-Site": "cross-site"})[0] == 403
        assert request(server, "POST", path, b"{}", {"Content-Type": "text/plain"})[0] == 415
        assert request(server, "GET", path)[0] == 405
        state = json.loads(request(server, "GET", "/api/state")[2])
        assert state["history"] == {"undo": 0, "redo": 1} and values(state)["offset"] == 0.2

"""The editor's session: changes through the pipeline, search, reload, the scene's forces."""

import numpy as np
import pytest
from editor_stack import STACK_BOUNDARY, STACK_WEIGHT, WAIT_BOUND_S, scanned

from shapegen.editor import EditorSession, RequestError
from shapegen.limits import work_limits
from shapegen.search.defaults import DEFAULT_MARGIN


@pytest.fixture
def session(stack_file):
    session = EditorSession(str(stack_file), scan=False)
    yield session
    session.close()


def verdict(state):
    return state["verdict"]["stands"]


def test_a_change_rebuilds_and_judges_the_design(session):
    state = session.state()
    assert verdict(state) and state["grammar"]["blocks"] == 2
    assert state["verdict"]["measure_name"] == "y/W²"
    # what the page says of a design that fails, and whether it colours tension, come from
    # the structure, not from its name
    assert state["verdict"]["fails_as"] == "needs tension" and state["grammar"]["judges_blocks"]
    assert state["verdict"]["judged"] and state["verdict"]["status"] == "optimal"
    before = state["model_version"]
    state = session.set_attrs({"offset": 0.7})
    assert not verdict(state)
    assert state["verdict"]["measure"] > 0 and state["verdict"]["max_tension"] > 0
    assert state["model_version"] == before + 1
    assert {a["name"]: a["value"] for a in state["attrs"]}["offset"] == 0.7
    assert state["timings"]["update_s"] > 0
    # either side of the closed-form boundary
    assert verdict(session.set_attrs({"offset": STACK_BOUNDARY - 0.01}))
    assert not verdict(session.set_attrs({"offset": STACK_BOUNDARY + 0.01}))


def test_a_request_past_its_clock_is_refused_and_the_design_kept(session):
    # one clock over the request's derivation and judging (shapegen.limits.work_clock), named
    before = session.state()
    with work_limits(max_seconds=1e-9), pytest.raises(RequestError) as refused:
        session.set_attrs({"offset": 0.7})
    assert refused.value.status == 422
    assert "the page's request" in str(refused.value) and "max_seconds" in str(refused.value)
    assert session.state()["model_version"] == before["model_version"]


def test_a_refused_change_leaves_the_design_alone(session):
    before = session.state()
    with pytest.raises(RequestError, match="takes a number"):
        session.set_attrs({"offset": "wide"})
    after = session.state()
    assert after["model_version"] == before["model_version"]
    assert after["attrs"] == before["attrs"]


def test_optimize_ends_on_a_standing_design(session):
    session.set_attrs({"offset": 0.8})
    state = session.optimize({"objective": "energy"})
    offset = {a["name"]: a["value"] for a in state["attrs"]}["offset"]
    assert verdict(state) and offset <= STACK_BOUNDARY + 1e-6
    assert state["optimization"]["running"] is False and state["optimization"]["stands"]
    assert state["optimization"]["iteration"] >= 1


@pytest.mark.slow  # about 40 evaluations: 3-5 s
def test_closest_snaps_to_the_boundary(session):
    session.set_attrs({"offset": 0.8})
    state = session.optimize({"objective": "closest"})
    offset = {a["name"]: a["value"] for a in state["attrs"]}["offset"]
    # The nearest design that stands with the default reserve: every joint shrunk about its
    # centroid to (1 - m) of its width, the overlap 1 - d must hold the upper centroid at d + 0.5,
    # so d <= (1 - m) / (2 - m) (0.5 at m = 0, 0.4737 at the default 0.1).
    boundary = (1 - DEFAULT_MARGIN) / (2 - DEFAULT_MARGIN)
    assert verdict(state) and offset == pytest.approx(boundary, abs=0.02)
    assert offset < STACK_BOUNDARY


@pytest.mark.parametrize(
    ("payload", "message"),
    [
        ({"objective": "fastest"}, "objective must be one of energy, closest"),
        ({"objectve": "energy"}, "optimize takes only 'objective'"),
        ([1], "send a JSON object"),
    ],
)
def test_bad_search_requests(session, payload, message):
    with pytest.raises(RequestError, match=message):
        session.optimize(payload)


def test_a_grammar_error_keeps_the_last_good_design(session, stack_file):
    good = stack_file.read_text()
    session.set_attrs({"offset": 0.3})
    version = session.state()["model_version"]
    stack_file.write_text(good.replace("attr offset = 0.2", "attr offset = 0.2 +"))
    state = session.reload()
    error = state["error"]
    assert error["file"].endswith("stack.grammar") and error["line"] == 6  # the next token
    assert error["column"] >= 1 and "^" in error["text"]
    assert state["model_version"] == version and verdict(state)
    # fixed: the designer's value is kept, a new default is taken
    stack_file.write_text(good.replace("@Range(0, 0.9)", "@Range(0, 0.8)").replace(
        'attr courses = 2', 'attr courses = 3'))  # fmt: skip
    state = session.reload()
    assert state["error"] is None and state["model_version"] == version + 1
    values = {a["name"]: a["value"] for a in state["attrs"]}
    assert values["offset"] == 0.3 and values["courses"] == 3
    assert {a["name"]: a["maximum"] for a in state["attrs"]}["offset"] == 0.8


def test_the_ground_reactions_carry_the_weight(session):
    scene = session.scene()
    forces = scene["forces"]
    ground = np.array(forces["ground"])
    joints = np.array(forces["joints"])
    assert len(ground) >= 1 and len(joints) >= 1
    # the supports push up on the structure with its whole weight; the joint carries the top cube
    assert ground[:, 4].sum() == pytest.approx(STACK_WEIGHT, rel=1e-6)
    assert np.abs(joints[:, 4]).sum() == pytest.approx(STACK_WEIGHT / 2, rel=1e-6)
    assert forces["metres_per_newton"] > 0
    # the top cube's load acts through its centroid: at x = offset + 0.5 on the joint
    assert joints[0, 0] == pytest.approx(0.2 + 0.5, abs=1e-6)


def test_the_scene_colours_blocks_by_label_and_by_tension(session):
    scene = session.scene()
    assert [b["label"] for b in scene["blocks"]] == ["lower", "upper"]
    assert [label for label, _ in scene["legend"]["labels"]] == ["lower", "upper"]
    grey = scene["legend"]["tension_zero"]
    assert all(b["tension_color"] == grey for b in scene["blocks"])  # it stands: no red
    session.set_attrs({"offset": 0.8})
    scene = session.scene()
    assert scene["legend"]["max_tension"] > 0
    assert any(b["tension_color"] == scene["legend"]["tension_max"] for b in scene["blocks"])
    assert scene["model_version"] == session.state()["model_version"]


def test_the_stable_interval_arrives_in_the_state(stack_file):
    session = EditorSession(str(stack_file))
    try:
        state = session.wait_for(scanned("offset"), timeout=WAIT_BOUND_S)
        stability = state["stability"]["offset"]
        ((low, high),) = stability["intervals"]
        assert low == 0 and abs(high - STACK_BOUNDARY) <= stability["resolution"] + 1e-9
    finally:
        session.close()


def test_a_bridge_shows_its_cable_sizing():
    session = EditorSession("suspension_bridge.grammar", scan=False)
    try:
        state = session.state()
        sizing = session.report()["analysis"]
        assert state["grammar"]["structure"] == "cable"
        assert sizing["cable_diameter"] > 0 and sizing["allowed_diameter"] > 0
        fits = sizing["cable_diameter"] <= sizing["allowed_diameter"]
        assert state["verdict"]["stands"] == fits
        assert state["verdict"]["fails_as"] == "cables too thick"
        assert not state["grammar"]["judges_blocks"]
        # the panel is the structure's, in its words: the page knows no cable
        panel = state["panel"]
        rows = dict(panel["rows"])
        assert panel["title"] == "Cable sizing"
        assert rows["cable diameter"] == f"{sizing['cable_diameter'] * 1000:.0f} mm"
        assert rows["main span"] == f"{sizing['main_span']:.1f} m"
        assert "cables" in state["grammar"]["judged_by"]
        assert session.scene()["forces"] is None
    finally:
        session.close()

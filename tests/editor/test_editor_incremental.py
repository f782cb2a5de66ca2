"""A change on the page is judged from the last design (shapegen/statics/incremental.py): the
answers are those of a session that judges every design from scratch; with the measure
following (``shapegen edit``), a design proven not to stand is answered with its verdict and
its measure follows as a new model version."""

from __future__ import annotations

import pytest
from editor_stack import STACK_BOUNDARY

from shapegen.editor import EditorSession


@pytest.fixture
def sessions(stack_file):
    opened = [
        EditorSession(str(stack_file), scan=False),
        EditorSession(str(stack_file), scan=False, measure_follows=True),
    ]
    yield opened
    for session in opened:
        session.close()


def fresh(stack_file, offset: float) -> dict:
    session = EditorSession(str(stack_file), attrs={"offset": offset}, scan=False)
    try:
        return session.state()["verdict"]
    finally:
        session.close()


OFFSETS = [0.3, 0.35, 0.7, 0.72, 0.75, STACK_BOUNDARY + 0.01, STACK_BOUNDARY - 0.01, 0.2]


def test_answers_equal_those_judged_from_scratch(sessions, stack_file):
    plain, follows = sessions
    pending = 0
    for offset in OFFSETS:
        expected = fresh(stack_file, offset)
        state = plain.set_attrs({"offset": offset})
        assert not state["verdict"]["pending"]
        assert state["verdict"]["stands"] == expected["stands"]
        assert state["verdict"]["measure"] == pytest.approx(expected["measure"], abs=1e-9)
        answer = follows.set_attrs({"offset": offset})
        assert answer["verdict"]["stands"] == expected["stands"]
        if answer["verdict"]["pending"]:
            pending += 1
            assert not answer["verdict"]["stands"]
            assert answer["verdict"]["measure"] is None and answer["verdict"]["max_tension"] is None
            version = answer["model_version"]
            scene = follows.scene()  # waits for the measure and the forces
            state = follows.state()
            assert not state["verdict"]["pending"]
            assert state["model_version"] == scene["model_version"] == version + 1
            assert scene["legend"]["max_tension"] > 0
            assert follows.report()["analysis"]["measure"] == state["verdict"]["measure"]
        else:
            state = answer
        assert state["verdict"]["measure"] == pytest.approx(expected["measure"], rel=1e-4, abs=1e-9)
    assert pending >= 2  # 0.72 and 0.75 follow 0.7, which needed tension


def test_a_block_of_a_pending_design_waits_for_its_forces(sessions):
    _, follows = sessions
    follows.set_attrs({"offset": 0.7})
    answer = follows.set_attrs({"offset": 0.74})
    assert answer["verdict"]["pending"]
    block = follows.block("b1")
    assert block["tension"] > 0 and all(j["force"] is not None for j in block["joints"])

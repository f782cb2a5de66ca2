"""The back-end contract: each back-end declares what it honours of a solve request, and the
exact cone is refused in one wording."""

import subprocess
import sys
from dataclasses import fields

import numpy as np
import pytest

from shapegen.errors import OptionError
from shapegen.statics.solvers import BACKENDS, SolveRequest, cone_refusal
from shapegen.statics.statics_options import StaticsOptions

REQUEST = SolveRequest(stop_above=1.0, accept=bool, screen_above=2.0, warm_start=np.zeros(4))


@pytest.mark.parametrize("name", list(BACKENDS))
def test_a_backend_takes_only_what_it_declares(name):
    backend = BACKENDS[name]()
    assert backend.honours <= {f.name for f in fields(SolveRequest)}
    assert backend.take(REQUEST) is backend
    for field in fields(SolveRequest):
        taken = getattr(backend, field.name, None)
        if field.name in backend.honours:
            assert taken is getattr(REQUEST, field.name)
        else:
            assert taken is None


def test_the_reduced_backend_honours_every_shortcut():
    assert BACKENDS["reduced"].honours == {f.name for f in fields(SolveRequest)}


def test_the_cone_refusal_has_one_wording(monkeypatch):
    # every bundled back-end takes cones: a back-end of linear rows only is one whose class
    # says not, and the options read it there
    monkeypatch.setattr(BACKENDS["reduced"], "second_order_cones", False)
    with pytest.raises(OptionError) as refused:
        StaticsOptions(pyramid="cone", solver="reduced")
    assert str(refused.value) == cone_refusal("reduced")
    assert cone_refusal("reduced").endswith("needs solver auto, clarabel or cvxpy")


def test_checking_options_loads_no_solver_library():
    # the default options (the exact cone) read what the back-ends' classes declare without
    # importing a solver's library: scipy.sparse.linalg would cost a plain build 0.2-0.4 s of
    # start-up
    code = (
        "import sys; from shapegen.statics.statics_options import StaticsOptions; StaticsOptions();"
        " StaticsOptions(pyramid='cone', solver='reduced');"
        " print(sorted(m for m in ('scipy', 'scipy.sparse', 'clarabel', 'cvxpy', 'cvxopt', 'qdldl',"
        " 'shapegen.statics.solvers.normal_equations', 'shapegen.statics.solvers.reduced_kkt')"
        " if m in sys.modules))"
    )
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert done.stdout.strip() == "[]", done.stdout

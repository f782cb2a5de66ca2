"""Tolerances live in shapegen/tolerances.py and are compared through its predicates.

The predicates keep the comparison they name (inclusive or strict) for scalars and arrays
alike, and no module but tolerances.py writes a bare tolerance: a float literal between 0 and
1e-5 (1e-6 ... 1e-15, the 1e-300 floor) is refused anywhere else, but for the solver settings
below, each a named constant beside the algorithm it tunes.
"""

import ast
import math
from pathlib import Path

import numpy as np
import pytest

from shapegen import tolerances
from shapegen.tolerances import (
    ROUNDOFF_REL,
    ZERO_LENGTH,
    are_close,
    are_positive,
    are_zero,
    at_least,
    at_most,
    is_close,
    is_negative,
    is_positive,
    is_zero,
)

PACKAGE = Path(__file__).resolve().parents[1] / "shapegen"
SMALLEST_PLAIN = 1e-5  # a float literal below this is a tolerance

# Module-level constants that may be bare: settings of a numerical method, not comparisons.
SOLVER_SETTINGS = {
    "geometry/inner_rectangle.py": {"RECTANGLE_FTOL"},  # SLSQP's ftol for the inscribed rectangle
    "search/methods.py": {"POWELL_FTOL", "SLSQP_FTOL", "POLISH_FTOL"},  # the search's stops
    "search/evaluator.py": {"ADJOINT_STEP"},  # the finite-difference step of a gradient check
    "statics/assembly.py": {"REGULARIZATION"},  # Tikhonov term of the block QP
    "statics/carried.py": {"CORRECTION_REGULARIZATION"},  # of the carried forces' correction
    "statics/cables.py": {"_HALF_ANGLE_XTOL"},  # brentq's tolerance on a cable's half angle
    "statics/solvers/clarabel_direct.py": {"TOLERANCE", "KKT_RATIO"},  # clarabel's settings
    "statics/solvers/cvxpy_reference.py": {"TOLERANCE"},  # cvxpy's back-end tolerance
    # the interior-point method's stopping rules, steps and floors, with why each is that size
    "statics/solvers/reduced.py": {
        "_GAP_REL",
        "_FAIR_GAP_REL",
        "_MIN_STEP",
        "_NEGLIGIBLE_HESSIAN",
        "_FARKAS_REL",
        "_SCALE_FLOOR",
        "_TOLERANCE",
        "_ACCEPT_BELOW",
    },
    "statics/solvers/reduced_kkt.py": {"_EQUILIBRATION_SHIFT", "_NORMAL_SHIFT", "_REFINED"},
    "statics/solvers/least_norm.py": {"_SHIFT"},  # the least-norm forces' diagonal shift
}


# Modules whose bare tolerances are still to be named, and why not yet. A module here must still
# have one (so the list only shrinks); every other module has none.
STILL_BARE: dict[str, str] = {}


def _bare_tolerances(path: Path) -> list[str]:
    """``line: literal`` of every bare tolerance in the module at ``path``."""
    tree = ast.parse(path.read_text(encoding="utf-8"))
    allowed = SOLVER_SETTINGS.get(path.relative_to(PACKAGE).as_posix(), set())
    named = set()
    for node in tree.body:
        targets = node.targets if isinstance(node, ast.Assign) else [getattr(node, "target", None)]
        value = getattr(node, "value", None)
        if isinstance(value, ast.Constant) and any(
            isinstance(t, ast.Name) and t.id in allowed for t in targets
        ):
            named.add(id(value))
    return [
        f"{node.lineno}: {ast.get_source_segment(path.read_text(encoding='utf-8'), node)}"
        for node in ast.walk(tree)
        if isinstance(node, ast.Constant)
        and isinstance(node.value, float)
        and 0.0 < node.value < SMALLEST_PLAIN
        and id(node) not in named
    ]


MODULES = sorted(p for p in PACKAGE.rglob("*.py") if p.name != "tolerances.py")


@pytest.mark.parametrize("path", MODULES, ids=lambda p: p.relative_to(PACKAGE).as_posix())
def test_no_bare_tolerance_outside_tolerances_py(path):
    bare = _bare_tolerances(path)
    if path.relative_to(PACKAGE).as_posix() in STILL_BARE:
        assert bare, "all named: take the module off STILL_BARE"
    else:
        assert bare == [], "name it in shapegen/tolerances.py"


def test_still_bare_names_modules_that_are_there():
    assert all((PACKAGE / name).is_file() for name in STILL_BARE), STILL_BARE


def test_the_scan_finds_a_bare_tolerance(tmp_path, monkeypatch):
    module = PACKAGE / "geometry" / "mesh.py"  # any module: only its path is used for the key
    text = "X = 1e-9\n\ndef f(a):\n    return a > 1e-12 and a < 1e-300\n"
    monkeypatch.setattr(Path, "read_text", lambda self, encoding=None: text)
    assert [line.split(":")[0] for line in _bare_tolerances(module)] == ["1", "4", "4"]


def test_every_solver_setting_is_there():
    for name, constants in SOLVER_SETTINGS.items():
        module = ast.parse((PACKAGE / name).read_text(encoding="utf-8"))
        assigned = {
            t.id
            for node in module.body
            if isinstance(node, ast.Assign)
            for t in node.targets
            if isinstance(t, ast.Name)
        }
        assert constants <= assigned, (name, constants - assigned)


def test_each_tolerance_has_its_meaning_and_unit_written():
    text = Path(tolerances.__file__).read_text(encoding="utf-8")
    for name in tolerances.__all__:
        if name.isupper() and name != "DEFAULT":
            assert "#: " in text.split(f"\n{name} = ")[0].rsplit("\n\n", 1)[-1], name


@pytest.mark.parametrize(
    ("predicate", "args", "expected"),
    [
        (is_zero, (1e-15, ZERO_LENGTH), True),  # inclusive
        (is_zero, (-2e-15, ZERO_LENGTH), False),
        (is_close, (0.1 + 0.2, 0.3, ROUNDOFF_REL), True),
        (is_close, (1.0, 1.0 + 2e-12, ROUNDOFF_REL), False),
        (is_positive, (1e-15, ZERO_LENGTH), False),  # strict
        (is_positive, (2e-15, ZERO_LENGTH), True),
        (is_negative, (-1e-15, ZERO_LENGTH), False),  # strict
        (is_negative, (-2e-15, ZERO_LENGTH), True),
        (at_least, (1.0 - 1e-12, 1.0, 1e-12), True),  # inclusive
        (at_least, (1.0 - 2e-12, 1.0, 1e-12), False),
        (at_most, (1.0 + 1e-12, 1.0, 1e-12), True),
        (at_most, (1.0 + 2e-12, 1.0, 1e-12), False),
    ],
)
def test_predicates(predicate, args, expected):
    assert predicate(*args) is expected


def test_predicates_on_arrays_match_the_scalar_ones():
    values = np.array([-1.0, -1e-15, 0.0, 1e-15, 2e-15, math.inf])
    assert are_zero(values, ZERO_LENGTH).tolist() == [is_zero(v, ZERO_LENGTH) for v in values]
    assert are_positive(values, ZERO_LENGTH).tolist() == [
        is_positive(v, ZERO_LENGTH) for v in values
    ]
    assert are_close(values, 0.0, ZERO_LENGTH).tolist() == [
        is_close(v, 0.0, ZERO_LENGTH) for v in values
    ]

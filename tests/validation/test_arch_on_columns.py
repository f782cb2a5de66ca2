"""An arch on two columns (the seed paper's Figure 8), checked against hand limit analysis.

The arch (extrados radius ``Re = W / 2``, intrados ``Ri = Re - t``) springs from the tops of two
columns of width ``c`` and height ``h``. Per unit depth and unit weight density:

- The half arch weighs ``V = pi (Re^2 - Ri^2) / 4`` with its centroid at
  ``xg = 4 (Re^3 - Ri^3) / (3 pi (Re^2 - Ri^2))`` from the arch's axis. Moments about the
  springing point of the reaction, with the crown thrust ``H`` acting no higher than ``Re``, give
  ``H Re >= V (Ri - xg)``: a thrust of at least ``Hmin = V (Ri - xg) / Re`` pushes each column
  outwards at its top, and at most ``Hmax = V (Re - xg) / Ri`` is ever needed.
- A column tips outwards about its outer base edge unless ``H h <= V t + Wc c / 2`` (the arch
  presses down at most ``t`` in from that edge; ``Wc = c h`` is the column's weight).

So an arch thinner than Milankovitch's ``t / R = 0.1075`` falls whatever its columns, an arch
thicker than that falls on columns for which ``Hmin h > V t + Wc c / 2``, and stands on columns
for which ``Hmax h < Wc c / 2`` (at every course joint too: ``Hmax < c^2 / 2``) and whose
friction carries ``Hmax / V`` at every bed joint.
"""

import math

import pytest

from shapegen.model.model import Model
from shapegen.model.scope import Scope
from shapegen.primitives import insert
from shapegen.statics import analyze

SPAN = 4.0  # m, the arch scope's width: outer face to outer face of the springings
HEIGHT = 3.0  # m, columns
DEPTH = 1.0  # m
FRICTION = 1.0


def arch_on_columns(thickness: float, column_width: float) -> Model:
    blocks = []
    for x in (0.0, SPAN - column_width):
        scope = Scope.axis_aligned((x, 0.0, 0.0), (column_width, HEIGHT, DEPTH))
        blocks += insert("column", scope, courses=3)
    arch_scope = Scope.axis_aligned((0.0, HEIGHT, 0.0), (SPAN, SPAN / 2, DEPTH))
    blocks += insert("arch", arch_scope, thickness=thickness, segments=60)
    return Model(blocks, ground=0.0, friction=FRICTION)


def thrust_bounds(thickness: float) -> tuple[float, float, float]:
    """(V, Hmin, Hmax) per unit depth and unit weight density."""
    outer = SPAN / 2
    inner = outer - thickness
    weight = math.pi * (outer**2 - inner**2) / 4
    centroid = 4 * (outer**3 - inner**3) / (3 * math.pi * (outer**2 - inner**2))
    return weight, weight * (inner - centroid) / outer, weight * (outer - centroid) / inner


def column_holds(thrust: float, weight: float, thickness: float, width: float) -> bool:
    return thrust * HEIGHT <= weight * thickness + width * HEIGHT * width / 2


@pytest.mark.parametrize(
    "thickness, column_width, stands",
    [
        (0.18, 1.5, False),  # t / R = 0.094 < 0.1075: the arch itself cannot stand
        (0.25, 0.25, False),  # thick enough arch, columns too narrow for its thrust
        (0.25, 1.5, True),  # thick enough arch on wide columns
        (0.40, 1.5, True),
    ],
)
def test_arch_on_two_columns(thickness, column_width, stands):
    weight, least_thrust, most_thrust = thrust_bounds(thickness)
    ratio = thickness / (SPAN / 2 - thickness / 2)
    # The hand analysis decides every case with a margin.
    if stands:
        assert ratio > 0.1075 * 1.1
        assert column_holds(1.5 * most_thrust, 0.0, 0.0, column_width)
        assert most_thrust / weight < FRICTION / math.sqrt(2)
    elif ratio > 0.1075:
        assert not column_holds(1.5 * least_thrust, weight, thickness, column_width)
    assert analyze(arch_on_columns(thickness, column_width)).feasible is stands

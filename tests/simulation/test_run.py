"""simulate(): closed-form motions (free fall, a block sliding after a ground shake), removal,
settings and error messages."""

import builtins

import numpy as np
import pytest

from shapegen.errors import ShapegenError
from shapegen.model.block import Block
from shapegen.model.model import Model
from shapegen.simulation import (
    TOLERANCE,
    SimulationSettings,
    default_tolerance,
    remove_blocks,
    simulate,
)
from shapegen.simulation.world import load_pybullet

G = 9.81


def test_free_fall_without_ground_follows_g_t2_over_2():
    block = Block.box([0, 10, 0], [0.2, 10.2, 0.2], id="stone")
    model = Model([block], ground=None)
    result = simulate(model, seconds=1.0, settle=0.5)
    # Semi-implicit Euler: after n steps of dt the body fell g dt^2 n (n + 1) / 2.
    dt = result.settings.time_step
    n = round(1.0 / dt)
    fallen = G * dt**2 * n * (n + 1) / 2
    assert result.motions[0].displacement == pytest.approx(fallen, rel=1e-6)
    assert fallen == pytest.approx(G / 2, rel=2e-3)
    assert result.verdict == "collapses"


@pytest.mark.parametrize("friction", [0.4, 0.8])
def test_ground_shake_slides_a_flat_block_by_the_coulomb_distance(friction):
    # A wide flat slab cannot tip (its half width / centroid height is 10 > a / g = 6.1); in the
    # ground's frame it gets the velocity (a - mu g) tau at the end of the shake, then slides
    # to rest at deceleration mu g.
    shake, tau = 1.0, 1.0 / 60.0
    slab = Block.box([0, 0, 0], [1.0, 0.1, 1.0], id="slab")
    result = simulate(Model([slab], friction=friction), seconds=1.5, shake=shake, settle=0.2)
    a = shake / tau
    v1 = (a - friction * G) * tau
    slide = v1 * tau / 2 + v1**2 / (2 * friction * G)
    motion = result.motions[0]
    assert motion.max_displacement == pytest.approx(slide, rel=0.03)
    final = result.frames[-1]
    # The slab slides against the ground's motion (+x), i.e. towards -x, without turning.
    assert final.translations[0][0] < 0
    assert motion.rotation < 1e-3


def test_resting_stack_of_ten_does_not_creep():
    blocks = [Block.box([0, 0.2 * k, 0], [0.4, 0.2 * (k + 1), 0.3]) for k in range(10)]
    result = simulate(Model(blocks, friction=0.895), seconds=5.0)
    assert result.verdict == "stands"
    assert result.max_displacement < 0.5e-3
    assert result.settlement < 0.5e-3


def test_fixed_blocks_do_not_move_and_carry_the_rest():
    support = Block.box([0, 1, 0], [1, 1.2, 1], id="beam", fixed=True)
    stone = Block.box([0.3, 1.2, 0.3], [0.7, 1.4, 0.7], id="stone")
    result = simulate(Model([support, stone], ground=None), seconds=1.0)
    assert result.verdict == "stands"
    assert result.motions[0].displacement == 0.0


def test_removing_the_support_by_label_drops_the_block():
    post = Block.box([0, 0, 0], [0.3, 1.0, 0.3], id="post", tags=("column",))
    lintel = Block.box([-0.5, 1.0, 0], [0.2, 1.2, 0.3], id="lintel")
    prop = Block.box([-0.5, 0, 0], [-0.2, 1.0, 0.3], id="prop", tags=("column",))
    model = Model([post, lintel, prop])
    assert simulate(model, seconds=1.0).stands
    result = simulate(model, seconds=1.5, remove=["column"])
    assert result.removed == ["post", "prop"]
    assert [m.id for m in result.motions] == ["lintel"]
    assert result.motions[0].displacement == pytest.approx(1.0, abs=0.05)  # onto the ground


def test_remove_unknown_name_suggests_close_ones():
    model = Model([Block.box([0, 0, 0], [1, 1, 1], id="pier_1")])
    with pytest.raises(ShapegenError, match="did you mean 'pier_1'"):
        remove_blocks(model, ["pier_l"])


@pytest.mark.parametrize(
    "overrides, message",
    [
        ({"seconds": 0}, "seconds must be a positive"),
        ({"time_step": -1}, "time_step must be a positive"),
        ({"shake": -4}, "shake must be a number >= 0"),
        ({"settle": 5.0}, "settling window"),
        ({"friction": float("nan")}, "friction"),
        ({"solver_iterations": 0}, "solver_iterations"),
        ({"tolerance": 0.0}, "tolerance must be a positive"),
    ],
)
def test_bad_settings_raise_one_clear_error(overrides, message):
    model = Model([Block.box([0, 0, 0], [1, 1, 1])])
    with pytest.raises(ShapegenError, match=message):
        simulate(model, SimulationSettings(**overrides))


def test_missing_pybullet_says_how_to_install(monkeypatch):
    real_import = builtins.__import__

    def no_pybullet(name, *args, **kwargs):
        if name == "pybullet":
            raise ImportError("No module named 'pybullet'")
        return real_import(name, *args, **kwargs)

    monkeypatch.setattr(builtins, "__import__", no_pybullet)
    with pytest.raises(ShapegenError, match=r"shapegen\[sim\]"):
        load_pybullet()


def test_report_has_the_documented_keys():
    result = simulate(Model([Block.box([0, 0, 0], [1, 0.5, 1], id="a")]), seconds=1.0)
    report = result.to_report()
    for key in ("verdict", "max_displacement", "moved_blocks", "simulated_seconds",
                "wall_seconds", "tolerance", "settlement", "per_block"):  # fmt: skip
        assert key in report
    block = report["per_block"][0]
    assert block["id"] == "a" and set(block) >= {"displacement", "rotation", "moved"}
    assert np.isfinite(report["wall_seconds"])


def test_default_tolerance_is_a_millimetre_up_to_10_m_then_grows_with_the_height():
    def pier(bottom, top, ground=0.0):
        return Model([Block.box([0, bottom, 0], [1, top, 1])], ground=ground)

    assert TOLERANCE == 1e-3
    assert default_tolerance(pier(0, 1)) == pytest.approx(1e-3)
    assert default_tolerance(pier(0, 10)) == pytest.approx(1e-3)
    assert default_tolerance(pier(0, 25)) == pytest.approx(2.5e-3)
    # Measured from the ground, also when the model starts above it; without a ground, its extent.
    assert default_tolerance(pier(15, 25)) == pytest.approx(2.5e-3)
    assert default_tolerance(pier(15, 45, ground=None)) == pytest.approx(3e-3)


def test_simulate_fills_in_the_default_tolerance_and_keeps_a_given_one():
    tall = Model([Block.box([0, 0, 0], [4, 20, 4], id="pier")])
    assert simulate(tall, seconds=0.2, settle=0.1).settings.tolerance == pytest.approx(2e-3)
    given = simulate(tall, seconds=0.2, settle=0.1, tolerance=5e-4)
    assert given.settings.tolerance == 5e-4
    assert given.to_report()["tolerance"] == 5e-4

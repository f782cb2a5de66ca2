"""simulate(): closed-form motions (free fall, a block sliding after a ground shake), removal,
settings and error messages."""

import builtins

import numpy as np
import pytest

from shapegen.errors import ShapegenError
from shapegen.model.block import Block
from shapegen.model.model import Model
from shapegen.simulation import SimulationSettings, remove_blocks, simulate
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
    # ... at the speed g dt n, the largest sampled (every vertex moves alike: no spin).
    assert result.final_speed == pytest.approx(G * dt * n, rel=1e-6)
    assert result.peak_speed == pytest.approx(result.final_speed)
    track = result.displacement_over_time()
    assert track["time"][0] == 0.0 and track["time"][-1] == pytest.approx(1.0)
    assert len(track["time"]) == round(result.settings.sample_rate * 1.0) + 1
    assert np.all(np.diff(track["max_displacement"]) > 0)


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


@pytest.mark.parametrize(("friction", "stands"), [(0.0, False), (0.8, True)])
def test_a_block_gliding_without_friction_is_still_moving(friction, stands):
    # A 1.5 mm/s nudge: without friction the slab glides on at that speed, 1.7 % of its 0.1 m
    # thickness per quarter of the judged window (over the 1 % floor) and 6.75 % in all after
    # 4.5 s (under the 10 % fall bar); it has not stopped, so it does not stand. With friction
    # the nudge (0.09 m/s^2 < mu g) moves nothing.
    nudge = 1.5e-3  # m/s
    slab = Block.box([0, 0, 0], [1.0, 0.1, 1.0], id="slab")
    result = simulate(Model([slab], friction=friction), seconds=5.0, shake=nudge)
    (motion,) = result.motions
    assert result.stands == stands
    assert not motion.fell
    assert motion.still_moving == (not stands)
    if not stands:
        assert motion.max_displacement == pytest.approx(nudge * 4.5, rel=0.05)
        assert motion.tail_motion == pytest.approx(motion.earlier_motion, rel=0.05)
        assert "still moving" in result.explanation()


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
    for key in ("verdict", "explanation", "criterion", "max_relative_displacement",
                "max_displacement", "peak_speed", "final_speed", "moved_blocks",
                "largest_movers", "displacement_over_time", "simulated_seconds",
                "wall_seconds", "tolerance", "settlement", "per_block"):  # fmt: skip
        assert key in report
    block = report["per_block"][0]
    assert block["id"] == "a"
    assert set(block) >= {"displacement", "rotation", "width", "relative_displacement",
                          "peak_speed", "final_speed", "fell", "still_moving", "moved"}  # fmt: skip
    assert block["width"] == pytest.approx(0.5)
    assert report["largest_movers"][0]["id"] == "a"
    assert report["tolerance"] is None  # judged relative to each block's width
    assert np.isfinite(report["wall_seconds"])


def test_a_fixed_tolerance_is_kept_and_reported():
    pier = Model([Block.box([0, 0, 0], [4, 20, 4], id="pier")])
    given = simulate(pier, seconds=0.2, settle=0.1, tolerance=5e-4)
    assert given.settings.tolerance == 5e-4
    assert given.to_report()["tolerance"] == 5e-4
    assert "0.5 mm after settling" in given.explanation()

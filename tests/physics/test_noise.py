"""Seeded noise: the model's draws, the world's use of them, the controller's fields and seed derivation."""

import dataclasses
import math

import pytest

from hakoniwa.physics.course import load_course
from hakoniwa.physics.noise import DEFAULT_NOISE, NoiseDraw, StartOffset
from hakoniwa.physics.robot import ULTRASONIC_MAX_MM
from hakoniwa.physics.sensors import SensorModel
from hakoniwa.physics.world import World
from hakoniwa.wire.protocol import ColorId, Rx, open_athrill, open_unity
from testctl.bench_options import DEFAULT_COURSE
from testctl.noise_seed import noise_seed
from testctl.runner import TestRunner


@pytest.fixture(scope="module")
def world():
    return World(load_course(DEFAULT_COURSE))


def per_test(draw: NoiseDraw) -> tuple:
    return draw.reflect_offset, draw.gyro_bias_dps, draw.motor_gain, draw.start


def test_same_seed_same_draws_and_another_seed_others():
    a, b, c = NoiseDraw(DEFAULT_NOISE, 7, 1.0), NoiseDraw(DEFAULT_NOISE, 7, 1.0), NoiseDraw(DEFAULT_NOISE, 8, 1.0)
    assert per_test(a) == per_test(b) != per_test(c)
    readings = [(a.reading(75.0, 10.0, 500), a.motor_factors()) for _ in range(50)]
    assert readings == [(b.reading(75.0, 10.0, 500), b.motor_factors()) for _ in range(50)]


def test_streams_do_not_shift_each_other():
    """Motor commands and sensor snapshots interleave differently in different programs; neither may change
    the other's draws."""
    a, b = NoiseDraw(DEFAULT_NOISE, 3, 1.0), NoiseDraw(DEFAULT_NOISE, 3, 1.0)
    for _ in range(5):
        b.motor_factors()
    assert [a.reading(75.0, 0.0, 500) for _ in range(5)] == [b.reading(75.0, 0.0, 500) for _ in range(5)]


def test_scale_multiplies_every_level():
    one, two = NoiseDraw(DEFAULT_NOISE, 11, 1.0), NoiseDraw(DEFAULT_NOISE, 11, 2.0)
    assert two.levels == DEFAULT_NOISE.scaled(2.0)
    assert two.reflect_offset == pytest.approx(2 * one.reflect_offset)
    assert two.start.dyaw_deg == pytest.approx(2 * one.start.dyaw_deg)
    assert two.motor_gain[0] - 1 == pytest.approx(2 * (one.motor_gain[0] - 1))
    zero = NoiseDraw(DEFAULT_NOISE, 11, 0.0)
    assert per_test(zero) == (0.0, 0.0, (1.0, 1.0), StartOffset(0.0, 0.0, 0.0))
    assert zero.reading(75.25, 3.5, 400) == (75.25, 3.5, 400) and zero.motor_factors() == (1.0, 1.0)


@pytest.mark.parametrize("scale", [-1.0, math.nan, math.inf])
def test_a_bad_scale_is_refused(scale):
    with pytest.raises(ValueError, match="noise scale"):
        NoiseDraw(DEFAULT_NOISE, 1, scale)


def test_readings_stay_in_the_sensors_ranges():
    loud = NoiseDraw(DEFAULT_NOISE, 5, 200.0)
    for _ in range(200):
        reflect, _, mm = loud.reading(95.0, 0.0, 100)
        assert 0.0 <= reflect <= 100.0
        assert 0 <= mm < ULTRASONIC_MAX_MM  # a noisy echo never reads as "nothing in range"
        assert loud.reading(75.0, 0.0, ULTRASONIC_MAX_MM)[2] == ULTRASONIC_MAX_MM  # nor the other way round
        assert min(loud.motor_factors()) >= 0.0  # no wheel turns backwards for a forward command


def test_gyro_drift_integrates_the_bias():
    d = NoiseDraw(DEFAULT_NOISE, 9, 1.0)
    assert d.gyro_drift_deg(0) == 0.0
    assert d.gyro_drift_deg(30_000_000) == pytest.approx(30 * d.gyro_bias_dps)


def test_colour_id_and_rgb_follow_the_noisy_reflect(world):
    """On plain floor the colour id and raw RGB derive from the reflect the program reads."""
    world.reset()
    true_reflect = world.measure().reflect
    model = SensorModel(world.course)
    dark = dataclasses.replace(DEFAULT_NOISE.scaled(0.0), reflect_offset_sd=100.0)
    seed = next(s for s in range(100) if NoiseDraw(dark, s, 1.0).reflect_offset < -150)
    model.begin(NoiseDraw(dark, seed, 1.0))
    s = model.read(world, 0)
    assert true_reflect > 50 and (s.reflect, s.color, s.rgb) == (0, ColorId.BLACK, (0, 0, 0))
    seed = next(s for s in range(100) if NoiseDraw(dark, s, 1.0).reflect_offset > 150)
    model.begin(NoiseDraw(dark, seed, 1.0))
    s = model.read(world, 0)
    assert (s.reflect, s.color, s.rgb) == (100, ColorId.WHITE, (255, 255, 255))


def test_put_down_moves_the_robot_by_the_offset(world):
    world.reset()
    x0, y0, yaw0 = world.pose()
    world.put_down(StartOffset(0.004, -0.003, 2.0))
    x, y, yaw = world.pose()
    assert (x - x0, y - y0, math.degrees(yaw - yaw0)) == pytest.approx((0.004, -0.003, 2.0))
    world.put_down(StartOffset(0.0, 0.0, 0.0))
    assert world.pose() == pytest.approx((x0, y0, yaw0), abs=1e-12)
    world.reset()


def test_motor_gains_scale_the_commanded_speeds(world):
    world.set_motor_power(20, 20)
    plain = world.data.ctrl[:2].copy()
    world.set_motor_power(20, 20, (1.1, 0.9))
    assert list(world.data.ctrl[:2]) == pytest.approx([plain[0] * 1.1, plain[1] * 0.9])
    world.reset()


# -- the controller's side ---------------------------------------------------------------------------
def test_noise_seed_is_a_pure_u32_function_of_its_place():
    assert noise_seed(1, 0, 0) == 2207748620  # pinned: a journal's noise must replay in later versions
    seeds = {noise_seed(c, s, r) for c in range(3) for s in range(10) for r in range(5)}
    assert len(seeds) == 150 and all(0 <= x < 2**32 for x in seeds)
    assert noise_seed(1, 2, 3) == noise_seed(1, 2, 3) != noise_seed(1, 3, 2)
    with pytest.raises(TypeError):
        noise_seed(1.0, 0, 0)


def test_the_runner_writes_seed_and_scale_and_refuses_bad_ones(tmp_path):
    open_unity(tmp_path, create=True).close()
    open_athrill(tmp_path, create=True).close()
    runner = TestRunner(tmp_path)
    runner.write_noise(4_000_000_000, 0.5)
    assert (runner.unity.read_u32(Rx.NOISE_SEED), runner.unity.read_f32(Rx.NOISE_SCALE)) == (4_000_000_000, 0.5)
    for seed, scale in ((-1, 1.0), (2**32, 1.0), (0, -0.5), (0, math.nan), (0, math.inf)):
        with pytest.raises(ValueError, match="noise"):
            runner.run_test({}, noise_seed=seed, noise_scale=scale)
    runner.close()

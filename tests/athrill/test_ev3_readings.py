"""The EV3 robot's colour and motor readings against EV3RT's own code and the real sensors, reading by reading
(docs/NATIVE.md, "The EV3 side against EV3RT"): raw RGB's range, the counts of HackEV's wheels, the gyro's sign.

Paths are under ../shared/third_party/ev3rt/ev3rt-athrill-v850e2m/ (EV3RT for Athrill) and
../shared/third_party/raspike/raspike-art-samples/ (ET Robocon's samples); none is read here, so nothing skips."""

from __future__ import annotations

import dataclasses

import pytest
from hypothesis import given
from hypothesis import strategies as st

from athrill_sim.mock.bus import MemoryBus
from athrill_sim.mock.ev3api import COLOR_SENSOR, EV3_PORT_1, Ev3Api, RgbRaw
from athrill_sim.mock.kernel import Kernel
from hakoniwa.physics import color_response as cr
from hakoniwa.physics.color_response import Calibration
from hakoniwa.physics.course import load_course
from hakoniwa.physics.environment import Environment
from hakoniwa.physics.noise import DEFAULT_NOISE, NoiseDraw
from hakoniwa.physics.robots import BUILT_IN, parse_robot
from hakoniwa.wire.protocol import Rx, open_athrill, open_unity
from tests.helpers.environments import environment

# The EV3 colour sensor's RGB-RAW mode: three values, each 0..1020 (LEGO's sensor mode table, as ev3dev's page
# "LEGO EV3 Color Sensor (45506)" lists it: mode 4, RGB-RAW, min 0, max 1020).
SENSOR_FULL_SCALE = 1020
# What ET Robocon's simulator's HackEV sensor reads on its course (etrobocon-l/course.toml, [sensor.ev3]).
ETROBOCON = Calibration(white=23, black=0)
C, B = 2, 1  # motor ports C and B


def test_raw_rgb_reads_past_the_courses_white_up_to_the_sensors_full_scale():
    """The sensor saturates at its own full scale, not at whatever white the course has: a spot brighter than
    the course's white (the room's light, in the noise) reads brighter, as its reflect does."""
    assert cr.raw_rgb(23, None, ETROBOCON) == (255, 255, 255)  # the course's white: the bench's calibration
    assert cr.raw_rgb(25, None, ETROBOCON) == (277, 277, 277)  # 25 / 23 * 255 = 277.2; was clamped to 255
    assert cr.raw_rgb(100, None, ETROBOCON) == (SENSOR_FULL_SCALE,) * 3  # 1108.7: the sensor's ceiling
    assert cr.raw_rgb(-2, None, ETROBOCON) == (0, 0, 0)
    assert cr.raw_rgb(25, (11.5, 0, 12), ETROBOCON) == (277, 128, 0)  # each channel on its own


@given(st.floats(-50, 150), st.floats(-50, 150), st.floats(-50, 150),
       st.floats(0, 90), st.floats(1, 100))
def test_raw_rgb_stays_in_the_sensors_range(red, green, blue, black, span):
    rgb = cr.raw_rgb(red, (green, blue, (red + green + blue) / 3), Calibration(black + span, black))
    assert all(0 <= c <= SENSOR_FULL_SCALE for c in rgb)


def test_a_noisy_bright_reading_keeps_rgb_and_reflect_together():
    """On ET Robocon's course, whose white reads 23, a brighter room lifts the reflect past 23 and the raw red
    with it (the physics side's snapshot, as the program reads it)."""
    course = load_course("etrobocon-l")
    robot = BUILT_IN["hackev"]
    env = environment(dataclasses.replace(course, wiring=robot.wiring), course.time_limit_us, robot)
    bright = dataclasses.replace(DEFAULT_NOISE.scaled(0.0), reflect_offset_sd=10.0)
    seed = next(s for s in range(100) if NoiseDraw(bright, s, 1.0).reflect_offset > 10)
    env.begin(NoiseDraw(bright, seed, 1.0))
    noisy = env.world.measure().reflect + env.sensors.noise.reflect_offset
    s = env.read_sensors()
    assert noisy > 23 + 10 and s.reflect == round(noisy)
    assert s.rgb[0] == round(noisy / 23 * 255) > 255


@pytest.fixture
def api(tmp_path):
    open_unity(tmp_path, create=True).close()
    open_athrill(tmp_path, create=True).close()
    bus = MemoryBus(tmp_path)
    yield Ev3Api(bus, Kernel(bus.unity, bus.athrill))
    bus.close()


def test_ev3rt_hands_the_programs_16_bits_of_each_raw_rgb_slot(api):
    """uart_dri.c:96-98: `array[i] = (uint16_t)sil_rew_mem(EV3_SENSOR_ADDR_RGB_*(index))`, into rgb_raw_t's
    uint16_t r, g, b (sdk/common/ev3api/src/ev3api_sensor.h:83-85): no scaling, the sensor's full 0..1020."""
    for offset, value in ((0, SENSOR_FULL_SCALE), (4, 0x0001_03FC), (8, 300)):
        api.bus.unity.write_i32(Rx.COLOR0_RGB + offset, value)
    api.ev3_sensor_config(EV3_PORT_1, COLOR_SENSOR)
    val = RgbRaw()
    api.ev3_color_sensor_get_rgb_raw(EV3_PORT_1, val)
    assert (val.r, val.g, val.b) == (1020, 0x03FC, 300)


def hackev(robot_toml: str | None = None) -> Environment:
    robot = BUILT_IN["hackev"] if robot_toml is None else parse_robot(robot_toml, "r.toml")
    course = load_course("oval")
    env = environment(dataclasses.replace(course, wiring=robot.wiring), course.time_limit_us, robot)
    env.begin(None)
    return env


def run(env: Environment, powers: dict[int, int], seconds: float) -> None:
    """Powers on motor ports as EV3RT's ev3_motor_set_power writes them (TX MOTOR_POWER + 4 * port), with a
    snapshot of the sensors every 10 ms, as the bench takes them while a program runs."""
    env.drive([powers.get(port, 0) for port in range(4)])
    for _ in range(round(seconds * 100)):
        env.advance_to(env.now_us + 10_000)
        env.read_sensors()


def test_hackevs_wheels_count_up_driving_forward():
    """ET Robocon's EV3-API sample wires HackEV's left wheel to C and its right to B (sample_c5/app.h:24-25)
    and drives forward on positive powers (sample_c5/LineTracer/LineTracer.c:53-58); ev3_motor_get_counts
    hands on the port's angle slot unchanged (sdk/common/ev3api/src/ev3api_motor.c:105-120 via
    target/v850_gcc/drivers/motor/src/motor_dri.c:12-15). An EV3 motor's count runs the way its power turns
    it, so both count up while the robot drives forward."""
    env = hackev()
    x0 = env.world.pose()[0]
    run(env, {C: 50, B: 50}, 0.5)
    counts = env.read_sensors().motor_angles_deg
    assert counts[C] > 100 and counts[B] > 100 and abs(counts[C] - counts[B]) < 10
    assert env.world.pose()[0] > x0 + 0.05  # the oval's start heads along +x
    run(env, {C: -50, B: -50}, 1.0)
    counts = env.read_sensors().motor_angles_deg
    assert counts[C] < -100 and counts[B] < -100


def test_an_ev3_count_follows_its_power_however_the_motor_is_mounted():
    """EV3RT has no direction setting (ev3api_motor.c:61-68: ev3_motor_config takes a type only): a motor
    mounted mirror-wise drives the robot backwards on a positive power, and its count still runs up."""
    env = hackev('left_motor = "C"\nright_motor = "B"\nleft_motor_forward = "negative"\n'
                 'right_motor_forward = "negative"\n')
    x0 = env.world.pose()[0]
    run(env, {C: 50, B: 50}, 0.5)
    counts = env.read_sensors().motor_angles_deg
    assert counts[C] > 100 and counts[B] > 100 and env.world.pose()[0] < x0 - 0.05


@pytest.mark.parametrize("left, right, sign", [(50, -50, 1), (-50, 50, -1)])
def test_the_gyro_counts_a_right_turn_up_and_a_left_turn_down(left, right, sign):
    """EV3RT hands on the gyro's angle and rate slots' 16 bits, signs untouched (ev3api_sensor.c:221-251,
    uart_dri.c:34-59). The EV3 gyro sensor counts clockwise seen from its top (Pybricks' EV3 GyroSensor:
    positive_direction defaults to Direction.CLOCKWISE, "when looking at the red dot on top"), and HackEV
    carries it top up: a right turn (clockwise seen from above) reads positive, a left turn negative."""
    env = hackev()
    run(env, {C: left, B: right}, 0.2)
    s = env.read_sensors()
    assert sign * s.gyro_rate_dps > 300 and sign * s.gyro_angle_deg > 60
    assert sign * env.world.pose()[2] < 0  # the world's heading turns the other way: counter-clockwise positive

"""The SPIKE robot on the physics side: HackSPi's wiring and body, robot files with SPIKE ports, the SPIKE
sensors' responses and the slots ET Robocon's SDK reads them from (raspike-athrill-v850e2m's spikeapi)."""

import dataclasses
import math
import struct

import pytest

from hakoniwa.physics.course import load_course
from hakoniwa.physics.environment import Environment
from hakoniwa.physics.robot import EV3_BODY, HACKSPI_BODY, ULTRASONIC_MAX_MM
from hakoniwa.physics.robots import BUILT_IN, DEFAULT_ROBOT, RobotError, parse_robot
from hakoniwa.physics.scenario import ScenarioError, parse_scenario
from hakoniwa.physics.sensors import hsv_of
from hakoniwa.physics.slots import Slots
from hakoniwa.physics.task import LapTask
from hakoniwa.physics.world import World
from hakoniwa.wire.protocol import UNITY_FILE
from testctl.bench_options import BenchOptions, load_bench
from tests.helpers.commands import hako, one_line_error
from tests.helpers.environments import environment
from tests.physics.test_color_response import colour_course, stripes

G_MM_S2 = 9806.65


def env_for(robot_name: str, scenario: str = "") -> Environment:
    robot = BUILT_IN[robot_name]
    course = load_course("oval")
    if robot.wiring is not None:
        course = dataclasses.replace(course, wiring=robot.wiring)
    env = Environment(World(course, robot.body, imu=robot.spike), LapTask(course, course.time_limit_us), robot,
                      parse_scenario(scenario))
    env.begin(None)
    return env


def test_hackspi_is_the_official_samples_wiring():
    r = BUILT_IN["hackspi"]
    assert r.hub == "spike" and r.spike and r.body == HACKSPI_BODY
    # sample_c5_spike: left motor B (counter-clockwise: mounted mirror-wise), right motor A
    assert (r.wiring.left, r.wiring.right, r.wiring.left_forward, r.wiring.right_forward) == (1, 0, -1, 1)
    assert dict(r.sensors) == {"D": "force", "E": "color", "F": "ultrasonic"}
    assert not r.bumper and r.press_slot("force", None) == 0 and r.press_slot("touch", "D") == 0
    assert DEFAULT_ROBOT.body == EV3_BODY and not DEFAULT_ROBOT.spike


def test_a_robot_file_takes_spike_port_letters_and_mounting_directions():
    r = parse_robot('hub = "spike"\nleft_motor = "C"\nright_motor = "D"\nleft_motor_forward = "negative"\n'
                    '[[sensor]]\nport = "a"\nkind = "color"\n[[sensor]]\nport = "F"\nkind = "force"\n', "r.toml")
    assert dict(r.sensors) == {"A": "color", "F": "force"} and r.body == HACKSPI_BODY
    assert (r.wiring.left, r.wiring.right, r.wiring.left_forward, r.wiring.right_forward) == (2, 3, -1, 1)
    ev3 = parse_robot('[[sensor]]\nport = 2\nkind = "touch"\n', "r.toml")
    assert ev3.hub == "ev3" and ev3.wiring.left_forward == 1 and ev3.body == EV3_BODY


@pytest.mark.parametrize("text, words", [
    ('hub = "spike"\n[[sensor]]\nport = "G"\nkind = "color"\n', "port 'G' does not exist on a SPIKE hub"),
    ('hub = "spike"\n[[sensor]]\nport = 1\nkind = "color"\n', "a SPIKE hub's ports are letters A..F"),
    ('[[sensor]]\nport = "E"\nkind = "color"\n', 'ports A..F are a SPIKE hub\'s: hub = "spike"'),
    ('hub = "spike"\n[[sensor]]\nport = "A"\nkind = "color"\n', "two devices on port A: left_motor and color"),
    ('hub = "spike"\n[[sensor]]\nport = "C"\nkind = "force"\n[[sensor]]\nport = "D"\nkind = "force"\n',
     "two force sensors"),
    ('hub = "spike"\n[[sensor]]\nport = "C"\nkind = "gyro"\n', "kind must be one of color, ultrasonic, force"),
    ('[[sensor]]\nport = 1\nkind = "force"\n', "kind must be one of color, ultrasonic, gyro, touch on an EV3"),
    ('hub = "spike"\nleft_motor = "E"\n', "motor port A..D"),
    ('left_motor_forward = "backwards"\n', "left_motor_forward must be one of positive, negative"),
    ('hub = "nxt"\n', "hub must be one of ev3, spike"),
    ('body = "huge"\n', "body must be one of ev3, hackspi"),
])
def test_bad_robot_files_are_one_line(text, words):
    with pytest.raises(RobotError, match=words) as e:
        parse_robot(text, "r.toml")
    assert "\n" not in str(e.value)


def test_presses_the_robot_cannot_take_are_one_line(tmp_path):
    scenario = tmp_path / "s.toml"
    for robot, press, words in [(None, 'sensor = "force"', "robot 'default' has no force sensor to press"),
                                ("hackspi", 'sensor = "touch"\nport = "A"', "no touch or force sensor on port A"),
                                ("hackspi", 'sensor = "force"\nport = "E"', "no force sensor on port E"),
                                ("hackspi", 'sensor = "touch"\nport = 1', "no touch or force sensor on port 1")]:
        scenario.write_text(f"[[press]]\n{press}\nat_s = 1\n")
        with pytest.raises(ScenarioError, match=words):
            load_bench(BenchOptions(robot=robot, scenario=str(scenario)))
    with pytest.raises(ScenarioError, match="port must be 1..4"):
        parse_scenario('[[press]]\nsensor = "touch"\nport = "G"\nat_s = 1\n')


def test_a_force_press_reads_as_the_sdk_reads_it():
    """raspike_forcesensor.c: force() = (float) TOUCH0 in N, touched() = TOUCH0 > 0."""
    for press in ('sensor = "force"', 'sensor = "touch"\nport = "D"'):
        env = env_for("hackspi", f"[[press]]\n{press}\nat_s = 0.5\nfor_s = 0.2\n")
        assert env.read_sensors().touch == (0, 0)
        env.advance_to(500_000)
        assert env.read_sensors().touch == (10, 0)
        env.advance_to(700_000)
        assert env.read_sensors().touch == (0, 0)


def test_the_spike_colour_sensor_reads_et_robocons_white_40_and_black_10():
    hackspi, default = env_for("hackspi"), env_for("default")
    course = hackspi.course
    for env in (hackspi, default):
        sensors = env.sensors
        assert sensors.robot.spike == (env is hackspi)
    spike = hackspi.sensors._spike_reflect
    assert (spike(course.reflect_white), spike(course.reflect_black)) == (40, 10)  # the oval's 100 and 50
    assert spike((course.reflect_white + course.reflect_black) / 2) == 25
    # At the start the sensor sits on the line's outer edge: a grey between the two, in both kinds' scales.
    ev3 = default.read_sensors().reflect
    assert course.reflect_black < ev3 < course.reflect_white and 10 < hackspi.read_sensors().reflect < 40


def test_hsv_agrees_with_the_rgb_of_the_same_snapshot():
    assert hsv_of((255, 255, 255)) == (0, 0, 100) and hsv_of((0, 0, 0)) == (0, 0, 0)
    assert hsv_of((220, 0, 0)) == (0, 100, 86) and hsv_of((0, 0, 255)) == (240, 100, 100)
    s = env_for("hackspi").read_sensors()
    assert s.hsv == hsv_of(s.rgb) and s.hsv[:2] == (0, 0)
    assert env_for("default").read_sensors().hsv is None


def drive(env: Environment, left_power: int, right_power: int, seconds: float) -> None:
    """Powers as a SPIKE program writes them to TX for the left (B) and right (A) motor."""
    powers = [0] * 4
    powers[1], powers[0] = left_power, right_power
    env.drive(powers)
    env.advance_to(env.now_us + round(seconds * 1e6))


def test_the_mirrored_left_motor_drives_forward_on_negative_power():
    env = env_for("hackspi")
    x0, y0, _ = env.world.pose()
    drive(env, -50, 50, 1.0)  # what the SDK writes for pup_motor_set_power(left, 50) set up counter-clockwise
    x1, y1, yaw = env.world.pose()
    assert x1 - x0 > 0.2 and abs(y1 - y0) < 0.01 and abs(yaw) < math.radians(2)
    angles = env.read_sensors().motor_angles_deg
    assert angles[1] < -300 and angles[0] > 300  # the mirrored encoder counts down, as the real one does
    env.reset_motor_angle(1)
    assert env.read_sensors().motor_angles_deg[1] == 0
    drive(env, -50, 50, 0.2)
    assert env.read_sensors().motor_angles_deg[1] < 0


def test_the_hub_imu_reads_gravity_at_rest_and_the_turn_counter_clockwise():
    env = env_for("hackspi")
    env.advance_to(300_000)
    imu = env.read_sensors().imu
    assert all(abs(w) < 0.5 for w in imu.angular_velocity_dps)
    ax, ay, az = imu.acceleration_mm_s2
    assert abs(ax) < 100 and abs(ay) < 100 and abs(az - G_MM_S2) < 50  # on its wheels and caster, level to 0.6 deg
    drive(env, 50, 50, 0.5)  # the mirrored left wheel backwards, the right forwards: a left turn
    s = env.read_sensors()
    assert s.imu.angular_velocity_dps[2] > 30 and s.gyro_rate_dps < -30  # the EV3 gyro counts clockwise
    assert math.isclose(s.imu.angular_velocity_dps[2], -s.gyro_rate_dps, abs_tol=1)
    assert env_for("default").read_sensors().imu is None


def test_the_spike_ultrasonic_sensor_reads_2000_mm_with_nothing_in_range(monkeypatch):
    hackspi, default = env_for("hackspi"), env_for("default")
    assert 1700 < hackspi.read_sensors().ultrasonic_mm < 1800  # the west wall, ahead at the start
    for env in (hackspi, default):
        monkeypatch.setattr(env.world, "_ultrasonic_mm", lambda yaw: ULTRASONIC_MAX_MM)  # no echo
    assert hackspi.read_sensors().ultrasonic_mm == 2000 and default.read_sensors().ultrasonic_mm == 2550


def test_only_a_spike_robot_gets_the_spike_slots_written(tmp_path):
    for name in ("default", "hackspi"):
        run_dir = tmp_path / name
        run_dir.mkdir()
        slots, env = Slots(run_dir), env_for(name)
        slots.publish(env.read_sensors(), 0, 0)
        body = (run_dir / UNITY_FILE).read_bytes()[32:]
        accel_z = struct.unpack_from("<f", body, 280)[0]
        if name == "default":
            assert body[272:308] == bytes(36)
        else:
            assert abs(accel_z - G_MM_S2) < 50 and struct.unpack_from("<3i", body, 296) == env.read_sensors().hsv
        slots.unity.close()
        slots.athrill.close()


def test_hako_trial_refuses_a_port_letter_a_hub_lacks_in_one_line(tmp_path):
    robot = tmp_path / "robot.toml"
    robot.write_text('hub = "spike"\n[[sensor]]\nport = "G"\nkind = "color"\n')
    one_line_error(hako("trial", "--robot", str(robot), timeout=60), "robot.toml sensor 1", "port 'G' does not exist")


@pytest.mark.parametrize("floor, basic, hackspi", [((255, 255, 255), 80, 40), ((0, 0, 0), 10, 10)])
def test_the_basic_robot_reads_white_80_and_black_10_whatever_the_courses_spike_figures(tmp_path, floor, basic,
                                                                                        hackspi):
    """The Basic class's robot carries its own calibration (SPIKE-RT sdk/workspace/sample_c5,
    LineTracer/LineTracer.h: WHITE_BRIGHTNESS 80, BLACK_BRIGHTNESS 10); HackSPi reads the course's [sensor.spike]
    (here RasPike-ART's 40 and 10) on the same floor."""
    course = colour_course(tmp_path, stripes(floor), "\n[sensor.spike]\nreflect_white = 40\nreflect_black = 10\n")
    robots = BUILT_IN["basic"], BUILT_IN["hackspi"]
    assert [environment(course, course.time_limit_us, r).read_sensors().reflect for r in robots] == [basic, hackspi]
    assert (BUILT_IN["basic"].wiring, BUILT_IN["basic"].sensors) == (BUILT_IN["hackspi"].wiring,
                                                                     BUILT_IN["hackspi"].sensors)

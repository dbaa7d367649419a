"""The SPIKE robot on the physics side: HackSPi's wiring and body, robot files with SPIKE ports, the SPIKE
sensors' responses and the slots ET Robocon's SDK reads them from (raspike-athrill-v850e2m's spikeapi)."""

import dataclasses
import math
import struct

import pytest

from hakoniwa.physics import spike_hub
from hakoniwa.physics.color_response import Calibration
from hakoniwa.physics.course import load_course
from hakoniwa.physics.environment import Environment
from hakoniwa.physics.robot import EV3_BODY, HACKSPI_BODY, ULTRASONIC_MAX_MM
from hakoniwa.physics.robots import BUILT_IN, DEFAULT_ROBOT, RobotError, parse_robot
from hakoniwa.physics.scenario import ScenarioError, parse_scenario
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
    """HackSPi's sensor reads the reflection ET Robocon's sample_c5_spike is tuned for (RasPike-ART
    sample_c5_spike LineTracer.h: WHITE_BRIGHTNESS 40, BLACK_BRIGHTNESS 10), from 10-bit RGB as the hub computes
    it (colorsensor.c 241); a robot file may give another response."""
    hackspi, default = env_for("hackspi"), env_for("default")
    course = hackspi.course
    assert hackspi.sensors.robot.spike and not default.sensors.robot.spike
    for robot, white, black in ((BUILT_IN["hackspi"].reflection, 40, 10), (Calibration(80, 10), 80, 10)):
        for reflect, want in ((course.reflect_white, white), (course.reflect_black, black)):
            seen = course.spike_reading(0.0, 0.0, reflect, None, robot)
            assert seen.reflection == want and seen.rgb[0] == seen.rgb[1] == seen.rgb[2] <= 1024
    # At the start the sensor sits on the line's outer edge: a grey between the two, in both kinds' scales.
    ev3, s = default.read_sensors().reflect, hackspi.read_sensors()
    assert course.reflect_black < ev3 < course.reflect_white and 10 < s.reflect < 40
    assert s.reflect == spike_hub.reflection(s.rgb) and s.spike.hsv == spike_hub.hsv(s.rgb)
    assert s.spike.hsv[:2] == (0, 0) and s.spike.color == spike_hub.color(s.spike.hsv)
    assert default.read_sensors().spike is None


def test_a_robot_file_gives_its_colour_sensors_response():
    spike = 'hub = "spike"\n[[sensor]]\nport = "E"\nkind = "color"\n'
    lower = parse_robot('hub = "spike"\nreflection = { white = 80, black = 10 }\n' + spike[14:], "r.toml")
    assert lower.reflection == Calibration(80, 10)
    assert parse_robot(spike, "r.toml").reflection == Calibration(40, 10)  # HackSPi's by default
    for text, error in (('hub = "spike"\nreflection = { white = 10, black = 40 }\n', "white must be above"),
                        ('hub = "spike"\nreflection = { white = 40 }\n', "reflection must be"),
                        ('reflection = { white = 40, black = 10 }\n', "a SPIKE colour sensor's")):
        with pytest.raises(RobotError, match=error):
            parse_robot(text, "r.toml")


def drive(env: Environment, left_power: int, right_power: int, seconds: float, directions=(0, 1, 0, 0)) -> None:
    """Powers as a SPIKE program sets them for the left (B) and right (A) motor, set up as sample_c5_spike
    sets them up (left counter-clockwise: it is mounted mirror-wise)."""
    powers = [0] * 4
    powers[1], powers[0] = left_power, right_power
    env.drive(powers, directions)
    env.advance_to(env.now_us + round(seconds * 1e6))


def test_the_mirrored_left_motor_set_up_counter_clockwise_drives_and_counts_forward():
    """The hub applies the setup direction to duty and count (pbio: angle = (raw - zero) * direction; the hub's
    raspike.c process_motor_cmd passes the direction to pup_motor_setup, motor.c 57-59): a program that sets
    its mirrored left motor up counter-clockwise drives it with positive power and counts up going forward."""
    env = env_for("hackspi")
    x0, y0, _ = env.world.pose()
    drive(env, 50, 50, 1.0)
    x1, y1, yaw = env.world.pose()
    assert x1 - x0 > 0.2 and abs(y1 - y0) < 0.01 and abs(yaw) < math.radians(2)
    s = env.read_sensors()
    assert s.motor_angles_deg[1] > 300 and s.motor_angles_deg[0] > 300
    assert abs(s.motor_angles_deg[1] - s.motor_angles_deg[0]) < 10  # the mean of both is the distance
    # motor.c 116-124: the hub reports the duty negated for the counter-clockwise motor
    assert s.spike.powers == (50, -50, 0, 0)
    env.reset_motor_angle(1)
    assert env.read_sensors().motor_angles_deg[1] == 0
    drive(env, 50, 50, 0.2)
    assert env.read_sensors().motor_angles_deg[1] > 0
    drive(env, -50, 50, 0.2, directions=(0, 0, 0, 0))  # set up clockwise: its raw encoder, as the SDK reads it
    assert env.read_sensors().motor_angles_deg[1] < 0


def test_the_hub_imu_reads_gravity_at_rest_and_the_turn_counter_clockwise():
    env = env_for("hackspi")
    env.advance_to(300_000)
    imu = env.read_sensors().imu
    assert all(abs(w) < 0.5 for w in imu.angular_velocity_dps)
    ax, ay, az = imu.acceleration_mm_s2
    assert abs(ax) < 100 and abs(ay) < 100 and abs(az - G_MM_S2) < 50  # on its wheels and caster, level to 0.6 deg
    drive(env, -50, 50, 0.5)  # the mirrored left wheel backwards, the right forwards: a left turn
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
            assert body[272:348] == bytes(76)
        else:
            hub = env.read_sensors().spike
            assert abs(accel_z - G_MM_S2) < 50
            assert struct.unpack_from("<13i", body, 296) == (*hub.hsv, *hub.ambient_hsv, *hub.color, *hub.powers)
        slots.unity.close()
        slots.athrill.close()


def test_hako_try_refuses_a_port_letter_a_hub_lacks_in_one_line(tmp_path):
    robot = tmp_path / "robot.toml"
    robot.write_text('hub = "spike"\n[[sensor]]\nport = "G"\nkind = "color"\n')
    one_line_error(hako("try", "--robot", str(robot), timeout=60), "robot.toml sensor 1", "port 'G' does not exist")


@pytest.mark.parametrize("floor, basic, hackspi", [((255, 255, 255), 80, 40), ((0, 0, 0), 10, 10)])
def test_the_basic_robot_reads_white_80_and_black_10_where_hackspi_reads_40_and_10(tmp_path, floor, basic, hackspi):
    """The Basic class's robot carries its own sensor response (SPIKE-RT sdk/workspace/sample_c5,
    LineTracer/LineTracer.h: WHITE_BRIGHTNESS 80, BLACK_BRIGHTNESS 10); HackSPi's is RasPike-ART's 40 and 10
    (sample_c5_spike, LineTracer/LineTracer.h), on the same floor."""
    course = colour_course(tmp_path, stripes(floor), "")
    robots = BUILT_IN["basic"], BUILT_IN["hackspi"]
    assert [environment(course, course.time_limit_us, r).read_sensors().reflect for r in robots] == [basic, hackspi]
    assert (BUILT_IN["basic"].wiring, BUILT_IN["basic"].sensors) == (BUILT_IN["hackspi"].wiring,
                                                                     BUILT_IN["hackspi"].sensors)

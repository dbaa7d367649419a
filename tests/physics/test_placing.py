"""Calibration and start-up by hand: a scenario's `[[place]]` sets the robot down over black, white, the start or
a pose, exactly at its time; `[[hand]]` holds a hand in front of the ultrasonic sensor; a SPIKE hub's buttons
by name. What the program sees (encoders counting on, the gyro following the turn, the hand's distance), what
the task counts (no carried distance), and the one line each bad entry gets, from `hako try` too."""

from __future__ import annotations

import dataclasses
import math
import shutil
from pathlib import Path

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from PIL import Image

from hakoniwa.physics.course import COURSES_DIR, Pose, load_course
from hakoniwa.physics.course_check import color_sensor_xy
from hakoniwa.physics.environment import Environment
from hakoniwa.physics.noise import NoiseDraw
from hakoniwa.physics.placing import shade_at, spot_over
from hakoniwa.physics.robot import EV3_BODY, HACKSPI_BODY
from hakoniwa.physics.robots import BUILT_IN
from hakoniwa.physics.scenario import EV3_BUTTONS, ScenarioError, parse_scenario
from hakoniwa.pictures.plot import read_trajectory
from hakoniwa.wire.protocol import Event
from testctl.bench_options import BenchOptions, load_bench
from tests.helpers.commands import hako, one_line_error
from tests.helpers.environments import environment

OVAL = load_course("oval")
CALIBRATION = ('[[place]]\nat_s = 0.5\nover = "black"\n[[place]]\nat_s = 1.0\nover = "white"\n'
               '[[place]]\nat_s = 1.5\nover = "start"\n')


def env_for(robot_name: str, scenario: str) -> Environment:
    robot = BUILT_IN[robot_name]
    course = OVAL if robot.wiring is None else dataclasses.replace(OVAL, wiring=robot.wiring)
    env = environment(course, course.time_limit_us, robot, parse_scenario(scenario))
    env.begin(None)
    return env


def forward(env: Environment, power: int) -> None:
    """Both wheels forward at `power`, whatever the robot's wiring."""
    w = env.course.wiring
    powers = [0] * 4
    powers[w.left], powers[w.right] = w.left_forward * power, w.right_forward * power
    env.drive(powers)


@pytest.mark.parametrize("body", [EV3_BODY, HACKSPI_BODY])
def test_over_black_is_the_lines_middle_and_over_white_clear_of_it(body):
    """On the oval the start's colour sensor sits on the line's outer edge: black is the line's centre (its
    darkest), white 3 cm out on the white floor; both across the start heading, which they keep."""
    black, white = spot_over(OVAL, body, "black"), spot_over(OVAL, body, "white")
    s = OVAL.start
    assert black == Pose(s.x, pytest.approx(-0.5, abs=0.001), s.yaw_deg)
    assert white is not None and white.x == s.x and white.y < s.y and white.yaw_deg == s.yaw_deg
    assert shade_at(OVAL, *color_sensor_xy(body, black)) == min(
        shade_at(OVAL, s.x + body.color_sensor_forward, y) for y in np.arange(-0.6, -0.4, 0.001))
    assert shade_at(OVAL, *color_sensor_xy(body, white)) == 1.0


def test_a_place_sets_the_robot_down_at_rest_at_its_instant_and_the_program_sees_it_as_on_the_robot():
    env = env_for("hackev", CALIBRATION + '[[place]]\nat_s = 2.0\nx = 0.9\ny = -0.6\nyaw_deg = 90\n')
    forward(env, 40)
    env.advance_to(499_000)
    before = env.read_sensors()
    driven = env.task.distance_m
    env.advance_to(500_000)
    assert env.world.pose() == pytest.approx((OVAL.start.x, -0.5, 0.0), abs=1e-9)
    assert not env.world.data.qvel[:6].any()  # at rest
    after = env.read_sensors()
    # The encoders count on (no reset); over black the colour sensor reads the line's centre.
    assert after.motor_angles_deg[2] >= before.motor_angles_deg[2] > 100
    assert after.reflect == round(OVAL.reflect_at(*color_sensor_xy(EV3_BODY, spot_over(OVAL, EV3_BODY, "black"))))
    env.advance_to(1_999_000)
    heading = env.read_sensors().gyro_angle_deg
    env.advance_to(2_000_000)
    assert env.read_sensors().gyro_angle_deg == heading - 90  # turned left by hand: the gyro counts clockwise
    # The trajectory jumps: each place is sampled where it was lifted and where it was set down, at its instant.
    times = [t for t, *_ in env.trajectory]
    assert [t for t in times if times.count(t) == 2] == [500_000] * 2 + [1_000_000] * 2 + [1_500_000] * 2 + \
        [2_000_000] * 2
    # Carried is not driven: the path is the sum of the drives, however far the places moved the robot.
    # Carried is not driven: four drives of 0.5 s at most 0.6 m/s, where the carries alone were over 2 m.
    assert driven < env.task.distance_m < 4 * 0.5 * 0.6


@settings(max_examples=15, deadline=None)
@given(st.lists(st.integers(1, 700), min_size=1, max_size=6))
def test_where_the_sync_loop_stops_does_not_change_a_place(stops_ms):
    """Lockstep, the real emulator's repeatable mode and its real-time mode step the world in different
    chunks; a place happens at its own instant in every one, so the state after it is the same."""
    def state_after(stops_us: list[int]) -> tuple[float, ...]:
        env = env_for("default", '[[place]]\nat_s = 0.3335\nover = "white"\n')
        forward(env, 50)
        for t in sorted(stops_us) + [800_000]:
            env.advance_to(t)
        return (*env.world.state(), env.task.distance_m, env.read_sensors().reflect)

    assert state_after([t * 1000 for t in stops_ms]) == state_after([])


def test_a_noisy_place_is_off_the_spot_as_the_start_is_and_repeats_with_its_seed():
    def placed(seed: int) -> tuple[float, float, float]:
        env = env_for("default", '[[place]]\nat_s = 0.2\nover = "start"\n')
        env.reset()
        env.begin(NoiseDraw(OVAL.noise, seed, 1.0))
        env.advance_to(200_000)
        return env.world.pose()

    assert placed(4) == placed(4) != placed(5)
    x, y, yaw = placed(4)
    assert math.hypot(x - OVAL.start.x, y - OVAL.start.y) < 0.02 and abs(math.degrees(yaw)) < 5


def test_the_drawn_trajectory_jumps_where_the_robot_was_carried(tmp_path):
    csv = tmp_path / "trajectory.csv"
    csv.write_text("time_us,x,y,yaw\n0,0,0,0\n50000,0.1,0,0\n50000,0.5,0.5,0\n100000,0.6,0.5,0\n")
    points = read_trajectory(csv)
    assert points[:2] == [(0, 0), (0.1, 0)] and all(math.isnan(v) for v in points[2]) and points[3:] == [
        (0.5, 0.5), (0.6, 0.5)]


@pytest.mark.parametrize("robot, hand_cm, reads_mm", [("hackev", 5, 50), ("hackspi", 7.5, 75), ("hackev", 250, None)])
def test_a_hand_in_front_of_the_ultrasonic_sensor_reads_its_distance_or_the_nearer_wall(robot, hand_cm, reads_mm):
    env = env_for(robot, f"[[hand]]\nat_s = 0.1\nfor_s = 0.2\ndistance_cm = {hand_cm}\n")
    free = env.read_sensors().ultrasonic_mm
    env.advance_to(100_000)
    held = env.read_sensors().ultrasonic_mm
    env.advance_to(300_000)
    assert held == (reads_mm or free) and env.read_sensors().ultrasonic_mm == free  # the wall is nearer than 250 cm


@pytest.mark.parametrize("name, bit", [("LEFT", 0), ("RIGHT", 1), ("CENTER", EV3_BUTTONS.index("ENTER")),
                                       ("BT", EV3_BUTTONS.index("BACK"))])
def test_a_spike_hubs_buttons_are_the_bits_et_robocons_sdk_reads_them_from(name, bit):
    s = parse_scenario(f'[[press]]\nbutton = "{name.lower()}"\nat_s = 0.5\n[[press]]\nbutton = "{name}"\nat_s = 0.55\n')
    assert s.buttons(549_999) == s.buttons(550_000) == 1 << bit  # two presses of one button overlap: one bit
    s.check_robot(BUILT_IN["hackspi"])


PLACE_OK = '[[place]]\nat_s = 1\nover = "black"\n'


WEST_WALL = '[[wall]]\nname = "west"\nx = -1.47\ny = 0.0\nhx = 0.02\nhy = 0.85\n'


def given_file(tmp_path: Path, arg: str) -> str:
    """The file an argument stands for: BLANK, the oval with a white floor; OPEN, the oval with no west wall
    (a robot facing west can look past its floor image); NOSONAR, a robot with no ultrasonic sensor."""
    if arg == "NOSONAR":
        (tmp_path / "nosonar.toml").write_text('[[sensor]]\nport = 1\nkind = "color"\n')
        return str(tmp_path / "nosonar.toml")
    if arg not in ("BLANK", "OPEN"):
        return arg
    folder = tmp_path / arg.lower()
    shutil.copytree(COURSES_DIR / "oval", folder)
    if arg == "BLANK":
        with Image.open(folder / "floor.png") as img:
            Image.new("L", img.size, 255).save(folder / "floor.png")
    else:
        toml = folder / "course.toml"
        toml.write_text(toml.read_text().replace(WEST_WALL, ""))
    return str(folder)


@pytest.mark.parametrize("scenario, args, words", [
    ('[[place]]\nat_s = 1\nx = 0\ny = 0\nyaw_deg = 0\n', (), ["place 1", "inside or touching wall 'island'"]),
    ('[[place]]\nat_s = 1\nx = 2\ny = 0\nyaw_deg = 0\n', (), ["place 1", "the place pose (2.000, 0.000) is off the "
                                                              "floor image"]),
    (PLACE_OK + '[[place]]\nat_s = 2\nx = -1.45\ny = 0\nyaw_deg = 180\n', ("--course", "OPEN"),
     ["place 2", "the colour sensor at the place (-1.530, 0.000) is off the floor image"]),
    ('[[place]]\nat_s = 1\nover = "black"\n', ("--course", "BLANK"), ["place 1", "no black floor within 30 cm"]),
    ('[[place]]\nat_s = 1\nover = "start"\nedge = "left"\n', ("--course", "BLANK"),
     ["place 1", "no line within 30 cm", "for edge = 'left'"]),
    ('[[place]]\nat_s = 1\nover = "grey"\n', (), ["place 1", "over must be one of 'black', 'white', 'start'"]),
    ('[[place]]\nat_s = 1\nover = "start"\nx = 0\n', (), ["place 1", "give either over"]),
    ('[[place]]\nat_s = 1\nx = 0\ny = 0.5\n', (), ["place 1", "missing 'yaw_deg'"]),
    ('[[place]]\nat_s = -1\nover = "start"\n', (), ["place 1", "'at_s' must be at least 0"]),
    ('[[place]]\nat_s = 60\nover = "start"\n', (), ["place 1", "is not before the time limit (60 s)"]),
    ('[[hand]]\nat_s = 60.5\ndistance_cm = 5\n', (), ["hand 1", "is not before the time limit"]),
    ('[[hand]]\nat_s = 1\nfor_s = -2\ndistance_cm = 5\n', (), ["hand 1", "'for_s' must be positive"]),
    ('[[hand]]\nat_s = 1\ndistance_cm = 300\n', (), ["hand 1", "'distance_cm' must be at least 0 and below 255"]),
    ('[[hand]]\nat_s = 1\ndistance_cm = 5\n', ("--robot", "NOSONAR"), ["hand 1", "has no ultrasonic sensor"]),
    ('[[press]]\nbutton = "CENTER"\nat_s = 1\n', ("--robot", "hackev"),
     ["press 1", "robot 'hackev' has no button CENTER (an EV3: LEFT, RIGHT, UP, DOWN, ENTER, BACK)"]),
    ('[[press]]\nbutton = "ENTER"\nat_s = 1\n', ("--robot", "hackspi"),
     ["press 1", "robot 'hackspi' has no button ENTER (a SPIKE hub: LEFT, RIGHT, CENTER, BT)"]),
    ('[[press]]\nbutton = "MIDDLE"\nat_s = 1\n', (), ["press 1", "'MIDDLE' is not one of an EV3's"]),
])
def test_each_bad_entry_is_one_line_naming_it_from_hako_trial(tmp_path, scenario, args, words):
    (tmp_path / "bad.toml").write_text(scenario)
    given = [given_file(tmp_path, a) for a in args]
    r = hako("try", "--scenario", str(tmp_path / "bad.toml"), *given, "--run-dir", str(tmp_path / "run"),
             timeout=120)
    one_line_error(r, "bad.toml", *words)
    assert not (tmp_path / "run" / "unity_mmap.bin").exists()  # refused before any bench started


@given(st.lists(st.tuples(st.sampled_from(["at_s", "over", "x", "y", "yaw_deg", "for_s", "distance_cm", "z", "edge"]),
                          st.sampled_from(['"black"', '"start"', '"red"', "0.5", "-1", "1e400", "true", "[1]",
                                           '"left"', '"centre"'])),
                max_size=5), st.sampled_from(["place", "hand"]))
def test_any_place_or_hand_table_is_one_or_one_scenario_error(pairs, kind):
    text = f"[[{kind}]]\n" + "".join(f"{k} = {v}\n" for k, v in dict(pairs).items())
    try:
        s = parse_scenario(text)
    except ScenarioError as e:
        assert "\n" not in str(e) and f"{kind} 1" in str(e)
        return
    entry = s.places[0] if kind == "place" else s.hands[0]
    assert entry.at_us >= 0
    if kind == "place":
        assert (entry.over is None) == ("over" not in dict(pairs))
        assert entry.edge is None or (entry.over == "start" and entry.edge in ("left", "centre"))
    else:
        assert entry.for_us > 0 and 0 <= entry.distance_mm < 2550


def test_places_happen_in_time_order_and_a_place_at_zero_before_the_first_step():
    env = env_for("default", '[[place]]\nat_s = 0.2\nover = "start"\n[[place]]\nat_s = 0\nover = "white"\n')
    assert env.world.pose()[1] == pytest.approx(spot_over(OVAL, EV3_BODY, "white").y)
    env.advance_to(200_000)
    assert env.world.pose()[:2] == pytest.approx((OVAL.start.x, OVAL.start.y))
    assert env.event == Event.NONE


@pytest.mark.parametrize("first, second", [("1", "1"), ("1.0002", "1.0008")])
def test_two_places_at_one_physics_step_are_refused_naming_both(first, second):
    """A place happens at the first physics step at or after its time; two there left the robot at the file's
    last, the other never seen."""
    def places(a: str, b: str) -> str:
        return f'[[place]]\nat_s = {a}\nover = "black"\n[[place]]\nat_s = {b}\nover = "white"\n'

    with pytest.raises(ScenarioError, match=rf"^s.toml place 2: at_s = {second} is the same physics step "
                                            rf"\(1000 us\) as s.toml place 1 \(at_s = {first}\)"):
        parse_scenario(places(first, second), "s.toml")
    assert len(parse_scenario(places(first, "1.0012"), "s.toml").places) == 2


def test_the_bench_checks_a_place_against_the_robot_it_runs(tmp_path):
    """HackSPi is narrower than the EV3 robot: a place beside a wall may suit one and not the other."""
    y = -0.85 + HACKSPI_BODY.track_width / 2 + HACKSPI_BODY.wheel_radius + 0.005  # HackSPi's wheel 5 mm clear
    (tmp_path / "s.toml").write_text(f"[[place]]\nat_s = 1\nx = 0\ny = {y}\nyaw_deg = 0\n")
    load_bench(BenchOptions(robot="hackspi", scenario=str(tmp_path / "s.toml")))
    with pytest.raises(ScenarioError, match="s.toml place 1: .* touching wall 'south'"):
        load_bench(BenchOptions(scenario=str(tmp_path / "s.toml")))

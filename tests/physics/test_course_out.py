"""The start and the end of a run as ET Robocon's rules have them: `[[place]] over = "start"` with `edge`
sets the robot down with its colour sensor on that edge of the line, and a run ends COURSE_OUT (ET Robocon's
コースアウト) where the robot leaves the course: past the mat's edge, or into an area the course marks out of
bounds, with the course's margin; the result says when and where, and `--objective etrobocon` scores it as
a run that did not finish. The oval keeps its walls: HIT_WALL comes first there."""

from __future__ import annotations

import dataclasses
import json
import os
import re
import shutil
from pathlib import Path

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from hakoniwa.physics.course import COURSES_DIR, Box, CourseError, CourseOut, load_course
from hakoniwa.physics.course_check import color_sensor_xy
from hakoniwa.physics.environment import Environment
from hakoniwa.physics.placing import shade_at, spot_on_edge
from hakoniwa.physics.robot import EV3_BODY, HACKSPI_BODY
from hakoniwa.physics.robots import BUILT_IN
from hakoniwa.physics.scenario import ScenarioError, parse_scenario
from hakoniwa.physics.slots import Slots
from hakoniwa.wire.etrobocon_rules import Score
from hakoniwa.wire.objective import objective_named
from hakoniwa.wire.protocol import Event
from hakoniwa.wire.result import TestResult
from hakoniwa.wire.rundir import RESULT_FILE
from testctl.campaign.repetition import RepetitionRule
from testctl.runner import PhysicsGone, TestRunner
from tests.helpers.commands import hako, one_line_error
from tests.helpers.environments import environment
from tests.helpers.native_fixtures import need_cc
from tests.helpers.paths import PROGRAMS

LANES = ("etrobocon-l", "etrobocon-r")
# A program that drives straight ahead at power 50 on both of the default robot's wheels, and never stops.
STRAIGHT_APP = '''
from athrill_sim.mock.ev3api import EV3_PORT_A, EV3_PORT_B, LARGE_MOTOR


def main_task(api):
    for port in (EV3_PORT_A, EV3_PORT_B):
        api.ev3_motor_config(port, LARGE_MOTOR)
        api.ev3_motor_set_power(port, 50)
    while True:
        api.tslp_tsk(100_000)
'''
OUT_AREA = '\n[course_out]\nmargin_m = 0.05\n[[course_out.area]]\nname = "pit"\nx = 0.0\ny = 0.0\nhx = 0.5\nhy = 0.3\n'


def lane_copy(tmp_path: Path, extra: str) -> Path:
    """A copy of the L lane with `extra` in place of its `[course_out]` table."""
    folder = tmp_path / "etrobocon-l"
    shutil.copytree(COURSES_DIR / "etrobocon-l", folder)
    toml = folder / "course.toml"
    text = re.sub(r"\[course_out\][^\n]*\nmargin_m = 0\n", "", toml.read_text())
    assert "course_out" not in text
    toml.write_text(text + extra)
    return folder


def drive_forward(env: Environment, power: int = 60, limit_us: int = 60_000_000) -> None:
    w = env.course.wiring
    powers = [0] * 4
    powers[w.left], powers[w.right] = w.left_forward * power, w.right_forward * power
    env.drive(powers)
    env.advance_to(limit_us)


def test_the_mat_ends_at_its_edge_and_the_margin_past_it():
    course = load_course("etrobocon-l")
    xmin, xmax, ymin, ymax = course.extent
    assert (xmin, xmax, ymin, ymax) == pytest.approx((-2.73, 2.73, -1.82, 1.82))  # ET Robocon's 5.46 x 3.64 m
    assert course.out == CourseOut() and course.left_at(0.0, 0.0) is None
    assert course.left_at(xmax, 0.0) is None and course.left_at(xmax + 0.001, 0.0) == "the mat"
    wide = dataclasses.replace(course, out=CourseOut(0.05))
    assert wide.left_at(0.0, ymin - 0.049) is None and wide.left_at(0.0, ymin - 0.051) == "the mat"


def test_an_out_of_bounds_area_counts_from_the_margin_inside_it(tmp_path):
    course = load_course(lane_copy(tmp_path, OUT_AREA))
    assert course.out == CourseOut(0.05, (Box("pit", 0.0, 0.0, 0.5, 0.3),))
    assert course.left_at(0.44, 0.0) == "pit" and course.left_at(0.46, 0.0) is None
    assert course.left_at(0.0, -0.24) == "pit" and course.left_at(0.0, -0.26) is None
    r = hako("course", "show", str(tmp_path / "etrobocon-l"), "--png", str(tmp_path / "c.png"), timeout=120)
    assert r.returncode == 0 and (tmp_path / "c.png").stat().st_size > 0, r.stderr  # drawn hatched in red


@pytest.mark.parametrize("extra, words", [
    ('\n[course_out]\n[[course_out.area]]\nname = "beyond"\nx = 2.7\ny = 0\nhx = 0.1\nhy = 0.1\n',
     ["out-of-bounds area 'beyond' reaches off the mat", "x -2.73..2.73"]),
    ('\n[course_out]\nmargin_m = -0.1\n', ["[course_out]", "'margin_m' must not be negative"]),
    ('\n[course_out]\nmargin = 0.1\n', ["[course_out]", "unknown key 'margin'"]),
    ('\n[course_out]\n[[course_out.area]]\nx = 0\ny = 0\nhx = 0.1\nhy = 0.1\nheight = 1\n',
     ["[[course_out.area]] 0", "unknown key 'height'"]),
    ('\n[course_out]\nmargin_m = 0.2\n[[course_out.area]]\nx = 0\ny = 0\nhx = 0.1\nhy = 0.5\n',
     ["no wider than twice the margin"]),
    ('\n[course_out]\n[[course_out.area]]\nname = "start"\nx = -0.43\ny = -1.5\nhx = 0.1\nhy = 0.1\n',
     ["the start pose (-0.430, -1.500) is in out-of-bounds area 'start'"]),
])
def test_a_bad_out_of_bounds_table_is_one_line_from_hako_trial(tmp_path, extra, words):
    folder = lane_copy(tmp_path, extra)
    r = hako("try", "--course", str(folder), "--run-dir", str(tmp_path / "run"), timeout=120)
    one_line_error(r, "course.toml", *words)


VALUES = st.sampled_from(["0", "0.05", "-1", "1e400", "true", '"wide"', "[1]", "{}", "0.3", "3"])


@settings(max_examples=40, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(st.dictionaries(st.sampled_from(["margin_m", "margin"]), VALUES, max_size=2),
       st.lists(st.dictionaries(st.sampled_from(["name", "x", "y", "hx", "hy", "z"]), VALUES, max_size=6), max_size=2))
def test_any_course_out_table_is_a_course_or_one_line_naming_it(tmp_path, table, areas):
    text = "\n[course_out]\n" + "".join(f"{k} = {v}\n" for k, v in table.items())
    text += "".join("[[course_out.area]]\n" + "".join(f"{k} = {v}\n" for k, v in a.items()) for a in areas)
    folder = lane_copy(tmp_path / f"c{abs(hash(text))}", text)
    try:
        course = load_course(folder)
    except CourseError as e:
        assert "\n" not in str(e) and "course.toml" in str(e)
        return
    assert course.out.margin_m >= 0 and len(course.out.areas) == len(areas)
    assert course.left_at(course.start.x, course.start.y) in (None, *(a.name for a in course.out.areas))


@pytest.mark.parametrize("lane", LANES + ("oval",))
@pytest.mark.parametrize("body", [EV3_BODY, HACKSPI_BODY])
def test_the_start_on_an_edge_puts_the_colour_sensor_half_way_between_black_and_white(lane, body):
    course = load_course(lane)
    s = course.start
    spots = {edge: spot_on_edge(course, body, edge) for edge in ("left", "right", "centre")}
    for edge, pose in spots.items():
        assert pose is not None and pose.yaw_deg == s.yaw_deg  # heading along the line, as the start does
        shade = shade_at(course, *color_sensor_xy(body, pose))
        assert shade == pytest.approx(0.5, abs=0.01) if edge != "centre" else shade < 0.3
    # Left and right as the robot faces: heading north (+y) on the lanes, east (+x) on the oval.
    across = (lambda p: -p.x) if s.yaw_deg == 90 else (lambda p: p.y)
    assert across(spots["left"]) > across(spots["centre"]) > across(spots["right"])
    width = abs(across(spots["left"]) - across(spots["right"]))
    assert width == pytest.approx(0.02, abs=0.002) if lane != "oval" else 0.02 < width < 0.05


def test_an_edge_needs_the_start_and_is_one_of_three():
    assert parse_scenario('[[place]]\nat_s = 0\nover = "start"\nedge = "left"\n').places[0].edge == "left"
    with pytest.raises(ScenarioError, match="place 1: edge must be one of 'left', 'right', 'centre', got 'middle'"):
        parse_scenario('[[place]]\nat_s = 0\nover = "start"\nedge = "middle"\n')
    with pytest.raises(ScenarioError, match="place 1: 'edge' goes with over = \"start\" only"):
        parse_scenario('[[place]]\nat_s = 0\nover = "black"\nedge = "left"\n')


def test_an_unknown_edge_is_one_line_from_hako_trial(tmp_path):
    (tmp_path / "s.toml").write_text('[[place]]\nat_s = 0\nover = "start"\nedge = "center-left"\n')
    r = hako("try", "--course", "etrobocon-l", "--scenario", str(tmp_path / "s.toml"), "--run-dir",
             str(tmp_path / "run"), timeout=120)
    one_line_error(r, "s.toml", "place 1", "edge must be one of 'left', 'right', 'centre', got 'center-left'")


@pytest.mark.parametrize("lane", LANES)
def test_driving_straight_off_the_mat_ends_course_out_at_its_edge(lane):
    course = load_course(lane)
    env = environment(course, course.time_limit_us, BUILT_IN["hackspi"], objective="etrobocon")
    env.begin(None)
    drive_forward(env)
    x, y = env.world.position()
    assert env.event == Event.COURSE_OUT and course.left_at(x, y) == "the mat"
    assert y == pytest.approx(course.extent[3], abs=0.01)  # heading north from the start: the mat's far edge
    assert 0 < env.event_us < course.time_limit_us
    score = env.score()
    assert score is not None and not score.finish and not score.lap_gate and score.lap_time_s is None


def test_the_oval_keeps_its_walls():
    course = load_course("oval")
    env = environment(course, course.time_limit_us)
    env.begin(None)
    drive_forward(env)
    assert env.event == Event.HIT_WALL


def test_a_course_out_result_keeps_its_time_and_place_and_is_a_scored_run():
    score = Score.of("applied", None, 1, False, False)
    r = TestResult(Event.COURSE_OUT, 0, 0.0, 1, 3320, objective=objective_named("etrobocon"), score=score,
                   out_time_us=12_340_000, out_xy_mm=(-430, 1821))
    d = r.to_dict()
    assert d["course_out"] == {"time_s": 12.34, "x_m": -0.43, "y_m": 1.821}
    assert TestResult.from_dict(d, 0.0) == r and r.success and r.cost == -2.0  # one checkpoint, 2 points
    lap = TestResult(Event.COURSE_OUT, 0, 0.0, out_time_us=1, out_xy_mm=(1, 2))
    assert not lap.success and "course_out" not in TestResult(Event.HIT_WALL, 0, 0.0).to_dict()
    v = RepetitionRule(repeats=1).judge([lap])
    assert (v.decided, v.success, v.crashes) == (True, False, 0)  # a failure of the parameters, not a crash


def test_when_and_where_travel_to_the_controller(tmp_path):
    """The physics side's result, read back as the controller reads it; the next test's result replaces it."""
    out = TestResult(Event.COURSE_OUT, 0, 0.0, 1, 3325, out_time_us=(1 << 32) + 5, out_xy_mm=(-430, 1824))
    Slots(tmp_path)
    runner = TestRunner(tmp_path)
    try:
        (tmp_path / RESULT_FILE).write_text(out.encode())
        assert runner.read_result() == out
        (tmp_path / RESULT_FILE).write_text(TestResult(Event.TIME_OVER, 0, 0.0).encode())
        assert runner.read_result() == TestResult(Event.TIME_OVER, 0, 0.0)
    finally:
        runner.close()


@pytest.mark.parametrize("text", [None, "", '{"event": "GOAL"}'])
def test_a_result_the_controller_cannot_read_is_the_benchs_fault(tmp_path, text):
    """No file, a torn one, one without its fields: PhysicsGone, which the bench turns into a bench fault."""
    Slots(tmp_path)
    runner = TestRunner(tmp_path)
    try:
        if text is not None:
            (tmp_path / RESULT_FILE).write_text(text)
        with pytest.raises(PhysicsGone, match="without its result"):
            runner.read_result()
    finally:
        runner.close()


@pytest.fixture
def straight_app(tmp_path) -> dict:
    (tmp_path / "straight_app.py").write_text(STRAIGHT_APP)
    return dict(os.environ, PYTHONPATH=os.pathsep.join([str(tmp_path), os.environ.get("PYTHONPATH", "")]))


@pytest.mark.slow
@pytest.mark.parametrize("lane", LANES)
def test_a_program_that_drives_straight_leaves_the_mat_and_the_run_ends_there(tmp_path, straight_app, lane):
    """It used to drive on for 17 m, until the time limit, and `--objective etrobocon` gave it points for it."""
    runs = {}
    for objective in ("lap", "etrobocon"):
        r = hako("try", "--course", lane, "--app", "straight_app:main_task", "--noise", "0", "--json",
                 "--objective", objective, "--run-dir", str(tmp_path / objective), env=straight_app, timeout=300)
        assert r.returncode == 0, r.stderr
        runs[objective] = json.loads(r.stdout)
    for result in runs.values():
        out = result["course_out"]
        assert result["event"] == "COURSE_OUT" and out["y_m"] == pytest.approx(1.82, abs=0.01)
        assert 3.2 < result["distance_m"] < 3.5 and 0 < out["time_s"] < 60  # from y = -1.5 to the edge
    score = runs["etrobocon"]["score"]
    assert (score["lap_gate"], score["finish"], score["lap_time_s"]) == (False, False, None)  # unfinished
    assert score["total"] == score["task_points"] == 2 * score["checkpoints"]  # no run points without the LAP
    log = (tmp_path / "etrobocon" / "physics.log").read_text()
    assert "COURSE_OUT" in log and "left the course at" in log and ": the mat" in log


LEFT_EDGE_START = ('[[place]]\nat_s = 0\nover = "start"\nedge = "left"\n'
                   '[[press]]\nsensor = "force"\nat_s = 1.0\nfor_s = 0.2\n')


@pytest.mark.slow
@pytest.mark.parametrize("lane", LANES)
def test_a_left_edge_tracer_set_down_on_the_left_edge_follows_the_line(tmp_path, lane):
    """The look-alike team program traces the line's left edge: set down there it drives up the start straight
    on the line (the lanes' first 1.9 m run north), through checkpoint 1; set down where the course's start
    puts the sensor, right of the line, it steers away at once."""
    need_cc()
    (tmp_path / "left.toml").write_text(LEFT_EDGE_START)
    runs = {}
    for name, scenario in (("left", tmp_path / "left.toml"), ("start", PROGRAMS / "scenarios" / "force-start.toml")):
        r = hako("try", "--course", lane, "--app", str(PROGRAMS / "spike_left_edge"), "--robot", "hackspi",
                 "--scenario", str(scenario), "--noise", "0", "--json", "--time-limit", "12",
                 "--run-dir", str(tmp_path / name), timeout=600)
        assert r.returncode == 0, r.stderr
        runs[name] = [line.split(",") for line in (tmp_path / name / "trajectory.csv").read_text().splitlines()[1:]]
    line_x = load_course(lane).start.x - 0.02  # both lanes start with the sensor 2 cm right of the line's centre
    on_line = [(float(x), float(y), float(yaw)) for t, x, y, yaw in runs["left"] if float(y) < 0.4]
    assert on_line[-1][1] > 0.3  # up the straight, past checkpoint 1 (y = -0.2)
    assert all(abs(x - line_x) < 0.03 and abs(yaw - 1.5708) < 0.2 for x, _, yaw in on_line)
    assert max(abs(float(yaw) - 1.5708) for _, _, _, yaw in runs["start"][:80]) > 1.0  # turned well away

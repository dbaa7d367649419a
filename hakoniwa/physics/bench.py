"""The world a bench serves: the course, the robot on it and the scenario of every test. Loaded once here,
so that the physics process and the commands that check a bench before starting one agree."""

from __future__ import annotations

import dataclasses

from hakoniwa.physics.course import Course, course_file, load_course
from hakoniwa.physics.course_check import check_course
from hakoniwa.physics.robots import Robot, load_robot
from hakoniwa.physics.scenario import Scenario, ScenarioError, load_scenario
from hakoniwa.wire.timebase import US_PER_S


def time_limit_us(course_limit_us: int, time_limit_s: float | None) -> int:
    """The simulated time a test may take: `time_limit_s` if one was given, else the course's. A campaign
    scores a failed test as this long, so the two can never disagree."""
    return course_limit_us if time_limit_s is None else round(time_limit_s * US_PER_S)


def load_world(course_name: str, robot_name: str | None, scenario_file: str | None,
               time_limit_s: float | None) -> tuple[Course, Robot, Scenario]:
    """The course (a built-in name or folder), the robot (a built-in name or TOML file; None: the default)
    and the scenario (a TOML file; None: none) of a bench whose tests may last `time_limit_s` (None: the
    course's limit).

    Raises CourseError, RobotError or ScenarioError, each one line: also for a course the robot cannot run
    (`course_check`) and a scenario whose stimuli come after the time limit, which no test would see."""
    course = load_course(course_name)
    robot = load_robot(robot_name)
    scenario = load_scenario(scenario_file)
    check_course(course, robot.body, course_file(course_name))
    scenario.check_within(time_limit_us(course.time_limit_us, time_limit_s))
    if robot.wiring is not None:
        course = dataclasses.replace(course, wiring=robot.wiring)
    for press in scenario.presses:
        if press.sensor is not None and robot.press_slot(press.sensor, press.port) is None:
            where = "" if press.port is None else f" on port {press.port}"
            what = "touch or force" if press.sensor == "touch" and robot.spike else press.sensor
            raise ScenarioError(f"scenario: robot {robot.name!r} has no {what} sensor{where} to press")
    return course, robot, scenario

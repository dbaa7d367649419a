"""The world a bench serves, from its options: the course, the robot on it and the scenario of every test.
Loaded once here, so that `hakoniwa-physics` and the commands that check a bench before starting one agree."""

from __future__ import annotations

import dataclasses

from hakoniwa.physics.course import Course, course_file, load_course
from hakoniwa.physics.course_check import check_course
from hakoniwa.physics.options import BenchOptions
from hakoniwa.physics.robots import Robot, load_robot
from hakoniwa.physics.scenario import Scenario, ScenarioError, load_scenario


def load_bench(options: BenchOptions) -> tuple[Course, Robot, Scenario]:
    """Raises CourseError, RobotError or ScenarioError, each one line: also for a course the robot cannot
    run (`course_check`) and a scenario whose stimuli come after the time limit, which no test would see."""
    course = load_course(options.course)
    robot = load_robot(options.robot)
    scenario = load_scenario(options.scenario)
    check_course(course, robot.body, course_file(options.course))
    scenario.check_within(options.time_limit_us(course.time_limit_us))
    if robot.wiring is not None:
        course = dataclasses.replace(course, wiring=robot.wiring)
    for press in scenario.presses:
        if press.sensor is not None and robot.press_slot(press.sensor, press.port) is None:
            where = "" if press.port is None else f" on port {press.port}"
            what = "touch or force" if press.sensor == "touch" and robot.spike else press.sensor
            raise ScenarioError(f"scenario: robot {robot.name!r} has no {what} sensor{where} to press")
    return course, robot, scenario

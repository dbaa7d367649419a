"""The world a bench serves, from its options: the course, the robot on it and the scenario of every test.
Loaded once here, so that `hakoniwa-physics` and the commands that check a bench before starting one agree."""

from __future__ import annotations

import dataclasses

from hakoniwa.physics.course import Course, course_file, load_course
from hakoniwa.physics.course_check import check_course
from hakoniwa.physics.options import BenchOptions
from hakoniwa.physics.placing import placements
from hakoniwa.physics.robots import Robot, load_robot
from hakoniwa.physics.scenario import Scenario, load_scenario


def load_bench(options: BenchOptions) -> tuple[Course, Robot, Scenario]:
    """Raises CourseError, RobotError or ScenarioError, each one line: also for a course the robot cannot
    run (`course_check`), a scenario whose stimuli come after the time limit, which no test would see, or that
    the robot cannot take (a place where it cannot stand, a button or sensor it does not have)."""
    course = load_course(options.course)
    robot = load_robot(options.robot)
    scenario = load_scenario(options.scenario)
    check_course(course, robot.body, course_file(options.course))
    scenario.check_within(options.time_limit_us(course.time_limit_us))
    if robot.wiring is not None:
        course = dataclasses.replace(course, wiring=robot.wiring)
    scenario.check_robot(robot)
    placements(course, robot.body, scenario)
    return course, robot, scenario

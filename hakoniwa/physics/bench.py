"""The world a bench serves: the course, the robot on it and the scenario of every test. Loaded once here,
so that the physics process and the commands that check a bench before starting one agree."""

from __future__ import annotations

import dataclasses

from hakoniwa.physics.course import Course, course_file, load_course
from hakoniwa.physics.course_check import check_course
from hakoniwa.physics.placing import placements
from hakoniwa.physics.robots import Robot, load_robot
from hakoniwa.physics.scenario import Scenario, load_scenario
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
    (`course_check`), a scenario whose stimuli come after the time limit, which no test would see, or that the
    robot cannot take (a place where it cannot stand, a button or sensor it does not have)."""
    course = load_course(course_name)
    robot = load_robot(robot_name)
    scenario = load_scenario(scenario_file)
    check_course(course, robot.body, course_file(course_name))
    scenario.check_within(time_limit_us(course.time_limit_us, time_limit_s))
    if robot.wiring is not None:
        course = dataclasses.replace(course, wiring=robot.wiring)
    scenario.check_robot(robot)
    placements(course, robot.body, scenario)
    return course, robot, scenario

"""An environment for a test of the physics alone: the world of a robot on a course and the task of an
objective, as the physics server makes them."""

from __future__ import annotations

from hakoniwa.physics.course import Course
from hakoniwa.physics.environment import Environment
from hakoniwa.physics.robots import DEFAULT_ROBOT, Robot
from hakoniwa.physics.scenario import Scenario
from hakoniwa.physics.world import World
from hakoniwa.wire.objective import DEFAULT, objective_named


def environment(course: Course, time_limit_us: int, robot: Robot = DEFAULT_ROBOT, scenario: Scenario = Scenario(),
                objective: str = DEFAULT) -> Environment:
    """`objective`: the key of the objective whose task scores the test."""
    return Environment(World(course, robot.body, imu=robot.spike),
                       objective_named(objective).task(course, time_limit_us), robot, scenario)

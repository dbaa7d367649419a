"""An environment for a test of the physics alone: the world of a robot on a course and the task of an
objective, as the physics server makes them."""

from __future__ import annotations

from hakoniwa.physics.course import Course
from hakoniwa.physics.environment import Environment
from hakoniwa.physics.robots import DEFAULT_ROBOT, Robot
from hakoniwa.physics.scenario import Scenario
from hakoniwa.physics.tasks import TASKS
from hakoniwa.physics.world import World
from hakoniwa.wire.protocol import Objective


def environment(course: Course, time_limit_us: int, robot: Robot = DEFAULT_ROBOT, scenario: Scenario = Scenario(),
                objective: Objective = Objective.LAP) -> Environment:
    return Environment(World(course, robot.body, imu=robot.spike), TASKS[objective](course, time_limit_us), robot,
                       scenario)

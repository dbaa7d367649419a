"""The paper's objective: GOAL at the course's last checkpoint, scored by the lap time (`--objective lap`)."""

from __future__ import annotations

from typing import TYPE_CHECKING

from hakoniwa.wire.objective import Objective
from hakoniwa.wire.protocol import Event

if TYPE_CHECKING:
    from hakoniwa.physics.course import Course
    from hakoniwa.physics.task import Task


def task(course: Course, time_limit_us: int) -> Task:
    from hakoniwa.physics.task import LapTask  # MuJoCo: in the physics process only, not in the controller

    return LapTask(course, time_limit_us)


OBJECTIVE = Objective("lap", Event.GOAL, task)

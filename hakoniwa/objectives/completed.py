"""ET Robocon's competition programs end their run with a completion notice
(`ETRoboc_notifyCompletedToSimulator()`): a test succeeds on COMPLETED and is scored by when the notice came
(`--objective completed`). The goal line does not end the test: the robot may drive on into the next lap."""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING

from hakoniwa.wire.objective import Objective
from hakoniwa.wire.protocol import Event
from hakoniwa.wire.result import TestResult

if TYPE_CHECKING:
    from hakoniwa.physics.course import Course
    from hakoniwa.physics.task import Task


def task(course: Course, time_limit_us: int) -> Task:
    from hakoniwa.physics.task import CompletedTask  # MuJoCo: in the physics process only

    return CompletedTask(course, time_limit_us)


@dataclass(frozen=True)
class Completed(Objective):
    def scored_time_us(self, r: TestResult) -> int:
        return r.completed_time_us


OBJECTIVE = Completed("completed", Event.COMPLETED, task)

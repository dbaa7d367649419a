"""ET Robocon's result points (`--objective etrobocon`): the LAP time, the gates, the sumo and the finish in the
garage, as `hakoniwa.physics.etrobocon_task` judges them. Every run that ends without a crash is scored (5.18:
a run that ends without the finish keeps the points it made: a robot off the course can no longer run, and the
referee ends its turn so); only a crash says nothing. The search minimises minus the score; a failed set has
no points."""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING

from hakoniwa.wire.measure import SCORE
from hakoniwa.wire.objective import Objective
from hakoniwa.wire.protocol import Event
from hakoniwa.wire.result import TestResult

if TYPE_CHECKING:
    from hakoniwa.physics.course import Course
    from hakoniwa.physics.task import Task

SCORED_EVENTS = (Event.FINISH, Event.TIME_OVER, Event.HIT_WALL, Event.COMPLETED, Event.COURSE_OUT)



def task(course: Course, time_limit_us: int) -> Task:
    from hakoniwa.physics.etrobocon_task import EtRoboconTask  # MuJoCo: in the physics process only

    return EtRoboconTask(course, time_limit_us)


@dataclass(frozen=True)
class EtRobocon(Objective):
    def success(self, r: TestResult) -> bool:
        return r.event in SCORED_EVENTS and r.score is not None

    def lap_time_s(self, r: TestResult) -> float | None:
        """The LAP gate's time (None if the run never reached it)."""
        return r.score.lap_time_s if self.success(r) and r.score is not None else None

    def cost(self, r: TestResult) -> float | None:
        return -r.score.total if self.success(r) and r.score is not None else None

    def set_value(self, mean_cost: float) -> float:
        return mean_cost  # points, not a time: no tick

    def failure_value(self, penalty_s: float) -> float:
        return 0.0


OBJECTIVE = EtRobocon("etrobocon", Event.FINISH, task, SCORE)

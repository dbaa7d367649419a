"""What scores a test of each objective (`--objective`), made for a course and a time limit: the task the
physics server gives its environment."""

from __future__ import annotations

from collections.abc import Callable

from hakoniwa.physics.course import Course
from hakoniwa.physics.etrobocon_task import EtRoboconTask
from hakoniwa.physics.task import CompletedTask, LapTask, Task
from hakoniwa.wire.protocol import Objective

TASKS: dict[Objective, Callable[[Course, int], Task]] = {
    task.objective: task for task in (LapTask, CompletedTask, EtRoboconTask)}

"""What a test is scored by: the task half of the dm_control split, given to the environment as an argument.

A task looks at the world at each event-check tick and never moves anything. `Task` is all the environment
and the physics server ask of one: `reset` at each test's start, `check` at each event tick (the event that
ends the test, or Event.NONE while it goes on), and what it reports (the checkpoints passed, the path driven,
its time limit and, under ET Robocon's score, the points). Each objective (`hakoniwa.objectives`) names its task:
`LapTask` (the paper's: GOAL at the last checkpoint, scored by the lap time), `CompletedTask` (ET Robocon's
competition programs end their run with a completion notice; the goal line is one more checkpoint) and
`etrobocon_task.EtRoboconTask` (the regulation's result points).

Every task ends a test where the robot leaves the course (COURSE_OUT, ET Robocon's コースアウト): past the
mat's edge or into an area the course marks out of bounds (`Course.left_at`); a course with walls round its
floor, as the oval's, ends it at the wall first (HIT_WALL).

Checkpoints are the paper's transparent squares; only the next one in order counts, so driving backwards over
the finish line first does not shorten a lap. Both tasks measure the path the robot drove, which says how far
a program got when it did not finish.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import ClassVar, Protocol

from hakoniwa.physics.course import Course
from hakoniwa.physics.world import World
from hakoniwa.wire.etrobocon_rules import Score
from hakoniwa.wire.protocol import Event


class Task(Protocol):
    """What scores a test: reset at its start, checked at each event tick, read for the report."""

    @property
    def time_limit_us(self) -> int:
        """The simulated time a test may take."""
        ...

    @property
    def passed_us(self) -> Sequence[int]:
        """When each checkpoint was passed, in order."""
        ...

    @property
    def distance_mm(self) -> int:
        """The path the robot drove so far."""
        ...

    def reset(self, start_xy: tuple[float, float] | None = None) -> None:
        """A new test, with the robot at `start_xy` (default: the course's start; a noisy test's start is
        jittered)."""
        ...

    def check(self, world: World, time_us: int, completed: bool = False) -> Event:
        """The event at `time_us`, Event.NONE while the test goes on; `completed`: the program has sent its
        completion notice (ET Robocon's `ETRoboc_notifyCompletedToSimulator()`)."""
        ...

    def carried(self, lifted_xy: tuple[float, float], set_xy: tuple[float, float]) -> None:
        """The robot was lifted at `lifted_xy` and set down at `set_xy` (a scenario's place): a carry is not
        driven."""
        ...

    def score(self, world: World, competition_class: str | None = None) -> Score | None:
        """ET Robocon's result points as they stand, by the points of `competition_class` (None: the course's);
        None from a task that scores no points."""
        ...


@dataclass
class LapTask:
    """One lap: GOAL at the course's last checkpoint, having passed every earlier one in order."""

    ends_at_goal: ClassVar[bool] = True  # False: passing the last checkpoint starts the next lap

    course: Course
    time_limit_us: int
    next_checkpoint: int = 0
    passed_us: list[int] = field(default_factory=list)
    distance_m: float = 0.0
    _last_xy: tuple[float, float] = (0.0, 0.0)

    def __post_init__(self) -> None:
        self.reset()

    def reset(self, start_xy: tuple[float, float] | None = None) -> None:
        self.next_checkpoint = 0
        self.passed_us.clear()
        self.distance_m = 0.0
        self._last_xy = start_xy or (self.course.start.x, self.course.start.y)

    @property
    def distance_mm(self) -> int:
        return round(self.distance_m * 1000)

    def score(self, world: World, competition_class: str | None = None) -> Score | None:
        return None  # a lap has no points

    def carried(self, lifted_xy: tuple[float, float], set_xy: tuple[float, float]) -> None:
        """The robot was lifted at `lifted_xy` and set down at `set_xy` (a scenario's place): its path counts to
        where it was lifted and goes on from where it was set down, as a carry is not driven distance."""
        self._walk(lifted_xy)
        self._last_xy = set_xy

    def _travel(self, world: World) -> tuple[float, float]:
        """Where the robot is now; the way there is added to the path driven."""
        x, y = world.position()
        self._walk((x, y))
        return x, y

    def _walk(self, xy: tuple[float, float]) -> None:
        self.distance_m += math.hypot(xy[0] - self._last_xy[0], xy[1] - self._last_xy[1])
        self._last_xy = xy

    def check(self, world: World, time_us: int, completed: bool = False) -> Event:
        """Wall contact wins over a goal seen at the same tick: a robot that crashes into the wall at the line
        has not finished cleanly; so does leaving the course (`Course.left_at`). A completion notice ends the
        test at the first check that raises nothing else."""
        x, y = self._travel(world)
        if world.touching_wall():
            return Event.HIT_WALL
        if self.course.left_at(x, y) is not None:
            return Event.COURSE_OUT
        checkpoints = self.course.checkpoints
        if checkpoints[self.next_checkpoint].contains(x, y):
            self.passed_us.append(time_us)
            self.next_checkpoint += 1
            if self.next_checkpoint == len(checkpoints):
                if self.ends_at_goal:
                    return Event.GOAL
                self.next_checkpoint = 0
        if time_us >= self.time_limit_us:
            return Event.TIME_OVER
        return Event.COMPLETED if completed else Event.NONE


@dataclass
class CompletedTask(LapTask):
    """A run the program ends itself (`--objective completed`): scored by when its completion notice came.
    The goal line is one more checkpoint, so the robot may drive on into the next lap."""

    ends_at_goal: ClassVar[bool] = False


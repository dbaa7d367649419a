"""The lap test: checkpoints passed in order, wall contact and the time limit, turned into one Event.

This is the task half of the dm_control split: it looks at the world at each event-check tick and never
moves anything. Checkpoints are the paper's transparent squares; only the next one in order counts, so
driving backwards over the finish line first does not shorten a lap. The task also measures the path the
robot drove, which says how far a program got when it did not finish.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

from hakoniwa.physics.course import Course
from hakoniwa.physics.world import World
from hakoniwa.wire.protocol import Event


@dataclass
class LapTask:
    course: Course
    time_limit_us: int
    ends_at_goal: bool = True  # False: passing the last checkpoint starts the next lap, and no GOAL is raised
    next_checkpoint: int = 0
    passed_us: list[int] = field(default_factory=list)
    distance_m: float = 0.0
    _last_xy: tuple[float, float] = (0.0, 0.0)

    def __post_init__(self) -> None:
        self.reset()

    def reset(self, start_xy: tuple[float, float] | None = None) -> None:
        """A new test, with the robot at `start_xy` (default: the course's start; a noisy test's start is
        jittered)."""
        self.next_checkpoint = 0
        self.passed_us.clear()
        self.distance_m = 0.0
        self._last_xy = start_xy or (self.course.start.x, self.course.start.y)

    def carried(self, lifted_xy: tuple[float, float], set_xy: tuple[float, float]) -> None:
        """The robot was lifted at `lifted_xy` and set down at `set_xy` (a scenario's place): its path counts to
        where it was lifted and goes on from where it was set down, as a carry is not driven distance."""
        self._walk(lifted_xy)
        self._last_xy = set_xy

    @property
    def passed(self) -> int:
        return len(self.passed_us)

    @property
    def distance_mm(self) -> int:
        return round(self.distance_m * 1000)

    def check(self, world: World, time_us: int) -> Event:
        """The event at `time_us` (Event.NONE while the test goes on). Wall contact wins over a goal seen at
        the same tick: a robot that crashes into the wall at the line has not finished cleanly."""
        x, y = world.position()
        self._walk((x, y))
        if world.touching_wall():
            return Event.HIT_WALL
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
        return Event.NONE

    def _walk(self, xy: tuple[float, float]) -> None:
        self.distance_m += math.hypot(xy[0] - self._last_xy[0], xy[1] - self._last_xy[1])
        self._last_xy = xy

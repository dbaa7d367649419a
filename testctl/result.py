"""What one test on the bench produced, as the controller reads it from `unity_mmap.bin`."""

from __future__ import annotations

from dataclasses import dataclass

from hakoniwa.protocol import Event


@dataclass(frozen=True)
class TestResult:
    """One test: the event the physics process reported and, for GOAL, the goal time.

    `goal_time_us` is 0 for every event but GOAL. `wall_s` is how long the test took in wall-clock time,
    which is informative only: the event and goal time never depend on it.
    """

    __test__ = False  # not a pytest class

    event: Event
    goal_time_us: int
    wall_s: float

    @property
    def success(self) -> bool:
        return self.event == Event.GOAL

    @property
    def lap_time_s(self) -> float | None:
        return self.goal_time_us / 1e6 if self.success else None

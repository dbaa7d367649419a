"""ET Robocon's run, scored as its regulation scores it (`--objective etrobocon`).

The task half of the dm_control split, as `task.py`'s lap is: it looks at the world at each event check and
never moves anything. A course's checkpoints are the competition's gates in the order the line passes them,
the last one the LAP gate; its `[score]` table names the garage, the sumo ring and the sumo bottle.

- At reset: nothing reached, the clock of a stop in the garage unset.
- At each event check: the path driven (as the lap task measures it), wall contact (HIT_WALL), leaving the
  course (COURSE_OUT: a run that ends so keeps the points it made, as 5.18 keeps them when the referee ends a
  turn whose robot can no longer run; it has no finish), each
  checkpoint reached once before the LAP gate, in any order and the way its arrow points where the course
  gives one (`heading_deg`; 5.12), the LAP gate (5.13, likewise; it does not end the
  run, which goes on to the tasks), the sumo bottle leaving the ring, and the finish: part of the robot in the
  garage with both wheels stopped for 3 s ends the run as FINISH (5.14). The time limit ends it as TIME_OVER,
  unless a stop in the garage began before it, which is then waited out.
- At the end (`score`): the result points of 5.6 with each component (`etrobocon_rules.Score`). The bottle
  is judged as the regulation judges it, when the points are given (5.15): wholly outside the ring, standing
  and still; and, as the issue that asked for it says, the robot must not have left with it: its axle was
  inside the ring when the bottle left.

Where the bench simplifies the regulation (a gate is reached when the robot's axle enters its box, not when
any part of the robot crosses its line; no flying start; no bottle delivery or rally), docs/DESIGN-NOTES.md
("ET Robocon's score") says so.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

from hakoniwa.physics.course import Box
from hakoniwa.physics.robot import CHASSIS_BACK_M
from hakoniwa.physics.task import LapTask
from hakoniwa.physics.world import World
from hakoniwa.wire.etrobocon_rules import FINISH_STOP_S, Score
from hakoniwa.wire.protocol import Event
from hakoniwa.wire.timebase import US_PER_S

STOPPED_RAD_S = 0.1  # a wheel turning slower than this is stopped (3 mm/s on HackSPi's wheel)
STILL_M_S = 0.01  # a bottle moving slower than this stands still


@dataclass
class EtRoboconTask(LapTask):
    """The lap task's path and checkpoint times (`passed_us`: each gate, checkpoint or LAP, when reached), and
    the competition's own judging."""

    _reached: set[int] = field(default_factory=set)
    _lap_us: int | None = None
    _stop_since_us: int | None = None
    _finished: bool = False
    _bottle_out: bool = False
    _left_with_robot_inside: bool = False

    def reset(self, start_xy: tuple[float, float] | None = None) -> None:
        """A new run, with the robot at `start_xy` (default: the course's start)."""
        super().reset(start_xy)
        self._reached.clear()
        self._lap_us = self._stop_since_us = None
        self._finished = self._bottle_out = self._left_with_robot_inside = False

    def check(self, world: World, time_us: int, completed: bool = False) -> Event:
        x, y = self._travel(world)
        if world.touching_wall():
            return Event.HIT_WALL
        if self.course.left_at(x, y) is not None:
            return Event.COURSE_OUT
        self._gates(world, x, y, time_us)
        self._sumo(world, x, y)
        if self._garage_stop(world, time_us):
            self._finished = True
            return Event.FINISH
        if time_us >= self.time_limit_us and self._stop_since_us is None:
            return Event.TIME_OVER
        return Event.COMPLETED if completed else Event.NONE

    def _gates(self, world: World, x: float, y: float, time_us: int) -> None:
        if self._lap_us is not None:
            return
        yaw = world.pose()[2]
        *checkpoints, lap = self.course.checkpoints
        for i, cp in enumerate(checkpoints):
            if i not in self._reached and _passes(cp, x, y, yaw):
                self._reached.add(i)
                self.passed_us.append(time_us)
        if _passes(lap, x, y, yaw):
            self._lap_us = time_us
            self.passed_us.append(time_us)

    def _sumo(self, world: World, x: float, y: float) -> None:
        spec = self.course.score
        if spec.sumo_ring is None or spec.sumo_bottle is None:
            return
        ring, bottle = self.course.zone(spec.sumo_ring), world.object_state(spec.sumo_bottle)
        out = not ring.contains(bottle.x, bottle.y, margin=self.course.object(spec.sumo_bottle).half_extent)
        if out and not self._bottle_out:
            self._left_with_robot_inside = ring.contains(x, y)
        self._bottle_out = out

    def _garage_stop(self, world: World, time_us: int) -> bool:
        """Whether the robot has now stood in the garage, stopped, for FINISH_STOP_S; a stop may begin only
        within the time limit."""
        garage = self.course.score.garage
        if garage is None:
            return False
        stopped = all(abs(w) < STOPPED_RAD_S for w in world.wheel_speeds())
        if not (stopped and self._in_zone(world, garage)):
            self._stop_since_us = None
            return False
        if self._stop_since_us is None:
            if time_us >= self.time_limit_us:
                return False
            self._stop_since_us = time_us
        return time_us - self._stop_since_us >= round(FINISH_STOP_S * US_PER_S)

    def _in_zone(self, world: World, name: str) -> bool:
        """Whether part of the robot is in the zone: its axle centre or a corner of its chassis."""
        zone = self.course.zone(name)
        x, y, yaw = world.pose()
        hx, hy, _ = world.body.chassis_half
        c, s = math.cos(yaw), math.sin(yaw)
        cx, cy = x - CHASSIS_BACK_M * c, y - CHASSIS_BACK_M * s
        points = [(x, y)] + [(cx + a * hx * c - b * hy * s, cy + a * hx * s + b * hy * c)
                             for a in (-1, 1) for b in (-1, 1)]
        return any(zone.contains(px, py) for px, py in points)

    def score(self, world: World, competition_class: str | None = None) -> Score:
        """The run's result points, as they stand now (at its end: the regulation's), by the points of
        `competition_class` (the robot's class; None: the course's)."""
        spec = self.course.score
        sumo = None
        if spec.sumo_ring is not None and spec.sumo_bottle is not None:
            bottle = world.object_state(spec.sumo_bottle)
            sumo = self._bottle_out and self._left_with_robot_inside and bottle.upright and bottle.speed < STILL_M_S
        return Score.of(competition_class or spec.competition_class, self._lap_us, len(self._reached),
                        self._finished, sumo)


def _passes(gate: Box, x: float, y: float, yaw: float) -> bool:
    """Whether the robot at (x, y) heading `yaw` [rad] passes `gate`: in its box, and facing the way its arrow
    points (5.12, 5.13: a gate counts only when passed in the arrow's direction), if it has one."""
    if not gate.contains(x, y):
        return False
    return gate.heading_deg is None or math.cos(yaw - math.radians(gate.heading_deg)) > 0

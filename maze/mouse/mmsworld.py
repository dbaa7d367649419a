"""The world an mms mouse program lives in: its pose in the true maze, what it has been told, and mms's statistics.

Follows mms's own rules (src/Window.cpp, Stats.cpp): the pose is a half-cell point and one of eight headings;
a wall query looks one half-step ahead (after N-1 half-steps in the queried direction) and a post or the far side
of a corner counts as a wall; a move goes as far as it can and answers `crash` if it was stopped; mms's score
is best run turns + best run effective distance + 0.1 x (total turns + total effective distance), 2000 until a
run reaches the goal. What the program learns is kept as the firmware's wall log would keep it: each wall the
first time an answer reveals it, in order (`records`); its own `setWall`/`clearWall` marks are its belief.
"""

from __future__ import annotations

from dataclasses import dataclass, field

from ..direction import ALONG, NORTH, STEP, opposite, rotate
from ..log.wallrecord import WallRecord
from ..model import Cell, Maze, point_side, point_wall
from ..timing.motion import SearchRun, search_counts
from ..timing.mouseparams import MouseParams
from .marks import CLEAR_ALL, Mark
from .mms import Command

START_POINT = (1, 1)  # the centre of cell (0, 0), in half cells
UNSOLVED_SCORE = 2000.0
RESET_PENALTY = 15.0  # effective distance mms adds to the next run after a reset
# the heading each wall query looks in, in eighths of a turn from the mouse's heading
QUERY_TURN = {"wallFront": 0, "wallLeft": 2, "wallRight": -2, "wallBack": 4, "wallFrontLeft": 1,
              "wallFrontRight": -1, "wallBackLeft": 3, "wallBackRight": -3}
TURN = {"turnLeft": 2, "turnLeft90": 2, "turnRight": -2, "turnRight90": -2, "turnLeft45": 1, "turnRight45": -1}


def effective_distance(half_steps: int) -> float:
    """mms's discount for a long straight issued as one command."""
    return half_steps / 2 + 1 if half_steps > 2 else float(half_steps)


def fmt(value: float) -> str:
    """A number as mms prints it (Qt's QString::number: up to six significant digits)."""
    return f"{value:.6g}"


@dataclass
class MmsStats:
    """mms's scorekeeping (Stats.cpp)."""

    total_distance: int = 0
    total_turns: int = 0
    total_effective: float = 0.0
    current_distance: int = 0
    current_turns: int = 0
    current_effective: float = 0.0
    best: tuple[int, int, float] | None = None  # distance, turns, effective distance of the best run
    started: bool = False
    penalty: float = 0.0

    def add_distance(self, half_steps: int) -> None:
        eff = effective_distance(half_steps)
        self.total_distance += half_steps
        self.total_effective += eff
        if self.started:
            self.current_distance += half_steps
            self.current_effective += eff

    def add_turn(self) -> None:
        self.total_turns += 1
        if self.started:
            self.current_turns += 1

    def start_run(self) -> None:
        self.current_distance = self.current_turns = 0
        self.current_effective = self.penalty
        self.total_effective += self.penalty
        self.penalty = 0.0
        self.started = True

    def finish_run(self) -> None:
        self.started = False
        run = (self.current_distance, self.current_turns, self.current_effective)
        if self.best is None or run[1] + run[2] < self.best[1] + self.best[2]:
            self.best = run

    @property
    def score(self) -> float:
        if self.best is None:
            return UNSOLVED_SCORE
        return self.best[1] + self.best[2] + 0.1 * (self.total_effective + self.total_turns)

    def value(self, name: str) -> str:
        best = {"best-run-distance": 0, "best-run-turns": 1, "best-run-effective-distance": 2}
        if name in best:
            return "-1" if self.best is None else fmt(self.best[best[name]])
        return fmt({"total-distance": self.total_distance, "total-turns": self.total_turns,
                    "current-run-distance": self.current_distance, "current-run-turns": self.current_turns,
                    "total-effective-distance": self.total_effective,
                    "current-run-effective-distance": self.current_effective, "score": self.score}[name])


@dataclass
class MmsWorld:
    truth: Maze
    mouse: MouseParams
    reset_at: tuple[int, ...] = ()  # steps (cells entered) at which the Reset button is pressed
    point: tuple[int, int] = START_POINT
    heading: int = NORTH
    steps: int = 0  # cells entered
    turns: int = 0  # for the time model: 90-degree turns in a cell; a turn-back counts two
    pivots: int = 0
    resets: int = 0
    stats: MmsStats = field(default_factory=MmsStats)
    warnings: list[str] = field(default_factory=list)
    marks: list[Mark] = field(default_factory=list)

    def __post_init__(self) -> None:
        size = self.truth.size
        self.sensed = Maze.unknown(size, self.truth.goals)
        self.records: list[WallRecord] = []
        self.belief: list[WallRecord] = []
        self.trace: list[Cell] = [(0, 0)]
        self.was_reset = False
        self.records_at_first_reset = 0  # the sensed log's length when the first reset happened (--power-cut)
        self._pending_resets = sorted(self.reset_at)
        self._last_move: int | None = None  # heading of the last cell-to-cell move, for the time model
        self._goals = set(self.truth.goals)

    # -- what the simulator answers ----------------------------------------------------------------------------
    def handle(self, cmd: Command) -> str | None:
        name = cmd.name
        if name in QUERY_TURN:
            ahead = (1 if cmd.count is None else cmd.count) - 1
            return "true" if self._blocked(rotate(self.heading, QUERY_TURN[name]), ahead, record=True) else "false"
        if name in ("moveForward", "moveForwardHalf"):
            half_steps = (1 if cmd.count is None else cmd.count) * (2 if name == "moveForward" else 1)
            return "ack" if self._move(half_steps) else "crash"
        if name in TURN:
            self.heading = rotate(self.heading, TURN[name])
            self.stats.add_turn()
            return "ack"
        if name in ("mazeWidth", "mazeHeight"):
            return str(self.truth.size)
        if name == "wasReset":
            return "true" if self.was_reset else "false"
        if name == "ackReset":
            self._ack_reset()
            return "ack"
        if name == "getStat":
            return self.stats.value(cmd.stat)
        self._mark(cmd)
        return None

    def _mark(self, cmd: Command) -> None:
        name = cmd.name
        if name in ("clearAllColor", "clearAllText"):
            self.marks.append(Mark(len(self.records), CLEAR_ALL, *(("", None) if "Color" in name else (None, ""))))
            return
        if not self.truth.inside(cmd.x, cmd.y):
            self.warnings.append(f"{name} {cmd.x} {cmd.y}: outside the {self.truth.size}x{self.truth.size} maze "
                                 f"(ignored, as mms does)")
            return
        cell = (cmd.x, cmd.y)
        if name in ("setWall", "clearWall"):
            self.belief.append(WallRecord(cmd.x, cmd.y, cmd.direction, name == "setWall"))
        elif name in ("setColor", "clearColor"):
            self.marks.append(Mark(len(self.records), cell, colour=cmd.colour if name == "setColor" else ""))
        else:
            self.marks.append(Mark(len(self.records), cell, text=cmd.text if name == "setText" else ""))

    # -- geometry -----------------------------------------------------------------------------------------------
    def _wall_at(self, point: tuple[int, int], heading: int, record: bool) -> bool:
        """mms's isWall: what lies one half-step from `point` in `heading`: a post is a wall, a cell's centre
        is not, a wall midpoint is what the maze has there (nothing beyond the outer edge)."""
        qx, qy = point[0] + STEP[heading][0], point[1] + STEP[heading][1]
        if qx % 2 == 0 and qy % 2 == 0:
            return True
        w = point_wall(self.truth.size, qx, qy)
        if w is None:
            return False
        present = bool(self.truth.wall[w])
        if record and not self.sensed.known[w]:
            x, y, d = point_side(self.truth.size, point, (qx, qy))
            self.sensed.set(x, y, d, present)
            self.records.append(WallRecord(x, y, d, present))
        return present

    def _blocked(self, heading: int, ahead: int, record: bool) -> bool:
        point = self.point
        for i in range(max(ahead, 0) + 1):
            if i:
                point = (point[0] + STEP[heading][0], point[1] + STEP[heading][1])
                if not (0 <= point[0] <= 2 * self.truth.size and 0 <= point[1] <= 2 * self.truth.size):
                    return False
            if self._wall_at(point, heading, record):
                return True
        return False

    def _move(self, half_steps: int) -> bool:
        if half_steps < 1 or self._blocked(self.heading, 0, record=False):
            return False
        allowed = 1
        while allowed < half_steps and not self._blocked(self.heading, allowed, record=False):
            allowed += 1
        if self._cell() == (0, 0):
            self.stats.start_run()
        self.stats.add_distance(half_steps)
        dx, dy = STEP[self.heading]
        for _ in range(allowed):
            self.point = (self.point[0] + dx, self.point[1] + dy)
            if self.point[0] % 2 and self.point[1] % 2:
                self._entered(self._cell())
        here = self._cell()
        if here in self._goals:
            self.stats.finish_run()
        elif here == (0, 0):
            self.stats.started = False
        return allowed == half_steps

    def _cell(self) -> Cell:
        return self.point[0] // 2, self.point[1] // 2

    def _entered(self, cell: Cell) -> None:
        last = self.trace[-1]
        step = (cell[0] - last[0], cell[1] - last[1])
        move = next((h for h in ALONG if STEP[h] == step), None)
        if move is not None and self._last_move is not None and move != self._last_move:
            if move == opposite(self._last_move):
                self.pivots += 1
                self.turns += 2
            else:
                self.turns += 1
        self._last_move = move
        self.trace.append(cell)
        self.steps += 1
        if self._pending_resets and self.steps >= self._pending_resets[0]:
            self._pending_resets.pop(0)
            self.was_reset = True
            if not self.resets:
                self.records_at_first_reset = len(self.records)
            self.resets += 1

    def _ack_reset(self) -> None:
        self.point, self.heading = START_POINT, NORTH
        self.was_reset = False
        self.stats.penalty = RESET_PENALTY
        self.stats.started = False
        self.trace.append((0, 0))
        self._last_move = None

    # -- our own figures ----------------------------------------------------------------------------------------
    def search(self) -> SearchRun:
        """The search under our time model; a turn-back's pivot and a diagonal are priced as the built-in
        strategies' are (a jump back to the start after a reset is not a move)."""
        if not self.steps:
            return SearchRun(0.0, 0.0, 0, 0, 0)
        return search_counts(self.steps, self.turns - 2 * self.pivots, self.pivots, self.mouse)

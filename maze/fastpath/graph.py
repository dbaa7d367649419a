"""What the move graph is, apart from how it is built (maze/fastpath/build.py in numpy, maze/fastpath/kernel.c in C):
its layers, the turns' shapes, each heading's steps and the prices of its straights, the start's edges and the
constants of a query (maze/fastpath/query.py says what they do). Free of numpy, so that the compiled kernel's
queries (maze/fastpath/native.py) import none.
"""

from __future__ import annotations

from dataclasses import dataclass
from math import ceil

from ..direction import ALONG, STEP, opposite
from ..model import Cell, sides_of
from ..timing.motion import HALF_DIAGONAL, straight_seconds
from ..timing.mouseparams import MouseParams

LAYERS = 4  # A, B, G, C
A, B, G, C = range(LAYERS)
MIN_SECONDS = 1e-9  # zero-length straights still need an edge, and scipy drops zero weights
MAX_CROSSINGS = 4  # the most walls a turn crosses (the 180)


@dataclass(frozen=True, order=True)
class TurnShape:
    """A turn placed with its entry point at the origin; `offsets` are the walls it crosses, the last one the exit."""

    name: str
    side: str  # "R" or "L"
    h_in: int
    h_out: int
    x_parity: int  # X % 2 of the entry point: 1 when it enters across a horizontal wall
    offsets: tuple[tuple[int, int], ...]

    @property
    def token(self) -> str:
        return self.side + self.name

    def rotated(self) -> TurnShape:
        """90 degrees anticlockwise: (x, y) -> (-y, x) swaps which walls are horizontal."""
        return TurnShape(self.name, self.side, (self.h_in + 2) % 8, (self.h_out + 2) % 8, 1 - self.x_parity,
                         tuple((-y, x) for x, y in self.offsets))

    def mirrored(self) -> TurnShape:
        return TurnShape(self.name, "L" if self.side == "R" else "R", (4 - self.h_in) % 8, (4 - self.h_out) % 8,
                         self.x_parity, tuple((-x, y) for x, y in self.offsets))

    def reversed(self) -> TurnShape:
        """The same curve run backwards (a 45 out of a diagonal is a 45 into one, run from its far end)."""
        ex, ey = self.offsets[-1]
        points = [(x - ex, y - ey) for x, y in self.offsets[-2::-1]] + [(-ex, -ey)]
        return TurnShape(self.name, "L" if self.side == "R" else "R", opposite(self.h_out), opposite(self.h_in),
                         (self.x_parity + ex) % 2, tuple(points))


# Right-hand turns entering northwards across a horizontal wall at (0, 0) (the V90: north-east across a
# vertical wall, turning left round the post at (1, 1)). The others are their rotations, mirror images and
# reversals.
ALONG_TURNS = (
    TurnShape("90s", "R", 2, 0, 1, ((1, 1),)),
    TurnShape("90", "R", 2, 0, 1, ((0, 2), (1, 3), (3, 3))),
    TurnShape("180", "R", 2, 6, 1, ((0, 2), (1, 3), (2, 2), (2, 0))),
)
DIAGONAL_TURNS = (
    TurnShape("45", "R", 2, 1, 1, ((0, 2), (1, 3))),
    TurnShape("135", "R", 2, 7, 1, ((0, 2), (1, 3), (2, 2))),
    TurnShape("V90", "L", 1, 3, 0, ((1, 1), (0, 2))),
)


def turn_shapes(diagonal: bool) -> list[TurnShape]:
    shapes: set[TurnShape] = set()
    for base in ALONG_TURNS + (DIAGONAL_TURNS if diagonal else ()):
        for shape in (base, base.reversed()):
            for _ in range(4):
                shape = shape.rotated()
                shapes.update((shape, shape.mirrored()))
    return sorted(shapes)


def entered_cell(point: tuple[int, int], previous: tuple[int, int]) -> Cell:
    """The cell on the far side of the wall at `point` for a mouse coming from `previous`."""
    x, y, _ = sides_of(point, previous)[1]
    return x, y


def stride(h: int) -> tuple[int, int]:
    """Half-cell points from one wall crossed in heading h to the next."""
    dx, dy = STEP[h]
    return (2 * dx, 2 * dy) if h in ALONG else (dx, dy)


def unit(h: int) -> float:
    """Cells per step in heading h."""
    return 1.0 if h in ALONG else HALF_DIAGONAL


def top_speed(mouse: MouseParams, h: int) -> float:
    return mouse.run.top_speed if h in ALONG else mouse.run.diagonal_top_speed


def chain_steps(mouse: MouseParams, h: int) -> int:
    """Steps a straight in heading h needs to reach top speed from turn speed (and to brake back)."""
    run, top = mouse.run, top_speed(mouse, h)
    step = unit(h) * mouse.cell
    d_up = (top * top - run.turn_speed ** 2) / (2 * run.accel)
    k = max(1, ceil(d_up / step))
    return k + 1 if k * step < d_up else k


def straight_prices(mouse: MouseParams, h: int, n: int) -> tuple[float, float]:
    """A straight of n steps in heading h from turn speed: braking back to turn speed, and free over the goal
    line."""
    run, top = mouse.run, top_speed(mouse, h)
    metres = n * unit(h) * mouse.cell
    return (max(MIN_SECONDS, straight_seconds(metres, run.turn_speed, run.turn_speed, top, run.accel)),
            max(MIN_SECONDS, straight_seconds(metres, run.turn_speed, None, top, run.accel)))


def chain_prices(mouse: MouseParams, h: int) -> tuple[float, float]:
    """The chain's (fastpath.build.StaticGraph._build_chain) k steps speeding up (braking costs the same), and
    one step at top speed."""
    run, top = mouse.run, top_speed(mouse, h)
    step = unit(h) * mouse.cell
    return straight_seconds(chain_steps(mouse, h) * step, run.turn_speed, None, top, run.accel), step / top


@dataclass
class StartEdge:
    """A straight from a standing start in the start cell's centre: it needs its first wall open and
    `open_needed` open walls after it, ahead of node `run_from`."""

    dst: int
    run_from: int
    open_needed: int
    first_wall: int
    seconds: float


def start_edges(size: int, wall_at: list[int], mouse: MouseParams, start: Cell, goals: tuple[Cell, ...]) \
        -> list[StartEdge]:
    """Straights from a standing start in the start cell's centre, along each of its four headings, of every
    length: the n-th needs the first wall open and n - 1 open ones after it. `wall_at`: the wall at each point."""
    p = mouse.run
    side = 2 * size + 1
    layer_size = 8 * side ** 2
    cx, cy = 2 * start[0] + 1, 2 * start[1] + 1
    out: list[StartEdge] = []
    goal_set = set(goals)
    for h in ALONG:
        dx, dy = STEP[h]
        first = (cy + dy) * side + cx + dx
        for n in range(1, 2 * size + 1):
            x, y = cx + (2 * n - 1) * dx, cy + (2 * n - 1) * dy
            if not (0 <= x < side and 0 <= y < side):
                break
            node = (y * side + x) * 8 + h
            metres = (n - 0.5) * mouse.cell
            ends = [(node + B * layer_size, straight_seconds(metres, 0.0, p.turn_speed, p.top_speed, p.accel))]
            if entered_cell((x, y), (x - dx, y - dy)) in goal_set:
                ends.append((node + G * layer_size, straight_seconds(metres, 0.0, None, p.top_speed, p.accel)))
            out += [StartEdge(end, first * 8 + h, n - 1, wall_at[first], seconds) for end, seconds in ends]
    return out


MAX_QUERY_GRAPHS = 4  # (start, goals) pairs kept per move graph: a search has one, `path` of a cell run another
TIME_SLACK = 1e-9  # rounding in reduced prices must not leave out a node of an equally fast route
LIMIT_GROWTH = 2.0  # how much the search limit grows when the goal lies beyond it
HINT_MARGIN = 1.25  # the first limit over the last answer: a search's walls only ever make its run slower
NARROW_FROM = 1000  # kept nodes: narrowing them costs about 0.1 ms, the exact search 0.3 us a node it spares
LIMIT_TRIES = 16  # then no limit: a route that slow is unlikely, and without one the goal may be out of reach


def first_limit_floor(mouse: MouseParams) -> float:
    """The least first limit of A*: one cell at top speed."""
    return mouse.cell / mouse.run.top_speed

"""An N x N maze whose every wall is either known (present/absent) or unknown.

Walls are numbered once (a wall between two cells is one wall, not two sides), so a record about the
east side of (x, y) and one about the west side of (x+1, y) touch the same bit.
"""

from __future__ import annotations

from collections.abc import Iterator
from functools import cache
from typing import NamedTuple

from .direction import DELTA, DIRECTIONS, EAST, NORTH, SOUTH, WEST
from .errors import MazeError
from .log.wallrecord import COORD_LIMIT

Cell = tuple[int, int]


class Topology(NamedTuple):
    """Per-size lookup tables; flat cell index c = y * N + x. Shared by every maze of that size."""

    size: int
    wall_count: int
    cell_walls: tuple[tuple[int, ...], ...]  # c -> wall id per DIRECTIONS entry
    neighbours: tuple[tuple[int, ...], ...]  # c -> neighbour index per DIRECTIONS entry, -1 outside
    outer: frozenset[int]
    passages: tuple[tuple[tuple[int, int], ...], ...]  # c -> (wall id, neighbour) through each inner wall


def wall_id(size: int, x: int, y: int, d: int) -> int:
    """Horizontal walls first (south of row y, y = 0..N), then vertical ones (west of column x, x = 0..N)."""
    if d == SOUTH:
        return y * size + x
    if d == NORTH:
        return (y + 1) * size + x
    vertical = size * (size + 1)
    if d == WEST:
        return vertical + y * (size + 1) + x
    if d == EAST:
        return vertical + y * (size + 1) + x + 1
    raise MazeError(f"direction {d} is not a wall direction")


def point_wall(size: int, px: int, py: int) -> int | None:
    """The wall whose midpoint is the half-cell point (px, py) (X + Y odd), else None (a centre or a post)."""
    if (px + py) % 2 == 0 or not (0 <= px <= 2 * size and 0 <= py <= 2 * size):
        return None
    if px % 2:  # horizontal wall: the south side of row py // 2 (the north edge: of the top row)
        return wall_id(size, px // 2, py // 2, SOUTH) if py < 2 * size else wall_id(size, px // 2, size - 1, NORTH)
    return wall_id(size, px // 2, py // 2, WEST) if px < 2 * size else wall_id(size, size - 1, py // 2, EAST)


def sides_of(mid: tuple[int, int], came_from: tuple[int, int]) -> tuple[tuple[int, int, int], tuple[int, int, int]]:
    """The two cells beside the wall at half-cell midpoint `mid`, as (x, y, direction of that wall from the cell):
    first the one on `came_from`'s side, then the one beyond (either may lie outside the maze)."""
    mx, my = mid
    if mx % 2:  # horizontal wall
        below, above = (mx // 2, my // 2 - 1, NORTH), (mx // 2, my // 2, SOUTH)
        return (below, above) if came_from[1] < my else (above, below)
    left, right = (mx // 2 - 1, my // 2, EAST), (mx // 2, my // 2, WEST)
    return (left, right) if came_from[0] < mx else (right, left)


def point_side(size: int, came_from: tuple[int, int], mid: tuple[int, int]) -> tuple[int, int, int]:
    """The wall at `mid` as a side of the cell on `came_from`'s side of it (the other cell when that one is
    outside the maze): how a mouse that sensed it would log it."""
    near, far = sides_of(mid, came_from)
    return near if 0 <= near[0] < size and 0 <= near[1] < size else far


@cache
def topology(size: int) -> Topology:
    cell_walls, neighbours, outer = [], [], set()
    for y in range(size):
        for x in range(size):
            walls, nbrs = [], []
            for d in DIRECTIONS:
                w = wall_id(size, x, y, d)
                nx, ny = x + DELTA[d][0], y + DELTA[d][1]
                inside = 0 <= nx < size and 0 <= ny < size
                walls.append(w)
                nbrs.append(ny * size + nx if inside else -1)
                if not inside:
                    outer.add(w)
            cell_walls.append(tuple(walls))
            neighbours.append(tuple(nbrs))
    passages = tuple(tuple((w, m) for w, m in zip(walls, nbrs) if m >= 0)
                     for walls, nbrs in zip(cell_walls, neighbours))
    return Topology(size, 2 * size * (size + 1), tuple(cell_walls), tuple(neighbours), frozenset(outer), passages)


def inner_wall_count(size: int) -> int:
    """Walls a log may have to record (the seed's N*(N-1)*2): the outer ones are known from the start."""
    return size * (size - 1) * 2


def central_goals(size: int) -> tuple[Cell, ...]:
    """The contest goal when a file marks none: the central 2x2 (or the centre cell of an odd maze)."""
    lo, hi = (size - 1) // 2, size // 2
    return tuple((x, y) for y in sorted({lo, hi}) for x in sorted({lo, hi}))


def goals_text(goals: tuple[Cell, ...]) -> str:
    """Goal cells as the commands print them: `(7,7) (8,7) ...` (`--goal` takes each as X,Y)."""
    return " ".join(f"({x},{y})" for x, y in goals)


class Maze:
    def __init__(self, size: int, start: Cell = (0, 0), goals: tuple[Cell, ...] = ()) -> None:
        if not 1 <= size <= COORD_LIMIT:
            raise MazeError(f"maze size {size} out of range 1-{COORD_LIMIT}")
        self.size = size
        self.topo = topology(size)
        self.start = start
        self.goals = goals
        self.wall = bytearray(self.topo.wall_count)
        self.known = bytearray(self.topo.wall_count)
        for w in self.topo.outer:
            self.wall[w] = self.known[w] = 1

    @classmethod
    def unknown(cls, size: int, goals: tuple[Cell, ...] = ()) -> Maze:
        """The state after a reset: outer walls known, and the start cell closed on three sides (contest rule)."""
        m = cls(size, (0, 0), goals)
        if size > 1:
            m.set(0, 0, EAST, True)
            m.set(0, 0, NORTH, False)
        return m

    def inside(self, x: int, y: int) -> bool:
        return 0 <= x < self.size and 0 <= y < self.size

    def wid(self, x: int, y: int, d: int) -> int:
        if not self.inside(x, y):
            raise MazeError(f"cell ({x}, {y}) is outside the {self.size}x{self.size} maze")
        return wall_id(self.size, x, y, d)

    def is_outer(self, x: int, y: int, d: int) -> bool:
        return self.wid(x, y, d) in self.topo.outer

    def is_wall(self, x: int, y: int, d: int) -> bool:
        return bool(self.wall[self.wid(x, y, d)])

    def is_known(self, x: int, y: int, d: int) -> bool:
        return bool(self.known[self.wid(x, y, d)])

    def set(self, x: int, y: int, d: int, present: bool) -> None:
        w = self.wid(x, y, d)
        if w in self.topo.outer and not present:
            raise MazeError(f"the outer wall {d} of ({x}, {y}) cannot be removed")
        self.wall[w], self.known[w] = int(present), 1

    def forget(self, x: int, y: int, d: int) -> None:
        w = self.wid(x, y, d)
        if w not in self.topo.outer:
            self.wall[w] = self.known[w] = 0

    def update(self, x: int, y: int, d: int, present: bool) -> bool:
        """Apply a sighting as the seed's library does: a contradiction makes the wall unknown again.

        Returns False on a contradiction, since the caller may want to count misreads.
        """
        w = self.wid(x, y, d)
        if self.known[w]:
            if bool(self.wall[w]) != present:
                self.forget(x, y, d)
                return False
            return True
        self.set(x, y, d, present)
        return True

    def cell_known(self, c: int) -> bool:
        k, (e, n, w, s) = self.known, self.topo.cell_walls[c]  # unrolled: the explorer asks this a lot
        return bool(k[e] and k[n] and k[w] and k[s])

    def inner_walls(self) -> Iterator[tuple[int, int, int]]:
        """Each inner wall once, as the east or north side of a cell, in row-major order."""
        n = self.size
        for y in range(n):
            for x in range(n):
                if x < n - 1:
                    yield x, y, EAST
                if y < n - 1:
                    yield x, y, NORTH

    def known_inner(self) -> int:
        return sum(self.known[self.wid(x, y, d)] for x, y, d in self.inner_walls())

    def same_walls(self, other: Maze) -> bool:
        return self.size == other.size and self.wall == other.wall and self.known == other.known

    def cell_index(self, cell: Cell) -> int:
        return cell[1] * self.size + cell[0]

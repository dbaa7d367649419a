"""The two other maze formats mms users have: mms's `.num` text (one line per cell: `X Y N E S W`, 1 = wall) and
the 256-byte binary `.maz` of the classic 16x16 collections (one byte per cell, column by column, bits
1 north, 2 east, 4 south, 8 west). Both formats give each inner wall twice, once from each cell beside it; a wall
either side of which is marked is a wall, and one marked on one side only (a damaged or hand-made file) is a
warning, or with `strict` an error, since the file then says two things about it. Outer walls are always closed.
"""

from __future__ import annotations

from collections.abc import Callable
from math import isqrt

from ..direction import DELTA, EAST, NORTH, SOUTH, WEST, opposite
from ..errors import MazeError
from ..log.wallrecord import COORD_LIMIT
from ..model import Maze
from ..search.stepmap import default_goals

MAZ_SIDE = 16
MAZ_BYTES = MAZ_SIDE * MAZ_SIDE
MAZ_BITS = ((1, NORTH), (2, EAST), (4, SOUTH), (8, WEST))
NUM_ORDER = (NORTH, EAST, SOUTH, WEST)
SIDE_NAMES = {EAST: "east", NORTH: "north", WEST: "west", SOUTH: "south"}

Warn = Callable[[str], None]
Side = tuple[int, int, int]  # a cell and one of its walls, as the file marks it


def one_sided(size: int, marked: set[Side]) -> list[tuple[Side, Side]]:
    """Each inner wall that one of its two cells marks and the other does not: (the marking side, the other)."""
    found = []
    for x, y, d in Maze(size).inner_walls():
        dx, dy = DELTA[d]
        here, there = (x, y, d), (x + dx, y + dy, opposite(d))
        if (here in marked) != (there in marked):
            found.append((here, there) if here in marked else (there, here))
    return found


def _build(size: int, marked: set[Side], strict: bool, warn: Warn | None) -> Maze:
    """The maze whose walls are those either side marks; one-sided walls are reported (or refused if strict)."""
    maze = Maze(size)
    for x, y, d in maze.inner_walls():
        dx, dy = DELTA[d]
        maze.set(x, y, d, (x, y, d) in marked or (x + dx, y + dy, opposite(d)) in marked)
    disagree = one_sided(size, marked)
    if disagree:
        (x, y, d), (ox, oy, od) = disagree[0]
        n = len(disagree)
        message = (f"{n} wall{'s' * (n > 1)} marked by one of {'their' if n > 1 else 'its'} two cells only "
                   f"(first: cell ({x}, {y}) marks its {SIDE_NAMES[d]} wall, cell ({ox}, {oy}) not its "
                   f"{SIDE_NAMES[od]} wall)")
        if strict:
            raise MazeError(f"{message}: refused with --strict")
        if warn is not None:
            warn(f"{message}: taken as walls")
    maze.goals = default_goals(maze)
    return maze


def parse_maz(data: bytes, strict: bool = False, warn: Warn | None = None) -> Maze:
    if len(data) != MAZ_BYTES:
        raise MazeError(f"a .maz file is {MAZ_BYTES} bytes (16x16, one per cell), this one is {len(data)}")
    marked = {(x, y, d) for i, byte in enumerate(data) for x, y in [divmod(i, MAZ_SIDE)]
              for bit, d in MAZ_BITS if byte & bit}
    return _build(MAZ_SIDE, marked, strict, warn)


def dump_maz(maze: Maze) -> bytes:
    if maze.size != MAZ_SIDE:
        raise MazeError(f"a .maz file holds a 16x16 maze, not {maze.size}x{maze.size}")
    return bytes(sum(bit for bit, d in MAZ_BITS if maze.is_wall(x, y, d))
                 for x in range(MAZ_SIDE) for y in range(MAZ_SIDE))


def parse_num(text: str, strict: bool = False, warn: Warn | None = None) -> Maze:
    cells: dict[tuple[int, int], tuple[int, ...]] = {}
    for lineno, raw in enumerate(text.splitlines(), 1):
        words = raw.split()
        if not words:
            continue
        if len(words) != 6 or not all(w.lstrip("-").isdigit() for w in words):
            raise MazeError(f"line {lineno}: expected 'X Y N E S W' (six integers), got {raw.strip()!r}")
        x, y, *walls = (int(w) for w in words)
        if any(w not in (0, 1) for w in walls):
            raise MazeError(f"line {lineno}: walls are 0 or 1, got {' '.join(words[2:])}")
        if not (0 <= x < COORD_LIMIT and 0 <= y < COORD_LIMIT):
            raise MazeError(f"line {lineno}: cell ({x}, {y}) is outside 0-{COORD_LIMIT - 1}")
        if (x, y) in cells:
            raise MazeError(f"line {lineno}: cell ({x}, {y}) a second time")
        cells[(x, y)] = tuple(walls)
    if not cells:
        raise MazeError("line 1: empty .num file")
    size = isqrt(len(cells))
    if size * size != len(cells) or any(not (x < size and y < size) for x, y in cells):
        raise MazeError(f"{len(cells)} cells do not make a square maze with every cell listed once")
    marked = {(x, y, d) for (x, y), walls in cells.items() for d, wall in zip(NUM_ORDER, walls) if wall}
    return _build(size, marked, strict, warn)


def dump_num(maze: Maze) -> str:
    return "".join(f"{x} {y} " + " ".join(str(int(maze.is_wall(x, y, d))) for d in NUM_ORDER) + "\n"
                   for x in range(maze.size) for y in range(maze.size))

"""The two other maze formats mms users have: mms's `.num` text (one line per cell: `X Y N E S W`, 1 = wall) and
the 256-byte binary `.maz` of the classic 16x16 collections (one byte per cell, column by column, bits
1 north, 2 east, 4 south, 8 west). A wall either side of which is marked is a wall; outer walls are always closed.
"""

from __future__ import annotations

from math import isqrt

from .direction import EAST, NORTH, SOUTH, WEST
from .errors import MazeError
from .model import Maze
from .stepmap import default_goals
from .wallrecord import COORD_LIMIT

MAZ_SIDE = 16
MAZ_BYTES = MAZ_SIDE * MAZ_SIDE
MAZ_BITS = ((1, NORTH), (2, EAST), (4, SOUTH), (8, WEST))
NUM_ORDER = (NORTH, EAST, SOUTH, WEST)


def _finish(maze: Maze) -> Maze:
    maze.goals = default_goals(maze)
    return maze


def _close(maze: Maze, x: int, y: int, d: int) -> None:
    if not maze.is_outer(x, y, d):
        maze.set(x, y, d, True)


def _open_inner(size: int) -> Maze:
    maze = Maze(size)
    for x, y, d in maze.inner_walls():
        maze.set(x, y, d, False)
    return maze


def parse_maz(data: bytes) -> Maze:
    if len(data) != MAZ_BYTES:
        raise MazeError(f"a .maz file is {MAZ_BYTES} bytes (16x16, one per cell), this one is {len(data)}")
    maze = _open_inner(MAZ_SIDE)
    for i, byte in enumerate(data):
        x, y = divmod(i, MAZ_SIDE)
        for bit, d in MAZ_BITS:
            if byte & bit:
                _close(maze, x, y, d)
    return _finish(maze)


def dump_maz(maze: Maze) -> bytes:
    if maze.size != MAZ_SIDE:
        raise MazeError(f"a .maz file holds a 16x16 maze, not {maze.size}x{maze.size}")
    return bytes(sum(bit for bit, d in MAZ_BITS if maze.is_wall(x, y, d))
                 for x in range(MAZ_SIDE) for y in range(MAZ_SIDE))


def parse_num(text: str) -> Maze:
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
    maze = _open_inner(size)
    for (x, y), walls in cells.items():
        for d, wall in zip(NUM_ORDER, walls):
            if wall:
                _close(maze, x, y, d)
    return _finish(maze)


def dump_num(maze: Maze) -> str:
    return "".join(f"{x} {y} " + " ".join(str(int(maze.is_wall(x, y, d))) for d in NUM_ORDER) + "\n"
                   for x in range(maze.size) for y in range(maze.size))

"""The common micromouse text format (micromouseonline/mazefiles), extended with ` . ` / `.` for unknown walls.

Each cell is four characters wide: a post (`o` or `+`) then a three-character wall segment on post rows;
a wall character (`|`, ` ` or `.`) then three characters of content (` S `, ` G `) on cell rows.
"""

from __future__ import annotations

from ..direction import EAST, NORTH, SOUTH, WEST
from ..errors import MazeError
from ..model import Cell, Maze
from ..search.stepmap import default_goals

POSTS = "o+"
H_WALL, H_OPEN, H_UNKNOWN = "---", "   ", " . "
V_WALL, V_OPEN, V_UNKNOWN = "|", " ", "."
START_MARK, GOAL_MARK = "S", "G"
CELL_WIDTH = 4

_H = {H_WALL: True, H_OPEN: False, H_UNKNOWN: None}
_V = {V_WALL: True, V_OPEN: False, V_UNKNOWN: None}


def _fail(lineno: int, col: int, what: str) -> MazeError:
    return MazeError(f"line {lineno}, column {col + 1}: {what}")


def _apply(maze: Maze, x: int, y: int, d: int, state: bool | None, lineno: int, col: int) -> None:
    if maze.is_outer(x, y, d):
        if state is not True:
            raise _fail(lineno, col, "the outer wall must be closed")
    elif state is None:
        maze.forget(x, y, d)
    else:
        maze.set(x, y, d, state)


def parse_maze(text: str) -> Maze:
    """Size comes from the first line's width; S defaults to (0, 0) and G to the central 2x2 if reachable."""
    lines = [ln.rstrip() for ln in text.splitlines()]
    while lines and not lines[-1]:
        lines.pop()
    if not lines:
        raise MazeError("line 1: empty maze file")
    n, rest = divmod(len(lines[0]) - 1, CELL_WIDTH)
    if n < 1 or rest:
        raise _fail(1, 0, f"a post row must be 4*N+1 characters wide, this one is {len(lines[0])}")
    if len(lines) != 2 * n + 1:
        raise MazeError(f"line {min(len(lines), 2 * n + 1) + 1}: a {n}x{n} maze needs {2 * n + 1} lines, "
                        f"the file has {len(lines)}")
    maze = Maze(n)
    start: Cell | None = None
    goals: list[Cell] = []
    width = CELL_WIDTH * n + 1
    for r, raw in enumerate(lines):
        lineno = r + 1
        if len(raw) > width:
            raise _fail(lineno, width, f"line is longer than {width} characters")
        line = raw.ljust(width)
        k, is_cell_row = divmod(r, 2)
        for i in range(n + 1):
            col = CELL_WIDTH * i
            if not is_cell_row:
                if line[col] not in POSTS:
                    raise _fail(lineno, col, f"expected a post ('o' or '+'), found {line[col]!r}")
                if i < n:
                    seg = line[col + 1: col + CELL_WIDTH]
                    if seg not in _H:
                        raise _fail(lineno, col + 1, f"bad wall segment {seg!r} (use '---', '   ' or ' . ')")
                    y, d = (n - 1 - k, NORTH) if k < n else (0, SOUTH)
                    _apply(maze, i, y, d, _H[seg], lineno, col + 1)
                continue
            y = n - 1 - k
            if line[col] not in _V:
                raise _fail(lineno, col, f"bad wall character {line[col]!r} (use '|', ' ' or '.')")
            x, d = (i, WEST) if i < n else (n - 1, EAST)
            _apply(maze, x, y, d, _V[line[col]], lineno, col)
            if i < n:
                mark = line[col + 1: col + CELL_WIDTH].strip()
                if mark == START_MARK:
                    if start is not None:
                        raise _fail(lineno, col + 1, "a second start cell")
                    start = (i, y)
                elif mark == GOAL_MARK:
                    goals.append((i, y))
                elif mark:
                    raise _fail(lineno, col + 1, f"unknown cell mark {mark!r} (use S or G)")
    maze.start = start or (0, 0)
    maze.goals = tuple(sorted(goals, key=lambda c: (c[1], c[0]))) or default_goals(maze)
    return maze


def dump_maze(maze: Maze, post: str = "o", extent: int | None = None) -> str:
    """Draw the lower-left `extent` x `extent` cells (all by default); unknown walls become dots."""
    n = extent or maze.size
    goals = set(maze.goals)
    out: list[str] = []
    for k in range(n + 1):
        y_top = n - k  # this post row is the south side of row y_top, or the north side of row n-1
        seg = []
        for x in range(n):
            y, d = (y_top, SOUTH) if y_top < maze.size else (y_top - 1, NORTH)
            seg.append(_draw(maze, x, y, d, H_WALL, H_OPEN, H_UNKNOWN))
        out.append(post + post.join(seg) + post)
        if k == n:
            break
        y = n - 1 - k
        row = []
        for x in range(n):
            mark = START_MARK if (x, y) == maze.start else GOAL_MARK if (x, y) in goals else " "
            row.append(_draw(maze, x, y, WEST, V_WALL, V_OPEN, V_UNKNOWN) + f" {mark} ")
        row.append(_draw(maze, n - 1, y, EAST, V_WALL, V_OPEN, V_UNKNOWN))
        out.append("".join(row))
    return "\n".join(out) + "\n"


def _draw(maze: Maze, x: int, y: int, d: int, wall: str, open_: str, unknown: str) -> str:
    if not maze.is_known(x, y, d):
        return unknown
    return wall if maze.is_wall(x, y, d) else open_

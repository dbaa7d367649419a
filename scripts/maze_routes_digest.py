"""Print every fastest-path route mazelog computes on the contest mazes, one line per query, and a digest.

Why: the fast-path search (maze/fastpath/__init__.py) is refactored and tuned for speed again and again, and its routes
must stay exactly the same through that: the same time to the last bit and the same moves, so that every
`mazelog path` / `explore --objective time` output and every log a timed search writes stays byte for byte
the same. Run this before a change and after it and compare the outputs (or just the last line):

    python scripts/maze_routes_digest.py > /tmp/routes-before.txt
    ... change ...
    python scripts/maze_routes_digest.py | diff /tmp/routes-before.txt -

Mazes: the built-in ones (maze/data/mazes) and those of ../shared/mazes when it is there (a copy of a built-in
one counts once). For each, straight and diagonal runs, through four wall sets the commands query:

  known        every wall known (`mazelog path MAZE --objective time`, the true route of `explore`)
  unknown      no inner wall known, unknown walls open (a search's first plan)
  goal-open    the walls a start-to-goal search (strategy goal) found, unknown ones open (a plan mid-search)
  stop-known   the walls a stop search with the time objective found, unknown ones closed (the route it proves)

and the cell path of `mazelog path MAZE` (the fewest cells, run as fast as possible: run_of_cells).
The stop search plans with the fast path itself, so its walls check the search's queries too.
"""

from __future__ import annotations

import hashlib
from collections.abc import Iterator
from pathlib import Path

from maze.fastpath import Route, fastest_route, run_of_cells
from maze.files.builtin import builtin_dir
from maze.files.mazeio import read_maze
from maze.model import Maze
from maze.search.explorer import explore
from maze.search.stepmap import optimistic, pessimistic, shortest_path
from maze.timing.mouseparams import load_mouse

SHARED = Path(__file__).resolve().parents[1].parent / "shared" / "mazes"


def maze_files() -> list[tuple[str, Path]]:
    """(label, file) of every maze, the built-in ones first, each layout once."""
    found: list[tuple[str, Path]] = []
    seen: set[bytes] = set()
    candidates = [("builtin", p) for p in sorted(builtin_dir().glob("*.txt"))]
    if SHARED.is_dir():
        candidates += [("shared", p) for p in sorted(SHARED.glob("*/*.txt"))]
    for where, path in candidates:
        content = hashlib.sha256(path.read_bytes()).digest()
        if content not in seen:
            seen.add(content)
            label = path.stem if where == "builtin" else f"{path.parent.name}/{path.stem}"
            found.append((label, path))
    return found


def describe(route: Route | None) -> str:
    if route is None:
        return "none"
    walls = hashlib.sha256(",".join(map(str, route.walls)).encode()).hexdigest()[:16]
    return f"{route.seconds!r} s, {route.length!r} cells, walls {walls}: {route.sequence}"


def queries(label: str, truth: Maze) -> Iterator[str]:
    mouse = load_mouse(None, truth.size)
    head = f"{label} {truth.size}x{truth.size}"
    for diagonal in (False, True):
        mode = "diagonal" if diagonal else "straight"
        goal_search = explore(truth, "goal", "cells", diagonal, mouse).maze
        stop_search = explore(truth, "stop", "time", diagonal, mouse).maze
        wall_sets = {"known": pessimistic(truth),
                     "unknown": optimistic(Maze.unknown(truth.size, truth.goals)),
                     "goal-open": optimistic(goal_search),
                     "stop-known": pessimistic(stop_search)}
        for name, blocked in wall_sets.items():
            yield f"{head} {mode} {name}: {describe(fastest_route(truth, blocked, diagonal, mouse))}"
        cells = [(c % truth.size, c // truth.size) for c in shortest_path(truth, pessimistic(truth))]
        yield f"{head} {mode} cell-path: {describe(run_of_cells(truth, cells, diagonal, mouse))}"


def main() -> None:
    digest = hashlib.sha256()
    count = 0
    for label, path in maze_files():
        for line in queries(label, read_maze(path)):
            print(line, flush=True)
            digest.update(line.encode() + b"\n")
            count += 1
    print(f"{count} routes, sha256 {digest.hexdigest()}")


if __name__ == "__main__":
    main()

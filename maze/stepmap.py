"""Breadth-first step maps (the Adachi method's 歩数マップ) over flat cell indices.

A step map counts cells from a set of sources through walls that are not blocked; which walls block
depends on the question, so callers pass a `blocked` array indexed by wall id (see `optimistic`/`pessimistic`).
"""

from __future__ import annotations

from typing import Iterable, Sequence

from .model import Cell, Maze, Topology, central_goals

UNREACHED = 1 << 30


def _as_int(flags: bytes) -> int:
    return int.from_bytes(flags, "little")


def optimistic(maze: Maze, virtual: bytes | None = None) -> bytes:
    """Unknown walls treated as open, as while searching; virtual walls block."""
    if virtual is None:
        return bytes(maze.wall)
    return (_as_int(maze.wall) | _as_int(virtual)).to_bytes(len(maze.wall), "little")


def pessimistic(maze: Maze) -> bytes:
    """Only known-open walls pass: the paths the mouse can be sure of."""
    n = len(maze.wall)
    ones = _as_int(b"\x01" * n)  # flags are 0/1 bytes, so xor with 1 per byte negates them
    return (_as_int(maze.wall) | (_as_int(maze.known) ^ ones)).to_bytes(n, "little")


def step_map(topo: Topology, blocked: Sequence[int], sources: Iterable[int], until: int | None = None,
             limit: int | None = None) -> list[int]:
    """Layer by layer (no deque, no per-step index arithmetic): the search asks for a thousand of these.

    `until`: stop once that cell is reached; `limit`: stop after that many steps. Cells not reached by then are
    UNREACHED, which is all a caller that only looks at nearer cells needs, at a fraction of the cost."""
    dist = [UNREACHED] * (topo.size * topo.size)
    frontier = []
    for s in sources:
        if dist[s]:
            dist[s] = 0
            frontier.append(s)
    passages = topo.passages
    d = 0
    while frontier:
        d += 1
        reached = []
        for c in frontier:
            for w, m in passages[c]:
                if dist[m] > d and not blocked[w]:
                    dist[m] = d
                    reached.append(m)
        frontier = reached
        if (until is not None and dist[until] < UNREACHED) or (limit is not None and d >= limit):
            break
    return dist


def path_down(topo: Topology, blocked: Sequence[int], dist: list[int], start: int) -> list[int]:
    """Follow a step map downhill from start to a source; empty if start is unreachable."""
    if dist[start] >= UNREACHED:
        return []
    path = [start]
    c = start
    while dist[c]:
        c = next(topo.neighbours[c][k] for k in range(4)
                 if not blocked[topo.cell_walls[c][k]] and dist[topo.neighbours[c][k]] == dist[c] - 1)
        path.append(c)
    return path


def shortest_path(maze: Maze, blocked: Sequence[int]) -> list[int]:
    """A shortest start-to-goal cell path through unblocked walls (empty when there is none)."""
    dist = step_map(maze.topo, blocked, [maze.cell_index(g) for g in maze.goals])
    return path_down(maze.topo, blocked, dist, maze.cell_index(maze.start))


def default_goals(maze: Maze) -> tuple[Cell, ...]:
    """The central 2x2 (classic contests); when the start cannot reach it (a training maze whose small active
    area leaves it out), the reachable cell farthest from the start (ties: the highest row, then the rightmost)."""
    dist = step_map(maze.topo, maze.wall, [maze.cell_index(maze.start)])
    central = central_goals(maze.size)
    if any(dist[maze.cell_index(g)] < UNREACHED for g in central):
        return central
    _, y, x = max((d, c // maze.size, c % maze.size) for c, d in enumerate(dist) if d < UNREACHED)
    return ((x, y),)

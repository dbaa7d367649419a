"""Dead-end area closing (seed dead-end-closing.md): stop the mouse from searching areas that can only be
entered through one branch cell and therefore cannot hold a start-to-goal shortest path."""

from __future__ import annotations

from collections import deque

from ..model import Maze
from .stepmap import UNREACHED, optimistic, step_map

Branch = tuple[int, list[tuple[int, int]]]  # (branch cell, [(wall id, cell beyond), ...])


def nearest_branch(maze: Maze, virtual: bytearray, here: int) -> Branch | None:
    """The closest known cell (all four walls known) with known openings into cells that are not.

    Searched breadth-first from the mouse with unknown walls open, so "closest" means in steps, as in the seed.
    """
    topo = maze.topo
    blocked = optimistic(maze, virtual)
    seen = {here}
    queue = deque([here])
    while queue:
        c = queue.popleft()
        if maze.cell_known(c):
            openings = [(w, m) for w, m in zip(topo.cell_walls[c], topo.neighbours[c])
                        if not blocked[w] and not maze.cell_known(m)]
            if openings:
                return c, openings
        for w, m in zip(topo.cell_walls[c], topo.neighbours[c]):
            if not blocked[w] and m not in seen:
                seen.add(m)
                queue.append(m)
    return None


def close_dead_ends(maze: Maze, virtual: bytearray, here: int, branch: Branch) -> list[int]:
    """Try virtual walls on the branch's openings; keep those whose far side the goal cannot reach
    any other way. Nothing is kept if it would cut the mouse or the start off from the goal.

    Returns the wall ids closed now (they stay set in `virtual`).
    """
    _, openings = branch
    for w, _ in openings:
        virtual[w] = 1
    dist = step_map(maze.topo, optimistic(maze, virtual), [maze.cell_index(g) for g in maze.goals])
    keep = [w for w, beyond in openings if dist[beyond] >= UNREACHED]
    if dist[here] >= UNREACHED or dist[maze.cell_index(maze.start)] >= UNREACHED:
        keep = []
    for w, _ in openings:
        if w not in keep:
            virtual[w] = 0
    return keep

"""A virtual mouse searching a true maze with the Adachi method, writing a wall log as it goes.

The mouse only knows what it has seen: entering a cell it reads the front, left and right walls (the back one
is the wall it came through), updates its map and appends each newly learned wall to its log.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Callable

from .closing import close_dead_ends, nearest_branch
from .direction import DIRECTIONS, NORTH, opposite
from .errors import MazeError
from .model import Cell, Maze
from .stepmap import UNREACHED, optimistic, pessimistic, shortest_path, step_map
from .wallrecord import WallRecord

STRATEGIES: dict[str, str] = {
    "goal": "start to goal only",
    "goal-return": "start to goal, then back to the start",
    "full": "goal, then every reachable cell with an unknown wall, then back",
    "closing": "full exploration with dead-end areas closed by virtual walls",
    "stop": "goal, then only cells that could shorten the path, until none can; then back",
    "closing-stop": "the stopping rule with dead-end closing",
}
SHORTEST_CLAIMED = frozenset({"full", "closing", "stop", "closing-stop"})


@dataclass
class SearchResult:
    strategy: str
    steps: int
    turns: int
    trace: list[Cell]
    records: list[WallRecord]
    batches: list[int]  # records written on entering each cell, in order (the flash writes)
    maze: Maze  # what the mouse knows at the end
    virtual: set[int]  # wall ids closed by dead-end closing
    found_path: list[Cell]  # shortest start-goal path through known-open walls
    true_length: int

    @property
    def found_length(self) -> int:
        return len(self.found_path) - 1

    @property
    def shortest(self) -> bool:
        return bool(self.found_path) and self.found_length == self.true_length


class Mouse:
    def __init__(self, truth: Maze, closing: bool) -> None:
        start = Maze.unknown(truth.size)
        if truth.start != start.start or any(
            truth.is_wall(0, 0, d) != start.is_wall(0, 0, d) for d in DIRECTIONS if start.is_known(0, 0, d)
        ):
            raise MazeError("the start cell must be (0, 0), closed on three sides and open to the north")
        self.truth = truth
        self.maze = Maze.unknown(truth.size, truth.goals)
        self.topo = self.maze.topo
        self.here = truth.cell_index(truth.start)
        self.heading = NORTH
        self.closing = closing
        self.virtual = bytearray(self.topo.wall_count)
        self.closed: set[int] = set()
        self.records: list[WallRecord] = []
        self.batches: list[int] = []
        self.steps = self.turns = 0
        self.trace = [self.here]
        self.version = 0  # bumped whenever the map changes, so step maps are rebuilt only then
        self._map_key: tuple[int, tuple[int, ...]] | None = None
        self._map: list[int] = []
        self._closing_key: tuple[int, int] | None = None  # (map version, branch cell) last judged

    def cell(self, c: int) -> Cell:
        return c % self.maze.size, c // self.maze.size

    def _sense(self) -> None:
        x, y = self.cell(self.here)
        new = 0
        for d in DIRECTIONS:
            if d != opposite(self.heading) and not self.maze.is_known(x, y, d):
                present = self.truth.is_wall(x, y, d)
                self.maze.set(x, y, d, present)
                self.records.append(WallRecord(x, y, d, present))
                new += 1
        self.batches.append(new)
        if new:
            self.version += 1

    def _move(self, k: int) -> None:
        d = DIRECTIONS[k]
        if d != self.heading:
            self.turns += 2 if d == opposite(self.heading) else 1
        self.heading = d
        self.here = self.topo.neighbours[self.here][k]
        self.steps += 1
        self.trace.append(self.here)
        self._sense()

    def _close(self) -> None:
        """The seed's check at every cell; a branch already judged on an unchanged map is not judged again."""
        branch = nearest_branch(self.maze, self.virtual, self.here)
        if branch is None or (self.version, branch[0]) == self._closing_key:
            return
        closed = close_dead_ends(self.maze, self.virtual, self.here, branch)
        if closed:
            self.closed.update(closed)
            self.version += 1
        self._closing_key = (self.version, branch[0])

    def step_towards(self, targets: list[int]) -> bool:
        """One Adachi step downhill on the step map from the targets; False when none can be reached."""
        if self.closing:
            self._close()
        key = (self.version, tuple(targets))
        blocked = optimistic(self.maze, self.virtual)
        if key != self._map_key:
            self._map, self._map_key = step_map(self.topo, blocked, targets), key
        dist = self._map
        if dist[self.here] >= UNREACHED:
            return False
        walls, nbrs = self.topo.cell_walls[self.here], self.topo.neighbours[self.here]
        downhill = [k for k in range(4) if not blocked[walls[k]] and dist[nbrs[k]] == dist[self.here] - 1]
        straight = DIRECTIONS.index(self.heading)
        self._move(straight if straight in downhill else downhill[0])
        return True

    def go_to(self, targets: list[int]) -> None:
        while self.here not in targets:
            if not self.step_towards(targets):
                raise MazeError(f"the mouse cannot reach {[self.cell(t) for t in targets]}")

    def explore(self, target_fn: Callable[[], list[int]]) -> None:
        cache: tuple[int, list[int]] = (-1, [])
        while True:
            if cache[0] != self.version:
                cache = (self.version, target_fn())
            if not cache[1] or not self.step_towards(cache[1]):
                return

    def unknown_cells(self) -> list[int]:
        return [c for c in range(self.maze.size ** 2) if not self.maze.cell_known(c)]

    def improvable_cells(self) -> list[int]:
        """Cells not yet fully seen on some optimistic shortest path; empty once no unknown wall can shorten
        the known shortest path (then the optimistic and the proven lengths agree)."""
        blocked = optimistic(self.maze, self.virtual)
        goals = [self.maze.cell_index(g) for g in self.maze.goals]
        start = self.maze.cell_index(self.maze.start)
        from_goal = step_map(self.topo, blocked, goals)
        known = step_map(self.topo, pessimistic(self.maze), goals)
        best = from_goal[start]
        if known[start] == best:
            return []
        from_start = step_map(self.topo, blocked, [start])
        return [c for c in range(self.maze.size ** 2)
                if from_start[c] + from_goal[c] == best and not self.maze.cell_known(c)]


def explore(truth: Maze, strategy: str) -> SearchResult:
    if strategy not in STRATEGIES:
        raise MazeError(f"unknown strategy {strategy!r}; choose from {', '.join(STRATEGIES)}")
    mouse = Mouse(truth, closing=strategy.startswith("closing"))
    goals = [truth.cell_index(g) for g in truth.goals]
    start = [truth.cell_index(truth.start)]
    mouse.go_to(goals)
    if strategy in ("full", "closing"):
        mouse.explore(mouse.unknown_cells)
    elif strategy in ("stop", "closing-stop"):
        mouse.explore(mouse.improvable_cells)
    if strategy != "goal":
        mouse.go_to(start)
    true_path = shortest_path(truth, pessimistic(truth))
    return SearchResult(
        strategy=strategy,
        steps=mouse.steps,
        turns=mouse.turns,
        trace=[mouse.cell(c) for c in mouse.trace],
        records=mouse.records,
        batches=mouse.batches,
        maze=mouse.maze,
        virtual=mouse.closed,
        found_path=[mouse.cell(c) for c in shortest_path(mouse.maze, pessimistic(mouse.maze))],
        true_length=len(true_path) - 1,
    )

"""A virtual mouse searching a true maze with the Adachi method, writing a wall log as it goes.

The mouse only knows what it has seen: entering a cell it reads the front, left and right walls (the back one
is the wall it came through), updates its map and appends each newly learned wall to its log. Where it goes
after reaching the goal depends on the strategy and, for the stopping rule, on the objective: the fewest cells,
or the fastest run under the time model (maze/fastpath/__init__.py).
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import TYPE_CHECKING

from ..direction import DIRECTIONS, NORTH, opposite
from ..errors import MazeError
from ..log.wallrecord import WallRecord
from ..model import Cell, Maze
from ..timing.motion import SearchRun, search_run
from ..timing.mouseparams import MouseParams, load_mouse
from .closing import close_dead_ends, nearest_branch
from .stepmap import (
    bit,
    cells_of,
    known_cells,
    layers,
    mask_of,
    open_sides,
    optimistic,
    pessimistic,
    shortest_path,
    topo_cells,
)
from .strategies import OBJECTIVES, STRATEGIES, AfterGoal

if TYPE_CHECKING:
    from ..fastpath import Route

TIME_TOLERANCE = 1e-9  # seconds: two routes of the same moves, summed in another order


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
    search: SearchRun  # the search's own run time under the time model
    found_route: Route | None = None  # fastest run through known-open walls (time objective only)
    true_route: Route | None = None  # fastest run in the fully known maze (time objective only)

    @property
    def found_length(self) -> int:
        return len(self.found_path) - 1

    @property
    def shortest(self) -> bool:
        return bool(self.found_path) and self.found_length == self.true_length

    @property
    def fastest(self) -> bool:
        return (self.found_route is not None and self.true_route is not None
                and self.found_route.seconds <= self.true_route.seconds + TIME_TOLERANCE)


class Mouse:
    def __init__(self, truth: Maze, closing: bool, planner: Callable[[bytes], Route | None]) -> None:
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
        self._map: list[int] = []  # breadth-first layers (bit masks) from the current targets
        self._closing_key: tuple[int, int] | None = None  # (map version, branch cell) last judged
        self.planner = planner  # fastest route through walls not blocked, for the time objective
        self._route: Route | None = None
        self.wall_cells: dict[int, list[int]] = {}
        for c, walls in enumerate(self.topo.cell_walls):
            for w in walls:
                self.wall_cells.setdefault(w, []).append(c)

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
            # only the cells nearer the targets than the mouse matter while it walks downhill on this map
            self._map = layers(self.topo, open_sides(self.topo, blocked), mask_of(targets, self.maze.size),
                               until=self.here)
            self._map_key = key
        size = self.maze.size
        here = 1 << bit(self.here, size)
        d = next((d for d, layer in enumerate(self._map) if layer & here), None)
        if d is None:
            return False
        below = self._map[d - 1]
        walls, nbrs = self.topo.cell_walls[self.here], self.topo.neighbours[self.here]
        downhill = [k for k in range(4) if not blocked[walls[k]] and nbrs[k] >= 0 and below >> bit(nbrs[k], size) & 1]
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
        size = self.maze.size
        return cells_of(~known_cells(self.topo, self.maze.known) & topo_cells(size), size)

    def improvable_cells(self) -> list[int]:
        """Cells not yet fully seen on some optimistic shortest path; empty once no unknown wall can shorten
        the known shortest path (then the optimistic and the proven lengths agree)."""
        sides = open_sides(self.topo, optimistic(self.maze, self.virtual))
        size = self.maze.size
        goals = mask_of((self.maze.cell_index(g) for g in self.maze.goals), size)
        start = self.maze.cell_index(self.maze.start)
        start_bit = 1 << bit(start, size)
        from_goal = layers(self.topo, sides, goals, until=start)
        if not from_goal[-1] & start_bit:
            return []  # the start cannot reach the goal even with every unknown wall open
        best = len(from_goal) - 1
        known = layers(self.topo, open_sides(self.topo, pessimistic(self.maze)), goals, until=start, limit=best)
        if known[-1] & start_bit and len(known) - 1 == best:
            return []
        from_start = layers(self.topo, sides, start_bit, limit=best)
        on_best = 0
        for k, layer in enumerate(from_start):
            on_best |= layer & from_goal[best - k]
        return cells_of(on_best & ~known_cells(self.topo, self.maze.known), size)

    def route_cells(self) -> list[int]:
        """The time objective's stopping rule: cells beside the unknown walls of one fastest route with unknown
        walls open; empty once that route is all known (then no unknown wall can make a faster one).

        The route is kept until a wall on it turns out closed: walls found anywhere else only slow other routes
        down, so it is still a fastest one."""
        maze, virtual = self.maze, self.virtual
        if self._route is None or any(maze.wall[w] or virtual[w] for w in self._route.walls):
            self._route = self.planner(optimistic(maze, virtual))
            if self._route is None:
                raise MazeError("no route from the start to the goal")
        return sorted({c for w in self._route.walls if not maze.known[w] for c in self.wall_cells[w]})


def explore(truth: Maze, strategy: str, objective: str = "cells", diagonal: bool = False,
            params: MouseParams | None = None) -> SearchResult:
    """`objective` decides what the stopping rule (strategies stop, closing-stop) must make sure of: the
    fewest cells, or the fastest run (`diagonal`: with diagonal moves) for the mouse `params` describes."""
    if strategy not in STRATEGIES:
        raise MazeError(f"unknown strategy {strategy!r}; choose from {', '.join(STRATEGIES)}")
    if objective not in OBJECTIVES:
        raise MazeError(f"unknown objective {objective!r}; choose from {', '.join(OBJECTIVES)}")
    params = params or load_mouse(None, truth.size)
    timed = objective == "time"

    def planner(blocked: bytes) -> Route | None:
        from ..fastpath import fastest_route  # numpy and scipy: only the time objective needs them

        return fastest_route(truth, blocked, diagonal, params)

    plan = STRATEGIES[strategy]
    mouse = Mouse(truth, closing=plan.closing, planner=planner)
    goals = [truth.cell_index(g) for g in truth.goals]
    start = [truth.cell_index(truth.start)]
    mouse.go_to(goals)
    targets = {AfterGoal.NOTHING: None, AfterGoal.EVERY_UNKNOWN: mouse.unknown_cells,
               AfterGoal.STOPPING_RULE: mouse.route_cells if timed else mouse.improvable_cells}[plan.after_goal]
    if targets is not None:
        mouse.explore(targets)
    if plan.returns:
        mouse.go_to(start)
    true_path = shortest_path(truth, pessimistic(truth))
    trace = [mouse.cell(c) for c in mouse.trace]
    return SearchResult(
        strategy=strategy,
        steps=mouse.steps,
        turns=mouse.turns,
        trace=trace,
        records=mouse.records,
        batches=mouse.batches,
        maze=mouse.maze,
        virtual=mouse.closed,
        found_path=[mouse.cell(c) for c in shortest_path(mouse.maze, pessimistic(mouse.maze))],
        true_length=len(true_path) - 1,
        search=search_run(trace, params),
        found_route=planner(pessimistic(mouse.maze)) if timed else None,
        true_route=planner(pessimistic(truth)) if timed else None,
    )

"""The fastest start-to-goal run under the time model: Dijkstra (compiled) over a graph of moves.

A node is a wall midpoint the mouse is crossing with its heading, in layers A (after a turn), B (before one),
G (over the goal line) and C (cruising on a long straight); maze/fastpath/build.py says more. Edges: straights
A->B and A->G, turns B->A, and straights from the standing start in the start cell's centre.
The graph of a maze size is built once; each query marks which edges its walls leave open and searches it as
A*: Dijkstra on reduced prices (each edge's price plus the drop in a lower bound of the time to the goal),
with a distance limit so that scipy settles only the nodes that could lie on a route no slower than the
fastest; the limit starts from the last query's answer and grows until the goal is reached (the compiled kernel
instead resumes the last query's A*, repairing only the times the closed walls raised). The bound is the
exact time to the goal under the walls of an earlier query (maze/fastpath/bound.py): walls only close while a
mouse searches, so it stays a bound, and A* settles little more than the fastest routes' nodes. The route
itself comes from a second search, on the real prices, of the small graph of the nodes A* found could lie on a
fastest route, and is walked back from the goal by those exact times alone, so that it depends neither on the
bound nor on the limit A* ran under.

The parts: fastpath/graph.py says what the graph is (layers, turns, prices, the start's edges); where a C
compiler works, a small C library compiled at first use (compiled.py and kernel.c) builds it and answers its
queries (fastpath/native.py), and no numpy is imported. Elsewhere fastpath/build.py builds the graph of a maze
size, diagonal flag and mouse in numpy, fastpath/query.py answers a query on it with scipy (pricing, A*, the
second search) and fastpath/decode.py decodes the nodes found into moves: the same routes to the bit either way.
"""

from __future__ import annotations

from functools import lru_cache
from typing import Protocol

from ..direction import DELTA
from ..errors import MazeError
from ..model import Cell, Maze
from ..timing.mouseparams import MouseParams
from ..timing.route import Route
from .compiled import kernel


class Graph(Protocol):
    def fastest(self, blocked: bytes | bytearray, start: Cell, goals: tuple[Cell, ...]) -> Route | None: ...


class MoveGraph:
    """The move graph of one maze size, diagonal flag and mouse in numpy, with its queries (scipy's searches)
    and their routes: the path where the kernel cannot be built."""

    def __init__(self, size: int, diagonal: bool, mouse: MouseParams) -> None:
        from .build import StaticGraph
        from .decode import RouteDecoder
        from .query import FastestSearch

        self.static = StaticGraph(size, diagonal, mouse)
        self.search = FastestSearch(self.static)
        self.decoder = RouteDecoder(self.static)

    def fastest(self, blocked: bytes | bytearray, start: Cell, goals: tuple[Cell, ...]) -> Route | None:
        """The fastest run through walls not blocked (1 = blocked, indexed by wall id); None if there is none."""
        q = self.search.query_graph(start, goals)
        self.search.price(q, blocked)
        found = self.search.search(q)
        if found is None:
            return None
        return self.decoder.route(*found, start)


@lru_cache(maxsize=4)
def move_graph(size: int, diagonal: bool, mouse: MouseParams) -> Graph:
    """The kernel's graph where it can be built (maze/fastpath/native.py), else numpy's and scipy's."""
    lib = kernel()
    if lib is None:
        return MoveGraph(size, diagonal, mouse)
    from .native import NativeGraph

    return NativeGraph(lib, size, diagonal, mouse)


def fastest_route(maze: Maze, blocked: bytes | bytearray, diagonal: bool, mouse: MouseParams) -> Route | None:
    return move_graph(maze.size, diagonal, mouse).fastest(blocked, maze.start, maze.goals)


def run_of_cells(maze: Maze, cells: list[Cell], diagonal: bool, mouse: MouseParams) -> Route:
    """The fastest way to run one given cell path: every wall is blocked except those the path passes."""
    blocked = bytearray([1]) * maze.topo.wall_count
    for (x, y), (nx, ny) in zip(cells, cells[1:]):
        d = next((d for d, step in DELTA.items() if step == (nx - x, ny - y)), None)
        if d is None:
            raise MazeError(f"cells {(x, y)} and {(nx, ny)} are not neighbours")
        blocked[maze.wid(x, y, d)] = 0
    route = move_graph(maze.size, diagonal, mouse).fastest(blocked, cells[0], (cells[-1],))
    if route is None:
        raise MazeError("the cell path cannot be run")
    return route

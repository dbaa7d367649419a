"""The fast-path search (A*, then a search of the nodes it kept, limited to the goal's time) against a plain
Dijkstra over the same priced graph, on random small mazes, one query after another on one graph (so that each
starts from the last one's limit and bound), and against the same query on a fresh graph."""

import copy
import heapq
import math

from hypothesis import given, settings
from hypothesis import strategies as st

from maze.fastpath import MoveGraph, move_graph
from maze.fastpath.graph import G
from maze.files.builtin import builtin_path
from maze.files.mazefile import parse_maze
from maze.model import Maze
from maze.search.stepmap import optimistic, pessimistic
from maze.timing.mouseparams import load_mouse


def plain_fastest(graph: MoveGraph, maze: Maze) -> float:
    """Textbook Dijkstra over the edges `fastest` just found open, at their prices, to the first goal-layer node."""
    q = graph.search.query_graph(maze.start, maze.goals)
    indptr, indices = q.prices.indptr, q.prices.indices
    prices = [price if ok else math.inf for price, ok in zip(q.prices.data, q.open)]
    start = len(q.nodes) - 1  # the query graph's number of the standing start
    dist = {start: 0.0}
    heap = [(0.0, start)]
    done = set()
    while heap:
        d, u = heapq.heappop(heap)
        if u in done:
            continue
        if q.nodes[u] // graph.static.layer_size == G:
            return d
        done.add(u)
        for j in range(indptr[u], indptr[u + 1]):
            v, nd = int(indices[j]), d + float(prices[j])
            if nd < dist.get(v, math.inf):
                dist[v] = nd
                heapq.heappush(heap, (nd, v))
    return math.inf


@st.composite
def maze_series(draw) -> list[Maze]:
    """Mazes of one size and goal, each with the last one's walls and some more set, as a search finds them."""
    size = draw(st.integers(2, 6))
    goal = (draw(st.integers(0, size - 1)), draw(st.integers(0, size - 1)))
    maze = Maze(size)
    maze.goals = (goal,)
    series = []
    for _ in range(draw(st.integers(1, 4))):
        for x, y, d in maze.inner_walls():
            if not maze.known[maze.wid(x, y, d)] and draw(st.integers(0, 3)) == 0:
                maze.set(x, y, d, draw(st.booleans()))
        series.append(copy.deepcopy(maze))
    return series


@settings(max_examples=60, deadline=None)
@given(maze_series(), st.booleans())
def test_fastest_is_a_plain_dijkstra(series: list[Maze], diagonal: bool) -> None:
    mouse = load_mouse(None, series[0].size)
    graph = MoveGraph(series[0].size, diagonal, mouse)  # the numpy path's graph, which plain_fastest reads
    for maze in series:
        for blocked in (optimistic(maze), pessimistic(maze)):
            route = graph.fastest(blocked, maze.start, maze.goals)
            expected = plain_fastest(graph, maze)
            if route is None:
                assert expected == math.inf
                continue
            assert route.seconds == expected
            assert all(not blocked[w] for w in route.walls)
            fresh = MoveGraph(maze.size, diagonal, mouse).fastest(blocked, maze.start, maze.goals)
            assert fresh == route  # what earlier queries left (bound, limit) never changes a route, ties included


def test_no_route_leaves_the_maze_even_if_the_outer_walls_are_given_open() -> None:
    """The bound of A* is the time with only the outer walls: a query that opened them would otherwise get a
    bound too high to be exact, and a route through the outside."""
    maze = Maze.unknown(32, parse_maze(builtin_path("japan2009hef").read_text()).goals)
    mouse = load_mouse(None, 32)
    for diagonal in (False, True):
        graph = move_graph(32, diagonal, mouse)
        no_walls = graph.fastest(bytes(len(maze.wall)), maze.start, maze.goals)
        inner_only = bytearray(len(maze.wall))
        for w in maze.topo.outer:
            inner_only[w] = 1
        expected = graph.fastest(bytes(inner_only), maze.start, maze.goals)
        assert no_walls is not None and expected is not None
        assert not set(no_walls.walls) & maze.topo.outer
        assert no_walls.seconds == expected.seconds and no_walls.sequence == expected.sequence

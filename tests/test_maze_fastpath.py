"""The fast-path search (A*, then a search limited to the goal's time) against a plain Dijkstra over the same
priced graph, on random small mazes, one query after another on one graph (so that each starts from the last
one's limit)."""

import copy
import heapq
import math

from hypothesis import given, settings
from hypothesis import strategies as st

from maze.fastpath import G, MoveGraph, move_graph
from maze.model import Maze
from maze.mouseparams import load_mouse
from maze.stepmap import optimistic, pessimistic


def plain_fastest(graph: MoveGraph, maze: Maze) -> float:
    """Textbook Dijkstra over the priced edges (those `fastest` just priced), to the first goal-layer node."""
    q = graph._query(maze.start, maze.goals)
    indptr, indices, prices = q.graph.indptr, q.graph.indices, q.graph.data
    dist = {graph.start_node: 0.0}
    heap = [(0.0, graph.start_node)]
    done = set()
    while heap:
        d, u = heapq.heappop(heap)
        if u in done:
            continue
        if u // graph.layer == G:
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
    graph = move_graph(series[0].size, diagonal, mouse)
    for maze in series:
        for blocked in (optimistic(maze), pessimistic(maze)):
            route = graph.fastest(blocked, maze.start, maze.goals)
            expected = plain_fastest(graph, maze)
            if route is None:
                assert expected == math.inf
                continue
            assert abs(route.seconds - expected) <= 1e-9
            assert all(not blocked[w] for w in route.walls)

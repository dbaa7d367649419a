"""One fastest-path query on the move graph (maze/fastpath/build.py): which edges its walls leave open, A* to the
goal, and the nodes and times of the fastest route (maze/fastpath/__init__.py says why it is searched this way)."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..model import Cell
from .bound import Csr, TimeBound, row_pointers
from .build import StaticGraph
from .graph import (
    HINT_MARGIN,
    LIMIT_GROWTH,
    LIMIT_TRIES,
    MAX_QUERY_GRAPHS,
    NARROW_FROM,
    TIME_SLACK,
    B,
    G,
    first_limit_floor,
    start_edges,
)
from .walls import wall_edges


def _predecessors(row: np.ndarray, col: np.ndarray, price: np.ndarray, dist: np.ndarray) -> np.ndarray:
    """Per node of a graph of edges row -> col, the node a route reaches it from (-1 for none): of the edges
    whose source's time plus price is exactly the node's time, the one from the node reached first; of equals,
    the highest-numbered. That is the predecessor scipy's Dijkstra returned on the graph (it keeps the first
    node that reaches another, and on every tie of 3517 queries checked it had settled the highest-numbered of
    the equally timed ones first), and it depends only on the times, not on which nodes a search happened to
    settle: so A*'s bound may change from query to query without changing a route."""
    tight = dist[row] + price == dist[col]
    row, col = row[tight], col[tight]
    order = np.lexsort((-row, dist[row], col))  # by node, then the earliest source, then the highest-numbered
    row, col = row[order], col[order]
    first = np.ones(len(col), dtype=bool)
    first[1:] = col[1:] != col[:-1]
    pred = np.full(len(dist), -1)
    pred[col[first]] = row[first]
    return pred


def _on_fastest_routes(row: np.ndarray, col: np.ndarray, price: np.ndarray, reduced: np.ndarray, nodes: np.ndarray,
                       goal: slice, fastest: float) -> np.ndarray:
    """Which of the nodes A* kept (`nodes`, local edges row -> col at reduced `price`, A*'s `reduced` times) lie
    on a route to the goal no slower than the fastest: those the goal is reached from by edges that A* found
    tight (the source's time plus the price is the destination's, up to rounding). A stale bound leaves
    A* keeping every node it could not rule out (up to 12 000 of them on japan2017hef), while the fastest
    routes pass a few hundred; every node of every equally fast route, and every edge that ties on one, is
    kept, so the exact search of them (`FastestSearch.search`) finds the same times and the same route."""
    from scipy.sparse import csr_array
    from scipy.sparse.csgraph import breadth_first_order

    slack = _with_slack(fastest) - fastest
    tight = reduced[row] + price <= reduced[col] + slack
    goals = np.flatnonzero((nodes >= goal.start) & (nodes < goal.stop))
    n = len(nodes)
    back = csr_array((np.ones(np.count_nonzero(tight) + len(goals)),
                      (np.concatenate([col[tight], np.full(len(goals), n)]), np.concatenate([row[tight], goals]))),
                     shape=(n + 1, n + 1))
    on = np.zeros(n + 1, dtype=bool)
    on[breadth_first_order(back, n, directed=True, return_predecessors=False)] = True
    return on[:n]


def _with_slack(seconds: float) -> float:
    """A time a little over `seconds`: reduced times carry rounding of their own."""
    return seconds + TIME_SLACK * (1 + seconds)


@dataclass
class StartEdges:
    """Straights from a standing start in the start cell's centre: the n-th of a heading needs its first wall
    open and n - 1 open walls after it, ahead of node `run_from`."""

    dst: np.ndarray
    run_from: np.ndarray
    open_needed: np.ndarray
    first_wall: np.ndarray
    seconds: np.ndarray


@dataclass
class QueryGraph:
    """The CSR graph of one start and goal set, and per edge (in its row order) what must be open for it: for a
    straight, `open_needed` open walls ahead of node `run_from`; for a turn, its walls (`turn_walls`, one row
    per wall crossed); for a start edge, its first wall too. `prices` holds the prices (they depend on the mouse
    only); `open` marks the edges the last query's walls leave open; `astar` has the same edges, with the
    reduced prices for A* where open and infinity elsewhere; `bound` is A*'s bound and the reduced prices under
    it (maze/fastpath/bound.py); `hint` is the last query's reduced time to the goal, where the next one's limit
    starts (walls change a few at a time). `walls` are the walls `open` was worked out for (None before the
    first query), and `wall_edges` the edges through each wall (maze/fastpath/walls.py).

    Its nodes are only those of the move graph with an edge: `nodes` holds their numbers there, ascending (so
    ties between nodes break as they would on the whole graph), the standing start last, and `goal` the range
    of them in the goal layer. Most nodes of the move graph have none (96 700 of a 32x32 diagonal graph's
    135 000: headings no move crosses a wall with, and the like), and every search, pricing and scan of the
    times would otherwise pay for them."""

    prices: Csr
    astar: Csr
    bound: TimeBound
    open: np.ndarray
    hint: float | None
    before_turns: int  # straights (rows of A) before the turns; the chain's (rows of C) after them
    run_from: np.ndarray
    open_needed: np.ndarray
    turn_walls: np.ndarray
    start: StartEdges
    nodes: np.ndarray
    goal: slice
    walls: np.ndarray | None = None
    wall_edges: tuple[np.ndarray, np.ndarray] | None = None  # built by the first query that can use it


class FastestSearch:
    """The queries of one move graph: the graph of each start and goal set is built once and kept."""

    def __init__(self, graph: StaticGraph) -> None:
        self.graph = graph
        self._goal_masks: dict[tuple[Cell, ...], np.ndarray] = {}
        self._local = np.zeros(graph.start_node + 1, dtype=np.int32)
        self._queries: dict[tuple[Cell, tuple[Cell, ...]], QueryGraph] = {}

    def _goal_mask(self, goals: tuple[Cell, ...]) -> np.ndarray:
        """Which straights end in a goal cell."""
        if goals not in self._goal_masks:
            flat = [y * self.graph.size + x for x, y in goals]
            self._goal_masks[goals] = np.isin(self.graph.straights.end_cell, flat)
        return self._goal_masks[goals]

    def _runs(self, open_ext: np.ndarray) -> np.ndarray:
        """Open walls straight ahead of every node: along each line, the distance to its next closed crossing."""
        g = self.graph
        width = g.line_walls.shape[1]
        position = np.arange(width, dtype=np.int16)
        closed_at = np.where(open_ext[g.line_walls], np.int16(width), position)
        next_closed = np.minimum.accumulate(closed_at[:, ::-1], axis=1)[:, ::-1]
        run = np.zeros(g.layer_size, dtype=np.int16)
        run[g.line_nodes] = (next_closed - position)[g.on_line]
        return run

    def query_graph(self, start: Cell, goals: tuple[Cell, ...]) -> QueryGraph:
        """The whole graph for one start and goal set, in row order, built once: a query only prices its edges
        (infinite where a wall blocks them), so no sparse matrix is assembled per query."""
        key = (start, goals)
        if key not in self._queries:
            if len(self._queries) >= MAX_QUERY_GRAPHS:
                self._queries.pop(next(iter(self._queries)))
            self._queries[key] = self._build_query(start, goals)
        return self._queries[key]

    def _build_query(self, start: Cell, goals: tuple[Cell, ...]) -> QueryGraph:
        g, straights, chain, turns = self.graph, self.graph.straights, self.graph.chain, self.graph.turns
        to_goal = self._goal_mask(goals) & straights.direct_to_goal
        in_goal = np.isin(chain.goal_cell, [y * g.size + x for x, y in goals])
        in_chain = (chain.goal_cell < 0) | in_goal
        # the straights' and the chain's edges all need open walls ahead; their rows (A, then C) come before and
        # after the turns' (B) in the matrix, so they are kept as one array in row order with the turns between
        src = np.concatenate([straights.src, straights.src[to_goal], chain.src[in_chain]])
        order = np.argsort(src, kind="stable")
        ahead_dst = np.concatenate([straights.dst + B * g.layer_size, straights.dst[to_goal] + G * g.layer_size,
                                    chain.dst[in_chain]])[order]
        run_from = np.concatenate([straights.run_from, straights.run_from[to_goal], chain.run_from[in_chain]])[order]
        open_needed = np.concatenate([straights.open_needed, straights.open_needed[to_goal],
                                      chain.open_needed[in_chain]])[order]
        ahead_cost = np.concatenate([straights.seconds_to_turn, straights.seconds_to_goal[to_goal],
                                     chain.seconds[in_chain]])[order]
        turn_order = np.argsort(turns.src, kind="stable")
        from_start = self._start_edges(start, goals)
        src = src[order]
        before = int(np.searchsorted(src, B * g.layer_size))  # rows of A; those of C follow the turns
        rows = np.concatenate([src[:before], turns.src[turn_order], src[before:],
                               np.full(len(from_start.dst), g.start_node)])
        cols = np.concatenate([ahead_dst[:before], turns.dst[turn_order], ahead_dst[before:], from_start.dst])
        used = np.zeros(g.start_node + 1, dtype=bool)
        used[rows], used[cols] = True, True
        nodes = np.flatnonzero(used)  # the start node has edges, and the highest number: it stays last
        number = (np.cumsum(used) - 1).astype(np.int32)
        rows, cols = number[rows], number[cols]
        n = len(nodes)
        indptr = row_pointers(rows, n)
        cost = np.concatenate([ahead_cost[:before], turns.seconds[turn_order], ahead_cost[before:],
                               from_start.seconds])
        prices = Csr(cost.astype(np.float64), cols, indptr)
        astar = Csr(np.zeros(len(cols)), cols, indptr)
        goal = slice(*np.searchsorted(nodes, [G * g.layer_size, (G + 1) * g.layer_size]).tolist())
        goal_layer = cols[(cols >= goal.start) & (cols < goal.stop)]
        return QueryGraph(prices, astar, TimeBound(prices, rows, np.unique(goal_layer).astype(np.int32)),
                          np.zeros(len(cols), dtype=bool), None, before, run_from, open_needed,
                          turns.walls[turn_order].T.copy(), from_start, nodes, goal)

    def _start_edges(self, start: Cell, goals: tuple[Cell, ...]) -> StartEdges:
        g = self.graph
        edges = start_edges(g.size, g.wall_at.tolist(), g.mouse, start, goals)
        return StartEdges(*(np.array([getattr(e, f) for e in edges], dtype=np.float64 if f == "seconds" else np.int64)
                            for f in ("dst", "run_from", "open_needed", "first_wall", "seconds")))

    def _open_edges(self, q: QueryGraph, blocked: np.ndarray) -> np.ndarray:
        """Per edge (in row order), whether the walls not blocked let the mouse make it. The outer walls are
        closed whatever `blocked` says: no move leaves the maze."""
        open_ext = np.concatenate([blocked == 0, [True, False]])
        open_ext[self.graph.outer_walls] = False
        run = self._runs(open_ext)
        straights = run[q.run_from] >= q.open_needed
        turns = open_ext[q.turn_walls[0]]
        for walls in q.turn_walls[1:]:
            turns &= open_ext[walls]
        starts = open_ext[q.start.first_wall] & (run[q.start.run_from] >= q.start.open_needed)
        return np.concatenate([straights[:q.before_turns], turns, straights[q.before_turns:], starts])

    def price(self, q: QueryGraph, blocked: bytes | bytearray) -> None:
        """Which edges the walls leave open, and the reduced prices for A* (infinite where a wall is blocked),
        under a bound found again for these walls where the one kept is stale."""
        walls = np.frombuffer(bytes(blocked), dtype=np.uint8)
        closed = self._closed_edges(q, walls)
        if closed is None:
            q.open = self._open_edges(q, walls)
        else:
            q.open[closed] = False
        q.walls = walls
        if q.bound.stale(walls):
            q.bound.find(q.open, walls)
            q.hint = None  # the last answer was under another bound
        elif closed is not None:
            q.astar.data[closed] = np.inf
            return
        q.astar.data = np.where(q.open, q.bound.reduced, np.inf)

    def _closed_edges(self, q: QueryGraph, walls: np.ndarray) -> np.ndarray | None:
        """The edges through the walls this query closes and the last one left open; None where it opens one
        (or is the first): then every edge is worked out again."""
        if q.walls is None:
            return None
        changed = np.flatnonzero(walls != q.walls)
        if not walls[changed].all():
            return None
        if not len(changed):
            return changed  # no edge to close: the same walls again (`mazelog path`, a benchmark)
        if q.wall_edges is None:
            q.wall_edges = wall_edges(self.graph, q.run_from, q.open_needed, q.before_turns, q.turn_walls,
                                      q.start.first_wall, q.start.run_from, q.start.open_needed)
        indptr, edges = q.wall_edges
        return np.concatenate([edges[indptr[w]:indptr[w + 1]] for w in changed.tolist()] + [edges[:0]])

    def search(self, q: QueryGraph) -> tuple[list[int], list[float]] | None:
        """The nodes of a fastest route and the time at each; None if the goal cannot be reached. A* on the
        reduced prices finds how fast the goal can be reached and which nodes could lie on so fast a route;
        a search on their prices, limited to that time, then finds the exact time of each (the sums of a
        search of the whole graph, bit for bit), and the route is walked back from the goal by those times
        alone (`_predecessors`), so that among equally fast routes it picks the same one whatever A*'s bound
        and limit were. That search runs on the graph of those nodes alone. The compiled kernel does the same on
        the graph it builds itself (maze/fastpath/native.py)."""
        from scipy.sparse.csgraph import dijkstra

        reduced = self._reduced_search(q)
        if reduced is None:
            return None
        fastest = float(reduced[self._goal_node(q, reduced)])
        kept = reduced <= _with_slack(fastest)
        nodes = np.flatnonzero(kept)  # ascending: local numbers keep the global order
        first = q.prices.indptr[nodes]
        count = q.prices.indptr[nodes + 1] - first
        row = np.repeat(np.arange(len(nodes)), count)
        edge = np.arange(len(row)) + np.repeat(first - (np.cumsum(count) - count), count)
        col = q.prices.indices[edge]
        use = q.open[edge] & kept[col]
        row, edge, col = row[use], edge[use], col[use]
        local = self._local  # node -> its number in `nodes`; read only where kept
        local[nodes] = np.arange(len(nodes), dtype=np.int32)
        col = local[col]
        if len(nodes) > NARROW_FROM:
            on = _on_fastest_routes(row, col, q.astar.data[edge], reduced[nodes], nodes, q.goal, fastest)
            renumber = np.cumsum(on) - 1
            use = on[row] & on[col]
            row, col, edge, nodes = renumber[row[use]], renumber[col[use]], edge[use], nodes[on]
        indptr = row_pointers(row, len(nodes))
        price = q.prices.data[edge]
        sub = Csr(price, col, indptr).scipy()
        dist = dijkstra(sub, directed=True, indices=len(nodes) - 1,  # the start node is the last node
                        limit=_with_slack(fastest + q.bound.at_start))
        in_goal = np.flatnonzero((nodes >= q.goal.start) & (nodes < q.goal.stop))
        at = [int(in_goal[np.argmin(dist[in_goal])])]  # the lowest-numbered of equals, as _goal_node
        pred = _predecessors(row, col, price, dist).tolist()
        while at[-1] != len(nodes) - 1:
            at.append(pred[at[-1]])
        at.reverse()
        return q.nodes[nodes[at]].tolist(), dist[at].tolist()

    def _first_limit(self, q: QueryGraph) -> float:
        return max((q.hint or 0.0) * HINT_MARGIN, first_limit_floor(self.graph.mouse))

    def _reduced_search(self, q: QueryGraph) -> np.ndarray | None:
        """A* up to the goal: the reduced times; None if the goal cannot be reached. The limit
        (on reduced time) only leaves out nodes whose time plus bound exceeds it, so the first limit that
        reaches the goal finds a fastest route. A query with every wall it needs open has a reduced time of 0;
        the first limit is at least one cell at top speed. A limit the goal lies beyond costs a whole search,
        and the walls a search finds only ever slow its fastest run, so the first limit has a margin over the
        last answer; the route does not depend on the limit (`search`)."""
        from scipy.sparse.csgraph import dijkstra

        limit, astar = self._first_limit(q), q.astar.scipy()
        for limit in [limit * LIMIT_GROWTH ** k for k in range(LIMIT_TRIES)] + [np.inf]:
            dist = dijkstra(astar, directed=True, indices=len(q.nodes) - 1, limit=limit)
            q.bound.spent += int(np.count_nonzero(dist < np.inf))
            best = self._goal_node(q, dist)
            if np.isfinite(dist[best]):
                q.hint = float(dist[best])
                return dist
        return None

    @staticmethod
    def _goal_node(q: QueryGraph, dist: np.ndarray) -> int:
        """The node of the goal layer reached first (the lowest-numbered of equals)."""
        return int(np.argmin(dist[q.goal])) + q.goal.start

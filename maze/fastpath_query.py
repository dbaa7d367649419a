"""One fastest-path query on the move graph (maze/fastpath_build.py): which edges its walls leave open, A* to the
goal, and the nodes and times of the fastest route (maze/fastpath.py says why it is searched this way)."""

from __future__ import annotations

import ctypes
from dataclasses import dataclass

import numpy as np

from .direction import ALONG, STEP
from .fastpath_bound import Csr, TimeBound, row_pointers
from .fastpath_build import B, G, StaticGraph, entered_cell
from .fastpath_kernel import Workspace, workspace
from .fastpath_walls import wall_edges
from .model import Cell
from .motion import straight_seconds

MAX_QUERY_GRAPHS = 4  # (start, goals) pairs kept per move graph: a search has one, `path` of a cell run another
TIME_SLACK = 1e-9  # rounding in reduced prices must not leave out a node of an equally fast route
LIMIT_GROWTH = 2.0  # how much the search limit grows when the goal lies beyond it
HINT_MARGIN = 1.25  # the first limit over the last answer: a search's walls only ever make its run slower
NARROW_FROM = 1000  # kept nodes: narrowing them costs about 0.1 ms, the exact search 0.3 us a node it spares
LIMIT_TRIES = 16  # then no limit: a route that slow is unlikely, and without one the goal may be out of reach


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
    reduced prices for A* where open and infinity elsewhere (the scipy path's: the kernel reads the bound's
    reduced prices where `open` says); `bound` is A*'s bound and the reduced prices under
    it (maze/fastpath_bound.py); `hint` is the last query's reduced time to the goal, where the next one's limit
    starts (walls change a few at a time). `walls` are the walls `open` was worked out for (None before the
    first query), and `wall_edges` the edges through each wall (maze/fastpath_walls.py).

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
    work: Workspace | None  # the compiled kernel's (maze/fastpath_kernel.py); None: scipy's searches
    priced_by: PriceArrays | None = None  # the kernel's copy of what pricing reads, made by its first query
    walls: np.ndarray | None = None
    wall_edges: tuple[np.ndarray, np.ndarray] | None = None  # built by the first query that can use it


@dataclass
class PriceArrays:
    """What fp_price (maze/fastpath_kernel.c) reads, as the 32-bit arrays it takes, and where it writes: the
    line of crossings each node lies on and which walls each edge needs open (`StaticGraph._build_lines`,
    `QueryGraph`)."""

    outer: np.ndarray
    line_walls: np.ndarray
    line_len: np.ndarray
    line_nodes: np.ndarray
    run_from: np.ndarray
    open_needed: np.ndarray
    turn_walls: np.ndarray
    start_first_wall: np.ndarray
    start_run_from: np.ndarray
    start_open_needed: np.ndarray
    run: np.ndarray  # written: open walls ahead of each node of a layer

    @classmethod
    def of(cls, graph: StaticGraph, q: QueryGraph) -> PriceArrays:
        def i32(a: np.ndarray) -> np.ndarray:
            return np.ascontiguousarray(a, dtype=np.int32)

        return cls(i32(graph.outer_walls), i32(graph.line_walls), i32(graph.on_line.sum(axis=1)),
                   i32(graph.line_nodes), i32(q.run_from), i32(q.open_needed), i32(q.turn_walls),
                   i32(q.start.first_wall), i32(q.start.run_from), i32(q.start.open_needed),
                   np.zeros(graph.layer_size, dtype=np.int16))


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
        start_edges = self._start_edges(start, goals)
        src = src[order]
        before = int(np.searchsorted(src, B * g.layer_size))  # rows of A; those of C follow the turns
        rows = np.concatenate([src[:before], turns.src[turn_order], src[before:],
                               np.full(len(start_edges.dst), g.start_node)])
        cols = np.concatenate([ahead_dst[:before], turns.dst[turn_order], ahead_dst[before:], start_edges.dst])
        used = np.zeros(g.start_node + 1, dtype=bool)
        used[rows], used[cols] = True, True
        nodes = np.flatnonzero(used)  # the start node has edges, and the highest number: it stays last
        number = (np.cumsum(used) - 1).astype(np.int32)
        rows, cols = number[rows], number[cols]
        n = len(nodes)
        indptr = row_pointers(rows, n)
        cost = np.concatenate([ahead_cost[:before], turns.seconds[turn_order], ahead_cost[before:],
                               start_edges.seconds])
        prices = Csr(cost.astype(np.float64), cols, indptr)
        astar = Csr(np.zeros(len(cols)), cols, indptr)
        goal = slice(*np.searchsorted(nodes, [G * g.layer_size, (G + 1) * g.layer_size]).tolist())
        goal_layer = cols[(cols >= goal.start) & (cols < goal.stop)]
        work = workspace(n, len(cols))
        return QueryGraph(prices, astar, TimeBound(prices, rows, np.unique(goal_layer).astype(np.int32), work),
                          np.zeros(len(cols), dtype=bool), None, before, run_from, open_needed,
                          turns.walls[turn_order].T.copy(), start_edges, nodes, goal, work)

    def _start_edges(self, start: Cell, goals: tuple[Cell, ...]) -> StartEdges:
        """Straights from a standing start in the start cell's centre, along each of its four headings, of every
        length: the n-th needs the first wall open and n - 1 open ones after it."""
        g = self.graph
        p = g.mouse.run
        cx, cy = 2 * start[0] + 1, 2 * start[1] + 1
        dst: list[int] = []
        run_from: list[int] = []
        open_needed: list[int] = []
        first_wall: list[int] = []
        cost: list[float] = []
        goal_set = set(goals)
        for h in ALONG:
            dx, dy = STEP[h]
            first = g.index(cx + dx, cy + dy)
            for n in range(1, 2 * g.size + 1):
                x, y = cx + (2 * n - 1) * dx, cy + (2 * n - 1) * dy
                if not (0 <= x < g.side and 0 <= y < g.side):
                    break
                node = g.index(x, y) * 8 + h
                metres = (n - 0.5) * g.mouse.cell
                ends = [(node + B * g.layer_size,
                         straight_seconds(metres, 0.0, p.turn_speed, p.top_speed, p.accel))]
                if entered_cell((x, y), (x - dx, y - dy)) in goal_set:
                    ends.append((node + G * g.layer_size,
                                 straight_seconds(metres, 0.0, None, p.top_speed, p.accel)))
                for end, seconds in ends:
                    dst.append(end)
                    run_from.append(first * 8 + h)
                    open_needed.append(n - 1)
                    first_wall.append(int(g.wall_at[first]))
                    cost.append(seconds)
        return StartEdges(np.array(dst, dtype=np.int64), np.array(run_from, dtype=np.int64),
                          np.array(open_needed, dtype=np.int64), np.array(first_wall, dtype=np.int64),
                          np.array(cost))

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
        if q.work is not None:
            self._price_kernel(q, q.work, walls)
            return
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

    def _price_kernel(self, q: QueryGraph, work: Workspace, walls: np.ndarray) -> None:
        """Which edges are open, by fp_price: as `_closed_edges` and `_open_edges` do, with no numpy call."""
        g, a = self.graph, q.priced_by
        if a is None:
            a = q.priced_by = PriceArrays.of(g, q)
        work.lib.fp_price(work.handle, walls.ctypes.data, g.walls, a.outer.ctypes.data, len(a.outer),
                          a.line_walls.ctypes.data, a.line_len.ctypes.data, len(a.line_len), a.line_walls.shape[1],
                          a.line_nodes.ctypes.data, a.run.ctypes.data, len(a.run), len(a.run_from), q.before_turns,
                          a.run_from.ctypes.data, a.open_needed.ctypes.data, a.turn_walls.shape[1],
                          a.turn_walls.shape[0], a.turn_walls.ctypes.data, len(a.start_run_from),
                          a.start_first_wall.ctypes.data, a.start_run_from.ctypes.data,
                          a.start_open_needed.ctypes.data, q.open.ctypes.data)
        q.walls = walls
        if q.bound.stale(walls):
            q.bound.find(q.open, walls)
            q.hint = None  # the last answer was under another bound

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
        and limit were. That search runs on the graph of those nodes alone. The compiled kernel does all of it
        in one call where there is one (fp_search in maze/fastpath_kernel.c)."""
        if q.work is not None:
            return self._search_kernel(q, q.work)
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

    def _search_kernel(self, q: QueryGraph, work: Workspace) -> tuple[list[int], list[float]] | None:
        spent, hint = ctypes.c_int64(0), ctypes.c_double(0.0)
        route, times = np.empty(len(q.nodes), dtype=np.int32), np.empty(len(q.nodes))
        length = work.lib.fp_search(
            work.handle, q.prices.indptr.ctypes.data, q.prices.indices.ctypes.data, q.bound.reduced.ctypes.data,
            q.prices.data.ctypes.data, q.open.ctypes.data, q.goal.start, q.goal.stop, self._first_limit(q),
            LIMIT_GROWTH, LIMIT_TRIES, q.bound.at_start, TIME_SLACK, NARROW_FROM, ctypes.byref(spent),
            ctypes.byref(hint), route.ctypes.data, times.ctypes.data)
        q.bound.spent += spent.value
        if not length:
            return None
        q.hint = hint.value
        return q.nodes[route[:length]].tolist(), times[:length].tolist()

    def _first_limit(self, q: QueryGraph) -> float:
        mouse = self.graph.mouse
        return max((q.hint or 0.0) * HINT_MARGIN, mouse.cell / mouse.run.top_speed)

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

"""The fastest start-to-goal run under the time model: Dijkstra (scipy's, in C) over a graph of moves.

Points are in half-cell units, X and Y in 0..2N; a wall's midpoint has X + Y odd (X odd: a horizontal wall).
A node is a wall midpoint the mouse is crossing, with its heading in the seed library's eight directions
(0 east, 1 north-east, 2 north, ... 7 south-east). Nodes come in layers so that a straight's price
depends only on its length: A (just left a turn, at turn speed), B (a straight ended here, a turn must
follow), G (crossed into a goal cell: the timed run is over) and C (cruising at top speed on a long
straight). Edges: straights A->B and A->G, turns B->A, and straights from the standing start in the start
cell's centre.
The graph of a maze size is built once; each query marks which edges its walls leave open and searches it as
A*: Dijkstra on reduced prices (each edge's price plus the drop in a lower bound of the time to the goal),
with a distance limit so that scipy settles only the nodes that could lie on a route no slower than the
fastest; the limit starts from the last query's answer and grows until the goal is reached. The bound is the
time to the goal with only the outer walls, found once per start and goal set by a search back from the goal:
it is exact where the query's walls are open, so the unknown walls a search assumes open cost A* next to
nothing, and a wall it meets costs only the detour. The route itself comes from a second search, on the real
prices, of the small graph of the nodes A* found could lie on a fastest route (a few thousand of the 135 000
nodes of a 32x32 diagonal graph), so that it does not depend on the limit A* ran under.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import cached_property, lru_cache
from math import ceil

import numpy as np
from scipy.sparse import csr_array
from scipy.sparse.csgraph import dijkstra

from .direction import ALONG, DELTA, DIAGONAL, STEP, opposite
from .errors import MazeError
from .model import Cell, Maze, point_wall, sides_of
from .motion import HALF_DIAGONAL, TURNS, straight_seconds, turn_seconds
from .mouseparams import MouseParams

LAYERS = 4  # A, B, G, C
A, B, G, C = range(LAYERS)
MIN_SECONDS = 1e-9  # zero-length straights still need an edge, and scipy drops zero weights
MAX_CROSSINGS = 4  # the most walls a turn crosses (the 180)
MAX_QUERY_GRAPHS = 4  # (start, goals) pairs kept per move graph: a search has one, `path` of a cell run another
TIME_SLACK = 1e-9  # rounding in reduced prices must not leave out a node of an equally fast route
LIMIT_GROWTH = 2.0  # how much the search limit grows when the goal lies beyond it
HINT_MARGIN = 1.25  # the first limit over the last answer: a search's walls only ever make its run slower
LIMIT_TRIES = 16  # then no limit: a route that slow is unlikely, and without one the goal may be out of reach


@dataclass(frozen=True, order=True)
class TurnShape:
    """A turn placed with its entry point at the origin; `offsets` are the walls it crosses, the last one the exit."""

    name: str
    side: str  # "R" or "L"
    h_in: int
    h_out: int
    x_parity: int  # X % 2 of the entry point: 1 when it enters across a horizontal wall
    offsets: tuple[tuple[int, int], ...]

    @property
    def token(self) -> str:
        return self.side + self.name

    def rotated(self) -> TurnShape:
        """90 degrees anticlockwise: (x, y) -> (-y, x) swaps which walls are horizontal."""
        return TurnShape(self.name, self.side, (self.h_in + 2) % 8, (self.h_out + 2) % 8, 1 - self.x_parity,
                         tuple((-y, x) for x, y in self.offsets))

    def mirrored(self) -> TurnShape:
        return TurnShape(self.name, "L" if self.side == "R" else "R", (4 - self.h_in) % 8, (4 - self.h_out) % 8,
                         self.x_parity, tuple((-x, y) for x, y in self.offsets))

    def reversed(self) -> TurnShape:
        """The same curve run backwards (a 45 out of a diagonal is a 45 into one, run from its far end)."""
        ex, ey = self.offsets[-1]
        points = [(x - ex, y - ey) for x, y in self.offsets[-2::-1]] + [(-ex, -ey)]
        return TurnShape(self.name, "L" if self.side == "R" else "R", opposite(self.h_out), opposite(self.h_in),
                         (self.x_parity + ex) % 2, tuple(points))


# Right-hand turns entering northwards across a horizontal wall at (0, 0) (the V90: north-east across a
# vertical wall, turning left round the post at (1, 1)). The others are their rotations, mirror images and
# reversals.
ALONG_TURNS = (
    TurnShape("90s", "R", 2, 0, 1, ((1, 1),)),
    TurnShape("90", "R", 2, 0, 1, ((0, 2), (1, 3), (3, 3))),
    TurnShape("180", "R", 2, 6, 1, ((0, 2), (1, 3), (2, 2), (2, 0))),
)
DIAGONAL_TURNS = (
    TurnShape("45", "R", 2, 1, 1, ((0, 2), (1, 3))),
    TurnShape("135", "R", 2, 7, 1, ((0, 2), (1, 3), (2, 2))),
    TurnShape("V90", "L", 1, 3, 0, ((1, 1), (0, 2))),
)


def turn_shapes(diagonal: bool) -> list[TurnShape]:
    shapes = set()
    for base in ALONG_TURNS + (DIAGONAL_TURNS if diagonal else ()):
        for shape in (base, base.reversed()):
            for _ in range(4):
                shape = shape.rotated()
                shapes.update((shape, shape.mirrored()))
    return sorted(shapes)


@dataclass(frozen=True)
class Move:
    token: str  # S3 (3 cells along the walls), D2 (2 diagonal steps), R90, L45, RV90, ...
    cells: float  # path length in cells
    seconds: float


@dataclass(frozen=True)
class Route:
    moves: list[Move]
    seconds: float
    points: list[tuple[int, int]]  # half-cell coordinates: the start cell's centre, then every wall crossed
    walls: list[int]  # wall ids crossed, in order
    cells: list[Cell]  # the start cell, then each cell entered

    @property
    def length(self) -> float:
        return sum(m.cells for m in self.moves)

    @property
    def sequence(self) -> str:
        return " ".join(m.token for m in self.moves)


def _with_slack(seconds: float) -> float:
    """A time a little over `seconds`: reduced times carry rounding of their own."""
    return seconds + TIME_SLACK * (1 + seconds)


def _entered(point: tuple[int, int], previous: tuple[int, int]) -> Cell:
    """The cell on the far side of the wall at `point` for a mouse coming from `previous`."""
    x, y, _ = sides_of(point, previous)[1]
    return x, y


@dataclass
class QueryGraph:
    """The CSR graph of one start and goal set, and per edge (in its row order) what must be open for it: for a
    straight, `len` open walls ahead at node `key`; for a turn, its walls (one row per wall crossed); for a start
    edge, its first wall too. `graph` holds the prices (they depend on the mouse only); `valid` marks the
    edges the last query's walls leave open; `work` has the same edges, with the reduced prices for A* where
    valid and infinity elsewhere; `reduced` is each edge's reduced price, `bound` the bound at the start;
    `hint` is the last query's reduced time to the goal, where the next one's limit starts (walls change a few
    at a time)."""

    graph: csr_array
    work: csr_array
    reduced: np.ndarray
    valid: np.ndarray
    bound: float
    hint: float | None
    before_turns: int  # straights (rows of A) before the turns; the chain's (rows of C) after them
    st_key: np.ndarray
    st_len: np.ndarray
    tu_walls: np.ndarray
    s_key: np.ndarray
    s_len: np.ndarray
    s_wall: np.ndarray


class MoveGraph:
    """Every move a mouse could make in an N x N maze with all inner walls open, priced for one mouse."""

    def __init__(self, size: int, diagonal: bool, mouse: MouseParams) -> None:
        self.size, self.diagonal, self.mouse = size, diagonal, mouse
        self.side = 2 * size + 1
        self.layer = 8 * self.side ** 2
        self.start_node = LAYERS * self.layer
        xs, ys = np.meshgrid(np.arange(self.side), np.arange(self.side))
        self.px, self.py = xs.ravel(), ys.ravel()
        self.walls = 2 * size * (size + 1)
        self.open_sentinel, self.closed_sentinel = self.walls, self.walls + 1
        ids = (point_wall(size, x, y) for y in range(self.side) for x in range(self.side))
        self.wall_at = np.array([self.closed_sentinel if w is None else w for w in ids])
        rim = (self.px == 0) | (self.px == 2 * size) | (self.py == 0) | (self.py == 2 * size)
        self.outer_walls = np.unique(self.wall_at[rim & ((self.px + self.py) % 2 == 1)])
        self.headings = ALONG + (DIAGONAL if diagonal else ())
        self._build_runs()
        self._build_straights()
        self._build_turns()
        self._goal_masks: dict[tuple[Cell, ...], np.ndarray] = {}
        self._local = np.zeros(self.start_node + 1, dtype=np.int32)
        self._queries: dict[tuple[Cell, tuple[Cell, ...]], QueryGraph] = {}

    # -- geometry helpers -------------------------------------------------------------------------------------
    def _index(self, x: np.ndarray, y: np.ndarray) -> np.ndarray:
        return y * self.side + x

    def _inside(self, x: np.ndarray, y: np.ndarray) -> np.ndarray:
        return (x >= 0) & (x < self.side) & (y >= 0) & (y < self.side)

    def _stride(self, h: int) -> tuple[int, int]:
        dx, dy = STEP[h]
        return (2 * dx, 2 * dy) if h in ALONG else (dx, dy)

    def _entry_points(self, h: int) -> np.ndarray:
        """Point indices where a straight in heading h may cross a wall (along the walls: only across them)."""
        mid = (self.px + self.py) % 2 == 1
        if h in (0, 4):
            mid &= self.px % 2 == 0
        elif h in (2, 6):
            mid &= self.px % 2 == 1
        return np.flatnonzero(mid)

    def _top_speed(self, h: int) -> float:
        return self.mouse.run.top_speed if h in ALONG else self.mouse.run.diagonal_top_speed

    def _unit(self, h: int) -> float:
        return 1.0 if h in ALONG else HALF_DIAGONAL

    # -- the static graph -------------------------------------------------------------------------------------
    def _build_runs(self) -> None:
        """For the per-query 'how many open walls lie straight ahead' array: each node's next crossing."""
        nxt = np.zeros(self.layer, dtype=np.int64)
        nxt_wall = np.full(self.layer, self.closed_sentinel)
        for h in self.headings:
            pts = self._entry_points(h)
            sx, sy = self._stride(h)
            qx, qy = self.px[pts] + sx, self.py[pts] + sy
            ok = self._inside(qx, qy)
            q = self._index(qx[ok], qy[ok])
            nxt[pts[ok] * 8 + h] = q * 8 + h
            nxt_wall[pts[ok] * 8 + h] = self.wall_at[q]
        self.run_next, self.run_next_wall = nxt, nxt_wall
        # every node lies on one line of crossings in its heading: the lines as rows (padded with -1), so that
        # a query counts the open walls ahead of every node at once
        nodes = np.concatenate([self._entry_points(h) * 8 + h for h in self.headings])
        has_next = nxt_wall != self.closed_sentinel
        followed = np.zeros(self.layer, dtype=bool)
        followed[nxt[nodes[has_next[nodes]]]] = True
        column = nodes[~followed[nodes]]
        columns = [column]
        while True:
            column = np.where((column >= 0) & has_next[np.maximum(column, 0)], nxt[np.maximum(column, 0)], -1)
            if (column < 0).all():
                break
            columns.append(column)
        lines = np.stack(columns, axis=1)
        on_line = lines >= 0
        self.line_walls = np.where(on_line, nxt_wall[np.maximum(lines, 0)], self.closed_sentinel)
        self.line_flat, self.line_mask = lines[on_line], on_line

    def _build_straights(self) -> None:
        run = self.mouse.run
        src, dst, key, length, cost_b, cost_g, ends = [], [], [], [], [], [], []
        for h in self.headings:
            pts = self._entry_points(h)
            sx, sy = self._stride(h)
            top, unit = self._top_speed(h), self._unit(h)
            for n in range(min(2 * self._chain_k(h), 2 * self.size + 1)):
                ex, ey = self.px[pts] + n * sx, self.py[pts] + n * sy
                ok = self._inside(ex, ey)
                if not ok.any():
                    break
                p, e = pts[ok], self._index(ex[ok], ey[ok])
                metres = n * unit * self.mouse.cell
                src.append(p * 8 + h)
                dst.append(e * 8 + h)
                key.append(p * 8 + h)
                length.append(np.full(len(p), n))
                cost_b.append(np.full(len(p), max(MIN_SECONDS, straight_seconds(
                    metres, run.turn_speed, run.turn_speed, top, run.accel))))
                cost_g.append(np.full(len(p), max(MIN_SECONDS, straight_seconds(
                    metres, run.turn_speed, None, top, run.accel))))
                ends.append(self._entered_cells(e, h))
        self.st_src = np.concatenate(src)
        self.st_dst = np.concatenate(dst)
        self.st_key = np.concatenate(key)
        self.st_len = np.concatenate(length)
        self.st_cost_b = np.concatenate(cost_b)
        self.st_cost_g = np.concatenate(cost_g)
        self.st_end_cell = np.concatenate(ends)
        # a free-ended straight to the goal line of k or more steps goes through the chain (see _build_chain)
        self.st_g_direct = self.st_len < np.array([self._chain_k(h) for h in range(8)])[self.st_key % 8]
        self._build_chain()

    def _chain_k(self, h: int) -> int:
        """Steps a straight in heading h needs to reach top speed from turn speed (and to brake back)."""
        run, top = self.mouse.run, self._top_speed(h)
        step = self._unit(h) * self.mouse.cell
        d_up = (top * top - run.turn_speed ** 2) / (2 * run.accel)
        k = max(1, ceil(d_up / step))
        return k + 1 if k * step < d_up else k

    def _build_chain(self) -> None:
        """Long straights as a chain, so that their count grows with the maze and not with its square: from A, k
        steps speeding up to top speed into layer C; in C one step at top speed at a time; from C, k steps braking
        into B, or straight over the goal line into G. A straight of n >= 2k steps then costs exactly its
        trapezoid, and one of n >= k steps to the goal line its free-ended time."""
        run = self.mouse.run
        src, dst, key, length, cost, goal_cell = [], [], [], [], [], []
        for h in self.headings:
            pts = self._entry_points(h)
            sx, sy = self._stride(h)
            k, top = self._chain_k(h), self._top_speed(h)
            step = self._unit(h) * self.mouse.cell
            speed_up = straight_seconds(k * step, run.turn_speed, None, top, run.accel)  # braking costs the same
            nodes = pts * 8 + h
            for n, seconds, from_layer, to_layer in ((k, speed_up, A, C), (1, step / top, C, C), (k, speed_up, C, B)):
                ex, ey = self.px[pts] + n * sx, self.py[pts] + n * sy
                ok = self._inside(ex, ey)
                src.append(nodes[ok] + from_layer * self.layer)
                dst.append(self._index(ex[ok], ey[ok]) * 8 + h + to_layer * self.layer)
                key.append(nodes[ok])
                length.append(np.full(ok.sum(), n))
                cost.append(np.full(ok.sum(), seconds))
                goal_cell.append(np.full(ok.sum(), -1))
            src.append(nodes + C * self.layer)  # C -> G: over the goal line at top speed (goals chosen per query)
            dst.append(nodes + G * self.layer)
            key.append(nodes)
            length.append(np.zeros(len(nodes), dtype=np.int64))
            cost.append(np.zeros(len(nodes)))  # an explicit zero in a CSR matrix is an edge to scipy
            goal_cell.append(self._entered_cells(pts, h))
        self.ch_src, self.ch_dst = np.concatenate(src), np.concatenate(dst)
        self.ch_key, self.ch_len = np.concatenate(key), np.concatenate(length)
        self.ch_cost, self.ch_goal_cell = np.concatenate(cost), np.concatenate(goal_cell)

    def _entered_cells(self, points: np.ndarray, h: int) -> np.ndarray:
        """Flat index of the cell a mouse heading h enters at each wall point (-1 outside the maze)."""
        x, y = self.px[points], self.py[points]
        dx, dy = STEP[h]
        horizontal = x % 2 == 1
        cx = np.where(horizontal, x // 2, x // 2 - (dx < 0))
        cy = np.where(horizontal, y // 2 - (dy < 0), y // 2)
        inside = (cx >= 0) & (cx < self.size) & (cy >= 0) & (cy < self.size)
        return np.where(inside, cy * self.size + cx, -1)

    def _build_turns(self) -> None:
        src, dst, walls, shape_ids = [], [], [], []
        self.shapes = turn_shapes(self.diagonal)
        costs = []
        for i, shape in enumerate(self.shapes):
            pts = np.flatnonzero(((self.px + self.py) % 2 == 1) & (self.px % 2 == shape.x_parity))
            ok = np.ones(len(pts), dtype=bool)
            crossed = []
            for ox, oy in shape.offsets:
                qx, qy = self.px[pts] + ox, self.py[pts] + oy
                ok &= self._inside(qx, qy)
                crossed.append((qx, qy))
            pts = pts[ok]
            cols = [self.wall_at[self._index(qx[ok], qy[ok])] for qx, qy in crossed]
            cols += [np.full(len(pts), self.open_sentinel)] * (MAX_CROSSINGS - len(cols))
            ex, ey = crossed[-1]
            src.append(pts * 8 + shape.h_in + self.layer)
            dst.append(self._index(ex[ok], ey[ok]) * 8 + shape.h_out)
            walls.append(np.stack(cols, axis=1))
            shape_ids.append(np.full(len(pts), i))
            costs.append(np.full(len(pts), turn_seconds(shape.name, self.mouse)))
        self.tu_src = np.concatenate(src)
        self.tu_dst = np.concatenate(dst)
        self.tu_walls = np.concatenate(walls)
        self.tu_shape = np.concatenate(shape_ids)
        self.tu_cost = np.concatenate(costs)

    @cached_property
    def _wall_list(self) -> list[int]:
        return self.wall_at.tolist()

    @cached_property
    def _turn_lookup(self) -> dict[tuple[int, int], int]:
        return dict(zip(zip(self.tu_src.tolist(), self.tu_dst.tolist()), self.tu_shape.tolist()))

    def _goal_mask(self, goals: tuple[Cell, ...]) -> np.ndarray:
        if goals not in self._goal_masks:
            flat = [y * self.size + x for x, y in goals]
            self._goal_masks[goals] = np.isin(self.st_end_cell, flat)
        return self._goal_masks[goals]

    # -- queries ----------------------------------------------------------------------------------------------
    def _runs(self, open_ext: np.ndarray) -> np.ndarray:
        """Open walls straight ahead of every node: along each line, the distance to its next closed crossing."""
        width = self.line_walls.shape[1]
        position = np.arange(width, dtype=np.int16)
        closed_at = np.where(open_ext[self.line_walls], np.int16(width), position)
        next_closed = np.minimum.accumulate(closed_at[:, ::-1], axis=1)[:, ::-1]
        run = np.zeros(self.layer, dtype=np.int16)
        run[self.line_flat] = (next_closed - position)[self.line_mask]
        return run

    def _query(self, start: Cell, goals: tuple[Cell, ...]) -> QueryGraph:
        """The whole graph for one start and goal set, in row order, built once: a query only prices its edges
        (infinite where a wall blocks them), so no sparse matrix is assembled per query."""
        key = (start, goals)
        if key not in self._queries:
            if len(self._queries) >= MAX_QUERY_GRAPHS:
                self._queries.pop(next(iter(self._queries)))
            self._queries[key] = self._build_query(start, goals)
        return self._queries[key]

    def _build_query(self, start: Cell, goals: tuple[Cell, ...]) -> QueryGraph:
        to_goal = self._goal_mask(goals) & self.st_g_direct
        in_goal = np.isin(self.ch_goal_cell, [y * self.size + x for x, y in goals])
        chain = (self.ch_goal_cell < 0) | in_goal
        # the straights' and the chain's edges all need open walls ahead; their rows (A, then C) come before and
        # after the turns' (B) in the matrix, so they are kept as one array in row order with the turns between
        src = np.concatenate([self.st_src, self.st_src[to_goal], self.ch_src[chain]])
        order = np.argsort(src, kind="stable")
        st_dst = np.concatenate([self.st_dst + B * self.layer, self.st_dst[to_goal] + G * self.layer,
                                 self.ch_dst[chain]])[order]
        st_key = np.concatenate([self.st_key, self.st_key[to_goal], self.ch_key[chain]])[order]
        st_len = np.concatenate([self.st_len, self.st_len[to_goal], self.ch_len[chain]])[order]
        st_cost = np.concatenate([self.st_cost_b, self.st_cost_g[to_goal], self.ch_cost[chain]])[order]
        t_order = np.argsort(self.tu_src, kind="stable")
        s_dst, s_key, s_len, s_wall, s_cost = self._start_edges(start, goals)
        src = src[order]
        before = int(np.searchsorted(src, B * self.layer))  # rows of A; those of C follow the turns
        rows = np.concatenate([src[:before], self.tu_src[t_order], src[before:],
                               np.full(len(s_dst), self.start_node)])
        cols = np.concatenate([st_dst[:before], self.tu_dst[t_order], st_dst[before:], s_dst]).astype(np.int32)
        n = self.start_node + 1
        indptr = np.concatenate([[0], np.cumsum(np.bincount(rows, minlength=n))]).astype(np.int32)
        cost = np.concatenate([st_cost[:before], self.tu_cost[t_order], st_cost[before:], s_cost])
        graph = csr_array((cost, cols, indptr), shape=(n, n))
        work = csr_array((np.zeros(len(cols)), cols, indptr), shape=(n, n))
        q = QueryGraph(graph, work, cost, np.zeros(len(cols), dtype=bool), 0.0, None, before, st_key, st_len,
                       self.tu_walls[t_order].T.copy(), s_key, s_len, s_wall)
        bound = self._time_bound(q)
        with np.errstate(invalid="ignore"):  # an edge between nodes that never reach the goal: inf - inf
            reduced = np.maximum(cost + bound[cols] - bound[rows], 0.0)
        reduced[~np.isfinite(reduced)] = np.inf  # such an edge is never on a route
        q.reduced, q.bound = reduced, float(bound[self.start_node])
        return q

    def _time_bound(self, q: QueryGraph) -> np.ndarray:
        """Per node, the time left to the goal in the maze with only its outer walls (infinite where even that
        never reaches it). Each query's open edges are some of these, at the same prices, so no route is faster
        than the bound: the reduced prices price + bound(v) - bound(u) are never negative (up to rounding,
        which is clamped) and A* stays exact."""
        outer_only = np.zeros(self.walls, dtype=np.uint8)  # _open_edges closes the outer walls itself
        prices = np.where(self._open_edges(q, outer_only), q.graph.data, np.inf)
        back = csr_array((prices, q.graph.indices, q.graph.indptr), shape=q.graph.shape).T
        goal_layer = q.graph.indices[(q.graph.indices >= G * self.layer) & (q.graph.indices < (G + 1) * self.layer)]
        return dijkstra(csr_array(back), directed=True, indices=np.unique(goal_layer), min_only=True)

    def _start_edges(self, start: Cell, goals: tuple[Cell, ...]) -> tuple[np.ndarray, ...]:
        """Straights from a standing start in the start cell's centre, along each of its four headings, of every
        length: the n-th needs the first wall open and n - 1 open ones after it."""
        p = self.mouse.run
        cx, cy = 2 * start[0] + 1, 2 * start[1] + 1
        dst: list[int] = []
        key: list[int] = []
        length: list[int] = []
        wall: list[int] = []
        cost: list[float] = []
        goal_set = set(goals)
        for h in ALONG:
            dx, dy = STEP[h]
            first = self._index(cx + dx, cy + dy)
            for n in range(1, 2 * self.size + 1):
                x, y = cx + (2 * n - 1) * dx, cy + (2 * n - 1) * dy
                if not (0 <= x < self.side and 0 <= y < self.side):
                    break
                node = self._index(x, y) * 8 + h
                metres = (n - 0.5) * self.mouse.cell
                ends = [(node + B * self.layer, straight_seconds(metres, 0.0, p.turn_speed, p.top_speed, p.accel))]
                if _entered((x, y), (x - dx, y - dy)) in goal_set:
                    ends.append((node + G * self.layer, straight_seconds(metres, 0.0, None, p.top_speed, p.accel)))
                for end, seconds in ends:
                    dst.append(end)
                    key.append(first * 8 + h)
                    length.append(n - 1)
                    wall.append(int(self.wall_at[first]))
                    cost.append(seconds)
        return (np.array(dst, dtype=np.int64), np.array(key, dtype=np.int64), np.array(length, dtype=np.int64),
                np.array(wall, dtype=np.int64), np.array(cost))

    def _open_edges(self, q: QueryGraph, blocked: bytes | bytearray | np.ndarray) -> np.ndarray:
        """Per edge (in row order), whether the walls not blocked let the mouse make it. The outer walls are
        closed whatever `blocked` says: no move leaves the maze (and the bound relies on it)."""
        open_ext = np.concatenate([np.frombuffer(bytes(blocked), dtype=np.uint8) == 0, [True, False]])
        open_ext[self.outer_walls] = False
        run = self._runs(open_ext)
        straights = run[q.st_key] >= q.st_len
        turns = open_ext[q.tu_walls[0]]
        for walls in q.tu_walls[1:]:
            turns &= open_ext[walls]
        starts = open_ext[q.s_wall] & (run[q.s_key] >= q.s_len)
        return np.concatenate([straights[:q.before_turns], turns, straights[q.before_turns:], starts])

    def _price(self, q: QueryGraph, blocked: bytes | bytearray) -> None:
        """Which edges the walls leave open, and the reduced prices for A* (infinite where a wall is blocked)."""
        q.valid = self._open_edges(q, blocked)
        q.work.data = np.where(q.valid, q.reduced, np.inf)

    def _search(self, q: QueryGraph) -> tuple[list[int], list[float]] | None:
        """The nodes of a fastest route and the time at each; None if the goal cannot be reached. A* on the
        reduced prices finds how fast the goal can be reached and which nodes could lie on so fast a route;
        a search on their prices, limited to that time, then settles them in the order a search of the whole
        graph would (so that among equally fast routes it picks the same one, whatever A*'s limit was). That
        search runs on the graph of those nodes alone, each row's edges in their order."""
        reduced = self._reduced_search(q)
        if reduced is None:
            return None
        fastest = float(reduced[self._goal_node(reduced)])
        kept = reduced <= _with_slack(fastest)
        nodes = np.flatnonzero(kept)  # ascending: local numbers keep the global order
        first = q.graph.indptr[nodes]
        count = q.graph.indptr[nodes + 1] - first
        row = np.repeat(np.arange(len(nodes)), count)
        edge = np.arange(len(row)) + np.repeat(first - (np.cumsum(count) - count), count)
        col = q.graph.indices[edge]
        use = q.valid[edge] & kept[col]
        row, edge, col = row[use], edge[use], col[use]
        indptr = np.concatenate([[0], np.cumsum(np.bincount(row, minlength=len(nodes)))])
        local = self._local  # node -> its number in `nodes`; read only where kept
        local[nodes] = np.arange(len(nodes), dtype=np.int32)
        sub = csr_array((q.graph.data[edge], local[col], indptr), shape=(len(nodes), len(nodes)))
        dist, pred = dijkstra(sub, directed=True, indices=len(nodes) - 1, return_predecessors=True,
                              limit=_with_slack(fastest + q.bound))  # the start node is the last node
        in_goal = np.flatnonzero((nodes >= G * self.layer) & (nodes < (G + 1) * self.layer))
        at = [int(in_goal[np.argmin(dist[in_goal])])]  # the lowest-numbered of equals, as _goal_node
        while at[-1] != len(nodes) - 1:
            at.append(int(pred[at[-1]]))
        at.reverse()
        return nodes[at].tolist(), dist[at].tolist()

    def _reduced_search(self, q: QueryGraph) -> np.ndarray | None:
        """A* up to the goal: the reduced times; None if the goal cannot be reached. The limit
        (on reduced time) only leaves out nodes whose time plus bound exceeds it, so the first limit that
        reaches the goal finds a fastest route. A query with every wall it needs open has a reduced time of 0;
        the first limit is at least one cell at top speed. A limit the goal lies beyond costs a whole search,
        and the walls a search finds only ever slow its fastest run, so the first limit has a margin over the
        last answer; the route does not depend on the limit (`_search`)."""
        limit = max((q.hint or 0.0) * HINT_MARGIN, self.mouse.cell / self.mouse.run.top_speed)
        for limit in [limit * LIMIT_GROWTH ** k for k in range(LIMIT_TRIES)] + [np.inf]:
            dist = dijkstra(q.work, directed=True, indices=self.start_node, limit=limit)
            best = self._goal_node(dist)
            if np.isfinite(dist[best]):
                q.hint = float(dist[best])
                return dist
        return None

    def _goal_node(self, dist: np.ndarray) -> int:
        """The node of the goal layer reached first (the lowest-numbered of equals)."""
        return int(np.argmin(dist[G * self.layer: (G + 1) * self.layer])) + G * self.layer

    def fastest(self, blocked: bytes | bytearray, start: Cell, goals: tuple[Cell, ...]) -> Route | None:
        """The fastest run through walls not blocked (1 = blocked, indexed by wall id); None if there is none."""
        q = self._query(start, goals)
        self._price(q, blocked)
        found = self._search(q)
        if found is None:
            return None
        return self._route(*found, start)

    def _point(self, node: int) -> tuple[tuple[int, int], int]:
        p, h = divmod(node % self.layer, 8)
        return (p % self.side, p // self.side), h

    def _edge(self, u: int, v: int, start: Cell) -> tuple[list[tuple[int, int]], str, float]:
        """The walls a start or turn edge u->v crosses (as points), its token and its length in cells."""
        (vx, vy), h = self._point(v)
        if u == self.start_node:
            cx, cy = 2 * start[0] + 1, 2 * start[1] + 1
            dx, dy = STEP[h]
            n = (abs(vx - cx) + abs(vy - cy) + 1) // 2
            return [(cx + (2 * k - 1) * dx, cy + (2 * k - 1) * dy) for k in range(1, n + 1)], f"S{n - 0.5:g}", n - 0.5
        (ux, uy), _ = self._point(u)
        shape = self.shapes[self._turn_lookup[(u, v)]]
        return [(ux + ox, uy + oy) for ox, oy in shape.offsets], shape.token, TURNS[shape.name].cells

    def _route(self, nodes: list[int], times: list[float], start: Cell) -> Route:
        """The moves of a route: a straight is its pieces (A to B or G directly, or through the chain in C)
        joined, its walls counted from where it began."""
        points = [(2 * start[0] + 1, 2 * start[1] + 1)]
        moves: list[Move] = []
        begin, length = 0, 0.0  # the step the straight being joined began at, and its cells so far
        for i, (u, v) in enumerate(zip(nodes, nodes[1:])):
            if u == self.start_node or u // self.layer == B:
                crossed, token, cells = self._edge(u, v, start)
                points += crossed
                moves.append(Move(token, cells, times[i + 1] - times[i]))
                begin, length = i + 1, 0.0
                continue
            (ux, uy), h = self._point(u)
            (vx, vy), _ = self._point(v)
            sx, sy = self._stride(h)
            length += max(abs(vx - ux) // max(abs(sx), 1), abs(vy - uy) // max(abs(sy), 1)) * self._unit(h)
            if v // self.layer in (B, G):  # the straight ends here
                (bx, by), _ = self._point(nodes[begin])
                steps = max(abs(vx - bx) // max(abs(sx), 1), abs(vy - by) // max(abs(sy), 1))
                points += [(bx + k * sx, by + k * sy) for k in range(1, steps + 1)]
                if steps:
                    moves.append(Move(f"{'S' if h in ALONG else 'D'}{steps}", length, times[i + 1] - times[begin]))
        cells = [start] + [_entered(p, q) for q, p in zip(points, points[1:])]
        wall_at = self._wall_list
        walls = [wall_at[y * self.side + x] for x, y in points[1:]]
        return Route(moves, times[-1], points, walls, cells)


@lru_cache(maxsize=4)
def move_graph(size: int, diagonal: bool, mouse: MouseParams) -> MoveGraph:
    return MoveGraph(size, diagonal, mouse)


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

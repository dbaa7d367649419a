"""A route as the commands print it: the nodes and times a query found (maze/fastpath_query.py) decoded into moves,
the wall points crossed, the walls and the cells entered."""

from __future__ import annotations

import ctypes
from dataclasses import dataclass
from functools import cached_property

import numpy as np

from .direction import ALONG, STEP
from .fastpath_build import MAX_CROSSINGS, B, G, StaticGraph
from .fastpath_kernel import kernel
from .model import Cell
from .motion import TURNS


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


class RouteDecoder:
    """Turns a path of nodes of one move graph into a Route."""

    def __init__(self, graph: StaticGraph) -> None:
        self.graph = graph

    @cached_property
    def _steps(self) -> list[tuple[int, int, int, int, float]]:
        """Per heading, the stride between the walls a straight crosses (x, y), what a coordinate difference
        is divided by to count them (x, y), and the cells a stride covers: looked up once per node."""
        g = self.graph
        out = []
        for h in range(8):
            sx, sy = g.stride(h)
            out.append((sx, sy, max(abs(sx), 1), max(abs(sy), 1), g.unit(h)))
        return out

    @cached_property
    def _turn_keys(self) -> tuple[np.ndarray, np.ndarray]:
        """The turn edges' keys (source node * node count + destination node, each pair once), sorted, and
        their shapes' indices in that order: a route looks up a few dozen of the 60 000 turns of a 32x32
        diagonal graph, so sorting once (milliseconds) beats building a dict of them all (tens)."""
        turns = self.graph.turns
        keys = turns.src * (self.graph.start_node + 1) + turns.dst
        order = np.argsort(keys)
        return keys[order], turns.shape[order]

    def _turn_shapes(self, keys: list[int]) -> list[int]:
        """The shapes' indices of turn edges u->v, keyed u * node count + v: one look-up for a whole route."""
        sorted_keys, shapes = self._turn_keys
        return shapes[np.searchsorted(sorted_keys, keys)].tolist()

    @cached_property
    def _kernel_arrays(self) -> tuple[np.ndarray, ...]:
        """What fp_route (maze/fastpath_kernel.c) reads: per heading its step, stride and cells a step; the
        turns' keys and shapes (`_turn_keys`); per shape its wall points (padded to MAX_CROSSINGS) and their
        count; the wall at each point."""
        g = self.graph
        offsets = np.zeros((len(g.shapes), MAX_CROSSINGS, 2), dtype=np.int32)
        for i, shape in enumerate(g.shapes):
            offsets[i, :len(shape.offsets)] = shape.offsets
        keys, shapes = self._turn_keys
        return (np.array([dx for dx, _ in STEP], dtype=np.int32), np.array([dy for _, dy in STEP], dtype=np.int32),
                np.array([max(abs(c) for c in g.stride(h)) for h in range(8)], dtype=np.int32),
                np.array([g.unit(h) for h in range(8)]), keys.astype(np.int64), shapes.astype(np.int32), offsets,
                np.array([len(s.offsets) for s in g.shapes], dtype=np.int32), g.wall_at.astype(np.int64))

    @cached_property
    def _cells_of_shape(self) -> list[float]:
        return [TURNS[shape.name].cells for shape in self.graph.shapes]

    def route(self, nodes: list[int], times: list[float], start: Cell) -> Route:
        """The moves of a route, by fp_route where the kernel was built, else in Python (`_route`)."""
        lib = kernel()
        if lib is None:
            return self._route(nodes, times, start)
        g = self.graph
        count = len(nodes)
        node_array, time_array = np.array(nodes, dtype=np.int64), np.array(times)
        kind, value = np.empty(count, dtype=np.int32), np.empty(count, dtype=np.int32)
        cells, seconds = np.empty(count), np.empty(count)
        most = count * (2 * g.side + MAX_CROSSINGS) + 1
        px, py, cell_x, cell_y = (np.empty(most, dtype=np.int32) for _ in range(4))
        wall, npoints = np.empty(most, dtype=np.int64), ctypes.c_int32(0)
        moves = lib.fp_route(
            node_array.ctypes.data, time_array.ctypes.data, count, g.start_node, g.layer_size, g.side,
            B, G, 2 * start[0] + 1, 2 * start[1] + 1,
            *(a.ctypes.data for a in self._kernel_arrays[:5]), len(self._kernel_arrays[4]),
            *(a.ctypes.data for a in self._kernel_arrays[5:8]), MAX_CROSSINGS, self._kernel_arrays[8].ctypes.data,
            *(a.ctypes.data for a in (kind, value, cells, seconds, px, py, cell_x, cell_y, wall)),
            ctypes.byref(npoints))
        n = npoints.value
        shapes, cells_of = self.graph.shapes, self._cells_of_shape
        out = []
        for k, v, c, t in zip(kind[:moves].tolist(), value[:moves].tolist(), cells[:moves].tolist(),
                              seconds[:moves].tolist()):
            if k == 0:
                out.append(Move(f"S{v - 0.5:g}", v - 0.5, t))
            elif k == 1:
                out.append(Move(shapes[v].token, cells_of[v], t))
            else:
                out.append(Move(f"{'S' if k == 2 else 'D'}{v}", c, t))
        return Route(out, times[-1], list(zip(px[:n].tolist(), py[:n].tolist())), wall[:n - 1].tolist(),
                     [start] + list(zip(cell_x[:n - 1].tolist(), cell_y[:n - 1].tolist())))

    def _route(self, nodes: list[int], times: list[float], start: Cell) -> Route:
        """The moves of a route: a straight is its pieces (A to B or G directly, or through the chain in C)
        joined, its walls counted from where it began. Nodes are decoded all at once and the turns looked up
        together: a route has a hundred-odd nodes, and a query with known walls is mostly this."""
        g = self.graph
        count = g.start_node + 1
        layer_of, within = np.divmod(np.array(nodes), g.layer_size)
        point, heading = np.divmod(within, 8)
        layers, headings = layer_of.tolist(), heading.tolist()
        xs, ys = (point % g.side).tolist(), (point // g.side).tolist()
        turning = [i for i in range(len(nodes) - 1) if layers[i] == B]
        shape_of = dict(zip(turning, self._turn_shapes([nodes[i] * count + nodes[i + 1] for i in turning])))
        cx, cy = 2 * start[0] + 1, 2 * start[1] + 1
        points = [(cx, cy)]
        moves: list[Move] = []
        begin, length = 0, 0.0  # the step the straight being joined began at, and its cells so far
        per_heading = self._steps
        for i in range(len(nodes) - 1):
            vx, vy = xs[i + 1], ys[i + 1]
            if nodes[i] == g.start_node:
                dx, dy = STEP[headings[i + 1]]
                n = (abs(vx - cx) + abs(vy - cy) + 1) // 2
                points += [(cx + (2 * k - 1) * dx, cy + (2 * k - 1) * dy) for k in range(1, n + 1)]
                moves.append(Move(f"S{n - 0.5:g}", n - 0.5, times[i + 1] - times[i]))
                begin, length = i + 1, 0.0
                continue
            ux, uy, h = xs[i], ys[i], headings[i]
            if layers[i] == B:
                shape = g.shapes[shape_of[i]]
                points += [(ux + ox, uy + oy) for ox, oy in shape.offsets]
                moves.append(Move(shape.token, TURNS[shape.name].cells, times[i + 1] - times[i]))
                begin, length = i + 1, 0.0
                continue
            sx, sy, ax, ay, unit = per_heading[h]
            length += max(abs(vx - ux) // ax, abs(vy - uy) // ay) * unit
            if layers[i + 1] in (B, G):  # the straight ends here
                bx, by = xs[begin], ys[begin]
                steps = max(abs(vx - bx) // ax, abs(vy - by) // ay)
                points += [(bx + k * sx, by + k * sy) for k in range(1, steps + 1)]
                if steps:
                    moves.append(Move(f"{'S' if h in ALONG else 'D'}{steps}", length, times[i + 1] - times[begin]))
        cells, walls = self._crossed(points)
        return Route(moves, times[-1], points, walls, [start] + cells)

    def _crossed(self, points: list[tuple[int, int]]) -> tuple[list[Cell], list[int]]:
        """The cells entered and the walls crossed at `points[1:]`, all at once: the cell beyond a horizontal
        wall (X odd) lies above it when coming from below, the one beyond a vertical wall right of it when
        coming from its left (`entered_cell`, one call a point, was a third of a known-walls query)."""
        g = self.graph
        at = np.array(points)
        x, y = at[1:, 0], at[1:, 1]
        came_x, came_y = at[:-1, 0], at[:-1, 1]
        horizontal = x % 2 == 1
        cell_x = x // 2 - (~horizontal & (came_x > x))
        cell_y = y // 2 - (horizontal & (came_y > y))
        cells = list(zip(cell_x.tolist(), cell_y.tolist()))
        return cells, g.wall_at[y * g.side + x].tolist()

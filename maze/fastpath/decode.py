"""The nodes and times a query of the scipy path found (maze/fastpath/query.py) decoded into a Route
(maze/timing/route.py): its moves, the wall points crossed, the walls and the cells entered. The compiled kernel
decodes its own (fp_decode in maze/fastpath/kernel.c)."""

from __future__ import annotations

from functools import cached_property

import numpy as np

from ..direction import ALONG, STEP
from ..model import Cell
from ..timing.motion import TURNS
from ..timing.route import Move, Route
from .build import StaticGraph
from .graph import B, G


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

    def route(self, nodes: list[int], times: list[float], start: Cell) -> Route:
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

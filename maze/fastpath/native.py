"""The fastest-path queries on the compiled kernel (maze/fastpath/kernel.c), with no numpy.

The kernel builds the move graph of each start and goal set itself (fp_graph), node for node and edge for edge
the graph maze/fastpath/build.py and fastpath/query.py build in numpy, and answers a query in two calls: the
search (fp_query: pricing, the bound, A*, the exact search) and the route's decoding (fp_decode). Python works
out only what the time model and the turns' shapes say (maze/fastpath/graph.py), a few hundred numbers, so that
a process that times a run imports neither numpy (0.1 s) nor scipy and builds no graph in them (0.05 s). The
routes are the numpy and scipy path's to the bit (tests/maze/test_maze_fastpath_kernel.py compares them query
after query).
"""

from __future__ import annotations

import ctypes
import weakref
from array import array
from collections.abc import Sequence
from typing import Any

from ..direction import ALONG, DIAGONAL
from ..model import Cell, point_wall
from ..timing.motion import TURNS, turn_seconds
from ..timing.mouseparams import MouseParams
from ..timing.route import Move, Route
from .compiled import Spec
from .graph import (
    MAX_CROSSINGS,
    MAX_QUERY_GRAPHS,
    TIME_SLACK,
    chain_prices,
    chain_steps,
    start_edges,
    straight_prices,
    turn_shapes,
    unit,
)


def _ints(values: Sequence[int]) -> ctypes.Array[ctypes.c_int32]:
    return (ctypes.c_int32 * max(len(values), 1))(*values)


def _doubles(values: Sequence[float]) -> ctypes.Array[ctypes.c_double]:
    return (ctypes.c_double * max(len(values), 1))(*values)


class _Graph:
    """The kernel's graph of one start and goal set (fp_graph copies what it keeps of the spec), freed with this;
    and what its queries write, kept from query to query (a 32x32 graph's route arrays alone are 0.5 MB)."""

    def __init__(self, lib: ctypes.CDLL, spec: Spec) -> None:
        self.handle = lib.fp_graph(ctypes.byref(spec))
        if not self.handle:
            raise MemoryError("no memory for the fastest-path kernel's graph")
        weakref.finalize(self, lib.fp_graph_free, self.handle)
        nodes = lib.fp_graph_nodes(self.handle)
        self.route, self.times = array("i", [0]) * nodes, array("d", [0.0]) * nodes
        self.kind, self.value = array("i", [0]) * nodes, array("i", [0]) * nodes
        self.cells, self.seconds = array("d", [0.0]) * nodes, array("d", [0.0]) * nodes
        self.points: list[array[int]] = []

    def point_arrays(self, most: int) -> list[array[int]]:
        """Per wall point of a route: x, y, the cell entered (x, y) and the wall; at least `most` of each."""
        if not self.points or len(self.points[0]) < most:
            self.points = [array("i", [0]) * (2 * most) for _ in range(5)]
        return self.points


class NativeGraph:
    """The move graph of one maze size, diagonal flag and mouse, on the kernel: what MoveGraph is on numpy."""

    def __init__(self, lib: ctypes.CDLL, size: int, diagonal: bool, mouse: MouseParams) -> None:
        self.lib, self.size, self.mouse = lib, size, mouse
        self.shapes = turn_shapes(diagonal)
        side = 2 * size + 1
        closed = 2 * size * (size + 1) + 1  # the always-closed sentinel, where a point is no wall
        self.wall_at = [closed if (w := point_wall(size, p % side, p // side)) is None else w
                        for p in range(side * side)]
        headings = ALONG + (DIAGONAL if diagonal else ())
        steps = [chain_steps(mouse, h) for h in range(8)]
        max_n = max(min(2 * k, 2 * size + 1) for k in steps)
        prices = [straight_prices(mouse, h, n) if h in headings and n < min(2 * steps[h], 2 * size + 1) else (0, 0)
                  for h in range(8) for n in range(max_n)]
        chain = [chain_prices(mouse, h) for h in range(8)]
        offsets = [c for s in self.shapes for c in [v for xy in s.offsets for v in xy] + [0] * (2 * MAX_CROSSINGS
                                                                                                - 2 * len(s.offsets))]
        self._arrays: dict[str, Any] = {  # kept alive for as long as the spec points at them
            "to_turn": _doubles([t for t, _ in prices]), "to_goal": _doubles([g for _, g in prices]),
            "shape_in": _ints([s.h_in for s in self.shapes]), "shape_out": _ints([s.h_out for s in self.shapes]),
            "shape_parity": _ints([s.x_parity for s in self.shapes]),
            "shape_noffsets": _ints([len(s.offsets) for s in self.shapes]), "shape_offsets": _ints(offsets),
            "shape_seconds": _doubles([turn_seconds(s.name, mouse) for s in self.shapes]),
            "wall_at": _ints(self.wall_at)}
        self._spec = dict(size=size, has=(ctypes.c_int32 * 8)(*(h in headings for h in range(8))),
                          k=(ctypes.c_int32 * 8)(*steps), max_n=max_n,
                          speed_up=(ctypes.c_double * 8)(*(s for s, _ in chain)),
                          cruise=(ctypes.c_double * 8)(*(c for _, c in chain)),
                          unit=(ctypes.c_double * 8)(*(unit(h) for h in range(8))), nshapes=len(self.shapes),
                          slack=TIME_SLACK)
        self._graphs: dict[tuple[Cell, tuple[Cell, ...]], _Graph] = {}
        self._turns = [(s.token, TURNS[s.name].cells) for s in self.shapes]  # per shape: its move's token, cells
        self._tokens: tuple[dict[int, str], ...] = ({}, {}, {}, {})  # per kind of move: its value's token, once made

    def _graph(self, start: Cell, goals: tuple[Cell, ...]) -> _Graph:
        """The kernel's graph of one start and goal set, built once and kept."""
        key = (start, goals)
        if key not in self._graphs:
            if len(self._graphs) >= MAX_QUERY_GRAPHS:
                self._graphs.pop(next(iter(self._graphs)))
            edges = start_edges(self.size, self.wall_at, self.mouse, start, goals)
            arrays = dict(self._arrays, start_dst=_ints([e.dst for e in edges]),
                          start_run_from=_ints([e.run_from for e in edges]),
                          start_open_needed=_ints([e.open_needed for e in edges]),
                          start_first_wall=_ints([e.first_wall for e in edges]),
                          start_seconds=_doubles([e.seconds for e in edges]),
                          goal_cells=_ints([y * self.size + x for x, y in goals]))
            spec = Spec(**self._spec, nstart=len(edges), ngoals=len(goals),
                        **{name: ctypes.cast(a, ctypes.POINTER(a._type_)) for name, a in arrays.items()})
            self._graphs[key] = _Graph(self.lib, spec)
        return self._graphs[key]

    def fastest(self, blocked: bytes | bytearray, start: Cell, goals: tuple[Cell, ...]) -> Route | None:
        """The fastest run through walls not blocked (1 = blocked, indexed by wall id); None if there is none."""
        g = self._graph(start, goals)
        count = self.lib.fp_query(g.handle, bytes(blocked), _at(g.route), _at(g.times))
        if not count:
            return None
        return self._decode(g, count, start)

    def _decode(self, g: _Graph, count: int, start: Cell) -> Route:
        """The moves of a route, by fp_decode: per move its kind (0 the start's straight, 1 a turn, 2 a straight
        along the walls, 3 a diagonal one), value (cells, shape or steps), cells and time."""
        points = g.point_arrays(count * (2 * (2 * self.size + 1) + MAX_CROSSINGS) + 1)
        npoints = ctypes.c_int32(0)
        moves = self.lib.fp_decode(g.handle, _at(g.route), _at(g.times), count, 2 * start[0] + 1, 2 * start[1] + 1,
                                   *(_at(a) for a in (g.kind, g.value, g.cells, g.seconds)),
                                   *(_at(a) for a in points), ctypes.addressof(npoints))
        turns, tokens, make = self._turns, self._tokens, Move._make  # dozens of moves: made tokens, no f-strings
        out = []
        for k, v, c, t in zip(g.kind[:moves].tolist(), g.value[:moves].tolist(), g.cells[:moves].tolist(),
                              g.seconds[:moves].tolist()):
            if k == 1:
                out.append(make(turns[v] + (t,)))
            else:
                token = tokens[k].get(v) or tokens[k].setdefault(v, _token(k, v))
                out.append(make((token, v - 0.5 if k == 0 else c, t)))
        n = npoints.value
        px, py, cell_x, cell_y, wall = (a[:n].tolist() for a in points)
        return Route(out, g.times[count - 1], list(zip(px, py)), wall[:n - 1],
                     [start] + list(zip(cell_x[:n - 1], cell_y[:n - 1])))


def _token(kind: int, value: int) -> str:
    """A straight's token: the start's (kind 0) of `value` cells less the half it starts in, else `value` steps
    along the walls (2) or diagonal (3)."""
    return f"S{value - 0.5:g}" if kind == 0 else f"{'S' if kind == 2 else 'D'}{value}"


def _at(a: array[int] | array[float]) -> int:
    """Where an array's items are, for the kernel."""
    return a.buffer_info()[0]

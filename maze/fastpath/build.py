"""The static graph of moves of one maze size and mouse (maze/fastpath/__init__.py says how it is searched).

Points are in half-cell units, X and Y in 0..2N; a wall's midpoint has X + Y odd (X odd: a horizontal wall).
A node is a wall midpoint the mouse is crossing, with its heading in the seed library's eight directions
(0 east, 1 north-east, 2 north, ... 7 south-east), numbered point * 8 + heading within its layer. Nodes come in
layers so that a straight's price depends only on its length: A (just left a turn, at turn speed), B (a straight
ended here, a turn must follow), G (crossed into a goal cell: the timed run is over) and C (cruising at top speed
on a long straight). This module builds, once per maze size, diagonal flag and mouse, every straight, chain
and turn edge with all inner walls open, and what each needs open; the start's edges and the goal's depend on
the query (maze/fastpath/query.py).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import overload

import numpy as np

from ..direction import ALONG, DIAGONAL, STEP
from ..model import point_wall
from ..timing.motion import turn_seconds
from ..timing.mouseparams import MouseParams
from .graph import (
    LAYERS,
    MAX_CROSSINGS,
    A,
    B,
    C,
    G,
    chain_prices,
    chain_steps,
    straight_prices,
    stride,
    turn_shapes,
    unit,
)


@dataclass
class StraightEdges:
    """Straights from layer A of up to 2k steps (k: `StaticGraph.chain_steps`), one edge per start and length.
    Each needs `open_needed` open walls straight ahead of node `run_from` (its first crossing)."""

    src: np.ndarray
    dst: np.ndarray  # node within a layer: B for a straight ending before a turn, G for one over the goal line
    run_from: np.ndarray
    open_needed: np.ndarray
    seconds_to_turn: np.ndarray  # braking back to turn speed (to B)
    seconds_to_goal: np.ndarray  # free-ended over the goal line (to G)
    end_cell: np.ndarray  # flat index of the cell entered at the end (-1 outside the maze)
    direct_to_goal: np.ndarray  # short enough to reach G directly; longer ones go through the chain


@dataclass
class ChainEdges:
    """Long straights as a chain through layer C: A -> C speeding up, C -> C one step at top speed, C -> B
    braking, and C -> G over the goal line (only into the query's goal cells, `goal_cell`; -1 on the others)."""

    src: np.ndarray
    dst: np.ndarray
    run_from: np.ndarray
    open_needed: np.ndarray
    seconds: np.ndarray
    goal_cell: np.ndarray


@dataclass
class TurnEdges:
    """Turns B -> A: the walls each crosses (padded with the always-open sentinel), which shape it is, its time."""

    src: np.ndarray
    dst: np.ndarray
    walls: np.ndarray  # one row per edge, MAX_CROSSINGS columns
    shape: np.ndarray  # index into StaticGraph.shapes
    seconds: np.ndarray


class StaticGraph:
    """Every move a mouse could make in an N x N maze with all inner walls open, priced for one mouse."""

    def __init__(self, size: int, diagonal: bool, mouse: MouseParams) -> None:
        self.size, self.diagonal, self.mouse = size, diagonal, mouse
        self.side = 2 * size + 1  # points along a side
        self.layer_size = 8 * self.side ** 2
        self.start_node = LAYERS * self.layer_size  # the standing start in the start cell's centre
        xs, ys = np.meshgrid(np.arange(self.side), np.arange(self.side))
        self.point_x, self.point_y = xs.ravel(), ys.ravel()
        self.walls = 2 * size * (size + 1)
        self.open_sentinel, self.closed_sentinel = self.walls, self.walls + 1  # wall ids past the real ones
        ids = (point_wall(size, x, y) for y in range(self.side) for x in range(self.side))
        self.wall_at = np.array([self.closed_sentinel if w is None else w for w in ids])
        rim = ((self.point_x == 0) | (self.point_x == 2 * size) | (self.point_y == 0)
               | (self.point_y == 2 * size))
        self.outer_walls = np.unique(self.wall_at[rim & ((self.point_x + self.point_y) % 2 == 1)])
        self.headings = ALONG + (DIAGONAL if diagonal else ())
        self._build_lines()
        self.straights = self._build_straights()
        self.chain = self._build_chain()
        self.shapes = turn_shapes(diagonal)
        self.turns = self._build_turns()

    # -- geometry helpers -------------------------------------------------------------------------------------
    @overload
    def index(self, x: int, y: int) -> int: ...
    @overload
    def index(self, x: np.ndarray, y: np.ndarray) -> np.ndarray: ...
    def index(self, x: int | np.ndarray, y: int | np.ndarray) -> int | np.ndarray:
        return y * self.side + x

    def inside(self, x: np.ndarray, y: np.ndarray) -> np.ndarray:
        return (x >= 0) & (x < self.side) & (y >= 0) & (y < self.side)

    def stride(self, h: int) -> tuple[int, int]:
        return stride(h)

    def point(self, node: int) -> tuple[tuple[int, int], int]:
        """The point and heading of a node of any layer."""
        p, h = divmod(node % self.layer_size, 8)
        return (p % self.side, p // self.side), h

    def _entry_points(self, h: int) -> np.ndarray:
        """Point indices where a straight in heading h may cross a wall (along the walls: only across them)."""
        mid = (self.point_x + self.point_y) % 2 == 1
        if h in (0, 4):
            mid &= self.point_x % 2 == 0
        elif h in (2, 6):
            mid &= self.point_x % 2 == 1
        return np.flatnonzero(mid)

    def unit(self, h: int) -> float:
        return unit(h)

    def chain_steps(self, h: int) -> int:
        return chain_steps(self.mouse, h)

    # -- the static graph -------------------------------------------------------------------------------------
    def _build_lines(self) -> None:
        """For the per-query 'how many open walls lie straight ahead' array: every node lies on one line of
        crossings in its heading; the lines as rows (padded with -1), so that a query counts the open walls
        ahead of every node at once."""
        next_node = np.zeros(self.layer_size, dtype=np.int64)
        next_wall = np.full(self.layer_size, self.closed_sentinel)
        for h in self.headings:
            pts = self._entry_points(h)
            sx, sy = self.stride(h)
            qx, qy = self.point_x[pts] + sx, self.point_y[pts] + sy
            ok = self.inside(qx, qy)
            q = self.index(qx[ok], qy[ok])
            next_node[pts[ok] * 8 + h] = q * 8 + h
            next_wall[pts[ok] * 8 + h] = self.wall_at[q]
        nodes = np.concatenate([self._entry_points(h) * 8 + h for h in self.headings])
        has_next = next_wall != self.closed_sentinel
        followed = np.zeros(self.layer_size, dtype=bool)
        followed[next_node[nodes[has_next[nodes]]]] = True
        column = nodes[~followed[nodes]]
        columns = [column]
        while True:
            column = np.where((column >= 0) & has_next[np.maximum(column, 0)], next_node[np.maximum(column, 0)], -1)
            if (column < 0).all():
                break
            columns.append(column)
        lines = np.stack(columns, axis=1)
        on_line = lines >= 0
        self.line_walls = np.where(on_line, next_wall[np.maximum(lines, 0)], self.closed_sentinel)
        self.line_nodes, self.on_line = lines[on_line], on_line

    def _build_straights(self) -> StraightEdges:
        src, dst, run_from, length, to_turn, to_goal, ends = [], [], [], [], [], [], []
        for h in self.headings:
            pts = self._entry_points(h)
            sx, sy = self.stride(h)
            for n in range(min(2 * self.chain_steps(h), 2 * self.size + 1)):
                ex, ey = self.point_x[pts] + n * sx, self.point_y[pts] + n * sy
                ok = self.inside(ex, ey)
                if not ok.any():
                    break
                p, e = pts[ok], self.index(ex[ok], ey[ok])
                seconds_to_turn, seconds_to_goal = straight_prices(self.mouse, h, n)
                src.append(p * 8 + h)
                dst.append(e * 8 + h)
                run_from.append(p * 8 + h)
                length.append(np.full(len(p), n))
                to_turn.append(np.full(len(p), seconds_to_turn))
                to_goal.append(np.full(len(p), seconds_to_goal))
                ends.append(self._entered_cells(e, h))
        from_node, open_needed = np.concatenate(run_from), np.concatenate(length)
        # a free-ended straight to the goal line of k or more steps goes through the chain (see _build_chain)
        direct = open_needed < np.array([self.chain_steps(h) for h in range(8)])[from_node % 8]
        return StraightEdges(np.concatenate(src), np.concatenate(dst), from_node, open_needed,
                             np.concatenate(to_turn), np.concatenate(to_goal), np.concatenate(ends), direct)

    def _build_chain(self) -> ChainEdges:
        """Long straights as a chain, so that their count grows with the maze and not with its square: from A, k
        steps speeding up to top speed into layer C; in C one step at top speed at a time; from C, k steps braking
        into B, or straight over the goal line into G. A straight of n >= 2k steps then costs exactly its
        trapezoid, and one of n >= k steps to the goal line its free-ended time."""
        src, dst, run_from, length, cost, goal_cell = [], [], [], [], [], []
        for h in self.headings:
            pts = self._entry_points(h)
            sx, sy = self.stride(h)
            k = self.chain_steps(h)
            speed_up, cruise = chain_prices(self.mouse, h)
            nodes = pts * 8 + h
            for n, seconds, from_layer, to_layer in ((k, speed_up, A, C), (1, cruise, C, C), (k, speed_up, C, B)):
                ex, ey = self.point_x[pts] + n * sx, self.point_y[pts] + n * sy
                ok = self.inside(ex, ey)
                src.append(nodes[ok] + from_layer * self.layer_size)
                dst.append(self.index(ex[ok], ey[ok]) * 8 + h + to_layer * self.layer_size)
                run_from.append(nodes[ok])
                length.append(np.full(ok.sum(), n))
                cost.append(np.full(ok.sum(), seconds))
                goal_cell.append(np.full(ok.sum(), -1))
            src.append(nodes + C * self.layer_size)  # C -> G: over the goal line at top speed (goals per query)
            dst.append(nodes + G * self.layer_size)
            run_from.append(nodes)
            length.append(np.zeros(len(nodes), dtype=np.int64))
            cost.append(np.zeros(len(nodes)))  # an explicit zero in a CSR matrix is an edge to scipy
            goal_cell.append(self._entered_cells(pts, h))
        return ChainEdges(np.concatenate(src), np.concatenate(dst), np.concatenate(run_from),
                          np.concatenate(length), np.concatenate(cost), np.concatenate(goal_cell))

    def _entered_cells(self, points: np.ndarray, h: int) -> np.ndarray:
        """Flat index of the cell a mouse heading h enters at each wall point (-1 outside the maze)."""
        x, y = self.point_x[points], self.point_y[points]
        dx, dy = STEP[h]
        horizontal = x % 2 == 1
        cx = np.where(horizontal, x // 2, x // 2 - (dx < 0))
        cy = np.where(horizontal, y // 2 - (dy < 0), y // 2)
        inside = (cx >= 0) & (cx < self.size) & (cy >= 0) & (cy < self.size)
        return np.where(inside, cy * self.size + cx, -1)

    def _build_turns(self) -> TurnEdges:
        src, dst, walls, shape_ids, costs = [], [], [], [], []
        for i, shape in enumerate(self.shapes):
            pts = np.flatnonzero(((self.point_x + self.point_y) % 2 == 1) & (self.point_x % 2 == shape.x_parity))
            ok = np.ones(len(pts), dtype=bool)
            crossed = []
            for ox, oy in shape.offsets:
                qx, qy = self.point_x[pts] + ox, self.point_y[pts] + oy
                ok &= self.inside(qx, qy)
                crossed.append((qx, qy))
            pts = pts[ok]
            cols = [self.wall_at[self.index(qx[ok], qy[ok])] for qx, qy in crossed]
            cols += [np.full(len(pts), self.open_sentinel)] * (MAX_CROSSINGS - len(cols))
            ex, ey = crossed[-1]
            src.append(pts * 8 + shape.h_in + self.layer_size)
            dst.append(self.index(ex[ok], ey[ok]) * 8 + shape.h_out)
            walls.append(np.stack(cols, axis=1))
            shape_ids.append(np.full(len(pts), i))
            costs.append(np.full(len(pts), turn_seconds(shape.name, self.mouse)))
        return TurnEdges(np.concatenate(src), np.concatenate(dst), np.concatenate(walls), np.concatenate(shape_ids),
                         np.concatenate(costs))

"""Which edges of a query graph (maze/fastpath/query.py) need each wall open.

The queries of a search differ from one another by the walls found in between, a handful, while a 32x32
diagonal graph has 176 000 edges: working out which are open from every wall costs more per query than A*
itself once A*'s bound is tight (maze/fastpath/bound.py). With this index a query that only closes walls closes
the edges through them and leaves the rest as the last query priced them.
"""

from __future__ import annotations

import numpy as np

from .bound import row_pointers
from .build import StaticGraph


def _ahead(graph: StaticGraph, run_from: np.ndarray, count: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(which, wall) pairs: for straight number `which`, each of the `count` walls it crosses straight ahead
    of node `run_from` (the walls `StaticGraph.line_walls` holds along that node's line)."""
    line_of = np.zeros(graph.layer_size, dtype=np.int64)
    position = np.zeros(graph.layer_size, dtype=np.int64)
    line, pos = np.nonzero(graph.on_line)
    line_of[graph.line_nodes], position[graph.line_nodes] = line, pos
    which = np.repeat(np.arange(len(run_from)), count)
    step = np.arange(len(which)) - np.repeat(np.cumsum(count) - count, count)
    at = run_from[which]
    return which, graph.line_walls[line_of[at], position[at] + step]


def wall_edges(graph: StaticGraph, run_from: np.ndarray, open_needed: np.ndarray, before_turns: int,
               turn_walls: np.ndarray, start_first_wall: np.ndarray, start_run_from: np.ndarray,
               start_open_needed: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Per wall id, the edges (numbered in the query graph's row order: straights of layer A, turns, straights
    of layer C, then the start's) that cross it, as CSR: edge ids `edges[indptr[w]:indptr[w + 1]]`."""
    turns = turn_walls.shape[1]
    straight, straight_walls = _ahead(graph, run_from, open_needed)
    straight = np.where(straight < before_turns, straight, straight + turns)
    turn = np.tile(np.arange(turns), turn_walls.shape[0]) + before_turns
    first = len(run_from) + turns
    start, start_walls = _ahead(graph, start_run_from, start_open_needed)
    edge = np.concatenate([straight, turn, start + first, np.arange(len(start_first_wall)) + first])
    wall = np.concatenate([straight_walls, turn_walls.ravel(), start_walls, start_first_wall])
    real = wall < graph.walls  # the sentinels past the real walls never change
    edge, wall = edge[real].astype(np.int32), wall[real].astype(np.min_scalar_type(graph.walls))
    order = np.argsort(wall, kind="stable")  # a radix sort on 8- or 16-bit keys: a few times faster
    indptr = row_pointers(wall, graph.walls)
    return indptr, edge[order]

"""The lower bound of the time to the goal that A* searches the move graph with (maze/fastpath/query.py), kept
from query to query.

The bound is the exact time to the goal from every node under the walls of an earlier query, found by one
search back from the goal over the whole graph. Walls only ever close between the queries of a search (an
unknown wall it assumed open turns out closed), and closing one only removes edges, so those times are a lower
bound for every later query whose walls include the earlier one's, and a consistent one: A* with it settles
little more than the nodes of the fastest routes, where the time with only the outer walls let it settle every
node a detour could pass (17 000-19 000 of a 32x32 diagonal graph's nodes on japan2017hef, against a few
hundred). A query that opens a wall the bound's query had closed (the true maze after a search) gets a bound of
its own.

The bound loosens as walls close near the fastest routes, and finding it again costs a search of the whole
graph. It is found again once the A* searches since the last time have settled as many nodes as that search
did: the rule that never spends more than twice what the best schedule in hindsight would (ski rental), with no
constant to fit to a maze.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

if TYPE_CHECKING:
    from scipy.sparse import csr_array


def row_pointers(rows: np.ndarray, count: int) -> np.ndarray:
    """Where each of `count` rows starts among entries sorted by row, and where the last ends: a compressed
    row index's `indptr`, for the query graphs and the per-wall index of edges alike."""
    return np.concatenate([[0], np.cumsum(np.bincount(rows, minlength=count))]).astype(np.int32)


@dataclass
class Csr:
    """A graph as compressed rows: the edges of node u are indices[indptr[u]:indptr[u + 1]], priced `data`.
    Its own type and not scipy's, so that scipy is imported (0.2 s) only by the searches that need it."""

    data: np.ndarray  # float64
    indices: np.ndarray  # int32
    indptr: np.ndarray  # int32

    @property
    def nodes(self) -> int:
        return len(self.indptr) - 1

    def scipy(self) -> csr_array:
        """The same graph for scipy's searches (the fallback where there is no kernel)."""
        from scipy.sparse import csr_array

        return csr_array((self.data, self.indices, self.indptr), shape=(self.nodes, self.nodes))


class TimeBound:
    """Per node of a query graph, a lower bound of the time left to the goal; and the reduced prices
    price(u, v) + bound(v) - bound(u) of the graph's edges (in row order) under it."""

    def __init__(self, prices: Csr, rows: np.ndarray, goal_nodes: np.ndarray) -> None:
        self.prices, self.rows, self.goal_nodes = prices, rows, goal_nodes
        self.valid_for: np.ndarray | None = None  # the walls it was found under (None: not found yet)
        self.nodes = np.zeros(prices.nodes)
        self.reduced = np.zeros(len(rows))
        self.cost = 0  # nodes the search that found it settled
        self.spent = 0  # nodes A* has settled since

    def stale(self, blocked: np.ndarray) -> bool:
        """Whether a query blocking `blocked` (1 = blocked, per wall) needs the bound found again: it is none
        for those walls, or A* has spent as much under it as finding it again costs."""
        return self.valid_for is None or self.spent > self.cost or bool((self.valid_for > blocked).any())

    def find(self, open_edges: np.ndarray, blocked: np.ndarray) -> None:
        """The exact times to the goal through the edges `open_edges` marks, which `blocked`'s walls leave
        open; infinite where the goal cannot be reached."""
        self._search_back(open_edges)
        self.valid_for = blocked.copy()
        self.spent = 0

    def _search_back(self, open_edges: np.ndarray) -> None:
        from scipy.sparse import csr_array
        from scipy.sparse.csgraph import dijkstra

        p = self.prices
        back = Csr(np.where(open_edges, p.data, np.inf), p.indices, p.indptr).scipy().T
        self.nodes = dijkstra(csr_array(back), directed=True, indices=self.goal_nodes, min_only=True)
        with np.errstate(invalid="ignore"):  # an edge between nodes that never reach the goal: inf - inf
            reduced = np.maximum(p.data + self.nodes[p.indices] - self.nodes[self.rows], 0.0)
        reduced[~np.isfinite(reduced)] = np.inf  # such an edge is never on a route
        self.reduced = reduced  # never negative up to rounding, which is clamped
        self.cost = int(np.isfinite(self.nodes).sum())

    @property
    def at_start(self) -> float:
        return float(self.nodes[-1])  # the standing start is the last node

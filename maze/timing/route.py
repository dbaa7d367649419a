"""A fastest run as the commands print it: its moves, its time, the wall points it crosses, the walls and the
cells it enters. Apart from the searches that find one (maze/fastpath/), so that reading one needs no numpy."""

from __future__ import annotations

from dataclasses import dataclass
from typing import NamedTuple

from ..model import Cell


class Move(NamedTuple):
    """One move of a route. A tuple rather than a frozen dataclass: a route is built of dozens, and a query with
    known walls spent a third of its time constructing them."""

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

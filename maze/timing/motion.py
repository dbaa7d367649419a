"""How long a mouse takes: trapezoidal straights, fixed-length turns, and the search run of a cell trace.

Distances are in cells unless a name says metres. The fast run enters and leaves every turn at one speed
(`turn_speed`), so a straight's time depends only on its length and on whether it starts from rest or ends
at the goal line; that is what lets the fast-path search price each move on its own.
"""

from __future__ import annotations

from dataclasses import dataclass
from math import pi, sqrt, tan

from ..direction import DELTA, DIRECTIONS, opposite
from ..model import Cell
from .mouseparams import MouseParams

HALF_DIAGONAL = sqrt(2) / 2  # one diagonal step: from a wall's midpoint to the next one's, in cells


@dataclass(frozen=True)
class TurnGeometry:
    cells: float  # path length
    radius: float  # of its arc, which sets how fast it can be run


def _widest_arc(angle: float, leg_in: float, leg_out: float) -> TurnGeometry:
    """A turn by `angle` between two straight legs meeting at a corner: the widest arc tangent to both
    (it touches the end of the shorter leg), plus what is left of the longer leg as a straight."""
    tangent = min(leg_in, leg_out)
    radius = tangent / tan(angle / 2)
    return TurnGeometry(radius * angle + max(leg_in, leg_out) - tangent, radius)


# Each turn's path, fixed by where it must enter and leave (docs/MAZELOG.md lists the walls each crosses).
TURNS: dict[str, TurnGeometry] = {
    "90s": TurnGeometry(pi / 4, 0.5),  # inside one cell, from an edge to a side edge
    "90": TurnGeometry(1 + pi / 2, 1.0),  # half a cell, a quarter circle, half a cell: across three cells
    "180": TurnGeometry(2 + pi / 2, 0.5),  # a cell, a half circle round a post, a cell: two columns
    "45": _widest_arc(pi / 4, 1, HALF_DIAGONAL),  # along the walls to diagonal (or back)
    "135": _widest_arc(3 * pi / 4, 2, 2 * HALF_DIAGONAL),
    "V90": TurnGeometry(HALF_DIAGONAL * pi / 2, HALF_DIAGONAL),  # diagonal to diagonal round a post
}


def turn_seconds(name: str, mouse: MouseParams) -> float:
    """Entered and left at turn_speed; a turn too tight for that is run at sqrt(lateral_accel * r), and the
    braking to that speed and back is charged to the turn, (v - v_k)^2 / (accel * v) over cruising, so
    that the straights on either side keep a price of their own."""
    run, turn = mouse.run, TURNS[name]
    v = run.turn_speed
    v_k = min(v, sqrt(run.lateral_accel * turn.radius * mouse.cell))
    return turn.cells * mouse.cell / v_k + (v - v_k) ** 2 / (run.accel * v)


def straight_seconds(metres: float, v_in: float, v_out: float | None, top: float, accel: float) -> float:
    """Trapezoid (or triangle) profile from v_in to v_out; v_out None means 'as fast as it gets there'
    (the goal line). Callers keep |v_out^2 - v_in^2| <= 2 a d, which the parameter checks guarantee."""
    if metres <= 0:
        return 0.0
    if v_out is None:
        d_up = (top * top - v_in * v_in) / (2 * accel)
        if metres <= d_up:
            return (sqrt(v_in * v_in + 2 * accel * metres) - v_in) / accel
        return (top - v_in) / accel + (metres - d_up) / top
    d_up = (top * top - v_in * v_in) / (2 * accel)
    d_down = (top * top - v_out * v_out) / (2 * accel)
    if d_up + d_down <= metres:
        return (2 * top - v_in - v_out) / accel + (metres - d_up - d_down) / top
    peak = sqrt((2 * accel * metres + v_in * v_in + v_out * v_out) / 2)
    return (2 * peak - v_in - v_out) / accel


@dataclass(frozen=True)
class SearchRun:
    seconds: float
    metres: float
    turns: int  # 90-degree turns taken inside a cell
    stops: int  # times it comes to rest: each turn-back and the end
    pivots: int  # 180-degree turns on the spot


def search_run(trace: list[Cell], mouse: MouseParams) -> SearchRun:
    """The search as a run at constant speed: a 90-degree turn is an arc inside the cell, a turn-back is a stop,
    a pivot and a start, and each start and stop costs speed/(2*accel) over cruising (the parameter check
    keeps both within half a cell)."""
    if len(trace) < 2:
        return SearchRun(0.0, 0.0, 0, 0, 0)
    headings = [next(d for d in DIRECTIONS if DELTA[d] == (b[0] - a[0], b[1] - a[1]))
                for a, b in zip(trace, trace[1:])]
    turns = sum(h != g and h != opposite(g) for g, h in zip(headings, headings[1:]))
    pivots = sum(h == opposite(g) for g, h in zip(headings, headings[1:]))
    return search_counts(len(headings), turns, pivots, mouse)


def search_counts(moves: int, turns: int, pivots: int, mouse: MouseParams) -> SearchRun:
    """The search run from its counts alone, so that a running search (a mouse program) can be timed as it
    goes: `moves` cells entered, `turns` 90-degree turns in a cell, `pivots` turn-backs."""
    p = mouse.search
    metres = (moves - turns * (1 - TURNS["90s"].cells)) * mouse.cell
    segments = pivots + 1
    seconds = metres / p.speed + segments * p.speed / p.accel + pivots * p.pivot_time
    return SearchRun(seconds, metres, turns, segments, pivots)

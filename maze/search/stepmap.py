"""Breadth-first step maps (the Adachi method's 歩数マップ) over flat cell indices.

A step map counts cells from a set of sources through walls that are not blocked; which walls block
depends on the question, so callers pass a `blocked` array indexed by wall id (see `optimistic`/`pessimistic`).
"""

from __future__ import annotations

from collections.abc import Iterable, Sequence
from functools import lru_cache

from ..model import Cell, Maze, Topology, central_goals

UNREACHED = 1 << 30


def _as_int(flags: bytes | bytearray) -> int:
    return int.from_bytes(flags, "little")


def optimistic(maze: Maze, virtual: bytes | bytearray | None = None) -> bytes:
    """Unknown walls treated as open, as while searching; virtual walls block."""
    if virtual is None:
        return bytes(maze.wall)
    return (_as_int(maze.wall) | _as_int(virtual)).to_bytes(len(maze.wall), "little")


def pessimistic(maze: Maze) -> bytes:
    """Only known-open walls pass: the paths the mouse can be sure of."""
    n = len(maze.wall)
    ones = _as_int(b"\x01" * n)  # flags are 0/1 bytes, so xor with 1 per byte negates them
    return (_as_int(maze.wall) | (_as_int(maze.known) ^ ones)).to_bytes(n, "little")


def step_map(topo: Topology, blocked: Sequence[int], sources: Iterable[int]) -> list[int]:
    """Layer by layer over precomputed passages (no deque, no per-step index arithmetic)."""
    dist = [UNREACHED] * (topo.size * topo.size)
    frontier = []
    for s in sources:
        if dist[s]:
            dist[s] = 0
            frontier.append(s)
    passages = topo.passages
    d = 0
    while frontier:
        d += 1
        reached = []
        for c in frontier:
            for w, m in passages[c]:
                if dist[m] > d and not blocked[w]:
                    dist[m] = d
                    reached.append(m)
        frontier = reached
    return dist


_OPEN_DIGIT = bytes([ord("1")]) + bytes([ord("0")]) * 255  # flag 0 (not blocked, or not known) -> "1"


def _bits(flags: bytes, size: int, rows: int, width: int) -> int:
    """`rows` runs of `width` 0/1 flags as a mask in the padded layout (bit y*(N+1) + x), 1 where a flag is 0."""
    digits = flags.translate(_OPEN_DIGIT)
    if width == size:  # a horizontal wall row: pad each row with a '0' to the stride N + 1
        digits = b"0".join(digits[i * size:(i + 1) * size] for i in range(rows))
    return int(digits[::-1], 2)


def open_sides(topo: Topology, blocked: Sequence[int]) -> tuple[int, int, int, int]:
    """Bit masks of the cells whose east, north, west and south walls are not blocked, in the padded layout
    (bit y*(N+1) + x; column N is never entered, its west wall being the outer east wall): a whole step-map layer
    is then a few operations on one integer instead of a loop over cells. Both masks of a wall family come
    from one slice of the flags, as the wall index lays them out (model.wall_id)."""
    n = topo.size
    flags = bytes(blocked)
    vertical = n * (n + 1)
    south = _bits(flags[:vertical], n, n + 1, n)  # south side of row y = horizontal wall row y
    west = _bits(flags[vertical:], n, n, n + 1)  # west side of (x, y) = vertical wall y*(N+1) + x
    return west >> 1, south >> (n + 1), west, south


def known_cells(topo: Topology, known: Sequence[int]) -> int:
    """Bit mask (padded layout) of the cells whose four walls are all known."""
    east, north, west, south = open_sides(topo, known)  # "open" here: the flag is 0, i.e. not known
    return ~(east | north | west | south) & topo_cells(topo.size)


@lru_cache(maxsize=8)
def topo_cells(size: int) -> int:
    """The mask of every real cell in the padded layout."""
    return mask_of(range(size * size), size)


def bit(c: int, size: int) -> int:
    """Cell index c = y*N + x as its bit number y*(N+1) + x in the padded layout."""
    return c + c // size


def layers(topo: Topology, sides: tuple[int, int, int, int], sources: int, until: int | None = None,
           limit: int | None = None) -> list[int]:
    """Breadth-first layers as bit masks: layer d holds the cells d steps from `sources` (a mask). Stops once
    cell `until` is reached, or after `limit` steps: callers that only look at nearer cells need no more."""
    east, north, west, south = sides
    stride = topo.size + 1
    seen = front = sources
    out = [front]
    stop = 0 if until is None else 1 << bit(until, topo.size)
    while front and not front & stop and (limit is None or len(out) <= limit):
        front = ((((front & east) << 1) | ((front & west) >> 1) | ((front & north) << stride)
                  | ((front & south) >> stride)) & ~seen)
        if not front:
            break
        seen |= front
        out.append(front)
    return out


def cells_of(mask: int, size: int) -> list[int]:
    """The cell indices of a mask (padded layout), in increasing order."""
    cells = []
    stride = size + 1
    while mask:
        low = mask & -mask
        b = low.bit_length() - 1
        cells.append(b - b // stride)
        mask ^= low
    return cells


def mask_of(cells: Iterable[int], size: int) -> int:
    mask = 0
    for c in cells:
        mask |= 1 << bit(c, size)
    return mask


def path_down(topo: Topology, blocked: Sequence[int], dist: list[int], start: int) -> list[int]:
    """Follow a step map downhill from start to a source; empty if start is unreachable."""
    if dist[start] >= UNREACHED:
        return []
    path = [start]
    c = start
    while dist[c]:
        c = next(topo.neighbours[c][k] for k in range(4)
                 if not blocked[topo.cell_walls[c][k]] and dist[topo.neighbours[c][k]] == dist[c] - 1)
        path.append(c)
    return path


def shortest_path(maze: Maze, blocked: Sequence[int]) -> list[int]:
    """A shortest start-to-goal cell path through unblocked walls (empty when there is none)."""
    dist = step_map(maze.topo, blocked, [maze.cell_index(g) for g in maze.goals])
    return path_down(maze.topo, blocked, dist, maze.cell_index(maze.start))


def default_goals(maze: Maze) -> tuple[Cell, ...]:
    """The central 2x2 (classic contests); when the start cannot reach it (a training maze whose small active
    area leaves it out), the reachable cell farthest from the start (ties: the highest row, then the rightmost)."""
    dist = step_map(maze.topo, maze.wall, [maze.cell_index(maze.start)])
    central = central_goals(maze.size)
    if any(dist[maze.cell_index(g)] < UNREACHED for g in central):
        return central
    _, y, x = max((d, c // maze.size, c % maze.size) for c, d in enumerate(dist) if d < UNREACHED)
    return ((x, y),)

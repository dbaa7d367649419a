"""Directions and headings, numbered as in the seed's maze library: the one owner of both.

The library numbers eight headings (0 east, 1 north-east, 2 north, ... 7 south-east) for diagonal runs; walls
only ever use the four even ones, which is why a WallRecord's direction field is three bits wide and odd values
are anomalies. Half-cell points (X, Y in 0..2N, a cell's centre at (2x+1, 2y+1)) move by STEP per half-step.
"""

EAST, NORTH, WEST, SOUTH = 0, 2, 4, 6
DIRECTIONS: tuple[int, ...] = (EAST, NORTH, WEST, SOUTH)

DELTA: dict[int, tuple[int, int]] = {EAST: (1, 0), NORTH: (0, 1), WEST: (-1, 0), SOUTH: (0, -1)}
HEADINGS = 8
STEP: tuple[tuple[int, int], ...] = ((1, 0), (1, 1), (0, 1), (-1, 1), (-1, 0), (-1, -1), (0, -1), (1, -1))
ALONG, DIAGONAL = (EAST, NORTH, WEST, SOUTH), (1, 3, 5, 7)
LETTER: dict[int, str] = {EAST: "E", NORTH: "N", WEST: "W", SOUTH: "S"}
ARROW: dict[int, str] = {EAST: ">", NORTH: "^", WEST: "<", SOUTH: "v"}


def opposite(d: int) -> int:
    return (d + 4) % HEADINGS


def rotate(h: int, eighths: int) -> int:
    """Anticlockwise by `eighths` of a turn (negative: clockwise)."""
    return (h + eighths) % HEADINGS


def parse_direction(token: str) -> int:
    """Accept the seed's arrows, compass letters and the numeric codes, since logs are written by hand."""
    t = token.strip()
    for table in (ARROW, LETTER):
        for d, sym in table.items():
            if t.upper() == sym.upper():
                return d
    if t.isdigit() and int(t) in DIRECTIONS:
        return int(t)
    raise ValueError(f"unknown direction {token!r} (use ^ > v <, N E S W or 0 2 4 6)")

"""Wall directions, numbered as in the seed's maze library.

The library numbers eight headings (for diagonal runs); walls only ever use the four even ones,
which is why a WallRecord's direction field is three bits wide and odd values are anomalies.
"""

EAST, NORTH, WEST, SOUTH = 0, 2, 4, 6
DIRECTIONS: tuple[int, ...] = (EAST, NORTH, WEST, SOUTH)

DELTA: dict[int, tuple[int, int]] = {EAST: (1, 0), NORTH: (0, 1), WEST: (-1, 0), SOUTH: (0, -1)}
LETTER: dict[int, str] = {EAST: "E", NORTH: "N", WEST: "W", SOUTH: "S"}
ARROW: dict[int, str] = {EAST: ">", NORTH: "^", WEST: "<", SOUTH: "v"}


def opposite(d: int) -> int:
    return (d + 4) % 8


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

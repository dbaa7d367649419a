"""The mms protocol (mackorone/mms): the line a mouse program prints, parsed into a command.

One command per line on the program's stdout; the simulator answers on its stdin the commands that have an
answer. mms drops a line it cannot parse without a reply, so a program waiting for one hangs: here such a line
is an MmsCommandError naming the line instead, and the harness stops the run with that one line.
"""

from __future__ import annotations

from dataclasses import dataclass

from ..direction import EAST, NORTH, SOUTH, WEST
from ..errors import MazeError

# name -> (the arguments it takes, whether it gets an answer). "n": an optional count of half-steps or cells;
# "xy": two cell coordinates; "xyd": coordinates and a wall letter; "xyc": coordinates and a colour letter;
# "xyt": coordinates and the rest of the line as text; "stat": a statistic's name.
COMMANDS: dict[str, tuple[str, bool]] = {
    "mazeWidth": ("", True), "mazeHeight": ("", True),
    **{f"wall{side}": ("n", True) for side in ("Front", "Right", "Left", "Back", "FrontLeft", "FrontRight",
                                                  "BackLeft", "BackRight")},
    "moveForward": ("n", True), "moveForwardHalf": ("n", True),
    **{name: ("", True) for name in ("turnLeft", "turnLeft90", "turnRight", "turnRight90", "turnLeft45",
                                     "turnRight45", "wasReset", "ackReset")},
    "setWall": ("xyd", False), "clearWall": ("xyd", False),
    "setColor": ("xyc", False), "clearColor": ("xy", False), "clearAllColor": ("", False),
    "setText": ("xyt", False), "clearText": ("xy", False), "clearAllText": ("", False),
    "getStat": ("stat", True),
}
WALL_LETTERS: dict[str, int] = {"n": NORTH, "e": EAST, "s": SOUTH, "w": WEST,
                                "N": NORTH, "E": EAST, "S": SOUTH, "W": WEST}  # mms's own README writes 'W'

COLOURS = "kbacgorwyBCAGRY"  # mms's colour letters: black, blue, grey, cyan, green, orange, red, white, yellow, dark...
STATS = ("total-distance", "total-turns", "best-run-distance", "best-run-turns", "current-run-distance",
         "current-run-turns", "total-effective-distance", "best-run-effective-distance",
         "current-run-effective-distance", "score")
MAX_TEXT = 10  # mms shows at most this many characters in a cell


class MmsCommandError(MazeError):
    """A line the mouse printed that no mms command matches. `fatal` unless it names a command that gets no
    answer (setWall, setColor, ...): mms ignores those, the program does not wait, and the run can go on."""

    def __init__(self, message: str, fatal: bool = True) -> None:
        super().__init__(message)
        self.fatal = fatal


@dataclass(frozen=True)
class Command:
    name: str
    count: int | None = None  # the optional N of wall queries and moves
    x: int = 0
    y: int = 0
    direction: int = 0  # setWall / clearWall, in the seed's numbering
    colour: str = ""
    text: str = ""
    stat: str = ""


def _int(token: str, what: str) -> int:
    try:
        return int(token)
    except ValueError:
        raise ValueError(f"{what} must be an integer, got {token!r}") from None


def parse_command(line: str) -> Command:
    """One line as the program printed it (without its newline); MmsCommandError says what is wrong with it."""
    head, _, rest = line.strip(" \r\t").partition(" ")
    if head not in COMMANDS:
        shown = line if len(line) <= 60 else line[:57] + "..."
        raise MmsCommandError(f"unknown command {shown!r} (mms would ignore it and the program would wait forever)")
    spec, answered = COMMANDS[head]
    try:
        return _parse_args(head, spec, rest)
    except ValueError as e:
        raise MmsCommandError(str(e), fatal=answered) from None


def _parse_args(head: str, spec: str, rest: str) -> Command:
    if spec == "xyt":
        xs, _, rest2 = rest.lstrip(" ").partition(" ")
        ys, _, text = rest2.lstrip(" ").partition(" ")
        if not xs or not ys:
            raise ValueError(f"{head} needs X Y TEXT")
        printable = "".join(c if " " <= c <= "~" else "?" for c in text)  # as mms does
        return Command(head, x=_int(xs, "X"), y=_int(ys, "Y"), text=printable[:MAX_TEXT])
    args = rest.split()
    if spec in ("", "n", "stat"):
        most = 0 if spec == "" else 1
        if len(args) > most or (spec == "stat" and len(args) != 1):
            raise ValueError(f"{head} takes {'no arguments' if spec == '' else 'one argument'}, got {rest!r}")
        if spec == "stat":
            if args[0] not in STATS:
                raise ValueError(f"unknown statistic {args[0]!r} (one of {', '.join(STATS)})")
            return Command(head, stat=args[0])
        return Command(head, count=_int(args[0], "N") if args else None)
    want = 2 if spec == "xy" else 3
    if len(args) != want:
        raise ValueError(f"{head} needs {'X Y' if want == 2 else 'X Y ' + spec[2].upper()}, got {rest!r}")
    x, y = _int(args[0], "X"), _int(args[1], "Y")
    if spec == "xyd":
        if args[2] not in WALL_LETTERS:
            raise ValueError(f"{head}: direction must be n, e, s or w, got {args[2]!r}")
        return Command(head, x=x, y=y, direction=WALL_LETTERS[args[2]])
    if spec == "xyc":
        if len(args[2]) != 1 or args[2] not in COLOURS:
            raise ValueError(f"{head}: colour must be one of {COLOURS}, got {args[2]!r}")
        return Command(head, x=x, y=y, colour=args[2])
    return Command(head, x=x, y=y)

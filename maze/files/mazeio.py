"""Reading and writing a maze file of any format the package knows, by its suffix (and telling a maze file from a
binary wall log by its content): the one reader and writer every command uses."""

from __future__ import annotations

from pathlib import Path

from ..errors import MazeError
from ..model import Maze
from ..outputs import write_bytes, write_text
from .mazefile import dump_maze, parse_maze
from .mazeformats import Warn, dump_maz, dump_num, parse_maz, parse_num

BINARY_SUFFIX, NUM_SUFFIX = ".maz", ".num"
TEXT_MAZE_STARTS = (b"o", b"+")  # the first post of the common text format


def read_maze(path: Path, strict: bool = False, warn: Warn | None = None) -> Maze:
    """By suffix: mms's `.num`, the 256-byte `.maz`, else the common text format. A `.num` / `.maz` wall that one
    of its two cells marks and the other does not goes to `warn` (naming the file), or is refused if `strict`."""
    suffix = path.suffix.lower()
    named = None if warn is None else (lambda message: warn(f"{path}: {message}"))
    try:
        if suffix == BINARY_SUFFIX:
            return parse_maz(path.read_bytes(), strict, named)
        text = path.read_text(encoding="utf-8")
        return parse_num(text, strict, named) if suffix == NUM_SUFFIX else parse_maze(text)
    except UnicodeDecodeError:
        raise MazeError(f"{path}: not a text maze file") from None
    except MazeError as e:
        raise MazeError(f"{path}: {e}") from None


def write_maze(path: Path, maze: Maze) -> None:
    """In the format the suffix names, as `read_maze` reads it back: `.num`, `.maz`, else the text format."""
    suffix = path.suffix.lower()
    if suffix == BINARY_SUFFIX:
        write_bytes(path, dump_maz(maze))
    else:
        write_text(path, dump_num(maze) if suffix == NUM_SUFFIX else dump_maze(maze))


def _is_text(data: bytes) -> bool:
    try:
        data.decode("utf-8")
    except UnicodeDecodeError:
        return False
    return True


def is_maze_file(path: Path, data: bytes) -> bool:
    """Whether `data`, read from `path`, is a maze file (text that starts with a post, or a .num / .maz) rather
    than a binary wall log, which has neither a suffix of its own nor a header."""
    return (data[:1] in TEXT_MAZE_STARTS and _is_text(data)) or path.suffix.lower() in (NUM_SUFFIX, BINARY_SUFFIX)

"""Reading a maze file of any format the package knows, by its suffix: the one reader every command uses."""

from __future__ import annotations

from pathlib import Path

from .errors import MazeError
from .mazefile import parse_maze
from .mazeformats import Warn, parse_maz, parse_num
from .model import Maze


def read_maze(path: Path, strict: bool = False, warn: Warn | None = None) -> Maze:
    """By suffix: mms's `.num`, the 256-byte `.maz`, else the common text format. A `.num` / `.maz` wall that one
    of its two cells marks and the other does not goes to `warn` (naming the file), or is refused if `strict`."""
    suffix = path.suffix.lower()
    named = None if warn is None else (lambda message: warn(f"{path}: {message}"))
    try:
        if suffix == ".maz":
            return parse_maz(path.read_bytes(), strict, named)
        text = path.read_text(encoding="utf-8")
        return parse_num(text, strict, named) if suffix == ".num" else parse_maze(text)
    except UnicodeDecodeError:
        raise MazeError(f"{path}: not a text maze file") from None
    except MazeError as e:
        raise MazeError(f"{path}: {e}") from None

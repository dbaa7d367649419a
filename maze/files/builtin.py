"""The real contest mazes shipped in maze/data/mazes (source and licence in the README there), so that commands
and tests work on a fresh clone without ../shared/mazes."""

from __future__ import annotations

from importlib.resources import files
from pathlib import Path

SUFFIX = ".txt"


def builtin_dir() -> Path:
    return Path(str(files("maze").joinpath("data", "mazes")))


def builtin_names() -> list[str]:
    return sorted(p.name.removesuffix(SUFFIX) for p in builtin_dir().glob("*" + SUFFIX))


def builtin_path(name: str) -> Path | None:
    """The file of a built-in maze, by its name with or without .txt; None if there is none."""
    path = builtin_dir() / (name if name.endswith(SUFFIX) else name + SUFFIX)
    return path if "/" not in name and path.is_file() else None


EXAMPLES = ("seed-log.txt",)  # text examples shipped beside the mazes, for the commands in docs/MAZELOG.md


def builtin_example(name: str) -> Path | None:
    if name not in EXAMPLES:
        return None
    return Path(str(files("maze").joinpath("data", name)))

"""Score a restored maze against the true one, to see what a log got right."""

from __future__ import annotations

from dataclasses import dataclass, field

from ..errors import MazeError
from ..model import Maze


@dataclass
class WallDiff:
    right: int = 0
    unknown: int = 0
    wrong: list[tuple[int, int, int]] = field(default_factory=list)  # (x, y, d) the log has backwards


def compare(truth: Maze, restored: Maze) -> WallDiff:
    if truth.size != restored.size:
        raise MazeError(f"sizes differ: maze {truth.size}x{truth.size}, log {restored.size}x{restored.size}")
    diff = WallDiff()
    for x, y, d in truth.inner_walls():
        if not restored.is_known(x, y, d):
            diff.unknown += 1
        elif restored.is_wall(x, y, d) == truth.is_wall(x, y, d):
            diff.right += 1
        else:
            diff.wrong.append((x, y, d))
    return diff

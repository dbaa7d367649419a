"""PNG pictures of a maze, drawn with the seed simulator's conventions: solid known walls, dotted unknown
ones, cyan virtual walls, so a replayed log and an exploration look alike."""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402  (the backend must be chosen first)
from matplotlib.collections import LineCollection  # noqa: E402

from .direction import EAST, NORTH, SOUTH, WEST  # noqa: E402
from .model import Cell, Maze  # noqa: E402

WALL_COLOUR, UNKNOWN_COLOUR, VIRTUAL_COLOUR = "#c00000", "#909090", "#00b0e0"
PATH_COLOUR, VISITED_COLOUR = "#2060ff", "#fff0b0"


@dataclass
class Overlay:
    """What an exploration adds to the picture."""

    path: list[Cell] = field(default_factory=list)
    visited: set[Cell] = field(default_factory=set)
    virtual: set[int] = field(default_factory=set)  # wall ids (Maze.wid) of virtual walls


def _segment(x: int, y: int, d: int) -> list[tuple[int, int]]:
    return {
        EAST: [(x + 1, y), (x + 1, y + 1)],
        WEST: [(x, y), (x, y + 1)],
        NORTH: [(x, y + 1), (x + 1, y + 1)],
        SOUTH: [(x, y), (x + 1, y)],
    }[d]


def save_png(maze: Maze, out: Path, title: str = "", overlay: Overlay | None = None) -> None:
    n = maze.size
    fig, ax = plt.subplots(figsize=(6, 6), dpi=110)
    overlay = overlay or Overlay()
    for x, y in overlay.visited:
        ax.add_patch(plt.Rectangle((x, y), 1, 1, color=VISITED_COLOUR, lw=0))
    for gx, gy in maze.goals:
        ax.add_patch(plt.Rectangle((gx, gy), 1, 1, color="#c0ffc0", lw=0))
    ax.text(maze.start[0] + 0.5, maze.start[1] + 0.5, "S", ha="center", va="center", fontsize=max(4, 120 // n))
    edges = [(x, y, d) for y in range(n) for x in range(n) for d in (EAST, NORTH)]
    edges += [(0, y, WEST) for y in range(n)] + [(x, 0, SOUTH) for x in range(n)]
    virtual, unknown, known = [], [], []
    for x, y, d in edges:
        if maze.wid(x, y, d) in overlay.virtual:
            virtual.append(_segment(x, y, d))
        elif not maze.is_known(x, y, d):
            unknown.append(_segment(x, y, d))
        elif maze.is_wall(x, y, d):
            known.append(_segment(x, y, d))
    ax.add_collection(LineCollection(unknown, colors=UNKNOWN_COLOUR, linewidths=0.8, linestyles=":"))
    ax.add_collection(LineCollection(known, colors=WALL_COLOUR, linewidths=2))
    ax.add_collection(LineCollection(virtual, colors=VIRTUAL_COLOUR, linewidths=2.5))
    if overlay.path:
        ax.plot([c[0] + 0.5 for c in overlay.path], [c[1] + 0.5 for c in overlay.path], color=PATH_COLOUR, lw=1.5)
    ax.set_xlim(-0.2, n + 0.2)
    ax.set_ylim(-0.2, n + 0.2)
    ax.set_aspect("equal")
    ax.axis("off")
    if title:
        ax.set_title(title, fontsize=9)
    fig.savefig(out, bbox_inches="tight")
    plt.close(fig)

"""A JSON view of a maze for other tools: every cell with the state of its four walls."""

from __future__ import annotations

import json

from ..direction import DIRECTIONS, LETTER
from ..model import Maze, inner_wall_count


def wall_state(maze: Maze, x: int, y: int, d: int) -> str:
    if not maze.is_known(x, y, d):
        return "unknown"
    return "wall" if maze.is_wall(x, y, d) else "open"


def maze_to_json(maze: Maze) -> str:
    cells = [
        {"x": x, "y": y, **{LETTER[d]: wall_state(maze, x, y, d) for d in DIRECTIONS}}
        for y in range(maze.size)
        for x in range(maze.size)
    ]
    doc = {
        "size": maze.size,
        "start": list(maze.start),
        "goals": [list(g) for g in maze.goals],
        "known_inner_walls": maze.known_inner(),
        "inner_walls": inner_wall_count(maze.size),
        "cells": cells,
    }
    return json.dumps(doc, indent=1)

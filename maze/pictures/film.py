"""A replay as pictures: the maze a log restores, record by record, for `replay --format png` and the
`replay --animate` GIF (whose last frame is that PNG, pixel for pixel).

With the true maze, the pictures also show the mouse's path and every known wall that contradicts the truth:
the wall-log seed's point that a log keeps the whole search, so a misread wall can be found after a contest.
"""

from __future__ import annotations

from collections.abc import Callable, Iterable, Iterator
from dataclasses import dataclass
from math import ceil
from typing import IO

import numpy as np
from PIL import GifImagePlugin, Image

from ..log.wallrecord import WallRecord
from ..model import Cell, Maze
from ..mouse.marks import Mark, marks_at
from ..search.stepmap import path_down, pessimistic, step_map
from .render import COLOURS, LEGEND, Overlay, draw_maze

FRAME_MS = 40
LAST_FRAME_MS = 3000  # hold the final state before the film loops
MAX_FRAMES = 400  # the default stride keeps a film to about this many frames (a few MB at most for 32x32)
TRANSPARENT = len(COLOURS)  # a palette index no picture uses: "this pixel did not change"


def default_stride(records: int) -> int:
    return max(1, ceil(records / MAX_FRAMES))


@dataclass
class Replay:
    """Applies records one at a time, keeping what a picture of the replay needs."""

    maze: Maze
    truth: Maze | None = None
    applied: int = 0
    contradictions: int = 0
    marks: list[Mark] | None = None  # a mouse program's setColor / setText, shown as they were at each record

    def __post_init__(self) -> None:
        self.trail: list[Cell] = [self.maze.start]
        self.wrong: set[int] = set()

    @classmethod
    def start(cls, size: int, truth: Maze | None, marks: list[Mark] | None = None) -> Replay:
        return cls(Maze.unknown(size, truth.goals if truth else ()), truth, marks=marks)

    def apply(self, rec: WallRecord) -> None:
        maze = self.maze
        if self.truth is not None and (rec.x, rec.y) != self.trail[-1]:
            self._walk_to((rec.x, rec.y))
        self.contradictions += not maze.update(rec.x, rec.y, rec.d, rec.wall)
        self.applied += 1
        if self.truth is not None:
            w = maze.wid(rec.x, rec.y, rec.d)
            if maze.known[w] and maze.wall[w] != self.truth.wall[w]:
                self.wrong.add(w)
            else:
                self.wrong.discard(w)

    def _walk_to(self, cell: Cell) -> None:
        """Records name the cell the mouse sensed from; between two such cells it went the shortest way it knew
        to be open (it may have crossed cells that taught it nothing). A jump if it knew of none."""
        maze = self.maze
        blocked = pessimistic(maze)
        target = maze.cell_index(cell)
        path = path_down(maze.topo, blocked, step_map(maze.topo, blocked, [target]), maze.cell_index(self.trail[-1]))
        self.trail += [(c % maze.size, c // maze.size) for c in path[1:]] or [cell]

    def legend(self) -> list[tuple[str, str]]:
        """Fixed for a whole film, so that every frame has the same size."""
        keys = ["wall", "unknown"] + (["goal", "trail", "mouse", "wrong"] if self.truth is not None else [])
        keys += ["marks"] if self.marks is not None else []
        return [(k, LEGEND[k]) for k in keys]

    def picture(self, title: list[str]) -> Image.Image:
        overlay = Overlay()
        if self.truth is not None:
            overlay = Overlay(trail=self.trail, mouse=self.trail[-1], wrong=set(self.wrong))
        if self.marks is not None:
            overlay.marks = marks_at(self.marks, self.applied)
        return draw_maze(self.maze, title, overlay, self.legend())


def film(replay: Replay, records: list[WallRecord], stride: int,
         title: Callable[[Replay], list[str]]) -> Iterator[Image.Image]:
    """A frame for the state before any record, then after every `stride` records and after the last one."""
    yield replay.picture(title(replay))
    for i, rec in enumerate(records, 1):
        replay.apply(rec)
        if i % stride == 0 or i == len(records):
            yield replay.picture(title(replay))


def frame_count(records: int, stride: int) -> int:
    """How many frames `film` yields for that many records."""
    return records // stride + 1 + (records % stride > 0)


def write_gif(frames: Iterable[Image.Image], fp: IO[bytes]) -> int:
    """Stream the frames into a GIF, each stored as the rectangle that changed, with the pixels in it that did not
    change transparent (long runs compress well). Pillow's own writer keeps every frame in memory: some 200 MB
    for a 32x32 search. Returns the number of frames."""
    count = 0
    previous: np.ndarray | None = None
    pending: tuple[Image.Image, tuple[int, int], int | None] | None = None
    for frame in frames:
        pixels = np.asarray(frame)
        if previous is None:
            header, _ = GifImagePlugin.getheader(frame, info={"loop": 0, "optimize": False})
            fp.writelines(header)
            part: tuple[Image.Image, tuple[int, int], int | None] = (frame, (0, 0), None)
        else:
            changed = pixels != previous
            rows, cols = np.nonzero(changed)
            if len(rows):  # an unchanged frame still gets a (one-pixel) frame: one per stride, as documented
                top, left, bottom, right = rows.min(), cols.min(), rows.max() + 1, cols.max() + 1
            else:
                top, left, bottom, right = 0, 0, 1, 1
            box = np.where(changed[top:bottom, left:right], pixels[top:bottom, left:right], TRANSPARENT)
            image = Image.frombytes("P", (int(right - left), int(bottom - top)), box.astype(np.uint8).tobytes())
            part = (image, (int(left), int(top)), TRANSPARENT)
        if pending is not None:
            _write_frame(fp, *pending, FRAME_MS)
        pending = part
        previous = pixels
        count += 1
    if pending is not None:
        _write_frame(fp, *pending, LAST_FRAME_MS)
    fp.write(b";")
    return count


def _write_frame(fp: IO[bytes], im: Image.Image, offset: tuple[int, int], transparent: int | None,
                 duration: int) -> None:
    extra = {} if transparent is None else {"transparency": transparent}
    fp.writelines(GifImagePlugin.getdata(im, offset=offset, duration=duration, disposal=1, **extra))

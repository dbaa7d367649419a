"""Pictures of a maze with Pillow, in one fixed palette of eleven colours: solid known walls, dotted unknown
ones, cyan virtual walls, as in the seed's simulator. One palette for PNG and GIF alike, so a replay film's
last frame and `replay --format png` are the same pixels.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from functools import lru_cache
from pathlib import Path

import numpy as np
from PIL import Image, ImageDraw, ImageFont

from ..direction import EAST, NORTH, SOUTH, WEST
from ..model import Cell, Maze, wall_id
from ..outputs import atomic_open

COLOURS: dict[str, tuple[int, int, int]] = {
    "background": (255, 255, 255),
    "text": (0, 0, 0),
    "wall": (192, 0, 0),
    "unknown": (150, 150, 150),
    "virtual": (0, 176, 224),
    "visited": (255, 240, 176),
    "goal": (192, 255, 192),
    "path": (32, 96, 255),
    "trail": (255, 140, 0),
    "wrong": (230, 0, 230),
    "mouse": (0, 0, 0),
    # the mms colour letters a mouse program may set with setColor
    "k": (0, 0, 0), "b": (0, 0, 255), "a": (128, 128, 128), "c": (0, 255, 255), "g": (0, 255, 0),
    "o": (255, 165, 0), "r": (255, 0, 0), "w": (255, 255, 255), "y": (255, 255, 0), "B": (0, 0, 139),
    "C": (0, 139, 139), "A": (64, 64, 64), "G": (0, 100, 0), "R": (139, 0, 0), "Y": (139, 139, 0),
}
INDEX = {name: i for i, name in enumerate(COLOURS)}
PALETTE = [c for rgb in COLOURS.values() for c in rgb]
MAX_SIDE_PX = 640  # the maze area; cells get what fits, within the limits below
CELL_PX = (12, 40)
MARGIN, FONT_PX = 14, 14
LINE_PX = FONT_PX + 4
LEGEND: dict[str, str] = {  # colour name: label; the swatch's shape follows from the name
    "wall": "wall",
    "unknown": "unknown wall",
    "virtual": "virtual wall (dead-end closing)",
    "wrong": "wall that contradicts the true maze",
    "visited": "cell visited",
    "goal": "goal",
    "path": "path",
    "trail": "mouse's path (from the log)",
    "mouse": "mouse (last record)",
    "marks": "the mouse's own setColor / setText",
}


@dataclass
class Overlay:
    """What a search or a replay adds to the maze."""

    path: list[tuple[float, float]] = field(default_factory=list)  # points in cells (cell centre = x + 0.5)
    path_label: str = "path"
    visited: set[Cell] = field(default_factory=set)
    virtual: set[int] = field(default_factory=set)  # wall ids (Maze.wid) closed by dead-end closing
    wrong: set[int] = field(default_factory=set)  # wall ids whose known state contradicts the true maze
    trail: list[Cell] = field(default_factory=list)
    mouse: Cell | None = None
    marks: dict[Cell, tuple[str, str]] = field(default_factory=dict)  # cell: (mms colour letter or "", text)


def cell_centres(cells: list[Cell]) -> list[tuple[float, float]]:
    return [(x + 0.5, y + 0.5) for x, y in cells]


@lru_cache(maxsize=2)
def _font(px: int) -> ImageFont.ImageFont | ImageFont.FreeTypeFont:
    try:
        return ImageFont.load_default(size=px)
    except (ImportError, OSError, TypeError):  # Pillow without FreeType: the small bitmap font
        return ImageFont.load_default()


def text_width(text: str) -> int:
    return int(_font(FONT_PX).getlength(text))


def title_width(size: int) -> int:
    """Pixels a title line may take: the maze's width."""
    return size * cell_px(size)


class Canvas:
    """Maps maze coordinates (cells, y up) to pixels (y down) and lays out title, maze and legend."""

    def __init__(self, size: int, lines: list[str], legend: list[tuple[str, str]]) -> None:
        self.n = size
        self.px = cell_px(size)
        self.font = _font(FONT_PX)
        self.top = MARGIN + LINE_PX * len(lines)
        self.image = _blank(size, len(lines), tuple(legend)).copy()
        self.draw = ImageDraw.Draw(self.image)
        self.draw.fontmode = "1"  # no anti-aliasing: the picture stays within the palette
        for i, line in enumerate(lines):
            self.draw.text((MARGIN, MARGIN + i * LINE_PX), line, fill=INDEX["text"], font=self.font)

    def xy(self, x: float, y: float) -> tuple[float, float]:
        return MARGIN + x * self.px, self.top + (self.n - y) * self.px

    def polyline(self, points: list[tuple[float, float]], colour: str, width: int) -> None:
        if len(points) > 1:
            self.draw.line([self.xy(x, y) for x, y in points], fill=INDEX[colour], width=width, joint="curve")


def cell_px(size: int) -> int:
    return max(CELL_PX[0], min(CELL_PX[1], MAX_SIDE_PX // size))


@lru_cache(maxsize=8)
def _blank(size: int, title_lines: int, legend: tuple[tuple[str, str], ...]) -> Image.Image:
    """The background with the legend drawn, kept: a film's frames share it and text is slow to draw."""
    px, font = cell_px(size), _font(FONT_PX)
    width = 2 * MARGIN + size * px
    rows: list[list[tuple[str, str, int]]] = [[]]
    used = MARGIN
    for key, label in legend:
        w = 28 + int(font.getlength(label)) + 16
        if used + w > width - MARGIN and rows[-1]:
            rows.append([])
            used = MARGIN
        rows[-1].append((key, label, used))
        used += w
    rows = [r for r in rows if r]
    y0 = MARGIN + LINE_PX * title_lines + size * px + MARGIN
    image = Image.new("P", (width, y0 + LINE_PX * len(rows) + (MARGIN if rows else 0)), INDEX["background"])
    image.putpalette(PALETTE)
    draw = ImageDraw.Draw(image)
    draw.fontmode = "1"
    for r, row in enumerate(rows):
        y = y0 + r * LINE_PX + LINE_PX // 2
        for key, label, x in row:
            if key in ("visited", "goal", "marks"):
                fill = INDEX["c" if key == "marks" else key]
                draw.rectangle((x, y - 6, x + 22, y + 6), fill=fill, outline=INDEX["unknown"])
            elif key == "unknown":
                for dx in range(0, 23, 5):
                    draw.point([(x + dx, y), (x + dx + 1, y)], fill=INDEX[key])
            elif key == "mouse":
                draw.ellipse((x + 6, y - 5, x + 16, y + 5), fill=INDEX[key])
            else:
                draw.line((x, y, x + 22, y), fill=INDEX[key], width=3)
            draw.text((x + 28, y - FONT_PX // 2 - 1), label, fill=INDEX["text"], font=font)
    return image


def legend_entries(maze: Maze, overlay: Overlay) -> list[tuple[str, str]]:
    """Only what the picture shows."""
    shown = {"wall": True, "unknown": not all(maze.known), "virtual": overlay.virtual, "wrong": overlay.wrong,
             "visited": overlay.visited, "goal": maze.goals, "path": overlay.path, "trail": overlay.trail,
             "mouse": overlay.mouse is not None, "marks": overlay.marks}
    labels = {**LEGEND, "path": overlay.path_label}
    return [(key, labels[key]) for key, present in shown.items() if present]


@dataclass(frozen=True)
class Geometry:
    """Pixel offsets (row * width + column, from the maze area's top-left) of everything drawn per wall or cell,
    so a picture is a few numpy assignments: a replay film draws hundreds of them."""

    walls: np.ndarray  # wall id of each drawn edge: every inner wall once, then the outer ones
    solid: dict[int, np.ndarray]  # thickness -> (edges, pixels) of each edge as a solid line
    dots: np.ndarray  # (edges, pixels) three small dots along each edge, for unknown walls
    cells: np.ndarray  # (cells, pixels) the inside of each cell, by flat cell index


def _rectangles(x0: np.ndarray, y0: np.ndarray, w: int, h: int, width: int) -> np.ndarray:
    dy, dx = np.mgrid[0:h, 0:w]
    return ((y0[:, None] + dy.ravel()) * width + x0[:, None] + dx.ravel()).astype(np.int64)


@lru_cache(maxsize=4)
def geometry(size: int, px: int, width: int, thicknesses: tuple[int, ...]) -> Geometry:
    n = size
    edges = [(x, y, d) for y in range(n) for x in range(n) for d in (EAST, NORTH)]
    edges += [(0, y, WEST) for y in range(n)] + [(x, 0, SOUTH) for x in range(n)]
    walls = np.array([wall_id(n, x, y, d) for x, y, d in edges])
    # each edge as the post it starts from (pixels, y down) and whether it runs across (east) or down
    start = {EAST: (1, 0), NORTH: (0, 1), WEST: (0, 0), SOUTH: (0, 0)}
    across = np.array([d in (NORTH, SOUTH) for _, _, d in edges])
    sx = np.array([(x + start[d][0]) * px for x, _, d in edges])
    sy = np.array([(n - y - start[d][1]) * px for _, y, d in edges])
    sy = np.where(across, sy, sy - px)  # a wall running up starts at its upper post in pixel rows
    solid = {}
    for t in thicknesses:
        along = _rectangles(sx, sy - t // 2, px + 1, t, width)  # as if every edge ran across
        down = _rectangles(sx - t // 2, sy, t, px + 1, width)
        solid[t] = np.where(across[:, None], along, down)
    dot_x = np.concatenate([np.where(across, sx + k * px // 4, sx) for k in (1, 2, 3)])
    dot_y = np.concatenate([np.where(across, sy, sy + k * px // 4) for k in (1, 2, 3)])
    dots = _rectangles(dot_x - 1, dot_y - 1, 2, 2, width).reshape(3, len(edges), 4)
    cx = np.array([c % n for c in range(n * n)]) * px
    cy = (n - 1 - np.array([c // n for c in range(n * n)])) * px
    return Geometry(walls, solid, np.concatenate(list(dots), axis=1), _rectangles(cx, cy, px + 1, px + 1, width))


def draw_maze(maze: Maze, title: list[str], overlay: Overlay | None = None,
              legend: list[tuple[str, str]] | None = None) -> Image.Image:
    """The picture: title lines above the maze, a legend below (by default, of what it shows; a film passes a
    fixed one so that every frame has the same size)."""
    overlay = overlay or Overlay()
    canvas = Canvas(maze.size, title, legend_entries(maze, overlay) if legend is None else legend)
    thick = max(2, canvas.px // 8)
    width = canvas.image.width
    geo = geometry(maze.size, canvas.px, width, (thick, thick + 1, thick + 2))
    pixels = np.array(canvas.image)
    # offsets are from the maze area's corner; the outer walls' thickness reaches above it, so the base is added
    # here rather than slicing: a negative offset into a slice would wrap round to the picture's bottom rows
    flat = pixels.reshape(-1)
    base = canvas.top * width + MARGIN
    n = maze.size
    for cells, colour in ((overlay.visited, "visited"), (maze.goals, "goal")):
        if cells:
            flat[base + geo.cells[[y * n + x for x, y in cells]]] = INDEX[colour]
    for (x, y), (letter, _) in overlay.marks.items():
        if letter:
            flat[base + geo.cells[y * n + x]] = INDEX[letter]
    known = np.frombuffer(bytes(maze.known), dtype=np.uint8)[geo.walls].astype(bool)
    wall = np.frombuffer(bytes(maze.wall), dtype=np.uint8)[geo.walls].astype(bool)
    virtual = np.isin(geo.walls, list(overlay.virtual))
    wrong = np.isin(geo.walls, list(overlay.wrong)) & ~virtual
    plain = ~virtual & ~wrong
    flat[base + geo.dots[plain & ~known]] = INDEX["unknown"]
    flat[base + geo.solid[thick][plain & known & wall]] = INDEX["wall"]
    flat[base + geo.solid[thick + 1][virtual]] = INDEX["virtual"]
    flat[base + geo.solid[thick + 2][wrong]] = INDEX["wrong"]
    canvas.image.paste(Image.fromarray(pixels, "L"))
    canvas.polyline(cell_centres(overlay.trail), "trail", max(2, canvas.px // 6))
    canvas.polyline(overlay.path, "path", max(2, canvas.px // 8))
    for (x, y), (_, text) in overlay.marks.items():
        if text:
            tx, ty = canvas.xy(x + 0.5, y + 0.5)
            canvas.draw.text((tx, ty), text, fill=INDEX["text"], font=_font(max(8, canvas.px // 3)), anchor="mm")
    sx, sy = canvas.xy(maze.start[0] + 0.5, maze.start[1] + 0.5)
    canvas.draw.text((sx, sy), "S", fill=INDEX["text"], font=canvas.font, anchor="mm")
    if overlay.mouse is not None:
        mx, my = canvas.xy(overlay.mouse[0] + 0.5, overlay.mouse[1] + 0.5)
        r = canvas.px / 4
        canvas.draw.ellipse((mx - r, my - r, mx + r, my + r), fill=INDEX["mouse"])
    return canvas.image


def save_png(maze: Maze, out: Path, title: list[str], overlay: Overlay | None = None,
             legend: list[tuple[str, str]] | None = None) -> None:
    with atomic_open(out) as fp:
        draw_maze(maze, title, overlay, legend).save(fp, format="PNG")

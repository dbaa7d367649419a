"""A course as data: a floor image, walls, ordered checkpoints, a start pose and a time limit.

A course lives in a folder with `course.toml` and the floor image it names, so a user adds a course by
copying a folder, not by writing code. The color sensor reads the floor the way Unity's does: the point
below the sensor is looked up in the floor image (bilinearly, as a texture sampler would). The same folder
describes the robot's wiring (which motor ports drive the wheels), since a course is built for a robot,
and the levels of the seeded noise tests may turn on (`[noise]`, see docs/NOISE.md).
"""

from __future__ import annotations

import dataclasses
import math
import tomllib
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from hakoniwa.physics.noise import DEFAULT_NOISE, NoiseLevels
from hakoniwa.physics.robot import DEFAULT_WIRING, Wiring
from hakoniwa.wire.errors import HakoError
from hakoniwa.wire.protocol import COURSE_BLOCK_POSITIONS, MOTOR_PORTS, ColorId
from hakoniwa.wire.timebase import US_PER_S

COURSES_DIR = Path(__file__).parent / "courses"


class CourseError(HakoError, ValueError):
    """A course folder or its course.toml is unusable; the message names the problem."""


@dataclass(frozen=True)
class Box:
    """An axis-aligned box on the floor: centre (x, y) and half sizes, in metres."""

    name: str
    x: float
    y: float
    hx: float
    hy: float

    def contains(self, x: float, y: float) -> bool:
        return abs(x - self.x) <= self.hx and abs(y - self.y) <= self.hy


@dataclass(frozen=True)
class ColorArea:
    """A patch of colour painted on the floor (a box); the colour sensor reports its colour id there."""

    box: Box
    color: ColorId


# What the colour sensor's colour mode reports for plain floor: the darkest third of the way from black to
# white is BLACK, the lightest third WHITE, the grey line edge in between no colour, as a real EV3 sensor
# half over a line often does.
BLACK_BELOW = 1 / 3
WHITE_ABOVE = 2 / 3
# Raw RGB of each colour id (0..255), for areas and for plain floor's black and white.
COLOR_RGB = {ColorId.BLACK: (0, 0, 0), ColorId.BLUE: (0, 0, 255), ColorId.GREEN: (0, 160, 0),
             ColorId.YELLOW: (255, 220, 0), ColorId.RED: (220, 0, 0), ColorId.WHITE: (255, 255, 255),
             ColorId.BROWN: (130, 80, 30)}


@dataclass(frozen=True)
class CourseInfo:
    """ET Robocon's course information (`[etroboc]`), which its programs read through etroboc_ext.h: the
    number card, the number on the black block, and each block's position (one byte each)."""

    card_number: int = 0
    block_number: int = 0
    block_positions: tuple[int, ...] = (0,) * COURSE_BLOCK_POSITIONS


@dataclass(frozen=True)
class Pose:
    x: float
    y: float
    yaw_deg: float


@dataclass(frozen=True)
class Course:
    name: str
    folder: Path
    floor: np.ndarray  # reflect value (float32) per pixel, row 0 at the top of the image
    meters_per_pixel: float
    origin: tuple[float, float]  # world (x, y) of the image's bottom-left corner
    walls: tuple[Box, ...]
    wall_height: float
    checkpoints: tuple[Box, ...]
    start: Pose
    time_limit_us: int
    reflect_white: float
    reflect_black: float
    color_areas: tuple[ColorArea, ...] = ()
    wiring: Wiring = DEFAULT_WIRING
    noise: NoiseLevels = DEFAULT_NOISE
    info: CourseInfo = CourseInfo()

    @property
    def extent(self) -> tuple[float, float, float, float]:
        """(xmin, xmax, ymin, ymax) of the floor image in world metres."""
        h, w = self.floor.shape
        x0, y0 = self.origin
        return x0, x0 + w * self.meters_per_pixel, y0, y0 + h * self.meters_per_pixel

    def reflect_at(self, x: float, y: float) -> float:
        """Bilinear lookup of the floor under world point (x, y); off the image reads as the image border."""
        h, w = self.floor.shape
        u = (x - self.origin[0]) / self.meters_per_pixel - 0.5
        v = (h - 1) - ((y - self.origin[1]) / self.meters_per_pixel - 0.5)
        u = min(max(u, 0.0), w - 1.0)
        v = min(max(v, 0.0), h - 1.0)
        i0, j0 = int(v), int(u)
        i1, j1 = min(i0 + 1, h - 1), min(j0 + 1, w - 1)
        fv, fu = v - i0, u - j0
        f = self.floor
        top = f[i0, j0] * (1 - fu) + f[i0, j1] * fu
        bottom = f[i1, j0] * (1 - fu) + f[i1, j1] * fu
        return float(top * (1 - fv) + bottom * fv)

    def color_at(self, x: float, y: float, reflect: float) -> tuple[ColorId, tuple[int, int, int]]:
        """Colour id and raw RGB of the floor under (x, y), whose reflect value is `reflect`."""
        for area in self.color_areas:
            if area.box.contains(x, y):
                return area.color, COLOR_RGB[area.color]
        f = (reflect - self.reflect_black) / (self.reflect_white - self.reflect_black)
        grey = round(min(max(f, 0.0), 1.0) * 255)
        color = ColorId.BLACK if f < BLACK_BELOW else ColorId.WHITE if f > WHITE_ABOVE else ColorId.NONE
        return color, (grey, grey, grey)


def _number(table: dict, key: str, where: str) -> float:
    if key not in table:
        raise CourseError(f"{where}: missing '{key}'")
    value = table[key]
    if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value):
        raise CourseError(f"{where}: '{key}' must be a number, got {value!r}")
    return float(value)


def _box(table: dict, where: str) -> Box:
    hx, hy = _number(table, "hx", where), _number(table, "hy", where)
    if hx <= 0 or hy <= 0:
        raise CourseError(f"{where}: half sizes must be positive")
    return Box(str(table.get("name", where)), _number(table, "x", where), _number(table, "y", where), hx, hy)


def _color_area(table: dict, where: str) -> ColorArea:
    name = str(table.get("color", "")).upper()
    if name not in ColorId.__members__ or name == "NONE":
        known = ", ".join(c.name.lower() for c in ColorId if c != ColorId.NONE)
        raise CourseError(f"{where}: 'color' must be one of {known}, got {table.get('color')!r}")
    return ColorArea(_box(table, where), ColorId[name])


def _wiring(table: object, where: str) -> Wiring:
    if table is None:
        return DEFAULT_WIRING
    if not isinstance(table, dict):
        raise CourseError(f"{where}: [robot] must be a table")
    ports = {}
    for key, default in (("left_motor", DEFAULT_WIRING.left), ("right_motor", DEFAULT_WIRING.right)):
        letter = str(table.get(key, "ABCD"[default])).upper()
        if len(letter) != 1 or letter not in "ABCD"[:MOTOR_PORTS]:
            raise CourseError(f"{where}: [robot] {key} must be a motor port A..D, got {table.get(key)!r}")
        ports[key] = "ABCD".index(letter)
    if ports["left_motor"] == ports["right_motor"]:
        raise CourseError(f"{where}: [robot] left_motor and right_motor must be different ports")
    return Wiring(ports["left_motor"], ports["right_motor"])


def _course_info(table: object, where: str) -> CourseInfo:
    if table is None:
        return CourseInfo()
    where = f"{where} [etroboc]"
    if not isinstance(table, dict):
        raise CourseError(f"{where}: must be a table")
    unknown = sorted(set(table) - {"card_number", "block_number", "block_positions"})
    if unknown:
        raise CourseError(f"{where}: unknown key {unknown[0]!r}")
    numbers = {}
    for key in ("card_number", "block_number"):
        value = table.get(key, 0)
        if isinstance(value, bool) or not isinstance(value, int) or not 0 <= value < 2**31:
            raise CourseError(f"{where}: '{key}' must be a whole number >= 0, got {value!r}")
        numbers[key] = value
    positions = table.get("block_positions", [0] * COURSE_BLOCK_POSITIONS)
    if not (isinstance(positions, list) and len(positions) == COURSE_BLOCK_POSITIONS
            and all(isinstance(p, int) and not isinstance(p, bool) and 0 <= p <= 255 for p in positions)):
        raise CourseError(f"{where}: 'block_positions' must be {COURSE_BLOCK_POSITIONS} whole numbers 0..255")
    return CourseInfo(numbers["card_number"], numbers["block_number"], tuple(positions))


def _noise(table: object, where: str) -> NoiseLevels:
    """The `[noise]` table: any of `NoiseLevels`' keys, each a number >= 0; absent keys keep the defaults."""
    if table is None:
        return DEFAULT_NOISE
    where = f"{where} [noise]"
    if not isinstance(table, dict):
        raise CourseError(f"{where}: must be a table")
    known = NoiseLevels.keys()
    unknown = sorted(set(table) - set(known))
    if unknown:
        raise CourseError(f"{where}: unknown key {unknown[0]!r} (known: {', '.join(known)})")
    levels = {key: _number(table, key, where) for key in known if key in table}
    for key, value in levels.items():
        if value < 0:
            raise CourseError(f"{where}: '{key}' must not be negative, got {value:g}")
    return dataclasses.replace(DEFAULT_NOISE, **levels)


def builtin_course(name: str | Path) -> Path | None:
    """The folder of the built-in course called `name`, if it is one. A built-in name means the built-in course
    even where the working directory holds a file or folder of that name (write `./oval` for that one), so
    that `--course oval` is the same course wherever it is typed."""
    name = str(name)
    folder = COURSES_DIR / name
    return folder if name and "/" not in name and folder.is_dir() else None


def course_file(name_or_path: str | Path) -> Path:
    """The course.toml a built-in name, a course folder or a course file names (it may not exist)."""
    path = builtin_course(name_or_path) or Path(name_or_path)
    return path / "course.toml" if path.is_dir() else path


def load_course(name_or_path: str | Path) -> Course:
    """Load a built-in course by name, or a course folder (or its course.toml) by path."""
    path = course_file(name_or_path)
    if not path.is_file():
        known = ", ".join(sorted(p.name for p in COURSES_DIR.iterdir() if p.is_dir()))
        raise CourseError(f"no course at {name_or_path} (built-in courses: {known})")
    try:
        spec = tomllib.loads(path.read_text())
    except (tomllib.TOMLDecodeError, UnicodeDecodeError) as e:
        raise CourseError(f"{path}: not valid TOML: {e}") from None
    where = path.name
    image_path = path.parent / str(spec.get("floor_image", ""))
    if not image_path.is_file():
        raise CourseError(f"{where}: floor_image {spec.get('floor_image')!r} not found")
    white, black = _number(spec, "reflect_white", where), _number(spec, "reflect_black", where)
    from PIL import Image, UnidentifiedImageError

    try:
        with Image.open(image_path) as img:
            luminance = np.asarray(img.convert("L"), dtype=np.float32) / 255.0
    except (UnidentifiedImageError, OSError) as e:
        raise CourseError(f"{image_path.name}: not a readable image: {e}") from None
    mpp = _number(spec, "meters_per_pixel", where)
    origin = spec.get("origin")
    if not (isinstance(origin, list) and len(origin) == 2):
        raise CourseError(f"{where}: 'origin' must be [x, y]")
    start = spec.get("start")
    if not isinstance(start, dict):
        raise CourseError(f"{where}: missing [start]")
    walls = tuple(_box(w, f"{where} wall {i}") for i, w in enumerate(spec.get("wall", [])))
    checkpoints = tuple(_box(c, f"{where} checkpoint {i}") for i, c in enumerate(spec.get("checkpoint", [])))
    if not checkpoints:
        raise CourseError(f"{where}: a course needs at least one [[checkpoint]]")
    limit = _number(spec, "time_limit_s", where)
    if limit <= 0 or mpp <= 0:
        raise CourseError(f"{where}: time_limit_s and meters_per_pixel must be positive")
    if white <= black:
        raise CourseError(f"{where}: reflect_white must be above reflect_black")
    areas = tuple(_color_area(a, f"{where} area {i}") for i, a in enumerate(spec.get("area", [])))
    return Course(
        name=str(spec.get("name", path.parent.name)),
        folder=path.parent,
        floor=(black + (white - black) * luminance).astype(np.float32),
        meters_per_pixel=mpp,
        origin=(float(origin[0]), float(origin[1])),
        walls=walls,
        wall_height=float(spec.get("wall_height", 0.1)),
        checkpoints=checkpoints,
        start=Pose(_number(start, "x", where), _number(start, "y", where), _number(start, "yaw_deg", where)),
        time_limit_us=round(limit * US_PER_S),
        reflect_white=white,
        reflect_black=black,
        color_areas=areas,
        wiring=_wiring(spec.get("robot"), where),
        noise=_noise(spec.get("noise"), where),
        info=_course_info(spec.get("etroboc"), where),
    )

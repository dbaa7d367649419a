"""A course as data: a floor image, walls, ordered checkpoints, a start pose and a time limit.

A course lives in a folder with `course.toml` and the floor image it names, so a user adds a course by
copying a folder, not by writing code. The color sensor reads the floor the way Unity's does: the point
below the sensor is looked up in the floor image (bilinearly, as a texture sampler would). The image may be
grey or in colour; each kind of sensor's response to a colour, calibrated per course (`[sensor.ev3]`,
`[sensor.spike]`), is `color_response.py`'s. The same folder describes the robot's wiring (which motor ports
drive the wheels), since a course is built for a robot, the levels of the seeded noise tests may turn on
(`[noise]`, see docs/NOISE.md), the movable objects and named zones on the floor (`course_items.py`), and
what ET Robocon's score calls its garage, ring and bottle (`[score]`), and where a run leaves the course
(`[course_out]`: the mat's edge, areas marked out of bounds, and the margin past them; ET Robocon's コースアウト).
"""

from __future__ import annotations

import dataclasses
import functools
import math
import tomllib
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from hakoniwa.physics import color_response
from hakoniwa.physics.color_response import (
    COLOR_RGB,
    SPIKE_FLOOR,
    Calibration,
    Channels,
    ColorReading,
    SpikeFloor,
    SpikeReading,
)
from hakoniwa.physics.course_items import CourseObject, ItemError, ScoreSpec, Zone, parse_items, parse_score
from hakoniwa.physics.noise import DEFAULT_NOISE, NoiseLevels
from hakoniwa.physics.robot import DEFAULT_WIRING, Wiring
from hakoniwa.physics.spike_hub import RGB_FULL
from hakoniwa.wire.errors import HakoError
from hakoniwa.wire.etrobocon_rules import CLASSES
from hakoniwa.wire.protocol import COURSE_BLOCK_POSITIONS, MOTOR_PORTS, ColorId
from hakoniwa.wire.timebase import US_PER_S

if TYPE_CHECKING:
    from PIL.Image import Image as PILImage

COURSES_DIR = Path(__file__).parent / "courses"
# The largest floor image the bench takes: a 5.46 x 3.64 m mat at 0.55 mm a pixel, finer than the colour sensor's
# spot. Loading a course holds about 30 bytes a pixel (its reflect, and for a colour image its channels).
MAX_FLOOR_PIXELS = 40_000_000


class CourseError(HakoError, ValueError):
    """A course folder or its course.toml is unusable; the message names the problem."""


_BOX = frozenset({"name", "x", "y", "hx", "hy"})
# Every key a course.toml may hold, by table ("" is the file's top level; an array of tables, [[wall]], is
# checked table by table): a key the course learns is added here, once, beside the code that reads it, and
# any other is refused in one line naming it and the file, as a scenario's are. [noise] is NoiseLevels', and
# [[zone]], [[object]] and [score] are course_items.py's.
KEYS: dict[str, frozenset[str]] = {
    "": frozenset({"name", "floor_image", "meters_per_pixel", "origin", "time_limit_s", "wall_height", "start",
                   "wall", "checkpoint", "area", "robot", "noise", "etroboc", "sensor", "reflect_white",
                   "reflect_black", "zone", "object", "score", "course_out"}),
    "start": frozenset({"x", "y", "yaw_deg"}),
    "wall": _BOX,
    "checkpoint": _BOX | {"heading_deg"},
    "area": _BOX | {"color"},
    "robot": frozenset({"left_motor", "right_motor"}),
    "etroboc": frozenset({"card_number", "block_number", "block_positions"}),
    "sensor.ev3": frozenset({"reflect_white", "reflect_black"}),
    # white and black, and the colours the floor image was painted to read (scripts/make_etrobocon_course.py)
    "sensor.spike": frozenset({"white", "black", "blue", "red", "green", "yellow", "grey", "brown"}),
    "course_out": frozenset({"margin_m", "area"}),
    "course_out.area": _BOX,
}


@dataclass(frozen=True)
class Box:
    """An axis-aligned box on the floor: centre (x, y) and half sizes, in metres. A checkpoint may say which way
    it is passed (`heading_deg`, counter-clockwise from +x: ET Robocon's gate arrow)."""

    name: str
    x: float
    y: float
    hx: float
    hy: float
    heading_deg: float | None = None

    def contains(self, x: float, y: float) -> bool:
        return abs(x - self.x) <= self.hx and abs(y - self.y) <= self.hy

    def distance(self, x: float, y: float) -> float:
        """How far (x, y) is from the box (0 inside it)."""
        return math.hypot(max(abs(x - self.x) - self.hx, 0.0), max(abs(y - self.y) - self.hy, 0.0))


@dataclass(frozen=True)
class ColorArea:
    """A patch of colour painted on the floor (a box); the colour sensor reports its colour id there."""

    box: Box
    color: ColorId



@dataclass(frozen=True)
class CourseOut:
    """Where a run leaves the course (COURSE_OUT, ET Robocon's コースアウト): the robot's axle centre more than
    `margin_m` past the mat's edge (the floor image's), or more than `margin_m` inside an area the course marks
    out of bounds. The axle, because the drive wheels sit on it: past the edge by the axle, a robot on a mat
    lying on a table or the floor has its wheels off the mat; the gates are judged at the same point."""

    margin_m: float = 0.0
    areas: tuple[Box, ...] = ()

    def area_at(self, x: float, y: float) -> Box | None:
        """The out-of-bounds area (x, y) is more than the margin inside, if any."""
        m = self.margin_m
        return next((a for a in self.areas if abs(x - a.x) < a.hx - m and abs(y - a.y) < a.hy - m), None)


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
    floor: np.ndarray  # the EV3's reflect (float32) per pixel, row 0 at the top of the image: the red channel
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
    # A colour image's green, blue and mean channels (float32, the EV3's reflect units) per pixel; None for a
    # grey image, whose channels are all `floor`.
    colour: np.ndarray | None = None
    spike: SpikeFloor = SPIKE_FLOOR  # what a SPIKE sensor reads on white, black and the course's colours
    zones: tuple[Zone, ...] = ()
    objects: tuple[CourseObject, ...] = ()
    score: ScoreSpec = ScoreSpec()
    out: CourseOut = CourseOut()

    @functools.cached_property
    def ev3(self) -> Calibration:
        """The EV3's reading on white and black (`reflect_white`, `reflect_black`)."""
        return Calibration(self.reflect_white, self.reflect_black)

    @property
    def extent(self) -> tuple[float, float, float, float]:
        """(xmin, xmax, ymin, ymax) of the floor image in world metres."""
        h, w = self.floor.shape
        x0, y0 = self.origin
        return x0, x0 + w * self.meters_per_pixel, y0, y0 + h * self.meters_per_pixel

    def left_at(self, x: float, y: float) -> str | None:
        """Where the robot with its axle centre at (x, y) has left the course ("the mat", or the out-of-bounds
        area's name), or None while it is on it."""
        xmin, xmax, ymin, ymax = self.extent
        m = self.out.margin_m
        if not (xmin - m <= x <= xmax + m and ymin - m <= y <= ymax + m):
            return "the mat"
        area = self.out.area_at(x, y)
        return None if area is None else area.name

    def reflect_at(self, x: float, y: float) -> float:
        """Bilinear lookup of the floor under world point (x, y); off the image reads as the image border."""
        f = self.floor
        i0, j0, i1, j1, fv, fu = self._texel(x, y)
        top = f[i0, j0] * (1 - fu) + f[i0, j1] * fu
        bottom = f[i1, j0] * (1 - fu) + f[i1, j1] * fu
        return float(top * (1 - fv) + bottom * fv)

    def colour_at(self, x: float, y: float) -> tuple[float, float, float] | None:
        """The green, blue and mean channels under (x, y), bilinearly, as `reflect_at` the red; None on a grey
        course."""
        c = self.colour
        if c is None:
            return None
        i0, j0, i1, j1, fv, fu = self._texel(x, y)
        top = c[i0, j0] * (1 - fu) + c[i0, j1] * fu
        bottom = c[i1, j0] * (1 - fu) + c[i1, j1] * fu
        g, b, mean = (top * (1 - fv) + bottom * fv).tolist()
        return g, b, mean

    def _texel(self, x: float, y: float) -> tuple[int, int, int, int, float, float]:
        """The four pixels around (x, y) and the weights between them; off the image, its border."""
        h, w = self.floor.shape
        u = (x - self.origin[0]) / self.meters_per_pixel - 0.5
        v = (h - 1) - ((y - self.origin[1]) / self.meters_per_pixel - 0.5)
        u = min(max(u, 0.0), w - 1.0)
        v = min(max(v, 0.0), h - 1.0)
        i0, j0 = int(v), int(u)
        return i0, j0, min(i0 + 1, h - 1), min(j0 + 1, w - 1), v - i0, u - j0

    def color_at(self, x: float, y: float, reflect: float,
                 colour: tuple[float, float, float] | None = None) -> tuple[ColorId, tuple[int, int, int]]:
        """Colour id and raw RGB of the floor under (x, y), whose red channel (reflect) is `reflect` and other
        channels `colour` (None: a grey)."""
        for area in self.color_areas:
            if area.box.contains(x, y):
                return area.color, COLOR_RGB[area.color]
        return color_response.ev3_color(reflect, colour, self.ev3), color_response.raw_rgb(reflect, colour, self.ev3)

    def reading_at(self, x: float, y: float) -> ColorReading:
        """What an EV3 colour sensor over (x, y) reads, without noise. For a scenario or a test that needs to
        know what the floor at a point looks like to the robot."""
        reflect, colour = self.reflect_at(x, y), self.colour_at(x, y)
        color, rgb = self.color_at(x, y, reflect, colour)
        return ColorReading(round(reflect), color, rgb)

    def spike_reading(self, x: float, y: float, reflect: float, colour: tuple[float, float, float] | None,
                      robot: Calibration) -> SpikeReading:
        """What a SPIKE colour sensor over (x, y) reads, the floor's channels there being `reflect` (red) and
        `colour` (None: a grey), on a robot whose sensor reads `robot` on the course's white and black."""
        area = next((a for a in self.color_areas if a.box.contains(x, y)), None)
        place: Channels = (color_response.fractions(reflect, colour, self.ev3) if area is None
                           else (COLOR_RGB[area.color][0] / 255, COLOR_RGB[area.color][1] / 255,
                                 COLOR_RGB[area.color][2] / 255))
        return color_response.spike_reading(place, self.spike, robot)

    def picture(self, max_pixels: int | None = None) -> np.ndarray:
        """The floor as a person sees it (RGB, 0..255, row 0 at the image's top): each channel's place between
        black and white, and the colour areas painted in; every n-th pixel each way where the floor has more
        than `max_pixels` (a figure shows no more, and a big mat's whole picture would take gigabytes)."""
        span = self.reflect_white - self.reflect_black
        step = math.ceil(math.sqrt(self.floor.size / max_pixels)) if max_pixels else 1

        def byte(channel: np.ndarray) -> np.ndarray:
            return (np.clip((channel[::step, ::step] - self.reflect_black) / span, 0, 1) * 255).astype(np.uint8)

        red = byte(self.floor)
        c = self.colour
        rgb = np.stack([red, red, red] if c is None else [red, byte(c[:, :, 0]), byte(c[:, :, 1])], axis=2)
        h = red.shape[0]
        mpp, (x0, y0) = self.meters_per_pixel * step, self.origin
        for area in self.color_areas:
            b = area.box
            c0, c1 = round((b.x - b.hx - x0) / mpp), round((b.x + b.hx - x0) / mpp)
            r0, r1 = h - round((b.y + b.hy - y0) / mpp), h - round((b.y - b.hy - y0) / mpp)
            rgb[max(r0, 0):max(r1, 0), max(c0, 0):max(c1, 0)] = COLOR_RGB[area.color]
        return rgb

    def zone(self, name: str) -> Zone:
        return next(z for z in self.zones if z.name == name)

    def object(self, name: str) -> CourseObject:
        return next(o for o in self.objects if o.name == name)


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


def _checkpoint(table: dict, where: str) -> Box:
    box = _box(table, where)
    if "heading_deg" not in table:
        return box
    return dataclasses.replace(box, heading_deg=_number(table, "heading_deg", where))


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


def _course_out(table: object, where: str) -> CourseOut:
    """The `[course_out]` table: `margin_m` (>= 0, default 0) and `[[course_out.area]]` boxes (x, y, hx, hy,
    name), each checked against the floor image once it is loaded (`_check_items`)."""
    if table is None:
        return CourseOut()
    where = f"{where} [course_out]"
    if not isinstance(table, dict):
        raise CourseError(f"{where}: must be a table")
    margin = _number(table, "margin_m", where) if "margin_m" in table else 0.0
    if margin < 0:
        raise CourseError(f"{where}: 'margin_m' must not be negative, got {margin:g}")
    areas = table.get("area", [])
    if not (isinstance(areas, list) and all(isinstance(a, dict) for a in areas)):
        raise CourseError(f"{where}: 'area' must be an array of tables ([[course_out.area]])")
    boxes = []
    for i, area in enumerate(areas):
        at = f"{where} area {i}"
        box = _box(area, at)
        if min(box.hx, box.hy) <= margin:
            raise CourseError(f"{at}: {box.name!r} is no wider than twice the margin ({margin:g} m): no robot "
                              f"could be out in it")
        boxes.append(box)
    return CourseOut(margin, tuple(boxes))


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
    _check_keys(spec, path)
    image_path = path.parent / str(spec.get("floor_image", ""))
    if not image_path.is_file():
        raise CourseError(f"{where}: floor_image {spec.get('floor_image')!r} not found")
    ev3, spike = _calibrations(spec, where)
    red, colour = _floor_channels(image_path)
    mpp = _number(spec, "meters_per_pixel", where)
    origin = spec.get("origin")
    if not (isinstance(origin, list) and len(origin) == 2):
        raise CourseError(f"{where}: 'origin' must be [x, y]")
    start = spec.get("start")
    if not isinstance(start, dict):
        raise CourseError(f"{where}: missing [start]")
    walls = tuple(_box(w, f"{where} wall {i}") for i, w in enumerate(spec.get("wall", [])))
    checkpoints = tuple(_checkpoint(c, f"{where} checkpoint {i}") for i, c in enumerate(spec.get("checkpoint", [])))
    if not checkpoints:
        raise CourseError(f"{where}: a course needs at least one [[checkpoint]]")
    limit = _number(spec, "time_limit_s", where)
    if limit <= 0 or mpp <= 0:
        raise CourseError(f"{where}: time_limit_s and meters_per_pixel must be positive")
    areas = tuple(_color_area(a, f"{where} area {i}") for i, a in enumerate(spec.get("area", [])))
    try:
        zones, objects = parse_items(spec, where)
        score = parse_score(spec.get("score"), zones, objects, where, CLASSES)
    except ItemError as e:
        raise CourseError(str(e)) from None
    course = Course(
        name=str(spec.get("name", path.parent.name)),
        folder=path.parent,
        floor=_scaled(red, ev3),
        meters_per_pixel=mpp,
        origin=(float(origin[0]), float(origin[1])),
        walls=walls,
        wall_height=float(spec.get("wall_height", 0.1)),
        checkpoints=checkpoints,
        start=Pose(_number(start, "x", where), _number(start, "y", where), _number(start, "yaw_deg", where)),
        time_limit_us=round(limit * US_PER_S),
        reflect_white=ev3.white,
        reflect_black=ev3.black,
        color_areas=areas,
        wiring=_wiring(spec.get("robot"), where),
        noise=_noise(spec.get("noise"), where),
        info=_course_info(spec.get("etroboc"), where),
        colour=None if colour is None else _scaled(colour, ev3),
        spike=spike,
        zones=zones,
        objects=objects,
        score=score,
        out=_course_out(spec.get("course_out"), where),
    )
    _check_items(course, where)
    return course


def _known(table: dict, kind: str, where: str) -> None:
    unknown = sorted(set(table) - KEYS[kind])
    if unknown:
        raise CourseError(f"{where}: unknown key {unknown[0]!r} (known: {', '.join(sorted(KEYS[kind]))})")


def _check_keys(spec: dict, path: Path) -> None:
    """No key the schema lacks (KEYS), in any table the file holds: a misspelt key would change nothing."""
    _known(spec, "", str(path))
    for kind in [k for k in KEYS if k]:
        table: object = spec
        for part in kind.split("."):
            table = table.get(part) if isinstance(table, dict) else None
        if isinstance(table, dict):
            _known(table, kind, f"{path} [{kind}]")
        elif isinstance(table, list):
            for i, entry in enumerate(table):
                if isinstance(entry, dict):
                    _known(entry, kind, f"{path} [[{kind}]] {i}")


def _calibrations(spec: dict, where: str) -> tuple[Calibration, SpikeFloor]:
    """The EV3's reflect on white and black (`[sensor.ev3]`, or the top-level reflect_white and reflect_black,
    the form the oval's file has always had), and what a SPIKE sensor reads on the course's white, black and
    colours (`[sensor.spike]`; default: `SPIKE_FLOOR`)."""
    sensor = spec.get("sensor", {})
    if not isinstance(sensor, dict):
        raise CourseError(f"{where}: [sensor] must be a table ([sensor.ev3], [sensor.spike])")
    kinds = sorted(k.removeprefix("sensor.") for k in KEYS if k.startswith("sensor."))
    unknown = sorted(set(sensor) - set(kinds))
    if unknown:
        raise CourseError(f"{where}: [sensor.{unknown[0]}]: no such sensor kind (known: {', '.join(kinds)})")
    top = {"reflect_white", "reflect_black"} & set(spec)
    if top and "ev3" in sensor:
        raise CourseError(f"{where}: the EV3's reflect is given twice: [sensor.ev3] and the top-level "
                          f"{sorted(top)[0]}; keep one")
    table = sensor.get("ev3", spec)
    at = f"{where} [sensor.ev3]" if table is not spec else where
    if not isinstance(table, dict):
        raise CourseError(f"{at}: must be a table")
    white, black = _number(table, "reflect_white", at), _number(table, "reflect_black", at)
    if white <= black:
        raise CourseError(f"{at}: reflect_white must be above reflect_black")
    if not (0 <= black and white <= 100):
        raise CourseError(f"{at}: a reflect reading is 0..100, got black {black:g} and white {white:g}")
    return Calibration(white, black), _spike_floor(sensor.get("spike"), f"{where} [sensor.spike]")


def _spike_floor(table: object, at: str) -> SpikeFloor:
    """`[sensor.spike]`: white, black and any colour, each the three channels a SPIKE sensor reads there."""
    if table is None:
        return SPIKE_FLOOR
    if not isinstance(table, dict):
        raise CourseError(f"{at}: must be a table")
    channels = {}
    for name, value in table.items():
        if not (isinstance(value, list) and len(value) == 3 and all(
                isinstance(c, (int, float)) and not isinstance(c, bool) and 0 <= c <= RGB_FULL for c in value)):
            raise CourseError(f"{at}: {name} must be three numbers 0..{RGB_FULL} (r, g, b as the sensor reads "
                              f"them), got {value!r}")
        channels[name] = (float(value[0]), float(value[1]), float(value[2]))
    for name in ("white", "black"):
        if name not in channels:
            raise CourseError(f"{at}: missing '{name}'")
    white, black = channels.pop("white"), channels.pop("black")
    if not all(w > b for w, b in zip(white, black)):
        raise CourseError(f"{at}: white must read above black on every channel")
    return SpikeFloor(white, black, tuple(channels.items()))


def _floor_channels(image_path: Path) -> tuple[np.ndarray, np.ndarray | None]:
    """The image's red channel (0..1, float32) and, for a colour image, its green, blue and mean channels
    (None for a grey one, where every channel is the red)."""
    try:
        with open_floor_image(image_path, image_path.name) as img:
            rgb = np.asarray(img.convert("RGB"))
    except OSError as e:
        raise CourseError(f"{image_path.name}: not a readable image: {e}") from None
    # In place, channel by channel: a whole-image temporary is as big as the result (loading a 40 Mpx colour
    # mat took 2.0 GB at its peak, now 0.9), and the values are the same float32 operations in the same order.
    red = rgb[:, :, 0].astype(np.float32)
    red /= 255.0
    if np.array_equal(rgb[:, :, 0], rgb[:, :, 1]) and np.array_equal(rgb[:, :, 1], rgb[:, :, 2]):
        return red, None
    colour = np.empty(rgb.shape, np.float32)
    colour[:, :, 0], colour[:, :, 1], colour[:, :, 2] = rgb[:, :, 1], rgb[:, :, 2], rgb[:, :, 0]
    colour[:, :, 2] += colour[:, :, 0]
    colour[:, :, 2] += colour[:, :, 1]
    colour[:, :, 2] /= 3
    colour /= 255.0
    return red, colour


def open_floor_image(path: Path, what: str) -> PILImage:
    """The image at `path`, opened (its pixels not yet decoded) when it is within MAX_FLOOR_PIXELS. The bound is
    the bench's, said in one line: PIL's own is a warning on every command above 89 Mpx and a traceback (its
    DecompressionBombError) above 179 Mpx, after which decoding would take gigabytes."""
    from PIL import Image, UnidentifiedImageError

    Image.MAX_IMAGE_PIXELS = None  # PIL's check, which warns or fails where this one says why in one line
    try:
        img = Image.open(path)
    except (UnidentifiedImageError, OSError) as e:
        raise CourseError(f"{what}: not a readable image: {e}") from None
    width, height = img.size
    if width * height > MAX_FLOOR_PIXELS:
        img.close()
        raise CourseError(f"{what}: {width} x {height} px ({width * height / 1e6:.0f} Mpx) is over the bench's limit "
                          f"of {MAX_FLOOR_PIXELS / 1e6:.0f} Mpx for a floor image: scale it down (1 mm a pixel is "
                          "finer than the colour sensor's spot)")
    return img


def _scaled(channels: np.ndarray, ev3: Calibration) -> np.ndarray:
    """Channels 0..1 (float32) as the EV3's reflect between the course's black and white, in place."""
    channels *= ev3.white - ev3.black
    channels += ev3.black
    return channels


def _check_items(course: Course, where: str) -> None:
    """Objects, zones and out-of-bounds areas on the floor image, and no object standing in a wall."""
    xmin, xmax, ymin, ymax = course.extent
    for area in course.out.areas:
        if not (xmin <= area.x - area.hx and area.x + area.hx <= xmax and ymin <= area.y - area.hy
                and area.y + area.hy <= ymax):
            raise CourseError(f"{where}: out-of-bounds area {area.name!r} reaches off the mat (the floor image, "
                              f"x {xmin:g}..{xmax:g}, y {ymin:g}..{ymax:g}): past the mat's edge the run has "
                              f"already left the course")
    for zone in course.zones:
        x0, x1, y0, y1 = zone.bounds()
        if not (xmin <= x0 and x1 <= xmax and ymin <= y0 and y1 <= ymax):
            raise CourseError(f"{where}: zone {zone.name!r} reaches off the floor image (x {xmin:g}..{xmax:g}, "
                              f"y {ymin:g}..{ymax:g})")
    for obj in course.objects:
        r = obj.half_extent
        if not (xmin + r <= obj.x <= xmax - r and ymin + r <= obj.y <= ymax - r):
            raise CourseError(f"{where}: object {obj.name!r} at ({obj.x:g}, {obj.y:g}) stands off the floor image "
                              f"(x {xmin:g}..{xmax:g}, y {ymin:g}..{ymax:g})")
        for wall in course.walls:
            if wall.distance(obj.x, obj.y) < r:
                raise CourseError(f"{where}: object {obj.name!r} at ({obj.x:g}, {obj.y:g}) stands inside wall "
                                  f"{wall.name!r}")

"""What a course places on its floor besides the line: movable objects (`[[object]]`) and named places
(`[[zone]]`) that a task refers to by name.

An object is a body MuJoCo moves: a 500 ml PET bottle is a cylinder, a block a box. It is pushed, carried or
knocked over by the robot, the ultrasonic sensor sees it, the colour sensor reads its colour when it is under
the sensor, and films draw it. A zone is only a place: a ring (a circle) or the garage (a box), painted or
not, which a task such as ET Robocon's score looks at (`[score]` names them).

    [[object]]
    name = "bottle"
    shape = "cylinder"         # or "box"
    radius = 0.0325            # a cylinder's; a box has length, width (its x and y at yaw 0) instead
    height = 0.205
    mass = 0.55                # kg
    friction = 0.5             # sliding friction against whatever it touches
    color = [40, 40, 40]       # its RGB, 0..255, or a colour name (black, blue, green, yellow, red, white, brown)
    x = 1.0                    # where it stands, and its turn about the vertical
    y = 0.5
    yaw_deg = 0

    [[zone]]
    name = "ring"
    x = 1.0
    y = 0.5
    radius = 0.35              # a circle; or hx, hy for a box
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from hakoniwa.physics.color_response import COLOR_RGB
from hakoniwa.wire.errors import HakoError
from hakoniwa.wire.protocol import ColorId

SHAPES = ("cylinder", "box")


class ItemError(HakoError, ValueError):
    """An object, zone or score table is unusable; the message says which and why (the course names its
    file)."""


@dataclass(frozen=True)
class Zone:
    """A named place on the floor: a circle (`radius`) or an axis-aligned box (`hx`, `hy`)."""

    name: str
    x: float
    y: float
    radius: float | None = None
    hx: float = 0.0
    hy: float = 0.0

    def contains(self, x: float, y: float, margin: float = 0.0) -> bool:
        """Whether (x, y) lies inside, the zone grown by `margin` (shrunk where negative)."""
        if self.radius is not None:
            return math.hypot(x - self.x, y - self.y) <= self.radius + margin
        return abs(x - self.x) <= self.hx + margin and abs(y - self.y) <= self.hy + margin

    def bounds(self) -> tuple[float, float, float, float]:
        """(xmin, xmax, ymin, ymax)."""
        rx, ry = (self.radius, self.radius) if self.radius is not None else (self.hx, self.hy)
        return self.x - rx, self.x + rx, self.y - ry, self.y + ry


@dataclass(frozen=True)
class CourseObject:
    """A movable body standing on the floor at the start."""

    name: str
    shape: str  # "cylinder" or "box"
    size: tuple[float, float, float]  # cylinder: radius, radius, height; box: length, width, height
    mass: float
    friction: float
    rgb: tuple[int, int, int]
    x: float
    y: float
    yaw_deg: float = 0.0

    @property
    def height(self) -> float:
        return self.size[2]

    @property
    def half_extent(self) -> float:
        """The largest distance from its axis to its side, seen from above: what clears a wall."""
        a, b, _ = self.size
        return a if self.shape == "cylinder" else math.hypot(a, b) / 2


def _number(table: dict, key: str, where: str, *, positive: bool = False, default: float | None = None) -> float:
    if key not in table:
        if default is not None:
            return default
        raise ItemError(f"{where}: missing '{key}'")
    value = table[key]
    if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value):
        raise ItemError(f"{where}: '{key}' must be a number, got {value!r}")
    if positive and value <= 0:
        raise ItemError(f"{where}: '{key}' must be positive, got {value!r}")
    return float(value)


def _name(table: dict, where: str) -> str:
    name = table.get("name")
    if not isinstance(name, str) or not name or not name.replace("-", "").replace("_", "").isalnum():
        raise ItemError(f"{where}: 'name' must be a word (letters, digits, - and _), got {name!r}")
    return name


def _rgb(value: object, where: str) -> tuple[int, int, int]:
    if isinstance(value, str) and value.upper() in ColorId.__members__ and value.upper() != "NONE":
        return COLOR_RGB[ColorId[value.upper()]]
    if (isinstance(value, list) and len(value) == 3
            and all(isinstance(v, int) and not isinstance(v, bool) and 0 <= v <= 255 for v in value)):
        return value[0], value[1], value[2]
    names = ", ".join(c.name.lower() for c in ColorId if c != ColorId.NONE)
    raise ItemError(f"{where}: 'color' must be [r, g, b] (0..255 each) or one of {names}, got {value!r}")


def _unknown(table: dict, known: set[str], where: str) -> None:
    extra = sorted(set(table) - known)
    if extra:
        raise ItemError(f"{where}: unknown key {extra[0]!r} (known: {', '.join(sorted(known))})")


def parse_zone(table: object, where: str) -> Zone:
    if not isinstance(table, dict):
        raise ItemError(f"{where}: must be a table ([[zone]])")
    _unknown(table, {"name", "x", "y", "radius", "hx", "hy"}, where)
    name = _name(table, where)
    x, y = _number(table, "x", where), _number(table, "y", where)
    if "radius" in table:
        if "hx" in table or "hy" in table:
            raise ItemError(f"{where}: a zone is a circle (radius) or a box (hx, hy), not both")
        return Zone(name, x, y, radius=_number(table, "radius", where, positive=True))
    return Zone(name, x, y, hx=_number(table, "hx", where, positive=True),
                hy=_number(table, "hy", where, positive=True))


def parse_object(table: object, where: str) -> CourseObject:
    if not isinstance(table, dict):
        raise ItemError(f"{where}: must be a table ([[object]])")
    shape = table.get("shape")
    if shape not in SHAPES:
        raise ItemError(f"{where}: 'shape' must be one of {', '.join(SHAPES)}, got {shape!r}")
    sides = ("radius",) if shape == "cylinder" else ("length", "width")
    _unknown(table, {"name", "shape", *sides, "height", "mass", "friction", "color", "x", "y", "yaw_deg"}, where)
    name = _name(table, where)
    dims = [_number(table, key, where, positive=True) for key in (*sides, "height")]
    size = (dims[0], dims[0], dims[1]) if shape == "cylinder" else (dims[0], dims[1], dims[2])
    friction = _number(table, "friction", where)
    if friction < 0:
        raise ItemError(f"{where}: 'friction' must not be negative, got {friction:g}")
    return CourseObject(name, shape, size, _number(table, "mass", where, positive=True), friction,
                        _rgb(table.get("color"), where), _number(table, "x", where), _number(table, "y", where),
                        _number(table, "yaw_deg", where, default=0.0))


def parse_items(spec: dict, where: str) -> tuple[tuple[Zone, ...], tuple[CourseObject, ...]]:
    """The course's zones and objects, each name used once among them."""
    tables = {}
    for key in ("zone", "object"):
        entries = spec.get(key, [])
        if not isinstance(entries, list):
            raise ItemError(f"{where}: '{key}' must be an array of tables ([[{key}]])")
        tables[key] = entries
    zones = tuple(parse_zone(t, f"{where} zone {i + 1}") for i, t in enumerate(tables["zone"]))
    objects = tuple(parse_object(t, f"{where} object {i + 1}") for i, t in enumerate(tables["object"]))
    seen: set[str] = set()
    for name in [z.name for z in zones] + [o.name for o in objects]:
        if name in seen:
            raise ItemError(f"{where}: two zones or objects named {name!r}")
        seen.add(name)
    return zones, objects


@dataclass(frozen=True)
class ScoreSpec:
    """The course's `[score]` table: which ET Robocon class's points apply, and which of its zones and objects
    are the garage, the sumo ring and the sumo bottle (a course without one scores no points for it)."""

    competition_class: str = "applied"
    garage: str | None = None
    sumo_ring: str | None = None
    sumo_bottle: str | None = None


def parse_score(table: object, zones: tuple[Zone, ...], objects: tuple[CourseObject, ...], where: str,
                classes: tuple[str, ...]) -> ScoreSpec:
    """The `[score]` table, its names checked against the course's zones and objects."""
    if table is None:
        return ScoreSpec()
    where = f"{where} [score]"
    if not isinstance(table, dict):
        raise ItemError(f"{where}: must be a table")
    _unknown(table, {"class", "garage", "sumo_ring", "sumo_bottle"}, where)
    competition_class = table.get("class", ScoreSpec.competition_class)
    if competition_class not in classes:
        raise ItemError(f"{where}: 'class' must be one of {', '.join(classes)}, got {competition_class!r}")
    names = {}
    for key, kind, known in (("garage", "zone", zones), ("sumo_ring", "zone", zones),
                             ("sumo_bottle", "object", objects)):
        name = table.get(key)
        if name is not None and name not in {item.name for item in known}:
            raise ItemError(f"{where}: '{key}' names no {kind} of the course: {name!r}")
        names[key] = name
    return ScoreSpec(competition_class, **names)

"""A test scenario beside the course (`--scenario FILE`, TOML): stimuli at simulated times, the same in every
test of a campaign. `[[press]]` presses a touch sensor (`sensor = "touch"`, `port` 1..4 on an EV3, or a SPIKE
port "A".."F", where it presses the force sensor), a SPIKE force sensor (`sensor = "force"`, `port` optional:
the robot has one), an EV3 brick's button (`button = "ENTER"`, ...) or a SPIKE hub's (`button = "CENTER"`,
...) at `at_s` for `for_s` seconds; `[[serial]]` makes `text` arrive on a serial port (`port` "bt" by default,
or "uart", "default") at `at_s`. A program that waits for a touch or a remote start then starts by itself.

What a person does by hand before a start, for a program that calibrates: `[[place]]` lifts the robot and sets
it down at `at_s` (`over = "black"`, `"white"` or `"start"`, the last with the colour sensor on the line's
`edge`, "left", "right" or "centre", if given; or a pose `x`, `y`, `yaw_deg`; `placing.py` finds the spot on
the course), and `[[hand]]` holds a hand `distance_cm` in front of the ultrasonic sensor
from `at_s` for `for_s`. Which robot can take which stimulus is checked against the robot (`check_robot`)."""

from __future__ import annotations

import math
import tomllib
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
from typing import TypeVar

from hakoniwa.physics.robot import ULTRASONIC_MAX_MM
from hakoniwa.physics.robots import Robot, hub_name
from hakoniwa.wire.errors import HakoError
from hakoniwa.wire.protocol import NEVER_WAKES
from hakoniwa.wire.rundir import SERIAL_PORTS
from hakoniwa.wire.timebase import PHYSICS_STEP_US, US_PER_S, Scheduler

EV3_BUTTONS = ("LEFT", "RIGHT", "UP", "DOWN", "ENTER", "BACK")  # button_t order: the bit in RX BUTTONS
# A SPIKE hub's buttons, each as the EV3 button whose bit ET Robocon's SPIKE SDK reads it from (raspike_hub.c:
# CENTER is ENTER's bit, BT BACK's).
SPIKE_BUTTONS = {"LEFT": "LEFT", "RIGHT": "RIGHT", "CENTER": "ENTER", "BT": "BACK"}
PRESSABLE = ("touch", "force")
EV3_PORTS = 4
SPIKE_PORTS = "ABCDEF"
PRESS_S = 0.1  # how long a press holds when `for_s` is not given: a click
HAND_S = 0.5  # how long a hand is held when `for_s` is not given: a wave in front of the sensor
PLACE_OVER = ("black", "white", "start")
START_EDGES = ("left", "right", "centre")  # where on the line `over = "start"` may put the colour sensor


class ScenarioError(HakoError, ValueError):
    """A scenario file is unusable; the message names the problem."""


@dataclass(frozen=True)
class Press:
    where: str  # "scenario.toml press 2": how the user finds it
    sensor: str | None  # "touch" or "force", or None for a button
    port: str | None  # the sensor's port name as the robot names it ("1".."4", "A".."F"); None: the robot's one
    button: str | None  # an EV3 brick's button name or a SPIKE hub's (the robot decides which are there)
    at_us: int
    for_us: int

    def active(self, now_us: int) -> bool:
        return self.at_us <= now_us < self.at_us + self.for_us

    @property
    def bit(self) -> int:
        """The button's bit in RX BUTTONS (a SPIKE hub's button: the EV3 one the SDK reads it from)."""
        assert self.button is not None
        return EV3_BUTTONS.index(SPIKE_BUTTONS.get(self.button, self.button))


@dataclass(frozen=True)
class SerialInput:
    where: str
    at_us: int
    port: str
    text: str


@dataclass(frozen=True)
class Place:
    """The robot lifted and set down at `at_us`: over the course's black line, its white floor or its start
    (`over`), or at an explicit pose (`x`, `y` [m], `yaw_deg` counter-clockwise from +x). `placing.py` turns
    it into a pose on the course."""

    where: str
    at_us: int
    over: str | None  # one of PLACE_OVER, or None for the explicit pose
    x: float = 0.0
    y: float = 0.0
    yaw_deg: float = 0.0
    edge: str | None = None  # over the start: one of START_EDGES, or None for the course's own start pose


@dataclass(frozen=True)
class Hand:
    """A hand `distance_mm` in front of the ultrasonic sensor from `at_us` for `for_us`."""

    where: str
    at_us: int
    for_us: int
    distance_mm: int

    def active(self, now_us: int) -> bool:
        return self.at_us <= now_us < self.at_us + self.for_us


@dataclass(frozen=True)
class Scenario:
    presses: tuple[Press, ...] = ()
    serial: tuple[SerialInput, ...] = ()
    places: tuple[Place, ...] = ()  # in the order they happen; at most one a physics step
    hands: tuple[Hand, ...] = ()

    def sensor_presses(self, now_us: int) -> list[Press]:
        """The sensor presses held at `now_us` (the robot says which slot each presses)."""
        return [p for p in self.presses if p.sensor is not None and p.active(now_us)]

    def buttons(self, now_us: int) -> int:
        """The RX buttons bitmask at `now_us`."""
        return sum({1 << p.bit for p in self.presses if p.button is not None and p.active(now_us)})

    def buttons_until(self, now_us: int) -> int:
        """The first instant after `now_us` at which a press or release may change the buttons (NEVER_WAKES if
        none does): a patched athrill2 needs no new snapshot to read them before then."""
        return min((edge for p in self.presses if p.button is not None for edge in (p.at_us, p.at_us + p.for_us)
                    if edge > now_us), default=NEVER_WAKES)

    def hand_mm(self, now_us: int) -> int | None:
        """How far the nearest hand held at `now_us` is from the ultrasonic sensor (None: no hand)."""
        return min((h.distance_mm for h in self.hands if h.active(now_us)), default=None)

    def check_within(self, time_limit_us: int) -> None:
        """Refuse a stimulus at or after the time limit: the test ends there (TIME_OVER) before it could
        happen, so a program waiting for it would fail every test for a reason the user did not mean."""
        stimuli: tuple[Press | SerialInput | Place | Hand, ...] = (*self.presses, *self.serial, *self.places,
                                                                   *self.hands)
        for s in stimuli:
            if s.at_us >= time_limit_us:
                raise ScenarioError(f"{s.where}: at_s = {s.at_us / US_PER_S:g} is not before the time limit "
                                    f"({time_limit_us / US_PER_S:g} s): no test would get there")

    def check_robot(self, robot: Robot) -> None:
        """Refuse a stimulus the robot cannot take, naming its entry: a press of a sensor it does not have,
        another hub's button, a hand with no ultrasonic sensor to hold it in front of."""
        for press in self.presses:
            if press.sensor is not None and robot.press_slot(press.sensor, press.port) is None:
                where = "" if press.port is None else f" on port {press.port}"
                what = "touch or force" if press.sensor == "touch" and robot.spike else press.sensor
                raise ScenarioError(f"{press.where}: robot {robot.name!r} has no {what} sensor{where} to press")
            names = tuple(SPIKE_BUTTONS) if robot.spike else EV3_BUTTONS
            if press.button is not None and press.button not in names:
                raise ScenarioError(f"{press.where}: robot {robot.name!r} has no button {press.button} "
                                    f"({hub_name(robot.hub)}: {', '.join(names)})")
        for hand in self.hands:
            if not robot.has("ultrasonic"):
                raise ScenarioError(f"{hand.where}: robot {robot.name!r} has no ultrasonic sensor to hold a hand "
                                    "in front of")

    def serial_lines(self) -> str:
        """The runtime's serial-input file: "<at_us> <port> <hex bytes>" per input."""
        return "".join(f"{s.at_us} {s.port} {s.text.encode().hex()}\n" for s in self.serial if s.text)


def _number(table: dict, key: str, where: str, what: str, default: float | None = None) -> float:
    value = table.get(key, default)
    if value is None:
        raise ScenarioError(f"{where}: missing '{key}'")
    if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value):
        raise ScenarioError(f"{where}: '{key}' must be {what}, got {value!r}")
    return float(value)


def _seconds(table: dict, key: str, where: str, *, default: float | None = None, positive: bool = False) -> int:
    value = _number(table, key, where, "a number of seconds", default)
    if value < 0 or (positive and value == 0):
        raise ScenarioError(f"{where}: '{key}' must be {'positive' if positive else 'at least 0'}, got {value:g}")
    return round(value * US_PER_S)


def _table(table: object, where: str, keys: set[str]) -> dict:
    """`table` as a TOML table with none but `keys`."""
    if not isinstance(table, dict):
        raise ScenarioError(f"{where}: must be a table")
    unknown = sorted(set(table) - keys)
    if unknown:
        raise ScenarioError(f"{where}: unknown key {unknown[0]!r}")
    return table


def _press(table: object, where: str) -> Press:
    table = _table(table, where, {"sensor", "button", "port", "at_s", "for_s"})
    at, length = _seconds(table, "at_s", where), _seconds(table, "for_s", where, default=PRESS_S, positive=True)
    if ("sensor" in table) == ("button" in table):
        raise ScenarioError(f"{where}: give either sensor = \"touch\" or button = \"ENTER\" (one of them)")
    if "sensor" in table:
        sensor = table["sensor"]
        if sensor not in PRESSABLE:
            raise ScenarioError(f"{where}: sensor {sensor!r} cannot be pressed (only \"touch\" or \"force\")")
        if "port" not in table and sensor == "touch":
            raise ScenarioError(f"{where}: a touch press needs port = 1..{EV3_PORTS} (an EV3's) or "
                                f"\"A\"..\"F\" (a SPIKE hub's)")
        return Press(where, sensor, None if "port" not in table else _port(table["port"], where), None, at, length)
    name = str(table["button"]).upper()
    if name not in EV3_BUTTONS and name not in SPIKE_BUTTONS:
        raise ScenarioError(f"{where}: button {table['button']!r} is not one of an EV3's "
                            f"({', '.join(EV3_BUTTONS)}) or a SPIKE hub's ({', '.join(SPIKE_BUTTONS)})")
    return Press(where, None, None, name, at, length)


def _port(value: object, where: str) -> str:
    """A sensor port as the robot names it: an EV3's 1..4, or a SPIKE hub's letter A..F."""
    if isinstance(value, int) and not isinstance(value, bool) and 1 <= value <= EV3_PORTS:
        return str(value)
    if isinstance(value, str) and len(value) == 1 and value.upper() in SPIKE_PORTS:
        return value.upper()
    raise ScenarioError(f"{where}: port must be 1..{EV3_PORTS} (an EV3's) or \"A\"..\"F\" (a SPIKE hub's), "
                        f"got {value!r}")


def _serial(table: object, where: str) -> SerialInput:
    table = _table(table, where, {"at_s", "text", "port"})
    text, port = table.get("text"), str(table.get("port", "bt")).lower()
    if not isinstance(text, str):
        raise ScenarioError(f"{where}: 'text' must be a string")
    if port not in SERIAL_PORTS:
        raise ScenarioError(f"{where}: port {table.get('port')!r} is not one of {', '.join(SERIAL_PORTS)}")
    return SerialInput(where, _seconds(table, "at_s", where), port, text)


def _place(table: object, where: str) -> Place:
    table = _table(table, where, {"at_s", "over", "x", "y", "yaw_deg", "edge"})
    at = _seconds(table, "at_s", where)
    pose = {"x", "y", "yaw_deg"} & set(table)
    if ("over" in table) == bool(pose):
        raise ScenarioError(f"{where}: give either over = \"black\", \"white\" or \"start\", or a pose x, y, "
                            "yaw_deg (one of them)")
    edge = table.get("edge")
    if edge is not None and table.get("over") != "start":
        raise ScenarioError(f"{where}: 'edge' goes with over = \"start\" only")
    if "over" in table:
        over = table["over"]
        if over not in PLACE_OVER:
            raise ScenarioError(f"{where}: over must be one of {', '.join(map(repr, PLACE_OVER))}, got {over!r}")
        if edge is not None and edge not in START_EDGES:
            raise ScenarioError(f"{where}: edge must be one of {', '.join(map(repr, START_EDGES))}, got {edge!r}")
        return Place(where, at, over, edge=edge)
    x, y = _number(table, "x", where, "metres"), _number(table, "y", where, "metres")
    return Place(where, at, None, x, y, _number(table, "yaw_deg", where, "degrees"))


def _hand(table: object, where: str) -> Hand:
    table = _table(table, where, {"at_s", "for_s", "distance_cm"})
    at, length = _seconds(table, "at_s", where), _seconds(table, "for_s", where, default=HAND_S, positive=True)
    distance = _number(table, "distance_cm", where, "a number of centimetres")
    top = ULTRASONIC_MAX_MM / 10
    if not 0 <= distance < top:
        raise ScenarioError(f"{where}: 'distance_cm' must be at least 0 and below {top:g} (the sensor's range), "
                            f"got {distance:g}")
    return Hand(where, at, length, round(distance * 10))


TABLES = ("press", "serial", "place", "hand")  # the scenario's arrays of tables
T = TypeVar("T")


def _entries(spec: dict, key: str, parse: Callable[[object, str], T], where: str) -> tuple[T, ...]:
    tables = spec.get(key, [])
    if not isinstance(tables, list):
        raise ScenarioError(f"{where}: '{key}' must be an array of tables ([[{key}]])")
    return tuple(parse(t, f"{where} {key} {i + 1}") for i, t in enumerate(tables))


def parse_scenario(text: str, where: str = "scenario") -> Scenario:
    try:
        spec = tomllib.loads(text)
    except tomllib.TOMLDecodeError as e:
        raise ScenarioError(f"{where}: not valid TOML: {e}") from None
    unknown = sorted(set(spec) - set(TABLES))
    if unknown:
        raise ScenarioError(f"{where}: unknown table {unknown[0]!r} (known: {', '.join(TABLES)})")
    presses, serial = _entries(spec, "press", _press, where), _entries(spec, "serial", _serial, where)
    places = tuple(sorted(_entries(spec, "place", _place, where), key=lambda p: p.at_us))
    _one_place_a_step(places)
    return Scenario(presses, serial, places, _entries(spec, "hand", _hand, where))


def _one_place_a_step(places: tuple[Place, ...]) -> None:
    """Two places at one physics step (a place happens at the first step at or after its time) would leave the
    robot at the file's last of them, the other never seen: refused, naming both."""
    steps = Scheduler(PHYSICS_STEP_US)
    for a, b in zip(places, places[1:]):
        if steps.quantize(a.at_us) == steps.quantize(b.at_us):
            raise ScenarioError(f"{b.where}: at_s = {b.at_us / US_PER_S:g} is the same physics step "
                                f"({PHYSICS_STEP_US} us) as {a.where} (at_s = {a.at_us / US_PER_S:g}): the robot "
                                "is set down in one place at a time; give them different times")


def load_scenario(path: str | Path | None) -> Scenario:
    if path is None:
        return Scenario()
    path = Path(path)
    try:
        text = path.read_text()
    except (OSError, UnicodeDecodeError) as e:
        raise ScenarioError(f"scenario {path}: cannot read it: {e}") from None
    return parse_scenario(text, path.name)

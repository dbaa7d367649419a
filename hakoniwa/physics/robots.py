"""Robots described by their wiring (`--robot NAME|FILE`): which motor ports drive the wheels and which sensor
sits on which port. The wiring decides what the program's ports mean: the wheel ports' encoders and powers,
and which touch slot a pressed touch sensor reads (EV3RT numbers touch sensors in port order). A robot file
is TOML: `left_motor = "C"`, `right_motor = "B"`, `bumper = true|false` (the first touch sensor reads wall
contact), and `[[sensor]] port = 1, kind = "touch"`, one per device.

Built in: `default`, the TOPPERS samples' robot (wheels A/B; colour 1, ultrasonic 2, touch 3 as the bumper,
touch 4), whose wheel ports a course's `[robot]` table may change; and `hackev`, ET Robocon's HackEV
(wheels C left, B right; touch 1, colour 2, ultrasonic 3, gyro 4).
"""

from __future__ import annotations

import tomllib
from dataclasses import dataclass
from pathlib import Path

from hakoniwa.physics.robot import DEFAULT_WIRING, Wiring

SENSOR_KINDS = ("color", "ultrasonic", "gyro", "touch")
PORT_LETTERS = "ABCD"
SENSOR_PORTS = 4


class RobotError(ValueError):
    """A robot description is unusable; the message names the problem."""


@dataclass(frozen=True)
class Robot:
    name: str
    wiring: Wiring | None  # None: the course's [robot] wheel ports
    sensors: tuple[tuple[int, str], ...]  # (0-based port, kind), in port order
    bumper: bool  # the first touch sensor reads the robot's contact with a wall

    def touch_slot(self, port: int) -> int | None:
        """The touch slot (0 or 1) the sensor on `port` reads, or None if no touch sensor is there."""
        touches = [p for p, kind in self.sensors if kind == "touch"]
        return touches.index(port) if port in touches[:2] else None


DEFAULT_ROBOT = Robot("default", None, ((0, "color"), (1, "ultrasonic"), (2, "touch"), (3, "touch")), True)
BUILT_IN = {"default": DEFAULT_ROBOT,
            "hackev": Robot("hackev", Wiring(left=2, right=1),
                            ((0, "touch"), (1, "color"), (2, "ultrasonic"), (3, "gyro")), False)}


def parse_robot(text: str, where: str) -> Robot:
    try:
        spec = tomllib.loads(text)
    except tomllib.TOMLDecodeError as e:
        raise RobotError(f"{where}: not valid TOML: {e}") from None
    unknown = sorted(set(spec) - {"name", "left_motor", "right_motor", "bumper", "sensor"})
    if unknown:
        raise RobotError(f"{where}: unknown key {unknown[0]!r}")
    ports = {}
    for key in ("left_motor", "right_motor"):
        letter = str(spec.get(key, PORT_LETTERS[getattr(DEFAULT_WIRING, key.removesuffix("_motor"))])).upper()
        if len(letter) != 1 or letter not in PORT_LETTERS:
            raise RobotError(f"{where}: {key} must be a motor port A..D, got {spec.get(key)!r}")
        ports[key] = PORT_LETTERS.index(letter)
    if ports["left_motor"] == ports["right_motor"]:
        raise RobotError(f"{where}: two devices on motor port {PORT_LETTERS[ports['left_motor']]}: "
                         "left_motor and right_motor")
    sensors: dict[int, str] = {}
    entries = spec.get("sensor", [])
    if not isinstance(entries, list):
        raise RobotError(f"{where}: 'sensor' must be an array of tables ([[sensor]])")
    for i, entry in enumerate(entries):
        at = f"{where} sensor {i + 1}"
        if not isinstance(entry, dict) or set(entry) - {"port", "kind"}:
            raise RobotError(f"{at}: needs exactly port and kind")
        port, kind = entry.get("port"), entry.get("kind")
        if isinstance(port, bool) or not isinstance(port, int) or not 1 <= port <= SENSOR_PORTS:
            raise RobotError(f"{at}: port must be 1..{SENSOR_PORTS}, got {port!r}")
        if kind not in SENSOR_KINDS:
            raise RobotError(f"{at}: kind must be one of {', '.join(SENSOR_KINDS)}, got {kind!r}")
        if port - 1 in sensors:
            raise RobotError(f"{where}: two devices on sensor port {port}: {sensors[port - 1]} and {kind}")
        sensors[port - 1] = kind
    bumper = spec.get("bumper", False)
    if not isinstance(bumper, bool):
        raise RobotError(f"{where}: bumper must be true or false")
    return Robot(str(spec.get("name", where)), Wiring(ports["left_motor"], ports["right_motor"]),
                 tuple(sorted(sensors.items())), bumper)


def load_robot(name_or_path: str | None) -> Robot:
    if name_or_path is None:
        return DEFAULT_ROBOT
    if name_or_path in BUILT_IN:
        return BUILT_IN[name_or_path]
    path = Path(name_or_path)
    if not path.is_file():
        raise RobotError(f"no robot {name_or_path!r} (built-in: {', '.join(BUILT_IN)}; or a robot TOML file)")
    try:
        return parse_robot(path.read_text(), path.name)
    except UnicodeDecodeError as e:
        raise RobotError(f"{path.name}: not a text file: {e}") from None

"""Robots described by their hub, wiring and body (`--robot NAME|FILE`): which motor ports drive the wheels and
how each motor is mounted, which sensor sits on which port, and the body the world builds. The wiring decides
what the program's ports mean: the wheel ports' encoders and powers, and which touch slot a pressed touch or
force sensor reads.

A robot file is TOML:

    name = "my-robot"
    hub = "ev3"                    # or "spike": the brick the program runs on (default ev3)
    left_motor = "C"               # motor ports A..D (the wire has four motor slots)
    right_motor = "B"
    left_motor_forward = "negative"   # the power sign that drives the robot forward ("positive" by default):
                                      # "negative" for a motor mounted mirror-wise
    bumper = false                 # the first touch (or the force) sensor reads wall contact
    body = "ev3"                   # or "hackspi" [default: ev3 on an EV3, hackspi on a SPIKE hub]
    reflection = { white = 40, black = 10 }  # a SPIKE hub's: what its colour sensor's reflection reads on a
                                   # course's white and black, from how high it sits [default: HackSPi's]
    class = "applied"              # or "basic": the ET Robocon class whose points --objective etrobocon
                                   # gives [default: the course's [score] class]
    [[sensor]]
    port = 2                       # an EV3's sensor ports are 1..4; a SPIKE hub's are "A".."F"
    kind = "color"                 # EV3: color, ultrasonic, gyro, touch; SPIKE: color, ultrasonic, force

The hub decides the port names: an EV3 brick has motor ports A..D and sensor ports 1..4; a SPIKE hub has
six ports A..F that take a motor or a sensor each (a SPIKE robot's motor and sensor ports must differ). A
SPIKE hub always has its IMU. ET Robocon's SDK reads every SPIKE sensor of a kind from one slot whatever its
port (`raspike_color.c` reads colour slot 0, `raspike_forcesensor.c` touch slot 0), so a SPIKE robot has at
most one sensor of each kind.

Built in: `default`, the TOPPERS samples' robot (wheels A/B; colour 1, ultrasonic 2, touch 3 as the bumper,
touch 4), whose wheel ports a course's `[robot]` table may change; `hackev`, ET Robocon's HackEV (wheels C
left, B right; touch 1, colour 2, ultrasonic 3, gyro 4); `hackspi`, ET Robocon's HackSPi (SPIKE hub: left
wheel B mounted mirror-wise, right A; force D, colour E, ultrasonic F); and `basic`, the Basic class's robot,
which runs SPIKE-RT on the hub itself: HackSPi's wiring and body, with its colour sensor mounted lower, so that it
reads white 80 and black 10, as SPIKE-RT's own samples assume. `hackspi` competes in ET Robocon's applied class
and `basic` in the basic class: `--objective etrobocon` scores each by its class's points, whatever class the
course's `[score]` names (that one is for robots of no class, the EV3s).

A SPIKE robot's colour sensor has its own response (`reflection`): the course says what a sensor reads on
its white, black and colours channel by channel, and the robot how its sensor, at its height, reads them
(`color_response.py`). HackSPi's reads white 40 and black 10, as ET Robocon's official sample is tuned for.
"""

from __future__ import annotations

import tomllib
from dataclasses import dataclass
from pathlib import Path

from hakoniwa.physics.color_response import SPIKE_DEFAULT, Calibration
from hakoniwa.physics.robot import DEFAULT_WIRING, EV3_BODY, HACKSPI_BODY, Body, Wiring
from hakoniwa.wire.errors import HakoError
from hakoniwa.wire.etrobocon_rules import CLASSES

EV3, SPIKE = "ev3", "spike"
HUB_PORTS = {EV3: ("1", "2", "3", "4"), SPIKE: ("A", "B", "C", "D", "E", "F")}  # sensor ports, by hub
HUB_SENSORS = {EV3: ("color", "ultrasonic", "gyro", "touch"), SPIKE: ("color", "ultrasonic", "force")}
MOTOR_LETTERS = "ABCD"
BODIES = {"ev3": EV3_BODY, "hackspi": HACKSPI_BODY}
DEFAULT_BODY = {EV3: "ev3", SPIKE: "hackspi"}
FORWARD = {"positive": 1, "negative": -1}


class RobotError(HakoError, ValueError):
    """A robot description is unusable; the message names the problem."""


@dataclass(frozen=True)
class Robot:
    name: str
    wiring: Wiring | None  # None: the course's [robot] wheel ports
    sensors: tuple[tuple[str, str], ...]  # (port name, kind), in port order: "1".."4" on an EV3, "A".."F" on SPIKE
    bumper: bool  # the first touch sensor (a SPIKE robot's force sensor) reads the robot's contact with a wall
    hub: str = EV3
    body: Body = EV3_BODY
    reflection: Calibration = SPIKE_DEFAULT  # a SPIKE colour sensor's reflection on white and black
    # The ET Robocon class the robot competes in (regulation 3, 表 3-1: HackSPi applied, SPIKE-RT on the hub
    # basic), whose points `--objective etrobocon` gives; None: the course's `[score] class`.
    competition_class: str | None = None

    @property
    def spike(self) -> bool:
        """A SPIKE hub: its IMU, and its sensors' SPIKE responses (`sensors.py`)."""
        return self.hub == SPIKE

    def has(self, kind: str) -> bool:
        return any(k == kind for _, k in self.sensors)

    def kind_at(self, port: str) -> str | None:
        return dict(self.sensors).get(port)

    def touch_slot(self, port: str) -> int | None:
        """The touch slot (0 or 1) the touch or force sensor on `port` reads, or None if neither is there.
        EV3RT numbers touch sensors in port order; ET Robocon's SDK reads the force sensor from slot 0."""
        if self.kind_at(port) == "force":
            return 0
        touches = [p for p, kind in self.sensors if kind == "touch"]
        return touches.index(port) if port in touches[:2] else None

    def press_slot(self, sensor: str, port: str | None) -> int | None:
        """The touch slot a scenario's press of `sensor` ("touch" or "force") on `port` (None: the robot's
        force sensor, wherever it is) holds down, or None if the robot has no such sensor there."""
        if sensor == "force":
            force = next((p for p, kind in self.sensors if kind == "force"), None)
            return 0 if force is not None and port in (None, force) else None
        return None if port is None else self.touch_slot(port)


DEFAULT_ROBOT = Robot("default", None, (("1", "color"), ("2", "ultrasonic"), ("3", "touch"), ("4", "touch")), True)
# HackSPi as ET Robocon's official sample_c5_spike wires it (app.c: colour E, left motor B, right motor A,
# force D; LineTracer.c sets the left motor PUP_DIRECTION_COUNTERCLOCKWISE: it is mounted mirror-wise). The
# ultrasonic sensor is on F in ET Robocon's libraspike-art test program (sample/raspike_test) and in teams'
# RasPike-ART programs; the samples do not use one (docs/DESIGN-NOTES.md).
HACKSPI = Robot("hackspi", Wiring(left=1, right=0, left_forward=-1),
                (("D", "force"), ("E", "color"), ("F", "ultrasonic")), False, SPIKE, HACKSPI_BODY,
                reflection=SPIKE_DEFAULT, competition_class="applied")
# The Basic class's robot as SPIKE-RT's own samples wire it (sdk/workspace/sample_c5 app.c and LineTracer.c:
# HackSPi's ports and directions) and calibrate it (LineTracer.h: WHITE_BRIGHTNESS 80, BLACK_BRIGHTNESS 10).
BASIC = Robot("basic", HACKSPI.wiring, HACKSPI.sensors, False, SPIKE, HACKSPI_BODY, Calibration(white=80, black=10),
              competition_class="basic")
BUILT_IN = {"default": DEFAULT_ROBOT,
            "hackev": Robot("hackev", Wiring(left=2, right=1),
                            (("1", "touch"), ("2", "color"), ("3", "ultrasonic"), ("4", "gyro")), False),
            "hackspi": HACKSPI,
            "basic": BASIC}


def sensor_port(value: object, hub: str) -> str:
    """The port name `value` means on `hub` (an EV3's 1..4, a SPIKE hub's "A".."F"), or RobotError."""
    ports = HUB_PORTS[hub]
    if hub == SPIKE:
        if not isinstance(value, str) or len(value) != 1 or not value.isalpha():
            raise RobotError(f"a SPIKE hub's ports are letters A..F, got {value!r}")
        if value.upper() not in ports:
            raise RobotError(f"port {value!r} does not exist on a SPIKE hub (ports A..F)")
        return value.upper()
    if isinstance(value, bool) or not isinstance(value, int) or str(value) not in ports:
        hint = ' (ports A..F are a SPIKE hub\'s: hub = "spike")' if isinstance(value, str) else ""
        raise RobotError(f"an EV3's sensor ports are 1..4, got {value!r}{hint}")
    return str(value)


def _choice(spec: dict, key: str, choices: dict | tuple, default: str, where: str) -> str:
    value = spec.get(key, default)
    if value not in choices:
        raise RobotError(f"{where}: {key} must be one of {', '.join(choices)}, got {value!r}")
    return value


def parse_robot(text: str, where: str) -> Robot:
    try:
        spec = tomllib.loads(text)
    except tomllib.TOMLDecodeError as e:
        raise RobotError(f"{where}: not valid TOML: {e}") from None
    unknown = sorted(set(spec) - {"name", "hub", "body", "left_motor", "right_motor", "left_motor_forward",
                                  "right_motor_forward", "bumper", "sensor", "reflection", "class"})
    if unknown:
        raise RobotError(f"{where}: unknown key {unknown[0]!r}")
    hub = _choice(spec, "hub", HUB_PORTS, EV3, where)
    body = BODIES[_choice(spec, "body", BODIES, DEFAULT_BODY[hub], where)]
    ports, forward = {}, {}
    for key in ("left_motor", "right_motor"):
        letter = spec.get(key, MOTOR_LETTERS[getattr(DEFAULT_WIRING, key.removesuffix("_motor"))])
        if not isinstance(letter, str) or len(letter) != 1 or letter.upper() not in MOTOR_LETTERS:
            raise RobotError(f"{where}: {key} must be a motor port A..D (the wire has four motor slots), "
                             f"got {letter!r}")
        ports[key] = MOTOR_LETTERS.index(letter.upper())
        forward[key] = FORWARD[_choice(spec, f"{key}_forward", FORWARD, "positive", where)]
    if ports["left_motor"] == ports["right_motor"]:
        raise RobotError(f"{where}: two devices on motor port {MOTOR_LETTERS[ports['left_motor']]}: "
                         "left_motor and right_motor")
    # On a SPIKE hub the motors take two of the six ports the sensors share.
    taken = {MOTOR_LETTERS[p]: key for key, p in ports.items()} if hub == SPIKE else {}
    sensors: dict[str, str] = {}
    entries = spec.get("sensor", [])
    if not isinstance(entries, list):
        raise RobotError(f"{where}: 'sensor' must be an array of tables ([[sensor]])")
    for i, entry in enumerate(entries):
        at = f"{where} sensor {i + 1}"
        if not isinstance(entry, dict) or set(entry) - {"port", "kind"}:
            raise RobotError(f"{at}: needs exactly port and kind")
        try:
            port = sensor_port(entry.get("port"), hub)
        except RobotError as e:
            raise RobotError(f"{at}: {e}") from None
        kind = entry.get("kind")
        if kind not in HUB_SENSORS[hub]:
            raise RobotError(f"{at}: kind must be one of {', '.join(HUB_SENSORS[hub])} on {hub_name(hub)}, "
                             f"got {kind!r}")
        if port in sensors or port in taken:
            raise RobotError(f"{where}: two devices on {'' if hub == SPIKE else 'sensor '}port {port}: "
                             f"{sensors.get(port) or taken[port]} and {kind}")
        if hub == SPIKE and kind in sensors.values():
            other = next(p for p, k in sensors.items() if k == kind)
            raise RobotError(f"{where}: two {kind} sensors (ports {other} and {port}): ET Robocon's SDK reads "
                             "every SPIKE sensor of a kind from one slot")
        sensors[port] = kind
    bumper = spec.get("bumper", False)
    if not isinstance(bumper, bool):
        raise RobotError(f"{where}: bumper must be true or false")
    competition_class = spec.get("class")
    if competition_class is not None and competition_class not in CLASSES:
        raise RobotError(f"{where}: class must be one of {', '.join(CLASSES)}, got {competition_class!r}")
    wiring = Wiring(ports["left_motor"], ports["right_motor"], forward["left_motor"], forward["right_motor"])
    return Robot(str(spec.get("name", where)), wiring, tuple(sorted(sensors.items())), bumper, hub, body,
                 _reflection(spec.get("reflection"), hub, where), competition_class)


def _reflection(table: object, hub: str, where: str) -> Calibration:
    """`reflection = { white = .., black = .. }`: a SPIKE colour sensor's reflection on white and black."""
    if table is None:
        return SPIKE_DEFAULT
    if hub != SPIKE:
        raise RobotError(f"{where}: reflection is a SPIKE colour sensor's (hub = \"spike\")")
    if not isinstance(table, dict) or set(table) != {"white", "black"} or not all(
            isinstance(v, int) and not isinstance(v, bool) and 0 <= v <= 100 for v in table.values()):
        raise RobotError(f"{where}: reflection must be {{ white = N, black = N }}, whole numbers 0..100")
    if table["white"] <= table["black"]:
        raise RobotError(f"{where}: reflection's white must be above its black")
    return Calibration(table["white"], table["black"])


def hub_name(hub: str) -> str:
    return "an EV3" if hub == EV3 else "a SPIKE hub"


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

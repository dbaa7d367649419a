"""A test scenario beside the course (`--scenario FILE`, TOML): stimuli at simulated times, the same in every
test of a campaign. `[[press]]` presses a touch sensor (`sensor = "touch"`, `port` 1..4 on an EV3, or a SPIKE
port "A".."F", where it presses the force sensor), a SPIKE force sensor (`sensor = "force"`, `port` optional:
the robot has one) or an EV3 button (`button = "ENTER"`, ...) at `at_s` for `for_s` seconds; `[[serial]]`
makes `text` arrive on a serial port (`port` "bt" by default, or "uart", "default") at `at_s`. A program that waits
for a touch or a remote start then starts by itself."""

from __future__ import annotations

import math
import tomllib
from dataclasses import dataclass
from pathlib import Path

from hakoniwa.wire.errors import HakoError
from hakoniwa.wire.protocol import NEVER_WAKES
from hakoniwa.wire.rundir import SERIAL_PORTS
from hakoniwa.wire.timebase import US_PER_S

BUTTONS = ("LEFT", "RIGHT", "UP", "DOWN", "ENTER", "BACK")  # button_t order: the bit in RX BUTTONS
PRESSABLE = ("touch", "force")
EV3_PORTS = 4
SPIKE_PORTS = "ABCDEF"


class ScenarioError(HakoError, ValueError):
    """A scenario file is unusable; the message names the problem."""


@dataclass(frozen=True)
class Press:
    where: str  # "scenario.toml press 2": how the user finds it
    sensor: str | None  # "touch" or "force", or None for a button
    port: str | None  # the sensor's port name as the robot names it ("1".."4", "A".."F"); None: the robot's one
    button: int | None
    at_us: int
    for_us: int

    def active(self, now_us: int) -> bool:
        return self.at_us <= now_us < self.at_us + self.for_us


@dataclass(frozen=True)
class SerialInput:
    where: str
    at_us: int
    port: str
    text: str


@dataclass(frozen=True)
class Scenario:
    presses: tuple[Press, ...] = ()
    serial: tuple[SerialInput, ...] = ()

    def sensor_presses(self, now_us: int) -> list[Press]:
        """The sensor presses held at `now_us` (the robot says which slot each presses)."""
        return [p for p in self.presses if p.sensor is not None and p.active(now_us)]

    def buttons(self, now_us: int) -> int:
        """The RX buttons bitmask at `now_us`."""
        return sum(1 << p.button for p in self.presses if p.button is not None and p.active(now_us)) & 0x3F

    def buttons_until(self, now_us: int) -> int:
        """The first instant after `now_us` at which a press or release may change the buttons (NEVER_WAKES if
        none does): a patched athrill2 needs no new snapshot to read them before then."""
        return min((edge for p in self.presses if p.button is not None for edge in (p.at_us, p.at_us + p.for_us)
                    if edge > now_us), default=NEVER_WAKES)

    def check_within(self, time_limit_us: int) -> None:
        """Refuse a stimulus at or after the time limit: the test ends there (TIME_OVER) before it could
        happen, so a program waiting for it would fail every test for a reason the user did not mean."""
        stimuli: tuple[Press | SerialInput, ...] = (*self.presses, *self.serial)
        for s in stimuli:
            if s.at_us >= time_limit_us:
                raise ScenarioError(f"{s.where}: at_s = {s.at_us / US_PER_S:g} is not before the time limit "
                                    f"({time_limit_us / US_PER_S:g} s): no test would get there")

    def serial_lines(self) -> str:
        """The runtime's serial-input file: "<at_us> <port> <hex bytes>" per input."""
        return "".join(f"{s.at_us} {s.port} {s.text.encode().hex()}\n" for s in self.serial if s.text)


def _seconds(table: dict, key: str, where: str, *, default: float | None = None, positive: bool = False) -> int:
    value = table.get(key, default)
    if value is None:
        raise ScenarioError(f"{where}: missing '{key}'")
    if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value):
        raise ScenarioError(f"{where}: '{key}' must be a number of seconds, got {value!r}")
    if value < 0 or (positive and value == 0):
        raise ScenarioError(f"{where}: '{key}' must be {'positive' if positive else 'at least 0'}, got {value:g}")
    return round(value * US_PER_S)


def _press(table: object, where: str) -> Press:
    if not isinstance(table, dict):
        raise ScenarioError(f"{where}: must be a table")
    unknown = sorted(set(table) - {"sensor", "button", "port", "at_s", "for_s"})
    if unknown:
        raise ScenarioError(f"{where}: unknown key {unknown[0]!r}")
    at, length = _seconds(table, "at_s", where), _seconds(table, "for_s", where, default=0.1, positive=True)
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
    if name not in BUTTONS:
        raise ScenarioError(f"{where}: button {table['button']!r} is not one of {', '.join(BUTTONS)}")
    return Press(where, None, None, BUTTONS.index(name), at, length)


def _port(value: object, where: str) -> str:
    """A sensor port as the robot names it: an EV3's 1..4, or a SPIKE hub's letter A..F."""
    if isinstance(value, int) and not isinstance(value, bool) and 1 <= value <= EV3_PORTS:
        return str(value)
    if isinstance(value, str) and len(value) == 1 and value.upper() in SPIKE_PORTS:
        return value.upper()
    raise ScenarioError(f"{where}: port must be 1..{EV3_PORTS} (an EV3's) or \"A\"..\"F\" (a SPIKE hub's), "
                        f"got {value!r}")


def _serial(table: object, where: str) -> SerialInput:
    if not isinstance(table, dict):
        raise ScenarioError(f"{where}: must be a table")
    unknown = sorted(set(table) - {"at_s", "text", "port"})
    if unknown:
        raise ScenarioError(f"{where}: unknown key {unknown[0]!r}")
    text, port = table.get("text"), str(table.get("port", "bt")).lower()
    if not isinstance(text, str):
        raise ScenarioError(f"{where}: 'text' must be a string")
    if port not in SERIAL_PORTS:
        raise ScenarioError(f"{where}: port {table.get('port')!r} is not one of {', '.join(SERIAL_PORTS)}")
    return SerialInput(where, _seconds(table, "at_s", where), port, text)


def parse_scenario(text: str, where: str = "scenario") -> Scenario:
    try:
        spec = tomllib.loads(text)
    except tomllib.TOMLDecodeError as e:
        raise ScenarioError(f"{where}: not valid TOML: {e}") from None
    unknown = sorted(set(spec) - {"press", "serial"})
    if unknown:
        raise ScenarioError(f"{where}: unknown table {unknown[0]!r} (known: press, serial)")
    for key in ("press", "serial"):
        if not isinstance(spec.get(key, []), list):
            raise ScenarioError(f"{where}: '{key}' must be an array of tables ([[{key}]])")
    return Scenario(tuple(_press(p, f"{where} press {i + 1}") for i, p in enumerate(spec.get("press", []))),
                    tuple(_serial(s, f"{where} serial {i + 1}") for i, s in enumerate(spec.get("serial", []))))


def load_scenario(path: str | Path | None) -> Scenario:
    if path is None:
        return Scenario()
    path = Path(path)
    try:
        text = path.read_text()
    except (OSError, UnicodeDecodeError) as e:
        raise ScenarioError(f"scenario {path}: cannot read it: {e}") from None
    return parse_scenario(text, path.name)

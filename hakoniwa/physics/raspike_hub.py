"""The SPIKE hub as RasPike-ART's `asp` meets it over USB serial: the hub's side of RasPike-ART's protocol,
answered on a pseudo-terminal from the bench's readings.

On HackSPi the hub runs `raspike.c` (spike-rt-hub/sdk/workspace/raspike/raspike.c, ET Robocon's SPIKE-RT app)
and the Pi's `libraspike-art` talks to it at 115200 8N1. This module plays that program: `Hub` is its state
(what each port holds and which reading the Pi asked of it, the acknowledgements it owes) and the bytes it
sends; `PtyHub` carries them over a pseudo-terminal whose other end `asp` opens as its serial port. What each
value means (counts in the set-up direction, the power report, 10-bit RGB, reflection, HSV, the colour, the
force sensor, the buttons) is `spike_hub.py`'s, through the `Sensors` the physics side reads, as the native
runtime's values are: one definition for both paths.

The protocol is 0.0.6, the one libraspike-art 28f3f38 (RasPike-ART e1d218c, the 2025 season) expects
(`src/expected_spike_version`). The hub program in ../shared (spike-rt-RasPike-ART 38ed091) is already 0.1.0
(`spike_version`): its status adds `heading`, `is_ready` and `is_statinary` after the button word
(raspike_protocol_com.h 196-198) and it takes two IMU commands (0xb4, 0xb5). A 0.0.6 Pi reads 128 bytes of
status (libraspike-art src/raspike_protocol_com.h 190-199) and would see every port 8 bytes off, so this hub
sends the 0.0.6 layout; everything else is raspike.c's behaviour, cited per line (raspike.c at 38ed091; the
0.0.6 hub program itself is not in ../shared, so its behaviour is taken to be 38ed091's less the IMU additions).

Frames (raspike.c 95-137): `0xEA cmd size port data[size]` both ways. The handshake (858-890): the Pi sends
`0xAE 0xCE`, the hub answers `0xAE 0xCE major minor patch`. An acknowledgement (179-183) is frame 0x02 with two
int32: the command and a result. The status (802-809) is frame 0x01 for port 255, every 10 ms (raspike.cfg
11: APP_NOTIFY_CYC, 10*1000 us), then the acknowledgements a motor reset owes (787-800).
"""

from __future__ import annotations

import os
import select
import struct
import time
from collections import deque
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path

from hakoniwa.physics import spike_hub
from hakoniwa.physics.robot import Wiring
from hakoniwa.physics.robots import HUB_PORTS, SPIKE, Robot
from hakoniwa.physics.sensors import Sensors
from hakoniwa.physics.slots import BATTERY_MA, BATTERY_MV
from hakoniwa.wire import rundir
from hakoniwa.wire.errors import HakoError
from hakoniwa.wire.protocol import NEVER_WAKES, RASPIKE_STATUS_PERIOD_US, RASPIKE_VERSION

INIT, INIT_MAGIC = 0xAE, 0xCE  # raspike_protocol_com.h 7-10: RP_CMD_INIT, RP_CMD_INIT_MAGIC
START = 0xEA  # RP_CMD_START: every frame's first byte
PORT_NONE = 255  # RP_PORT_NONE: the hub itself
PORTS = 6  # RP_MAX_DEVICES: A..F as 0..5 (raspike_protocol_com.h 175-179)
DELIVERY_LIMIT_S = 20.0  # how long asp's counted bytes may take to arrive through qemu and the pty (wall time)

# Command types (the top three bits: raspike_protocol_com.h 12-21) and commands (29-135).
SYS, COLOR, FORCE, MOTOR, ULTRASONIC, HUB = range(6)
ALL_STATUS, ACK, SHUTDOWN = 0x01, 0x02, 0x03
COL_RGB, COL_COL, COL_COL_SUR_OFF, COL_HSV, COL_HSV_SUR_OFF, COL_REF, COL_AMB = range(0x21, 0x28)
COL_LIGHT_SET = 0x28
MOT_STU, MOT_RST, MOT_SPD, MOT_POW, MOT_STP, MOT_STP_BRK, MOT_STP_HLD, MOT_SET_DTY, MOT_RST_DTY = range(0x61, 0x6a)
US_LGT_SET, US_LGT_ON, US_LGT_OFF = 0x83, 0x84, 0x85
COLOR_READINGS = (COL_RGB, COL_COL, COL_COL_SUR_OFF, COL_HSV, COL_HSV_SUR_OFF, COL_REF, COL_AMB)
# What the hub does for the hub commands of 0.0.6 (0xa1..0xb3: display, light, speaker): nothing a program
# reads back, and none is acknowledged (raspike.c 661-757); the bench has no display or speaker.
HUB_COMMANDS = frozenset((0xa1, 0xa2, 0xa3, 0xa4, 0xa5, 0xa6, 0xa7, 0xa8, 0xaa, 0xab, 0xac, 0xb1, 0xb2, 0xb3))
ROBOT_KINDS = {"color": COLOR, "force": FORCE, "ultrasonic": ULTRASONIC}  # robots.py's sensor kinds

# The 0.0.6 status (libraspike-art src/raspike_protocol_com.h 181-199): voltage, current (uint16), acceleration
# and angular velocity (3 float each), the button word (uint32), then per port: port, cmd, 2 pad, 12 data.
STATUS_HEAD = struct.Struct("<HH3f3fI")
PORT_STATUS = struct.Struct("<BB2x12s")
STATUS_SIZE = STATUS_HEAD.size + PORTS * PORT_STATUS.size  # 128
ACK_DATA = struct.Struct("<ii")

class HubFault(HakoError):
    """The program and the hub no longer speak the protocol (a malformed frame, a command the hub would
    assert on, the pty closed): one line, a fault of the run and never of the parameters under test."""


@dataclass
class Port:
    """One port as raspike.c keeps it (RPDevice, 47-52, and the port's status): the device configured there,
    the reading the status carries (`cmd`), the one asked for next (`next_cmd`), a reset whose
    acknowledgement is owed, and the data bytes, which each reading overwrites only as far as it goes."""

    kind: int | None  # what is plugged in (the robot's): MOTOR, COLOR, FORCE, ULTRASONIC or None
    configured: bool = False
    cmd: int = 0
    next_cmd: int = 0
    reset: bool = False
    data: bytes = bytes(12)


@dataclass
class Motor:
    """What the hub's pbio keeps of a motor: the direction it was set up with, the power asked (in the
    program's direction), the zero of its count, and the counts of the last statuses for its speed."""

    direction: int = spike_hub.PBIO_CLOCKWISE
    power: int = 0
    zero: int = 0
    rezero: bool = False  # the count is zeroed at the next status (a reset, or a set-up that resets)
    driven_since_us: int | None = None
    counts: deque[tuple[int, int]] = field(
        default_factory=lambda: deque(maxlen=spike_hub.STALL_TIME_US // RASPIKE_STATUS_PERIOD_US + 1))


_IDLE = Motor()  # a port without a motor, as `Hub.powers` reports it: never changed


def hub_kinds(wiring: Wiring, robot: Robot) -> dict[int, int]:
    """What is plugged into each port of `robot`'s hub: its wheels' motors (on `wiring`'s ports) and its
    sensors."""
    kinds = {wiring.left: MOTOR, wiring.right: MOTOR}
    kinds.update((HUB_PORTS[SPIKE].index(port), ROBOT_KINDS[kind]) for port, kind in robot.sensors)
    return kinds


def frame(cmd: int, port: int, data: bytes = b"") -> bytes:
    """A frame as raspike_send_data sends it (95-109)."""
    return bytes((START, cmd, len(data), port)) + data


class Hub:
    """raspike.c's state and answers, fed the bytes the Pi sends, asked for a status every 10 ms."""

    def __init__(self, kinds: dict[int, int]) -> None:
        """`kinds`: what is plugged into each port (0..5 for A..F) of the robot."""
        self.ports = [Port(kinds.get(p)) for p in range(PORTS)]
        self.motors = {p: Motor() for p, kind in kinds.items() if kind == MOTOR}
        self.shook_hands = False
        self.shut_down = False
        self._pending = bytearray()
        self._powers: tuple[tuple[int, ...], tuple[int, ...]] | None = None  # `powers`, until a command comes

    def feed(self, data: bytes) -> bytes:
        """The hub's answers to what the Pi sent (the handshake's reply, acknowledgements)."""
        self._powers = None  # only a command changes a motor's power or direction
        self._pending += data
        out = bytearray()
        if not self.shook_hands:
            at = self._pending.find(bytes((INIT, INIT_MAGIC)))
            if at < 0:  # raspike.c 858-869 skips anything before 0xAE 0xCE
                del self._pending[:max(len(self._pending) - 1, 0)]
                return b""
            del self._pending[:at + 2]
            self.shook_hands = True
            out += bytes((INIT, INIT_MAGIC, *RASPIKE_VERSION))  # 884-890
        while self._pending:
            if self._pending[0] != START:
                raise HubFault(f"the program sent a malformed frame: byte 0x{self._pending[0]:02x} where a frame "
                               f"starts (0x{START:02x}, raspike.c 117-124)")
            if len(self._pending) < 4 or len(self._pending) < 4 + self._pending[2]:
                break
            cmd, size, port = self._pending[1], self._pending[2], self._pending[3]
            payload = bytes(self._pending[4:4 + size])
            del self._pending[:4 + size]
            out += self._command(cmd, port, payload)
        return bytes(out)

    def _port(self, port: int, cmd: int) -> Port:
        if port >= PORTS:
            raise HubFault(f"the program sent command 0x{cmd:02x} for port {port}, not a hub port (0..5 for A..F)")
        return self.ports[port]

    def _command(self, cmd: int, port: int, data: bytes) -> bytes:
        kind = cmd >> 5
        if kind == SYS:
            if cmd == SHUTDOWN:  # 385-387: hub_system_shutdown
                self.shut_down = True
            return b""
        if kind == HUB:
            if cmd not in HUB_COMMANDS:
                raise HubFault(f"the program sent hub command 0x{cmd:02x}, which protocol 0.0.6 has not")
            return b""
        p = self._port(port, cmd)
        if cmd & 0x1f == 0:  # a device's configuration (400-409 and alike): acknowledged 1 if it is there
            found = p.kind == kind  # (configured twice, the hub's RP_ASSERT shows a number and it goes on)
            p.configured = p.configured or found
            return self._ack(port, cmd, int(found))
        if not p.configured or p.kind != kind:  # raspike.c's RP_ASSERT: the hub shows an error and goes on
            raise HubFault(f"the program sent command 0x{cmd:02x} for port {chr(ord('A') + port)}, "
                           "which it has not configured as that device")
        if kind == COLOR:
            return self._color(p, port, cmd, data)
        if kind == MOTOR:
            return self._motor(p, port, cmd, data)
        if kind == ULTRASONIC and cmd in (US_LGT_SET, US_LGT_ON, US_LGT_OFF):  # 638-657: lights, no ack
            return b""
        raise HubFault(f"the program sent command 0x{cmd:02x} for port {chr(ord('A') + port)}, which raspike.c "
                       "does not take")

    def _ack(self, port: int, cmd: int, result: int) -> bytes:
        return frame(ACK, port, ACK_DATA.pack(cmd, result))

    def _color(self, p: Port, port: int, cmd: int, data: bytes) -> bytes:
        if cmd in COLOR_READINGS:  # 415-428: the next status carries that reading
            if p.cmd != cmd:
                p.next_cmd = cmd
            return b""
        if cmd == COL_LIGHT_SET:  # 429-436: the lights, acknowledged with pbio's result
            return self._ack(port, cmd, 0)
        raise HubFault(f"the program sent colour sensor command 0x{cmd:02x}, which raspike.c does not take")

    def _motor(self, p: Port, port: int, cmd: int, data: bytes) -> bytes:
        motor = self.motors[port]
        if cmd == MOT_STU:  # 502-528: pup_motor_setup(direction, reset), acknowledged 1
            direction, reset = struct.unpack_from("<i?", data.ljust(5, b"\0"))
            motor.direction, p.next_cmd = direction, MOT_STU
            motor.rezero = motor.rezero or reset
            return self._ack(port, cmd, 1)
        if cmd == MOT_RST:  # 529-551: reset at the next status, acknowledged after it (789-800)
            p.reset = motor.rezero = True
            return b""
        if cmd == MOT_POW:  # 562-569: no ack
            motor.power = struct.unpack_from("<i", data.ljust(4, b"\0"))[0]
            return b""
        if cmd in (MOT_STP, MOT_STP_BRK):  # 570-586: stop and brake, acknowledged 1
            motor.power = 0
            return self._ack(port, cmd, 1)
        if cmd in (MOT_SET_DTY, MOT_RST_DTY):  # 595-611: the duty limit, acknowledged
            return self._ack(port, cmd, 0 if cmd == MOT_SET_DTY else 1)
        raise HubFault(f"the program sent motor command 0x{cmd:02x} (pup_motor_set_speed or pup_motor_hold), "
                       "whose regulation the pty hub does not play yet")

    def powers(self, motor_ports: int) -> tuple[tuple[int, ...], tuple[int, ...]]:
        """Each motor port's power (the program's direction) and set-up direction, for the physics side's
        `SensorModel.drive`, ports 0 .. motor_ports - 1."""
        if self._powers is None or len(self._powers[0]) != motor_ports:  # asked twice a stop: kept till a command
            motors = [self.motors.get(p, _IDLE) for p in range(motor_ports)]
            self._powers = tuple(m.power for m in motors), tuple(m.direction for m in motors)
        return self._powers

    def status(self, s: Sensors, now_us: int) -> bytes:
        """The status frame raspike.c's notify task sends (802-809) from the readings `s` at `now_us`, then
        the acknowledgements of motor resets done in it (789-800)."""
        acks = bytearray()
        for port, p in enumerate(self.ports):
            if not p.configured:
                continue
            if p.next_cmd and p.next_cmd != p.cmd:  # 325-330
                p.cmd, p.next_cmd = p.next_cmd, 0
            data = b""
            if p.kind == COLOR:
                data = color_data(p.cmd, s)
            elif p.kind == FORCE:
                force, distance, touched = spike_hub.force_report(s.touch[0])
                data = struct.pack("<ff?", force, distance, touched)
            elif p.kind == ULTRASONIC:  # 299-311: distance only ("calling presence break distance")
                data = struct.pack("<i", s.ultrasonic_mm)
            elif p.kind == MOTOR and p.cmd == MOT_STU:  # 265-297: nothing before the motor is set up
                data = self._motor_data(port, s, now_us)
            p.data = data + p.data[len(data):]  # memcpy over the last reading (205-250)
            if p.reset:  # acknowledged even when the motor was not set up and so not reset (268-269, 789-800)
                acks += self._ack(port, MOT_RST, 1)
                p.reset = self.motors[port].rezero = False
        # The battery is the bench's charged pack, as the native runtime reads RX BATTERY_VOLTAGE / _CURRENT.
        head = STATUS_HEAD.pack(BATTERY_MV, BATTERY_MA,
                                *(s.imu.acceleration_mm_s2 if s.imu else (0.0, 0.0, 0.0)),
                                *(s.imu.angular_velocity_dps if s.imu else (0.0, 0.0, 0.0)),
                                spike_hub.hub_buttons(s.buttons))
        ports = b"".join(PORT_STATUS.pack(i, p.cmd, p.data) for i, p in enumerate(self.ports))
        return frame(ALL_STATUS, PORT_NONE, head + ports) + bytes(acks)

    def _motor_data(self, port: int, s: Sensors, now_us: int) -> bytes:
        motor = self.motors[port]
        raw = s.motor_angles_deg.get(port, 0)  # already in the set-up direction (SensorModel.drive)
        if motor.rezero:
            motor.zero, motor.counts, motor.rezero = raw, deque(maxlen=motor.counts.maxlen), False
        count = raw - motor.zero
        motor.counts.append((now_us, count))
        speed = spike_hub.speed_over(motor.counts, spike_hub.SPEED_WINDOW_US)
        if motor.power == 0:
            motor.driven_since_us = None
        elif motor.driven_since_us is None:
            motor.driven_since_us = now_us
        stalled = spike_hub.stalled(motor.counts, motor.driven_since_us, now_us)
        power = spike_hub.power_report(motor.power, motor.direction)
        return struct.pack("<iih?", count, speed, power, stalled)


def color_data(cmd: int, s: Sensors) -> bytes:
    """A colour sensor port's data for the reading `cmd` (raspike.c 205-250): RGB as three uint16, HSV and the
    colour as pbio_color_hsv_t (uint16 h, uint8 s, uint8 v), reflection and ambient as int32."""
    hub = s.spike
    if cmd == COL_RGB:
        return struct.pack("<3H", *s.rgb)
    if cmd == COL_REF:
        return struct.pack("<i", s.reflect)
    if cmd == COL_AMB:
        return struct.pack("<i", s.ambient)
    if hub is None:
        return bytes(12)
    hsv = {COL_HSV: hub.hsv, COL_HSV_SUR_OFF: hub.ambient_hsv, COL_COL: hub.color,
           COL_COL_SUR_OFF: spike_hub.color(hub.ambient_hsv)}.get(cmd)
    return bytes(12) if hsv is None else struct.pack("<HBB", *hsv)


class PtyHub:
    """A `Hub` on a pseudo-terminal: `device` is the path a program opens as its serial port; `pump` moves
    what is waiting both ways and sends a status when one is due."""

    def __init__(self, hub: Hub) -> None:
        import pty
        import tty

        self.hub = hub
        self.master, slave = pty.openpty()
        self._slave: int | None = slave
        tty.setraw(slave)  # bytes as they are, no echo (the Pi's own tcsetattr makes it raw too)
        os.set_blocking(self.master, False)
        self.device = os.ttyname(slave)
        self._next_status_us = 0
        self.received = 0  # bytes of the program's taken in
        self.sent = 0  # bytes the hub wrote

    def close(self) -> None:
        for fd in (self.master, self._slave):
            if fd is not None:
                os.close(fd)
        self._slave = None

    def pump(self, read: Callable[[], Sensors] | None, now_us: int) -> None:
        """Answer what the program sent; at each multiple of 10 ms after the handshake, send a status of the
        readings `read()` takes then (raspike.c starts its notify cycle once the handshake is done, 905)."""
        try:
            while True:
                data = os.read(self.master, 4096)
                if not data:
                    break
                self._take(data)
        except BlockingIOError:
            pass
        except OSError as e:  # EIO: every copy of the program's end is closed
            raise HubFault(f"the program's serial port closed ({e.strerror})") from None
        self._after(read, now_us)

    def exchange(self, read: Callable[[], Sensors] | None, now_us: int, program_sent: int) -> int:
        """`pump` in the lockstep, between two steps: read exactly the bytes the program says it sent so far
        (`program_sent`, asp_serial.c's count), answer them, send the status when due; the count of bytes the
        hub has sent, which the program waits for before its tasks run at the step."""
        deadline = time.monotonic() + DELIVERY_LIMIT_S
        while self.received < program_sent:
            if not select.select([self.master], [], [], max(0.0, deadline - time.monotonic()))[0]:
                raise HubFault(f"asp's bytes did not reach the hub in {DELIVERY_LIMIT_S:.0f} s")
            try:
                self._take(os.read(self.master, program_sent - self.received))
            except BlockingIOError:
                continue
            except OSError as e:
                raise HubFault(f"the program's serial port closed ({e.strerror})") from None
        self._after(read, now_us)
        return self.sent

    @property
    def next_status_us(self) -> int:
        """When the hub sends its next status: at the first snapshot after the handshake, then every 10 ms."""
        return self._next_status_us if self.hub.shook_hands else NEVER_WAKES

    def _take(self, data: bytes) -> None:
        self.received += len(data)
        self._write(self.hub.feed(data))

    def _after(self, read: Callable[[], Sensors] | None, now_us: int) -> None:
        if self.hub.shook_hands and self._slave is not None:  # the program has its end open: ours may go, so
            os.close(self._slave)  # that its closing reads as EIO here
            self._slave = None
        if self.hub.shook_hands and read is not None and now_us >= self._next_status_us:
            self._write(self.hub.status(read(), now_us))
            self._next_status_us = (now_us // RASPIKE_STATUS_PERIOD_US + 1) * RASPIKE_STATUS_PERIOD_US

    def _write(self, data: bytes) -> None:
        self.sent += len(data)
        while data:
            try:
                data = data[os.write(self.master, data):]
            except BlockingIOError:
                select.select([], [self.master], [], 1.0)


class SerialCounts:
    """The run's count of what each side of asp's serial port sent (rundir.RASPIKE_SERIAL), which the hub and
    asp's clock library (asp_serial.c) share: the program publishes its count with each answer, the hub its
    count before the next unity time."""

    def __init__(self, run_dir: Path) -> None:
        import mmap

        path = run_dir / rundir.RASPIKE_SERIAL
        path.write_bytes(bytes(rundir.RASPIKE_SERIAL_SIZE))
        with path.open("r+b") as f:
            self._map = mmap.mmap(f.fileno(), rundir.RASPIKE_SERIAL_SIZE)

    @property
    def program_sent(self) -> int:
        return int(struct.unpack_from("<Q", self._map, rundir.RASPIKE_PROGRAM_SENT)[0])

    def publish(self, hub_sent: int, next_status_us: int) -> None:
        """The hub's count, and when it sends its next status: asp's clock library moves the bench no further
        than that while a thread of asp's waits for what the hub brings (asp_threads.c)."""
        struct.pack_into("<q", self._map, rundir.RASPIKE_HUB_NEXT_STATUS, next_status_us)
        struct.pack_into("<Q", self._map, rundir.RASPIKE_HUB_SENT, hub_sent)

    def close(self) -> None:
        self._map.close()

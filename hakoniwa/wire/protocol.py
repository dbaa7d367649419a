"""The Hakoniwa wire layout shared by the physics process, every Athrill and the test controller.

This module is the only place that knows a byte offset; the C runtime's header is generated from it
(`c_header()`), and tests pin it byte for byte against the real layout read from the TOPPERS code
(EV3RT's athrill drivers and Athrill's VDEV device): each file is 8 KiB, a 32-byte header followed by the
body; the body of `unity_mmap.bin` (RX: physics -> Athrill) is Athrill's guest memory at 0x090F0000 and the
body of `athrill_mmap.bin` (TX: Athrill -> physics) is at 0x090F1000. All integers are little-endian.

Offsets in `Rx` and `Tx` are *body* offsets; the file offset is body offset + HEADER_SIZE. The fields our
own lockstep and our test reports need live in body bytes the real layout leaves unused (`Rx.TEST_SEQ`..,
`Tx.NEXT_WAKE`..) and below ET Robocon's extension (body 480..511 of both files); a real Athrill and a real
EV3RT program never look there.

Only the standard library is imported here: the mock Athrill is started once per test, and its start-up
time is part of every test.
"""

from __future__ import annotations

import ctypes
import enum
import mmap
import os
import struct
from pathlib import Path

from hakoniwa.wire.errors import HakoError
from hakoniwa.wire.exits import EXIT_BENCH_FAULT
from hakoniwa.wire.processes import BENCH_FAULT_MARKER

FILE_SIZE = 8192
HEADER_SIZE = 32
PACKET_SIZE = 1024  # the part of each body a real Unity and Athrill exchange
WINDOW_SIZE = 0x1000  # each body's guest window; reads past the packet still see the file
LAYOUT_VERSION = 1
EXT_OFF = 512  # header fields ext_off / ext_size: the paper's automation area, body 512..1023
EXT_SIZE = 512

UNITY_FILE = "unity_mmap.bin"
ATHRILL_FILE = "athrill_mmap.bin"
UNITY_MAGIC = b"ETRX"
ATHRILL_MAGIC = b"ETTX"

RX_GUEST_BASE = 0x090F0000  # unity_mmap.bin's body in Athrill's guest memory (EV3RT's VDEV base)
TX_GUEST_BASE = RX_GUEST_BASE + WINDOW_SIZE  # athrill_mmap.bin's body


class Header:
    """File offsets in the 32-byte header of both files."""

    MAGIC = 0  # 4 bytes, ETRX / ETTX
    VERSION = 4  # u32 = 1
    ATHRILL_TIME = 8  # u64 [us], TX only: Athrill's ("micon") simulation time
    SNAPSHOT_END = 8  # u64 [us], RX only (reserved in the real layout): the instant up to which the snapshot
    # holds, physics' time + one step; a patched athrill2 in the repeatable mode stops at a load or store of the
    # files at or past it (scripts/athrill-patches/01-*)
    UNITY_TIME = 16  # u64 [us]: the physics side's simulation time (in TX: Athrill's echo of it)
    EXT_OFF = 24  # u32 = 512
    EXT_SIZE = 28  # u32 = 512


_HEADER = struct.Struct("<4sI8xQII")  # magic, version, (athrill time), unity time, ext_off, ext_size
assert _HEADER.size == HEADER_SIZE


class Rx:
    """Body offsets in `unity_mmap.bin`: sensors written by the physics side, as EV3RT's drivers read them
    (each an i32 slot, of which EV3RT reads the low 8 or 16 bits where noted)."""

    BUTTONS = 0  # bitmask: LEFT 0, RIGHT 1, UP 2, DOWN 3, ENTER 4, BACK 5
    COLOR0_AMBIENT = 4  # 0..100, low byte read
    COLOR0_COLOR = 8  # colorid_t (ColorId), low byte read
    COLOR0_REFLECT = 12  # 0..100, low byte read
    COLOR0_RGB = 16  # r, g, b at 16, 20, 24; 16 bits read
    GYRO_ANGLE = 28  # degrees, clockwise positive seen from above; 16 bits read
    GYRO_RATE = 32  # degrees/s; 16 bits read
    ULTRASONIC_MM = 88  # distance ahead in mm (EV3RT returns it / 10, in cm); 16 bits read
    ULTRASONIC_LISTEN = 92  # another ultrasonic sensor heard (nonzero); EV3RT reads the whole word. 0 here
    TOUCH0 = 112  # 0 released / 4095 pressed (EV3RT: pressed when > 2048)
    BATTERY_CURRENT = 116  # mA, i32 (ev3_vdev_common.h EV3_BATTERY_INX_CURRENT 28); Unity leaves it 0
    BATTERY_VOLTAGE = 120  # mV, i32 (EV3_BATTERY_INX_VOLTAGE 29)
    TOUCH1 = 124
    COLOR1_AMBIENT = 128  # a second colour sensor: ambient, colour id, reflect, then r, g, b at 140..148
    COLOR1_COLOR = 132
    COLOR1_REFLECT = 136
    COLOR1_RGB = 140
    MOTOR_ANGLE = 256  # + 4 p: encoder of motor port p (A = 0 .. D = 3) [deg], i32
    # ET Robocon's SPIKE SDK (raspike-athrill-v850e2m: ev3_vdev_common.h, read by spikeapi's raspike_hub.c and
    # raspike_color.c), written only for a robot with a SPIKE hub.
    SPIKE_IMU = 272  # the hub IMU: six f32 words, acceleration then angular velocity
    SPIKE_IMU_ACCEL_X = SPIKE_IMU  # f32 bits [mm/s^2]: hub_imu_get_acceleration() x, y, z at 272, 276, 280
    SPIKE_IMU_ACCEL_Y = 276
    SPIKE_IMU_ACCEL_Z = 280
    SPIKE_IMU_ANGVEL_X = SPIKE_IMU + 12  # f32 bits [deg/s]: hub_imu_get_angular_velocity() x, y, z at 284, 288, 292
    SPIKE_IMU_ANGVEL_Y = 288
    SPIKE_IMU_ANGVEL_Z = 292
    SPIKE_HSV = 296  # the colour sensor's HSV: three i32 words
    SPIKE_HSV_H = SPIKE_HSV  # i32, 0..359 [deg]: pup_color_sensor_hsv() h, s, v at 296, 300, 304
    SPIKE_HSV_S = 300  # i32, 0..100 [%]
    SPIKE_HSV_V = 304  # i32, 0..100 [%]
    # Our extension for the native SPIKE runtime (the SDK never reads it): what SPIKE-RT on the hub answers
    # that the SDK's slots do not carry (hakoniwa/physics/spike_hub.py), as the hub's status carries it.
    SPIKE_SHSV = 308  # i32 h, s, v at 308, 312, 316: pup_color_sensor_hsv(surface = false)
    SPIKE_COLOR = 320  # i32 h, s, v at 320, 324, 328: pup_color_sensor_color(), the detectable colour
    SPIKE_MOTOR_POWER = 332  # + 4 p: pup_motor_get_power() of motor port p (A = 0 .. D = 3) on the hub, i32
    # Our extension (unused by the real layout): the lockstep's words. A test's result is no slot: the physics
    # process sends it whole (`hakoniwa.wire.result.TestResult.encode`, the run directory's result.json).
    BUTTONS_UNTIL = 416  # u64 [us]: the buttons hold their value until then (the scenario's next press or release;
    # NEVER_WAKES: none); a patched athrill2 reads them before then without stopping (scripts/athrill-patches/01-*)
    TEST_SEQ = 448  # u32: the test in progress; a pre-launched Athrill waits for its own number
    PHYSICS_PID = 452  # u32: so an orphaned Athrill can notice the physics process is gone
    NOISE_SEED = 440  # u32, written by the controller before start: the seed of this test's noise draw
    NOISE_SCALE = 444  # f32, written by the controller: 0 = no noise, 1 = the course's noise levels
    # ET Robocon's simulator extension (its etroboc_ext.h reads them), written by the physics side from the
    # course: body 480..511 of both files is ET Robocon's, so ours stays below it.
    COURSE_CARD_NUMBER = 480  # u32, ETROBOC_COURSE_INFO_CARD_NUMBER
    COURSE_BLOCK_NUMBER = 484  # u32, ETROBOC_COURSE_INFO_BLOCK_NUMBER
    COURSE_BLOCK_POS = 488  # u8 each, ETROBOC_COURSE_INFO_BLOCK_POS_BLACK1 .. _GREEN2
    # The paper's test automation (Table 1), in the ext area.
    EVENT = 528  # i32, Event
    GOAL_TIME_HI = 532  # u32, goal time [us], upper 32 bits
    GOAL_TIME_LO = 536  # u32, goal time [us], lower 32 bits
    PARAMS = 540  # f32 control parameters, up to the end of the packet
    KP = 540
    KI = 544
    KD = 548
    MOTOR_POWER = 552


class Tx:
    """Body offsets in `athrill_mmap.bin`: actuators written by Athrill (the controller writes the flags)."""

    LED = 0  # bits: RED 0, GREEN 1 (ORANGE = both), YELLOW 2, BLUE 3
    MOTOR_POWER = 4  # + 4 p: power of motor port p, -100..100, i32
    MOTOR_BRAKE = 20  # + 4 p: 1 = brake when the power is 0, 0 = float
    MOTOR_RESET_ANGLE = 36  # + 4 p (A..D: motor_dri.c's motor_clr_angle writes 36 + 4 p, D at 48): 1 = reset the
    # encoder; the physics side clears it again
    GYRO_RESET = 52  # 1 = reset the gyro angle; the physics side clears it again
    # Our extension (the SDK never writes it): the native SPIKE runtime's pup_motor_setup direction.
    SPIKE_DIRECTION = 56  # + 4 p: pbio_direction_t of motor port p (0 clockwise, 1 counter-clockwise), which
    # the physics side, as the hub, applies to the power and the count
    # Our extension (unused by the real layout): lockstep.
    NEXT_WAKE = 448  # i64: the simulation time [us] the robot program sleeps until (NEVER_WAKES: it ended)
    ANSWER_SEQ = 456  # u32: bumped last whenever Athrill publishes its outputs
    ATHRILL_PID = 460  # u32: the mock's pid (the real Athrill does not write it)
    # Our extension: the repeatable mode.
    STOPPED_AT = 464  # u64: the clock [us] at which the patched athrill2 last stopped to wait for physics
    # ET Robocon's simulator extension.
    COMPLETED = 480  # i32: ETRoboc_notifyCompletedToSimulator() writes 1, which ends the test (COMPLETED)
    # The paper's test automation (Table 2), in the ext area.
    START = 512  # i32, start flag
    END = 516  # i32, end flag


ETROBOC_EXT = (480, 512)  # body bytes of both files that ET Robocon's extension owns
COURSE_BLOCK_POSITIONS = 10  # BLACK1, BLACK2, RED1, RED2, YELLOW1, YELLOW2, BLUE1, BLUE2, GREEN1, GREEN2
MOTOR_PORTS = 4
# RasPike-ART's protocol the hub the physics side plays speaks (hakoniwa/physics/raspike_hub.py): what
# libraspike-art 28f3f38, the 2025 season's, expects (its src/expected_spike_version). asp built against another
# stops at the handshake, so `hako build --raspike-art` checks it first.
RASPIKE_VERSION = (0, 0, 6)
RASPIKE_STATUS_PERIOD_US = 10_000  # raspike.cfg 11: the hub sends the status of every port every 10 ms
PARAM_END = PACKET_SIZE
NEVER_WAKES = (1 << 63) - 1
TOUCH_PRESSED = 4095
# A pressed SPIKE force sensor in RX TOUCH0, where ET Robocon's SDK reads it (raspike_forcesensor.c): its
# pup_force_sensor_force() is the slot's value as a float in newtons, touched() is the slot > 0. The SPIKE
# force sensor measures up to 10 N, so a press reads as a full press.
FORCE_PRESSED_N = 10


class Event(enum.IntEnum):
    """Event state at RX 528 (paper Table 3, plus CRASH for an Athrill that dies or goes silent, COMPLETED for
    a program that said it is done, ET Robocon's `ETRoboc_notifyCompletedToSimulator()`, FINISH for ET
    Robocon's finish: the robot stopped in the garage for 3 s, and COURSE_OUT for what ET Robocon's teams
    call コースアウト, course-out: the robot left the course, past the mat's edge or into an area the course
    marks out of bounds; `Course.left_at`)."""

    NONE = 0
    GOAL = 1
    TIME_OVER = 2
    HIT_WALL = 3
    CRASH = 4
    COMPLETED = 5
    FINISH = 6
    COURSE_OUT = 7


class CrashKind(enum.IntEnum):
    """Why a test ended as CRASH. Only PROGRAM and SILENT can be the robot program's (and so the
    parameters') doing; BENCH is the bench's own fault and is never scored."""

    NONE = 0
    PROGRAM = 1  # the Athrill process died: the program crashed (a signal, an exception, a bad access)
    SILENT = 2  # it stopped advancing simulation time for longer than the Athrill timeout
    PROTOCOL = 3  # it broke the time protocol (woke in the past, drifted beyond the allowed difference)
    BENCH = 4  # it could not start or could not use the mapped files


class BenchCause(enum.IntEnum):
    """What spoiled a test that is the bench's fault (a CRASH of kind BENCH), the result's `bench_cause`: what a
    campaign tells the user its reruns were for. The physics side writes the Athrill and file causes; the
    controller's side adds the physics process's own end, which the physics side cannot report."""

    NONE = 0  # no bench fault (or a journal from before causes were recorded)
    ATHRILL_STALLED = 1  # Athrill was stopped (SIGSTOP) or got no CPU: a stall of the machine
    ATHRILL_FAILED = 2  # Athrill could not start, or could not use the mapped files, and said so
    FILE_DAMAGED = 3  # a mapped file was truncated or overwritten under the bench
    PHYSICS_KILLED = 4  # the physics process died mid-test
    TIME_STALLED = 5  # simulated time stopped (the emulator's clock), or crept past the test's wall-clock ceiling
    ATHRILL_KILLED = 6  # Athrill killed by SIGKILL: by the machine (the OOM killer) or a person, not by its program
    HUB_FAILED = 7  # the serial link to the hub the physics side plays failed (RasPike-ART's asp: docs/REAL-ATHRILL.md)

    @property
    def words(self) -> str:
        return {BenchCause.NONE: "unknown cause", BenchCause.ATHRILL_STALLED: "athrill stalled",
                BenchCause.ATHRILL_FAILED: "athrill could not run", BenchCause.FILE_DAMAGED: "mapped file damaged",
                BenchCause.PHYSICS_KILLED: "physics process killed",
                BenchCause.TIME_STALLED: "simulated time stalled",
                BenchCause.ATHRILL_KILLED: "athrill killed", BenchCause.HUB_FAILED: "hub link failed"}[self]


class SyncMode(enum.IntEnum):
    """How physics and Athrill keep time; chosen by the kind of program that runs."""

    LOCKSTEP = 0  # ours: the program's wake-ups drive physics; deterministic to the microsecond
    HAKONIWA = 1  # the real protocol: physics runs at most ALLOWED_TIME_DIFF ahead of Athrill's clock
    REPEATABLE = 2  # the real emulator, patched to wait at each sync point: deterministic to the microsecond


class LedBit(enum.IntFlag):
    """The bits of the TX LED byte (ev3_vdev_common.h, EV3_GPIO_LED_BITS_*): EV3RT sets RED and GREEN, ET
    Robocon's SPIKE SDK any one of the four (`hub_light_on_color`)."""

    RED = 1
    GREEN = 2
    YELLOW = 4
    BLUE = 8


class ColorId(enum.IntEnum):
    """EV3RT's colorid_t."""

    NONE = 0
    BLACK = 1
    BLUE = 2
    GREEN = 3
    YELLOW = 4
    RED = 5
    WHITE = 6
    BROWN = 7




MAX_NOISE_SCALE = 100.0  # the largest Rx.NOISE_SCALE a controller writes: far beyond any use, finite in f32


def guest_to_body(addr: int) -> tuple[str, int]:
    """Map an Athrill guest address to (file name, body offset); ValueError outside both windows."""
    for base, name in ((RX_GUEST_BASE, UNITY_FILE), (TX_GUEST_BASE, ATHRILL_FILE)):
        if base <= addr < base + WINDOW_SIZE:
            return name, addr - base
    raise ValueError(f"guest address 0x{addr:08X} is outside the mapped windows "
                     f"0x{RX_GUEST_BASE:08X}..0x{TX_GUEST_BASE + WINDOW_SIZE - 1:08X}")


class LayoutError(HakoError, RuntimeError):
    """A mapped file is not what the layout says it should be."""


def check_file(path: Path, magic: bytes) -> None:
    """Raise LayoutError unless `path` is a whole, well-formed file of its kind. Reads it with plain file
    I/O, so it is safe on a file that someone truncated under a mapping."""
    try:
        with open(path, "rb") as f:
            size = os.fstat(f.fileno()).st_size
            head = f.read(8)
    except FileNotFoundError:
        raise LayoutError(f"{path}: no such file (is the physics process running?)") from None
    if size != FILE_SIZE:
        raise LayoutError(f"{path}: size {size} bytes, expected {FILE_SIZE}")
    got_magic, version = struct.unpack("<4sI", head)
    if got_magic != magic:
        raise LayoutError(f"{path}: magic {got_magic!r}, expected {magic!r}")
    if version != LAYOUT_VERSION:
        raise LayoutError(f"{path}: layout version {version}, expected {LAYOUT_VERSION}")


def _fresh_header(magic: bytes) -> bytes:
    return _HEADER.pack(magic, LAYOUT_VERSION, 0, EXT_OFF, EXT_SIZE)


class LayoutFile:
    """Typed access to one protocol file's header times and body, by the layout's offsets; how the bytes are
    reached is the subclass's (`_unpack`, `_pack`, `_read`, `_write`, at file offsets)."""

    path: Path

    def _unpack(self, fmt: str, offset: int) -> tuple:
        raise NotImplementedError

    def _pack(self, fmt: str, offset: int, *values: int | float) -> None:
        raise NotImplementedError

    def _read(self, offset: int, size: int) -> bytes:
        raise NotImplementedError

    def _write(self, offset: int, data: bytes) -> None:
        raise NotImplementedError

    def close(self) -> None:
        raise NotImplementedError

    def __enter__(self):
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()

    # Header times.
    @property
    def unity_time_us(self) -> int:
        return self._unpack("<Q", Header.UNITY_TIME)[0]

    @unity_time_us.setter
    def unity_time_us(self, value: int) -> None:
        self._pack("<Q", Header.UNITY_TIME, value)

    @property
    def snapshot_end_us(self) -> int:
        return self._unpack("<Q", Header.SNAPSHOT_END)[0]

    @snapshot_end_us.setter
    def snapshot_end_us(self, value: int) -> None:
        self._pack("<Q", Header.SNAPSHOT_END, value)

    @property
    def athrill_time_us(self) -> int:
        return self._unpack("<Q", Header.ATHRILL_TIME)[0]

    @athrill_time_us.setter
    def athrill_time_us(self, value: int) -> None:
        self._pack("<Q", Header.ATHRILL_TIME, value)

    # Body, by body offset.
    def _at(self, offset: int, size: int) -> int:
        if not 0 <= offset <= WINDOW_SIZE - size:
            raise LayoutError(f"body offset {offset} (+{size}) is outside the {WINDOW_SIZE}-byte window")
        return HEADER_SIZE + offset

    def read(self, fmt: str, offset: int) -> int | float:
        """One little-endian value of struct format `fmt` ('i', 'I', 'q', 'f', 'h', 'B', ...)."""
        return self._unpack("<" + fmt, self._at(offset, struct.calcsize(fmt)))[0]

    def write(self, fmt: str, offset: int, value: int | float) -> None:
        self._pack("<" + fmt, self._at(offset, struct.calcsize(fmt)), value)

    def read_i32(self, offset: int) -> int:
        return self._unpack("<i", self._at(offset, 4))[0]

    def write_i32(self, offset: int, value: int) -> None:
        self._pack("<i", self._at(offset, 4), value)

    def read_u32(self, offset: int) -> int:
        return self._unpack("<I", self._at(offset, 4))[0]

    def write_u32(self, offset: int, value: int) -> None:
        self._pack("<I", self._at(offset, 4), value)

    def read_f32(self, offset: int) -> float:
        return self._unpack("<f", self._at(offset, 4))[0]

    def write_f32(self, offset: int, value: float) -> None:
        self._pack("<f", self._at(offset, 4), value)

    def read_i32s(self, offset: int, count: int) -> tuple[int, ...]:
        return self._unpack(f"<{count}i", self._at(offset, 4 * count))

    def write_i32s(self, offset: int, values: tuple[int, ...] | list[int]) -> None:
        self._pack(f"<{len(values)}i", self._at(offset, 4 * len(values)), *values)

    def clear(self, start: int, end: int) -> None:
        self._write(self._at(start, end - start), bytes(end - start))

    def read_bytes(self, offset: int, size: int) -> bytes:
        return self._read(self._at(offset, size), size)

    def write_bytes(self, offset: int, data: bytes) -> None:
        self._write(self._at(offset, len(data)), data)


class MappedFile(LayoutFile):
    """One memory-mapped protocol file: how the physics side and Athrill share it. A mapping of a file that
    someone truncates kills whoever touches the lost pages (SIGBUS); the physics side owns the files and
    repairs them, and the controller reads them with `PolledFile`, which survives it."""

    def __init__(self, path: Path, magic: bytes, *, create: bool = False) -> None:
        self.path = Path(path)
        self.magic = magic
        if create:
            tmp = self.path.with_name(self.path.name + ".tmp")
            tmp.write_bytes(_fresh_header(magic) + bytes(FILE_SIZE - HEADER_SIZE))
            tmp.replace(self.path)
        check_file(self.path, magic)
        fd = os.open(self.path, os.O_RDWR)
        try:
            self._mm = mmap.mmap(fd, FILE_SIZE)
        finally:
            os.close(fd)
        self._view: ctypes.c_char | None = None  # pins the mapping's address while we hand it out

    def close(self) -> None:
        self._view = None
        self._mm.close()

    def address(self, file_offset: int) -> int:
        """The memory address of a byte of the mapping: a futex on a word of it is a doorbell between
        processes (`hakoniwa.wire.waiting`)."""
        if self._view is None:
            self._view = ctypes.c_char.from_buffer(self._mm)
        return ctypes.addressof(self._view) + file_offset

    def damage(self) -> str | None:
        """What is wrong with the file (size, magic, version), or None: read with plain file I/O, so that
        looking is safe after a truncation."""
        try:
            check_file(self.path, self.magic)
        except LayoutError as e:
            return str(e)
        return None

    def repair(self) -> str | None:
        """Make the file whole again if someone damaged it (the physics side owns it): restore its size and
        header. Returns what was wrong, or None if nothing was."""
        problem = self.damage()
        if problem is None:
            return None
        with open(self.path, "r+b") as f:
            if os.fstat(f.fileno()).st_size != FILE_SIZE:
                f.truncate(FILE_SIZE)
        self._mm[:HEADER_SIZE] = _fresh_header(self.magic)
        return problem

    def _unpack(self, fmt: str, offset: int) -> tuple:
        return struct.unpack_from(fmt, self._mm, offset)

    def _pack(self, fmt: str, offset: int, *values: int | float) -> None:
        struct.pack_into(fmt, self._mm, offset, *values)

    def _read(self, offset: int, size: int) -> bytes:
        return self._mm[offset:offset + size]

    def _write(self, offset: int, data: bytes) -> None:
        self._mm[offset:offset + len(data)] = data

    def file_bytes(self, size: int) -> bytes:
        """The file's first `size` bytes, header included: what a UDP packet carries (`hakoniwa.wire.packets`)."""
        return self._mm[:size]


class PolledFile(LayoutFile):
    """A protocol file read and written with pread / pwrite: the controller's view, which polls a few words
    and so needs no mapping. Someone truncating the file cannot kill the controller with SIGBUS, as it would
    through a mapping (the physics process may die of it; the controller then reports a spoiled test);
    bytes beyond a truncated end read as zeros, as they would in the mapping's last page."""

    def __init__(self, path: Path, magic: bytes) -> None:
        self.path = Path(path)
        check_file(self.path, magic)
        self._fd: int | None = os.open(self.path, os.O_RDWR)

    def close(self) -> None:
        if self._fd is not None:
            os.close(self._fd)
            self._fd = None

    def _unpack(self, fmt: str, offset: int) -> tuple:
        return struct.unpack(fmt, self._read(offset, struct.calcsize(fmt)))

    def _pack(self, fmt: str, offset: int, *values: int | float) -> None:
        self._write(offset, struct.pack(fmt, *values))

    def _read(self, offset: int, size: int) -> bytes:
        assert self._fd is not None
        return os.pread(self._fd, size, offset).ljust(size, b"\0")

    def _write(self, offset: int, data: bytes) -> None:
        assert self._fd is not None
        os.pwrite(self._fd, data, offset)


def open_unity(run_dir: Path, *, create: bool = False) -> MappedFile:
    return MappedFile(Path(run_dir) / UNITY_FILE, UNITY_MAGIC, create=create)


def open_athrill(run_dir: Path, *, create: bool = False) -> MappedFile:
    return MappedFile(Path(run_dir) / ATHRILL_FILE, ATHRILL_MAGIC, create=create)


def poll_unity(run_dir: Path) -> PolledFile:
    return PolledFile(Path(run_dir) / UNITY_FILE, UNITY_MAGIC)


def poll_athrill(run_dir: Path) -> PolledFile:
    return PolledFile(Path(run_dir) / ATHRILL_FILE, ATHRILL_MAGIC)


def goal_time_words(goal_time_us: int) -> tuple[int, int]:
    """Split a goal time into the (upper, lower) 32-bit words of Table 1."""
    return (goal_time_us >> 32) & 0xFFFFFFFF, goal_time_us & 0xFFFFFFFF


def c_header() -> str:
    """The layout as C #defines, for the native runtime: generated, so it cannot disagree with this file."""
    lines = ["/* Generated from hakoniwa/wire/protocol.py by c_header(); do not edit. */",
             "#ifndef HAKO_LAYOUT_H", "#define HAKO_LAYOUT_H"]
    scalars = {"FILE_SIZE": FILE_SIZE, "HEADER_SIZE": HEADER_SIZE, "PACKET_SIZE": PACKET_SIZE,
               "WINDOW_SIZE": WINDOW_SIZE, "LAYOUT_VERSION": LAYOUT_VERSION, "EXT_OFF": EXT_OFF,
               "EXT_SIZE": EXT_SIZE, "RX_GUEST_BASE": RX_GUEST_BASE, "TX_GUEST_BASE": TX_GUEST_BASE,
               "MOTOR_PORTS": MOTOR_PORTS, "TOUCH_PRESSED": TOUCH_PRESSED, "FORCE_PRESSED_N": FORCE_PRESSED_N,
               "EXIT_BENCH_FAULT": EXIT_BENCH_FAULT,
               "COURSE_BLOCK_POSITIONS": COURSE_BLOCK_POSITIONS}
    lines += [f"#define HAKO_{k} 0x{v:X}u" for k, v in scalars.items()]
    lines.append("#define HAKO_NEVER_WAKES 0x7FFFFFFFFFFFFFFFll")
    lines += [f'#define HAKO_{name}_FILE "{f}"' for name, f in (("UNITY", UNITY_FILE), ("ATHRILL", ATHRILL_FILE))]
    lines.append(f'#define HAKO_BENCH_FAULT_MARKER "{BENCH_FAULT_MARKER}"')
    lines += [f'#define HAKO_{name}_MAGIC "{m.decode()}"' for name, m in (("UNITY", UNITY_MAGIC),
                                                                          ("ATHRILL", ATHRILL_MAGIC))]
    for prefix, cls in (("HDR", Header), ("RX", Rx), ("TX", Tx)):
        lines += [f"#define HAKO_{prefix}_{k} {v}" for k, v in vars(cls).items() if isinstance(v, int)]
    for prefix, enum_cls in (("EVENT", Event), ("CRASH", CrashKind), ("SYNC", SyncMode), ("COLOR", ColorId),
                             ("LED", LedBit)):
        lines += [f"#define HAKO_{prefix}_{m.name} {m.value}" for m in enum_cls]
    lines.append("#endif")
    return "\n".join(lines) + "\n"

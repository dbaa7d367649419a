"""The binary layout shared by the physics process, Athrill and the test controller.

This module is the only place that knows a byte offset. Every file is a 32-byte header followed by a
1024-byte data area; offsets below are *data* offsets, as in the paper's tables, and the file offset is
data offset + HEADER_SIZE (the paper's "base offset 32"). All integers are little-endian.

Only the standard library is imported here: the Athrill process is started once per test, and its start-up
time is part of every trial.
"""

from __future__ import annotations

import enum
import mmap
import os
import struct
from pathlib import Path

LAYOUT_VERSION = 1
HEADER_SIZE = 32
DATA_SIZE = 1024
FILE_SIZE = HEADER_SIZE + DATA_SIZE

UNITY_FILE = "unity_mmap.bin"
ATHRILL_FILE = "athrill_mmap.bin"
UNITY_MAGIC = b"HKUN"
ATHRILL_MAGIC = b"HKAT"

# Header: magic, layout version, writer's simulation time [us], sequence counter, writer pid, reserved.
_HEADER = struct.Struct("<4sIqII8x")
assert _HEADER.size == HEADER_SIZE
_HDR_TIME = 8
_HDR_SEQ = 16
_HDR_PID = 20

# Guest addresses of the data areas in Athrill's virtual memory.
UNITY_GUEST_BASE = 0x090F0000
ATHRILL_GUEST_BASE = 0x09100000


class Event(enum.IntEnum):
    """Event state at unity data offset 528 (paper Table 3, plus CRASH for a dead or silent Athrill)."""

    NONE = 0
    GOAL = 1
    TIME_OVER = 2
    HIT_WALL = 3
    CRASH = 4


class Unity:
    """Data offsets in `unity_mmap.bin` (physics -> Athrill; the controller writes the parameter area)."""

    # Sensors, published at each Athrill wake-up.
    COLOR_REFLECT = 0  # i32, 0..100
    COLOR_AMBIENT = 4  # i32, 0..100
    COLOR_RGB = 8  # 3 x i32 (r, g, b), 0..255
    ULTRASONIC_CM = 20  # i32, distance ahead in cm, 255 when nothing is in range
    GYRO_ANGLE = 24  # i32, degrees, positive clockwise seen from above (EV3 convention)
    GYRO_RATE = 28  # i32, degrees/s
    TOUCH = 32  # i32, 0/1
    MOTOR_COUNTS = 36  # 4 x i32, encoder degrees for ports A..D
    SNAPSHOT_TIME = 56  # i64, simulation time [us] the sensor values above belong to
    TEST_SEQ = 64  # i32, number of the test in progress; a waiting Athrill starts when it sees its own
    # Test automation (paper Table 1).
    EVENT = 528  # i32, Event
    GOAL_TIME_HI = 532  # u32, goal time [us], upper 32 bits
    GOAL_TIME_LO = 536  # u32, goal time [us], lower 32 bits
    PARAMS = 540  # 121 x f32 control parameters, up to the end of the data area
    KP = 540
    KI = 544
    KD = 548
    MOTOR_POWER = 552


class Athrill:
    """Data offsets in `athrill_mmap.bin` (Athrill -> physics; the controller writes the flags)."""

    MOTOR_POWER = 0  # 4 x i32, -100..100, ports A..D
    LED = 16  # i32, LED colour code
    NEXT_WAKE = 24  # i64, the simulation time [us] Athrill sleeps until (valid with the header time)
    START = 512  # i32, start flag (paper Table 2)
    END = 516  # i32, end flag


NEVER_WAKES = (1 << 63) - 1  # NEXT_WAKE of a robot task that has returned: no wake-up is ever due
PARAM_END = DATA_SIZE


def guest_to_data_offset(addr: int) -> tuple[str, int]:
    """Map an Athrill guest address to (file name, data offset); raise ValueError outside both areas."""
    for base, name in ((UNITY_GUEST_BASE, UNITY_FILE), (ATHRILL_GUEST_BASE, ATHRILL_FILE)):
        if base <= addr < base + DATA_SIZE:
            return name, addr - base
    raise ValueError(f"guest address 0x{addr:08X} is outside the mapped data areas")


class ProtocolError(RuntimeError):
    """A mapped file is not what the layout says it should be."""


class MappedFile:
    """One memory-mapped protocol file with typed access to its data area."""

    def __init__(self, path: Path, magic: bytes, *, create: bool = False) -> None:
        self.path = Path(path)
        self.magic = magic
        if create:
            with open(self.path, "wb") as f:
                f.write(_HEADER.pack(magic, LAYOUT_VERSION, 0, 0, os.getpid()) + bytes(DATA_SIZE))
        try:
            fd = os.open(self.path, os.O_RDWR)
        except FileNotFoundError:
            raise ProtocolError(f"{self.path}: no such file (is the physics process running?)") from None
        try:
            size = os.fstat(fd).st_size
            if size != FILE_SIZE:
                raise ProtocolError(f"{self.path}: size {size} bytes, expected {FILE_SIZE}")
            self._mm = mmap.mmap(fd, FILE_SIZE)
        finally:
            os.close(fd)
        got_magic, version = struct.unpack_from("<4sI", self._mm, 0)
        if got_magic != magic:
            self._mm.close()
            raise ProtocolError(f"{self.path}: magic {got_magic!r}, expected {magic!r}")
        if version != LAYOUT_VERSION:
            self._mm.close()
            raise ProtocolError(f"{self.path}: layout version {version}, expected {LAYOUT_VERSION}")

    def close(self) -> None:
        self._mm.close()

    def __enter__(self) -> "MappedFile":
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()

    # Header fields.
    @property
    def time_us(self) -> int:
        return struct.unpack_from("<q", self._mm, _HDR_TIME)[0]

    @property
    def seq(self) -> int:
        return struct.unpack_from("<I", self._mm, _HDR_SEQ)[0]

    @property
    def pid(self) -> int:
        return struct.unpack_from("<I", self._mm, _HDR_PID)[0]

    def stamp(self, time_us: int) -> None:
        """Publish: write the time, then bump the sequence counter, so a reader that sees the new sequence
        also sees everything written before it."""
        struct.pack_into("<q", self._mm, _HDR_TIME, time_us)
        struct.pack_into("<II", self._mm, _HDR_SEQ, (self.seq + 1) & 0xFFFFFFFF, os.getpid())

    # Data area, by data offset.
    def _check(self, offset: int, size: int) -> int:
        if not 0 <= offset <= DATA_SIZE - size:
            raise ProtocolError(f"data offset {offset} (+{size}) is outside the {DATA_SIZE}-byte data area")
        return HEADER_SIZE + offset

    def read_i32(self, offset: int) -> int:
        return struct.unpack_from("<i", self._mm, self._check(offset, 4))[0]

    def write_i32(self, offset: int, value: int) -> None:
        struct.pack_into("<i", self._mm, self._check(offset, 4), value)

    def read_u32(self, offset: int) -> int:
        return struct.unpack_from("<I", self._mm, self._check(offset, 4))[0]

    def write_u32(self, offset: int, value: int) -> None:
        struct.pack_into("<I", self._mm, self._check(offset, 4), value)

    def read_i64(self, offset: int) -> int:
        return struct.unpack_from("<q", self._mm, self._check(offset, 8))[0]

    def write_i64(self, offset: int, value: int) -> None:
        struct.pack_into("<q", self._mm, self._check(offset, 8), value)

    def read_f32(self, offset: int) -> float:
        return struct.unpack_from("<f", self._mm, self._check(offset, 4))[0]

    def write_f32(self, offset: int, value: float) -> None:
        struct.pack_into("<f", self._mm, self._check(offset, 4), value)

    def read_i32s(self, offset: int, count: int) -> tuple[int, ...]:
        return struct.unpack_from(f"<{count}i", self._mm, self._check(offset, 4 * count))

    def write_i32s(self, offset: int, values: tuple[int, ...] | list[int]) -> None:
        struct.pack_into(f"<{len(values)}i", self._mm, self._check(offset, 4 * len(values)), *values)

    def clear_data(self, start: int, end: int) -> None:
        self._mm[self._check(start, end - start) : HEADER_SIZE + end] = bytes(end - start)


def open_unity(run_dir: Path, *, create: bool = False) -> MappedFile:
    return MappedFile(Path(run_dir) / UNITY_FILE, UNITY_MAGIC, create=create)


def open_athrill(run_dir: Path, *, create: bool = False) -> MappedFile:
    return MappedFile(Path(run_dir) / ATHRILL_FILE, ATHRILL_MAGIC, create=create)


def goal_time_words(goal_time_us: int) -> tuple[int, int]:
    """Split a goal time into the (upper, lower) 32-bit words of Table 1."""
    return (goal_time_us >> 32) & 0xFFFFFFFF, goal_time_us & 0xFFFFFFFF


def goal_time_from_words(hi: int, lo: int) -> int:
    return (hi << 32) | lo

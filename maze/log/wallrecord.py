"""The 16-bit WallRecord of the seed and the append-only log built from it.

Layout (little-endian on disk): bits 0-5 x, 6-11 y, 12-14 direction, 15 wall present.
A log is records back to back; erased flash reads 0xFFFF, so that value ends the log.
"""

from __future__ import annotations

import re
import struct
from collections.abc import Iterable
from dataclasses import dataclass

from ..direction import ARROW, DIRECTIONS, parse_direction
from ..errors import MazeError

COORD_BITS = 6
DIR_BITS = 3
COORD_LIMIT = 1 << COORD_BITS  # a maze side the record can address (64)
Y_SHIFT = COORD_BITS
DIR_SHIFT = 2 * COORD_BITS
WALL_BIT = 1 << (DIR_SHIFT + DIR_BITS)
COORD_MASK = COORD_LIMIT - 1
DIR_MASK = (1 << DIR_BITS) - 1
RECORD_BYTES = 2
TERMINATOR = 0xFFFF  # what an erased NOR flash half-word reads as
ERASED_BYTE = 0xFF


@dataclass(frozen=True)
class WallRecord:
    x: int
    y: int
    d: int
    wall: bool

    def encode(self) -> int:
        return self.x | self.y << Y_SHIFT | self.d << DIR_SHIFT | (WALL_BIT if self.wall else 0)

    @classmethod
    def decode(cls, word: int) -> WallRecord:
        return cls(word & COORD_MASK, word >> Y_SHIFT & COORD_MASK, word >> DIR_SHIFT & DIR_MASK, bool(word & WALL_BIT))

    def to_text(self) -> str:
        return f"({self.x:5d}, {self.y:5d}, {ARROW[self.d]:>7}, {'true ' if self.wall else 'false'})"


@dataclass(frozen=True)
class Anomaly:
    """Something wrong with one record; index is its position in the log (0-based)."""

    index: int
    reason: str

    def __str__(self) -> str:
        return f"record {self.index}: {self.reason}"


@dataclass
class LogScan:
    records: list[tuple[int, WallRecord]]  # (index in the log, record), anomalous ones left out
    anomalies: list[Anomaly]
    total_bytes: int
    used_bytes: int  # up to the terminator (or the end)


def encode_log(records: Iterable[WallRecord]) -> bytes:
    words = [r.encode() for r in records]
    return struct.pack(f"<{len(words)}H", *words)


def scan_log(data: bytes) -> LogScan:
    """Split raw bytes into records, noting instead of raising: a crashed mouse leaves torn logs behind."""
    anomalies: list[Anomaly] = []
    records: list[tuple[int, WallRecord]] = []
    whole = len(data) - len(data) % RECORD_BYTES
    count = whole // RECORD_BYTES
    words = struct.unpack(f"<{count}H", data[:whole])
    used = len(data)
    for i, word in enumerate(words):
        if word == TERMINATOR:
            used = i * RECORD_BYTES
            if any(b != ERASED_BYTE for b in data[used:]):
                anomalies.append(Anomaly(i, "data after the 0xFFFF terminator (ignored)"))
            break
        rec = WallRecord.decode(word)
        if word >> 8 == ERASED_BYTE:
            anomalies.append(Anomaly(i, f"torn record: its second byte is still erased (0x{word:04X})"))
        elif rec.d not in DIRECTIONS:
            anomalies.append(Anomaly(i, f"diagonal direction {rec.d} (0x{word:04X})"))
        else:
            records.append((i, rec))
    else:
        if len(data) % RECORD_BYTES:
            anomalies.append(Anomaly(count, f"torn last record: {len(data)} bytes is an odd length"))
    return LogScan(records, anomalies, len(data), used)


_TEXT_RECORD = re.compile(r"^\(?\s*(\d+)\s*,\s*(\d+)\s*,\s*(\S+?)\s*,\s*(\w+)\s*\)?$")
_BOOLS = {"true": True, "1": True, "false": False, "0": False}


def parse_text_records(text: str) -> list[WallRecord]:
    """Read the seed's `(x, y, dir, bool)` lines; a header line without numbers and `#` comments are allowed."""
    out: list[WallRecord] = []
    for lineno, raw in enumerate(text.splitlines(), 1):
        line = raw.strip()
        if not line or line.startswith("#") or line.startswith("```"):
            continue
        m = _TEXT_RECORD.match(line)
        if m is None:
            if not out and not any(c.isdigit() for c in line):
                continue  # the seed's column header
            raise MazeError(f"line {lineno}: not a (x, y, dir, bool) record: {line!r}")
        x, y = int(m.group(1)), int(m.group(2))
        if x >= COORD_LIMIT or y >= COORD_LIMIT:
            raise MazeError(f"line {lineno}: coordinate out of the record's range 0-{COORD_MASK}")
        try:
            d = parse_direction(m.group(3))
        except ValueError as e:
            raise MazeError(f"line {lineno}: {e}") from None
        flag = m.group(4).lower()
        if flag not in _BOOLS:
            raise MazeError(f"line {lineno}: wall flag must be true/false, got {m.group(4)!r}")
        out.append(WallRecord(x, y, d, _BOOLS[flag]))
    if not out:
        raise MazeError("no (x, y, dir, bool) records found")
    return out


TEXT_HEADER = "(    x,     y,     dir, wall )"

"""A NOR flash model for comparing how a search backs up its map.

NOR flash rules: erase sets a whole sector to 0xFF (and wears it); program can only clear bits; power may
fail before any byte. Two ways to back up are compared on the same search: the wall log (erase once, append
each cell's new records) and a whole-maze snapshot rewritten after each cell (one sector, or two used in turn).
"""

from __future__ import annotations

import random
from dataclasses import dataclass, field
from math import ceil
from typing import TYPE_CHECKING

import numpy as np

from ..errors import MazeError
from ..model import Maze, inner_wall_count
from .restore import apply_records, load_log, restore
from .wallrecord import ERASED_BYTE, RECORD_BYTES, WallRecord, encode_log

if TYPE_CHECKING:
    from ..search.explorer import SearchResult

SECTOR_BYTES = 2048  # a typical MCU flash page (STM32F1/G4)
SEQ_BYTES = 2
COMMIT = b"\x5a\xa5"  # written last: a snapshot without it was cut off
SCHEMES = ("wall log", "snapshot, 1 sector", "snapshot, 2 sectors")


class PowerCut(Exception):
    """Raised by the flash when the power fails; what was programmed so far stays."""


class NorFlash:
    def __init__(self, sectors: int, budget: int | None = None) -> None:
        self.data = bytearray([ERASED_BYTE]) * (sectors * SECTOR_BYTES)
        self.erases = [0] * sectors
        self.programmed = 0
        self.budget = budget  # bytes that can still be programmed before the power fails

    def erase(self, sector: int) -> None:
        base = sector * SECTOR_BYTES
        self.data[base: base + SECTOR_BYTES] = bytes([ERASED_BYTE]) * SECTOR_BYTES
        self.erases[sector] += 1

    def program(self, addr: int, payload: bytes) -> None:
        room = len(payload) if self.budget is None else max(0, min(len(payload), self.budget - self.programmed))
        chunk = payload[:room]
        old = int.from_bytes(self.data[addr: addr + room], "little")
        new = int.from_bytes(chunk, "little")
        if new & ~old:
            raise MazeError(f"programming 0x{addr:04X} would need a 0 bit set to 1: erase first")
        self.data[addr: addr + room] = (old & new).to_bytes(room, "little")
        self.programmed += room
        if room < len(payload):
            raise PowerCut()


@dataclass
class Write:
    batch: int  # index of the cell (in SearchResult.batches) whose records this write saves
    addr: int
    payload: bytes
    erase: tuple[int, ...] = ()  # sectors erased just before


def inner_wall_ids(maze: Maze) -> np.ndarray:
    return np.array([maze.wid(x, y, d) for x, y, d in maze.inner_walls()])


def pack_snapshot(maze: Maze, ids: np.ndarray) -> bytes:
    """The seed's minimal representation: two bits per inner wall (known, present), N*(N-1)/2 bytes."""
    known = np.frombuffer(bytes(maze.known), dtype=np.uint8)[ids]
    wall = np.frombuffer(bytes(maze.wall), dtype=np.uint8)[ids]
    return np.packbits(np.stack([known, wall], axis=1).ravel()).tobytes()


def unpack_snapshot(data: bytes, size: int) -> Maze:
    maze = Maze.unknown(size)
    ids = inner_wall_ids(maze)
    bits = np.unpackbits(np.frombuffer(data, dtype=np.uint8))[: 2 * len(ids)].reshape(-1, 2)
    for w, (known, wall) in zip(ids.tolist(), bits.tolist()):
        maze.known[w], maze.wall[w] = known, wall
    return maze


def snapshot_bytes(size: int) -> int:
    return ceil(inner_wall_count(size) * 2 / 8)


def log_sectors(size: int) -> int:
    return ceil(inner_wall_count(size) * RECORD_BYTES / SECTOR_BYTES)


def _batches(result: SearchResult) -> list[tuple[int, int, int]]:
    """(cell index, first record, end record) of each cell that learned something."""
    out, pos = [], 0
    for j, n in enumerate(result.batches):
        if n:
            out.append((j, pos, pos + n))
        pos += n
    return out


def log_writes(result: SearchResult) -> list[Write]:
    writes = []
    for i, (j, lo, hi) in enumerate(_batches(result)):
        erase = tuple(range(log_sectors(result.maze.size))) if i == 0 else ()
        writes.append(Write(j, lo * RECORD_BYTES, encode_log(result.records[lo:hi]), erase))
    return writes


def cut_log(records: list[WallRecord], size: int, cut: int) -> tuple[bytes, int]:
    """The flash image a log appended record by record leaves when the power fails before byte `cut`, and the
    bytes that made it (an odd count: the last record is torn)."""
    flash = NorFlash(max(log_sectors(size), ceil(len(records) * RECORD_BYTES / SECTOR_BYTES)), budget=cut)
    try:
        flash.program(0, encode_log(records))
    except PowerCut:
        pass
    return bytes(flash.data), flash.programmed


def snapshot_writes(result: SearchResult, sectors: int) -> list[Write]:
    maze = Maze.unknown(result.maze.size)
    ids = inner_wall_ids(maze)
    writes = []
    for seq, (j, lo, hi) in enumerate(_batches(result)):
        apply_records(maze, result.records[lo:hi])
        sector = seq % sectors
        payload = pack_snapshot(maze, ids) + seq.to_bytes(SEQ_BYTES, "little") + COMMIT
        writes.append(Write(j, sector * SECTOR_BYTES, payload, (sector,)))
    return writes


def snapshot_restore(image: bytes, size: int, sectors: int) -> Maze:
    """The newest committed snapshot; an all-unknown maze when none survived."""
    body = snapshot_bytes(size)
    best: tuple[int, bytes] | None = None
    for s in range(sectors):
        raw = image[s * SECTOR_BYTES: s * SECTOR_BYTES + body + SEQ_BYTES + len(COMMIT)]
        if raw[-len(COMMIT):] == COMMIT:
            seq = int.from_bytes(raw[body: body + SEQ_BYTES], "little")
            if best is None or seq > best[0]:
                best = (seq, raw[:body])
    return unpack_snapshot(best[1], size) if best else Maze.unknown(size)


def run_writes(writes: list[Write], sectors: int, cut: int | None = None) -> tuple[NorFlash, int | None]:
    """Play the writes; with a cut, stop when byte number `cut` was about to be programmed.

    Returns the flash and the batch whose write the power cut interrupted (None if none was).
    """
    flash = NorFlash(sectors, cut)
    for w in writes:
        for s in w.erase:
            flash.erase(s)
        try:
            flash.program(w.addr, w.payload)
        except PowerCut:
            return flash, w.batch
    return flash, None


@dataclass
class SchemeReport:
    name: str
    bytes_written: int
    erases: int
    max_sector_erases: int
    writes: int
    lost: list[int] = field(default_factory=list)  # walls the mouse knew but the flash lost, per cut

    @property
    def mean_lost(self) -> float:
        return sum(self.lost) / len(self.lost) if self.lost else 0.0


def compare_schemes(result: SearchResult, cuts: int, seed: int = 0) -> list[SchemeReport]:
    """Write the same search three ways and cut the power at `cuts` random bytes of each."""
    size = result.maze.size
    known_after = np.cumsum([0, *result.batches]).tolist()  # records known once batch j is sensed: [j + 1]
    plans = [
        (SCHEMES[0], log_sectors(size), log_writes(result),
         lambda img: restore(load_log(bytes(img), size).records, size)[0]),
        (SCHEMES[1], 1, snapshot_writes(result, 1), lambda img: snapshot_restore(bytes(img), size, 1)),
        (SCHEMES[2], 2, snapshot_writes(result, 2), lambda img: snapshot_restore(bytes(img), size, 2)),
    ]
    rng = random.Random(seed)
    baseline = Maze.unknown(size).known_inner()
    reports = []
    for name, sectors, writes, recover in plans:
        full, _ = run_writes(writes, sectors)
        if not recover(full.data).same_walls(result.maze):
            raise MazeError(f"{name}: an uninterrupted search does not restore the mouse's maze")
        rep = SchemeReport(name, full.programmed, sum(full.erases), max(full.erases), len(writes))
        for _ in range(cuts):
            flash, batch = run_writes(writes, sectors, rng.randrange(full.programmed))
            assert batch is not None  # a cut before the last programmed byte interrupts a write
            knew = baseline + known_after[batch + 1]
            rep.lost.append(knew - recover(flash.data).known_inner())
        reports.append(rep)
    return reports

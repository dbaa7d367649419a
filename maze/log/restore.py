"""Rebuild a maze from a wall log, the way the mouse does after a reset."""

from __future__ import annotations

from dataclasses import dataclass

from ..errors import MazeError
from ..model import Cell, Maze, wall_id
from .wallrecord import RECORD_BYTES, Anomaly, LogScan, WallRecord, scan_log


@dataclass
class LoadedLog:
    records: list[WallRecord]  # usable ones, in log order
    anomalies: list[Anomaly]
    scan: LogScan

    @property
    def in_log(self) -> int:
        """Records the log holds before its terminator, a torn last one included: what a user counts."""
        return -(-self.scan.used_bytes // RECORD_BYTES)


def load_log(data: bytes, size: int, strict: bool = False) -> LoadedLog:
    """Scan the bytes and drop records this maze cannot hold; strict mode refuses the whole log instead."""
    scan = scan_log(data)
    anomalies = list(scan.anomalies)
    records: list[WallRecord] = []
    probe = Maze(size)
    for index, rec in scan.records:
        if not probe.inside(rec.x, rec.y):
            anomalies.append(Anomaly(index, f"cell ({rec.x}, {rec.y}) is outside the {size}x{size} maze"))
        elif not rec.wall and wall_id(size, rec.x, rec.y, rec.d) in probe.topo.outer:
            anomalies.append(Anomaly(index, f"claims no outer wall at ({rec.x}, {rec.y}) dir {rec.d}"))
        else:
            records.append(rec)
    anomalies.sort(key=lambda a: a.index)
    if strict and anomalies:
        more = f" (and {len(anomalies) - 1} more)" if len(anomalies) > 1 else ""
        raise MazeError(f"corrupt log: {anomalies[0]}{more}")
    return LoadedLog(records, anomalies, scan)


def apply_records(maze: Maze, records: list[WallRecord]) -> int:
    """Apply in order; returns how many records contradicted a known wall (and so made it unknown)."""
    return sum(not maze.update(r.x, r.y, r.d, r.wall) for r in records)


def select(records: list[WallRecord], until: int | None = None, drop_last: int = 0) -> list[WallRecord]:
    """Rollback first (the records a crash may have corrupted), then the prefix asked for."""
    if drop_last < 0 or (until is not None and until < 0):
        raise MazeError("--until and --drop-last must not be negative")
    if drop_last > len(records):
        raise MazeError(f"cannot drop {drop_last} records: the log holds {len(records)}")
    kept = records[: len(records) - drop_last]
    if until is not None:
        if until > len(kept):
            raise MazeError(f"--until {until} is past the end: {len(kept)} records are available")
        kept = kept[:until]
    return kept


def restore(records: list[WallRecord], size: int, goals: tuple[Cell, ...] = ()) -> tuple[Maze, int]:
    maze = Maze.unknown(size, goals)
    return maze, apply_records(maze, records)


def records_for(maze: Maze) -> list[WallRecord]:
    """A log naming every known inner wall once: what a search that saw everything would have written."""
    return [WallRecord(x, y, d, maze.is_wall(x, y, d)) for x, y, d in maze.inner_walls() if maze.is_known(x, y, d)]

"""The campaign journal: one JSON line per finished test, written as soon as the test is known.

A campaign of 100 parameter sets takes hours on the bench, and the user may kill it at any moment; the
journal is what makes that cheap. Each line is flushed and fsynced before the next test starts, so a kill
loses at most the test that was running. A kill in the middle of a write leaves a torn last line, one without
its newline (we write each line with its newline in one call); loading drops it (and truncates it away
before appending). Anything else that does not read back (a complete line that is not a record, a second
record of the same repetition) means the file is not what we wrote: an error naming the line, and the file
is left as it is, as Optuna's journal storage does. The first line is a header (space, options and the bench)
written atomically with the file, so `--resume` can refuse to continue a campaign under different settings.

Tests run on several benches at once finish in any order, so lines are in the order tests finished; a
reader orders them by (set, repetition) where it matters. Sets are numbered from 1 in the file, as everywhere
a person reads them (format 1 numbered them from 0; it is still read). A test the bench itself spoiled
is a CRASH of kind `bench` (`TestResult.bench_fault`, the one encoding of a bench fault): it is kept for the
record, never scored, and its repetition runs again.
"""

from __future__ import annotations

import json
import os
from collections.abc import Mapping
from dataclasses import dataclass
from datetime import UTC, datetime
from pathlib import Path
from typing import IO, Any

from hakoniwa.wire.errors import HakoError
from hakoniwa.wire.result import TestResult

JOURNAL_FILE = "journal.jsonl"
PHASE_VALIDATION = "validation"  # a draw of the best set's validation, past its repetitions: no test of the search
FORMAT = 2
READABLE_FORMATS = (1, 2)
_KIND = "hakoniwa-campaign-journal"


class JournalError(HakoError, RuntimeError):
    """The journal cannot be used: missing, damaged, or written for different settings."""


@dataclass(frozen=True)
class TestRecord:
    """One finished test of one parameter set: `set_index` counts from 0 (written from 1), `rep` from 1,
    and a repetition spoiled by a bench fault appears again with the same number and noise seed."""

    __test__ = False  # not a pytest class

    set_index: int
    phase: str
    params: Mapping[str, float]
    rep: int
    result: TestResult
    timestamp: str
    noise_seed: int = 0
    bench: str = ""  # which bench ran it (informative)

    def to_json(self) -> str:
        r = self.result
        d = {"set": self.set_index + 1, "phase": self.phase, "params": dict(self.params), "rep": self.rep,
             "noise_seed": self.noise_seed, **r.to_dict(), "wall_s": r.wall_s, "bench": self.bench,
             "time": self.timestamp}
        return json.dumps(d)

    @classmethod
    def from_json(cls, line: str, fmt: int = FORMAT) -> TestRecord:
        d = json.loads(line)
        result = TestResult.from_dict(d, float(d["wall_s"]))
        params = {str(k): float(v) for k, v in d["params"].items()}
        set_index = int(d["set"]) - (1 if fmt >= 2 else 0)
        return cls(set_index, str(d["phase"]), params, int(d["rep"]), result, str(d["time"]),
                   int(d.get("noise_seed", 0)), str(d.get("bench", "")))


def now_timestamp() -> str:
    return datetime.now(UTC).isoformat(timespec="milliseconds")


class Journal:
    """An open journal: its header, the records already in it, and an append handle."""

    def __init__(self, path: Path, header: dict[str, Any], records: list[TestRecord], fh: IO[bytes]) -> None:
        self.path = path
        self.header = header
        self.records = records
        self._fh = fh

    @classmethod
    def create(cls, path: Path, header: Mapping[str, Any]) -> Journal:
        """Start a new journal; an existing one is never overwritten (that would lose a campaign)."""
        path = Path(path)
        if path.exists():
            raise JournalError(f"{path} already exists; use --resume to continue that campaign")
        full = {"kind": _KIND, "format": FORMAT, **header}
        tmp = path.with_name(path.name + ".tmp")
        with open(tmp, "wb") as f:
            f.write(_line(json.dumps(full)))
            f.flush()
            os.fsync(f.fileno())
        os.replace(tmp, path)
        return cls(path, full, [], open(path, "ab"))

    @classmethod
    def open(cls, path: Path) -> Journal:
        """Open an existing journal for appending, cutting off a torn last line first."""
        path = Path(path)
        header, records, good_len = _parse(path)
        fh = open(path, "r+b")
        fh.truncate(good_len)
        fh.seek(good_len)
        return cls(path, header, records, fh)

    def append(self, record: TestRecord, keep: bool = True) -> None:
        """Write `record` for good; `keep` adds it to `records` too (a long validation keeps none)."""
        self._fh.write(_line(record.to_json()))
        self._fh.flush()
        os.fsync(self._fh.fileno())
        if keep:
            self.records.append(record)

    def close(self) -> None:
        self._fh.close()

    def __enter__(self) -> Journal:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()


def read_journal(path: Path) -> tuple[dict[str, Any], list[TestRecord]]:
    """Header and records, without changing the file (a torn last line is ignored)."""
    header, records, _ = _parse(Path(path))
    return header, records


def _line(text: str) -> bytes:
    return text.encode("utf-8") + b"\n"


def _parse(path: Path) -> tuple[dict[str, Any], list[TestRecord], int]:
    """Header, records, and the byte length of the intact part of the file."""
    try:
        data = path.read_bytes()
    except FileNotFoundError:
        raise JournalError(f"{path}: no journal here") from None
    lines = data.split(b"\n")  # the last element is b"" for a file that ends with a newline
    if len(lines) < 2:
        raise JournalError(f"{path}: no header line")
    try:
        header = json.loads(lines[0])
    except ValueError:
        raise JournalError(f"{path}: the header line is not JSON") from None
    if not isinstance(header, dict) or header.get("kind") != _KIND:
        raise JournalError(f"{path}: not a campaign journal")
    fmt = header.get("format")
    if fmt not in READABLE_FORMATS:
        raise JournalError(f"{path}: journal format {fmt}; this version reads formats "
                           f"{', '.join(map(str, READABLE_FORMATS))}")
    records: list[TestRecord] = []
    counted: dict[tuple[int, int], int] = {}  # (set, repetition) of each scored record -> its line number
    good_len = len(lines[0]) + 1
    # Every element but the last ended with a newline, so it was written whole; the last follows the final
    # newline: b"" for an intact file, else a line torn by a kill, which is dropped.
    for number, raw in enumerate(lines[1:-1], start=2):
        try:
            record = TestRecord.from_json(raw.decode("utf-8"), fmt)
        except (ValueError, KeyError, TypeError, AttributeError):
            raise JournalError(f"{path}: line {number} is damaged (a complete line that is not a test record); "
                               "the file was left as it is") from None
        if not record.result.bench_fault:  # a spoiled test is run again under the same (set, repetition)
            key = (record.set_index, record.rep)
            if key in counted:
                raise JournalError(f"{path}: line {number} records set {record.set_index + 1} repetition "
                                   f"{record.rep} a second time (first on line {counted[key]}); the file was "
                                   "left as it is")
            counted[key] = number
        records.append(record)
        good_len += len(raw) + 1
    return header, records, good_len

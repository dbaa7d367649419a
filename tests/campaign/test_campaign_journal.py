"""The JSON-lines journal: durable appends, torn-tail tolerance, refusal of damaged files."""

from __future__ import annotations

from pathlib import Path

import pytest

from hakoniwa.wire.protocol import Event
from testctl.campaign.journal import Journal, JournalError, TestRecord, read_journal
from tests.helpers.campaign_doubles import result

HEADER = {"space": {"param": []}, "options": {}}


def record(i: int, event: Event = Event.GOAL) -> TestRecord:
    return TestRecord(i // 3, "init", {"Kp": 0.1 * i, "Ki": 1 / 3}, i % 3 + 1, result(event, 30.5 + i), "t")


def write(path: Path, n: int) -> list[TestRecord]:
    records = [record(i, Event.GOAL if i % 2 else Event.HIT_WALL) for i in range(n)]
    with Journal.create(path, HEADER) as j:
        for r in records:
            j.append(r)
    return records


def test_round_trip_is_exact(tmp_path: Path) -> None:
    path = tmp_path / "j.jsonl"
    records = write(path, 5)
    header, loaded = read_journal(path)
    assert loaded == records
    assert header["options"] == {} and header["format"] == 2
    assert loaded[1].result.lap_time_s == 31.5


def test_sets_are_numbered_from_1_in_the_file_and_bench_faults_are_marked(tmp_path: Path) -> None:
    import json

    from tests.helpers.campaign_doubles import BENCH_FAULT

    path = tmp_path / "j.jsonl"
    fault = TestRecord(0, "init", {"Kp": 1.0}, 1, BENCH_FAULT, "t", noise_seed=77, bench="w0")
    with Journal.create(path, HEADER) as j:
        j.append(record(0))
        j.append(fault)
    lines = [json.loads(line) for line in path.read_text().splitlines()[1:]]
    assert [d["set"] for d in lines] == [1, 1]
    assert "crash" not in lines[0] and lines[1]["crash"] == "bench"
    assert read_journal(path)[1][1] == fault


def test_a_format_1_journal_is_still_read(tmp_path: Path) -> None:
    path = tmp_path / "j.jsonl"
    path.write_text('{"kind": "hakoniwa-campaign-journal", "format": 1, "space": {}, "options": {}}\n'
                    '{"set": 0, "phase": "init", "params": {"Kp": 1.0}, "rep": 1, "event": "GOAL", '
                    '"goal_time_us": 33000000, "lap_time_s": 33.0, "wall_s": 0.5, "time": "t"}\n')
    header, records = read_journal(path)
    assert header["format"] == 1
    assert records[0].set_index == 0 and records[0].result.lap_time_s == 33.0


def test_create_never_overwrites(tmp_path: Path) -> None:
    path = tmp_path / "j.jsonl"
    write(path, 1)
    with pytest.raises(JournalError, match="--resume"):
        Journal.create(path, HEADER)


@pytest.mark.parametrize("tail", [b'{"set": 1, "pha', b"\x00\x00\x00", b'{"set": 1}'])
def test_torn_last_line_is_dropped_and_cut_before_appending(tmp_path: Path, tail: bytes) -> None:
    path = tmp_path / "j.jsonl"
    records = write(path, 4)
    with open(path, "ab") as f:
        f.write(tail)
    assert read_journal(path)[1] == records
    with Journal.open(path) as j:
        assert j.records == records
        j.append(record(9))
    assert read_journal(path)[1] == [*records, record(9)]


def test_damage_before_the_last_line_is_an_error(tmp_path: Path) -> None:
    path = tmp_path / "j.jsonl"
    write(path, 4)
    lines = path.read_bytes().split(b"\n")
    lines[2] = lines[2][:10]
    path.write_bytes(b"\n".join(lines))
    with pytest.raises(JournalError, match="line 3 is damaged"):
        read_journal(path)


@pytest.mark.parametrize(
    "content, problem",
    [(b"", "no header"), (b"not json\n", "header line is not JSON"), (b'{"kind": "x"}\n', "not a campaign journal")],
)
def test_bad_header(tmp_path: Path, content: bytes, problem: str) -> None:
    path = tmp_path / "j.jsonl"
    path.write_bytes(content)
    with pytest.raises(JournalError, match=problem):
        read_journal(path)


def test_missing_journal(tmp_path: Path) -> None:
    with pytest.raises(JournalError, match="no journal"):
        Journal.open(tmp_path / "j.jsonl")


@pytest.mark.parametrize("tail", [b'{"set": 1}\n', b"\n", b'{"set": 1, "event": "NEW_EVENT"}\n', b"\x00\x00\n"])
def test_a_complete_last_line_that_is_not_a_record_is_corruption_and_kept(tmp_path: Path, tail: bytes) -> None:
    """Only a line without its newline can be a torn write; a finished line that does not read back is damage,
    reported with its number, and opening the journal to append must not cut it away."""
    path = tmp_path / "j.jsonl"
    write(path, 4)
    with open(path, "ab") as f:
        f.write(tail)
    before = path.read_bytes()
    with pytest.raises(JournalError, match="line 6 is damaged"):
        read_journal(path)
    with pytest.raises(JournalError, match="line 6 is damaged"):
        Journal.open(path)
    assert path.read_bytes() == before


def test_a_duplicated_record_is_corruption_naming_its_line(tmp_path: Path) -> None:
    path = tmp_path / "j.jsonl"
    write(path, 4)
    lines = path.read_bytes().split(b"\n")
    path.write_bytes(b"\n".join([*lines[:3], lines[2], *lines[3:]]))  # the second record, twice
    before = path.read_bytes()
    with pytest.raises(JournalError, match="line 4 records set 1 repetition 2 a second time \\(first on line 3\\)"):
        Journal.open(path)
    assert path.read_bytes() == before


def test_a_bench_fault_and_its_rerun_share_a_repetition(tmp_path: Path) -> None:
    from tests.helpers.campaign_doubles import BENCH_FAULT

    path = tmp_path / "j.jsonl"
    fault = TestRecord(0, "init", {"Kp": 1.0}, 1, BENCH_FAULT, "t")
    rerun = TestRecord(0, "init", {"Kp": 1.0}, 1, result(Event.GOAL, 33.0), "t")
    with Journal.create(path, HEADER) as j:
        j.append(fault)
        j.append(fault)
        j.append(rerun)
    assert read_journal(path)[1] == [fault, fault, rerun]

import struct

import pytest
from hypothesis import given
from hypothesis import strategies as st

from maze.direction import DIRECTIONS, EAST, NORTH, SOUTH, WEST
from maze.errors import MazeError
from maze.log.wallrecord import (
    COORD_LIMIT,
    TERMINATOR,
    WallRecord,
    encode_log,
    parse_text_records,
    scan_log,
)

records = st.builds(
    WallRecord,
    st.integers(0, COORD_LIMIT - 1),
    st.integers(0, COORD_LIMIT - 1),
    st.sampled_from(DIRECTIONS),
    st.booleans(),
)


def test_bit_layout_matches_the_seed_union():
    # x in bits 0-5, y in 6-11, d in 12-14, wall in 15, little-endian on disk
    word = 3 | 5 << 6 | NORTH << 12 | 1 << 15
    assert WallRecord(3, 5, NORTH, True).encode() == word
    assert encode_log([WallRecord(3, 5, NORTH, True)]) == bytes([word & 0xFF, word >> 8])
    assert WallRecord.decode(63 | 63 << 6 | WEST << 12) == WallRecord(63, 63, WEST, False)


def test_direction_codes_are_the_libraries_eight_way_numbers():
    assert (EAST, NORTH, WEST, SOUTH) == (0, 2, 4, 6)


@given(st.lists(records, max_size=200))
def test_encode_scan_round_trip(recs):
    data = encode_log(recs)
    scan = scan_log(data)
    assert [r for _, r in scan.records] == recs
    assert scan.anomalies == []
    assert len(data) == 2 * len(recs)


@given(st.lists(records, max_size=50), st.integers(1, 40))
def test_terminator_ends_the_log_and_erased_tail_is_silent(recs, erased_words):
    scan = scan_log(encode_log(recs) + b"\xff" * 2 * erased_words)
    assert [r for _, r in scan.records] == recs
    assert scan.anomalies == []
    assert scan.used_bytes == 2 * len(recs)


def test_torn_last_record_is_reported_with_its_index():
    data = encode_log([WallRecord(1, 2, EAST, True)] * 3)[:-1]
    scan = scan_log(data)
    assert len(scan.records) == 2
    assert [a.index for a in scan.anomalies] == [2]
    assert "torn" in scan.anomalies[0].reason


def test_diagonal_direction_is_reported_and_skipped():
    bad = 1 | 1 << 6 | 3 << 12
    data = (encode_log([WallRecord(0, 1, NORTH, False)]) + struct.pack("<H", bad)
            + encode_log([WallRecord(0, 1, EAST, True)]))
    scan = scan_log(data)
    assert [i for i, _ in scan.records] == [0, 2]
    assert [a.index for a in scan.anomalies] == [1]
    assert "diagonal" in scan.anomalies[0].reason


def test_data_after_the_terminator_is_reported():
    data = encode_log([WallRecord(0, 1, NORTH, False)]) + struct.pack("<HH", TERMINATOR, 0x1234)
    scan = scan_log(data)
    assert len(scan.records) == 1
    assert [a.index for a in scan.anomalies] == [1]


@given(st.binary(max_size=300))
def test_scan_never_raises_and_accounts_for_every_word(data):
    scan = scan_log(data)
    indices = [i for i, _ in scan.records]
    assert indices == sorted(set(indices))
    assert all(2 * i + 2 <= scan.used_bytes for i in indices)
    assert all(r.d in DIRECTIONS for _, r in scan.records)


@given(st.lists(records, min_size=1, max_size=60))
def test_text_round_trip(recs):
    text = "\n".join(r.to_text() for r in recs)
    assert parse_text_records(text) == recs


def test_text_accepts_letters_numbers_and_the_seed_header():
    text = "( x座標, y座標, 壁の方向, 壁の有無)\n(0, 1, N, true)\n# comment\n(2, 3, 6, 0)\n"
    assert parse_text_records(text) == [WallRecord(0, 1, NORTH, True), WallRecord(2, 3, SOUTH, False)]


@pytest.mark.parametrize(
    "text, line",
    [("(0, 1, ^, true)\n(0, 1, ^, maybe)", 2), ("(0, 1, ^, true)\n(0, 1, /, true)", 2),
     ("(0, 99, ^, true)", 1), ("(0, 1, ^, true)\nnonsense", 2)],
)
def test_text_errors_name_the_line(text, line):
    with pytest.raises(MazeError, match=f"line {line}:"):
        parse_text_records(text)

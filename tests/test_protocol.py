import struct

import pytest
from hypothesis import given
from hypothesis import strategies as st

from hakoniwa.protocol import (ATHRILL_GUEST_BASE, DATA_SIZE, FILE_SIZE, HEADER_SIZE, UNITY_FILE,
                               UNITY_GUEST_BASE, Athrill, ProtocolError, Unity, goal_time_from_words,
                               goal_time_words, guest_to_data_offset, open_athrill, open_unity)


def test_file_is_header_plus_data_area(tmp_path):
    with open_unity(tmp_path, create=True):
        pass
    raw = (tmp_path / UNITY_FILE).read_bytes()
    assert len(raw) == FILE_SIZE == 32 + 1024
    assert raw[:4] == b"HKUN"


def test_paper_offsets_are_data_offsets_plus_32(tmp_path):
    with open_unity(tmp_path, create=True) as u:
        u.write_f32(Unity.KP, 1.5)
        u.write_i32(Unity.EVENT, 3)
    raw = (tmp_path / UNITY_FILE).read_bytes()
    assert struct.unpack_from("<f", raw, 540 + 32)[0] == 1.5
    assert struct.unpack_from("<i", raw, 528 + 32)[0] == 3
    assert (Unity.EVENT, Unity.GOAL_TIME_HI, Unity.GOAL_TIME_LO, Unity.KP, Unity.KI, Unity.KD,
            Unity.MOTOR_POWER) == (528, 532, 536, 540, 544, 548, 552)
    assert (Athrill.START, Athrill.END) == (512, 516)


@given(st.integers(min_value=0, max_value=2**64 - 1))
def test_goal_time_words_round_trip(us):
    hi, lo = goal_time_words(us)
    assert 0 <= hi < 2**32 and 0 <= lo < 2**32
    assert goal_time_from_words(hi, lo) == us


@given(st.lists(st.tuples(st.integers(0, (DATA_SIZE - 8) // 4).map(lambda i: 4 * i),
                          st.integers(-2**31, 2**31 - 1)), max_size=20))
def test_i32_round_trip(tmp_path_factory, writes):
    d = tmp_path_factory.mktemp("rt")
    with open_athrill(d, create=True) as a:
        expect = {}
        for off, v in writes:
            a.write_i32(off, v)
            expect[off] = v
        for off, v in expect.items():
            assert a.read_i32(off) == v


def test_stamp_bumps_sequence_and_time(tmp_path):
    with open_unity(tmp_path, create=True) as u:
        seq = u.seq
        u.stamp(123_456_789_012)
        assert u.seq == seq + 1
        assert u.time_us == 123_456_789_012


def test_reader_sees_writer(tmp_path):
    with open_unity(tmp_path, create=True) as w, open_unity(tmp_path) as r:
        w.write_i64(Unity.SNAPSHOT_TIME, 2**40 + 7)
        assert r.read_i64(Unity.SNAPSHOT_TIME) == 2**40 + 7


@pytest.mark.parametrize("damage, message", [
    (lambda raw: b"XXXX" + raw[4:], "magic"),
    (lambda raw: raw[:4] + struct.pack("<I", 99) + raw[8:], "layout version 99"),
    (lambda raw: raw[:-1], "size 1055"),
    (lambda raw: raw + b"\0", "size 1057"),
    (lambda raw: b"", "size 0"),
])
def test_bad_files_are_clear_errors(tmp_path, damage, message):
    with open_unity(tmp_path, create=True):
        pass
    path = tmp_path / UNITY_FILE
    path.write_bytes(damage(path.read_bytes()))
    with pytest.raises(ProtocolError, match=message):
        open_unity(tmp_path)


def test_wrong_file_kind_is_refused(tmp_path):
    with open_athrill(tmp_path, create=True):
        pass
    (tmp_path / UNITY_FILE).write_bytes((tmp_path / "athrill_mmap.bin").read_bytes())
    with pytest.raises(ProtocolError, match="magic"):
        open_unity(tmp_path)


def test_missing_file_is_a_clear_error(tmp_path):
    with pytest.raises(ProtocolError, match="no such file"):
        open_unity(tmp_path)


def test_access_outside_data_area_is_refused(tmp_path):
    with open_unity(tmp_path, create=True) as u:
        with pytest.raises(ProtocolError):
            u.read_f32(DATA_SIZE - 2)
        with pytest.raises(ProtocolError):
            u.write_i32(-4, 0)


def test_guest_addresses():
    assert guest_to_data_offset(0x090F0000 + 540) == (UNITY_FILE, 540)
    assert guest_to_data_offset(ATHRILL_GUEST_BASE + 512)[1] == 512
    assert UNITY_GUEST_BASE == 0x090F0000
    with pytest.raises(ValueError):
        guest_to_data_offset(UNITY_GUEST_BASE + DATA_SIZE)
    assert HEADER_SIZE == 32

"""The wire layout, pinned byte for byte against the real Hakoniwa tables (../shared/third_party/athrill/README.md,
read from EV3RT's athrill drivers and Athrill's VDEV device)."""

import re
import struct

import pytest
from hypothesis import given
from hypothesis import strategies as st

from hakoniwa.wire.protocol import (
    ATHRILL_FILE,
    COURSE_BLOCK_POSITIONS,
    FILE_SIZE,
    HEADER_SIZE,
    RX_GUEST_BASE,
    TX_GUEST_BASE,
    UNITY_FILE,
    WINDOW_SIZE,
    ColorId,
    Event,
    Header,
    LayoutError,
    Rx,
    Tx,
    c_header,
    goal_time_words,
    guest_to_body,
    open_athrill,
    open_unity,
)
from tests.helpers.paths import DOCS

# The README's tables, written out independently of protocol.py.
REAL_HEADER = {"magic": 0, "version": 4, "athrill_time": 8, "unity_time": 16, "ext_off": 24, "ext_size": 28}
REAL_RX = {"buttons": 0, "color0_ambient": 4, "color0_color": 8, "color0_reflect": 12, "color0_rgb": 16,
           "gyro_angle": 28, "gyro_rate": 32, "ultrasonic_mm": 88,
           "ultrasonic_listen": 92,  # ev3_vdev_common.h: EV3_SENSOR_INX_ULTRASONIC_LISTEN 22, 4 bytes each
           "touch0": 112, "touch1": 124,
           # ev3_vdev_common.h: EV3_SENSOR_OFF 4 + 4 * EV3_BATTERY_INX_CURRENT (28) / _VOLTAGE (29)
           "battery_current": 116, "battery_voltage": 120,
           "color1_ambient": 128, "color1_color": 132, "color1_reflect": 136, "color1_rgb": 140, "motor_angle": 256,
           "event": 528, "goal_time_hi": 532, "goal_time_lo": 536, "params": 540, "kp": 540, "ki": 544, "kd": 548,
           "motor_power": 552}
REAL_TX = {"led": 0, "motor_power": 4, "motor_brake": 20, "motor_reset_angle": 36, "gyro_reset": 52, "start": 512,
           "end": 516}
# ET Robocon's etroboc_ext.h (ETrobocon/etrobo, dist/etroboc_common), which writes guest addresses as
# base + 512 - 32 + n: the course info it reads and the completion flag it writes.
REAL_ETROBOC_RX = {"course_card_number": 512 - 32, "course_block_number": 516 - 32, "course_block_pos": 520 - 32}
REAL_ETROBOC_TX = {"completed": 512 - 32}
# ET Robocon's SPIKE SDK, raspike-athrill-v850e2m target/v850_gcc/pil/include/ev3_vdev_common.h:
# SPIKE_SENSOR_IMU_OFF 272 + 4 * (ACCELARATION_X 0, _Y 1, _Z 2, VELOCITY_X 3, _Y 4, _Z 5) and
# SPIKE_SENSOR_HSV_OFF 296 + 4 * (H 0, S 1, V 2); raspike_hub.c reads the IMU words as float bits.
REAL_SPIKE_RX = {"spike_imu": 272, "spike_hsv": 296,
                 "spike_imu_accel_x": 272, "spike_imu_accel_y": 276, "spike_imu_accel_z": 280,
                 "spike_imu_angvel_x": 284, "spike_imu_angvel_y": 288, "spike_imu_angvel_z": 292,
                 "spike_hsv_h": 296, "spike_hsv_s": 300, "spike_hsv_v": 304}


def test_header_offsets_are_the_real_ones():
    assert {k: getattr(Header, k.upper()) for k in REAL_HEADER} == REAL_HEADER
    assert HEADER_SIZE == 32 and FILE_SIZE == 8192 and WINDOW_SIZE == 0x1000


def test_body_offsets_are_the_real_ones():
    assert {k: getattr(Rx, k.upper()) for k in REAL_RX} == REAL_RX
    assert {k: getattr(Tx, k.upper()) for k in REAL_TX} == REAL_TX
    assert RX_GUEST_BASE == 0x090F0000 and TX_GUEST_BASE == 0x090F1000


def test_et_robocons_extension_is_where_its_header_looks():
    assert {k: getattr(Rx, k.upper()) for k in REAL_ETROBOC_RX} == REAL_ETROBOC_RX
    assert {k: getattr(Tx, k.upper()) for k in REAL_ETROBOC_TX} == REAL_ETROBOC_TX
    assert Rx.COURSE_BLOCK_POS + COURSE_BLOCK_POSITIONS <= 512


def test_the_spike_sdks_slots_are_where_its_header_looks():
    assert {k: getattr(Rx, k.upper()) for k in REAL_SPIKE_RX} == REAL_SPIKE_RX
    assert "#define HAKO_RX_SPIKE_IMU_ANGVEL_Z 292\n" in c_header()


def test_the_spike_slots_leave_our_extension_and_et_robocons_alone():
    spike = {b for o in REAL_SPIKE_RX.values() for b in range(o, o + 4)}
    assert spike == set(range(272, 308))  # nine words, no gap
    assert not spike & set(range(448, 480)) and not spike & set(range(480, 512))


def test_our_extension_stays_in_bytes_the_real_layouts_leave_unused():
    """Below ET Robocon's 480..511 in both files, and clear of every real RX slot (the SPIKE SDK's too)."""
    real_rx = [(o, o + 4) for o in REAL_RX.values() if o < 512] + [(16, 28), (140, 152), (256, 272), (36, 88),
                                                                    (96, 124), (272, 308)]
    ours_rx = [(k, v) for k, v in vars(Rx).items() if isinstance(v, int) and k.lower() not in REAL_RX
               and k.lower() not in REAL_ETROBOC_RX and k.lower() not in REAL_SPIKE_RX
               and k not in ("COLOR0_RGB", "COLOR1_RGB")]
    ours_tx = [(k, v) for k, v in vars(Tx).items() if isinstance(v, int) and k.lower() not in REAL_TX
               and k.lower() not in REAL_ETROBOC_TX]
    assert ours_rx and ours_tx
    width = {"NEXT_WAKE": 8}
    for name, off in ours_rx:
        assert 272 <= off and off + width.get(name, 4) <= 480 and not any(a <= off < b for a, b in real_rx), name
    for name, off in ours_tx:
        assert 56 <= off and off + width.get(name, 4) <= 480, name


def test_a_new_file_has_the_real_header(tmp_path):
    with open_unity(tmp_path, create=True):
        pass
    with open_athrill(tmp_path, create=True):
        pass
    rx = (tmp_path / UNITY_FILE).read_bytes()
    tx = (tmp_path / ATHRILL_FILE).read_bytes()
    assert len(rx) == len(tx) == 8192
    assert rx[:8] == b"ETRX\x01\x00\x00\x00" and tx[:8] == b"ETTX\x01\x00\x00\x00"
    assert struct.unpack_from("<II", rx, 24) == (512, 512) == struct.unpack_from("<II", tx, 24)


def test_a_file_written_by_the_real_athrill2_is_accepted(tmp_path):
    # What athrill2 writes at start (seen in a probe of the real emulator): its header, its clock, the echo.
    header = b"ETTX" + struct.pack("<IQQII", 1, 123_456, 120_000, 512, 512)
    (tmp_path / ATHRILL_FILE).write_bytes(header + bytes(8192 - 32))
    with open_athrill(tmp_path) as a:
        assert a.athrill_time_us == 123_456
        assert a.unity_time_us == 120_000


def test_field_values_land_at_body_offset_plus_32_with_their_units(tmp_path):
    with open_unity(tmp_path, create=True) as u:
        u.write_f32(Rx.KP, 1.5)
        u.write_i32(Rx.EVENT, int(Event.HIT_WALL))
        u.write_i32(Rx.COLOR0_COLOR, int(ColorId.WHITE))
        u.write_i32(Rx.ULTRASONIC_MM, 1234)
        u.write_i32(Rx.TOUCH0, 4095)
        u.write_i32(Rx.MOTOR_ANGLE + 4 * 1, -720)
        u.unity_time_us = 2**40 + 5
    raw = (tmp_path / UNITY_FILE).read_bytes()
    assert struct.unpack_from("<f", raw, 540 + 32)[0] == 1.5
    assert struct.unpack_from("<i", raw, 528 + 32)[0] == 3
    assert raw[8 + 32] == 6  # EV3RT reads the colour id's low byte: COLOR_WHITE
    assert struct.unpack_from("<h", raw, 88 + 32)[0] == 1234  # mm; EV3RT divides by 10
    assert struct.unpack_from("<i", raw, 112 + 32)[0] == 4095
    assert struct.unpack_from("<i", raw, 256 + 4 + 32)[0] == -720  # port B
    assert struct.unpack_from("<Q", raw, 16)[0] == 2**40 + 5


@given(st.integers(min_value=0, max_value=2**64 - 1))
def test_goal_time_words_round_trip(us):
    hi, lo = goal_time_words(us)
    assert 0 <= hi < 2**32 and 0 <= lo < 2**32
    assert (hi << 32) | lo == us


@given(st.lists(st.tuples(st.integers(0, (WINDOW_SIZE - 4) // 4).map(lambda i: 4 * i),
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


def test_reader_sees_writer(tmp_path):
    with open_unity(tmp_path, create=True) as w, open_unity(tmp_path) as r:
        w.unity_time_us = 2**40 + 7
        assert r.unity_time_us == 2**40 + 7


@pytest.mark.parametrize("damage, message", [
    (lambda raw: b"XXXX" + raw[4:], "magic"),
    (lambda raw: raw[:4] + struct.pack("<I", 99) + raw[8:], "layout version 99"),
    (lambda raw: raw[:-1], "size 8191"),
    (lambda raw: raw + b"\0", "size 8193"),
    (lambda raw: raw[:1056], "size 1056"),  # our old layout's size
    (lambda raw: b"", "size 0"),
])
def test_bad_files_are_clear_errors(tmp_path, damage, message):
    with open_unity(tmp_path, create=True):
        pass
    path = tmp_path / UNITY_FILE
    path.write_bytes(damage(path.read_bytes()))
    with pytest.raises(LayoutError, match=message):
        open_unity(tmp_path)


def test_wrong_file_kind_is_refused(tmp_path):
    with open_athrill(tmp_path, create=True):
        pass
    (tmp_path / UNITY_FILE).write_bytes((tmp_path / ATHRILL_FILE).read_bytes())
    with pytest.raises(LayoutError, match="magic"):
        open_unity(tmp_path)


def test_missing_file_is_a_clear_error(tmp_path):
    with pytest.raises(LayoutError, match="no such file"):
        open_unity(tmp_path)


@pytest.mark.parametrize("damage", ["magic", "truncate"])
def test_the_owner_repairs_a_damaged_file(tmp_path, damage):
    with open_unity(tmp_path, create=True) as u:
        u.write_f32(Rx.KP, 2.5)
        path = tmp_path / UNITY_FILE
        if damage == "magic":
            with open(path, "r+b") as f:
                f.write(b"JUNK")
        else:
            with open(path, "r+b") as f:
                f.truncate(100)
        assert u.repair() is not None
        assert u.repair() is None
        with open_unity(tmp_path) as again:  # a fresh reader accepts it
            assert again.read_f32(Rx.KP) == (2.5 if damage == "magic" else 0.0)


def test_access_outside_the_window_is_refused(tmp_path):
    with open_unity(tmp_path, create=True) as u:
        u.read_f32(WINDOW_SIZE - 4)  # the whole 4 KiB window is readable, as in the real Athrill
        with pytest.raises(LayoutError):
            u.read_f32(WINDOW_SIZE - 2)
        with pytest.raises(LayoutError):
            u.write_i32(-4, 0)


def test_guest_addresses():
    assert guest_to_body(0x090F0000 + 540) == (UNITY_FILE, 540)
    assert guest_to_body(0x090F1000 + 512) == (ATHRILL_FILE, 512)
    assert guest_to_body(0x090F0FFF) == (UNITY_FILE, 0xFFF)
    with pytest.raises(ValueError):
        guest_to_body(0x090F2000)
    with pytest.raises(ValueError):
        guest_to_body(0x090EFFFF)


def test_the_c_header_is_generated_from_this_layout():
    text = c_header()
    assert "#define HAKO_RX_KP 540\n" in text
    assert "#define HAKO_TX_START 512\n" in text
    assert "#define HAKO_RX_ULTRASONIC_MM 88\n" in text
    assert "#define HAKO_RX_GUEST_BASE 0x90F0000u\n" in text
    assert "#define HAKO_EVENT_CRASH 4\n" in text


def test_the_spike_slots_are_where_the_sdks_header_puts_them():
    """raspike-athrill-v850e2m's ev3_vdev_common.h, read from ../shared: each slot is OFF + 4 * INX."""
    from tests.helpers.raspike_sdk import NEEDS_RASPIKE, VDEV_HEADER

    if not VDEV_HEADER.is_file():
        pytest.skip(NEEDS_RASPIKE)
    defines = {name: int(value) for name, value in
               re.findall(r"#define\s+(SPIKE_SENSOR_\w+)\s+\((\d+)U\)", VDEV_HEADER.read_text())}
    imu, hsv = defines["SPIKE_SENSOR_IMU_OFF"], defines["SPIKE_SENSOR_HSV_OFF"]
    assert Rx.SPIKE_IMU == imu and Rx.SPIKE_HSV == hsv
    assert Rx.SPIKE_IMU_ACCEL_X == imu + 4 * defines["SPIKE_SENSOR_IMU_INX_ACCELARATION_X"]
    assert Rx.SPIKE_IMU_ANGVEL_X == imu + 4 * defines["SPIKE_SENSOR_IMU_INX_VELOCITY_X"]
    assert defines["SPIKE_SENSOR_IMU_INX_VELOCITY_Z"] == defines["SPIKE_SENSOR_IMU_INX_VELOCITY_X"] + 2
    for axis in "HSV":
        assert getattr(Rx, f"SPIKE_HSV_{axis}") == hsv + 4 * defines[f"SPIKE_SENSOR_HSV_INX_{axis}"]


OFFSET_ROW = re.compile(r"^\|\s*`(Rx|Tx)\.([A-Z0-9_]+)`\s*\|\s*(\d+)\s*\|", re.MULTILINE)


def test_the_docs_offset_tables_match_the_layout():
    """A table row `| `Rx.NAME` | offset |` in docs/ restates protocol.py; it must not drift (it once did)."""
    rows = [(doc.name, *m.groups()) for doc in sorted(DOCS.glob("*.md")) for m in OFFSET_ROW.finditer(doc.read_text())]
    assert rows, "no offset table found in docs/: the pattern no longer matches how they are written"
    layouts = {"Rx": Rx, "Tx": Tx}
    wrong = [(doc, f"{side}.{name}", int(offset), getattr(layouts[side], name, None))
             for doc, side, name, offset in rows if getattr(layouts[side], name, None) != int(offset)]
    assert not wrong, f"(doc, field, documented, actual): {wrong}"

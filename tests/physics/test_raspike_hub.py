"""The SPIKE hub played on a pseudo-terminal (`hakoniwa/physics/raspike_hub.py`): the bytes it sends, each
checked against the hub's own program (spike-rt-hub sdk/workspace/raspike/raspike.c at 38ed091, cited by
line) and the Pi's reader (libraspike-art 28f3f38 src/raspike_protocol_com.h); then the Pi's real
libraspike-art, compiled natively into a small C program, talking to it."""

from __future__ import annotations

import os
import select
import shutil
import struct
import subprocess
import time
from collections import deque
from functools import partial
from pathlib import Path

import pytest
from hypothesis import given
from hypothesis import strategies as st

from athrill_sim.programs.third_party import RASPIKE_ART
from hakoniwa.physics import spike_hub
from hakoniwa.physics.raspike_hub import COLOR, FORCE, MOTOR, Hub, HubFault, PtyHub, SerialCounts
from hakoniwa.physics.sensors import HubReadings, Sensors
from hakoniwa.physics.slots import BATTERY_MA, BATTERY_MV
from hakoniwa.physics.spike_hub import speed_over
from hakoniwa.physics.world import Inertial
from hakoniwa.wire import rundir
from hakoniwa.wire.protocol import NEVER_WAKES, RASPIKE_STATUS_PERIOD_US, ColorId
from tests.helpers.paths import PROGRAMS, SHARED, needs_shared

LIBRASPIKE_ART = SHARED / "third_party" / "raspike-art" / "RasPike-ART" / "libraspike-art"
PROBE = PROGRAMS / "raspike_hub_probe" / "probe.c"
# sample_c5_spike's wiring (app.c): right motor A, left motor B, force D, colour E; nothing on C.
KINDS = {0: MOTOR, 1: MOTOR, 3: FORCE, 4: COLOR}
RGB = (300, 500, 700)


def readings(hub: Hub, pressed: bool = True) -> Sensors:
    """What the physics side would read, as a function of the powers the program set: each motor's raw
    count (already in its set-up direction, as SensorModel gives it) 1000 + 7 * power."""
    powers, _ = hub.powers(4)
    hsv = spike_hub.hsv(RGB)
    return Sensors(reflect=spike_hub.reflection(RGB), ambient=0, color=ColorId.BLUE, rgb=RGB, ultrasonic_mm=2000,
                   gyro_angle_deg=0, gyro_rate_dps=0, touch=(10 if pressed else 0, 0), buttons=0b100001,
                   buttons_until_us=0, motor_angles_deg={p: 1000 + 7 * powers[p] for p in range(4)},
                   spike=HubReadings(hsv, (0, 0, 0), spike_hub.color(hsv), (0, 0, 0, 0)),
                   imu=Inertial((1.0, 2.0, 3.0), (0.0, 0.0, 9806.5)))


def frame(cmd: int, port: int, data: bytes = b"") -> bytes:
    """A frame as raspike.c 97-106 (and libraspike-art's raspike_prot_send) lays it out, written out here."""
    return bytes([0xEA, cmd, len(data), port]) + data


def test_the_handshake_answers_init_magic_and_the_version_libraspike_art_expects():
    hub = Hub(KINDS)
    assert hub.feed(b"\x00\x13") == b""  # raspike.c 858-869: anything before 0xAE 0xCE is skipped
    # 884-890: INIT, MAGIC, major, minor, patch; libraspike-art's src/expected_spike_version is 0.0.6
    assert hub.feed(b"\xae\xce") == bytes([0xAE, 0xCE, 0, 0, 6])
    assert hub.shook_hands


def test_a_configuration_is_acknowledged_with_whether_the_device_is_there():
    hub = Hub(KINDS)
    hub.feed(b"\xae\xce")
    # 179-183: ACK (0x02) carrying int32 cmd and int32 result; 400-409, 488-498: 1 when the device is there
    assert hub.feed(frame(0x60, 1)) == frame(0x02, 1, struct.pack("<ii", 0x60, 1))
    assert hub.feed(frame(0x60, 2)) == frame(0x02, 2, struct.pack("<ii", 0x60, 0))  # nothing on C
    assert hub.feed(frame(0x20, 0)) == frame(0x02, 0, struct.pack("<ii", 0x20, 0))  # A is a motor
    assert hub.feed(frame(0x20, 4)) == frame(0x02, 4, struct.pack("<ii", 0x20, 1))


def test_the_status_is_the_0_0_6_layout_libraspike_art_reads():
    hub = Hub(KINDS)
    hub.feed(b"\xae\xce" + frame(0x60, 0) + frame(0x20, 4) + frame(0x40, 3))
    hub.feed(frame(0x61, 0, struct.pack("<i?", 0, True).ljust(12, b"\0")) + frame(0x26, 4))
    out = hub.status(readings(hub), 10_000)
    # 802-806: ALL_STATUS (0x01) for port 255; 0.0.6's RPProtocolSpikeStatus (libraspike-art
    # raspike_protocol_com.h 190-199) is 2 + 2 + 12 + 12 + 4 + 6 * 16 = 128 bytes
    assert out[:4] == bytes([0xEA, 0x01, 128, 0xFF]) and len(out) == 4 + 128
    body = out[4:]
    voltage, current, *imu, buttons = struct.unpack_from("<HH3f3fI", body)
    assert (voltage, current) == (BATTERY_MV, BATTERY_MA)
    assert imu == [0.0, 0.0, 9806.5, 1.0, 2.0, 3.0]  # acceleration then angular velocity (193-194)
    assert buttons == (1 << 4) | (1 << 9)  # LEFT and BT: pbio's bits (button.h 51-54)
    ports = [struct.unpack_from("<BB2x12s", body, 32 + 16 * i) for i in range(6)]
    assert [p[0] for p in ports] == list(range(6))  # 894-896
    # 265-290: a set-up motor's count, speed, power (int16), stalled; the set-up reset the count (514-516)
    assert ports[0][1] == 0x61 and struct.unpack_from("<iih?", ports[0][2]) == (0, 0, 0, False)
    # 231-236: the reflection (int32) once asked, in the next status (325-330)
    assert ports[4][1] == 0x26 and struct.unpack_from("<i", ports[4][2])[0] == (300 + 500 + 700) * 100 // 3072
    # 252-262: force, distance (float), touched: a full 10 N press (forcesensor.c 74-81: whole N and mm)
    assert ports[3][1] == 0 and struct.unpack_from("<ff?", ports[3][2]) == (10.0, 6.0, True)
    assert ports[1][1:] == (0, bytes(12)) and ports[2][1:] == (0, bytes(12))  # not configured: nothing


def test_a_motor_reset_is_done_in_the_next_status_and_acknowledged_after_it():
    hub = Hub(KINDS)
    hub.feed(b"\xae\xce" + frame(0x60, 1) + frame(0x61, 1, bytes(12)) + frame(0x64, 1, struct.pack("<i", 40)))
    first = hub.status(readings(hub), 10_000)
    assert struct.unpack_from("<i", first, 4 + 32 + 16 + 4)[0] == 1000 + 280  # no reset at set-up
    assert hub.feed(frame(0x62, 1)) == b""  # 529-551: no immediate ack
    out = hub.status(readings(hub), 20_000)
    assert struct.unpack_from("<i", out, 4 + 32 + 16 + 4)[0] == 0  # 272-283: reset, then the count
    assert out[4 + 128:] == frame(0x02, 1, struct.pack("<ii", 0x62, 1))  # 789-800, after the status
    assert hub.status(readings(hub), 30_000)[4 + 128:] == b""  # owed once


def test_a_reset_before_the_set_up_is_acknowledged_and_dropped():
    hub = Hub(KINDS)
    hub.feed(b"\xae\xce" + frame(0x60, 1) + frame(0x64, 1, struct.pack("<i", 40)) + frame(0x62, 1))
    # 268-269: no set-up, no reset and no data; 789-800: the ack all the same, and the reset is gone
    assert hub.status(readings(hub), 10_000)[4 + 128:] == frame(0x02, 1, struct.pack("<ii", 0x62, 1))
    hub.feed(frame(0x61, 1, bytes(12)))
    assert struct.unpack_from("<i", hub.status(readings(hub), 20_000), 4 + 32 + 16 + 4)[0] == 1000 + 280


def test_a_reading_overwrites_only_its_own_bytes_of_the_port_data():
    hub = Hub(KINDS)
    hub.feed(b"\xae\xce" + frame(0x20, 4) + frame(0x21, 4))
    hub.status(readings(hub), 10_000)
    hub.feed(frame(0x26, 4))
    data = struct.unpack_from("<BB2x12s", hub.status(readings(hub), 20_000), 4 + 32 + 16 * 4)[2]
    # 211, 234: memcpy of the reflection over the RGB: bytes 4.. keep the blue channel
    assert data[:4] == struct.pack("<i", 48) and data[4:6] == struct.pack("<H", 700)


def test_power_is_reported_as_the_hub_does_for_the_set_up_direction():
    hub = Hub(KINDS)
    hub.feed(b"\xae\xce" + frame(0x60, 1) + frame(0x61, 1, struct.pack("<i", 1).ljust(12, b"\0")))
    hub.feed(frame(0x64, 1, struct.pack("<i", 55)))
    assert hub.powers(4) == ((0, 55, 0, 0), (0, 1, 0, 0))
    data = struct.unpack_from("<BB2x12s", hub.status(readings(hub), 10_000), 4 + 32 + 16)[2]
    assert struct.unpack_from("<h", data, 8)[0] == spike_hub.power_report(55, 1) == -55  # motor.c 116-124


def test_speed_is_the_counts_change_over_the_newest_100_ms_as_pbio_measures_it():
    # motor.c's speed_over (PBIO_CONFIG_DIFFERENTIATOR_WINDOW_MS 100): back to the newest sample 100 ms older
    counts = deque([(t * 10_000, 3 * t) for t in range(21)])  # 3 degrees per 10 ms
    assert speed_over(counts, 100_000) == 300
    assert speed_over(deque([(0, 5)]), 100_000) == 0  # one sample: no speed yet
    assert speed_over(deque([(0, 0), (10_000, -2)]), 100_000) == -200  # the oldest kept, when less is kept


@pytest.mark.parametrize("sent, words", [
    (b"\xae\xce\x13", ["malformed", "0x13"]),
    (b"\xae\xce" + frame(0x26, 4), ["0x26", "port E", "not configured"]),
    (b"\xae\xce" + frame(0x60, 9), ["port 9"]),
    (b"\xae\xce" + frame(0x60, 1) + frame(0x63, 1, bytes(4)), ["0x63", "set_speed"]),
    (b"\xae\xce" + frame(0xb5, 255), ["0xb5", "0.0.6"]),
])
def test_what_the_hub_cannot_take_is_a_fault_in_one_line(sent, words):
    with pytest.raises(HubFault) as e:
        Hub(KINDS).feed(sent)
    assert "\n" not in str(e.value) and all(w in str(e.value) for w in words)


@given(st.lists(st.binary(max_size=40), max_size=8))
def test_any_bytes_are_answered_or_refused_never_anything_else(chunks):
    hub = Hub(KINDS)
    hub.feed(b"\xae\xce")
    try:
        for chunk in chunks:
            out = hub.feed(chunk)
            while out:  # whatever comes back is whole frames
                assert out[0] == 0xEA and len(out) >= 4 + out[2]
                out = out[4 + out[2]:]
    except HubFault:
        pass


@given(st.lists(st.sampled_from([frame(0x60, 0), frame(0x61, 0, bytes(12)), frame(0x20, 4), frame(0x24, 4),
                                 frame(0x64, 0, struct.pack("<i", 30)), frame(0x62, 0), frame(0xa2, 255)]),
                max_size=12), st.integers(1, 30))
def test_frames_split_anywhere_get_the_same_answers(frames, cut):
    stream = b"\xae\xce" + b"".join(frames)
    whole = Hub(KINDS)
    split = Hub(KINDS)
    try:
        expected = whole.feed(stream)
    except HubFault:
        return
    got = b"".join(split.feed(stream[i:i + cut]) for i in range(0, len(stream), cut))
    assert got == expected


def compile_probe(out: Path, version: str | None = None) -> Path:
    """The probe with the Pi's libraspike-art, natively, as libraspike-art's own Makefile compiles it
    (build/obj-libraspike-art/Makefile: the version from src/expected_spike_version, unless `version`
    says another), or a skip."""
    if not LIBRASPIKE_ART.is_dir():
        pytest.skip(needs_shared("libraspike-art", LIBRASPIKE_ART, RASPIKE_ART))
    if shutil.which("gcc") is None:
        pytest.skip("needs gcc (apt-get install gcc) to compile libraspike-art natively")
    expected = version or (LIBRASPIKE_ART / "src" / "expected_spike_version").read_text().strip()
    major, minor, patch = expected.split(".")
    includes = ["include", "src", "drivers/include", "drivers/include/spike/pup", "drivers/include/spike/hub",
                "drivers", "external/libpybricks/lib/pbio/include/pbio", "external/libpybricks/lib/pbio/include"]
    sources = ["raspike_protocol.c", "raspike_com.c", "raspike_color.c", "raspike_forcesensor.c", "raspike_motor.c",
               "raspike_ultrasonicsensor.c", "raspike_hub.c"]
    subprocess.run(["gcc", "-O1", "-o", str(out), *(f"-I{LIBRASPIKE_ART / i}" for i in includes),
                    f"-DSPIKE_EXPECTED_VERSION_MAJOR={major}", f"-DSPIKE_EXPECTED_VERSION_MINOR={minor}",
                    f"-DSPIKE_EXPECTED_VERSION_PATCH={patch}", str(PROBE),
                    *(str(LIBRASPIKE_ART / "src" / s) for s in sources), "-pthread"], check=True, timeout=120)
    return out


def run_against_the_hub(program: Path, pressed: bool = True) -> tuple[int, str]:
    """Run the probe against a hub on a pty, the hub pumped every millisecond of wall time with the status
    every 10 ms, until it ends; its exit status and output."""
    hub = PtyHub(Hub(KINDS))
    proc = subprocess.Popen([str(program), hub.device], stdout=subprocess.PIPE, text=True)
    start = time.monotonic()
    try:
        while proc.poll() is None and time.monotonic() - start < 20:
            try:
                hub.pump(partial(readings, hub.hub, pressed), int((time.monotonic() - start) * 1e6))
            except HubFault:  # the probe closed its port: it is done
                break
            select.select([hub.master], [], [], 0.001)
        out, _ = proc.communicate(timeout=5)
    finally:
        if proc.poll() is None:
            proc.kill()
        hub.close()
    return proc.returncode, out


def test_libraspike_art_itself_reads_what_the_hub_sends(tmp_path):
    status, out = run_against_the_hub(compile_probe(tmp_path / "probe"))
    assert status == 0, out
    lines = {line.split()[0]: line.split()[1:] for line in out.splitlines() if line.split()}
    assert lines["devices"] == ["1", "1", "1", "1", "0"]  # nothing on C: NULL, as the real hub's ack 0
    assert lines["setup"] == ["1", "1"]
    # raw 1000 + 7 * power, zeroed at the set-up (reset_count true) when the power was 0
    assert lines["count"] == [str(7 * 50), str(7 * -30)]
    assert lines["speed"] == ["0", "0"] and lines["stalled"] == ["1", "1"]  # driven 200 ms, never moving
    hsv = spike_hub.hsv(RGB)
    assert lines["reflection"] == [str(spike_hub.reflection(RGB))]
    assert lines["rgb"] == [str(c) for c in RGB]
    assert lines["hsv"] == [str(c) for c in hsv]
    assert lines["color"] == [str(c) for c in spike_hub.color(hsv)]
    assert lines["force"] == ["10.0", "6.0", "1"]
    assert lines["imu"] == ["0.0", "0.0", "9806.5", "1.0", "2.0", "3.0"]
    assert lines["hub"] == [str(BATTERY_MV), str(BATTERY_MA), str((1 << 4) | (1 << 9))]
    assert lines["reset"] == ["1"] and lines["after_reset"] == ["0"]  # still at power 50: no move since
    assert lines["stop"] == ["1"]


def test_a_pi_that_expects_another_version_stops_at_the_handshake(tmp_path):
    # libraspike-art raspike_protocol.c 161-174: the three version bytes after INIT MAGIC, compared with its
    # own, and exit(-1) with a line when they differ (protocol 0.1.0: RasPike-ART 46d328e's libraspike-art)
    status, out = run_against_the_hub(compile_probe(tmp_path / "probe", "0.1.0"))
    assert status == 255 and "version=0.0.6 expected=0.1.0" in out and "mismatched" in out


def test_in_the_lockstep_the_hub_takes_exactly_what_the_program_counted_and_counts_its_own(tmp_path):
    """What asp_serial.c relies on: between two steps the hub reads the bytes asp says it sent, however the
    pty delivers them, answers them, and says how many it sent in all and when it sends its next status; the
    counts lie where the generated header tells asp they do (rundir.RASPIKE_SERIAL)."""
    hub = PtyHub(Hub(KINDS))
    counts = SerialCounts(tmp_path)
    fd = os.open(hub.device, os.O_RDWR | os.O_NOCTTY)
    try:
        os.write(fd, b"\xae")
        os.write(fd, b"\xce")  # two writes, one count
        raw = (tmp_path / rundir.RASPIKE_SERIAL).read_bytes()
        assert len(raw) == rundir.RASPIKE_SERIAL_SIZE and counts.program_sent == 0
        assert hub.next_status_us == NEVER_WAKES  # none before the handshake
        with (tmp_path / rundir.RASPIKE_SERIAL).open("r+b") as f:  # as asp's write does
            f.seek(rundir.RASPIKE_PROGRAM_SENT)
            f.write(struct.pack("<Q", 2))
        sent = hub.exchange(lambda: readings(hub.hub), 0, counts.program_sent)
        assert sent == 5 + 4 + 128  # the version (raspike.c 858-890), then the first status
        counts.publish(sent, hub.next_status_us)
        raw = (tmp_path / rundir.RASPIKE_SERIAL).read_bytes()
        assert struct.unpack_from("<Q", raw, rundir.RASPIKE_HUB_SENT) == (sent,)
        assert struct.unpack_from("<q", raw, rundir.RASPIKE_HUB_NEXT_STATUS) == (RASPIKE_STATUS_PERIOD_US,)
        got = b""
        while len(got) < sent:
            got += os.read(fd, sent - len(got))
        assert got[:5] == bytes([0xAE, 0xCE, 0, 0, 6]) and got[5] == 0xEA
        assert hub.exchange(lambda: readings(hub.hub), 1_000, 2) == sent  # nothing new, no status due: nothing sent
    finally:
        os.close(fd)
        counts.close()
        hub.close()


def test_bytes_the_program_counted_but_never_sent_are_a_fault(tmp_path, monkeypatch):
    monkeypatch.setattr("hakoniwa.physics.raspike_hub.DELIVERY_LIMIT_S", 0.2)
    hub = PtyHub(Hub(KINDS))
    try:
        with pytest.raises(HubFault, match="did not reach the hub"):
            hub.exchange(None, 0, 2)
    finally:
        hub.close()


def test_a_program_that_closes_the_port_is_a_fault(tmp_path):
    hub = PtyHub(Hub(KINDS))
    try:
        fd = os.open(hub.device, os.O_RDWR | os.O_NOCTTY)
        os.write(fd, b"\xae\xce")
        hub.pump(None, 0)
        assert os.read(fd, 5) == bytes([0xAE, 0xCE, 0, 0, 6])
        os.close(fd)
        with pytest.raises(HubFault, match="closed"):
            hub.pump(None, 10_000)
    finally:
        hub.close()


@pytest.mark.slow
def test_raspike_arts_own_sample_in_its_asp_under_qemu_drives_the_hub(tmp_path):
    """sample_c5_spike's asp, built by RasPike-ART's make, against the hub: it configures the force sensor,
    waits for the press, then sets the motors up and drives them by the reflection."""
    from athrill_sim.raspike_art import AspError
    from athrill_sim.raspike_art.build import DEFAULT_FOLDER, build_asp
    from athrill_sim.raspike_art.launch import asp_argv, prefix_folder

    if not DEFAULT_FOLDER.is_dir():
        pytest.skip(needs_shared("RasPike-ART", DEFAULT_FOLDER, RASPIKE_ART))
    try:
        asp = build_asp(DEFAULT_FOLDER / "sdk" / "workspace" / "sample_c5_spike")
        hub = PtyHub(Hub(KINDS))
        argv = asp_argv(asp, prefix_folder(tmp_path / "prefix", hub.device))
    except AspError as e:
        pytest.skip(f"cannot build or start RasPike-ART's asp: {e}")
    proc = subprocess.Popen(argv, cwd=tmp_path, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    start, pressed_at = time.monotonic(), None
    try:
        while proc.poll() is None and time.monotonic() - start < 60:
            now = time.monotonic() - start
            if pressed_at is None and hub.hub.ports[3].configured:
                pressed_at = now + 0.5  # the program waits on the force sensor: press it a little later
            hub.pump(partial(readings, hub.hub, pressed=pressed_at is not None and now >= pressed_at), int(now * 1e6))
            if hub.hub.powers(4)[0] != (0, 0, 0, 0):
                break
            select.select([hub.master], [], [], 0.001)
    finally:
        proc.kill()
        proc.wait()
        hub.close()
    assert pressed_at is not None, "asp never configured the force sensor on D"
    # LineTracer.c 52-79 with LineTracer.h: target (40 + 10) / 2 = 25, reflection 48, steering
    # (int16_t)((25 - 48) * 1.5F) = -34; left (B) 30 + -34, right (A) 30 - -34; left counter-clockwise (24-25)
    assert hub.hub.powers(4) == ((64, -4, 0, 0), (0, 1, 0, 0))
    assert hub.hub.ports[4].cmd == 0x26  # the reflection asked of the colour sensor on E

"""The UDP relay between the mapped files and athrill2's `vdev_udp` device (hakoniwa/physics/relay.py),
against a stand-in for athrill2's side written from vdev_udp.c: it binds its RX port, takes the unity time
from each RX packet it accepts, and sends its TX window as a packet from a fresh socket. Every socket is bound
to 127.0.0.1."""

import socket
import struct
import time
from pathlib import Path

import pytest

from hakoniwa.physics.relay import UdpRelay
from hakoniwa.physics.slots import Slots
from hakoniwa.wire.packets import TX_BODY_SIZE, TxPacket, decode_rx, encode_tx
from hakoniwa.wire.protocol import Rx, Tx
from hakoniwa.wire.vdev_udp import UDP_DEVICE_CONFIG, Endpoint, bench_link, lookup, parse_device_config, user_link

WAIT_S = 5.0


class FakeAthrill:
    """athrill2's half of the link: RX on its bound port, TX to the physics side's."""

    def __init__(self, run_dir: Path) -> None:
        pairs = parse_device_config((run_dir / UDP_DEVICE_CONFIG).read_text())
        self.physics = ("127.0.0.1", lookup(pairs, "DEBUG_FUNC_VDEV_TX_PORTNO", int))
        self.sock = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
        self.sock.bind(("127.0.0.1", lookup(pairs, "DEBUG_FUNC_VDEV_RX_PORTNO", int)))
        self.sock.settimeout(WAIT_S)
        self.body = bytearray(TX_BODY_SIZE)

    def receive(self) -> tuple[int, bytes]:
        return decode_rx(self.sock.recv(4096))

    def send(self, athrill_us: int, unity_us: int = 0) -> None:
        with socket.socket(socket.AF_INET, socket.SOCK_DGRAM) as out:  # udp_comm_remote_write: a fresh socket
            out.sendto(encode_tx(TxPacket(athrill_us, unity_us, bytes(self.body))), self.physics)

    def close(self) -> None:
        self.sock.close()


@pytest.fixture
def bench(tmp_path):
    """A relay with its own ports, in a test that has begun (`launching`)."""
    slots = Slots(tmp_path)
    notes: list[str] = []
    relay = UdpRelay(bench_link([("DEBUG_FUNC_ENABLE_VDEV", "1")]), slots, tmp_path, notes.append)
    relay.launching()
    yield relay, slots, notes
    relay.close()


@pytest.fixture
def athrill(bench, tmp_path):
    """athrill2's side, bound to the port the bench's device config names."""
    fake = FakeAthrill(tmp_path)
    yield fake
    fake.close()


def wait_until(relay: UdpRelay, ready) -> None:
    deadline = time.monotonic() + WAIT_S

    def give_up() -> None:
        assert time.monotonic() < deadline, "timed out"

    relay.wait_for(ready, give_up)


def test_each_publication_reaches_athrill_as_the_file_holds_it(bench, athrill):
    relay, slots, _ = bench
    slots.unity.write_f32(Rx.KP, 1.5)
    slots.unity.unity_time_us = 20000
    relay.published()
    unity_us, body = athrill.receive()
    assert unity_us == 20000 and body == slots.unity.read_bytes(0, len(body))
    assert struct.unpack_from("<f", body, Rx.KP)[0] == 1.5


def test_athrills_packets_reach_the_tx_file_and_leave_the_controllers_flags(bench, athrill):
    relay, slots, notes = bench
    slots.athrill.write_i32(Tx.START, 1)
    struct.pack_into("<i", athrill.body, Tx.MOTOR_POWER + 4, 35)
    athrill.send(10184, 20000)
    with socket.socket(socket.AF_INET, socket.SOCK_DGRAM) as stranger:
        stranger.sendto(b"hello", athrill.physics)
    wait_until(relay, lambda: slots.athrill.athrill_time_us == 10184)
    assert slots.athrill.read_i32(Tx.MOTOR_POWER + 4) == 35 and slots.athrill.unity_time_us == 20000
    assert slots.athrill.read_i32(Tx.START) == 1
    assert slots.take_commands().powers[1] == 35
    assert notes and "not athrill2's" in notes[0]


def test_until_athrill_is_heard_from_the_latest_rx_packet_is_sent_again(bench, tmp_path):
    """A packet sent before athrill2 has bound its port is lost, and until one arrives athrill2 runs
    unchecked: the relay repeats the latest one while it waits."""
    relay, slots, _ = bench
    slots.unity.unity_time_us = 20000
    relay.published()  # nobody listens yet
    athrill = FakeAthrill(tmp_path)  # athrill2 binds its port now
    athrill.sock.setblocking(False)
    got = []

    def heard() -> bool:  # athrill2's receiving thread, looked at while the relay waits
        try:
            got.append(athrill.receive())
        except BlockingIOError:
            return False
        return True

    try:
        wait_until(relay, heard)
        assert got[0][0] == 20000
    finally:
        athrill.close()


def test_a_new_test_starts_without_the_last_athrills_packets(bench, athrill):
    relay, slots, _ = bench
    athrill.send(59000)
    wait_until(relay, lambda: slots.athrill.athrill_time_us == 59000)
    athrill.send(60000)  # in flight when the test ends (loopback: queued once sent)
    relay.ended()
    slots.athrill.athrill_time_us = 0
    relay.launching()
    relay.receive()
    assert slots.athrill.athrill_time_us == 0


def test_two_benches_write_device_configs_with_ports_of_their_own(tmp_path):
    relays = []
    try:
        for name in ("a", "b"):
            (tmp_path / name).mkdir()
            relays.append(UdpRelay(bench_link([]), Slots(tmp_path / name), tmp_path / name, print))
        ports = [FakeAthrill(tmp_path / name) for name in ("a", "b")]
        assert len({*(p.physics for p in ports), *(p.sock.getsockname() for p in ports)}) == 4
        for p in ports:
            p.close()
    finally:
        for relay in relays:
            relay.close()


def test_a_user_configs_ports_are_held_only_while_a_test_runs(tmp_path):
    with socket.socket(socket.AF_INET, socket.SOCK_DGRAM) as probe:
        probe.bind(("127.0.0.1", 0))
        port = probe.getsockname()[1]
    path = tmp_path / "etroboc.txt"
    path.write_text(f"DEBUG_FUNC_ENABLE_VDEV\t\t1\nDEBUG_FUNC_VDEV_TX_PORTNO   {port}\n"
                    f"DEBUG_FUNC_VDEV_TX_IPADDR\t127.0.0.1\nDEBUG_FUNC_VDEV_RX_PORTNO   {port + 1}\n")
    link = user_link(path)
    first, second = (UdpRelay(link, Slots(tmp_path), tmp_path, print) for _ in range(2))  # a worker's bench and
    try:                                                                                  # the best set's
        assert (tmp_path / UDP_DEVICE_CONFIG).read_bytes() == path.read_bytes()
        first.launching()
        assert link.physics == Endpoint("127.0.0.1", port)
        with pytest.raises(OSError, match=f"127.0.0.1:{port} .* in use"):
            second.launching()
        first.ended()
        second.launching()
    finally:
        first.close()
        second.close()

"""athrill2's UDP packets as pieces of the mapped files (hakoniwa/wire/packets.py), pinned against
`vdev.h` / `vdev_udp.c` of ../shared/third_party/athrill, written out independently here."""

import struct

import pytest
from hypothesis import given
from hypothesis import strategies as st

from hakoniwa.wire.packets import (
    REQUESTS,
    RX_PACKET_SIZE,
    TX_BODY_SIZE,
    TX_PACKET_SIZE,
    TX_TAKEN_END,
    PacketError,
    TxPacket,
    decode_rx,
    decode_tx,
    encode_tx,
    merge_requests,
    rx_packet,
    store_tx,
)
from hakoniwa.wire.protocol import PARAM_END, Rx, Tx, open_athrill, open_unity

# vdev.h: VDEV_TX_DATA_COMM_SIZE 1024, a 32-byte header (magic ETTX, version 1, micon time at 8, unity time
# at 16, ext_off / ext_size 512 at 24 / 28); vdev_udp_packet_check's RX checks.
VDEV_COMM_SIZE = 1024
RX_CHECKS = {0: b"ETRX", 4: 1, 24: 512, 28: 512}  # p[0..3], p_int[1], p_int[6], p_int[7]
RX_SIM_TIME = 16  # VDEV_RX_SIM_TIME(VDEV_SIM_INX_ME)
RESET_AREA = (68, 20)  # ET Robocon's DEVICE_CONFIG_RESET_AREA_OFFSET / _SIZE: packet bytes of the reset flags

times = st.integers(0, (1 << 64) - 1)
bodies = st.binary(min_size=TX_BODY_SIZE, max_size=TX_BODY_SIZE)


def test_sizes_and_the_reset_area_are_athrill2s():
    assert TX_PACKET_SIZE == VDEV_COMM_SIZE and TX_BODY_SIZE == VDEV_COMM_SIZE - 32
    assert RX_PACKET_SIZE == 32 + PARAM_END  # every parameter a campaign writes reaches the program
    assert (REQUESTS[0] + 32, REQUESTS[1] - REQUESTS[0]) == RESET_AREA
    assert TX_TAKEN_END <= Tx.START  # the controller's flags are never taken from a packet


@given(times, times, bodies)
def test_a_tx_packet_has_athrill2s_header_and_decodes_to_itself(athrill_us, unity_us, body):
    data = encode_tx(TxPacket(athrill_us, unity_us, body))
    assert len(data) == VDEV_COMM_SIZE
    assert data[0:4] == b"ETTX" and struct.unpack_from("<I", data, 4)[0] == 1
    assert struct.unpack_from("<QQII", data, 8) == (athrill_us, unity_us, 512, 512)
    assert data[32:] == body
    assert decode_tx(data) == TxPacket(athrill_us, unity_us, body)


@given(st.sampled_from([0, 4, 24, 28]), st.integers(1, 255), times, bodies)
def test_a_tx_packet_with_a_wrong_header_field_is_refused(offset, delta, athrill_us, body):
    data = bytearray(encode_tx(TxPacket(athrill_us, 0, body)))
    data[offset] = (data[offset] + delta) % 256
    with pytest.raises(PacketError):
        decode_tx(bytes(data))


@given(st.binary(max_size=2 * VDEV_COMM_SIZE).filter(lambda b: len(b) != VDEV_COMM_SIZE))
def test_a_datagram_of_another_length_is_not_athrill2s(data):
    with pytest.raises(PacketError, match="bytes"):
        decode_tx(data)


@given(times, st.binary(min_size=PARAM_END, max_size=PARAM_END))
def test_the_rx_packet_is_the_start_of_unity_mmap_bin_as_athrill2_checks_it(tmp_path_factory, unity_us, body):
    with open_unity(tmp_path_factory.mktemp("rx"), create=True) as unity:
        unity.write_bytes(0, body)
        unity.unity_time_us = unity_us
        data = rx_packet(unity)
    assert len(data) == RX_PACKET_SIZE
    for offset, want in RX_CHECKS.items():
        got = data[offset:offset + 4]
        assert got == (want if isinstance(want, bytes) else struct.pack("<I", want))
    assert struct.unpack_from("<Q", data, RX_SIM_TIME)[0] == unity_us
    assert decode_rx(data) == (unity_us, body)
    assert data[32 + Rx.KP:32 + Rx.KP + 4] == body[Rx.KP:Rx.KP + 4]  # the guest reads body k at packet 32 + k


def test_an_rx_packet_with_a_foreign_header_is_refused():
    with pytest.raises(PacketError, match="magic"):
        decode_rx(encode_tx(TxPacket(0, 0, bytes(TX_BODY_SIZE))))
    with pytest.raises(PacketError, match="shorter"):
        decode_rx(b"ETRX")


words = st.lists(st.sampled_from([0, 1, 2, -1]), min_size=TX_TAKEN_END // 4, max_size=TX_TAKEN_END // 4)


@given(words, words)
def test_a_packet_never_lowers_a_reset_request_the_physics_side_has_not_taken(held_words, sent_words):
    held, sent = (struct.pack(f"<{len(w)}i", *w) for w in (held_words, sent_words))
    out = struct.unpack(f"<{len(sent_words)}i", merge_requests(held, sent))
    for i, (h, s, o) in enumerate(zip(held_words, sent_words, out)):
        in_requests = REQUESTS[0] <= 4 * i < REQUESTS[1]
        assert o == (s if s or not in_requests else h), i


def test_store_tx_writes_times_and_the_body_below_the_ext_area_only(tmp_path):
    with open_athrill(tmp_path, create=True) as athrill:
        athrill.write_i32(Tx.START, 1)
        athrill.write_i32(Tx.END, 7)
        body = bytearray(b"\xAB" * TX_BODY_SIZE)
        struct.pack_into("<i", body, Tx.MOTOR_POWER, -40)
        struct.pack_into("<i", body, Tx.MOTOR_RESET_ANGLE + 4, 1)
        store_tx(TxPacket(123456, 120000, bytes(body)), athrill)
        assert (athrill.athrill_time_us, athrill.unity_time_us) == (123456, 120000)
        assert athrill.read_i32(Tx.MOTOR_POWER) == -40
        assert (athrill.read_i32(Tx.START), athrill.read_i32(Tx.END)) == (1, 7)  # the controller's, untouched
        athrill.write_i32(Tx.MOTOR_RESET_ANGLE + 4, 0)  # the physics side takes the request ...
        struct.pack_into("<i", body, Tx.MOTOR_RESET_ANGLE + 4, 0)
        store_tx(TxPacket(133456, 130000, bytes(body)), athrill)
        assert athrill.read_i32(Tx.MOTOR_RESET_ANGLE + 4) == 0  # ... and the next packet does not raise it again
        struct.pack_into("<i", body, Tx.GYRO_RESET, 1)
        store_tx(TxPacket(143456, 140000, bytes(body)), athrill)
        struct.pack_into("<i", body, Tx.GYRO_RESET, 0)
        store_tx(TxPacket(153456, 150000, bytes(body)), athrill)  # two packets before the physics side looks
        assert athrill.read_i32(Tx.GYRO_RESET) == 1

"""athrill2's UDP packets (its `vdev_udp` device, the transport of ET Robocon's simulator) as pieces of the
two mapped files.

Over UDP each packet is the start of a mapped file as it is over mmap: the same 32-byte header (magic, version,
the two simulation times, ext_off 512, ext_size 512), then the body at the same offsets. So the bench keeps the
files as its state and relays packets into and out of them (`hakoniwa.physics.relay`); nothing else changes.
What athrill2 does, read from `src/device/peripheral/vdev/vdev_udp.c` and `athrill/src/lib/udp/udp_comm.c`:

- TX (Athrill -> physics): 1024 bytes (`VDEV_TX_DATA_COMM_SIZE`), the header and TX body 0..991, sent whenever
  the program stores a byte at 0x090F2000 (`VDEV_TX_FLAG(0)`); EV3RT's brick cyclic does that every 10 ms
  (`gpio_out_flush`, then it clears the reset requests it raised). Its clock and its echo of the last unity
  time it received are copied into the header at that moment, not at every device clock as over mmap.
- RX (physics -> Athrill): a receiving thread checks magic ETRX, version, ext_off and ext_size (not the
  length), copies the whole datagram over the start of its RX window and takes the unity time from it.
  Until the first one arrives the unity time is 0, which lets Athrill run unchecked.

The TX body Athrill sends is the guest's; the test automation's area (ext, body 512..) of `athrill_mmap.bin`
is the controller's (start and end flags), so only body 0..511 is taken from a packet. Reset requests are kept
until the physics side takes them: a packet never lowers one (EV3RT raises each in one packet only).
"""

from __future__ import annotations

import struct
from dataclasses import dataclass

from hakoniwa.wire.errors import HakoError
from hakoniwa.wire.protocol import (
    ATHRILL_MAGIC,
    EXT_OFF,
    EXT_SIZE,
    HEADER_SIZE,
    LAYOUT_VERSION,
    PACKET_SIZE,
    PARAM_END,
    UNITY_MAGIC,
    MappedFile,
    Tx,
)

TX_PACKET_SIZE = PACKET_SIZE  # VDEV_TX_DATA_COMM_SIZE: header + TX body 0..991
TX_BODY_SIZE = TX_PACKET_SIZE - HEADER_SIZE
TX_TAKEN_END = EXT_OFF  # TX body bytes a packet carries into athrill_mmap.bin; the ext area is the controller's
# The real Unity sends 1024 bytes; ours carries the RX body up to the end of the parameter area, so that every
# parameter a campaign writes reaches the program as over mmap (athrill2 copies whatever length arrives).
RX_PACKET_SIZE = HEADER_SIZE + PARAM_END
REQUESTS = (Tx.MOTOR_RESET_ANGLE, Tx.GYRO_RESET + 4)  # body words EV3RT raises and the physics side lowers
MAX_DATAGRAM = 4096  # athrill2's UDP_BUFFER_LEN: no packet of either side is longer

_TX_HEADER = struct.Struct("<4sIQQII")  # magic, version, athrill time, unity time (echo), ext_off, ext_size
_RX_HEADER = struct.Struct("<4sI8xQII")  # magic, version, reserved, unity time, ext_off, ext_size


class PacketError(HakoError, ValueError):
    """A datagram that is not the packet its sender should send; the message says what is wrong."""


@dataclass(frozen=True)
class TxPacket:
    """What athrill2 sends: its clock, its echo of the unity time, and the TX body 0..TX_BODY_SIZE."""

    athrill_time_us: int
    unity_time_us: int
    body: bytes


def encode_tx(packet: TxPacket) -> bytes:
    if len(packet.body) != TX_BODY_SIZE:
        raise PacketError(f"a TX body is {TX_BODY_SIZE} bytes, not {len(packet.body)}")
    return _TX_HEADER.pack(ATHRILL_MAGIC, LAYOUT_VERSION, packet.athrill_time_us, packet.unity_time_us,
                           EXT_OFF, EXT_SIZE) + packet.body


def decode_tx(data: bytes) -> TxPacket:
    if len(data) != TX_PACKET_SIZE:
        raise PacketError(f"{len(data)} bytes, expected {TX_PACKET_SIZE}")
    magic, version, athrill_us, unity_us, ext_off, ext_size = _TX_HEADER.unpack_from(data)
    _check_header(magic, ATHRILL_MAGIC, version, ext_off, ext_size)
    return TxPacket(athrill_us, unity_us, bytes(data[HEADER_SIZE:]))


def rx_packet(unity: MappedFile) -> bytes:
    """The packet that hands Athrill what `unity_mmap.bin` holds now."""
    return unity.file_bytes(RX_PACKET_SIZE)


def decode_rx(data: bytes) -> tuple[int, bytes]:
    """(unity time, body) of an RX packet, checked as athrill2's `vdev_udp_packet_check` does."""
    if len(data) < HEADER_SIZE:
        raise PacketError(f"{len(data)} bytes, shorter than the {HEADER_SIZE}-byte header")
    magic, version, unity_us, ext_off, ext_size = _RX_HEADER.unpack_from(data)
    _check_header(magic, UNITY_MAGIC, version, ext_off, ext_size)
    return unity_us, bytes(data[HEADER_SIZE:])


def _check_header(magic: bytes, expected: bytes, version: int, ext_off: int, ext_size: int) -> None:
    if magic != expected:
        raise PacketError(f"magic {magic!r}, expected {expected!r}")
    if version != LAYOUT_VERSION:
        raise PacketError(f"version {version}, expected {LAYOUT_VERSION}")
    if (ext_off, ext_size) != (EXT_OFF, EXT_SIZE):
        raise PacketError(f"ext_off/ext_size {ext_off}/{ext_size}, expected {EXT_OFF}/{EXT_SIZE}")


def merge_requests(held: bytes, sent: bytes) -> bytes:
    """The TX body to hold: `sent` (a packet's), except that a reset request still `held` (raised by an
    earlier packet, not yet taken by the physics side) stays raised where the packet has none."""
    out = bytearray(sent)
    for at in range(*REQUESTS, 4):
        if not any(sent[at:at + 4]):
            out[at:at + 4] = held[at:at + 4]
    return bytes(out)


def store_tx(packet: TxPacket, athrill: MappedFile) -> None:
    """Write a TX packet into `athrill_mmap.bin` as athrill2 writes the file over mmap: the body first, then
    its echo of the unity time, then its clock (last: whoever sees the clock sees the commands of that time)."""
    athrill.write_bytes(0, merge_requests(athrill.read_bytes(0, TX_TAKEN_END), packet.body[:TX_TAKEN_END]))
    athrill.unity_time_us = packet.unity_time_us
    athrill.athrill_time_us = packet.athrill_time_us

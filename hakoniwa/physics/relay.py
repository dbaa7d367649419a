"""How the physics side's mapped files reach Athrill: directly (mmap), or relayed as athrill2's UDP packets.

Over UDP the two files stay the bench's state: the sync loop, the slots, the controller and the reports read
and write them exactly as over mmap. The relay copies each TX packet athrill2 sends into `athrill_mmap.bin`
(`hakoniwa.wire.packets.store_tx`: its clock, its echo and the TX body below the ext area) whenever the loop
looks for Athrill's news, and sends `unity_mmap.bin`'s content as an RX packet each time the loop has
published a snapshot and its unity time, so Athrill sees what it would see in the file, at the same moments.

Two things UDP adds. Athrill's clock reaches the physics side only with its packets (EV3RT's brick cyclic,
every 10 emulated ms), not at every device clock. And a packet sent before athrill2 has bound its port is
lost, while athrill2 runs unchecked until its first RX packet (a unity time of 0): so the latest RX packet is
sent again every FIRST_RESEND_S of wall time until Athrill's first packet arrives, and every RESEND_S without
news after that, which also heals a lost packet (resending the same content changes nothing for Athrill).
"""

from __future__ import annotations

import select
import socket
import time
from collections.abc import Callable
from pathlib import Path
from typing import Protocol

from hakoniwa.physics.sensors import Sensors
from hakoniwa.physics.slots import Slots
from hakoniwa.wire.packets import MAX_DATAGRAM, PacketError, decode_tx, rx_packet, store_tx
from hakoniwa.wire.vdev_udp import UDP_DEVICE_CONFIG, LinkError, UdpLink, bind_fixed, bind_pair, check_free
from hakoniwa.wire.waiting import CHECK_EVERY_S, wait_for

FIRST_RESEND_S = 0.0005  # until athrill2's first packet: how long it may run unchecked after binding its port
RESEND_S = 0.02  # after that: the RX packet again when Athrill has been silent this long


class Transport(Protocol):
    reads_files: bool
    """Whether the program reads its sensors from `unity_mmap.bin` (Athrill does; RasPike-ART's asp hears the
    hub instead)."""

    def launching(self) -> None:
        """Just before this test's Athrill starts; OSError if it cannot (the bench's fault)."""

    def publishing(self, read: Callable[[], Sensors], now_us: int) -> None:
        """The loop is about to publish the snapshot of `now_us`, whose readings `read()` takes: a device the
        physics side plays answers first (`hub_relay.HubRelay`), and reads them only when it sends them."""

    def published(self) -> None:
        """The loop has published a snapshot and its unity time into `unity_mmap.bin`."""

    def answered(self, now_us: int) -> None:
        """Athrill has answered the snapshot of `now_us`: what it asked of a device the physics side plays goes
        where its commands are taken from (`athrill_mmap.bin`)."""

    def receive(self) -> None:
        """Bring what Athrill has sent into `athrill_mmap.bin`."""

    def wait_for(self, ready: Callable[[], bool], on_idle: Callable[[], None]) -> None:
        """`hakoniwa.wire.waiting.wait_for`, receiving meanwhile."""

    def ended(self) -> None:
        """This test's Athrill has been stopped."""

    def close(self) -> None: ...


class MappedFiles:
    """The mmap transport: Athrill reads and writes the files themselves; there is nothing to relay."""

    reads_files = True

    def launching(self) -> None:
        pass

    def publishing(self, read: Callable[[], Sensors], now_us: int) -> None:
        pass

    def published(self) -> None:
        pass

    def answered(self, now_us: int) -> None:
        pass

    def receive(self) -> None:
        pass

    def wait_for(self, ready: Callable[[], bool], on_idle: Callable[[], None]) -> None:
        wait_for(ready, on_idle)

    def ended(self) -> None:
        pass

    def close(self) -> None:
        pass


class UdpRelay:
    """The UDP transport, between the files and athrill2's `vdev_udp` device. A bench's own pair of ports is
    held for its life (the pair is then its own); the ports a user's device config fixes are bound only while a
    test runs, so benches that never test at the same time (a campaign's worker and the bench that draws its
    best set) can share them."""

    reads_files = True

    def __init__(self, link: UdpLink, slots: Slots, run_dir: Path, log: Callable[[str], None]) -> None:
        self.link = link
        self.slots = slots
        self.log = log
        self._sock: socket.socket | None = None
        if link.fixed:
            check_free(link)
            physics, athrill = link.physics, link.athrill
        else:
            self._sock, physics, athrill = bind_pair(link)
        self.athrill_endpoint = athrill
        (run_dir / UDP_DEVICE_CONFIG).write_bytes(link.device_config(physics.port, athrill.port))
        self._heard = False  # whether this test's Athrill has sent anything yet
        self._dropped = 0  # datagrams of this test that were not athrill2's packets

    def launching(self) -> None:
        if self.link.fixed:
            try:
                self._sock = bind_fixed(self.link)
            except LinkError as e:
                raise OSError(str(e)) from None
        else:
            self._drain()  # the last test's Athrill is dead: what it sent is all here, and stale
        self._heard = False
        self._dropped = 0

    def publishing(self, read: Callable[[], Sensors], now_us: int) -> None:
        pass

    def answered(self, now_us: int) -> None:
        pass

    def published(self) -> None:
        if self._sock is not None:
            self._sock.sendto(rx_packet(self.slots.unity), (self.athrill_endpoint.addr, self.athrill_endpoint.port))

    def receive(self) -> None:
        for data in self._drain():
            try:
                packet = decode_tx(data)
            except PacketError as e:
                self._dropped += 1
                if self._dropped == 1:
                    self.log(f"dropped a datagram that is not athrill2's TX packet ({e})")
                continue
            store_tx(packet, self.slots.athrill)
            self._heard = True

    def _drain(self) -> list[bytes]:
        out = []
        while self._sock is not None:
            try:
                out.append(self._sock.recv(MAX_DATAGRAM, socket.MSG_DONTWAIT))
            except BlockingIOError:
                break
        return out

    def wait_for(self, ready: Callable[[], bool], on_idle: Callable[[], None]) -> None:
        """Sleep on the socket (the packet is the doorbell), sending the RX packet again on silence."""
        next_check = time.monotonic() + CHECK_EVERY_S
        self.receive()
        while not ready():
            timeout = RESEND_S if self._heard else FIRST_RESEND_S
            if self._sock is None or not select.select([self._sock], [], [], timeout)[0]:
                self.published()
            self.receive()
            now = time.monotonic()
            if now > next_check:
                next_check = now + CHECK_EVERY_S
                on_idle()

    def ended(self) -> None:
        if self.link.fixed:
            self.close()

    def close(self) -> None:
        if self._sock is not None:
            self._sock.close()
            self._sock = None


"""Where athrill2's `vdev_udp` device and the physics side meet: the addresses and ports of a device config,
read as athrill2 reads them, and the ports a bench picks when it writes its own.

athrill2 (`vdev_udp.c`) binds `DEBUG_FUNC_VDEV_RX_IPADDR` (default 127.0.0.1) : `DEBUG_FUNC_VDEV_RX_PORTNO`
and receives the physics side's RX packets there; it sends its TX packets, each from a fresh socket, to
`DEBUG_FUNC_VDEV_TX_IPADDR` (default 127.0.0.1) : `DEBUG_FUNC_VDEV_TX_PORTNO`, where the physics side
listens. ET Robocon's `device_config.txt` names 127.0.0.1, 54001 (TX) and 54002 (RX). A missing port, or a
bind that fails, makes athrill2 exit with status 1 before it runs.

How athrill2 reads a device config (`cpuemu_load_devcfg`, `token_split`): line by line up to the first empty
line; each line is exactly two tokens split at white space, ',' and ':'; a token is decimal if `strtol` reads
all of it, hexadecimal if it starts with 0x, else a string, in which `{NAME}` is replaced by the environment
variable NAME; a lookup takes the first line with that key whose value has the type asked for.
"""

from __future__ import annotations

import errno
import ipaddress
import os
import random
import re
import socket
from collections.abc import Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import TypeVar

from hakoniwa.wire.errors import HakoError

TX_ADDR_KEY, TX_PORT_KEY = "DEBUG_FUNC_VDEV_TX_IPADDR", "DEBUG_FUNC_VDEV_TX_PORTNO"  # where physics listens
RX_ADDR_KEY, RX_PORT_KEY = "DEBUG_FUNC_VDEV_RX_IPADDR", "DEBUG_FUNC_VDEV_RX_PORTNO"  # where athrill2 binds
ENABLE_KEY, SYNC_TYPE_KEY = "DEBUG_FUNC_ENABLE_VDEV", "DEBUG_FUNC_VDEV_SIMSYNC_TYPE"
COMPLEMENTAL_KEY = "DEVICE_CONFIG_COMPLEMENTAL_TX_SENDING"
RESET_AREA_KEYS = ("DEVICE_CONFIG_RESET_AREA_OFFSET", "DEVICE_CONFIG_RESET_AREA_SIZE")
DEFAULT_ADDR = "127.0.0.1"  # vdev_udp.c's default for both addresses
UDP_DEVICE_CONFIG = "device_config.txt"  # the device config athrill2 runs with over UDP, as ET Robocon names it
MAX_PARAMS = 128  # CPUEMU_DEVCFG_PARAM_MAXNUM: athrill2 does not check it, and overruns its table past it
# A bench's own ports: an even port for the physics side and the odd one above it for athrill2, below Linux's
# ephemeral ports (32768..60999 by default), so that no socket the kernel numbers itself (athrill2 sends from
# such sockets) can take athrill2's port between two tests. The physics side holds its even port for the
# bench's life, so two benches never pick the same pair.
PORT_RANGE = (20000, 32768)
_DELIMITERS = re.compile(r"[\s,:]+")


class LinkError(HakoError, ValueError):
    """A device config or a port the bench cannot use; the message is one line."""


@dataclass(frozen=True)
class Endpoint:
    addr: str
    port: int  # 0: the bench picks one

    def __str__(self) -> str:
        return f"{self.addr}:{self.port}"


@dataclass(frozen=True)
class UdpLink:
    """athrill2's two UDP endpoints and the device config that names them: the user's file, passed to athrill2
    as it is (with the bench's ports put first where it names none), or the bench's own `keys` and ports."""

    physics: Endpoint  # TX: athrill2 sends here
    athrill: Endpoint  # RX: athrill2 binds here
    user_file: Path | None = None
    keys: tuple[tuple[str, str], ...] = ()

    @property
    def fixed(self) -> bool:
        """Whether the user's file names the ports (else the bench picks a pair of its own)."""
        return self.physics.port != 0

    def device_config(self, physics_port: int, athrill_port: int) -> bytes:
        """The device config athrill2 runs with, byte for byte (athrill2 takes the first line of a key, and
        stops at an empty line, so ports the bench adds go first)."""
        ports = [(TX_ADDR_KEY, self.physics.addr), (TX_PORT_KEY, str(physics_port)),
                 (RX_ADDR_KEY, self.athrill.addr), (RX_PORT_KEY, str(athrill_port))]
        if self.user_file is None:
            return _lines([*self.keys, *ports])
        text = self.user_file.read_bytes()
        return text if self.fixed else _lines(ports) + text


def _lines(keys: list[tuple[str, str]]) -> bytes:
    return "".join(f"{key}\t{value}\n" for key, value in keys).encode()


def bench_link(keys: list[tuple[str, str]]) -> UdpLink:
    """A bench's own link on 127.0.0.1, its ports picked when the bench starts (`bind_pair`)."""
    return UdpLink(Endpoint(DEFAULT_ADDR, 0), Endpoint(DEFAULT_ADDR, 0), keys=tuple(keys))


# -- a user's device config --------------------------------------------------------------------------------
class Hex(str):
    """A hexadecimal value (athrill2's HEX type), kept as its text: no string or decimal lookup finds it."""


Token = int | Hex | str


def parse_device_config(text: str, env: Mapping[str, str] | None = None) -> list[tuple[str, Token]]:
    """The (key, value) pairs athrill2 reads from `text`; LinkError for a line it would refuse."""
    names = os.environ if env is None else env
    pairs: list[tuple[str, Token]] = []
    for number, line in enumerate(text.split("\n"), 1):
        if not line:
            break  # athrill2 stops at the first empty line
        tokens = [t for t in _DELIMITERS.split(line) if t]
        if len(tokens) != 2:
            raise LinkError(f"line {number} has {len(tokens)} fields ({line.strip()[:60]!r}); athrill2 reads "
                            "KEY VALUE lines and refuses the file")
        pairs.append((tokens[0], _token(tokens[1], names)))
    if len(pairs) > MAX_PARAMS:
        raise LinkError(f"{len(pairs)} settings; athrill2 holds at most {MAX_PARAMS}")
    return pairs


def _token(text: str, env: Mapping[str, str]) -> Token:
    if re.fullmatch(r"[+-]?\d+", text) and -(1 << 63) <= int(text) < (1 << 63):
        return int(text)  # strtol(text, 10) read all of it without overflow
    if re.fullmatch(r"0x[0-9A-Fa-f]+", text):
        return Hex(text)
    return _expand(text, env)


def _expand(text: str, env: Mapping[str, str]) -> str:
    """`cpuemu_env_parse_devcfg_string`: from the first '{' to the first '}' names a variable; its value
    replaces everything up to that '}' (what comes before the '{' too), unless it is unset."""
    start, end = text.find("{"), text.find("}")
    if start < 0 or end <= start + 1 or text[start + 1:end] not in env:
        return text
    return env[text[start + 1:end]] + text[end + 1:]


T = TypeVar("T", int, str)


def lookup(pairs: list[tuple[str, Token]], key: str, kind: type[T]) -> T | None:
    """The value athrill2's `cpuemu_get_devcfg_value` (int), `_value_hex` (Hex) or `_string` (str) finds."""
    for k, value in pairs:
        if k == key and isinstance(value, kind) and (kind is not str or not isinstance(value, Hex)):
            return value
    return None


def user_link(path: Path) -> UdpLink:
    """The link a user's device config names (ET Robocon's `device_config.txt`), checked as athrill2 will
    use it: VDEV on, UDP (not MMAP), both addresses this machine's loopback, and both ports or neither (the
    bench then picks them)."""
    try:
        text = path.read_text(errors="surrogateescape")
    except OSError as e:
        raise LinkError(f"--device-config {path}: {e.strerror}") from None
    try:
        pairs = parse_device_config(text)
        if not lookup(pairs, ENABLE_KEY, int):
            raise LinkError(f"{ENABLE_KEY} is not 1: athrill2 would run without the virtual devices")
        sync_type = lookup(pairs, SYNC_TYPE_KEY, str)
        if sync_type is not None and sync_type.startswith("MMAP"):
            raise LinkError(f"{SYNC_TYPE_KEY} {sync_type} is the mmap transport; leave --device-config out "
                            "for it (the bench writes athrill2's mmap configuration)")
        if lookup(pairs, COMPLEMENTAL_KEY, int) and not all(lookup(pairs, k, int) for k in RESET_AREA_KEYS):
            raise LinkError(f"{COMPLEMENTAL_KEY} needs {' and '.join(RESET_AREA_KEYS)} (athrill2 stops without them)")
        physics = _endpoint(pairs, TX_ADDR_KEY, TX_PORT_KEY)
        athrill = _endpoint(pairs, RX_ADDR_KEY, RX_PORT_KEY)
        if (physics.port == 0) != (athrill.port == 0):
            raise LinkError(f"give both {TX_PORT_KEY} and {RX_PORT_KEY} (decimal), or neither (the bench then "
                            "picks a pair of its own)")
        if physics.port and (physics.addr, physics.port) == (athrill.addr, athrill.port):
            raise LinkError(f"{TX_PORT_KEY} and {RX_PORT_KEY} are both {physics}")
    except LinkError as e:
        raise LinkError(f"--device-config {path}: {e}") from None
    return UdpLink(physics, athrill, user_file=path.resolve())


def _endpoint(pairs: list[tuple[str, Token]], addr_key: str, port_key: str) -> Endpoint:
    port = lookup(pairs, port_key, int)
    if port is not None and not 1 <= port <= 0xFFFF:
        raise LinkError(f"{port_key} {port} is not a UDP port (1..65535)")
    addr = lookup(pairs, addr_key, str) or DEFAULT_ADDR
    try:
        local = ipaddress.IPv4Address(addr).is_loopback
    except ipaddress.AddressValueError:
        raise LinkError(f"{addr_key} {addr} is not an IPv4 address (athrill2 reads dotted decimal)") from None
    if not local:
        raise LinkError(f"{addr_key} {addr} is not this machine's loopback (127.x.x.x): the bench's physics "
                        "and athrill2 run side by side on one machine")
    return Endpoint(addr, port or 0)


# -- ports -------------------------------------------------------------------------------------------------
def port_free(endpoint: Endpoint) -> bool:
    """Whether athrill2 can bind `endpoint` now (athrill2 sets SO_REUSEADDR; this probe does not, so it fails
    on a port anyone holds, an athrill2 too)."""
    with socket.socket(socket.AF_INET, socket.SOCK_DGRAM) as probe:
        try:
            probe.bind((endpoint.addr, endpoint.port))
        except OSError:
            return False
    return True


def check_free(link: UdpLink) -> None:
    """LinkError, one line, unless the user's two ports are free now."""
    for endpoint, key in ((link.physics, TX_PORT_KEY), (link.athrill, RX_PORT_KEY)):
        if not port_free(endpoint):
            raise _in_use(link, endpoint, key)


def bind_fixed(link: UdpLink) -> socket.socket:
    """The physics side's socket on the user's TX port, for one test (LinkError if it or the RX port is in use)."""
    sock = _bound(link.physics)
    if sock is None:
        raise _in_use(link, link.physics, TX_PORT_KEY)
    if not port_free(link.athrill):
        sock.close()
        raise _in_use(link, link.athrill, RX_PORT_KEY)
    return sock


def _in_use(link: UdpLink, endpoint: Endpoint, key: str) -> LinkError:
    return LinkError(f"UDP port {endpoint} ({key} of {link.user_file}) is in use: another bench, athrill2 or "
                     "ET Robocon's simulator?")


def bind_pair(link: UdpLink) -> tuple[socket.socket, Endpoint, Endpoint]:
    """The physics side's socket on an even port of PORT_RANGE, held for the bench's life, with the odd
    port above it free for athrill2; and the two endpoints."""
    low, high = PORT_RANGE
    pairs = (high - low) // 2
    first = random.randrange(pairs)
    for i in range(pairs):
        physics = Endpoint(link.physics.addr, low + 2 * ((first + i) % pairs))
        sock = _bound(physics)
        if sock is None:
            continue
        athrill = Endpoint(link.athrill.addr, physics.port + 1)
        if port_free(athrill):
            return sock, physics, athrill
        sock.close()
    raise LinkError(f"no free pair of UDP ports in {low}..{high - 1} on {link.physics.addr}")


def _bound(endpoint: Endpoint) -> socket.socket | None:
    sock = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
    try:
        sock.bind((endpoint.addr, endpoint.port))
    except OSError as e:
        sock.close()
        if e.errno in (errno.EADDRINUSE, errno.EACCES):
            return None
        raise LinkError(f"cannot bind UDP {endpoint}: {e.strerror}") from None
    return sock

"""athrill2's device config as athrill2 reads it, and the UDP endpoints a bench takes from it or picks
(hakoniwa/wire/vdev_udp.py). Every socket here is bound to 127.0.0.1."""

import re
import socket
from pathlib import Path

import pytest
from hypothesis import given
from hypothesis import strategies as st

from athrill_sim.programs.program import ProgramError
from athrill_sim.programs.resolve import resolve_program
from athrill_sim.programs.third_party import EV3RT_SDK, RASPIKE_SDK
from hakoniwa.wire.vdev_udp import (
    PORT_RANGE,
    Endpoint,
    Hex,
    LinkError,
    bench_link,
    bind_fixed,
    bind_pair,
    check_free,
    lookup,
    parse_device_config,
    port_free,
    user_link,
)
from tests.helpers.commands import hako, one_line_error
from tests.helpers.paths import needs_shared
from tests.helpers.realemu_fixtures import ETROBOC_DEVICE_CONFIGS

UDP_BASE = "DEBUG_FUNC_ENABLE_VDEV\t1\nDEVICE_CONFIG_TIMER_FD\t400\n"

keys = st.from_regex(r"[A-Z][A-Z0-9_]{0,30}", fullmatch=True)
values = st.one_of(st.integers(0, 2**31 - 1).map(str), st.integers(0, 2**32 - 1).map(hex),
                   st.from_regex(r"[A-Za-z_./][A-Za-z0-9_./]{0,20}", fullmatch=True))
separators = st.from_regex(r"[ \t,:]{1,4}", fullmatch=True)


def config(tmp_path: Path, text: str) -> Path:
    path = tmp_path / "device_config.txt"
    path.write_text(text)
    return path


@pytest.mark.parametrize("path", ETROBOC_DEVICE_CONFIGS, ids=["raspike", "ev3rt"])
def test_et_robocons_device_config_names_54001_and_54002_on_127_0_0_1(path):
    if not path.is_file():
        piece = RASPIKE_SDK if "raspike" in path.parts else EV3RT_SDK
        pytest.skip(needs_shared("ET Robocon's SDK", path.parent, piece))
    link = user_link(path)
    assert (link.physics, link.athrill) == (Endpoint("127.0.0.1", 54001), Endpoint("127.0.0.1", 54002))
    assert link.fixed and link.device_config(54001, 54002) == path.read_bytes()  # athrill2 runs with it as it is


@given(st.lists(st.tuples(keys, separators, values, st.sampled_from(["", " ", "\t", "\r"])), max_size=30))
def test_the_parser_reads_key_value_lines_as_athrill2_does(lines):
    text = "".join(f"{k}{sep}{v}{end}\n" for k, sep, v, end in lines)
    pairs = parse_device_config(text, env={})
    assert [k for k, _ in pairs] == [k for k, *_ in lines]
    for (_, value), (*_, text_value, _) in zip(pairs, lines):
        if re.fullmatch(r"\d+", text_value):
            assert value == int(text_value)
        else:
            assert isinstance(value, str) and value == text_value
            assert isinstance(value, Hex) == text_value.startswith("0x")


@given(keys, st.integers(0, 65535), st.integers(0, 65535))
def test_a_lookup_takes_the_first_line_of_the_type_asked_for(key, first, second):
    pairs = parse_device_config(f"{key} text\n{key} {first}\n{key} {hex(second)}\n{key} {second}\n", env={})
    assert lookup(pairs, key, int) == first
    assert lookup(pairs, key, Hex) == hex(second)
    assert lookup(pairs, key, str) == "text"


def test_athrill2_stops_reading_at_an_empty_line_and_expands_braces():
    pairs = parse_device_config("A 1\nB pre{HOME_X}/fs\n\nC 3\n", env={"HOME_X": "/root"})
    assert pairs == [("A", 1), ("B", "/root/fs")]
    with pytest.raises(LinkError, match="line 2 has 3 fields"):
        parse_device_config("A 1\nB 2 3\n")


@pytest.mark.parametrize("text, words", [
    ("DEBUG_FUNC_ENABLE_VDEV 0\n", ["DEBUG_FUNC_ENABLE_VDEV is not 1"]),
    (UDP_BASE + "DEBUG_FUNC_VDEV_SIMSYNC_TYPE MMAP\n", ["mmap transport"]),
    (UDP_BASE + "DEBUG_FUNC_VDEV_TX_IPADDR 192.168.1.20\nDEBUG_FUNC_VDEV_TX_PORTNO 54001\n"
     "DEBUG_FUNC_VDEV_RX_PORTNO 54002\n", ["192.168.1.20", "loopback"]),
    (UDP_BASE + "DEBUG_FUNC_VDEV_RX_IPADDR localhost\n", ["localhost", "IPv4"]),
    (UDP_BASE + "DEBUG_FUNC_VDEV_TX_PORTNO 54001\n", ["both", "or neither"]),
    (UDP_BASE + "DEBUG_FUNC_VDEV_TX_PORTNO 70000\nDEBUG_FUNC_VDEV_RX_PORTNO 54002\n", ["70000", "1..65535"]),
    (UDP_BASE + "DEBUG_FUNC_VDEV_TX_PORTNO 54001\nDEBUG_FUNC_VDEV_RX_PORTNO 54001\n", ["both 127.0.0.1:54001"]),
    (UDP_BASE + "DEVICE_CONFIG_COMPLEMENTAL_TX_SENDING 1\n", ["DEVICE_CONFIG_RESET_AREA_OFFSET"]),
])
def test_a_device_config_the_bench_cannot_use_is_one_line(tmp_path, text, words):
    with pytest.raises(LinkError) as e:
        user_link(config(tmp_path, text))
    assert "\n" not in str(e.value) and str(tmp_path) in str(e.value)
    for w in words:
        assert w in str(e.value)


def test_a_non_local_address_is_one_line_before_anything_is_built(tmp_path):
    path = config(tmp_path, UDP_BASE + "DEBUG_FUNC_VDEV_TX_IPADDR 10.0.0.5\n")
    with pytest.raises(ProgramError, match="10.0.0.5 is not this machine's loopback"):
        resolve_program("line_trace_c", emulator="athrill2", device_config=str(path))
    one_line_error(hako("try", "--app", "line_trace_c", "--emulator", "athrill2", "--device-config", str(path),
                        timeout=60), "DEBUG_FUNC_VDEV_TX_IPADDR 10.0.0.5", "loopback")


def test_a_device_config_without_ports_gets_the_benchs_first(tmp_path):
    text = UDP_BASE + "DEBUG_FUNC_VDEV_TX_IPADDR 127.0.0.2\n\nDEBUG_FUNC_VDEV_TX_PORTNO 1\n"  # after the empty line
    link = user_link(config(tmp_path, text))
    assert not link.fixed and link.physics == Endpoint("127.0.0.2", 0)
    pairs = parse_device_config(link.device_config(20000, 20001).decode())
    assert lookup(pairs, "DEBUG_FUNC_VDEV_TX_PORTNO", int) == 20000  # not the 1 athrill2 never reads
    assert lookup(pairs, "DEBUG_FUNC_VDEV_RX_PORTNO", int) == 20001
    assert lookup(pairs, "DEBUG_FUNC_VDEV_TX_IPADDR", str) == "127.0.0.2"
    assert lookup(pairs, "DEVICE_CONFIG_TIMER_FD", int) == 400  # the user's settings follow


def test_two_benches_pick_distinct_pairs_below_the_ephemeral_ports():
    link = bench_link([("DEBUG_FUNC_ENABLE_VDEV", "1")])
    first, second = bind_pair(link), bind_pair(link)
    try:
        (_, p1, a1), (_, p2, a2) = first, second
        assert len({p1.port, a1.port, p2.port, a2.port}) == 4
        for physics, athrill in ((p1, a1), (p2, a2)):
            assert physics.port % 2 == 0 and athrill.port == physics.port + 1
            assert PORT_RANGE[0] <= physics.port < PORT_RANGE[1] and physics.addr == "127.0.0.1"
            assert not port_free(physics) and port_free(athrill)  # held by the bench; free for its athrill2
        pairs = parse_device_config(link.device_config(p1.port, a1.port).decode())
        assert (lookup(pairs, "DEBUG_FUNC_VDEV_TX_PORTNO", int), lookup(pairs, "DEBUG_FUNC_VDEV_RX_PORTNO", int)) \
            == (p1.port, a1.port)
    finally:
        first[0].close()
        second[0].close()


def test_a_fixed_port_in_use_is_one_line_naming_it(tmp_path):
    with socket.socket(socket.AF_INET, socket.SOCK_DGRAM) as taken:
        taken.bind(("127.0.0.1", 0))
        port = taken.getsockname()[1]
        other = port + 1 if port < 65535 else port - 1
        for tx, rx in ((port, other), (other, port)):
            link = user_link(config(tmp_path, UDP_BASE + f"DEBUG_FUNC_VDEV_TX_PORTNO {tx}\n"
                                               f"DEBUG_FUNC_VDEV_RX_PORTNO {rx}\n"))
            for attempt in (check_free, bind_fixed):
                with pytest.raises(LinkError, match=f"UDP port 127.0.0.1:{port} .* is in use"):
                    attempt(link)
    with bind_fixed(link) as sock:  # free again: bound for one test
        assert sock.getsockname() == ("127.0.0.1", other)

"""The real TOPPERS emulator, athrill2, as the bench runs it: where it is found, the memory map and device
configuration it gets for each sync mode, its command line, its UDP link, and a v850 image under it as a
`Program` (the `elf` kind's program, and the `image` kind's once built).

Our own programs run in the deterministic lockstep; the real emulator runs in the repeatable mode (athrill2
built with scripts/athrill-patches waits at each sync point) unless `--sync hakoniwa` asks for the unmodified
protocol. Its packets travel over the mapped files (athrill2's MMAP transport) or, with `--transport udp`, over
UDP as in ET Robocon's simulator (its `vdev_udp` device; `hakoniwa.wire.vdev_udp`), which has the hakoniwa mode
only.
"""

from __future__ import annotations

import os
import shutil
import sys
from enum import StrEnum
from pathlib import Path

from athrill_sim.programs.program import Program, ProgramError
from hakoniwa.wire.protocol import ATHRILL_FILE, UNITY_FILE, SyncMode
from hakoniwa.wire.rundir import SDCARD_DIR
from hakoniwa.wire.vdev_udp import UDP_DEVICE_CONFIG, LinkError, UdpLink, bench_link, user_link

PROJECT = Path(__file__).resolve().parents[2]
BUILD_ATHRILL_HINT = ("build it from TOPPERS' sources (github.com/toppers/athrill-target-v850e2m @ d7123b6 with "
                      "github.com/toppers/athrill @ 8bf811e as its athrill/ folder: ATHRILL_SRC=that/folder "
                      "scripts/build_athrill2.sh build/athrill; docs/REAL-ATHRILL.md), then pass --athrill2 "
                      "build/athrill/athrill2")
REPEATABLE_DIR = "build/athrill-repeatable"  # where scripts/build_athrill2.sh --repeatable is documented to build
BUILD_REPEATABLE_HINT = (f"build one with scripts/build_athrill2.sh --repeatable {REPEATABLE_DIR} (or pass "
                         "--sync hakoniwa: the unmodified protocol, whose results depend on the machine's load)")


class RealSync(StrEnum):
    """How the real emulator keeps time with physics (`--sync`): the sync modes it can run in."""

    REPEATABLE = "repeatable"
    HAKONIWA = "hakoniwa"

    @property
    def mode(self) -> SyncMode:
        return SyncMode[self.name]


SYNC_WAIT_KEY = "DEBUG_FUNC_VDEV_MMAP_SYNC_WAIT"  # read by scripts/athrill-patches/01-*.patch


class AthrillTransport(StrEnum):
    """How athrill2's packets travel (`--transport`)."""

    MMAP = "mmap"  # the two mapped files
    UDP = "udp"  # its vdev_udp device, as in ET Robocon's simulator


# Athrill's memory map and device configuration for an EV3RT image in MMAP mode: the layout the TOPPERS
# ev3rt-athrill-v850e2m images are linked for (v850es_fk3.ld, and the SDK's sdk/common/memory.txt: 2048 KB of
# ROM and of data RAM; a C++ program with libstdc++'s iostream outgrows the 512 KB of the older ble_sample's
# map), the serial FIFO's RAM, and the two mapped files at the VDEV addresses below. Athrill finds the mapped
# files by these names, relative to its working directory (the run directory).
MMAP_TX_ADDR = 0x40000000
MMAP_RX_ADDR = 0x40010000
MEMORY_CONFIG = "memory_mmap.txt"
DEVICE_CONFIG = "device_config_mmap.txt"
ATHRILL_MEMORY = [("ROM", 0x00000000, "2048"), ("RAM", 0x00200000, "2048"), ("RAM", 0x03FF7000, "1024"),
                  ("RAM", 0x05FF7000, "10240"), ("RAM", 0x07FF7000, "10240"),
                  ("MMAP", MMAP_TX_ADDR, ATHRILL_FILE), ("MMAP", MMAP_RX_ADDR, UNITY_FILE)]
ATHRILL_DEVICE = [
    ("DEVICE_CONFIG_TIMER_FD", "400"),
    ("DEBUG_FUNC_ENABLE_FT", "1"), ("DEBUG_FUNC_ENABLE_BT", "1"), ("DEBUG_FUNC_ENABLE_PROF", "1"),
    ("DEBUG_FUNC_ENABLE_WATCH", "1"), ("DEBUG_FUNC_ENABLE_SKIP_CLOCK", "1"), ("DEBUG_FUNC_ENABLE_SYNC_TIME", "0"),
    ("DEBUG_FUNC_ENABLE_VDEV", "1"), ("DEBUG_FUNC_VDEV_MMAP_TX", f"0x{MMAP_TX_ADDR:08X}"),
    ("DEBUG_FUNC_VDEV_MMAP_RX", f"0x{MMAP_RX_ADDR:08X}"), ("DEBUG_FUNC_VDEV_SIMSYNC_TYPE", "MMAP"),
    ("DEVICE_CONFIG_SERIAL_FILFO_BASE_ADDR", "0x03FF7000"), ("DEVICE_CONFIG_SERIAL_FILFO_0_SIZE", "4096"),
    ("DEVICE_CONFIG_SERIAL_FILFO_0_RD_INTNO", "57"), ("DEVICE_CONFIG_SERIAL_FILFO_0_WR_INTNO", "65"),
    ("DEVICE_CONFIG_SERIAL_FILFO_0_RD_INTOFF", "8"), ("DEVICE_CONFIG_SERIAL_FILFO_0_WR_INTOFF", "0"),
    ("DEVICE_CONFIG_SERIAL_FILFO_0_EXDEV_ENABLE", "1"), ("DEVICE_CONFIG_EV3_SERIAL_ID", "0"),
    ("DEVICE_CONFIG_VIRTFS_TOP", SDCARD_DIR),  # the SD card's folder, as the native runtime's (default _ev3rtfs)
]
# Over UDP: the same configuration without the two mapped files (athrill2 then keeps its VDEV window in its
# own memory and exchanges it as packets), under the names of ET Robocon's; the physics side writes the device
# config once it holds its port (`hakoniwa.wire.vdev_udp.UdpLink.device_config`).
MMAP_ONLY_KEYS = ("DEBUG_FUNC_VDEV_MMAP_TX", "DEBUG_FUNC_VDEV_MMAP_RX", "DEBUG_FUNC_VDEV_SIMSYNC_TYPE")
UDP_MEMORY_CONFIG = "memory.txt"


def athrill_config(sync: SyncMode) -> dict[str, str]:
    """athrill2's memory map and device configuration for a run in `sync` mode over mmap, by file name."""
    device = [*ATHRILL_DEVICE, *([(SYNC_WAIT_KEY, "1")] if sync == SyncMode.REPEATABLE else [])]
    return {MEMORY_CONFIG: _memory_map(ATHRILL_MEMORY),
            DEVICE_CONFIG: "".join(f"{key}\t{value}\n" for key, value in device)}


def _memory_map(regions: list[tuple[str, int, str]]) -> str:
    return "".join(f"{kind}, 0x{addr:08X}, {arg}\n" for kind, addr, arg in regions)


def athrill_argv(exe: str, image: Path, udp: bool = False) -> tuple[str, ...]:
    memory, device = (UDP_MEMORY_CONFIG, UDP_DEVICE_CONFIG) if udp else (MEMORY_CONFIG, DEVICE_CONFIG)
    return exe, "-c1", "-t", "-1", "-m", memory, "-d", device, str(image.resolve())


def udp_link(transport: AthrillTransport | None, device_config: str | None) -> UdpLink | None:
    """The UDP link `--transport` and `--device-config` ask for (a device config alone means UDP), or None
    for the mapped files."""
    if (transport or (AthrillTransport.UDP if device_config else AthrillTransport.MMAP)) == AthrillTransport.MMAP:
        if device_config is not None:
            raise ProgramError(f"--device-config {device_config} configures athrill2's UDP transport; it does "
                               "not go with --transport mmap")
        return None
    if device_config is None:
        return bench_link([(k, v) for k, v in ATHRILL_DEVICE if k not in MMAP_ONLY_KEYS])
    try:
        return user_link(Path(device_config))
    except LinkError as e:
        raise ProgramError(str(e)) from None


def elf_program(image: Path, athrill2: str | None, sync: SyncMode = SyncMode.REPEATABLE,
                udp: UdpLink | None = None) -> Program:
    """A v850 image under the real athrill2; checked (by a short run of its own, over the mapped files, as
    the image and the emulator do not depend on the transport) before the first test."""
    from athrill_sim.v850 import ImageError
    from athrill_sim.v850.elf import check_image

    try:
        check_image(image)
    except ImageError as e:
        raise ProgramError(f"--app {e}") from None
    exe = find_athrill2(athrill2, sync)
    config = athrill_config(sync) if udp is None else {
        UDP_MEMORY_CONFIG: _memory_map([region for region in ATHRILL_MEMORY if region[0] != "MMAP"])}
    over = "" if udp is None else " over UDP"
    return Program(f"v850 image {image} on {exe}{over}", sync, False, athrill_argv(exe, image, udp is not None),
                   in_run_dir=True, config_files=config, files=(image.resolve(),), image=image.resolve(),
                   check_argv=(sys.executable, "-m", "athrill_sim.v850.check", exe, str(image.resolve()),
                               sync.name.lower()), udp=udp)


def find_athrill2(given: str | None, sync: SyncMode) -> str:
    """--athrill2, else athrill2 on PATH; the repeatable mode needs one built with the sync patch, and takes
    the one the build script leaves in this project's build/ when PATH has none."""
    repeatable = sync == SyncMode.REPEATABLE
    if given is not None:
        path = Path(given)
        if not (path.is_file() and os.access(path, os.X_OK)):
            raise ProgramError(f"--athrill2 {given}: not an executable file; {BUILD_ATHRILL_HINT}")
        if repeatable and not has_sync_patch(path):
            raise ProgramError(f"--athrill2 {given} lacks the repeatable-sync patch; {BUILD_REPEATABLE_HINT}")
        return str(path.resolve())
    on_path = shutil.which("athrill2")
    if not repeatable:
        if on_path is None:
            raise ProgramError(f"athrill2 (the TOPPERS emulator) is not on PATH; {BUILD_ATHRILL_HINT}")
        return on_path
    ours = PROJECT / REPEATABLE_DIR / "athrill2"
    for found in (on_path, str(ours) if ours.is_file() else None):
        if found and has_sync_patch(Path(found)):
            return found
    raise ProgramError(f"no athrill2 with the repeatable-sync patch on PATH or in {REPEATABLE_DIR}; "
                       f"{BUILD_REPEATABLE_HINT}")


def has_sync_patch(exe: Path) -> bool:
    """Whether `exe` reads the patch's device-config key (an unpatched athrill2 ignores the key, and would
    run ahead of the physics while the bench waited for it to stop)."""
    try:
        return SYNC_WAIT_KEY.encode() in exe.read_bytes()
    except OSError:
        return False

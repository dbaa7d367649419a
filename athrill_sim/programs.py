"""What `--app` names, and how to start a fresh Athrill process for it for every test.

Three kinds of robot program run against the same physics:

- a Python program (a built-in name or `module:function`) on the mock Athrill, `athrill-sim`;
- a v850 ELF image (an EV3RT application built for the real emulator) under the real TOPPERS `athrill2`,
  with the memory and device configuration written into the run directory;
- (see `athrill_sim.native`) a user's EV3RT C program compiled for this machine, or, with
  `--emulator athrill2`, the same program built into a v850 image (`athrill_sim.v850`) and run as one.

The kind decides how time is kept (`SyncMode`): our own programs run in the deterministic lockstep; the real
emulator runs in the repeatable mode (athrill2 built with scripts/athrill-patches waits at each sync point)
unless `--sync hakoniwa` asks for the unmodified protocol. The real emulator's packets travel over the mapped
files (athrill2's MMAP transport) or, with `--transport udp`, over UDP as in ET Robocon's simulator (its
`vdev_udp` device; `athrill_sim.vdev_udp`), which has the hakoniwa mode only. Everything here is checked before
the first test, so a bad `--app` is one clear error instead of a campaign of crashed tests.
"""

from __future__ import annotations

import os
import shutil
import subprocess
import sys
from collections.abc import Callable
from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import TYPE_CHECKING, Any

from hakoniwa.wire.errors import HakoError
from hakoniwa.wire.processes import die_with_parent
from hakoniwa.wire.protocol import ATHRILL_FILE, UNITY_FILE, SyncMode
from hakoniwa.wire.rundir import SDCARD_DIR

if TYPE_CHECKING:
    from athrill_sim.vdev_udp import UdpLink
    from athrill_sim.working_folder import WorkingFolder

PROJECT = Path(__file__).resolve().parents[1]
NATIVE_DIR = Path(__file__).resolve().parent / "native"  # the bench's runtime and libraries, not the user's program
BUILD_ATHRILL_HINT = ("build it from TOPPERS' sources (github.com/toppers/athrill-target-v850e2m @ d7123b6 with "
                      "github.com/toppers/athrill @ 8bf811e as its athrill/ folder: ATHRILL_SRC=that/folder "
                      "scripts/build_athrill2.sh build/athrill; docs/REAL-ATHRILL.md), then pass --athrill2 "
                      "build/athrill/athrill2")
REPEATABLE_DIR = "build/athrill-repeatable"  # where scripts/build_athrill2.sh --repeatable is documented to build
BUILD_REPEATABLE_HINT = (f"build one with scripts/build_athrill2.sh --repeatable {REPEATABLE_DIR} (or pass "
                         "--sync hakoniwa: the unmodified protocol, whose results depend on the machine's load)")
EMULATORS = ("native", "athrill2")  # what a C program runs on: compiled for this machine, or the real emulator
REAL_SYNCS = {"repeatable": SyncMode.REPEATABLE, "hakoniwa": SyncMode.HAKONIWA}
SYNC_WAIT_KEY = "DEBUG_FUNC_VDEV_MMAP_SYNC_WAIT"  # read by scripts/athrill-patches/01-*.patch
TRANSPORTS = ("mmap", "udp")  # how athrill2's packets travel: the mapped files, or UDP (ET Robocon's simulator)

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
# config once it holds its port (`athrill_sim.vdev_udp.UdpLink.device_config`).
MMAP_ONLY_KEYS = ("DEBUG_FUNC_VDEV_MMAP_TX", "DEBUG_FUNC_VDEV_MMAP_RX", "DEBUG_FUNC_VDEV_SIMSYNC_TYPE")
UDP_MEMORY_CONFIG = "memory.txt"
UDP_DEVICE_CONFIG = "device_config.txt"


class ProgramError(HakoError, ValueError):
    """`--app` (or `--athrill2`) names nothing that can run; the message is one line."""


@dataclass(frozen=True)
class Program:
    """A robot program, ready to be started once per test."""

    description: str
    sync: SyncMode
    prelaunch: bool  # start test N+1's process while test N runs (it waits for its own test number)
    argv: tuple[str, ...]  # the command; "{test}" and "{run_dir}" are filled in per test
    in_run_dir: bool = False  # run with the run directory as working directory
    config_files: dict[str, str] = field(default_factory=dict)  # written into the run directory once
    check_argv: tuple[str, ...] = ()  # a command that exits non-zero, saying why, if the program cannot run
    files: tuple[Path, ...] = ()  # what the program is made of (its sources, its image), for a campaign's journal
    udp: UdpLink | None = None  # the real emulator over UDP: its endpoints (else the mapped files carry all)
    image: Path | None = None  # the file argv runs: the native Athrill, or the v850 image athrill2 loads
    sdcard: Path | None = None  # the program's own sdcard/ folder, copied onto the bench's SD card
    tuning: Any = field(default=None, compare=False)  # athrill_sim.tuning.Tuning: the parameters' bindings
    forkable: bool = False  # argv is MOCK_ARGV + arguments: `athrill_sim.zygote` can fork it instead
    working_folder: WorkingFolder | None = None  # a scratch copy of the program's workspace per test, its cwd
    interrupted_at_end: bool = False  # a test's end sends SIGINT (Ctrl-C) before the process is stopped
    env: tuple[tuple[str, str], ...] = ()  # set in the process's environment

    def prepare(self, run_dir: Path) -> None:
        for name, text in self.config_files.items():
            (run_dir / name).write_text(text)
        if self.sdcard is not None:
            shutil.copytree(self.sdcard, run_dir / SDCARD_DIR, dirs_exist_ok=True)

    def with_image(self, image: Path) -> Program:
        """The same program run from another copy of its image (one with other initial values)."""
        assert self.image is not None
        return replace(self, argv=tuple(str(image) if a == str(self.image) else a for a in self.argv), image=image,
                       tuning=None)

    def start_check(self) -> subprocess.Popen | None:
        """Start checking, in a process of its own exactly as a test would load it, that the program can
        run; the caller does its own start-up meanwhile and then calls `finish_check`."""
        if not self.check_argv:
            return None
        return subprocess.Popen(self.check_argv, stdin=subprocess.DEVNULL, stdout=subprocess.PIPE,
                                stderr=subprocess.STDOUT, text=True)

    @staticmethod
    def finish_check(check: subprocess.Popen | None) -> None:
        if check is None:
            return
        out, _ = check.communicate()
        if check.returncode != 0:
            lines = [line for line in out.strip().splitlines() if line.strip()]
            raise ProgramError(lines[-1].removeprefix("Error: ") if lines else "the robot program cannot run")

    def args(self, run_dir: Path, test_seq: int) -> list[str]:
        return [a.format(test=test_seq, run_dir=run_dir) for a in self.argv]

    def spawn(self, run_dir: Path, test_seq: int, output, cwd: Path | None = None) -> subprocess.Popen:
        """Start the process for test `test_seq` (in `cwd`, its working folder, if it has one). It gets a
        session of its own, so that a Ctrl-C meant for the campaign does not kill it mid-test (the physics
        process stops it), and dies with the physics process, so that nothing is left running if that is
        killed."""
        return subprocess.Popen(self.args(run_dir, test_seq), stdin=subprocess.DEVNULL, stdout=output,
                                stderr=subprocess.STDOUT, cwd=cwd or (run_dir if self.in_run_dir else None),
                                env={**os.environ, **dict(self.env)} if self.env else None,
                                start_new_session=True, preexec_fn=die_with_parent)


MOCK_ARGV = (sys.executable, "-m", "athrill_sim.main")  # the mock Athrill, whose arguments follow
NATIVE_ENV = (("TZ", "UTC0"),)  # localtime() of the simulated clock: the same on every machine (docs/NATIVE.md)


def python_program(spec: str) -> Program:
    mock = (*MOCK_ARGV, "--app", spec)
    return Program(f"python app {spec}", SyncMode.LOCKSTEP, True,
                   (*mock, "--run-dir", "{run_dir}", "--test", "{test}"), check_argv=(*mock, "--check"),
                   files=python_program_files(spec), forkable=True)


def python_program_files(spec: str) -> tuple[Path, ...]:
    """The source files of a Python program: its module and the user's modules it imports."""
    from athrill_sim.apps import BUILTIN
    from athrill_sim.python_sources import program_sources

    return program_sources(BUILTIN.get(spec, spec).partition(":")[0])


def native_program(source: Path, flags: tuple[str, ...] = ()) -> Program:
    """A user's EV3RT C program (a .c file or a workspace folder), built now, before any test starts, with
    the extra compiler `flags` (a tuned program's -D definitions)."""
    from athrill_sim.native import NativeBuildError
    from athrill_sim.native.build import build_app
    from athrill_sim.native.workspace import find_app
    from athrill_sim.working_folder import WorkingFolder, WorkingFolderError

    try:
        exe = build_app(source, flags=flags)
        files = tuple(f for f in find_app(source).hashed if not f.is_relative_to(NATIVE_DIR))  # the user's
        card = program_sdcard(source)
        folder = WorkingFolder.of(source, card)
    except (NativeBuildError, WorkingFolderError) as e:
        raise ProgramError(str(e)) from None
    return Program(f"native C app {source}", SyncMode.LOCKSTEP, True,
                   (str(exe), "--run-dir", "{run_dir}", "--test", "{test}"), files=(*files, *card_files(card)),
                   image=exe, working_folder=folder, interrupted_at_end=True, env=NATIVE_ENV)


def program_sdcard(source: Path) -> Path | None:
    """A C program's own SD card: the sdcard/ folder beside its sources, if it has one."""
    folder = (source if source.is_dir() else source.parent) / SDCARD_DIR
    return folder.resolve() if folder.is_dir() else None


def card_files(card: Path | None) -> tuple[Path, ...]:
    return tuple(sorted(f.resolve() for f in card.rglob("*") if f.is_file())) if card is not None else ()


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


def udp_link(transport: str | None, device_config: str | None) -> UdpLink | None:
    """The UDP link `--transport` and `--device-config` ask for (a device config alone means UDP), or None
    for the mapped files."""
    from athrill_sim.vdev_udp import LinkError, bench_link, user_link

    if (transport or ("udp" if device_config else "mmap")) == "mmap":
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


def _given(path: Path | None) -> Path:
    """A recipe's path, for the recipes that have one (only the Python program's is None)."""
    assert path is not None
    return path


@dataclass(frozen=True)
class Recipe:
    """How the program `--app` names is made: `make(path, flags)` builds it from `path` (its sources, or a
    scratch copy of them) with extra compiler flags; a Python program or a v850 image is taken as it is."""

    kind: str  # "python", "native" (C built for this machine), "image" (C built into a v850 image), "elf"
    path: Path | None  # the C program (file or folder), or the v850 image
    make: Callable[[Path | None, tuple[str, ...]], Program]
    sync: SyncMode = SyncMode.LOCKSTEP  # how the program keeps time with physics


def resolve_program(spec: str, *, athrill2: str | None = None, emulator: str | None = None,
                    sync: str | None = None, transport: str | None = None, device_config: str | None = None,
                    bindings: str | None = None) -> Program:
    """The program `--app SPEC` names: a built-in or `module:function` Python program, an EV3RT C or C++
    program (a .c or .cpp file, a workspace folder or a built-in C name), or a v850 ELF. `emulator` athrill2
    builds a C or C++ program into a v850 image; `sync` (repeatable, hakoniwa) is how a real emulator keeps
    time, `transport` (mmap, udp) and `device_config` how its packets travel. `bindings`
    (JSON, `athrill_sim.bindings`) says how parameters of other kinds than `offset` reach the program: they
    are checked against it now, and each test then runs the program as its values make it."""
    recipe = program_recipe(spec, athrill2=athrill2, emulator=emulator, sync=sync, transport=transport,
                            device_config=device_config)
    if bindings:
        from athrill_sim.bindings import BindingError, from_json
        from athrill_sim.tuning import tune

        try:
            return tune(recipe, from_json(bindings))
        except BindingError as e:
            raise ProgramError(f"--space: {e}") from None
    return recipe.make(recipe.path, ())


def program_recipe(spec: str, *, athrill2: str | None = None, emulator: str | None = None,
                   sync: str | None = None, transport: str | None = None,
                   device_config: str | None = None) -> Recipe:
    """How to make the program `--app SPEC` names (see `resolve_program`)."""
    from athrill_sim.apps import BUILTIN, C_BUILTIN
    from athrill_sim.native.workspace import SOURCE_SUFFIXES
    from athrill_sim.v850.elf import is_elf

    path = Path(spec)
    builtins = ", ".join([*BUILTIN, *C_BUILTIN])
    c_source = C_BUILTIN.get(spec) or (path if path.is_dir() or (path.is_file() and path.suffix in SOURCE_SUFFIXES)
                                       else None)
    real = emulator == "athrill2" or (c_source is None and path.is_file() and is_elf(path))
    if sync is not None and not real:
        raise ProgramError(f"--sync {sync} is for the real emulator (a v850 image, or --emulator athrill2); "
                           f"{spec} runs in the lockstep")
    udp = udp_link(transport, device_config)
    if udp is not None and not real:
        raise ProgramError(f"--transport udp is for the real emulator (a v850 image, or --emulator athrill2); "
                           f"{spec} runs in the lockstep over the mapped files")
    if udp is not None and sync == "repeatable":
        raise ProgramError("--sync repeatable needs --transport mmap (the wait is patched into athrill2's mmap "
                           "device); over UDP athrill2 keeps TOPPERS' protocol: --sync hakoniwa")
    real_sync = REAL_SYNCS[sync or ("hakoniwa" if udp is not None else "repeatable")]
    if spec in BUILTIN and emulator != "athrill2":
        return Recipe("python", None, lambda _path, _flags: python_program(spec))
    if c_source is not None:
        if real:
            return Recipe("image", Path(c_source), lambda source, flags: image_program(_given(source), athrill2,
                                                                                         real_sync, udp, flags),
                          real_sync)
        return Recipe("native", Path(c_source), lambda source, flags: native_program(_given(source), flags))
    if path.is_file():
        if real:
            if emulator == "native":
                raise ProgramError(f"--app {spec}: a v850 image runs only in the real emulator (--emulator athrill2)")
            return Recipe("elf", path, lambda image, _flags: elf_program(_given(image), athrill2, real_sync, udp),
                          real_sync)
        raise ProgramError(f"--app {spec}: not a v850 ELF image, a C or C++ file (.c, .cpp), a built-in app "
                           f"({builtins}) or module:function")
    if emulator == "athrill2":
        raise ProgramError(f"--app {spec}: --emulator athrill2 runs EV3RT C and C++ programs (app.c, app.cpp, a "
                           "workspace folder, line_trace_c) and v850 images, not Python programs")
    module, _, func = spec.partition(":")
    if not (module and func):
        raise ProgramError(f"--app {spec}: no such file or folder, and not a built-in app ({builtins}) "
                           "or module:function")
    return Recipe("python", None, lambda _path, _flags: python_program(spec))


def image_program(source: Path, athrill2: str | None, sync: SyncMode, udp: UdpLink | None = None,
                  flags: tuple[str, ...] = ()) -> Program:
    """A user's EV3RT C or C++ program, built now into a v850 image (cached) with the extra compiler `flags`,
    and run in the real emulator."""
    from athrill_sim.v850 import ImageError
    from athrill_sim.v850.build import build_image

    try:
        image = build_image(source, flags=flags)
    except ImageError as e:
        raise ProgramError(str(e)) from None
    card = program_sdcard(source)
    program = elf_program(image, athrill2, sync, udp)
    return replace(program, sdcard=card, files=(*program.files, *card_files(card)))

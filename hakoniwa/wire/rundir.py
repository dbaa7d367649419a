"""The run directory: what lives in it, one run at a time, and what to say when a run in it died.

A crashed run leaves its files behind but not its lock (the kernel drops a flock when the process dies),
so the next run in the same directory simply takes over and recreates the files, while a second live run
is refused with the first one's pid.
"""

from __future__ import annotations

import fcntl
import os
from pathlib import Path

from hakoniwa.wire.errors import HakoError
from hakoniwa.wire.protocol import ATHRILL_FILE, ATHRILL_MAGIC, UNITY_FILE, UNITY_MAGIC, LayoutError, check_file

LOCK_FILE = ".hako.lock"
TRAJECTORY_FILE = "trajectory.csv"  # the last test's path, for pictures
PHYSICS_LOG = "physics.log"  # one line per test: what the physics process saw
ATHRILL_LOG = "athrill.log"  # what the Athrill processes printed (the program's syslog)
RESULT_FILE = "result.json"  # the last test's result (`TestResult.encode`), written before its event is raised
# What a native EV3RT program leaves of its test (the C runtime writes them; docs/NATIVE.md).
LCD_LOG = "lcd.txt"  # every LCD drawing call of the test, in order, stamped with the simulated time
LCD_PNG = "lcd.png"  # the 178x128 screen at the test's end, drawn from LCD_LOG by the physics process
SERIAL_LOG = "serial-{port}.log"  # what the program wrote to ev3_serial_open_file(port)
SERIAL_PORTS = ("default", "uart", "bt")  # serial_port_t order (EV3_SERIAL_DEFAULT, _UART, _BT): SERIAL_LOG's names
SERIAL_INPUT = "serial-input.txt"  # the scenario's [[serial]] input: "<at_us> <port> <hex bytes>" per line
# asp's serial port in the lockstep (RasPike-ART's asp, athrill_sim/native/runtime/asp/asp_serial.c): how many
# bytes the hub (the physics side) and asp have each sent over the pty so far, two little-endian u64 at these
# offsets, so that each side waits for exactly what the other sent (docs/DESIGN-NOTES.md, RasPike-ART).
RASPIKE_SERIAL = "raspike-serial.bin"
# the hub's count, asp's count, and when the hub sends its next status [simulated us] (NEVER_WAKES: not yet)
RASPIKE_HUB_SENT, RASPIKE_PROGRAM_SENT, RASPIKE_HUB_NEXT_STATUS, RASPIKE_SERIAL_SIZE = 0, 8, 16, 24
RASPIKE_PORT = "raspike-port"  # a link to the pty on which the physics side plays asp's hub, made anew each test
SDCARD_DIR = "sdcard"  # the folder standing in for the SD card: the program's working directory
# A native program's working folder, a scratch copy of its workspace per test
# (athrill_sim/programs/working_folder.py): the test being run's under WORKSPACES_DIR, the last test's, with what the
# program wrote, kept as WORKSPACE_DIR.
WORKSPACES_DIR = "workspaces"
WORKSPACE_DIR = "workspace"

# What the physics process tells the controller it starts (the paper's arrangement), in its environment.
RUN_DIR_ENV = "HAKO_RUN_DIR"  # the run directory
COURSE_ENV = "HAKO_COURSE"  # the course folder
OBJECTIVE_ENV = "HAKO_OBJECTIVE"  # the bench's objective by name (lap, completed, etrobocon): what a test's value is
TIME_LIMIT_ENV = "HAKO_TIME_LIMIT_S"  # the bench's time limit in simulated seconds: what a failure scores


def diagnose(run_dir: Path) -> str | None:
    """What is wrong with the mapped files, if anything: the likely cause when a process of the bench was
    killed by SIGBUS (someone truncated a file it had mapped)."""
    problems = []
    for name, magic in ((UNITY_FILE, UNITY_MAGIC), (ATHRILL_FILE, ATHRILL_MAGIC)):
        try:
            check_file(Path(run_dir) / name, magic)
        except LayoutError as e:
            problems.append(str(e))
    return "; ".join(problems) or None


class RunDirBusy(HakoError, RuntimeError):
    pass


class RunDirLock:
    """One live process per folder: a run directory, or a campaign folder (`what` names it in the refusal)."""

    def __init__(self, run_dir: Path, what: str = "run directory") -> None:
        self.run_dir = Path(run_dir)
        self.what = what
        self._fd: int | None = None

    def acquire(self) -> None:
        self.run_dir.mkdir(parents=True, exist_ok=True)
        fd = os.open(self.run_dir / LOCK_FILE, os.O_RDWR | os.O_CREAT, 0o644)
        try:
            fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except BlockingIOError:
            holder = os.read(fd, 32).decode(errors="replace").strip() or "?"
            os.close(fd)
            raise RunDirBusy(f"{self.what} {self.run_dir} is in use by another run (pid {holder})") from None
        os.ftruncate(fd, 0)
        os.write(fd, f"{os.getpid()}\n".encode())
        self._fd = fd

    def release(self) -> None:
        if self._fd is not None:
            os.close(self._fd)
            self._fd = None

    def __enter__(self) -> RunDirLock:
        self.acquire()
        return self

    def __exit__(self, *exc: object) -> None:
        self.release()

"""What every process of the bench needs to know about its children: that they die with it and what their
exit statuses mean (the statuses the bench itself uses are `hakoniwa.wire.exits`'s).

Whose fault an Athrill's exit is cannot be read from its status: a user's program may `exit(3)` as well as
we can. So an Athrill (the mock and the C runtime alike) that stops for a fault of the bench first writes a
marker file, `athrill-bench-fault.PID` in the run directory, holding its reason; an exit without one, once
the program runs, is the program's outcome."""

from __future__ import annotations

import ctypes
import os
import signal
import subprocess
from pathlib import Path
from typing import NamedTuple

_PR_SET_PDEATHSIG = 1
BENCH_FAULT_MARKER = "athrill-bench-fault."  # + the pid: the file that makes an Athrill's exit a bench fault


def die_with_parent() -> None:
    """preexec_fn: have the kernel kill this child when its parent dies, so that killing `hako` (even with
    SIGKILL) takes the physics process and the controller with it instead of leaving them running."""
    try:
        ctypes.CDLL(None, use_errno=True).prctl(_PR_SET_PDEATHSIG, signal.SIGTERM)
    except (OSError, AttributeError):  # not Linux: children merely outlive a killed parent
        pass


def kill(proc: subprocess.Popen) -> None:
    """Stop a child now and reap it (one that has exited already is only reaped)."""
    if proc.poll() is None:
        proc.kill()
    proc.wait()


def mark_bench_fault(run_dir: Path, reason: str) -> None:
    """Before an Athrill exits for a fault of the bench: say so where the physics process looks."""
    try:
        (Path(run_dir) / f"{BENCH_FAULT_MARKER}{os.getpid()}").write_text(reason + "\n")
    except OSError:  # no run directory to write in: the physics process sees an Athrill that never got going
        pass


def take_bench_fault(run_dir: Path, pid: int) -> str | None:
    """The reason Athrill `pid` gave for a bench fault, if it marked one (the marker is removed)."""
    marker = Path(run_dir) / f"{BENCH_FAULT_MARKER}{pid}"
    try:
        reason = marker.read_text().strip()
        marker.unlink()
    except OSError:
        return None
    return reason


def describe_exit(code: int) -> str:
    """A child's exit status (negative: the signal that killed it) in words."""
    if code < 0:
        try:
            return f"was killed by {signal.Signals(-code).name}"
        except ValueError:
            return f"was killed by signal {-code}"
    return f"exited with status {code}"


class CpuUse(NamedTuple):
    state: str  # /proc's one-letter state: R running or runnable, S sleeping, T stopped, D waiting on I/O, ...
    cpu_s: float  # user + system CPU time so far


def cpu_use(pid: int) -> CpuUse | None:
    """What a process is doing and how much CPU it has had (None where /proc cannot say): how a silent child
    is told apart as spinning (it has CPU and uses it) or stalled (stopped, or runnable and given none)."""
    try:
        with open(f"/proc/{pid}/stat", "rb") as f:
            fields = f.read().rsplit(b")", 1)[1].split()
        return CpuUse(fields[0].decode(), (int(fields[11]) + int(fields[12])) / os.sysconf("SC_CLK_TCK"))
    except (OSError, IndexError, ValueError):
        return None
